//! Maximum and Minimum intensity projection with the most promising blocks first: the same
//! pixels as the plain march, bit for bit, from a fraction of its samples and its block steps.
//!
//! The largest value along a ray does not depend on the order its samples are looked at. So a
//! ray first walks the *superblocks* it crosses (`crate::bricks::SUPER`³ blocks of
//! `crate::skip`, with the union of their value ranges), samples the one with the largest
//! range first (the smallest, for Minimum), then the one with the next best range, and so on,
//! until no superblock left can beat the best value. Where the eight lanes apply (`value_lanes.rs`) a superblock is
//! sampled as one run, each eight positions tested against their cells' bricks
//! (`crate::bricks`, 4³ cells) and passed over when none can beat the best so far (which the
//! first eight set); without them its blocks are walked — in the first superblock the best
//! block first — and only those that can beat the best are sampled, in runs of consecutive
//! blocks. Ties are skipped too: the data are integers, whose interpolated values never leave
//! their corners' range. A front-to-back march meets a CT's brightest bone late and has to
//! sample everything before it; this one samples the bone first and passes over the rest.
//!
//! Exact for the same reason as the front-to-back skipping (`crate::skip`): at either block
//! level a block's share of the samples is those with `t` in `[t_in − margin, t_out − margin)`
//! of its walk, the very set that march passes over when the block cannot help, so the
//! block's range (its apron included) bounds every one of them; a brick is looked up by each
//! sample's own cell. The best value is kept in raw units and converted to data units after
//! each run: `raw·slope + intercept` is monotone in floating point, so the largest converted
//! value is the converted largest (the smallest, for a negative slope).

use super::{Marcher, SKIP_MARGIN_VOXELS};
use crate::bricks::{SUPER, Superblocks};
use crate::composite::{Method, ValueStats};
use crate::sample::{cell, sample};
use crate::skip::{BLOCK, BlockRanges, BlockWalk};
use crate::step::{StepPlan, first_index_from, sample_t};
use crate::volume::Voxel;
use glam::Vec3;
use std::cell::RefCell;

/// A ray's superblocks that hold samples, in order along it, and the blocks of the one being
/// sampled: each one's bound — its largest value for Maximum, its smallest negated for
/// Minimum (larger is better either way) — and its share of the samples.
#[derive(Default)]
struct Walked {
    supers: Vec<Share>,
    /// The blocks of the superblock being sampled.
    shares: Vec<Share>,
}

/// A block's bound and its share of the samples, `k0..k1`.
struct Share {
    bound: f32,
    k0: u32,
    k1: u32,
}

thread_local! {
    /// A ray's superblocks, kept between rays of a thread.
    static WALKED: RefCell<Walked> = RefCell::new(Walked::default());
}

