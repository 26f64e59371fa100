//! The preview's resolution and step in effect this frame: the settings, the motion and the
//! measured frame time together ([`Quality`]), and the resolution a moving frame drops to.

use crate::sandbox::shared::quality::{Backend, FullQuality, Motion, PreviewSettings};
use crate::sandbox::shared::viewport::Viewport;
use bevy::prelude::*;

/// The resolutions the preview drops to while moving, highest first: the measured frame time
/// picks one, so the image changes size only when the speed does.
const MOVING_LADDER: [f32; 9] = [1.0, 0.75, 0.5, 0.35, 0.25, 0.18, 0.125, 0.09, 0.05];

/// The resolution fraction for a moving frame: the highest on [`MOVING_LADDER`] whose volume
/// work (`per_work` seconds a pixel at step multiplier 1, `pixels` in the whole viewport,
/// `step` the moving step multiplier) fits in `share` seconds, within `[lowest, highest]`.
pub fn moving_scale_fit(
    per_work: f64,
    share: f64,
    pixels: f64,
    step: f32,
    lowest: f32,
    highest: f32,
) -> f32 {
    let full = per_work * pixels / f64::from(step.max(1e-3));
    let fit = (share / full).sqrt();
    let fit = if fit.is_finite() { fit as f32 } else { highest };
    MOVING_LADDER
        .iter()
        .copied()
        .find(|&s| s <= fit)
        .unwrap_or(lowest)
        .clamp(lowest.min(highest), highest)
}

/// The preview's quality controls, when the preview plugin is present.
#[derive(bevy::ecs::system::SystemParam)]
pub struct Quality<'w> {
    preview: Option<Res<'w, PreviewSettings>>,
    motion: Option<Res<'w, Motion>>,
    full: Option<Res<'w, FullQuality>>,
    /// The measured frame time, and the viewport's size, for the resolution while moving.
    progressive: Option<Res<'w, crate::sandbox::preview::progressive::Progressive>>,
    viewport: Option<Res<'w, Viewport>>,
}

impl Quality<'_> {
    pub fn changed(&self) -> bool {
        self.preview.as_ref().is_some_and(|p| p.is_changed())
            || self.motion.as_ref().is_some_and(|m| m.is_changed())
            || self.full.as_ref().is_some_and(|f| f.is_changed())
    }

    /// While moving with adaptive quality: the resolution the measured frame time allows,
    /// never below `lowest` (the moving resolution `effective` gives) nor above the resting one
    /// (a GPU that draws the whole view within a frame's share keeps it, and the scene's meshes
    /// stay sharp).
    fn moving_scale(&self, p: &PreviewSettings, lowest: f32, step: f32) -> f32 {
        let fitted = self.progressive.as_ref().and_then(|pr| {
            let per_work = pr.cost.per_work?;
            let (_, size) = self.viewport.as_ref()?.physical();
            let pixels = f64::from(size.x) * f64::from(size.y);
            Some(moving_scale_fit(
                per_work,
                pr.cost.share(),
                pixels,
                step,
                lowest,
                p.scale,
            ))
        });
        fitted.unwrap_or(lowest)
    }

    /// The fraction of the window's pixels the main camera renders: the GPU preview's
    /// resolution, or 1 when the CPU draws the volume (the camera draws only spheres then).
    pub fn scale(&self) -> f32 {
        let moving = self.motion.as_ref().is_some_and(|m| m.moving);
        let full = self.full.as_ref().is_some_and(|f| f.0);
        self.preview.as_ref().map_or(1.0, |p| {
            let (scale, step) = p.effective(moving, full);
            if p.backend == Backend::Cpu {
                1.0
            } else if moving && p.adaptive && !full {
                self.moving_scale(p, scale, step)
            } else {
                scale
            }
        })
    }

    /// How many times longer the preview's step is than the settings' (1 without a preview).
    pub fn step_multiplier(&self) -> f32 {
        let moving = self.motion.as_ref().is_some_and(|m| m.moving);
        let full = self.full.as_ref().is_some_and(|f| f.0);
        self.preview
            .as_ref()
            .map_or(1.0, |p| p.effective(moving, full).1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fast GPU keeps the resting resolution while moving; a slow one drops as far as its
    /// measured speed needs, on the ladder, never below the moving resolution.
    #[test]
    fn the_moving_resolution_follows_the_measured_speed() {
        let pixels = 1280.0 * 720.0;
        // 1 ns a pixel: the whole view in under a millisecond.
        assert_eq!(moving_scale_fit(1e-9, 0.025, pixels, 2.0, 0.25, 1.0), 1.0);
        // 1.6 µs a pixel at step ×2: 0.74 s whole; 0.025 s allows √(0.025/0.74) ≈ 0.18.
        assert_eq!(
            moving_scale_fit(1.6e-6, 0.025, pixels, 2.0, 0.05, 1.0),
            0.18
        );
        assert_eq!(
            moving_scale_fit(1.6e-6, 0.025, pixels, 2.0, 0.25, 1.0),
            0.25
        );
        // Never above the resting resolution, whatever the speed.
        assert_eq!(moving_scale_fit(1e-12, 0.025, pixels, 2.0, 0.25, 0.5), 0.5);
        assert_eq!(moving_scale_fit(0.0, 0.025, pixels, 2.0, 0.25, 0.5), 0.5);
        assert_eq!(
            moving_scale_fit(f64::NAN, 0.025, pixels, 2.0, 0.25, 0.5),
            0.5
        );
    }
}
