//! Tracing one ray: enter the box, step, sample, classify, shade, composite — optionally recording
//! every number on the way.
//!
//! Twin: `shaders/trace.wgsl` (`trace`).
//!
//! [`Scene`] holds what every ray of a render shares (the baked transfer function, the resolved
//! settings in world units, the light). The march is written once, generic over the voxel type
//! and over a [`Recorder`]: [`trace_ray`] records each sample for the ray inspector and
//! `voxcast trace`, while the image renderer ([`crate::render`]) runs the very same code with
//! [`NoRecord`], whose recording calls compile away. The picture and the breakdown therefore
//! cannot disagree.
//!
//! The plain marches here are the twin of `shaders/trace.wgsl`; `trace/skipping.rs` passes over
//! empty space with the same samples; `trace/lanes.rs` runs Accumulate's hot path eight
//! positions and eight samples at a time on CPUs with AVX2, SSE 4.1 or NEON, to the same bits
//! ([`uses_lanes`]).

use crate::classify::Classifier;
use crate::clip::clip_interval;
use crate::composite::{
    Method, Order, ValueStats, accumulate_back_to_front, accumulate_front_to_back,
    blend_background, correct_opacity_with, crossing_fraction, reaches, sum_to_value,
};
use crate::ray::{Ray, intersect_box};
use crate::sample::{
    Cell, Interpolation, gradient, gradient_from_differences, gradient_in_cell, sample,
    sample_detail, trilinear_in_cell, value_and_gradient_in_cell,
};
use crate::shade::{Phong, ShadeTerms, Viewing, shade};
use crate::step::{StepPlan, plan_steps, sample_t, segment_length};
use crate::volume::{Grid, GridVisitor, Voxel};
use glam::{Vec3, Vec4};
use serde::Serialize;

use crate::breakdown::Breakdown;
pub use crate::breakdown::{
    FirstHit, NoRecord, RayTrace, Recorder, RefineStep, SampleRecord, StopReason, SumDetail,
};
pub use crate::scene::Scene;

mod dispatch;
mod extreme;
mod first;
mod record;
pub use crate::vectors::{Vectors, set_vectors, vectors};
pub use dispatch::{lane_instructions, uses_lanes, uses_value_lanes, value_lane_instructions};
pub use record::trace_ray;
#[cfg(lanes)]
mod lanes;
#[cfg(target_arch = "x86_64")]
mod leaps;
#[cfg(all(lanes, not(target_arch = "x86_64")))]
#[path = "trace/leaps_scalar.rs"]
mod leaps;
#[cfg(lanes)]
mod positions;
#[cfg(lanes)]
mod simd;
mod skipping;
#[cfg(lanes)]
mod value_lanes;

/// The result of one ray.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RayOutcome {
    /// Composited colour, premultiplied (before the background).
    pub color: Vec3,
    /// Composited opacity.
    pub opacity: f32,
    /// Samples interpolated (refinement and gradient reads not counted).
    pub samples: u32,
    /// Sample positions the ray passed until it stopped, interpolated or skipped as empty
    /// space: what a caster without skipping would have interpolated.
    pub positions: u32,
    pub stop: StopReason,
    /// First's refined hit: its distance along the ray (world units from the ray's origin);
    /// NaN where the ray found no target (and for the other methods).
    pub hit_t: f32,
}

impl RayOutcome {
    const MISS: Self = Self {
        color: Vec3::ZERO,
        opacity: 0.0,
        samples: 0,
        positions: 0,
        stop: StopReason::Missed,
        hit_t: f32::NAN,
    };

    /// The pixel colour over `background`.
    pub fn pixel(&self, background: Vec3) -> Vec3 {
        blend_background(self.color, self.opacity, background)
    }
}

/// How far inside a transparent block (in voxels) a sample must lie to be skipped.
pub const SKIP_MARGIN_VOXELS: f32 = 0.01;

