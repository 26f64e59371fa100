//! Accumulate's hot path eight sample positions at a time, on x86-64 CPUs with AVX2: the same
//! pixels as the one-at-a-time march of `skipping.rs`, bit for bit.
//!
//! A ray starts at its pixel's entry bound ([`crate::entry::EntryBounds`], where the render
//! has one) and leaps over empty bricks by their distance to the nearest visible cell ahead
//! ([`VisibleCells::forward_distances`]; the look at the next brick and the leap, three axes in
//! one vector, are in `leaps.rs`). Elsewhere its sample positions are located eight at
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
//! classification, the precomputed records (an integer volume, shading on), directional lights
//! and a whole-number shininess (the scalar code then raises by repeated squaring, which lanes
//! repeat step for step). Anything else, or a CPU without AVX2, takes the scalar march.
//! `tests/lanes.rs` renders random scenes both ways and compares every bit.

use super::leaps::Leaps;
use super::{Accumulation, Marcher};
use crate::composite::correct_opacity_with;
use crate::power::StepPower;
use crate::scene::Scene;
use crate::shade::{Highlight, MAX_LIGHTS, ResolvedLight, SpecularModel, Viewing};
use crate::skip::VisibleCells;
use crate::step::{StepPlan, first_index_from, sample_t, segment_length};
use crate::volume::{Grid, Voxel};
use glam::Vec3;
use std::arch::x86_64::*;

/// Lanes per batch (AVX2: eight `f32`).
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
}

impl<'s> Lanes<'s> {
    /// The fast path's constants, if it applies to `s` and this CPU has AVX2.
    pub(super) fn new<T: Voxel>(s: &'s Scene<'_>, g: &Grid<'_, T>) -> Option<Self> {
        let set = &s.settings;
        let p = &set.phong;
        let applies = s.simd
            && std::arch::is_x86_feature_detected!("avx2")
            && set.interpolation == crate::sample::Interpolation::Trilinear
            && s.classifier == crate::classify::Classifier::Table
            && set.shading
            // `shade::power` squares repeatedly for these only (else it calls `powf`).
            && p.shininess.fract() == 0.0
            && (0.0..=1024.0).contains(&p.shininess);
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
        })
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

/// Per set of lanes (a bit each), the lanes' numbers in order, packed to the front: the
/// permutation that queues the visible ones of eight located positions.
const PACK: [[u8; LANES]; 256] = {
    let mut table = [[0u8; LANES]; 256];
    let mut mask = 0;
    while mask < 256 {
        let (mut lane, mut n) = (0, 0);
        while lane < LANES {
            if mask & (1 << lane) != 0 {
                table[mask][n] = lane as u8;
                n += 1;
            }
            lane += 1;
        }
        mask += 1;
    }
    table
};

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

impl<T: Voxel> Marcher<'_, '_, '_, T> {
    /// [`Marcher::accumulate_skipping`] on the fast path; `None` where this ray cannot take it
    /// (a light straight behind the viewer has no half vector: the scalar code then derives
    /// one per sample). Otherwise the index of the sample that stopped the ray, if one did.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn accumulate_lanes(
        &self,
        lanes: &Lanes<'_>,
        cells: &VisibleCells,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        from: f32,
        viewing: &Viewing,
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
        // SAFETY: `Lanes` exists only where the CPU has AVX2 (checked in `Lanes::new`).
        Some(unsafe { lanes.march(cells, plan, (o_v, d_v), from, &rl, stop_at, acc) })
    }
}

