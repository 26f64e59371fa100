//! The skipping marches: the same samples as the plain marches of `trace.rs` (the twin of
//! `shaders/trace.wgsl`), with empty space passed over where that leaves every pixel as it
//! was (`crate::skip`) — Accumulate over bricks and cells the transfer function makes
//! transparent, First through blocks below the target, Maximum and Minimum through blocks
//! that cannot beat the running extreme.

use super::{Accumulation, Marcher, NoRecord, RayOutcome, SKIP_MARGIN_VOXELS, StopReason};
use crate::composite::{Method, ValueStats, reaches};
use crate::minmax::fmax;
use crate::ray::Ray;
use crate::sample::cell;
use crate::shade::Viewing;
use crate::skip::{BlockRanges, BlockWalk, Cell as CellState, VisibleCells, octant};
use crate::step::{StepPlan, first_index_from, sample_t};
use crate::volume::Voxel;
use glam::Vec3;

impl<T: Voxel> Marcher<'_, '_, '_, T> {
    /// Accumulate front to back with empty-space skipping (see `crate::skip`), one sample at a
    /// time along the eight lanes' route (`lanes.rs`): from the pixel's entry bound `from` (no
    /// visible cell before it) to the end of the box of the visible bricks, leaping over empty
    /// bricks by their distance ahead in the ray's octant, taking every sample whose cell can be
    /// seen. The samples passed over lie in cells the transfer function makes transparent, so
    /// the image is the plain march's. Returns the index of the sample that stopped the ray, if
    /// one did.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // the march's per-sample hot path: see trace.rs
    pub(super) fn accumulate_skipping(
        &self,
        cells: &VisibleCells,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        from: f32,
        viewing: &Viewing<'_>,
        stop_at: f32,
        acc: &mut Accumulation,
    ) -> Option<u32> {
        let inv_d = 1.0 / d_v;
        // Multiplying by the inverse step may round an index by one either way; each bound
        // below lies in invisible cells by more than that rounding (`BRICK_MARGIN`).
        let inv_dt = 1.0 / plan.dt;
        let (t0, t1) = cells.visible_interval(o_v, inv_d)?;
        let mut k = first_index_from(plan, fmax(t0, from), inv_dt);
        let end = first_index_from(plan, t1, inv_dt);
        let ahead = cells.forward_distances(octant(d_v));
        while k < end {
            let t = sample_t(plan, k);
            let pv = o_v + d_v * t;
            let here = cell(&self.g, pv);
            match cells.lookup(here.lo) {
                CellState::Visible => {
                    let (here, rec) = (Some(&here), &mut NoRecord);
                    if self.accumulate_sample(viewing, plan, k, t, pv, here, stop_at, acc, rec) {
                        return Some(k);
                    }
                }
                CellState::EmptyBrick => {
                    let distance = ahead[cells.brick_of(here.lo)];
                    let t_leap = cells.leap_exit_at(here.lo, distance, o_v, inv_d);
                    let next = first_index_from(plan, t_leap, inv_dt);
                    if next > k {
                        k = next;
                        continue;
                    }
                }
                CellState::Invisible => {}
            }
            k += 1;
        }
        None
    }

    /// Maximum and Minimum with block skipping, for float data (integer data take the best
    /// blocks first: `extreme.rs`): a block whose value range cannot beat the running maximum
    /// (minimum) is crossed without sampling, which leaves the result exactly as it was (see
    /// `crate::skip`; ranges include a one-point apron for rounding). A block that can only tie
    /// it is still sampled: float rounding could exceed the corners' range by an ulp.
    pub(super) fn project_extreme(
        &self,
        ranges: &BlockRanges,
        plan: &StepPlan,
        o_v: Vec3,
        d_v: Vec3,
        stats: &mut ValueStats,
    ) {
        debug_assert!(T::TABLE.is_none());
        let maximum = self.s.settings.method == Method::Maximum;
        self.project_blocks(ranges, plan, (o_v, d_v), stats, false, |(lo, hi), stats| {
            stats.count > 0
                && if maximum {
                    hi < stats.max
                } else {
                    lo > stats.min
                }
        });
    }

    /// Sum with block skipping: a block whose values (apron included) are all exactly zero
    /// adds exactly zero a sample, so its samples are passed over and only counted — the sum,
    /// and so the image, are bit for bit the plain march's. Only called where a zero block
    /// interpolates to exactly zero (`Scene::sum_skipping`). Returns the samples passed over.
    pub(super) fn project_sum(
        &self,
        ranges: &BlockRanges,
        plan: &StepPlan,
        o_v: Vec3,
        d_v: Vec3,
        stats: &mut ValueStats,
    ) -> u32 {
        self.project_blocks(ranges, plan, (o_v, d_v), stats, true, |range, _| {
            range == (0.0, 0.0)
        })
    }

    /// The projection methods' block walk: the blocks the ray crosses in order; one that
    /// `useless(range, stats)` says cannot change the result is crossed without sampling
    /// (samples within the margin of its faces are still taken), the others' samples are added
    /// to `stats`. Returns the samples passed over.
    ///
    /// Where `useless` does not read `stats` (`stats_free`: Sum's zero blocks), the samples of
    /// consecutive useful blocks are added as one run, in the same order — the same sums,
    /// without a run's set-up per block (on the CT, where no block is zero, that set-up had
    /// made Sum's skipping twice as slow as none).
    fn project_blocks(
        &self,
        ranges: &BlockRanges,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        stats: &mut ValueStats,
        stats_free: bool,
        useless: impl Fn((f32, f32), &ValueStats) -> bool,
    ) -> u32 {
        let margin_t = SKIP_MARGIN_VOXELS / d_v.length();
        let inv_dt = 1.0 / plan.dt;
        let first = cell(&self.g, o_v + d_v * sample_t(plan, 0)).lo;
        let mut walk = BlockWalk::new(ranges.grid(), first, o_v, d_v);
        let mut passed = 0u32;
        let mut k = 0u32;
        // The samples waiting to be added: `run..k`.
        let mut run = 0u32;
        loop {
            let t_out = walk.exit();
            if !stats_free {
                self.add_samples(plan, (o_v, d_v), (run, k), stats);
                run = k;
            }
            if useless(ranges.ranges[walk.index()], stats) {
                let next = first_index_from(plan, t_out - margin_t, inv_dt).min(plan.count);
                if next > k {
                    self.add_samples(plan, (o_v, d_v), (run, k), stats);
                    passed += next - k;
                    k = next;
                    run = k;
                }
            } else {
                // The samples before a margin past the block's exit face.
                k = first_at_or_after(plan, t_out + margin_t, inv_dt, k);
            }
            if k >= plan.count || !t_out.is_finite() {
                break;
            }
            walk.advance();
        }
        self.add_samples(plan, (o_v, d_v), (run, k), stats);
        passed
    }

    /// First with block skipping: a block whose values all lie below the target holds no hit, so
    /// its samples are passed over — except the last, which becomes the previous sample (the
    /// lower end of a later hit's bracket). The hits found, and so the image, are exactly those
    /// of the plain march.
    pub(super) fn first_skipping(
        &self,
        ranges: &BlockRanges,
        ray: &Ray,
        plan: &StepPlan,
        o_v: Vec3,
        d_v: Vec3,
    ) -> RayOutcome {
        let target = self.s.target;
        let margin_t = SKIP_MARGIN_VOXELS / d_v.length();
        let inv_dt = 1.0 / plan.dt;
        let first = cell(&self.g, o_v + d_v * sample_t(plan, 0)).lo;
        let mut walk = BlockWalk::new(ranges.grid(), first, o_v, d_v);
        let mut prev: Option<(f32, f32)> = None;
        let mut taken = 0u32;
        let mut k = 0u32;
        loop {
            let t_out = walk.exit();
            let (_, hi) = ranges.ranges[walk.index()];
            if hi < target {
                let next = first_index_from(plan, t_out - margin_t, inv_dt);
                if next > k {
                    // Samples k..last are inside the block: only `last` is needed, as `prev`.
                    let last = next - 1;
                    let t = sample_t(plan, last);
                    let v = self.value(o_v + d_v * t);
                    prev = v.is_finite().then_some((t, v));
                    taken += 1;
                    k = last + 1;
                }
            } else {
                while k < plan.count {
                    let t = sample_t(plan, k);
                    if t >= t_out + margin_t {
                        break;
                    }
                    let v = self.value(o_v + d_v * t);
                    taken += 1;
                    if reaches(v, target) {
                        let (pt, p) = prev.unwrap_or((t, v));
                        let mut out = self.hit(ray, (pt, p, t, v), o_v, d_v, k + 1, &mut NoRecord);
                        out.samples = taken;
                        return out;
                    }
                    prev = v.is_finite().then_some((t, v));
                    k += 1;
                }
            }
            if k >= plan.count || !t_out.is_finite() {
                break;
            }
            walk.advance();
        }
        RayOutcome {
            samples: taken,
            positions: plan.count,
            stop: StopReason::LeftVolume,
            ..RayOutcome::MISS
        }
    }
}

/// The first sample from `k` on whose `t` is at or past `t` (`count` if none): exactly the
/// first that a loop from `k` testing `sample_t(plan, j) >= t` stops at, since `sample_t` is
/// monotone in `j`; `first_index_from` gives the estimate, corrected by a step either way.
fn first_at_or_after(plan: &StepPlan, t: f32, inv_dt: f32, k: u32) -> u32 {
    if t.is_nan() || t == f32::INFINITY {
        return plan.count; // nothing is at or past it
    }
    let mut j = first_index_from(plan, t, inv_dt).clamp(k, plan.count);
    while j > k && sample_t(plan, j - 1) >= t {
        j -= 1;
    }
    while j < plan.count && sample_t(plan, j) < t {
        j += 1;
    }
    j
}