/// The march for one voxel type: borrowed scene plus the typed grid.
pub(crate) struct Marcher<'s, 'a, 'g, T: Voxel> {
    s: &'s Scene<'a>,
    g: Grid<'g, T>,
    inv_spacing: Vec3,
    interp: Interpolation,
    /// Gradient needed for every classified sample (Levoy's modes).
    classify_gradient: bool,
    /// Opacity independent of the table's opacity at the value (Levoy's isovalue contours,
    /// the value-and-gradient rectangles): a sample the table makes transparent may show.
    beyond_table: bool,
    /// The cut keeps the whole box: a ray outside it missed the box (no second test).
    uncut: bool,
    /// Accumulate's eight-lane path, where it applies (see `lanes.rs`).
    #[cfg(lanes)]
    lanes: Option<lanes::Lanes<'s>>,
    /// Maximum and Minimum's coarser block level, for integer data (see `extreme.rs`).
    superblocks: Option<&'s crate::bricks::Superblocks>,
    /// The projections' eight-lane values, where they apply (see `value_lanes.rs`).
    #[cfg(lanes)]
    values: Option<value_lanes::ValueLanes<'g>>,
}

/// Accumulate's running state along a ray.
struct Accumulation {
    c: Vec3,
    o: f32,
    taken: u32,
}

/// A sample evaluated ([`Marcher::evaluate`]): all it contributes that does not depend on the
/// samples before it.
struct Evaluated {
    /// Its value, data units.
    v: f32,
    cl: Classified,
    /// Its gradient, if read.
    grad: Option<Vec3>,
    /// Where its opacity is above zero: its colour shaded, and the gradient.
    shaded: Option<(Vec3, Option<Vec3>)>,
}

/// Per-sample classification result.
struct Classified {
    rgba: Vec4,
    alpha: f32,
    grad: Option<Vec3>,
}

impl<'s, 'a, 'g, T: Voxel> Marcher<'s, 'a, 'g, T> {
    /// Whether a sample's value may be non-finite ("no data"): only float volumes hold such
    /// voxels, so for integer data the per-sample checks below fold away at compile time.
    const MAY_LACK_DATA: bool = matches!(T::TYPE, crate::volume::ScalarType::F32);

    pub(crate) fn new(s: &'s Scene<'a>, g: Grid<'g, T>) -> Self {
        Self {
            inv_spacing: 1.0 / g.spacing,
            interp: s.settings.interpolation,
            classify_gradient: s.classifier != Classifier::Table,
            beyond_table: s.classifier.beyond_table(),
            uncut: s.clip.keeps_box(s.bounds),
            #[cfg(lanes)]
            lanes: lanes::Lanes::new(s, &g),
            superblocks: s.superblocks.filter(|_| T::TABLE.is_some()),
            #[cfg(lanes)]
            // Every value finite, as the lanes count every sample (`ValueStats::add` counts
            // only those): the rescale of the type's whole range is, and it is monotone.
            values: value_lanes::ValueLanes::new(&g, s.simd).filter(|_| {
                s.settings.interpolation == Interpolation::Trilinear
                    && T::TABLE.is_some_and(|(offset, count)| {
                        let ends = [-offset, count as i32 - 1 - offset];
                        ends.iter().all(|&r| g.to_data(r as f32).is_finite())
                    })
            }),
            s,
            g,
        }
    }

    /// Where `ray` samples: its interval in the volume's box, cut by the crop box and the clip
    /// plane.
    fn interval(&self, ray: &Ray) -> Option<(f32, f32)> {
        clip_interval(ray, &self.s.clip)
    }

    /// The reconstructed value (data units) at voxel-space point `pv`.
    #[inline(always)]
    fn value(&self, pv: Vec3) -> f32 {
        self.g.to_data(sample(&self.g, pv, self.interp))
    }

