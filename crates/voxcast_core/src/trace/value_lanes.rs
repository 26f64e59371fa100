//! The projections' samples eight at a time, on x86-64 CPUs with AVX2 or SSE 4.1 and on 64-bit
//! ARM (written once over [`Simd`], as Accumulate's lanes are): trilinear raw values of an
//! integer volume, each lane computing exactly what `sample_t`, `crate::sample::cell` and
//! `crate::sample::trilinear_in_cell` compute for one position (the same operations in the
//! same order, no fused multiply-add), so a projection over them is the scalar one bit for bit.
//!
//! A cell's two x corners sit side by side in memory, so one read per lane and row (two bytes
//! of an 8-bit volume, four of a 16-bit one; one gather of eight where the CPU has AVX-512)
//! takes both, and four read the whole cell. Before it reads a cell, each lane gathers the
//! range of its cell's brick (`crate::bricks`): eight positions none of whose bricks can beat
//! the best value so far are passed over, and the best is kept in every lane, updated after
//! each eight. Used by Maximum and Minimum (`extreme.rs`), and by every projection that adds
//! all its samples (Average, Sum, and Maximum and Minimum with skipping off:
//! [`ValueLanes::add_range`]), where the volume is of integers and is interpolated
//! trilinearly; `tests/projections.rs` compares them with the scalar march.

use super::Vectors;
use super::positions::{Cells, cells};
use super::simd::{Backend, Kernel, Simd, lerp};
use crate::composite::ValueStats;
use crate::step::StepPlan;
use crate::volume::{ScalarType, Voxel};
use glam::Vec3;

/// What every ray of a render shares: the data and the lattice's constants.
#[derive(Clone, Copy, Debug)]
pub(super) struct ValueLanes<'g> {
    data: *const u8,
    kind: ScalarType,
    /// Element offsets of a cell's upper y and z rows (0 on a one-point axis).
    dy: i32,
    dz: i32,
    nx: i32,
    nxy: i32,
    last: Vec3,
    max_lo: Vec3,
    /// Whether a cell's pairs are gathered rather than read lane by lane ([`Simd::pairs`]):
    /// with AVX2 where the CPU has AVX-512, as the CPUs measured that have it (Zen 4) gather
    /// cheaply and those without it (Zen 1) do not. The same values either way.
    gather: bool,
    backend: Backend,
    _data: std::marker::PhantomData<&'g [u8]>,
}

// SAFETY: the pointer is a shared borrow of the grid's data (`'g`), only ever read.
unsafe impl Send for ValueLanes<'_> {}
unsafe impl Sync for ValueLanes<'_> {}

/// A stretch of one ray's samples, `k0..k1`, and the ray.
struct Run<'p> {
    plan: &'p StepPlan,
    o_v: Vec3,
    d_v: Vec3,
    k0: u32,
    k1: u32,
}

