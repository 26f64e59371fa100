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
//! waiting they are *evaluated* together: the eight corners' records
//! ([`crate::sample::Differences`]) gathered, the value and gradient blended, the table looked
//! up, the colour shaded — the very operations of `Marcher::evaluate`, in the same order, with
//! no fused multiply-add, so every lane's numbers are the scalar ones — and, where every sample
//! of the batch stands for one whole step, their opacity corrected. Then the samples are
//! *composited* one by one, in order along the ray, by the scalar code itself (opacity
//! correction where not done yet, front-to-back blend, early termination). A ray that stops
//! early has evaluated up to seven samples beyond its last; they are dropped, as are positions
//! located past it.
//!
//! Used where it applies exactly: Accumulate front to back with skipping, trilinear, table
//! classification, the precomputed records (an integer volume, shading on), directional lights,
//! the shortened illumination model (no emission, global ambient 1, no light's own ambient, no
//! depth cue: [`crate::shade::Phong::full_form`]) and a whole-number shininess (the scalar
//! code then raises by repeated squaring, which lanes repeat step for step). Anything else, or a CPU with none of those vector units, takes the
//! scalar march. `tests/lanes.rs` renders random scenes with each backend and without lanes, and compares
//! every bit.

use super::leaps::Leaps;
use super::simd::{Backend, Kernel, Simd};
use super::{Accumulation, Marcher};
use crate::composite::correct_opacity_with;
use crate::power::StepPower;
use crate::scene::Scene;
use crate::shade::{Highlight, MAX_LIGHTS, ResolvedLight, SpecularModel, Viewing};
use crate::skip::VisibleCells;
use crate::step::{StepPlan, first_index_from, sample_t, segment_length};
use crate::volume::{Grid, Voxel};
use glam::Vec3;

/// Lanes per batch (eight `f32`: one AVX2 vector, two SSE or NEON ones).
const LANES: usize = 8;

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
        let (_, cells) = s.empty.as_ref()?;
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
struct Ray<'p> {
    plan: &'p StepPlan,
    o_v: Vec3,
    d_v: Vec3,
    from: f32,
    /// Borrowed: a `RayLights` moved in was copied by a call to `memcpy` a ray.
    lights: &'p RayLights,
    stop_at: f32,
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
            o_v,
            d_v,
            from,
            lights: &rl,
            stop_at,
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
        // look costs nearly what locating eight does). Leaps skip only empty cells, so the
        // image is the same either way.
        let mut look_first = true;
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
                if pending.n >= LANES {
                    // SAFETY: every pending base is a cell of the lattice.
                    let e = unsafe { self.evaluate(s, &pending, ray.lights, Some(plan)) };
                    let stop = self.composite(plan, &pending, LANES, &e, ray.stop_at, acc);
                    if stop.is_some() {
                        return stop;
                    }
                    pending.shift();
                }
            }
            k += taken;
        }
        if pending.n > 0 {
            // Unused lanes read the first record (their results are ignored).
            let n = pending.n;
            pending.base[n..LANES].fill(0);
            // SAFETY: as above.
            let e = unsafe { self.evaluate(s, &pending, ray.lights, None) };
            return self.composite(plan, &pending, n, &e, ray.stop_at, acc);
        }
        None
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

/// Eight positions located: their index `k` and `t`, the cell's record index and the
/// fractions inside it.
struct Located<S: Simd> {
    k: S::I,
    t: S::F,
    base: S::I,
    fx: S::F,
    fy: S::F,
    fz: S::F,
}

impl Pending {
    /// Queues the positions of `located` whose bit is set in `visible`, in order,
    /// behind those waiting; the range of `base` they took. Fewer than [`LANES`] may be
    /// waiting.
    #[inline(always)]
    fn push<S: Simd>(
        &mut self,
        s: S,
        visible: u32,
        located: &Located<S>,
    ) -> std::ops::Range<usize> {
        let n = self.n;
        assert!(n < LANES);
        let order = s.order(visible);
        // SAFETY: n < 8, so lanes n .. n + 8 lie in the arrays of sixteen.
        unsafe {
            s.pack_i(self.k.as_mut_ptr().add(n), located.k, order);
            s.pack_i(self.base.as_mut_ptr().add(n), located.base, order);
            s.pack(self.t.as_mut_ptr().add(n), located.t, order);
            s.pack(self.fx.as_mut_ptr().add(n), located.fx, order);
            s.pack(self.fy.as_mut_ptr().add(n), located.fy, order);
            s.pack(self.fz.as_mut_ptr().add(n), located.fz, order);
        }
        self.n = n + visible.count_ones() as usize;
        n..self.n
    }

