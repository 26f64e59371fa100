//! The step size's trade of speed for accuracy, measured: one view rendered at several steps,
//! each timed, its samples counted and its error taken against a reference render at a much
//! finer step, always with trilinear interpolation (the best reconstruction the core has), so
//! with nearest interpolation the error shows what the staircase costs as well. The sampling
//! and interpolation levels show these numbers; `voxcast bench` measures the same trade with
//! repeats and the peer.

use crate::camera::Camera;
use crate::error::SettingsError;
use crate::render::{Cancelled, render};
use crate::sample::Interpolation;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use crate::step::Length;
use crate::transfer::TransferFunction;
use crate::volume::Volume;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// The steps (voxels) the sampling level measures, besides the player's own.
pub const STEPS: [f32; 4] = [2.0, 1.0, 0.5, 0.25];
/// The reference step (voxels): sixteen samples per voxel.
pub const REFERENCE: f32 = 1.0 / 16.0;

/// One step's render against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeRow {
    pub step_voxels: f32,
    /// Wall-clock seconds of the render (one run, every core).
    pub seconds: f64,
    /// Samples interpolated over all rays.
    pub samples: u64,
    /// Largest and root-mean-square difference from the reference, per channel (0–1).
    pub max_error: f32,
    pub rmse: f32,
}

/// The trade: the reference's own cost, then one row per step, finest last.
#[derive(Clone, Debug, PartialEq)]
pub struct Trade {
    pub reference_voxels: f32,
    pub reference_seconds: f64,
    pub reference_samples: u64,
    pub rows: Vec<TradeRow>,
}

/// Why a trade has no result.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum TradeError {
    #[error(transparent)]
    Settings(#[from] SettingsError),
    #[error(transparent)]
    Cancelled(#[from] Cancelled),
}

/// Renders `camera`'s view (`width`×`height`) with `settings` at the reference step and at each
/// of `steps` (voxels, sorted coarsest first, duplicates dropped); `progress(done, total)`
/// counts renders.
#[allow(clippy::too_many_arguments)]
pub fn step_trade(
    volume: &Volume,
    transfer: &TransferFunction,
    settings: &RenderSettings,
    camera: &Camera,
    (width, height): (u32, u32),
    steps: &[f32],
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<Trade, TradeError> {
    let mut steps: Vec<f32> = steps.to_vec();
    steps.sort_by(|a, b| b.total_cmp(a));
    steps.dedup();
    let total = steps.len() + 1;
    let timed = |step: f32, interpolation: Interpolation| -> Result<_, TradeError> {
        let mut s = settings.clone();
        s.step = Length::Voxels(step);
        s.interpolation = interpolation;
        // Jitter would add noise the reference does not share.
        s.jitter = false;
        let scene = Scene::new(volume, transfer, &s, camera.forward())?;
        let start = Instant::now();
        let (image, stats) = render(&scene, camera, width, height, &|_, _| {}, cancel)?;
        Ok((image, stats.samples, start.elapsed().as_secs_f64()))
    };
    progress(0, total);
    let (reference, reference_samples, reference_seconds) =
        timed(REFERENCE, Interpolation::Trilinear)?;
    let mut rows = Vec::with_capacity(steps.len());
    for (i, &step) in steps.iter().enumerate() {
        progress(i + 1, total);
        let (image, samples, seconds) = timed(step, settings.interpolation)?;
        let diff = image.diff(&reference).expect("the same size");
        rows.push(TradeRow {
            step_voxels: step,
            seconds,
            samples,
            max_error: diff.max_abs,
            rmse: diff.rmse as f32,
        });
    }
    progress(total, total);
    Ok(Trade {
        reference_voxels: REFERENCE,
        reference_seconds,
        reference_samples,
        rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::bucky;

    fn trade(steps: &[f32]) -> Trade {
        trade_with(steps, Interpolation::Trilinear)
    }

    fn trade_with(steps: &[f32], interpolation: Interpolation) -> Trade {
        let v = bucky();
        let p = crate::preset::for_volume("bucky").unwrap();
        let mut s = p.settings_over(&RenderSettings::default()).unwrap();
        s.interpolation = interpolation;
        let (lo, hi) = v.bounds();
        let cam = Camera::framing(lo, hi, glam::Vec3::new(1.0, 0.8, 1.4), glam::Vec3::Y).unwrap();
        step_trade(
            &v,
            &p.transfer,
            &s,
            &cam,
            (48, 48),
            steps,
            &|_, _| {},
            &AtomicBool::new(false),
        )
        .unwrap()
    }

    /// Finer steps take proportionally more samples and err less; the reference itself is
    /// the finest of all.
    #[test]
    fn finer_steps_cost_more_samples_and_err_less() {
        let t = trade(&[0.25, 2.0, 1.0, 0.5, 1.0]);
        let steps: Vec<f32> = t.rows.iter().map(|r| r.step_voxels).collect();
        assert_eq!(steps, [2.0, 1.0, 0.5, 0.25], "sorted, duplicates dropped");
        for w in t.rows.windows(2) {
            let ratio = w[1].samples as f64 / w[0].samples as f64;
            assert!(
                (1.7..2.3).contains(&ratio),
                "halving the step: ×{ratio} samples"
            );
            assert!(w[1].rmse < w[0].rmse, "{w:?}");
        }
        assert!(t.reference_samples > t.rows[3].samples * 3);
        assert!(t.rows.iter().all(|r| r.max_error >= r.rmse && r.rmse > 0.0));
    }

    #[test]
    fn the_reference_against_itself_has_no_error_and_cancel_stops() {
        let t = trade(&[REFERENCE]);
        assert_eq!(t.rows[0].max_error, 0.0);
        assert_eq!(t.rows[0].samples, t.reference_samples);
        let v = bucky();
        let tf = TransferFunction::ramp(0.0, 255.0, 0.5).unwrap();
        let (lo, hi) = v.bounds();
        let cam = Camera::framing(lo, hi, glam::Vec3::Z, glam::Vec3::Y).unwrap();
        let r = step_trade(
            &v,
            &tf,
            &RenderSettings::default(),
            &cam,
            (8, 8),
            &STEPS,
            &|_, _| {},
            &AtomicBool::new(true),
        );
        assert_eq!(r, Err(TradeError::Cancelled(Cancelled)));
    }

    /// The reference is trilinear whatever the settings: nearest interpolation errs more than
    /// trilinear at every step, and keeps erring at the finest (its staircase does not go away).
    #[test]
    fn nearest_is_measured_against_the_trilinear_reference() {
        let tri = trade_with(&[1.0, 0.25], Interpolation::Trilinear);
        let near = trade_with(&[1.0, 0.25], Interpolation::Nearest);
        for (t, n) in tri.rows.iter().zip(&near.rows) {
            assert!(
                n.rmse > 2.0 * t.rmse,
                "{} vs {} at {}",
                n.rmse,
                t.rmse,
                t.step_voxels
            );
        }
        assert!(
            near.rows[1].rmse > 0.5 * near.rows[0].rmse,
            "the staircase stays"
        );
    }
}