/// What a ray has found so far: the best value (data units, negated for Minimum), the same
/// in raw units (the largest or the smallest raw value, whichever is the best data value), and
/// how many samples it interpolated.
struct Found {
    best: f32,
    raw: f32,
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
        // Raw values compared in whichever direction makes the data value the best.
        let raw_larger = maximum == (self.g.slope >= 0.0);
        let ray = ProjectionRay {
            plan,
            o_v,
            d_v,
            margin_t: SKIP_MARGIN_VOXELS / d_v.length(),
            inv_dt: 1.0 / plan.dt,
            maximum,
            raw_larger,
            bricks: self.s.bricks.map(|b| {
                let bound = if raw_larger { &b.max } else { &b.min };
                (&bound[..], [b.bricks[0] as i32, b.bricks[1] as i32])
            }),
        };
        let by_bricks = self.by_bricks(&ray);
        let mut found = Found {
            best: f32::NEG_INFINITY,
            raw: if raw_larger {
                f32::NEG_INFINITY
            } else {
                f32::INFINITY
            },
            taken: 0,
        };
        WALKED.with_borrow_mut(|w| {
            self.walk_superblocks(supers, &ray, &mut w.supers);
            // Best first: the superblock with the best bound, until none left can beat the
            // value found (a superblock taken is marked with the worst bound).
            for round in 0..w.supers.len() {
                // Of equal bounds the furthest along the ray (fewer samples in these scenes
                // than the nearest: 2 % for Maximum, 15 % for Minimum).
                let mut j = 0;
                for (i, s) in w.supers.iter().enumerate() {
                    if s.bound >= w.supers[j].bound {
                        j = i;
                    }
                }
                let next = &mut w.supers[j];
                if round > 0 && !found.open(next.bound) {
                    break;
                }
                next.bound = f32::NEG_INFINITY;
                let range = (next.k0, next.k1);
                // Where each sample's brick is tested against the best so far (found after
                // the first eight), the blocks' walk would pass over little more.
                if by_bricks {
                    self.sample_run(&ray, range, &mut found);
                } else {
                    self.sample_blocks(blocks, &ray, range, &mut found, &mut w.shares);
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

    /// Walks the superblocks the ray crosses, noting each one's bound and its share of the
    /// samples — from where the ray is a margin short of leaving the superblock before to
    /// where it is a margin short of leaving this one — up to the one where its last sample
    /// lies; superblocks with no share are left out.
    fn walk_superblocks(
        &self,
        supers: &Superblocks,
        ray: &ProjectionRay<'_>,
        out: &mut Vec<Share>,
    ) {
        out.clear();
        let first = cell(&self.g, ray.position(0)).lo;
        let mut walk = BlockWalk::sized(BLOCK * SUPER, supers.grid, first, ray.o_v, ray.d_v);
        let mut k0 = 0;
        loop {
            let t_out = walk.exit();
            // No sample lies a margin short of a face beyond the ray's end.
            let last = !t_out.is_finite() || t_out - ray.margin_t > ray.plan.t_exit;
            let k1 = if last {
                ray.plan.count
            } else {
                ray.index(t_out)
            };
            if k1 > k0 {
                let bound = ray.bound(supers.ranges[walk.index()]);
                out.push(Share { bound, k0, k1 });
                k0 = k1;
            }
            if last {
                break;
            }
            walk.advance();
        }
    }

    /// Samples `k0..k1` (one superblock's share): the block with the best bound first if
    /// nothing has been found yet, then front to back, in runs of consecutive blocks that can
    /// still beat the best found; blocks that cannot are passed over.
    fn sample_blocks(
        &self,
        blocks: &BlockRanges,
        ray: &ProjectionRay<'_>,
        (k0, k1): (u32, u32),
        found: &mut Found,
        shares: &mut Vec<Share>,
    ) {
        if k1 <= k0 {
            return;
        }
        shares.clear();
        let start = cell(&self.g, ray.position(k0)).lo;
        let mut walk = BlockWalk::new(blocks.grid(), start, ray.o_v, ray.d_v);
        let mut k = k0;
        loop {
            let t_out = walk.exit();
            let end = ray.index(t_out).min(k1);
            if end > k {
                let bound = ray.bound(blocks.ranges[walk.index()]);
                shares.push(Share {
                    bound,
                    k0: k,
                    k1: end,
                });
                k = end;
            }
            if k >= k1 || !t_out.is_finite() {
                break;
            }
            walk.advance();
        }
        if found.taken == 0 {
            let best = (0..shares.len())
                .max_by(|&a, &b| shares[a].bound.total_cmp(&shares[b].bound))
                .expect("a share with samples has a block");
            let first = &mut shares[best];
            self.sample_run(ray, (first.k0, first.k1), found);
            // Taken: no bound beats a value found.
            first.bound = f32::NEG_INFINITY;
        }
        let mut run: Option<(u32, u32)> = None;
        for share in shares.iter() {
            if found.open(share.bound) {
                run = Some((run.map_or(share.k0, |r| r.0), share.k1));
            } else if let Some(r) = run.take() {
                self.sample_run(ray, r, found);
            }
        }
        if let Some(r) = run {
            self.sample_run(ray, r, found);
        }
    }

    /// Samples `k0..k1` and keeps the best.
    fn sample_run(&self, ray: &ProjectionRay<'_>, (k0, k1): (u32, u32), found: &mut Found) {
        let (raw, taken) = self.raw_extreme(ray, (k0, k1), found.raw);
        if taken > 0 {
            // `raw` includes the best before, and the rescale is monotone.
            let value = self.g.to_data(raw);
            found.raw = raw;
            found.best = if ray.maximum { value } else { -value };
            found.taken += taken;
        }
    }

    /// Whether the ray's samples are tested against their bricks before they are interpolated
    /// (the eight lanes with the volume's bricks).
    fn by_bricks(&self, ray: &ProjectionRay<'_>) -> bool {
        #[cfg(lanes)]
        return ray.bricks.is_some() && self.values.is_some();
        #[cfg(not(lanes))]
        {
            let _ = ray;
            false
        }
    }

    /// The best of `prior` and the raw values of the samples `k0..k1`, and how many of them
    /// were interpolated: eight at a time where the CPU and the grid allow, passing over those
    /// whose bricks cannot beat the best (`value_lanes.rs`, the same numbers), else one by one.
    #[inline]
    fn raw_extreme(&self, ray: &ProjectionRay<'_>, (k0, k1): (u32, u32), prior: f32) -> (f32, u32) {
        let larger = ray.raw_larger;
        #[cfg(lanes)]
        if let Some(lanes) = &self.values {
            let (o_d, range) = ((ray.o_v, ray.d_v), (k0, k1));
            // SAFETY: `ValueLanes` built from this grid; the bricks are this volume's.
            return unsafe { lanes.extreme(ray.plan, o_d, range, (larger, prior), ray.bricks) };
        }
        let mut raw = prior;
        for k in k0..k1 {
            let v = sample(&self.g, ray.position(k), self.interp);
            raw = if larger { raw.max(v) } else { raw.min(v) };
        }
        (raw, k1 - k0)
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
    /// Whether the largest raw value is the best (Maximum with a positive rescale slope, or
    /// Minimum with a negative one).
    raw_larger: bool,
    /// The bricks' bounds in that direction and the bricks per axis along x and y.
    #[cfg_attr(not(lanes), allow(dead_code))]
    bricks: Option<(&'p [f32], [i32; 2])>,
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