    /// Drops the first batch (at least [`LANES`] are waiting): those waiting behind it move to
    /// the front.
    #[inline(always)]
    fn shift(&mut self) {
        self.k.copy_within(LANES.., 0);
        self.base.copy_within(LANES.., 0);
        self.t.copy_within(LANES.., 0);
        self.fx.copy_within(LANES.., 0);
        self.fy.copy_within(LANES.., 0);
        self.fz.copy_within(LANES.., 0);
        self.n -= LANES;
    }
}

impl Lanes<'_> {
    /// Locates positions `k .. k + 8`: how many of them lie before `end`, and as bits which of
    /// those lie in a visible cell.
    #[inline(always)]
    fn locate<S: Simd>(
        &self,
        s: S,
        plan: &StepPlan,
        k: u32,
        end: u32,
        (o_v, d_v): (Vec3, Vec3),
    ) -> (u32, u32, Located<S>) {
        let c = super::positions::cells(s, plan, k, (o_v, d_v), (self.last, self.max_lo));
        let taken = (end - k).min(LANES as u32);
        let [ix, iy, iz] = c.i;
        // VisibleCells::lookup: the brick's word, the cell's bit in it (read as 32-bit halves).
        let word = s.add_i(
            s.shr_i::<2>(ix),
            s.add_i(
                s.mul_i(s.shr_i::<2>(iy), s.splat_i(self.bricks_x)),
                s.mul_i(s.shr_i::<2>(iz), s.splat_i(self.bricks_xy)),
            ),
        );
        let three = s.splat_i(3);
        let bit = s.or_i(
            s.and_i(ix, three),
            s.or_i(
                s.shl_i::<2>(s.and_i(iy, three)),
                s.shl_i::<4>(s.and_i(iz, three)),
            ),
        );
        let half = s.add_i(s.shl_i::<1>(word), s.shr_i::<5>(bit));
        // SAFETY: every lane's cell is in the lattice (clamped), so its word exists.
        let set = unsafe { s.bit_set(self.words.as_ptr() as *const i32, half, bit) };
        let visible = set & ((1u32 << taken) - 1);
        let [fx, fy, fz] = c.f;
        let out = Located {
            k: c.k,
            t: c.t,
            base: c.corner(s, self.nx, self.nxy),
            fx,
            fy,
            fz,
        };
        (taken, visible, out)
    }

    /// Evaluates the pending samples: `value_and_gradient_in_cell`, `Grid::to_data`,
    /// `Lut::lookup_if_visible` and `shade` for eight lanes, operation for operation; for a
    /// full batch (`plan` given) also the opacity correction where [`Lanes::correct_batch`]
    /// can.
    ///
    /// # Safety
    /// Every pending base of the first eight is the lower corner of a cell of the lattice.
    #[inline(always)]
    unsafe fn evaluate<S: Simd>(
        &self,
        s: S,
        p: &Pending,
        rl: &RayLights,
        plan: Option<&StepPlan>,
    ) -> Evaluated {
        // SAFETY: the caller's.
        let b = unsafe { self.blend_records(s, p) };
        let half = s.splat(0.5);
        let gs = self.gradient_scale;
        let grad = [
            s.mul(s.mul(b[0], half), s.splat(gs.x)),
            s.mul(s.mul(b[1], half), s.splat(gs.y)),
            s.mul(s.mul(b[2], half), s.splat(gs.z)),
        ];
        let v = s.add(s.mul(b[3], s.splat(self.slope)), s.splat(self.intercept));
        // The table: position, the two entries, opaque where either has opacity.
        let zero = s.splat(0.0);
        let x = s.min(
            s.max(
                s.mul(s.sub(v, s.splat(self.lut_lo)), s.splat(self.lut_scale)),
                zero,
            ),
            s.splat(self.lut_last),
        );
        let i = s.min_i(s.trunc(x), s.splat_i(self.lut_max_index));
        let f = s.sub(x, s.to_f(i));
        // SAFETY: i ≤ len − 2, so entries i and i + 1 exist.
        let (a, bb) = unsafe { self.entry_pairs(s, i) };
        let opaque = s.or(s.gt(a[3], zero), s.gt(bb[3], zero));
        let rgba = [
            lerp(s, a[0], bb[0], f),
            lerp(s, a[1], bb[1], f),
            lerp(s, a[2], bb[2], f),
            lerp(s, a[3], bb[3], f),
        ];
        let alpha = s.and(opaque, rgba[3]);
        let color = [rgba[0], rgba[1], rgba[2]];
        let shaded = self.shade(s, color, grad, rl);
        let corrected = match plan {
            Some(plan) => self.correct_batch(s, plan, p, alpha),
            None => None,
        };
        let alpha = corrected.unwrap_or(alpha);
        let mut out = Evaluated {
            alpha: [0.0; LANES],
            // Not `≤ 0`, as the scalar composite asks (unordered: a NaN is blended there too).
            opaque: s.bits(s.not_le(alpha, zero)),
            rgb: [[0.0; LANES]; 3],
            corrected: corrected.is_some(),
        };
        // SAFETY: eight lanes each.
        unsafe {
            s.store(out.alpha.as_mut_ptr(), alpha);
            for (ch, c) in shaded.iter().enumerate() {
                s.store(out.rgb[ch].as_mut_ptr(), *c);
            }
        }
        out
    }

    /// `correct_opacity` for a full batch at once, where it is the same for every lane: each
    /// sample stands for exactly one step (`segment_length`'s interior case) and the step's
    /// power is one the scalar code takes without `powf` ([`Lanes::batch_power`]): ½ is a
    /// square root and 2 a square, correctly rounded in lanes as alone. `None` otherwise (the
    /// composite then corrects sample by sample).
    #[inline(always)]
    fn correct_batch<S: Simd>(
        &self,
        s: S,
        plan: &StepPlan,
        p: &Pending,
        alpha: S::F,
    ) -> Option<S::F> {
        let e = self.batch_power.filter(|_| self.correction)?;
        // SAFETY: the arrays hold sixteen lanes; the batch is the first eight.
        let (k, t) = unsafe { (s.load_i(p.k.as_ptr()), s.load(p.t.as_ptr())) };
        // segment_length's interior: k > 0, not the last sample, t + dt/2 ≤ t_exit.
        let first = s.eq_i(k, s.splat_i(0));
        let last = if plan.capped {
            s.splat(0.0)
        } else {
            s.eq_i(k, s.splat_i(plan.count as i32 - 1))
        };
        let inside = s.le(s.add(t, s.splat(0.5 * plan.dt)), s.splat(plan.t_exit));
        let edge = s.or(first, last);
        if s.bits(s.and_not(edge, inside)) != 0xFF {
            return None;
        }
        let one = s.splat(1.0);
        let keep = s.sub(one, alpha);
        let raised = if e == 1.0 {
            alpha
        } else if e == 0.5 {
            s.sub(one, s.sqrt(keep))
        } else {
            s.sub(one, s.mul(keep, keep))
        };
        // α ≤ 0 stays (the composite passes over it); α ≥ 1 is 1 (the step is positive).
        let opaque = s.ge(alpha, one);
        let clear = s.le(alpha, s.splat(0.0));
        Some(s.select(s.select(raised, one, opaque), alpha, clear))
    }

    /// `value_and_gradient_in_cell` for the pending lanes: each lane's cell read as four pairs
    /// of records side by side along x (16 bytes each), blended x, y, z in its own lanes, then
    /// the eight results turned into one vector per channel (differences x, y, z, raw value).
    /// The pairs are regrouped as 64-bit integers before widening — `[c000 | c001]` against
    /// `[c100 | c101]`, `[c010 | c011]` against `[c110 | c111]` — so that the x blend gives
    /// `[x00 | x01]` and `[x10 | x11]` and the y blend `[y0 | y1]` with no move across AVX2's
    /// halves (`vperm2f128`: one micro-operation on Zen 4, eight on Zen 1).
    ///
    /// # Safety
    /// Every pending base of the first eight is the lower corner of a cell whose upper x
    /// corner is the next record (`Lanes::new` takes volumes with more than one point along x
    /// only).
    #[inline(always)]
    unsafe fn blend_records<S: Simd>(&self, s: S, p: &Pending) -> [S::F; 4] {
        let [_, _, dy, _, dz, _, dzy, _] = self.corners;
        let records = self.records.as_ptr();
        let mut rows = [s.zero_h(); LANES];
        for (lane, row) in rows.iter_mut().enumerate() {
            let at = records.wrapping_add(p.base[lane] as usize);
            // SAFETY: the cell's corners (so both records of each pair) are in the lattice.
            let (p00, p10, p01, p11) = unsafe {
                (
                    pair_at(s, at, 0),
                    pair_at(s, at, dy),
                    pair_at(s, at, dz),
                    pair_at(s, at, dzy),
                )
            };
            let (tx, ty) = (s.splat(p.fx[lane]), s.splat(p.fy[lane]));
            // [x00 | x01] and [x10 | x11]: each low corner against its high one along x.
            // SAFETY: the pairs were just taken, of records nothing writes.
            let (lo, hi) = unsafe { s.widen_pairs(p00, p01) };
            let x0 = lerp(s, lo, hi, tx);
            // SAFETY: as above.
            let (lo, hi) = unsafe { s.widen_pairs(p10, p11) };
            let x1 = lerp(s, lo, hi, tx);
            // [y0 | y1] = [x00 | x01] against [x10 | x11].
            let (y0, y1) = s.halves(lerp(s, x0, x1, ty));
            *row = s.lerp_h(y0, y1, p.fz[lane]);
        }
        s.columns(rows)
    }

    /// Table entries `i` and `i + 1` of each lane as columns (red, green, blue, opacity):
    /// each lane's two entries read as rows of four and turned around, which costs less than
    /// eight gathers (on Zen 1 a gather of eight is some twenty micro-operations).
    ///
    /// # Safety
    /// Every lane's `i` is at most the table's length − 2.
    #[inline(always)]
    unsafe fn entry_pairs<S: Simd>(&self, s: S, i: S::I) -> ([S::F; 4], [S::F; 4]) {
        let mut at = [0i32; LANES];
        // SAFETY: eight lanes into eight slots.
        unsafe { s.store_i(at.as_mut_ptr(), i) };
        let entries = self.entries.as_ptr() as *const f32;
        let (mut lo, mut hi) = ([s.zero_h(); LANES], [s.zero_h(); LANES]);
        for lane in 0..LANES {
            // SAFETY: the caller's bound; an entry is four floats.
            unsafe {
                let row = entries.add(4 * at[lane] as usize);
                lo[lane] = s.load_h(row);
                hi[lane] = s.load_h(row.add(4));
            }
        }
        (s.columns(lo), s.columns(hi))
    }

    /// `crate::shade::shade` for eight lanes with directional lights, operation for operation.
    #[inline(always)]
    fn shade<S: Simd>(&self, s: S, c: [S::F; 3], grad: [S::F; 3], rl: &RayLights) -> [S::F; 3] {
        let len = s.sqrt(s.add(
            s.add(s.mul(grad[0], grad[0]), s.mul(grad[1], grad[1])),
            s.mul(grad[2], grad[2]),
        ));
        // lit: len > threshold and finite (ordered comparisons: NaN is neither).
        let lit = s.and(
            s.gt(len, s.splat(self.threshold)),
            s.lt(len, s.splat(f32::INFINITY)),
        );
        let inv = s.div(s.splat(-1.0), len);
        let mut n = [
            s.mul(grad[0], inv),
            s.mul(grad[1], inv),
            s.mul(grad[2], inv),
        ];
        let zero = s.splat(0.0);
        if self.two_sided {
            let back = s.lt(dot(s, &n, rl.view), zero);
            let sign = s.and(back, s.splat(-0.0));
            n = [s.xor(n[0], sign), s.xor(n[1], sign), s.xor(n[2], sign)];
        }
        let tint = if self.levoy { c } else { [s.splat(1.0); 3] };
        let (mut diffuse, mut specular) = ([zero; 3], [zero; 3]);
        for &(l, color, half) in &rl.lights[..self.light_count] {
            let n_dot_l = dot(s, &n, l);
            let lambert = s.max(n_dot_l, zero);
            let base = if self.blinn {
                dot(s, &n, half)
            } else {
                // (n·(2·n_dot_l) − l)·view
                let two = s.mul(s.splat(2.0), n_dot_l);
                let r = [
                    s.sub(s.mul(n[0], two), s.splat(l.x)),
                    s.sub(s.mul(n[1], two), s.splat(l.y)),
                    s.sub(s.mul(n[2], two), s.splat(l.z)),
                ];
                dot(s, &r, rl.view)
            };
            let spec = s.and(
                s.gt(n_dot_l, zero),
                power(s, s.max(base, zero), self.exponent),
            );
            let kd_lambert = s.mul(s.splat(self.kd), lambert);
            let ks_spec = s.mul(s.splat(self.ks), spec);
            let light = color.to_array();
            for ch in 0..3 {
                let d = s.mul(c[ch], s.mul(s.splat(light[ch]), kd_lambert));
                let sp = s.mul(s.mul(tint[ch], s.splat(light[ch])), ks_spec);
                diffuse[ch] = s.add(diffuse[ch], d);
                specular[ch] = s.add(specular[ch], sp);
            }
        }
        // A loop, not `map` with a closure: the closure was left out of line (a call per
        // channel, its vectors through memory).
        let mut shaded = [zero; 3];
        for (ch, out) in shaded.iter_mut().enumerate() {
            let ambient = s.mul(c[ch], s.splat(self.ka));
            let sum = s.add(s.add(ambient, diffuse[ch]), specular[ch]);
            let clamped = s.min(s.max(sum, zero), s.splat(1.0));
            *out = s.select(c[ch], clamped, lit);
        }
        shaded
    }
}

