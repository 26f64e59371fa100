//! The projections' samples eight at a time, on x86-64 CPUs with AVX2: trilinear raw values of
//! an integer volume, each lane computing exactly what `sample_t`, `crate::sample::cell` and
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

use super::positions::{Cells, cells};
use super::simd::Avx2;
use crate::composite::ValueStats;
use crate::step::StepPlan;
use crate::volume::{ScalarType, Voxel};
use glam::Vec3;
use std::arch::x86_64::*;

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
    /// Whether a cell's pairs are read with gathers ([`gathered_pairs`]) rather than lane by
    /// lane ([`read_pairs`]): where the CPU has AVX-512, as the CPUs measured that have it
    /// (Zen 4) gather cheaply and those without it (Zen 1) do not. The same values either way.
    gather: bool,
    /// The AVX2 token: these lanes exist only where the CPU has it.
    simd: Avx2,
    _data: std::marker::PhantomData<&'g [u8]>,
}

// SAFETY: the pointer is a shared borrow of the grid's data (`'g`), only ever read.
unsafe impl Send for ValueLanes<'_> {}
unsafe impl Sync for ValueLanes<'_> {}

impl<'g> ValueLanes<'g> {
    /// The lanes for `g`, if this CPU has AVX2 and the grid suits them (integers, at least two
    /// points along x so a cell's x corners are two elements, indices within `i32`).
    pub(super) fn new<T: Voxel>(g: &crate::volume::Grid<'g, T>) -> Option<Self> {
        let simd = Avx2::detect()?;
        let applies =
            T::TYPE != ScalarType::F32 && g.dims[0] >= 2 && g.data.len() < (i32::MAX / 2) as usize;
        applies.then(|| Self {
            data: g.data.as_ptr() as *const u8,
            kind: T::TYPE,
            dy: g.corner_step[1] as i32,
            dz: g.corner_step[2] as i32,
            nx: g.dims[0] as i32,
            nxy: (g.dims[0] * g.dims[1]) as i32,
            last: g.last,
            max_lo: g.max_lo,
            simd,
            gather: std::arch::is_x86_feature_detected!("avx512f")
                && (T::TYPE != ScalarType::U8 || g.data.len() >= 4),
            _data: std::marker::PhantomData,
        })
    }

