//! Sample placement along a ray: where each sample sits and what length of ray it stands for.
//!
//! Twin: `shaders/step.wgsl` (`plan_steps`, `sample_t`, `segment_length`).
//!
//! Inside `[t_enter, t_exit]` (world units along the ray), sample `k` sits at
//!
//! ```text
//! t_k = t_enter + (j + k)·dt,   k = 0, 1, … while t_k ≤ t_exit,
//! ```
//!
//! with `j = 0`, or with jitter a per-pixel fraction in `[0, 1)` from [`crate::hash`]. So there are
//! `floor((t_exit − t_enter)/dt − j) + 1` samples (none when jitter pushes the first one out),
//! limited by the sample cap, which stops the ray and says so rather than hang on a tiny step.
//!
//! Each sample stands for the stretch of ray nearer to it than to its neighbours (its "cell"
//! along the ray); the first cell starts at `t_enter` and the last ends at `t_exit`:
//!
//! ```text
//! ds_k = (k last ? t_exit : t_k + dt/2) − (k = 0 ? t_enter : t_k − dt/2)
//! ```
//!
//! Interior samples get exactly `dt`; the first and last get what is left (up to `1.5·dt`), and
//! the lengths sum to `t_exit − t_enter`. (When the cap cuts the ray, its last sample is not the
//! ray's last and keeps `t_k + dt/2`.) Opacity correction uses `ds_k`, which makes constant density give
//! Beer–Lambert exactly for any step (see [`crate::composite`]).

use crate::error::SettingsError;
use serde::{Deserialize, Serialize};

/// A length given in voxels (of the smallest spacing) or in world units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Length {
    Voxels(f32),
    World(f32),
}

impl Length {
    /// In world units, for a volume whose smallest spacing is `voxel`.
    pub fn world(self, voxel: f32) -> f32 {
        match self {
            Length::Voxels(v) => v * voxel,
            Length::World(w) => w,
        }
    }

    /// The same length `factor` times longer, in the same unit.
    pub fn scaled(self, factor: f32) -> Length {
        match self {
            Length::Voxels(v) => Length::Voxels(v * factor),
            Length::World(w) => Length::World(w * factor),
        }
    }

    /// In voxels of the smallest spacing `voxel`.
    pub fn voxels(self, voxel: f32) -> f32 {
        match self {
            Length::Voxels(v) => v,
            Length::World(w) => w / voxel,
        }
    }

    pub fn validate(self, name: &'static str) -> Result<(), SettingsError> {
        let v = match self {
            Length::Voxels(v) | Length::World(v) => v,
        };
        SettingsError::check_positive(name, v)
    }
}

/// The samples of one ray.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StepPlan {
    pub t_enter: f32,
    pub t_exit: f32,
    /// World units between samples.
    pub dt: f32,
    /// Jitter fraction `j` in `[0, 1)`.
    pub jitter: f32,
    /// Samples that will be taken (after the cap).
    pub count: u32,
    /// True when the cap cut the ray short.
    pub capped: bool,
}

/// Plans the samples for `[t_enter, t_exit]` at step `dt` with jitter fraction `jitter`,
/// taking at most `max_samples`.
#[inline]
pub fn plan_steps(t_enter: f32, t_exit: f32, dt: f32, jitter: f32, max_samples: u32) -> StepPlan {
    let span = (t_exit - t_enter) / dt - jitter;
    // `span` ≥ 0 → floor(span) + 1 samples; computed in f32 like the GPU twin. A span too large
    // for u32 saturates, and the cap applies.
    let wanted = if span >= 0.0 { floor(span) + 1.0 } else { 0.0 };
    let capped = wanted > max_samples as f32;
    let count = if capped { max_samples } else { wanted as u32 };
    StepPlan {
        t_enter,
        t_exit,
        dt,
        jitter,
        count,
        capped,
    }
}

/// Where sample `k` sits: `t_enter + (j + k)·dt`, never past `t_exit`.
#[inline(always)]
pub fn sample_t(plan: &StepPlan, k: u32) -> f32 {
    crate::minmax::fmin(
        plan.t_enter + (plan.jitter + k as f32) * plan.dt,
        plan.t_exit,
    )
}

/// The length of ray sample `k` (at `t_k`) stands for (see the module docs).
#[inline(always)]
pub fn segment_length(plan: &StepPlan, k: u32, t_k: f32) -> f32 {
    let half = 0.5 * plan.dt;
    let last = k + 1 == plan.count && !plan.capped;
    if k > 0 && !last && t_k + half <= plan.t_exit {
        // An interior sample: `(t_k + dt/2) − (t_k − dt/2)` is `dt` exactly; computed in
        // floats it would be `dt` give or take the rounding of `t_k`.
        return plan.dt;
    }
    let start = if k == 0 { plan.t_enter } else { t_k - half };
    let end = if last {
        plan.t_exit
    } else {
        (t_k + half).min(plan.t_exit)
    };
    (end - start).max(0.0)
}

/// The index of the first sample at or after `t` (`inv_dt` = 1/dt), at most `count`: where a
/// ray resumes after skipping to `t`.
#[inline(always)]
pub fn first_index_from(plan: &StepPlan, t: f32, inv_dt: f32) -> u32 {
    first_index_with(plan, t, inv_dt, ceil)
}

/// [`first_index_from`] with the ceiling given: one a caller with SSE 4.1 takes in a single
/// instruction (the lanes' leaps) gives the same index, the clamping being this one.
#[inline(always)]
pub(crate) fn first_index_with(
    plan: &StepPlan,
    t: f32,
    inv_dt: f32,
    ceil: impl Fn(f32) -> f32,
) -> u32 {
    let k = ceil((t - plan.t_enter) * inv_dt - plan.jitter);
    if k <= 0.0 {
        0
    } else if k >= plan.count as f32 {
        plan.count
    } else {
        k as u32
    }
}