    /// The gradient at `pv` (in `cell` if the march has located it); zero where it would need
    /// a lattice point that holds no data (a non-finite difference), so such a sample is lit as
    /// one without a normal.
    #[inline(always)]
    fn gradient(&self, pv: Vec3, cell: Option<&Cell>) -> Vec3 {
        let g = match (self.s.differences, cell, self.interp) {
            (Some(d), Some(c), Interpolation::Trilinear) => gradient_in_cell(&self.g, d, c),
            (Some(d), _, _) => gradient_from_differences(&self.g, d, pv, self.interp),
            (None, _, _) => gradient(&self.g, pv, self.interp),
        };
        if !Self::MAY_LACK_DATA || g.is_finite() {
            g
        } else {
            Vec3::ZERO
        }
    }

    /// Colour and opacity of value `v` at `pv`: the table, then the classifier (with the
    /// gradient `known` if it has been read already). Unless `full` is asked for, a sample the
    /// table makes transparent returns at once (its colour unread).
    #[inline(always)]
    fn classify(
        &self,
        v: f32,
        (pv, cell): (Vec3, Option<&Cell>),
        known: Option<Vec3>,
        full: bool,
    ) -> Classified {
        if Self::MAY_LACK_DATA && !v.is_finite() {
            // No data (a corner of the sample's cell holds none): transparent, unread.
            return Classified {
                rgba: Vec4::ZERO,
                alpha: 0.0,
                grad: None,
            };
        }
        let rgba = match self.s.lut.lookup_if_visible(v) {
            Some(rgba) => rgba,
            None if !full && !self.beyond_table => {
                return Classified {
                    rgba: Vec4::ZERO,
                    alpha: 0.0,
                    grad: None,
                };
            }
            None => self.s.lut.lookup(v),
        };
        let table_alpha = rgba.w;
        if !self.classify_gradient {
            return Classified {
                rgba,
                alpha: table_alpha,
                grad: None,
            };
        }
        let grad = known.unwrap_or_else(|| self.gradient(pv, cell));
        Classified {
            rgba,
            alpha: self.s.classifier.classify(v, table_alpha, grad.length()),
            grad: Some(grad),
        }
    }

    /// Shades `color` at `pv` if shading is on, reusing a gradient already computed.
    #[inline(always)]
    fn shade(
        &self,
        color: Vec3,
        (pv, cell): (Vec3, Option<&Cell>),
        grad: Option<Vec3>,
        view: &Viewing<'_>,
    ) -> (Vec3, Option<Vec3>, Option<ShadeTerms>) {
        if !self.s.settings.shading {
            return (color, grad, None);
        }
        let grad = grad.unwrap_or_else(|| self.gradient(pv, cell));
        let phong: &Phong = &self.s.settings.phong;
        let (c, terms) = shade(color, grad, pv * self.g.spacing, view, phong);
        (c, Some(grad), Some(terms))
    }

    /// Marches `ray` with jitter fraction `jitter`.
    #[inline]
    pub(crate) fn march<R: Recorder>(&self, ray: &Ray, jitter: f32, rec: &mut R) -> RayOutcome {
        self.march_from(ray, jitter, f32::NEG_INFINITY, rec)
    }

    /// Whether [`Marcher::march_from`] makes use of its `from`: Accumulate front to back with
    /// skipping (on the eight lanes or one sample at a time), the only march that reads it.
    pub(crate) fn reads_entry_bounds(&self) -> bool {
        self.s.empty.is_some()
            && self.s.settings.method == Method::Accumulate
            && self.s.settings.order != Order::BackToFront
    }

