//! The step size's trade of speed for accuracy, measured: one view rendered at several steps,
//! its samples counted and its error taken against a reference render at a much finer step,
//! always with trilinear interpolation (the best reconstruction the core has), so with nearest
//! interpolation the error shows what the staircase costs as well. The sampling and
//! interpolation levels show these numbers; `voxcast bench` measures the same trade with the
//! peer.
//!
//! Timed as the benchmark times: the first render of each setting (the one the error is taken
//! from) warms the caches and is not counted; then [`TIMED_RUNS`] rounds render every setting
//! once, the reference included, in alternating order (forwards, then backwards, so that no
//! setting always follows the same one), and each setting's time is the median of its runs,
//! with their fastest and slowest as its spread. A render's time is the time of its own slices
//! ([`crate::slices`]): the frames the window draws between them are not counted.

use crate::camera::Camera;
use crate::error::SettingsError;
use crate::image_out::LinearImage;
use crate::knob::Knob;
use crate::prepared::Prepared;
use crate::render::{Cancelled, Job, TileSlices, render_in};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use crate::slices::{Deadline, Step};
use crate::transfer::TransferFunction;
use std::sync::atomic::AtomicBool;
use web_time::Instant;

/// The steps (voxels) the sampling level measures, besides the player's own.
pub const STEPS: [f32; 4] = [2.0, 1.0, 0.5, 0.25];
/// The reference step (voxels): sixteen samples per voxel.
#[cfg(test)]
pub const REFERENCE: f32 = crate::knob::REFERENCE_STEP;
/// Timed renders of each setting, after one untimed (see the module docs).
pub const TIMED_RUNS: usize = 5;

/// The median, fastest and slowest of some runs' seconds.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Timing {
    pub median: f64,
    pub fastest: f64,
    pub slowest: f64,
}

impl Timing {
    /// Of `runs` seconds (zeros where there are none).
    pub fn of(runs: &[f64]) -> Self {
        let Some(median) = crate::numbers::median(runs) else {
            return Self::default();
        };
        Self {
            median,
            fastest: runs.iter().copied().fold(f64::INFINITY, f64::min),
            slowest: runs.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        }
    }
}

/// One setting's render against the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct TradeRow {
    /// The knob's value, in words ("0.5", "nearest", "2×2", "×4").
    pub label: String,
    /// The row's step (voxels).
    pub step_voxels: f32,
    /// Median wall-clock seconds of its timed renders (every core of the render's pool).
    pub seconds: f64,
    /// Their median, fastest and slowest.
    pub timing: Timing,
    /// Samples interpolated over all rays.
    pub samples: u64,
    /// Largest and root-mean-square difference from the reference, per channel (0–1).
    pub max_error: f32,
    pub rmse: f32,
}

/// The trade: the reference's own cost, then one row per setting tried, cheapest first.
#[derive(Clone, Debug, PartialEq)]
pub struct Trade {
    pub knob: Knob,
    /// The reference, in words.
    pub reference: String,
    pub reference_voxels: f32,
    pub reference_seconds: f64,
    pub reference_timing: Timing,
    pub reference_samples: u64,
    pub rows: Vec<TradeRow>,
    /// Timed renders per setting, and the threads each render ran on.
    pub runs: usize,
    pub threads: usize,
}

impl Trade {
    /// The trade as a markdown table headed by the knob and its reference: each setting's
    /// median time, its fastest–slowest, samples, errors and speed-up (`voxcast bench
    /// --knobs`, `voxcast --measure-knob`).
    pub fn markdown(&self) -> String {
        use std::fmt::Write as _;
        let mut out = String::new();
        let knob = self.knob;
        let _ = writeln!(out, "**{}** — against {}.\n", knob.label(), self.reference);
        let _ = writeln!(
            out,
            "| {} | time (ms) | fastest–slowest (ms) | samples | max error (/255) | RMSE (/255) | speed-up |",
            knob.label().to_lowercase()
        );
        let _ = writeln!(out, "| --- | ---: | ---: | ---: | ---: | ---: | ---: |");
        let spread = |t: &Timing| format!("{:.1}–{:.1}", t.fastest * 1e3, t.slowest * 1e3);
        for r in &self.rows {
            let _ = writeln!(
                out,
                "| {} | {:.1} | {} | {} | {:.1} | {:.2} | ×{:.1} |",
                r.label,
                r.seconds * 1e3,
                spread(&r.timing),
                r.samples,
                r.max_error * 255.0,
                r.rmse * 255.0,
                self.reference_seconds / r.seconds.max(1e-9)
            );
        }
        let _ = writeln!(
            out,
            "| {} (reference) | {:.1} | {} | {} | 0 | 0 | ×1 |\n",
            self.reference,
            self.reference_seconds * 1e3,
            spread(&self.reference_timing),
            self.reference_samples
        );
        out
    }
}