impl Lanes<'_> {
    /// The positions of the ray from `t = from` on (its pixel's entry bound) located eight at
    /// a time, the visible samples evaluated eight at a time; where the next position lies in
    /// an empty brick, the ray first leaps over the empty bricks ahead of it
    /// ([`VisibleCells::leap_exit_at`]).
    #[allow(clippy::too_many_arguments)]
    #[target_feature(enable = "avx2")]
    unsafe fn march(
        &self,
        cells: &VisibleCells,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        from: f32,
        rl: &RayLights,
        stop_at: f32,
        acc: &mut Accumulation,
    ) -> Option<u32> {
        let inv_dt = 1.0 / plan.dt;
        let inv_d = 1.0 / d_v;
        let mut pending = Pending::default();
        // Only the part of the ray in the box of the visible bricks, and from its entry bound
        // on, can hold a visible cell.
        let (t0, t1) = cells.visible_interval(o_v, inv_d)?;
        let t0 = crate::minmax::fmax(t0, from);
        let mut k = first_index_from(plan, t0, inv_dt);
        let end = first_index_from(plan, t1, inv_dt);
        // The distances ahead of a ray moving in this one's octant: its leaps are as long as
        // the empty bricks in front of it allow (positions only grow along an axis it moves
        // up and only shrink along one it moves down, rounding included).
        let ahead = cells.forward_distances(crate::skip::octant(d_v));
        let rows = self.corner_rows();
        let leaps = Leaps::new(cells, (o_v, d_v, inv_d), (self.last, self.max_lo));
        while k < end {
            // In an empty brick the ray leaps before it locates anything.
            let look = leaps.look(sample_t(plan, k));
            let distance = ahead[look.index];
            if distance > 0 {
                let t = leaps.exit(&look, distance);
                let next = super::leaps::first_index_from(plan, t, inv_dt);
                if next > k {
                    k = next;
                    continue;
                }
            }
            // SAFETY: AVX2 (this function's own feature).
            let (taken, visible, located) = unsafe { self.locate(plan, k, end, (o_v, d_v)) };
            if visible != 0 {
                // SAFETY: AVX2; fewer than eight are waiting, so eight more fit.
                let queued = unsafe { pending.push(visible, &located) };
                for &base in &pending.base[queued] {
                    prefetch(&rows, base);
                }
                if pending.n >= LANES {
                    // SAFETY: AVX2; every pending base is a cell of the lattice.
                    let e = unsafe { self.evaluate(&pending, rl, Some(plan)) };
                    if let Some(stop) = self.composite(plan, &pending, LANES, &e, stop_at, acc) {
                        return Some(stop);
                    }
                    // SAFETY: AVX2.
                    unsafe { pending.shift() };
                }
            }
            k += taken;
        }
        if pending.n > 0 {
            // Unused lanes read the first record (their results are ignored).
            let n = pending.n;
            pending.base[n..LANES].fill(0);
            // SAFETY: as above.
            let e = unsafe { self.evaluate(&pending, rl, None) };
            return self.composite(plan, &pending, n, &e, stop_at, acc);
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
    /// opacity and the three colour channels are carried as four scalars: packed into one
    /// vector (as the compiler did with `Vec3`s), each sample's opacity waited for the colour's
    /// shuffles too (about 16 cycles a sample instead of the 9 of subtract, multiply, add).
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
        let [mut r, mut g, mut b] = acc.c.to_array();
        let mut o = acc.o;
        let mut stopped = None;
        let mut taken = n as u32;
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
                // accumulate_front_to_back, channel by channel.
                let w = (1.0 - o) * alpha;
                r += e.rgb[0][lane] * w;
                g += e.rgb[1][lane] * w;
                b += e.rgb[2][lane] * w;
                o += w;
            }
            if o >= stop_at {
                stopped = Some(k);
                taken = lane as u32 + 1;
                break;
            }
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
#[inline]
#[target_feature(enable = "avx2")]
fn prefetch(rows: &[*const crate::sample::Differences; 4], base: i32) {
    let base = base as usize;
    for &row in rows {
        _mm_prefetch::<_MM_HINT_T0>(row.wrapping_add(base) as *const i8);
    }
}

/// Eight positions located: their index `k` and `t`, the cell's record index and the
/// fractions inside it.
struct Located {
    k: __m256i,
    t: __m256,
    base: __m256i,
    fx: __m256,
    fy: __m256,
    fz: __m256,
}

impl Pending {
    /// Queues the positions of `located` whose bit is set in `visible`, in order,
    /// behind those waiting; the range of `base` they took.
    ///
    /// # Safety
    /// AVX2; fewer than [`LANES`] are waiting.
    #[inline]
    #[target_feature(enable = "avx2")]
    unsafe fn push(&mut self, visible: u32, located: &Located) -> std::ops::Range<usize> {
        let n = self.n;
        debug_assert!(n < LANES);
        // SAFETY: the table's row is eight bytes.
        let order = _mm256_cvtepu8_epi32(unsafe {
            _mm_loadl_epi64(PACK[visible as usize].as_ptr() as *const __m128i)
        });
        let pack = |v: __m256| _mm256_permutevar8x32_ps(v, order);
        // SAFETY: n < 8, so lanes n .. n + 8 lie in the arrays of sixteen.
        unsafe {
            _mm256_storeu_si256(
                self.k.as_mut_ptr().add(n) as *mut __m256i,
                _mm256_permutevar8x32_epi32(located.k, order),
            );
            _mm256_storeu_si256(
                self.base.as_mut_ptr().add(n) as *mut __m256i,
                _mm256_permutevar8x32_epi32(located.base, order),
            );
            _mm256_storeu_ps(self.t.as_mut_ptr().add(n), pack(located.t));
            _mm256_storeu_ps(self.fx.as_mut_ptr().add(n), pack(located.fx));
            _mm256_storeu_ps(self.fy.as_mut_ptr().add(n), pack(located.fy));
            _mm256_storeu_ps(self.fz.as_mut_ptr().add(n), pack(located.fz));
        }
        self.n = n + visible.count_ones() as usize;
        n..self.n
    }

    /// Drops the first batch: those waiting behind it move to the front.
    ///
    /// # Safety
    /// AVX2; at least [`LANES`] are waiting.
    #[inline]
    #[target_feature(enable = "avx2")]
    unsafe fn shift(&mut self) {
        // SAFETY: lanes 8 .. 16 exist in each array.
        unsafe {
            let move_i = |a: &mut [i32; 2 * LANES]| {
                let upper = _mm256_loadu_si256(a.as_ptr().add(LANES) as *const __m256i);
                _mm256_storeu_si256(a.as_mut_ptr() as *mut __m256i, upper);
            };
            let move_f = |a: &mut [f32; 2 * LANES]| {
                _mm256_storeu_ps(a.as_mut_ptr(), _mm256_loadu_ps(a.as_ptr().add(LANES)));
            };
            move_i(&mut self.k);
            move_i(&mut self.base);
            move_f(&mut self.t);
            move_f(&mut self.fx);
            move_f(&mut self.fy);
            move_f(&mut self.fz);
        }
        self.n -= LANES;
    }
}

impl Lanes<'_> {
    /// Locates positions `k .. k + 8`: how many of them lie before `end`, and as bits which of
    /// those lie in a visible cell.
    #[target_feature(enable = "avx2")]
    unsafe fn locate(
        &self,
        plan: &StepPlan,
        k: u32,
        end: u32,
        (o_v, d_v): (Vec3, Vec3),
    ) -> (u32, u32, Located) {
        let c = super::value_lanes::cells(plan, k, (o_v, d_v), (self.last, self.max_lo));
        let taken = (end - k).min(LANES as u32);
        let [ix, iy, iz] = c.i;
        // VisibleCells::lookup: the brick's word, the cell's bit in it (read as 32-bit halves).
        let word = _mm256_add_epi32(
            _mm256_srli_epi32::<2>(ix),
            _mm256_add_epi32(
                _mm256_mullo_epi32(_mm256_srli_epi32::<2>(iy), _mm256_set1_epi32(self.bricks_x)),
                _mm256_mullo_epi32(
                    _mm256_srli_epi32::<2>(iz),
                    _mm256_set1_epi32(self.bricks_xy),
                ),
            ),
        );
        let three = _mm256_set1_epi32(3);
        let bit = _mm256_or_si256(
            _mm256_and_si256(ix, three),
            _mm256_or_si256(
                _mm256_slli_epi32::<2>(_mm256_and_si256(iy, three)),
                _mm256_slli_epi32::<4>(_mm256_and_si256(iz, three)),
            ),
        );
        let half = _mm256_add_epi32(_mm256_slli_epi32::<1>(word), _mm256_srli_epi32::<5>(bit));
        // SAFETY: every lane's cell is in the lattice (clamped above), so its word exists.
        let halves =
            unsafe { _mm256_i32gather_epi32::<4>(self.words.as_ptr() as *const i32, half) };
        let set = _mm256_and_si256(
            _mm256_srlv_epi32(halves, _mm256_and_si256(bit, _mm256_set1_epi32(31))),
            _mm256_set1_epi32(1),
        );
        let visible = _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(
            set,
            _mm256_set1_epi32(1),
        ))) as u32
            & ((1u32 << taken) - 1);
        let [fx, fy, fz] = c.f;
        let out = Located {
            k: c.k,
            t: c.t,
            base: c.corner(self.nx, self.nxy),
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
    #[target_feature(enable = "avx2")]
    unsafe fn evaluate(&self, p: &Pending, rl: &RayLights, plan: Option<&StepPlan>) -> Evaluated {
        // SAFETY: every pending base is a cell of the lattice.
        let b = unsafe { self.blend_records(p) };
        let half = _mm256_set1_ps(0.5);
        let gs = self.gradient_scale;
        let grad = [
            _mm256_mul_ps(_mm256_mul_ps(b[0], half), _mm256_set1_ps(gs.x)),
            _mm256_mul_ps(_mm256_mul_ps(b[1], half), _mm256_set1_ps(gs.y)),
            _mm256_mul_ps(_mm256_mul_ps(b[2], half), _mm256_set1_ps(gs.z)),
        ];
        let v = _mm256_add_ps(
            _mm256_mul_ps(b[3], _mm256_set1_ps(self.slope)),
            _mm256_set1_ps(self.intercept),
        );
        // The table: position, the two entries, opaque where either has opacity.
        let x = _mm256_min_ps(
            _mm256_max_ps(
                _mm256_mul_ps(
                    _mm256_sub_ps(v, _mm256_set1_ps(self.lut_lo)),
                    _mm256_set1_ps(self.lut_scale),
                ),
                _mm256_setzero_ps(),
            ),
            _mm256_set1_ps(self.lut_last),
        );
        let i = _mm256_min_epi32(
            _mm256_cvttps_epi32(x),
            _mm256_set1_epi32(self.lut_max_index),
        );
        let f = _mm256_sub_ps(x, _mm256_cvtepi32_ps(i));
        // SAFETY: i ≤ len − 2, so entries i and i + 1 exist.
        let (a, bb) = unsafe { self.entry_pairs(i) };
        let zero = _mm256_setzero_ps();
        let opaque = _mm256_or_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(a[3], zero),
            _mm256_cmp_ps::<_CMP_GT_OQ>(bb[3], zero),
        );
        let lerp = |a: [__m256; 4], b: [__m256; 4], f: __m256| -> [__m256; 4] {
            [0, 1, 2, 3].map(|c| _mm256_add_ps(a[c], _mm256_mul_ps(_mm256_sub_ps(b[c], a[c]), f)))
        };
        let rgba = lerp(a, bb, f);
        let alpha = _mm256_and_ps(opaque, rgba[3]);
        let color = [rgba[0], rgba[1], rgba[2]];
        let shaded = self.shade(color, grad, rl);
        let corrected = plan.and_then(|plan| self.correct_batch(plan, p, alpha));
        let alpha = corrected.unwrap_or(alpha);
        let mut out = Evaluated {
            alpha: [0.0; LANES],
            // Not `≤ 0`, as the scalar composite asks (unordered: a NaN is blended there too).
            opaque: _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_NLE_UQ>(alpha, zero)) as u32,
            rgb: [[0.0; LANES]; 3],
            corrected: corrected.is_some(),
        };
        // SAFETY: eight lanes each.
        unsafe {
            _mm256_storeu_ps(out.alpha.as_mut_ptr(), alpha);
            for (ch, s) in shaded.iter().enumerate() {
                _mm256_storeu_ps(out.rgb[ch].as_mut_ptr(), *s);
            }
        }
        out
    }

    /// `correct_opacity` for a full batch at once, where it is the same for every lane: each
    /// sample stands for exactly one step (`segment_length`'s interior case) and the step's
    /// power is one the scalar code takes without `powf` ([`Lanes::batch_power`]): ½ is a
    /// square root and 2 a square, correctly rounded in lanes as alone. `None` otherwise (the
    /// composite then corrects sample by sample).
    #[target_feature(enable = "avx2")]
    fn correct_batch(&self, plan: &StepPlan, p: &Pending, alpha: __m256) -> Option<__m256> {
        let e = self.batch_power.filter(|_| self.correction)?;
        // SAFETY: the arrays hold sixteen lanes; the batch is the first eight.
        let (k, t) = unsafe {
            (
                _mm256_loadu_si256(p.k.as_ptr() as *const __m256i),
                _mm256_loadu_ps(p.t.as_ptr()),
            )
        };
        // segment_length's interior: k > 0, not the last sample, t + dt/2 ≤ t_exit.
        let first = _mm256_cmpeq_epi32(k, _mm256_setzero_si256());
        let last = if plan.capped {
            _mm256_setzero_si256()
        } else {
            _mm256_cmpeq_epi32(k, _mm256_set1_epi32(plan.count as i32 - 1))
        };
        let inside = _mm256_cmp_ps::<_CMP_LE_OQ>(
            _mm256_add_ps(t, _mm256_set1_ps(0.5 * plan.dt)),
            _mm256_set1_ps(plan.t_exit),
        );
        let edge = _mm256_castsi256_ps(_mm256_or_si256(first, last));
        if _mm256_movemask_ps(_mm256_andnot_ps(edge, inside)) != 0xFF {
            return None;
        }
        let one = _mm256_set1_ps(1.0);
        let keep = _mm256_sub_ps(one, alpha);
        let raised = if e == 1.0 {
            alpha
        } else if e == 0.5 {
            _mm256_sub_ps(one, _mm256_sqrt_ps(keep))
        } else {
            _mm256_sub_ps(one, _mm256_mul_ps(keep, keep))
        };
        // α ≤ 0 stays (the composite passes over it); α ≥ 1 is 1 (the step is positive).
        let opaque = _mm256_cmp_ps::<_CMP_GE_OQ>(alpha, one);
        let clear = _mm256_cmp_ps::<_CMP_LE_OQ>(alpha, _mm256_setzero_ps());
        Some(_mm256_blendv_ps(
            _mm256_blendv_ps(raised, one, opaque),
            alpha,
            clear,
        ))
    }

    /// `value_and_gradient_in_cell` for the pending lanes: each lane's cell read as four pairs
    /// of records side by side along x (16 bytes each), blended x, y, z in its own lanes, then
    /// the eight results turned into one vector per channel (differences x, y, z, raw value).
    /// The pairs are regrouped as 64-bit integers before widening — `[c000 | c001]` against
    /// `[c100 | c101]`, `[c010 | c011]` against `[c110 | c111]` — so that the x blend gives
    /// `[x00 | x01]` and `[x10 | x11]` and the y blend `[y0 | y1]` with no move across the
    /// vectors' halves (`vperm2f128`: one micro-operation on Zen 4, eight on Zen 1).
    ///
    /// # Safety
    /// AVX2; every pending base is the lower corner of a cell whose upper x corner is the next
    /// record (`Lanes::new` takes volumes with more than one point along x only).
    #[target_feature(enable = "avx2")]
    unsafe fn blend_records(&self, p: &Pending) -> [__m256; 4] {
        let [_, _, dy, _, dz, _, dzy, _] = self.corners;
        let records = self.records.as_ptr();
        let mut rows = [_mm_setzero_ps(); LANES];
        for (lane, row) in rows.iter_mut().enumerate() {
            let at = records.wrapping_add(p.base[lane] as usize);
            // SAFETY: the cell's corners (and so both records of each pair) are in the lattice.
            let pair = |o: i32| unsafe { _mm_loadu_si128(at.add(o as usize) as *const __m128i) };
            let (p00, p10, p01, p11) = (pair(0), pair(dy), pair(dz), pair(dzy));
            let widen = |raw: __m128i| _mm256_cvtepi32_ps(_mm256_cvtepi16_epi32(raw));
            let (tx, ty, tz) = (
                _mm256_set1_ps(p.fx[lane]),
                _mm256_set1_ps(p.fy[lane]),
                _mm256_set1_ps(p.fz[lane]),
            );
            let lerp = |a: __m256, b: __m256, t: __m256| {
                _mm256_add_ps(a, _mm256_mul_ps(_mm256_sub_ps(b, a), t))
            };
            // [x00 | x01] and [x10 | x11]: each low corner against its high one along x.
            let x0 = lerp(
                widen(_mm_unpacklo_epi64(p00, p01)),
                widen(_mm_unpackhi_epi64(p00, p01)),
                tx,
            );
            let x1 = lerp(
                widen(_mm_unpacklo_epi64(p10, p11)),
                widen(_mm_unpackhi_epi64(p10, p11)),
                tx,
            );
            // [y0 | y1] = [x00 | x01] against [x10 | x11].
            let y = lerp(x0, x1, ty);
            let (y0, y1) = (_mm256_castps256_ps128(y), _mm256_extractf128_ps::<1>(y));
            *row = _mm_add_ps(
                y0,
                _mm_mul_ps(_mm_sub_ps(y1, y0), _mm256_castps256_ps128(tz)),
            );
        }
        columns(rows)
    }

    /// Table entries `i` and `i + 1` of each lane as columns (red, green, blue, opacity):
    /// each lane's two entries read as rows of four and turned around, which costs less than
    /// eight gathers (on Zen 1 a gather of eight is some twenty micro-operations).
    ///
    /// # Safety
    /// AVX2; every lane's `i` is at most the table's length − 2.
    #[inline]
    #[target_feature(enable = "avx2")]
    unsafe fn entry_pairs(&self, i: __m256i) -> ([__m256; 4], [__m256; 4]) {
        let mut at = [0i32; LANES];
        // SAFETY: eight lanes into eight slots.
        unsafe { _mm256_storeu_si256(at.as_mut_ptr() as *mut __m256i, i) };
        let entries = self.entries.as_ptr() as *const f32;
        // SAFETY: the caller's bound; an entry is four floats.
        let row = |lane: usize, next: usize| unsafe {
            _mm_loadu_ps(entries.add(4 * (at[lane] as usize + next)))
        };
        (
            columns([0, 1, 2, 3, 4, 5, 6, 7].map(|lane| row(lane, 0))),
            columns([0, 1, 2, 3, 4, 5, 6, 7].map(|lane| row(lane, 1))),
        )
    }

    /// `crate::shade::shade` for eight lanes with directional lights, operation for operation.
    #[target_feature(enable = "avx2")]
    fn shade(&self, c: [__m256; 3], grad: [__m256; 3], rl: &RayLights) -> [__m256; 3] {
        let splat = _mm256_set1_ps;
        let dot = |a: &[__m256; 3], b: Vec3| {
            _mm256_add_ps(
                _mm256_add_ps(
                    _mm256_mul_ps(a[0], splat(b.x)),
                    _mm256_mul_ps(a[1], splat(b.y)),
                ),
                _mm256_mul_ps(a[2], splat(b.z)),
            )
        };
        let len = _mm256_sqrt_ps(_mm256_add_ps(
            _mm256_add_ps(
                _mm256_mul_ps(grad[0], grad[0]),
                _mm256_mul_ps(grad[1], grad[1]),
            ),
            _mm256_mul_ps(grad[2], grad[2]),
        ));
        // lit: len > threshold and finite (ordered comparisons: NaN is neither).
        let lit = _mm256_and_ps(
            _mm256_cmp_ps::<_CMP_GT_OQ>(len, splat(self.threshold)),
            _mm256_cmp_ps::<_CMP_LT_OQ>(len, splat(f32::INFINITY)),
        );
        let inv = _mm256_div_ps(splat(-1.0), len);
        let mut n = grad.map(|g| _mm256_mul_ps(g, inv));
        if self.two_sided {
            let back = _mm256_cmp_ps::<_CMP_LT_OQ>(dot(&n, rl.view), _mm256_setzero_ps());
            let sign = _mm256_and_ps(back, splat(-0.0));
            n = n.map(|x| _mm256_xor_ps(x, sign));
        }
        let tint = if self.levoy { c } else { [splat(1.0); 3] };
        let zero = _mm256_setzero_ps();
        let (mut diffuse, mut specular) = ([zero; 3], [zero; 3]);
        for &(l, color, half) in &rl.lights[..self.light_count] {
            let n_dot_l = dot(&n, l);
            let lambert = _mm256_max_ps(n_dot_l, zero);
            let base = if self.blinn {
                dot(&n, half)
            } else {
                // (n·(2·n_dot_l) − l)·view
                let two = _mm256_mul_ps(splat(2.0), n_dot_l);
                let r = [
                    _mm256_sub_ps(_mm256_mul_ps(n[0], two), splat(l.x)),
                    _mm256_sub_ps(_mm256_mul_ps(n[1], two), splat(l.y)),
                    _mm256_sub_ps(_mm256_mul_ps(n[2], two), splat(l.z)),
                ];
                dot(&r, rl.view)
            };
            let spec = _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_GT_OQ>(n_dot_l, zero),
                power(_mm256_max_ps(base, zero), self.exponent),
            );
            let kd_lambert = _mm256_mul_ps(splat(self.kd), lambert);
            let ks_spec = _mm256_mul_ps(splat(self.ks), spec);
            let light = color.to_array();
            for ch in 0..3 {
                let d = _mm256_mul_ps(c[ch], _mm256_mul_ps(splat(light[ch]), kd_lambert));
                let s = _mm256_mul_ps(_mm256_mul_ps(tint[ch], splat(light[ch])), ks_spec);
                diffuse[ch] = _mm256_add_ps(diffuse[ch], d);
                specular[ch] = _mm256_add_ps(specular[ch], s);
            }
        }
        // A loop, not `map` with a closure: the closure was left out of line (a call per
        // channel, its vectors through memory).
        let mut shaded = [zero; 3];
        for (ch, out) in shaded.iter_mut().enumerate() {
            let ambient = _mm256_mul_ps(c[ch], splat(self.ka));
            let sum = _mm256_add_ps(_mm256_add_ps(ambient, diffuse[ch]), specular[ch]);
            let clamped = _mm256_min_ps(_mm256_max_ps(sum, zero), splat(1.0));
            *out = _mm256_blendv_ps(c[ch], clamped, lit);
        }
        shaded
    }
}