// The helpers below are functions, not closures: a closure in these generic functions is
// compiled without the backend's instructions and may be left out of line, with every
// intrinsic in it a call.

/// `a + (b − a)·t`, lane by lane.
#[inline(always)]
fn lerp<S: Simd>(s: S, a: S::F, b: S::F, t: S::F) -> S::F {
    s.add(a, s.mul(s.sub(b, a), t))
}

/// `a · b` for eight vectors `a` and one `b`, summed x, y, z in that order.
#[inline(always)]
fn dot<S: Simd>(s: S, a: &[S::F; 3], b: Vec3) -> S::F {
    s.add(
        s.add(s.mul(a[0], s.splat(b.x)), s.mul(a[1], s.splat(b.y))),
        s.mul(a[2], s.splat(b.z)),
    )
}

/// Two records side by side (16 bytes) at record `at + o`.
///
/// # Safety
/// Records `at + o` and `at + o + 1` exist.
#[inline(always)]
unsafe fn pair_at<S: Simd>(s: S, at: *const crate::sample::Differences, o: i32) -> S::R {
    // SAFETY: the caller's.
    unsafe { s.load_pair(at.add(o as usize) as *const u8) }
}

/// `crate::shade::power` for a whole exponent, lane by lane: the same squarings and products.
#[inline(always)]
fn power<S: Simd>(s: S, x: S::F, n: u32) -> S::F {
    let (mut base, mut e, mut acc) = (x, n, s.splat(1.0));
    while e > 0 {
        if e & 1 == 1 {
            acc = s.mul(acc, base);
        }
        base = s.mul(base, base);
        e >>= 1;
    }
    acc
}
