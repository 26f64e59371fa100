//! Accumulate's hot path eight sample positions at a time, on x86-64 CPUs with AVX2 or SSE 4.1
//! and on 64-bit ARM (written once over [`Simd`], `simd.rs`, with a backend for each): the
//! same pixels as the one-at-a-time march of `skipping.rs`, bit for bit.
//!
//! A ray starts at its pixel's entry bound ([`crate::entry::EntryBounds`], where the render
//! has one) and leaps over empty bricks by their distance to the nearest visible cell ahead
//! ([`VisibleCells::forward_distances`]; the look at the next brick and the leap, three axes in
//! one vector, are in `leaps.rs`; on ARM the scalar ones, `leaps_scalar.rs`). Elsewhere its sample positions are located eight at
//! a time — `t`, the voxel position, the cell and the cell's visibility bit
//! ([`crate::skip::VisibleCells`]), each lane computing exactly what `sample_t`,
//! `crate::sample::cell` and `VisibleCells::lookup` compute for one position. The positions in
//! visible cells are queued, in order, by one permutation of the eight lanes; once eight are
//! waiting they are *evaluated* together (`lanes/batch.rs`): the eight corners' records
//! ([`crate::sample::Differences`]) gathered, the value and gradient blended, the table looked
//! up, the colour shaded — the very operations of `Marcher::evaluate`, in the same order, with
//! no fused multiply-add, so every lane's numbers are the scalar ones — and, where every sample
//! of the batch stands for one whole step, their opacity corrected. Then the samples are
//! *composited* one by one, in order along the ray, by the scalar code itself (opacity
//! correction where not done yet, front-to-back blend, early termination). A ray that stops
//! early has evaluated up to seven samples beyond its last (three where its last batches
//! predicted its end and it took four at a time: [`Ray::ends_within_four`]); they are dropped,
//! as are positions located past it.
//!
//! Used where it applies exactly: Accumulate front to back with skipping, trilinear, table
//! classification, the precomputed records (an integer volume, shading on), directional lights,
//! the shortened illumination model (no emission, global ambient 1, no light's own ambient, no
//! depth cue: [`crate::shade::Phong::full_form`]) and a whole-number shininess (the scalar
//! code then raises by repeated squaring, which lanes repeat step for step). Anything else, or a CPU with none of those vector units, takes the
//! scalar march. `tests/lanes.rs` renders random scenes with each backend and without lanes, and compares
//! every bit.

use super::leaps::Leaps;
use super::simd::{Backend, Kernel, Simd, lerp};
use super::{Accumulation, Marcher};
use crate::composite::correct_opacity_with;
use crate::power::StepPower;
use crate::scene::Scene;
use crate::shade::{Highlight, MAX_LIGHTS, ResolvedLight, SpecularModel, Viewing};
use crate::skip::VisibleCells;
use crate::step::{StepPlan, first_index_from, sample_t, segment_length};
use crate::volume::{Grid, Voxel};
use glam::{Vec3, Vec3A};

/// Lanes per batch (eight `f32`: one AVX2 vector, two SSE or NEON ones).
mod batch;

const LANES: usize = 8;
/// Lanes evaluated at a time near a ray's end ([`Ray::ends_within_four`]).
const HALF: usize = 4;

/// What every ray of a render shares on the fast path, where it applies.
#[derive(Clone, Debug)]
pub(super) struct Lanes<'s> {
    records: &'s [crate::sample::Differences],
    words: &'s [u64],
    entries: &'s [glam::Vec4],
    /// Record offsets of a cell's 8 corners (`a + 2b + 4c`).
    corners: [i32; 8],
    /// Lattice points per row and per slice.
    nx: i32,
    nxy: i32,
    /// Bricks of visibility words per row and per slice.
    bricks_x: i32,
    bricks_xy: i32,
    last: Vec3,
    max_lo: Vec3,
    gradient_scale: Vec3,
    slope: f32,
    intercept: f32,
    lut_lo: f32,
    lut_scale: f32,
    lut_last: f32,
    lut_max_index: i32,
    ka: f32,
    kd: f32,
    ks: f32,
    exponent: u32,
    threshold: f32,
    two_sided: bool,
    levoy: bool,
    blinn: bool,
    lights: [(Vec3, Vec3); MAX_LIGHTS],
    light_count: usize,
    correction: bool,
    dt_ref: f32,
    /// The power `dt / dt_ref` that opacity correction raises by for a sample standing for
    /// one step, where it is one the scalar code takes without `powf` (½, 1 or 2): then a whole
    /// batch of such samples is corrected at once.
    batch_power: Option<f32>,
    /// The scene's whole-step power ([`Scene::step_power`]), for the composite.
    whole_step: Option<&'s StepPower>,
    backend: Backend,
}