    /// [`Marcher::march`], told that no sample before `t = from` lies in a visible cell
    /// ([`crate::entry::EntryBounds`]); the lanes start there, the other marches ignore it.
    ///
    /// Always inlined, for the same reason as [`clip_interval`]: the renderer read the
    /// outcome's sample and position counts, written one by one, as one 64-bit load.
    #[inline(always)]
    pub(crate) fn march_from<R: Recorder>(
        &self,
        ray: &Ray,
        jitter: f32,
        from: f32,
        rec: &mut R,
    ) -> RayOutcome {
        let Some((t0, t1)) = self.interval(ray) else {
            let cut = !self.uncut && intersect_box(ray, self.s.bounds.0, self.s.bounds.1).is_some();
            return RayOutcome {
                stop: if cut {
                    StopReason::CutAway
                } else {
                    StopReason::Missed
                },
                ..RayOutcome::MISS
            };
        };
        let set = &self.s.settings;
        let plan = plan_steps(t0, t1, self.s.dt, jitter, set.max_samples);
        if R::ACTIVE {
            rec.plan(&plan);
        }
        let o_v = ray.origin * self.inv_spacing;
        let d_v = ray.dir * self.inv_spacing;
        let mut out = match set.method {
            Method::Accumulate => self.accumulate(ray, &plan, (o_v, d_v), from, rec),
            Method::First => self.first(ray, &plan, o_v, d_v, rec),
            Method::Average | Method::Maximum | Method::Minimum | Method::Sum => {
                self.project(&plan, o_v, d_v, rec)
            }
        };
        out.samples = out.samples.min(plan.count);
        if out.stop != StopReason::Cutoff && out.stop != StopReason::FirstHit {
            out.positions = plan.count;
        }
        if out.stop == StopReason::LeftVolume && plan.capped {
            out.stop = StopReason::SampleCap;
        }
        out
    }

    fn accumulate<R: Recorder>(
        &self,
        ray: &Ray,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        from: f32,
        rec: &mut R,
    ) -> RayOutcome {
        let set = &self.s.settings;
        let back_to_front = set.order == Order::BackToFront;
        let stop_at = if set.early_termination && !back_to_front {
            set.cutoff
        } else {
            f32::INFINITY
        };
        let mut acc = Accumulation {
            c: Vec3::ZERO,
            o: 0.0,
            taken: 0,
        };
        let skip = if R::ACTIVE || back_to_front {
            None
        } else {
            self.s.empty.as_deref()
        };
        if from == f32::INFINITY && skip.is_some() {
            // No visible cell along the ray (its pixel's entry bound): nothing to composite,
            // as either skipping march would find.
            return self.accumulated(acc, None);
        }
        let viewing = Viewing::from_origin(ray.origin, -ray.dir, &self.s.lights);
        let mut stopped_at = None;
        match skip {
            Some((_, cells)) if plan.count > 0 => {
                #[cfg(lanes)]
                if let Some(lanes) = self.lanes.as_ref().filter(|_| !R::ACTIVE)
                    && let Some(stop) = self.accumulate_lanes(
                        lanes,
                        cells,
                        plan,
                        (o_v, d_v),
                        from,
                        &viewing,
                        stop_at,
                        &mut acc,
                    )
                {
                    return self.accumulated(acc, stop);
                }
                stopped_at = self.accumulate_skipping(
                    cells,
                    plan,
                    (o_v, d_v),
                    from,
                    &viewing,
                    stop_at,
                    &mut acc,
                );
            }
            _ => {
                for i in 0..plan.count {
                    let k = if back_to_front { plan.count - 1 - i } else { i };
                    let t = sample_t(plan, k);
                    let pv = o_v + d_v * t;
                    if self
                        .accumulate_sample(&viewing, plan, k, t, pv, None, stop_at, &mut acc, rec)
                    {
                        stopped_at = Some(i);
                        break;
                    }
                }
            }
        }
        self.accumulated(acc, stopped_at)
    }

    /// Accumulate's outcome: what was gathered, and where the ray stopped if it did (the
    /// positions are then counted up to that sample; `march` sets them otherwise).
    fn accumulated(&self, acc: Accumulation, stopped_at: Option<u32>) -> RayOutcome {
        RayOutcome {
            color: acc.c,
            opacity: acc.o,
            samples: acc.taken,
            positions: stopped_at.map_or(0, |k| k + 1),
            stop: if stopped_at.is_some() {
                StopReason::Cutoff
            } else {
                StopReason::LeftVolume
            },
            hit_t: f32::NAN,
        }
    }