/// Why a trade has no result.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum TradeError {
    #[error(transparent)]
    Settings(#[from] SettingsError),
    #[error(transparent)]
    Cancelled(#[from] Cancelled),
}

/// The step's trade: [`trade`] of [`Knob::Step`] at `steps` (voxels; sorted coarsest first,
/// duplicates dropped).
pub fn step_trade(
    view: &View,
    settings: &RenderSettings,
    steps: &[f32],
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<Trade, TradeError> {
    trade(view, settings, Knob::Step, steps, progress, cancel)
}

/// What a trade renders: a volume and transfer function seen by a camera at a size.
pub struct View<'a> {
    pub volume: &'a Prepared,
    pub transfer: &'a TransferFunction,
    pub camera: &'a Camera,
    pub size: (u32, u32),
}

/// Renders the view with `settings` at `knob`'s reference and at each of its tries
/// ([`Knob::tries`]; `steps` for the step knob), timing each and taking its error against the
/// reference; `progress(done, total)` counts renders.
pub fn trade(
    view: &View<'_>,
    settings: &RenderSettings,
    knob: Knob,
    steps: &[f32],
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &AtomicBool,
) -> Result<Trade, TradeError> {
    let job = TradeJob {
        view,
        settings,
        knob,
        steps,
        progress,
        cancel,
    };
    trade_in(&job, &mut TradeSlices::default(), Deadline::NONE).map(Step::whole)
}

/// What a trade measures, and who watches it: [`trade`]'s arguments.
#[derive(Clone, Copy)]
pub struct TradeJob<'x, 'a> {
    pub view: &'x View<'a>,
    pub settings: &'x RenderSettings,
    pub knob: Knob,
    pub steps: &'x [f32],
    pub progress: &'x (dyn Fn(usize, usize) + Sync),
    pub cancel: &'x AtomicBool,
}

/// A trade's work kept between slices ([`crate::slices`]): the renders finished (the
/// reference first) with their samples, the timed runs so far (per setting, the reference
/// first), and the render under way with the seconds it has taken so far (a render's time is
/// its slices' time, not the frames drawn between them).
#[derive(Clone, Debug, Default)]
pub struct TradeSlices {
    finished: Vec<(LinearImage, u64)>,
    runs: Vec<Vec<f64>>,
    /// Timed renders done, over all rounds.
    timed: usize,
    current: TileSlices,
    seconds: f64,
}

/// Which setting the `k`-th timed render renders, of `total`: rounds alternate forwards and
/// backwards (the sandbox times the preview's frames in the same order).
pub fn timed_order(k: usize, total: usize) -> usize {
    let (round, i) = (k / total, k % total);
    if round % 2 == 0 { i } else { total - 1 - i }
}

/// [`trade`] in slices: its renders' tiles up to `deadline`, kept in `slices`.
pub fn trade_in(
    job: &TradeJob<'_, '_>,
    slices: &mut TradeSlices,
    deadline: Deadline,
) -> Result<Step<Trade>, TradeError> {
    let (view, settings, knob) = (job.view, job.settings, job.knob);
    let voxel = view.volume.spacing().min_element();
    let tries = knob.tries(settings, voxel, job.steps);
    let reference_try = knob.reference(settings);
    let total = tries.len() + 1;
    let renders = total * (1 + TIMED_RUNS);
    let try_at = |i: usize| {
        if i == 0 {
            &reference_try
        } else {
            &tries[i - 1]
        }
    };
    // The untimed renders, whose images the errors are taken from; then the timed rounds.
    while slices.finished.len() < total {
        let i = slices.finished.len();
        (job.progress)(i, renders);
        // Its seconds are the warm-up's: not counted.
        let Some((image, samples, _)) = render_try(job, try_at(i), slices, deadline)? else {
            return Ok(Step::Paused);
        };
        slices.finished.push((image, samples));
        if deadline.passed() {
            return Ok(Step::Paused);
        }
    }
    slices.runs.resize(total, Vec::new());
    while slices.timed < total * TIMED_RUNS {
        (job.progress)(total + slices.timed, renders);
        let i = timed_order(slices.timed, total);
        let Some((_, _, seconds)) = render_try(job, try_at(i), slices, deadline)? else {
            return Ok(Step::Paused);
        };
        slices.runs[i].push(seconds);
        slices.timed += 1;
        if deadline.passed() {
            return Ok(Step::Paused);
        }
    }
    (job.progress)(renders, renders);
    let (reference, reference_samples) = &slices.finished[0];
    let timings: Vec<Timing> = slices.runs.iter().map(|r| Timing::of(r)).collect();
    let rows = tries
        .iter()
        .zip(&slices.finished[1..])
        .zip(&timings[1..])
        .map(|((t, (image, samples)), timing)| {
            let diff = image.diff(reference).expect("the same size");
            TradeRow {
                label: t.label.clone(),
                step_voxels: t.settings.step.voxels(voxel),
                seconds: timing.median,
                timing: *timing,
                samples: *samples,
                max_error: diff.max_abs,
                rmse: diff.rmse as f32,
            }
        })
        .collect();
    Ok(Step::Done(Trade {
        knob,
        reference: reference_try.label,
        reference_voxels: reference_try.settings.step.voxels(voxel),
        reference_seconds: timings[0].median,
        reference_timing: timings[0],
        reference_samples: *reference_samples,
        rows,
        runs: TIMED_RUNS,
        threads: crate::render::threads(),
    }))
}

/// Renders `t` at the view's size (its own scale, then resized), in slices up to `deadline`:
/// `None` while it is unfinished, else its image, its samples and the seconds of its slices
/// (kept in `slices.seconds` between calls, and cleared for the next render).
fn render_try(
    job: &TradeJob<'_, '_>,
    t: &crate::knob::Try,
    slices: &mut TradeSlices,
    deadline: Deadline,
) -> Result<Option<(LinearImage, u64, f64)>, TradeError> {
    let view = job.view;
    let (w, h) = view.size;
    let scene = Scene::new(
        view.volume,
        view.transfer,
        &t.settings,
        view.camera.forward(),
    )?;
    let (sw, sh) = (
        ((w as f32 * t.scale).round() as u32).max(1),
        ((h as f32 * t.scale).round() as u32).max(1),
    );
    let start = Instant::now();
    let render = Job::plain(&scene, view.camera, (sw, sh), &|_, _| {}, job.cancel);
    let step = render_in(&render, &mut slices.current, deadline)?;
    slices.seconds += start.elapsed().as_secs_f64();
    let Step::Done((image, stats)) = step else {
        return Ok(None);
    };
    slices.current = TileSlices::default();
    let seconds = std::mem::take(&mut slices.seconds);
    let image = if (sw, sh) == (w, h) {
        image
    } else {
        image.resized_bilinear(w, h)
    };
    Ok(Some((image, stats.samples, seconds)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::bucky;
    use crate::sample::Interpolation;

    fn trade(steps: &[f32]) -> Trade {
        trade_with(steps, Interpolation::Trilinear)
    }

    fn trade_with(steps: &[f32], interpolation: Interpolation) -> Trade {
        let (v, transfer, mut s, cam) = bucky_scene();
        s.interpolation = interpolation;
        step_trade(
            &View {
                volume: &v,
                transfer: &transfer,
                camera: &cam,
                size: (48, 48),
            },
            &s,
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
        let v = crate::Prepared::from(bucky());
        let tf = TransferFunction::ramp(0.0, 255.0, 0.5).unwrap();
        let (lo, hi) = v.bounds();
        let cam = Camera::framing(lo, hi, glam::Vec3::Z, glam::Vec3::Y).unwrap();
        let r = step_trade(
            &View {
                volume: &v,
                transfer: &tf,
                camera: &cam,
                size: (8, 8),
            },
            &RenderSettings::default(),
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

    /// Every other knob: its reference against itself has no error where it is one of its
    /// tries; the cheaper setting errs more.
    /// The bucky cage with its preset, seen from above one side.
    fn bucky_scene() -> (crate::Prepared, TransferFunction, RenderSettings, Camera) {
        let v = crate::Prepared::from(bucky());
        let p = crate::preset::for_volume("bucky").unwrap();
        let s = p.settings_over(&RenderSettings::default()).unwrap();
        let (lo, hi) = v.bounds();
        let cam = Camera::framing(lo, hi, glam::Vec3::new(1.0, 0.8, 1.4), glam::Vec3::Y).unwrap();
        (v, p.transfer, s, cam)
    }

    #[test]
    fn every_knob_is_measured_against_its_own_exact_setting() {
        let (v, transfer, s, cam) = bucky_scene();
        let view = View {
            volume: &v,
            transfer: &transfer,
            camera: &cam,
            size: (40, 40),
        };
        let run = |k: Knob| {
            super::trade(&view, &s, k, &STEPS, &|_, _| {}, &AtomicBool::new(false)).unwrap()
        };
        let preview = run(Knob::PreviewScale);
        assert!(
            preview.rows[0].rmse > preview.rows[2].rmse,
            "a quarter errs more than ¾"
        );
        assert!(preview.rows[0].samples * 8 < preview.reference_samples);
        let multiplier = run(Knob::PreviewStepMultiplier);
        assert!(
            multiplier.rows[0].rmse > multiplier.rows[2].rmse,
            "×8 errs more than ×2"
        );
        let cutoff = run(Knob::Cutoff);
        assert!(cutoff.rows[0].max_error >= cutoff.rows[3].max_error);
        assert!(
            cutoff.rows[3].max_error <= 0.01 + 1.0 / 255.0,
            "at most 1 − cutoff"
        );
        let supersampling = run(Knob::Supersampling);
        let ratio = supersampling.rows[1].samples as f64 / supersampling.rows[0].samples as f64;
        assert!((3.0..5.0).contains(&ratio), "2×2 rays cost ×{ratio}");
        assert!(supersampling.rows[0].rmse > supersampling.rows[3].rmse);
        let interpolation = run(Knob::Interpolation);
        assert_eq!(interpolation.rows[0].label, "nearest");
        assert!(interpolation.rows[0].rmse > interpolation.rows[1].rmse);
        assert_eq!(run(Knob::Jitter).rows.len(), 4);
        // The moving frame as a whole: the cheapest errs most and costs least; every one is
        // cheaper than the resting frame.
        let adaptive = run(Knob::AdaptiveQuality);
        assert!(adaptive.rows[0].rmse > adaptive.rows[3].rmse);
        assert!(adaptive.rows[0].samples < adaptive.rows[3].samples);
        assert!(
            adaptive
                .rows
                .iter()
                .all(|r| r.samples < adaptive.reference_samples)
        );
    }

    /// Each row is timed [`TIMED_RUNS`] times after its untimed render, in alternating order;
    /// on a scene whose cost is its samples (halving the step doubles them), the times rise
    /// from the coarsest step to the reference within their spread.
    #[test]
    fn the_times_are_medians_of_alternating_runs_and_rise_with_the_samples() {
        assert_eq!(
            (0..12).map(|k| timed_order(k, 3)).collect::<Vec<_>>(),
            [0, 1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0]
        );
        assert_eq!(
            Timing::of(&[3.0, 1.0, 2.0, 9.0]),
            Timing {
                median: 2.5,
                fastest: 1.0,
                slowest: 9.0
            }
        );
        let (v, transfer, s, cam) = bucky_scene();
        let t = step_trade(
            &View {
                volume: &v,
                transfer: &transfer,
                camera: &cam,
                size: (64, 64),
            },
            &s,
            &STEPS,
            &|_, _| {},
            &AtomicBool::new(false),
        )
        .unwrap();
        assert_eq!(t.runs, TIMED_RUNS);
        assert!(t.threads >= 1);
        let timings: Vec<Timing> = t
            .rows
            .iter()
            .map(|r| r.timing)
            .chain([t.reference_timing])
            .collect();
        for (r, timing) in t.rows.iter().zip(&timings) {
            assert_eq!(r.seconds, timing.median);
        }
        for x in &timings {
            assert!(0.0 < x.fastest && x.fastest <= x.median && x.median <= x.slowest);
        }
        for w in timings.windows(2) {
            let (coarse, fine) = (w[0], w[1]);
            let spread = (coarse.slowest - coarse.fastest) + (fine.slowest - fine.fastest);
            assert!(
                fine.median + spread >= coarse.median,
                "a finer step timed faster beyond the spread: {coarse:?} then {fine:?}"
            );
        }
    }

    /// In slices, one tile a call, the trade has the same rows but their times.
    #[test]
    fn a_trade_in_slices_is_the_trade() {
        let (v, transfer, s, cam) = bucky_scene();
        let view = View {
            volume: &v,
            transfer: &transfer,
            camera: &cam,
            size: (20, 20),
        };
        let stop = AtomicBool::new(false);
        let job = TradeJob {
            view: &view,
            settings: &s,
            knob: Knob::Supersampling,
            steps: &STEPS,
            progress: &|_, _| {},
            cancel: &stop,
        };
        let whole = trade_in(&job, &mut TradeSlices::default(), Deadline::NONE)
            .unwrap()
            .whole();
        let mut state = TradeSlices::default();
        let (sliced, calls) = crate::slices::until_done(crate::slices::Duration::ZERO, |d| {
            trade_in(&job, &mut state, d)
        })
        .unwrap();
        assert!(calls > 5 * 4, "{calls} calls: a tile at a time");
        let untimed = |t: &Trade| {
            let mut t = t.clone();
            t.reference_seconds = 0.0;
            t.reference_timing = Timing::default();
            t.rows.iter_mut().for_each(|r| {
                r.seconds = 0.0;
                r.timing = Timing::default();
            });
            t
        };
        assert_eq!(untimed(&sliced), untimed(&whole));
    }
}