impl<'s> Lanes<'s> {
    /// The fast path's constants, if it applies to `s` and this CPU has AVX2 or SSE 4.1 (as
    /// [`Scene::simd`] allows).
    pub(super) fn new<T: Voxel>(s: &'s Scene<'_>, g: &Grid<'_, T>) -> Option<Self> {
        let set = &s.settings;
        let p = &set.phong;
        let backend = Backend::for_cpu(s.simd)?;
        let applies = set.interpolation == crate::sample::Interpolation::Trilinear
            && s.classifier == crate::classify::Classifier::Table
            && set.shading
            // `shade::power` squares repeatedly for these only (else it calls `powf`).
            && p.shininess.fract() == 0.0
            && (0.0..=1024.0).contains(&p.shininess)
            // Voxcast's shortened form only: no emission, light's ambient or depth cue.
            && !p.full_form();
        if !applies {
            return None;
        }
        let records = s.differences?;
        if g.dims[0] < 2 {
            return None; // a cell's two x corners are then one record, not two side by side
        }
        let (_, cells) = s.empty.as_deref()?;
        // Indices stay in i32 (gathers take 32-bit offsets, records are read as two halves).
        if records.len() >= (i32::MAX / 4) as usize
            || cells.words().len() >= (i32::MAX / 4) as usize
        {
            return None;
        }
        let mut lights = [(Vec3::ZERO, Vec3::ZERO); MAX_LIGHTS];
        let resolved = s.lights.as_slice();
        for (slot, l) in lights.iter_mut().zip(resolved) {
            let ResolvedLight::Toward(dir) = l.at else {
                return None; // a point light: its direction changes along the ray
            };
            *slot = (dir, l.color);
        }
        let [dx, dy, dz] = g.corner_step.map(|c| c as i32);
        let [bx, by, _] = cells.bricks().map(|b| b as i32);
        Some(Self {
            records,
            words: cells.words(),
            entries: &s.lut.entries,
            corners: [0, dx, dy, dy + dx, dz, dz + dx, dz + dy, dz + dy + dx],
            nx: g.dims[0] as i32,
            nxy: (g.dims[0] * g.dims[1]) as i32,
            bricks_x: bx,
            bricks_xy: bx * by,
            last: g.last,
            max_lo: g.max_lo,
            gradient_scale: g.slope / g.spacing,
            slope: g.slope,
            intercept: g.intercept,
            lut_lo: s.lut.lo,
            lut_scale: s.lut.scale,
            lut_last: (s.lut.entries.len() - 1) as f32,
            lut_max_index: (s.lut.entries.len() - 2) as i32,
            ka: p.ka,
            kd: p.kd,
            ks: p.ks,
            exponent: p.shininess as u32,
            threshold: p.gradient_threshold,
            two_sided: p.two_sided,
            levoy: p.highlight == Highlight::Levoy,
            blinn: p.model == SpecularModel::BlinnPhong,
            lights,
            light_count: resolved.len(),
            correction: set.opacity_correction,
            dt_ref: s.dt_ref,
            batch_power: Some(s.dt / s.dt_ref).filter(|e| [0.5, 1.0, 2.0].contains(e)),
            whole_step: s.step_power.as_deref(),
            backend,
        })
    }
}

impl Lanes<'_> {
    /// The instruction set the lanes run on, in words.
    pub(super) fn instructions(&self) -> &'static str {
        self.backend.name()
    }
}

/// The samples waiting to be evaluated: their index and `t` along the ray, their cell's
/// lower corner as a record index, and the position inside the cell. Room for two batches:
/// eight located positions are queued at once, behind up to seven waiting.
#[derive(Default)]
struct Pending {
    n: usize,
    k: [i32; 2 * LANES],
    t: [f32; 2 * LANES],
    base: [i32; 2 * LANES],
    fx: [f32; 2 * LANES],
    fy: [f32; 2 * LANES],
    fz: [f32; 2 * LANES],
}