/// What is done with a stretch's values.
enum Job<'a> {
    /// [`ValueLanes::add_range`]: the rescale and the statistics to add to.
    Add((f32, f32), &'a mut ValueStats),
    /// [`ValueLanes::extreme`]: the direction, the best so far and the bricks.
    Extreme((bool, f32), Option<(&'a [f32], [i32; 2])>),
}

/// A [`Job`] on a [`Run`], to run with the backend's vectors. Made only by
/// [`ValueLanes::dispatch`], whose caller vouches for the lanes, the grid and the bricks.
struct Stretch<'a, 'g> {
    lanes: &'a ValueLanes<'g>,
    run: &'a Run<'a>,
    job: Job<'a>,
}

impl Kernel for Stretch<'_, '_> {
    type Output = (f32, u32);
    #[inline(always)]
    fn run<S: Simd>(self, s: S) -> (f32, u32) {
        // SAFETY: `dispatch`'s caller's.
        unsafe { self.lanes.job(s, self.run, self.job) }
    }
}

impl<'g> ValueLanes<'g> {
    /// The lanes for `g`, if this CPU has the vectors (up to `cap`) and the grid suits them
    /// (integers, at least two points along x so a cell's x corners are two elements, indices
    /// within `i32`).
    pub(super) fn new<T: Voxel>(g: &crate::volume::Grid<'g, T>, cap: Vectors) -> Option<Self> {
        let backend = Backend::for_cpu(cap)?;
        let applies =
            T::TYPE != ScalarType::F32 && g.dims[0] >= 2 && g.data.len() < (i32::MAX / 2) as usize;
        #[cfg(target_arch = "x86_64")]
        let gather = matches!(backend, Backend::Avx2(_))
            && std::arch::is_x86_feature_detected!("avx512f")
            && (T::TYPE != ScalarType::U8 || g.data.len() >= 4);
        #[cfg(not(target_arch = "x86_64"))]
        let gather = false;
        applies.then(|| Self {
            data: g.data.as_ptr() as *const u8,
            kind: T::TYPE,
            dy: g.corner_step[1] as i32,
            dz: g.corner_step[2] as i32,
            nx: g.dims[0] as i32,
            nxy: (g.dims[0] * g.dims[1]) as i32,
            last: g.last,
            max_lo: g.max_lo,
            gather,
            backend,
            _data: std::marker::PhantomData,
        })
    }

    /// The instruction set the lanes run on, in words.
    pub(super) fn instructions(&self) -> &'static str {
        self.backend.name()
    }

    /// Adds the ray's samples `k0..k1` to `stats` in order, as [`ValueStats::add`] would one
    /// by one: each value in data units (`raw·slope + intercept`, as `Grid::to_data`), the
    /// sum in `f64` added lane by lane in sample order (so the same rounding), the extremes
    /// kept per lane and folded at the end (order does not matter to them). Integer data have
    /// no missing values, so every sample counts.
    ///
    /// # Safety
    /// `self` built from the grid the ray samples.
    pub(super) unsafe fn add_range(
        &self,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        (k0, k1): (u32, u32),
        rescale: (f32, f32),
        stats: &mut ValueStats,
    ) {
        // SAFETY: the caller's.
        unsafe { self.dispatch(plan, (o_v, d_v), (k0, k1), Job::Add(rescale, stats)) };
    }

    /// The largest (`larger`) or smallest of `prior` and the raw values of the ray's samples
    /// `k0..k1`, and how many of those samples were interpolated: with `bricks` (the bricks'
    /// largest raw values for `larger`, else their smallest, and the bricks per axis along x
    /// and y), eight positions whose bricks cannot beat the best value so far are passed over
    /// (`crate::bricks`).
    ///
    /// # Safety
    /// `self` built from the grid the ray samples, `bricks` from its volume.
    pub(super) unsafe fn extreme(
        &self,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        (k0, k1): (u32, u32),
        best: (bool, f32),
        bricks: Option<(&[f32], [i32; 2])>,
    ) -> (f32, u32) {
        // SAFETY: the caller's.
        unsafe { self.dispatch(plan, (o_v, d_v), (k0, k1), Job::Extreme(best, bricks)) }
    }

    /// Runs `job` on the ray's samples `k0..k1` with the backend's vectors, in a function
    /// compiled for them.
    ///
    /// # Safety
    /// As [`ValueLanes::extreme`].
    unsafe fn dispatch(
        &self,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        (k0, k1): (u32, u32),
        job: Job<'_>,
    ) -> (f32, u32) {
        let run = Run {
            plan,
            o_v,
            d_v,
            k0,
            k1,
        };
        self.backend.run(Stretch {
            lanes: self,
            run: &run,
            job,
        })
    }

    /// # Safety
    /// As [`ValueLanes::extreme`].
    #[inline(always)]
    unsafe fn job<S: Simd>(&self, s: S, run: &Run<'_>, job: Job<'_>) -> (f32, u32) {
        // SAFETY: the caller's.
        unsafe {
            match job {
                Job::Add(rescale, stats) => {
                    self.add_in(s, run, rescale, stats);
                    (0.0, 0)
                }
                Job::Extreme(best, bricks) => self.extreme_in(s, run, best, bricks),
            }
        }
    }

    /// [`ValueLanes::add_range`] in the backend's vectors.
    ///
    /// # Safety
    /// As [`ValueLanes::add_range`].
    #[inline(always)]
    unsafe fn add_in<S: Simd>(
        &self,
        s: S,
        run: &Run<'_>,
        (slope, intercept): (f32, f32),
        stats: &mut ValueStats,
    ) {
        let (k0, k1) = (run.k0, run.k1);
        let lane = s.iota();
        let mut hi = s.splat(stats.max);
        let mut lo = s.splat(stats.min);
        let mut sum = stats.sum;
        let mut out = [0f32; 8];
        let mut k = k0;
        while k < k1 {
            let c = self.locate(s, run, k);
            // SAFETY: the cells are clamped into the lattice, this grid's.
            let raw = unsafe { self.values(s, &c) };
            let v = s.add(s.mul(raw, s.splat(slope)), s.splat(intercept));
            let n = (k1 - k).min(8) as usize;
            // Lanes past the range's end repeat its first: no new extreme.
            let inside = s.gt_i(s.splat_i(n as i32), lane);
            let v = s.select(s.broadcast_first(v), v, inside);
            hi = s.max(hi, v);
            lo = s.min(lo, v);
            // SAFETY: eight floats.
            unsafe { s.store(out.as_mut_ptr(), v) };
            for &x in &out[..n] {
                sum += x as f64;
            }
            k += 8;
        }
        stats.count += k1 - k0;
        stats.sum = sum;
        // SAFETY: eight floats each.
        unsafe {
            let mut o = [0f32; 8];
            s.store(o.as_mut_ptr(), hi);
            stats.max = o.into_iter().fold(stats.max, f32::max);
            s.store(o.as_mut_ptr(), lo);
            stats.min = o.into_iter().fold(stats.min, f32::min);
        }
    }

    /// [`ValueLanes::extreme`] in the backend's vectors.
    ///
    /// # Safety
    /// As [`ValueLanes::extreme`].
    #[inline(always)]
    unsafe fn extreme_in<S: Simd>(
        &self,
        s: S,
        run: &Run<'_>,
        (larger, prior): (bool, f32),
        bricks: Option<(&[f32], [i32; 2])>,
    ) -> (f32, u32) {
        let (k0, k1) = (run.k0, run.k1);
        let worst = if larger {
            f32::NEG_INFINITY
        } else {
            f32::INFINITY
        };
        // Every lane holds the best so far, `prior` included.
        let mut best = s.splat(prior);
        let lane = s.iota();
        let mut taken = 0;
        let mut k = k0;
        while k < k1 {
            // Positions past k1 belong to other stretches: left out.
            let inside = s.gt_i(s.splat_i((k1 - k) as i32), lane);
            let c = self.locate(s, run, k);
            let mut wanted = inside;
            if let Some((bound, [bx, by])) = bricks {
                let [ix, iy, iz] = c.i;
                let (ix, iy, iz) = (s.shr_i::<2>(ix), s.shr_i::<2>(iy), s.shr_i::<2>(iz));
                let at = s.add_i(
                    ix,
                    s.mul_i(s.splat_i(bx), s.add_i(iy, s.mul_i(s.splat_i(by), iz))),
                );
                // SAFETY: every lane's cell lies in the lattice, so its brick in `bound`.
                let b = unsafe { s.gather(bound.as_ptr(), at) };
                let beats = if larger { s.gt(b, best) } else { s.lt(b, best) };
                wanted = s.and(wanted, beats);
                if s.bits(wanted) == 0 {
                    k += 8;
                    continue;
                }
            }
            taken += s.bits(inside).count_ones();
            // SAFETY: the cells are clamped into the lattice, this grid's.
            let v = unsafe { self.values(s, &c) };
            let v = s.select(s.splat(worst), v, inside);
            // The best of the eight, in every lane.
            let m = if larger {
                s.max(best, v)
            } else {
                s.min(best, v)
            };
            best = s.best_across(m, larger);
            k += 8;
        }
        (s.first(best), taken)
    }

    /// Positions `k .. k + 8` of the run's ray located in this lattice.
    #[inline(always)]
    fn locate<S: Simd>(&self, s: S, run: &Run<'_>, k: u32) -> Cells<S> {
        cells(s, run.plan, k, (run.o_v, run.d_v), (self.last, self.max_lo))
    }

    /// The raw trilinear values at eight located positions.
    ///
    /// # Safety
    /// `self` built from the grid the cells lie in.
    #[inline(always)]
    unsafe fn values<S: Simd>(&self, s: S, c: &Cells<S>) -> S::F {
        let [fx, fy, fz] = c.f;
        let base = c.corner(s, self.nx, self.nxy);
        // The four rows' x pairs: lower corner and the one after it. A cell's lower corner
        // has its upper x neighbour in the data (at least two points along x), in every row.
        // SAFETY: so every pair lies in the data.
        let [(v000, v100), (v010, v110), (v001, v101), (v011, v111)] = unsafe {
            [
                self.row(s, base, 0),
                self.row(s, base, self.dy),
                self.row(s, base, self.dz),
                self.row(s, base, self.dz + self.dy),
            ]
        };
        let x00 = lerp(s, v000, v100, fx);
        let x10 = lerp(s, v010, v110, fx);
        let x01 = lerp(s, v001, v101, fx);
        let x11 = lerp(s, v011, v111, fx);
        lerp(s, lerp(s, x00, x10, fy), lerp(s, x01, x11, fy), fz)
    }

    /// One row's x pairs of the cells whose lower corners are `base`, `offset` elements on.
    ///
    /// # Safety
    /// Elements `base + offset` and the next lie in the data in every lane.
    #[inline(always)]
    unsafe fn row<S: Simd>(&self, s: S, base: S::I, offset: i32) -> (S::F, S::F) {
        let at = s.add_i(base, s.splat_i(offset));
        // SAFETY: the caller's.
        let (lo, hi) = unsafe { self.pair(s, at) };
        (s.to_f(lo), s.to_f(hi))
    }

    /// Elements `at` and `at + 1` of every lane, as 32-bit integers ([`Simd::pairs`], gathered
    /// or not as [`ValueLanes::gather`] chose).
    ///
    /// # Safety
    /// `at + 1` is an element of the data in every lane.
    #[inline(always)]
    unsafe fn pair<S: Simd>(&self, s: S, at: S::I) -> (S::I, S::I) {
        // SAFETY: as this function's (8-bit data gathered has four bytes: `new`).
        let w = unsafe { s.pairs(self.data, self.kind, at, self.gather) };
        match self.kind {
            ScalarType::U8 => {
                let byte = s.splat_i(0xff);
                (s.and_i(w, byte), s.and_i(s.shr_i::<8>(w), byte))
            }
            ScalarType::I16 => (
                s.shr_signed_i::<16>(s.shl_i::<16>(w)),
                s.shr_signed_i::<16>(w),
            ),
            _ => (s.and_i(w, s.splat_i(0xffff)), s.shr_i::<16>(w)),
        }
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::trace::simd::Avx2;

    /// Both ways of reading a cell's pairs give the same words' pairs, for every element of
    /// small volumes of each integer type (the first and last pairs included).
    #[test]
    fn gathers_and_reads_agree() {
        let Some(s) = Avx2::detect() else {
            return;
        };
        let bytes: Vec<u8> = (0..203u32).map(|i| (i * 37 + 11) as u8).collect();
        for kind in [ScalarType::U8, ScalarType::I16, ScalarType::U16] {
            let elements = if kind == ScalarType::U8 { 203 } else { 101 };
            for first in 0..elements - 8 {
                let at: [i32; 8] = std::array::from_fn(|l| (first + l) as i32);
                let mask = if kind == ScalarType::U8 { 0xffff } else { -1 };
                let (mut a, mut b) = ([0i32; 8], [0i32; 8]);
                // SAFETY: every lane's pair lies in the data (at + 1 ≤ last).
                unsafe {
                    let at = s.load_i(at.as_ptr());
                    s.store_i(a.as_mut_ptr(), s.pairs(bytes.as_ptr(), kind, at, true));
                    s.store_i(b.as_mut_ptr(), s.pairs(bytes.as_ptr(), kind, at, false));
                }
                let a = a.map(|w| w & mask);
                let b = b.map(|w| w & mask);
                assert_eq!(a, b, "{kind:?} from {first}");
            }
        }
    }
}