/// `x.floor()` without the library call that baseline x86-64 makes of it (no SSE4.1
/// `roundss`; it was 1 % of a render, once per ray).
#[inline(always)]
fn floor(x: f32) -> f32 {
    if x.is_nan() || x.abs() >= 8_388_608.0 {
        return x; // already whole (or infinite/NaN)
    }
    let i = x as i32 as f32;
    // Truncation rounds towards zero; below zero that is up. (−0.0 gives 0.0: the same count.)
    if i > x { i - 1.0 } else { i }
}

/// `x.ceil()` without the library call that baseline x86-64 makes of it (no SSE4.1 `roundss`).
#[inline(always)]
fn ceil(x: f32) -> f32 {
    if x.is_nan() || x.abs() >= 8_388_608.0 {
        return x; // already whole (or infinite/NaN)
    }
    let i = x as i32 as f32;
    if i < x { i + 1.0 } else { i }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scaling_keeps_the_unit() {
        assert_eq!(Length::Voxels(0.5).scaled(2.0), Length::Voxels(1.0));
        assert_eq!(Length::World(0.25).scaled(4.0), Length::World(1.0));
        assert_eq!(Length::World(3.0).scaled(2.0).world(7.0), 6.0);
    }

    #[test]
    fn counts_positions_and_lengths() {
        let p = plan_steps(1.0, 3.0, 0.5, 0.0, 100);
        assert_eq!(p.count, 5);
        let ts: Vec<f32> = (0..p.count).map(|k| sample_t(&p, k)).collect();
        assert_eq!(ts, vec![1.0, 1.5, 2.0, 2.5, 3.0]);
        let ds: Vec<f32> = ts
            .iter()
            .enumerate()
            .map(|(k, &t)| segment_length(&p, k as u32, t))
            .collect();
        assert_eq!(ds, vec![0.25, 0.5, 0.5, 0.5, 0.25]);
    }

    /// Far from the origin, where `t_k ± dt/2` round, an interior sample still stands for `dt`
    /// exactly (so opacity correction sees the step the user chose, not its rounding).
    #[test]
    fn interior_samples_stand_for_exactly_the_step() {
        let p = plan_steps(1234.567, 1300.1, 0.2392578, 0.37, 1 << 20);
        assert!(p.count > 10);
        for k in 1..p.count - 1 {
            assert_eq!(segment_length(&p, k, sample_t(&p, k)), p.dt, "sample {k}");
        }
        assert!(segment_length(&p, 0, sample_t(&p, 0)) <= 1.5 * p.dt);
    }

    #[test]
    fn lengths_sum_to_the_span_for_any_step_and_jitter() {
        for &(dt, j) in &[(0.3f32, 0.0f32), (0.7, 0.5), (1e3, 0.0), (0.001, 0.99)] {
            let p = plan_steps(0.0, 2.0, dt, j, 1 << 20);
            let sum: f64 = (0..p.count)
                .map(|k| segment_length(&p, k, sample_t(&p, k)) as f64)
                .sum();
            let expect = if p.count == 0 { 0.0 } else { 2.0 };
            assert!((sum - expect).abs() < 1e-3, "dt {dt} j {j}: {sum}");
        }
    }

    #[test]
    fn huge_step_gives_one_sample_and_tiny_step_hits_the_cap() {
        let p = plan_steps(0.0, 10.0, 1e3, 0.0, 65536);
        assert_eq!((p.count, p.capped), (1, false));
        let p = plan_steps(0.0, 10.0, 1e-6, 0.0, 65536);
        assert_eq!((p.count, p.capped), (65536, true));
        // A zero-length span (a corner) still gets its one sample.
        assert_eq!(plan_steps(2.0, 2.0, 0.5, 0.0, 10).count, 1);
        // Jitter can push the only sample out.
        assert_eq!(plan_steps(0.0, 0.1, 1.0, 0.5, 10).count, 0);
    }

    #[test]
    fn fast_ceil_and_floor_match_the_library() {
        for x in [
            -2.5f32,
            -2.0,
            -0.1,
            0.0,
            0.3,
            1.0,
            1.0001,
            7.9e6,
            1e9,
            f32::INFINITY,
        ] {
            assert_eq!(ceil(x), x.ceil(), "{x}");
            assert_eq!(floor(x), x.floor(), "{x}");
        }
        // Every 4099th bit pattern: both signs, every exponent, subnormals, NaNs.
        for bits in (0..u32::MAX).step_by(4099) {
            let x = f32::from_bits(bits);
            if !x.is_nan() {
                assert_eq!(ceil(x), x.ceil(), "{x}");
                assert_eq!(floor(x), x.floor(), "{x}");
            }
        }
    }

    #[test]
    fn resuming_after_a_skip() {
        let p = plan_steps(0.0, 10.0, 0.5, 0.0, 100);
        assert_eq!(first_index_from(&p, 2.0, 2.0), 4);
        assert_eq!(first_index_from(&p, 2.1, 2.0), 5);
        assert_eq!(first_index_from(&p, -3.0, 2.0), 0);
        assert_eq!(first_index_from(&p, f32::INFINITY, 2.0), p.count);
    }

    #[test]
    fn lengths_convert() {
        assert_eq!(Length::Voxels(2.0).world(0.5), 1.0);
        assert_eq!(Length::World(2.0).voxels(0.5), 4.0);
        assert!(Length::Voxels(0.0).validate("step").is_err());
        assert!(Length::World(f32::NAN).validate("step").is_err());
    }
}