    /// Adds the ray's samples `k0..k1` to `stats` in order, as [`ValueStats::add`] would one
    /// by one: each value in data units (`raw·slope + intercept`, as `Grid::to_data`), the
    /// sum in `f64` added lane by lane in sample order (so the same rounding), the extremes
    /// kept per lane and folded at the end (order does not matter to them). Integer data have
    /// no missing values, so every sample counts.
    ///
    /// # Safety
    /// AVX2 (as checked in [`ValueLanes::new`]); `self` built from the grid the ray samples.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn add_range(
        &self,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        (k0, k1): (u32, u32),
        (slope, intercept): (f32, f32),
        stats: &mut ValueStats,
    ) {
        let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        let mut hi = _mm256_set1_ps(stats.max);
        let mut lo = _mm256_set1_ps(stats.min);
        let mut sum = stats.sum;
        let mut out = [0f32; 8];
        let mut k = k0;
        while k < k1 {
            let c = cells(self.simd, plan, k, (o_v, d_v), (self.last, self.max_lo));
            // SAFETY: AVX2; the cells are clamped into the lattice.
            let raw = unsafe { self.values(&c) };
            let v = _mm256_add_ps(
                _mm256_mul_ps(raw, _mm256_set1_ps(slope)),
                _mm256_set1_ps(intercept),
            );
            let n = (k1 - k).min(8) as usize;
            // Lanes past the range's end repeat its first: no new extreme.
            let inside = _mm256_cmpgt_epi32(_mm256_set1_epi32(n as i32), lane);
            let v = _mm256_blendv_ps(
                _mm256_permutevar8x32_ps(v, _mm256_setzero_si256()),
                v,
                _mm256_castsi256_ps(inside),
            );
            hi = _mm256_max_ps(hi, v);
            lo = _mm256_min_ps(lo, v);
            // SAFETY: eight floats.
            unsafe { _mm256_storeu_ps(out.as_mut_ptr(), v) };
            for &x in &out[..n] {
                sum += x as f64;
            }
            k += 8;
        }
        let fold = |v: __m256, f: fn(f32, f32) -> f32, start: f32| {
            let mut o = [0f32; 8];
            // SAFETY: eight floats.
            unsafe { _mm256_storeu_ps(o.as_mut_ptr(), v) };
            o.into_iter().fold(start, f)
        };
        stats.count += k1 - k0;
        stats.sum = sum;
        stats.max = fold(hi, f32::max, stats.max);
        stats.min = fold(lo, f32::min, stats.min);
    }

    /// The largest (`larger`) or smallest of `prior` and the raw values of the ray's samples
    /// `k0..k1`, and how many of those samples were interpolated: with `bricks` (the bricks'
    /// largest raw values for `larger`, else their smallest, and the bricks per axis along x
    /// and y), eight positions whose bricks cannot beat the best value so far are passed over
    /// (`crate::bricks`).
    ///
    /// # Safety
    /// AVX2 (as checked in [`ValueLanes::new`]); `self` built from the grid the ray samples,
    /// `bricks` from its volume.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn extreme(
        &self,
        plan: &StepPlan,
        (o_v, d_v): (Vec3, Vec3),
        (k0, k1): (u32, u32),
        (larger, prior): (bool, f32),
        bricks: Option<(&[f32], [i32; 2])>,
    ) -> (f32, u32) {
        let worst = if larger {
            f32::NEG_INFINITY
        } else {
            f32::INFINITY
        };
        let better = |a: __m256, b: __m256| {
            if larger {
                _mm256_max_ps(a, b)
            } else {
                _mm256_min_ps(a, b)
            }
        };
        // Every lane holds the best so far, `prior` included.
        let mut best = _mm256_set1_ps(prior);
        let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
        let mut taken = 0;
        let mut k = k0;
        while k < k1 {
            // Positions past k1 belong to other stretches: left out.
            let inside = _mm256_cmpgt_epi32(_mm256_set1_epi32((k1 - k) as i32), lane);
            let c = cells(self.simd, plan, k, (o_v, d_v), (self.last, self.max_lo));
            let mut wanted = _mm256_castsi256_ps(inside);
            if let Some((bound, [bx, by])) = bricks {
                let [ix, iy, iz] = c.i;
                let (ix, iy, iz) = (
                    _mm256_srli_epi32::<2>(ix),
                    _mm256_srli_epi32::<2>(iy),
                    _mm256_srli_epi32::<2>(iz),
                );
                let at = _mm256_add_epi32(
                    ix,
                    _mm256_mullo_epi32(
                        _mm256_set1_epi32(bx),
                        _mm256_add_epi32(iy, _mm256_mullo_epi32(_mm256_set1_epi32(by), iz)),
                    ),
                );
                // SAFETY: every lane's cell lies in the lattice, so its brick in `bound`.
                let b = unsafe { _mm256_i32gather_ps::<4>(bound.as_ptr(), at) };
                let beats = if larger {
                    _mm256_cmp_ps::<_CMP_GT_OQ>(b, best)
                } else {
                    _mm256_cmp_ps::<_CMP_LT_OQ>(b, best)
                };
                wanted = _mm256_and_ps(wanted, beats);
                if _mm256_movemask_ps(wanted) == 0 {
                    k += 8;
                    continue;
                }
            }
            taken += _mm256_movemask_ps(_mm256_castsi256_ps(inside)).count_ones();
            // SAFETY: AVX2; the cells are clamped into the lattice.
            let v = unsafe { self.values(&c) };
            let v = _mm256_blendv_ps(_mm256_set1_ps(worst), v, _mm256_castsi256_ps(inside));
            // The best of the eight, in every lane.
            let mut m = better(best, v);
            m = better(m, _mm256_permute2f128_ps::<1>(m, m));
            m = better(m, _mm256_shuffle_ps::<0b01_00_11_10>(m, m));
            best = better(m, _mm256_shuffle_ps::<0b10_11_00_01>(m, m));
            k += 8;
        }
        (_mm256_cvtss_f32(best), taken)
    }

    /// The raw trilinear values at eight located positions.
    ///
    /// # Safety
    /// AVX2; `self` built from the grid the ray samples.
    #[inline]
    #[target_feature(enable = "avx2")]
    unsafe fn values(&self, c: &Cells<Avx2>) -> __m256 {
        let [fx, fy, fz] = c.f;
        let base = c.corner(self.simd, self.nx, self.nxy);
        // The four rows' x pairs: lower corner and the one after it.
        let row = |offset: i32| -> (__m256, __m256) {
            let at = _mm256_add_epi32(base, _mm256_set1_epi32(offset));
            // SAFETY: a cell's lower corner has its upper x neighbour in the data (at least
            // two points along x), in every row of the cell.
            let (lo, hi) = unsafe { self.pair(at) };
            (_mm256_cvtepi32_ps(lo), _mm256_cvtepi32_ps(hi))
        };
        let lerp = |a: __m256, b: __m256, f: __m256| {
            _mm256_add_ps(a, _mm256_mul_ps(_mm256_sub_ps(b, a), f))
        };
        let (v000, v100) = row(0);
        let (v010, v110) = row(self.dy);
        let (v001, v101) = row(self.dz);
        let (v011, v111) = row(self.dz + self.dy);
        let x00 = lerp(v000, v100, fx);
        let x10 = lerp(v010, v110, fx);
        let x01 = lerp(v001, v101, fx);
        let x11 = lerp(v011, v111, fx);
        lerp(lerp(x00, x10, fy), lerp(x01, x11, fy), fz)
    }

    /// Elements `at` and `at + 1` of every lane, as 32-bit integers ([`gathered_pairs`] or
    /// [`read_pairs`], as [`ValueLanes::gather`] chose).
    ///
    /// # Safety
    /// AVX2; `at + 1` is an element of the data in every lane.
    #[inline]
    #[target_feature(enable = "avx2")]
    unsafe fn pair(&self, at: __m256i) -> (__m256i, __m256i) {
        // SAFETY: as this function's.
        let w = unsafe {
            if self.gather {
                gathered_pairs(self.data, self.kind, at)
            } else {
                read_pairs(self.data, self.kind, at)
            }
        };
        match self.kind {
            ScalarType::U8 => {
                let byte = _mm256_set1_epi32(0xff);
                (
                    _mm256_and_si256(w, byte),
                    _mm256_and_si256(_mm256_srli_epi32::<8>(w), byte),
                )
            }
            ScalarType::I16 => (
                _mm256_srai_epi32::<16>(_mm256_slli_epi32::<16>(w)),
                _mm256_srai_epi32::<16>(w),
            ),
            _ => (
                _mm256_and_si256(w, _mm256_set1_epi32(0xffff)),
                _mm256_srli_epi32::<16>(w),
            ),
        }
    }
}

