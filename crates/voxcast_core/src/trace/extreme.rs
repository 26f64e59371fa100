//! Maximum and Minimum intensity projection with the most promising blocks first: the same
//! pixels as the plain march, bit for bit, from a fraction of its samples and its block steps.
//!
//! The largest value along a ray does not depend on the order its samples are looked at. So a
//! ray first walks the *superblocks* it crosses ([`SUPER`]³ blocks of `crate::skip`, with the
//! union of their value ranges), samples the one with the largest range first (the smallest,
//! for Minimum), and then, front to back, only the superblocks — and in them only the blocks
//! — whose range can still beat the value found; consecutive such blocks are sampled as one
//! run, eight positions at a time where the CPU allows (`value_lanes.rs`). Ties are skipped
//! too: the data are integers, whose interpolated values never leave their corners' range. A
//! front-to-back march meets a CT's brightest bone late and has to sample everything before
//! it; this one samples the bone first and passes over the rest.
//!
//! Exact for the same reason as the front-to-back skipping (`crate::skip`): at either level
//! a block's share of the samples is those with `t` in `[t_in − margin, t_out − margin)` of
//! its walk, the very set that march passes over when the block cannot help, so the block's
//! range (its apron included) bounds every one of them. The value found is converted to data
//! units once per run: `raw·slope + intercept` is monotone in floating point, so the largest
//! converted value is the converted largest (the smallest, for a negative slope).

use super::{Marcher, SKIP_MARGIN_VOXELS};
use crate::composite::{Method, ValueStats};
use crate::sample::{cell, sample};
use crate::skip::{BLOCK, BlockRanges, BlockWalk};
use crate::step::{StepPlan, first_index_from, sample_t};
use crate::volume::Voxel;
use glam::Vec3;
use std::cell::RefCell;

/// Blocks per superblock edge.
const SUPER: usize = 4;

/// The blocks' value ranges gathered into superblocks of [`SUPER`]³ blocks.
#[derive(Clone, Debug)]
pub(super) struct Superblocks {
    grid: [usize; 3],
    ranges: Vec<(f32, f32)>,
}

impl Superblocks {
    /// The union of each superblock's block ranges (its blocks' aprons included).
    pub(super) fn of(blocks: &BlockRanges) -> Self {
        let fine = blocks.grid();
        let grid = fine.map(|n| n.div_ceil(SUPER));
        let mut ranges = vec![(f32::INFINITY, f32::NEG_INFINITY); grid[0] * grid[1] * grid[2]];
        for z in 0..fine[2] {
            for y in 0..fine[1] {
                for x in 0..fine[0] {
                    let (lo, hi) = blocks.ranges[x + fine[0] * (y + fine[1] * z)];
                    let at = x / SUPER + grid[0] * (y / SUPER + grid[1] * (z / SUPER));
                    let r = &mut ranges[at];
                    *r = (r.0.min(lo), r.1.max(hi));
                }
            }
        }
        Self { grid, ranges }
    }
}

/// A ray's superblocks in order along it: each one's bound — its largest value for Maximum,
/// its smallest negated for Minimum (larger is better either way) — and the `t` where the ray
/// leaves it (infinite for the last).
#[derive(Default)]
struct Walked {
    bound: Vec<f32>,
    t_out: Vec<f32>,
}

thread_local! {
    /// A ray's superblocks, kept between rays of a thread.
    static WALKED: RefCell<Walked> = RefCell::new(Walked::default());
}

/// What a ray has found so far: the best value (data units, negated for Minimum) and how many
/// samples it took.
struct Found {
    best: f32,
    taken: u32,
}

impl Found {
    /// Whether a block whose bound is `bound` may still change the result.
    fn open(&self, bound: f32) -> bool {
        self.taken == 0 || bound > self.best
    }
}