    /// Takes sample `k` (at `t`, voxel position `pv`, in `cell` if already located, seen as
    /// `viewing` describes) into the accumulation; returns true when early termination stops
    /// the ray.
    #[inline(always)]
    // Many arguments, kept (here and in the march's other per-sample functions: lanes.rs,
    // record.rs, skipping.rs): they are inlined into the per-sample loop whose speed
    // BENCHMARKS.md measures, and the ray's running state travels as values the optimiser keeps
    // in registers; a struct of borrowed state was not tried against the benchmarks.
    #[allow(clippy::too_many_arguments)]
    fn accumulate_sample<R: Recorder>(
        &self,
        viewing: &Viewing<'_>,
        plan: &StepPlan,
        k: u32,
        t: f32,
        pv: Vec3,
        cell: Option<&Cell>,
        stop_at: f32,
        acc: &mut Accumulation,
        rec: &mut R,
    ) -> bool {
        let (e, terms) = self.evaluate(pv, cell, viewing, R::ACTIVE);
        self.composite_sample(plan, (k, t, pv), &e, terms, stop_at, acc, rec)
    }

    /// What sample at `pv` (in `cell` if already located) contributes, whatever came before
    /// it: its value, classification, and its colour shaded where the table shows it (with
    /// the shading's terms, for a record). Unless `full` is asked for, a sample the table makes
    /// transparent is left unclassified.
    #[inline(always)]
    fn evaluate(
        &self,
        pv: Vec3,
        cell: Option<&Cell>,
        viewing: &Viewing<'_>,
        full: bool,
    ) -> (Evaluated, Option<ShadeTerms>) {
        // In a located cell the value and its gradient come from one read of the corners'
        // records where those exist (the same numbers as reading them apart).
        let (v, known) = match (cell, self.interp, self.s.differences) {
            (Some(c), Interpolation::Trilinear, Some(d)) => {
                let (raw, grad) = value_and_gradient_in_cell(&self.g, d, c);
                (self.g.to_data(raw), Some(grad))
            }
            (Some(c), Interpolation::Trilinear, None) => {
                (self.g.to_data(trilinear_in_cell(&self.g, c)), None)
            }
            _ => (self.value(pv), None),
        };
        let cl = self.classify(v, (pv, cell), known, full);
        let grad = cl.grad.or(known);
        let (mut shaded, mut terms) = (None, None);
        if cl.alpha > 0.0 {
            let (color, g, t) = self.shade(cl.rgba.truncate(), (pv, cell), grad, viewing);
            (shaded, terms) = (Some((color, g)), t);
        }
        let e = Evaluated {
            v,
            cl,
            grad,
            shaded,
        };
        (e, terms)
    }

    /// Composites evaluated sample `k` (at `t`, voxel position `pv`): its opacity corrected
    /// for its segment, then the running colour and opacity; returns true when early
    /// termination stops the ray.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // the march's per-sample hot path: see trace.rs
    fn composite_sample<R: Recorder>(
        &self,
        plan: &StepPlan,
        (k, t, pv): (u32, f32, Vec3),
        e: &Evaluated,
        terms: Option<ShadeTerms>,
        stop_at: f32,
        acc: &mut Accumulation,
        rec: &mut R,
    ) -> bool {
        let set = &self.s.settings;
        acc.taken += 1;
        if !R::ACTIVE && e.cl.alpha <= 0.0 {
            return false; // transparent: nothing changes
        }
        let ds = segment_length(plan, k, t);
        let alpha = if set.opacity_correction {
            correct_opacity_with(e.cl.alpha, ds, self.s.dt_ref, self.s.step_power.as_deref())
        } else {
            e.cl.alpha
        };
        let (color, grad, terms) = match e.shaded {
            Some((color, grad)) if alpha > 0.0 => {
                (acc.c, acc.o) = if set.order == Order::BackToFront {
                    accumulate_back_to_front(acc.c, acc.o, color, alpha)
                } else {
                    accumulate_front_to_back(acc.c, acc.o, color, alpha)
                };
                (color, grad, terms)
            }
            _ => (e.cl.rgba.truncate(), e.grad, None),
        };
        if R::ACTIVE {
            rec.sample(self.record(
                k,
                t,
                ds,
                pv,
                e.v,
                &e.cl,
                alpha,
                grad,
                terms,
                color,
                Vec4::from((acc.c, acc.o)),
                None,
            ));
        }
        acc.o >= stop_at
    }