/// Per lane, elements `at` and `at + 1` of `data` (of `kind`, 8 or 16 bits) in the low 16 or
/// 32 bits of a 32-bit word, element `at` lowest: each lane's pair read on its own and the
/// eight put together. Cheaper than a gather where a gather of eight is some twenty
/// micro-operations (Zen 1: the gathers were 18 % of a Maximum render).
///
/// # Safety
/// AVX2; `at + 1` is an element of the data in every lane.
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn read_pairs(data: *const u8, kind: ScalarType, at: __m256i) -> __m256i {
    let mut lanes = [0i32; 8];
    // SAFETY: eight lanes into eight slots.
    unsafe { _mm256_storeu_si256(lanes.as_mut_ptr() as *mut __m256i, at) };
    let byte = kind == ScalarType::U8;
    // SAFETY: elements `at` and `at + 1` lie in the data; the read is unaligned at worst.
    let read = |lane: usize| unsafe {
        if byte {
            (data.add(lanes[lane] as usize) as *const u16).read_unaligned() as i32
        } else {
            (data.add(lanes[lane] as usize * 2) as *const i32).read_unaligned()
        }
    };
    _mm256_setr_epi32(
        read(0),
        read(1),
        read(2),
        read(3),
        read(4),
        read(5),
        read(6),
        read(7),
    )
}

/// [`read_pairs`] as one gather of eight 32-bit words: for 8-bit voxels the word ends at the
/// pair, starting two bytes early, so it never reads past the data (a pair at 0 or 1 is read
/// from bytes 0 ..= 3 and shifted down). Cheaper than eight reads where a gather is a few
/// micro-operations (Zen 4: Maximum on brainsmall 6–16 % faster than with [`read_pairs`], in
/// two pairings of alternating rounds).
///
/// # Safety
/// AVX2; `at + 1` is an element of the data in every lane; 8-bit data has at least four bytes.
#[inline]
#[target_feature(enable = "avx2")]
unsafe fn gathered_pairs(data: *const u8, kind: ScalarType, at: __m256i) -> __m256i {
    // SAFETY (both arms): every lane reads four bytes that lie in the data.
    unsafe {
        if kind == ScalarType::U8 {
            let start = _mm256_max_epi32(
                _mm256_sub_epi32(at, _mm256_set1_epi32(2)),
                _mm256_setzero_si256(),
            );
            let word = _mm256_i32gather_epi32::<1>(data as *const i32, start);
            // Bit offset of the pair inside the word: (at − start)·8.
            _mm256_srlv_epi32(word, _mm256_slli_epi32::<3>(_mm256_sub_epi32(at, start)))
        } else {
            _mm256_i32gather_epi32::<2>(data as *const i32, at)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both ways of reading a cell's pairs give the same words' pairs, for every element of
    /// small volumes of each integer type (the first and last pairs included).
    #[test]
    fn gathers_and_reads_agree() {
        if !std::arch::is_x86_feature_detected!("avx2") {
            return;
        }
        let bytes: Vec<u8> = (0..203u32).map(|i| (i * 37 + 11) as u8).collect();
        for kind in [ScalarType::U8, ScalarType::I16, ScalarType::U16] {
            let elements = if kind == ScalarType::U8 { 203 } else { 101 };
            for first in 0..elements - 8 {
                let at: [i32; 8] = std::array::from_fn(|l| (first + l) as i32);
                let mask = if kind == ScalarType::U8 { 0xffff } else { -1 };
                let (mut a, mut b) = ([0i32; 8], [0i32; 8]);
                // SAFETY: AVX2 detected; every lane's pair lies in the data (at + 1 ≤ last).
                unsafe {
                    let at = _mm256_loadu_si256(at.as_ptr() as *const __m256i);
                    let g = gathered_pairs(bytes.as_ptr(), kind, at);
                    let r = read_pairs(bytes.as_ptr(), kind, at);
                    _mm256_storeu_si256(a.as_mut_ptr() as *mut __m256i, g);
                    _mm256_storeu_si256(b.as_mut_ptr() as *mut __m256i, r);
                }
                let a = a.map(|w| w & mask);
                let b = b.map(|w| w & mask);
                assert_eq!(a, b, "{kind:?} from {first}");
            }
        }
    }
}