impl<T: Voxel> Marcher<'_, '_, '_, T> {
    /// Maximum or Minimum of the ray's samples, the best superblock first (see the module
    /// docs), into `stats` (its count and extreme; the sum is left alone, as neither method
    /// reads it). For integer data only (every sample is a value, and ties with a block's bound
    /// are skippable).
    pub(super) fn project_extreme_ordered(
        &self,
        (blocks, supers): (&BlockRanges, &Superblocks),
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        stats: &mut ValueStats,
    ) {
        debug_assert!(T::TABLE.is_some() && plan.count > 0);
        let maximum = self.s.settings.method == Method::Maximum;
        let margin_t = SKIP_MARGIN_VOXELS / d_v.length();
        let inv_dt = 1.0 / plan.dt;
        let ray = ProjectionRay {
            plan,
            o_v,
            d_v,
            margin_t,
            inv_dt,
            maximum,
        };
        let mut found = Found {
            best: f32::NEG_INFINITY,
            taken: 0,
        };
        WALKED.with_borrow_mut(|w| {
            self.walk_superblocks(supers, &ray, w);
            // Superblock j's samples: from where the ray is a margin short of leaving
            // superblock j − 1 to where it is a margin short of leaving superblock j.
            let share = |j: usize| {
                let k0 = if j == 0 { 0 } else { ray.index(w.t_out[j - 1]) };
                (k0, ray.index(w.t_out[j]).max(k0))
            };
            let first = (0..w.bound.len())
                .max_by(|&a, &b| w.bound[a].total_cmp(&w.bound[b]))
                .expect("a ray with samples crosses a superblock");
            self.sample_blocks(blocks, &ray, share(first), &mut found);
            for j in 0..w.bound.len() {
                if j != first && found.open(w.bound[j]) {
                    self.sample_blocks(blocks, &ray, share(j), &mut found);
                }
            }
        });
        stats.count += found.taken;
        if maximum {
            stats.max = stats.max.max(found.best);
        } else {
            stats.min = stats.min.min(-found.best);
        }
    }

    /// Walks the superblocks the ray crosses, noting each one's bound and where the ray leaves
    /// it, up to the one where its last sample lies.
    fn walk_superblocks(&self, supers: &Superblocks, ray: &ProjectionRay<'_>, w: &mut Walked) {
        w.bound.clear();
        w.t_out.clear();
        let first = cell(&self.g, ray.position(0)).lo;
        let mut walk = BlockWalk::sized(BLOCK * SUPER, supers.grid, first, ray.o_v, ray.d_v);
        loop {
            w.bound.push(ray.bound(supers.ranges[walk.index()]));
            let t_out = walk.exit();
            // No sample lies a margin short of a face beyond the ray's end.
            if !t_out.is_finite() || t_out - ray.margin_t > ray.plan.t_exit {
                w.t_out.push(f32::INFINITY);
                break;
            }
            w.t_out.push(t_out);
            walk.advance();
        }
    }

    /// Samples `k0..k1` (one superblock's share), front to back, in runs of consecutive blocks
    /// that can still beat the best found; blocks that cannot are passed over.
    fn sample_blocks(
        &self,
        blocks: &BlockRanges,
        ray: &ProjectionRay<'_>,
        (k0, k1): (u32, u32),
        found: &mut Found,
    ) {
        if k1 <= k0 {
            return;
        }
        let start = cell(&self.g, ray.position(k0)).lo;
        let mut walk = BlockWalk::new(blocks.grid(), start, ray.o_v, ray.d_v);
        let mut run: Option<(u32, u32)> = None;
        let mut k = k0;
        loop {
            let t_out = walk.exit();
            let end = ray.index(t_out).min(k1);
            if end > k {
                if found.open(ray.bound(blocks.ranges[walk.index()])) {
                    run = Some((run.map_or(k, |r| r.0), end));
                } else if let Some(r) = run.take() {
                    self.sample_run(ray, r, found);
                }
                k = end;
            }
            if k >= k1 || !t_out.is_finite() {
                break;
            }
            walk.advance();
        }
        if let Some(r) = run {
            self.sample_run(ray, r, found);
        }
    }

    /// Samples `k0..k1` and keeps the best.
    fn sample_run(&self, ray: &ProjectionRay<'_>, (k0, k1): (u32, u32), found: &mut Found) {
        // Raw values, compared in whichever direction makes the data value the best.
        let raw_larger = ray.maximum == (self.g.slope >= 0.0);
        let value = self.g.to_data(self.raw_extreme(ray, (k0, k1), raw_larger));
        found.best = found.best.max(if ray.maximum { value } else { -value });
        found.taken += k1 - k0;
    }

    /// The largest (`larger`) or smallest raw value of the samples `k0..k1`: eight at a time
    /// where the CPU and the grid allow (`value_lanes.rs`, the same numbers), else one by one.
    #[inline]
    fn raw_extreme(&self, ray: &ProjectionRay<'_>, (k0, k1): (u32, u32), larger: bool) -> f32 {
        #[cfg(target_arch = "x86_64")]
        if let Some(lanes) = &self.values {
            // SAFETY: `ValueLanes` exists only where the CPU has AVX2, built from this grid.
            return unsafe { lanes.extreme(ray.plan, (ray.o_v, ray.d_v), (k0, k1), larger) };
        }
        let mut raw = if larger {
            f32::NEG_INFINITY
        } else {
            f32::INFINITY
        };
        for k in k0..k1 {
            let v = sample(&self.g, ray.position(k), self.interp);
            raw = if larger { raw.max(v) } else { raw.min(v) };
        }
        raw
    }
}

/// A ray of a projection, as its marches need it.
struct ProjectionRay<'p> {
    plan: &'p StepPlan,
    o_v: Vec3,
    d_v: Vec3,
    margin_t: f32,
    inv_dt: f32,
    maximum: bool,
}

impl ProjectionRay<'_> {
    /// Voxel-space position of sample `k`.
    fn position(&self, k: u32) -> Vec3 {
        self.o_v + self.d_v * sample_t(self.plan, k)
    }

    /// The first sample at or past a margin short of `t_out` (all of them for an infinite one).
    fn index(&self, t_out: f32) -> u32 {
        if t_out.is_finite() {
            first_index_from(self.plan, t_out - self.margin_t, self.inv_dt)
        } else {
            self.plan.count
        }
    }

    /// A block's bound from its value range.
    fn bound(&self, (lo, hi): (f32, f32)) -> f32 {
        if self.maximum { hi } else { -lo }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::UVec3;

    #[test]
    fn superblocks_hold_the_union_of_their_blocks_ranges() {
        // 5 × 1 × 2 blocks: superblocks of 4 along x make two columns, one slab deep.
        let ranges = (0..10).map(|i| (i as f32, 10.0 * i as f32)).collect();
        let blocks = BlockRanges {
            blocks: UVec3::new(5, 1, 2),
            ranges,
        };
        let s = Superblocks::of(&blocks);
        assert_eq!(s.grid, [2, 1, 1]);
        // Blocks x = 0..4 of both z layers (0..=3 and 5..=8), then x = 4 (4 and 9).
        assert_eq!(s.ranges, vec![(0.0, 80.0), (4.0, 90.0)]);
    }
}