    /// Adds the ray's samples `k0..k1` to `stats` in order: eight at a time where the
    /// projections' lanes apply (`value_lanes.rs`: integer data, trilinear, vectors) — the same
    /// statistics — else one by one; nothing for an empty range.
    fn add_samples(
        &self,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        (k0, k1): (u32, u32),
        stats: &mut ValueStats,
    ) {
        if k0 >= k1 {
            return;
        }
        #[cfg(lanes)]
        if let Some(lanes) = &self.values {
            let rescale = (self.g.slope, self.g.intercept);
            // SAFETY: `ValueLanes` built from this grid.
            unsafe { lanes.add_range(plan, (o_v, d_v), (k0, k1), rescale, stats) };
            return;
        }
        for k in k0..k1 {
            stats.add(self.value(o_v + d_v * sample_t(plan, k)));
        }
    }

    fn project<R: Recorder>(
        &self,
        plan: &StepPlan,
        o_v: Vec3,
        d_v: Vec3,
        rec: &mut R,
    ) -> RayOutcome {
        let method = self.s.settings.method;
        let mut stats = ValueStats::default();
        let extreme = matches!(method, Method::Maximum | Method::Minimum);
        // Samples passed over as exactly zero (Sum's skipping): values of the ray all the same.
        let mut zeros = 0u32;
        let ranges = self.s.blocks.filter(|_| !R::ACTIVE && plan.count > 0);
        if let Some(ranges) = ranges.filter(|_| extreme && self.s.block_skipping) {
            if let Some(supers) = self.superblocks {
                self.project_extreme_ordered((ranges, supers), plan, (o_v, d_v), &mut stats);
            } else {
                self.project_extreme(ranges, plan, o_v, d_v, &mut stats);
            }
        } else if let Some(ranges) = ranges.filter(|_| self.s.sum_skipping) {
            zeros = self.project_sum(ranges, plan, o_v, d_v, &mut stats);
        } else if !R::ACTIVE {
            self.add_samples(plan, (o_v, d_v), (0, plan.count), &mut stats);
        } else {
            for k in 0..plan.count {
                let t = sample_t(plan, k);
                let pv = o_v + d_v * t;
                let v = self.value(pv);
                stats.add(v);
                if R::ACTIVE {
                    rec.sample(self.record_plain(plan, k, t, pv, v, Some(stats)));
                }
            }
        }
        let taken = stats.count;
        stats.add_zeros(zeros);
        let ds = self.s.dt * d_v.length();
        let Some(value) = stats.projected(method, ds) else {
            return RayOutcome {
                samples: 0,
                stop: StopReason::LeftVolume,
                ..RayOutcome::MISS
            };
        };
        if R::ACTIVE {
            rec.projected(value);
        }
        let lut = &self.s.lut;
        let rgba = if method == Method::Sum {
            let (a, b) = self.s.sum_range;
            let table_value = sum_to_value(value, (a, b), (lut.lo, lut.hi));
            if R::ACTIVE {
                rec.sum(SumDetail {
                    ds_voxels: ds,
                    values: stats.sum,
                    sum: value,
                    range: [a, b],
                    table: [lut.lo, lut.hi],
                    fraction: sum_to_value(value, (a, b), (0.0, 1.0)),
                    table_value,
                });
            }
            lut.lookup(table_value)
        } else {
            lut.lookup(value)
        };
        RayOutcome {
            color: rgba.truncate() * rgba.w,
            opacity: rgba.w,
            samples: taken,
            positions: plan.count,
            stop: StopReason::LeftVolume,
            hit_t: f32::NAN,
        }
    }
}