/// What a batch contributes: the table's opacity and the shaded colour per lane.
struct Evaluated {
    alpha: [f32; LANES],
    /// The lanes whose `alpha` is not `≤ 0` (a bit each): those the composite blends.
    opaque: u32,
    rgb: [[f32; LANES]; 3],
    /// Whether `alpha` is already corrected for the step ([`Lanes::correct_batch`]).
    corrected: bool,
}

/// One ray's view of the lights: the direction to the viewer and, per light, its direction,
/// colour and Blinn half vector.
struct RayLights {
    view: Vec3,
    lights: [(Vec3, Vec3, Vec3); MAX_LIGHTS],
}

/// One ray's march: its step plan, its origin and direction in voxels, its pixel's entry
/// bound, its lights, the opacity that stops it.
///
/// The origin and direction are kept as 16-byte vectors: as `Vec3`s, written as a pair and a
/// single and read back at the march's start in other pairs, a read waited for the writes to
/// reach the cache (a failed store forward, once a ray).
struct Ray<'p> {
    plan: &'p StepPlan,
    o_v: Vec3A,
    d_v: Vec3A,
    from: f32,
    /// Borrowed: a `RayLights` moved in was copied by a call to `memcpy` a ray.
    lights: &'p RayLights,
    stop_at: f32,
    /// The transparency `1 − O` the ray stops at (`1 − stop_at`; below zero, or NaN, where it
    /// never stops early).
    clear_at: f32,
}

impl Ray<'_> {
    /// Whether the ray's last batch (four samples if `half`, else eight), which took its
    /// transparency from `before` to `after`, says that four more at the same opacity would
    /// stop it: then it takes four at a time. A batch of eight at the end of a ray evaluated
    /// on average three past it (the bunny from inside: a quarter of its evaluations); four at
    /// a time wherever the ray might end would cost a batch's fixed work twice as often where
    /// the opacity grows slowly (the MRIs' soft tissue: 8–10 % slower, measured).
    #[inline(always)]
    fn ends_within_four(&self, half: bool, before: f32, after: f32) -> bool {
        let c = self.clear_at;
        // Four more samples leave `after · (after/before)` of a half batch's rate, and
        // `after · √(after/before)` at a whole batch's: compared without dividing.
        c >= 0.0
            && if half {
                after * after <= c * before
            } else {
                after * after * after <= c * c * before
            }
    }
}

impl<T: Voxel> Marcher<'_, '_, '_, T> {
    /// [`Marcher::accumulate_skipping`] on the fast path; `None` where this ray cannot take it
    /// (a light straight behind the viewer has no half vector: the scalar code then derives
    /// one per sample). Otherwise the index of the sample that stopped the ray, if one did.
    #[allow(clippy::too_many_arguments)] // the march's per-sample hot path: see trace.rs
    pub(super) fn accumulate_lanes(
        &self,
        lanes: &Lanes<'_>,
        cells: &VisibleCells,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        from: f32,
        viewing: &Viewing<'_>,
        stop_at: f32,
        acc: &mut Accumulation,
    ) -> Option<Option<u32>> {
        let mut rl = RayLights {
            view: viewing.view,
            lights: [(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO); MAX_LIGHTS],
        };
        for i in 0..lanes.light_count {
            let (dir, color) = lanes.lights[i];
            let half = if lanes.blinn {
                viewing.half(i)?
            } else {
                Vec3::ZERO
            };
            rl.lights[i] = (dir, color, half);
        }
        let ray = Ray {
            plan,
            o_v: o_v.into(),
            d_v: d_v.into(),
            from,
            lights: &rl,
            stop_at,
            clear_at: 1.0 - stop_at,
        };
        Some(lanes.backend.run(March {
            lanes,
            cells,
            ray: &ray,
            acc,
        }))
    }
}

/// One ray's [`Lanes::march`], to run with the backend's vectors.
struct March<'a, 'l> {
    lanes: &'a Lanes<'l>,
    cells: &'a VisibleCells,
    ray: &'a Ray<'a>,
    acc: &'a mut Accumulation,
}

impl Kernel for March<'_, '_> {
    type Output = Option<u32>;
    #[inline(always)]
    fn run<S: Simd>(self, s: S) -> Option<u32> {
        self.lanes.march(s, self.cells, self.ray, self.acc)
    }
}