/// Eight rows (one lane's four channels each) turned into four columns (one channel's eight
/// lanes).
#[inline]
#[target_feature(enable = "avx2")]
fn columns(rows: [__m128; LANES]) -> [__m256; 4] {
    let pair = |a: usize| _mm256_set_m128(rows[a + 4], rows[a]);
    let (r0, r1, r2, r3) = (pair(0), pair(1), pair(2), pair(3));
    let t0 = _mm256_unpacklo_ps(r0, r1);
    let t1 = _mm256_unpackhi_ps(r0, r1);
    let t2 = _mm256_unpacklo_ps(r2, r3);
    let t3 = _mm256_unpackhi_ps(r2, r3);
    [
        _mm256_shuffle_ps::<0x44>(t0, t2),
        _mm256_shuffle_ps::<0xEE>(t0, t2),
        _mm256_shuffle_ps::<0x44>(t1, t3),
        _mm256_shuffle_ps::<0xEE>(t1, t3),
    ]
}

/// `crate::shade::power` for a whole exponent, lane by lane: the same squarings and products.
#[target_feature(enable = "avx2")]
fn power(x: __m256, n: u32) -> __m256 {
    let (mut base, mut e, mut acc) = (x, n, _mm256_set1_ps(1.0));
    while e > 0 {
        if e & 1 == 1 {
            acc = _mm256_mul_ps(acc, base);
        }
        base = _mm256_mul_ps(base, base);
        e >>= 1;
    }
    acc
}
