//! Lines over the scene, drawn by egui at the window's full resolution and anti-aliased
//! whatever resolution the volume is rendered at: the volume's box and lattice, the virtual
//! camera's frustum and pixel grid, the light's ring and arrow. Systems add world-space
//! segments during the frame ([`OverlayLines`]); they are projected through the main camera's
//! view into the viewport after the preview is painted, beneath every panel, and cleared.
//!
//! Like the rays of the inspector, they are drawn over the volume rather than inside it: a
//! wireframe that stays visible where the volume is opaque.

use crate::sandbox::shared::state::{MainCamera, View};
use crate::sandbox::shared::viewport::Viewport;
use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};

/// The segments to draw this frame: ends in world space, colour, width in points.
#[derive(Resource, Default)]
pub struct OverlayLines {
    segments: Vec<(Vec3, Vec3, egui::Color32, f32)>,
}

impl OverlayLines {
    /// A segment from `a` to `b`.
    pub fn line(&mut self, a: Vec3, b: Vec3, color: Color, width: f32) {
        self.segments.push((a, b, color32(color), width));
    }

    /// A circle of `radius` around `centre` facing the main camera (a sphere's outline).
    pub fn ring(&mut self, centre: Vec3, radius: f32, view: &View, color: Color, width: f32) {
        let (right, up, _) = view.0.basis();
        const N: usize = 40;
        let at = |i: usize| {
            let a = i as f32 / N as f32 * std::f32::consts::TAU;
            centre + (right * a.cos() + up * a.sin()) * radius
        };
        for i in 0..N {
            self.line(at(i), at(i + 1), color, width);
        }
    }

    /// A line from `a` to `b` with a head at `b`.
    pub fn arrow(&mut self, a: Vec3, b: Vec3, view: &View, color: Color, width: f32) {
        self.line(a, b, color, width);
        let d = b - a;
        let len = d.length();
        if len <= 0.0 {
            return;
        }
        let (_, _, forward) = view.0.basis();
        let side = d.cross(forward).normalize_or_zero() * len * 0.06;
        let back = b - d * 0.12;
        self.line(b, back + side, color, width);
        self.line(b, back - side, color, width);
    }
}

/// A colour as egui's: its sRGB channels quantised as the core writes a picture's
/// (`image_out::to_u8`), alpha too; the panels' display colours come as
/// `Color::srgb_from_array`.
pub fn color32(c: Color) -> egui::Color32 {
    let s = c.to_srgba();
    let [r, g, b] = voxcast_core::image_out::to_u8(Vec3::new(s.red, s.green, s.blue));
    let [a, _, _] = voxcast_core::image_out::to_u8(Vec3::splat(s.alpha));
    egui::Color32::from_rgba_unmultiplied(r, g, b, a)
}

/// Projects world points into the viewport through the main camera.
pub struct Projector {
    pub view: voxcast_core::camera::Camera,
    pub rect: egui::Rect,
}

impl Projector {
    /// Where `p` appears in the viewport (`None` behind the eye).
    pub fn at(&self, p: Vec3) -> Option<egui::Pos2> {
        let (w, h) = (self.rect.width(), self.rect.height());
        let (x, y) = self.view.project(p, w.max(1.0) as u32, h.max(1.0) as u32)?;
        // Image positions scale with the true (fractional) size of the viewport.
        Some(self.rect.min + egui::vec2(x * w / w.floor().max(1.0), y * h / h.floor().max(1.0)))
    }

    /// The segment a–b, clipped to the part in front of the eye.
    pub fn segment(&self, a: Vec3, b: Vec3) -> Option<[egui::Pos2; 2]> {
        let (eye, f) = (self.view.eye, self.view.forward());
        let near = 1e-3 * (self.view.target - eye).length();
        let (da, db) = ((a - eye).dot(f), (b - eye).dot(f));
        if da < near && db < near {
            return None;
        }
        let clip = |p: Vec3, q: Vec3, dp: f32, dq: f32| {
            if dp >= near {
                p
            } else {
                p + (q - p) * ((near - dp) / (dq - dp))
            }
        };
        Some([self.at(clip(a, b, da, db))?, self.at(clip(b, a, db, da))?])
    }
}

/// A painter into the scene's viewport (beneath every panel, clipped to it) and the projector
/// that maps world points into it through the main camera's `view`.
pub fn scene_painter(
    ctx: &egui::Context,
    viewport: Option<&Viewport>,
    view: &View,
) -> (Projector, egui::Painter) {
    let rect = Viewport::rect(viewport, ctx);
    let painter = ctx
        .layer_painter(egui::LayerId::background())
        .with_clip_rect(rect);
    (Projector { view: view.0, rect }, painter)
}

pub(crate) fn plugin(app: &mut App) {
    // The features draw their lines in any order: each only adds its own, and the order they
    // are painted in is not seen (no two features' lines are meant to overlap).
    app.init_resource::<OverlayLines>()
        .allow_ambiguous_resource::<OverlayLines>()
        .add_systems(
            bevy_egui::EguiPrimaryContextPass,
            paint_overlay.in_set(crate::sandbox::shared::schedule::Paint::Over),
        );
}

/// Paints this frame's segments into the viewport, then forgets them.
fn paint_overlay(
    mut contexts: EguiContexts,
    mut lines: ResMut<OverlayLines>,
    views: Query<&View, With<MainCamera>>,
    viewport: Option<Res<Viewport>>,
) -> Result {
    let segments = std::mem::take(&mut lines.segments);
    let Ok(view) = views.single() else {
        return Ok(());
    };
    let (projector, painter) = scene_painter(contexts.ctx_mut()?, viewport.as_deref(), view);
    for (a, b, color, width) in segments {
        if let Some(points) = projector.segment(a, b) {
            painter.line_segment(points, egui::Stroke::new(width, color));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_projects_into_the_viewport_and_behind_is_clipped() {
        let view = voxcast_core::camera::Camera::new(
            Vec3::new(0.0, 0.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            voxcast_core::camera::Projection::Perspective { fov_y_deg: 60.0 },
        )
        .unwrap();
        let rect = egui::Rect::from_min_size(egui::pos2(100.0, 50.0), egui::vec2(400.0, 300.0));
        let p = Projector { view, rect };
        let centre = p.at(Vec3::ZERO).unwrap();
        assert!((centre - rect.center()).length() < 1e-3, "{centre:?}");
        // A segment from in front to behind the eye keeps its front part.
        let s = p.segment(Vec3::ZERO, Vec3::new(0.0, 0.0, 20.0)).unwrap();
        assert!((s[0] - rect.center()).length() < 1e-3);
        assert!(
            p.segment(Vec3::new(0.0, 0.0, 11.0), Vec3::new(1.0, 0.0, 12.0))
                .is_none()
        );
    }
}