impl Lanes<'_> {
    /// The positions of the ray from `t = from` on (its pixel's entry bound) located eight at
    /// a time, the visible samples evaluated eight at a time; where the next position lies in
    /// an empty brick, the ray first leaps over the empty bricks ahead of it
    /// ([`VisibleCells::leap_exit_at`]).
    #[inline(always)]
    fn march<S: Simd>(
        &self,
        s: S,
        cells: &VisibleCells,
        ray: &Ray<'_>,
        acc: &mut Accumulation,
    ) -> Option<u32> {
        let Ray { plan, o_v, d_v, .. } = *ray;
        let (o_v, d_v) = (Vec3::from(o_v), Vec3::from(d_v));
        let inv_dt = 1.0 / plan.dt;
        let inv_d = 1.0 / d_v;
        let mut pending = Pending::default();
        // Only the part of the ray in the box of the visible bricks, and from its entry bound
        // on, can hold a visible cell.
        let (t0, t1) = cells.visible_interval(o_v, inv_d)?;
        let t0 = crate::minmax::fmax(t0, ray.from);
        let mut k = first_index_from(plan, t0, inv_dt);
        let end = first_index_from(plan, t1, inv_dt);
        // The distances ahead of a ray moving in this one's octant: its leaps are as long as
        // the empty bricks in front of it allow (positions only grow along an axis it moves
        // up and only shrink along one it moves down, rounding included).
        let ahead = cells.forward_distances(crate::skip::octant(d_v));
        let rows = self.corner_rows();
        // SAFETY: every x86-64 backend's CPU has SSE 4.1 (`simd.rs`), all that `Leaps` uses
        // (`leaps_scalar.rs`, on ARM, needs nothing).
        let leaps = unsafe { Leaps::new(cells, (o_v, d_v, inv_d), (self.last, self.max_lo)) };
        // Whether to look for an empty brick before locating the next eight: not right after
        // a visible cell, whose brick is visible and most likely the next position's too (a
        // look costs nearly what locating eight does), nor right after a leap, which ends
        // where the largest cube of empty bricks ahead does, so often beside a visible brick
        // (a ray of the CT's peer view looked ten times and leapt six; locating at once after
        // a leap made the CT 6 % faster: BENCHMARKS.md). Leaps skip only empty cells, so the
        // image is the same either way.
        let mut look_first = true;
        // Whether the ray is near its end (`Ray::ends_within_four`): then it takes four
        // samples at a time.
        let mut near = false;
        while k < end {
            // In an empty brick the ray leaps before it locates anything.
            if look_first {
                // SAFETY: SSE 4.1, as above.
                let look = unsafe { leaps.look(sample_t(plan, k)) };
                let distance = ahead[look.index];
                if distance > 0 {
                    // SAFETY: SSE 4.1, as above.
                    let t = unsafe { leaps.exit(&look, distance) };
                    let next = unsafe { super::leaps::first_index_from(plan, t, inv_dt) };
                    if next > k {
                        k = next;
                        look_first = false;
                        continue;
                    }
                }
            }
            let (taken, visible, located) = self.locate(s, plan, k, end, (o_v, d_v));
            look_first = visible >> (taken - 1) & 1 == 0;
            if visible != 0 {
                // Fewer than eight are waiting, so eight more fit.
                let queued = pending.push(s, visible, &located);
                for &base in &pending.base[queued] {
                    prefetch(s, &rows, base);
                }
                loop {
                    // Near its end a ray takes four at a time: fewer evaluated past it.
                    let before = 1.0 - acc.o;
                    // SAFETY: every pending base is a cell of the lattice.
                    let stop = if near {
                        if pending.n < HALF {
                            break;
                        }
                        unsafe { self.take::<S, HALF>(s, &mut pending, ray, plan, acc) }
                    } else {
                        if pending.n < LANES {
                            break;
                        }
                        unsafe { self.take::<S, LANES>(s, &mut pending, ray, plan, acc) }
                    };
                    if stop.is_some() {
                        return stop;
                    }
                    near = ray.ends_within_four(near, before, 1.0 - acc.o);
                }
            }
            k += taken;
        }
        if pending.n > 0 {
            // Unused lanes read the first record (their results are ignored).
            let n = pending.n;
            pending.base[n..LANES].fill(0);
            // SAFETY: as above.
            let e = unsafe {
                if n <= HALF {
                    self.evaluate::<S, HALF>(s, &pending, ray.lights, None)
                } else {
                    self.evaluate::<S, LANES>(s, &pending, ray.lights, None)
                }
            };
            return self.composite(plan, &pending, n, &e, ray.stop_at, acc);
        }
        None
    }

    /// Evaluates the first `W` pending samples (at least `W` are waiting), composites them and
    /// drops them: the index of the sample that stopped the ray, if one did.
    ///
    /// # Safety
    /// As [`Lanes::evaluate`].
    #[inline(always)]
    unsafe fn take<S: Simd, const W: usize>(
        &self,
        s: S,
        pending: &mut Pending,
        ray: &Ray<'_>,
        plan: &StepPlan,
        acc: &mut Accumulation,
    ) -> Option<u32> {
        // SAFETY: the caller's.
        let e = unsafe { self.evaluate::<S, W>(s, pending, ray.lights, Some(plan)) };
        let stop = self.composite(plan, pending, W, &e, ray.stop_at, acc);
        pending.shift::<W>();
        stop
    }

    /// Where the rows of a cell's corners start in the records, for [`prefetch`]: the lower
    /// row and the rows above it, behind it, and both.
    fn corner_rows(&self) -> [*const crate::sample::Differences; 4] {
        let p = self.records.as_ptr();
        // Only hints are given with them: an address past the records is never dereferenced.
        [0, 2, 4, 6].map(|c| p.wrapping_add(self.corners[c] as usize))
    }

    /// Composites the first `n` pending samples in order, exactly as
    /// `Marcher::composite_sample` does (`accumulate_front_to_back`'s operations, each
    /// rounded as there); the index of the sample that stopped the ray, if one did. The
    /// opacity goes first, alone: it is the chain every sample waits on (subtract, multiply,
    /// add: 9 cycles). Carried with the colour, the compiler packed all four into one vector
    /// (first with `Vec3`s, then with four scalars), and each sample's opacity waited for the
    /// shuffles too: 11 to 16 cycles.
    #[inline(always)]
    fn composite(
        &self,
        plan: &StepPlan,
        p: &Pending,
        n: usize,
        e: &Evaluated,
        stop_at: f32,
        acc: &mut Accumulation,
    ) -> Option<u32> {
        let mut o = acc.o;
        let mut stopped = None;
        let mut taken = n as u32;
        // accumulate_front_to_back in two passes: the opacity and each sample's weight, then
        // the colour with those weights in the same order (so the same sums).
        let mut weights = [0.0f32; LANES];
        let mut blended = 0u32;
        // Only the lanes with opacity: a bit each, so that the many transparent samples cost
        // no unpredictable branch apiece.
        let mut lanes = e.opaque & ((1u32 << n) - 1);
        while lanes != 0 {
            let lane = lanes.trailing_zeros() as usize;
            lanes &= lanes - 1;
            let a = e.alpha[lane];
            let (k, t) = (p.k[lane] as u32, p.t[lane]);
            let alpha = if self.correction && !e.corrected {
                correct_opacity_with(a, segment_length(plan, k, t), self.dt_ref, self.whole_step)
            } else {
                a
            };
            if alpha > 0.0 {
                let w = (1.0 - o) * alpha;
                weights[lane] = w;
                blended |= 1 << lane;
                o += w;
            }
            if o >= stop_at {
                stopped = Some(k);
                taken = lane as u32 + 1;
                break;
            }
        }
        let [mut r, mut g, mut b] = acc.c.to_array();
        while blended != 0 {
            let lane = blended.trailing_zeros() as usize;
            blended &= blended - 1;
            let w = weights[lane];
            r += e.rgb[0][lane] * w;
            g += e.rgb[1][lane] * w;
            b += e.rgb[2][lane] * w;
        }
        acc.c = Vec3::new(r, g, b);
        acc.o = o;
        acc.taken += taken;
        stopped
    }
}

/// Asks for the cache lines of a queued sample's corners (`base`: its cell's lower corner;
/// `rows` from [`Lanes::corner_rows`]) while the batch fills up: they are read once it is full.
/// One instruction a row, the row's start per ray.
#[inline(always)]
fn prefetch<S: Simd>(s: S, rows: &[*const crate::sample::Differences; 4], base: i32) {
    let base = base as usize;
    for &row in rows {
        s.prefetch(row.wrapping_add(base) as *const u8);
    }
}
