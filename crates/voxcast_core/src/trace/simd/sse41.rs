//! [`Simd`] on SSE 4.1: each vector two 128-bit halves, lanes 0–3 and 4–7. No gathers, no
//! lane permutation across halves: the visibility bits are read lane by lane, and the packing
//! shuffles each half by a table of sixteen.

use super::{Pair, Simd};
use std::arch::x86_64::*;

/// The SSE 4.1 backend: exists only where the CPU has SSE 4.1 ([`Sse41::detect`]).
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) struct Sse41(());

impl Sse41 {
    /// The token, if this CPU has SSE 4.1.
    pub(in crate::trace) fn detect() -> Option<Self> {
        std::arch::is_x86_feature_detected!("sse4.1").then_some(Self(()))
    }
}

/// How [`Simd::pack`] moves a vector's chosen lanes: each half's byte shuffle, and how many
/// lanes the low half keeps.
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) struct Order {
    lo: __m128i,
    hi: __m128i,
    kept_lo: usize,
}

/// [`super::pack4`]'s table, the rest of each row 0x80 (its top bit set: `pshufb` zeroes such
/// a byte).
const PACK4: [[u8; 16]; 16] = super::pack4(0x80);

/// Applies a two-argument intrinsic to both halves.
macro_rules! halves {
    ($f:ident, $a:expr, $b:expr) => {{
        let (a, b) = ($a, $b);
        // SAFETY: see the impl below.
        unsafe { Pair($f(a.0, b.0), $f(a.1, b.1)) }
    }};
    ($f:ident, $a:expr) => {{
        let a = $a;
        // SAFETY: see the impl below.
        unsafe { Pair($f(a.0), $f(a.1)) }
    }};
}

type F = Pair<__m128>;
type I = Pair<__m128i>;

// SAFETY (every `unsafe` block below): the token exists only where the CPU has SSE 4.1 (and so
// SSE2 and below); pointers are the callers' to vouch for, as each method's contract says (a
// prefetch is a hint: it reads nothing and never faults). No closures, as in `avx2.rs`.
impl Simd for Sse41 {
    type F = F;
    type I = I;
    type Order = Order;
    type H = __m128;
    type R = *const u8;

    #[inline(always)]
    fn splat(self, x: f32) -> F {
        let h = unsafe { _mm_set1_ps(x) };
        Pair(h, h)
    }
    #[inline(always)]
    fn splat_i(self, x: i32) -> I {
        let h = unsafe { _mm_set1_epi32(x) };
        Pair(h, h)
    }
    #[inline(always)]
    fn iota(self) -> I {
        unsafe { Pair(_mm_setr_epi32(0, 1, 2, 3), _mm_setr_epi32(4, 5, 6, 7)) }
    }
    #[inline(always)]
    fn add(self, a: F, b: F) -> F {
        halves!(_mm_add_ps, a, b)
    }
    #[inline(always)]
    fn sub(self, a: F, b: F) -> F {
        halves!(_mm_sub_ps, a, b)
    }
    #[inline(always)]
    fn mul(self, a: F, b: F) -> F {
        halves!(_mm_mul_ps, a, b)
    }
    #[inline(always)]
    fn div(self, a: F, b: F) -> F {
        halves!(_mm_div_ps, a, b)
    }
    #[inline(always)]
    fn sqrt(self, a: F) -> F {
        halves!(_mm_sqrt_ps, a)
    }
    #[inline(always)]
    fn min(self, a: F, b: F) -> F {
        halves!(_mm_min_ps, a, b)
    }
    #[inline(always)]
    fn max(self, a: F, b: F) -> F {
        halves!(_mm_max_ps, a, b)
    }
    #[inline(always)]
    fn and(self, a: F, b: F) -> F {
        halves!(_mm_and_ps, a, b)
    }
    #[inline(always)]
    fn or(self, a: F, b: F) -> F {
        halves!(_mm_or_ps, a, b)
    }
    #[inline(always)]
    fn xor(self, a: F, b: F) -> F {
        halves!(_mm_xor_ps, a, b)
    }
    #[inline(always)]
    fn and_not(self, a: F, b: F) -> F {
        halves!(_mm_andnot_ps, a, b)
    }
    #[inline(always)]
    fn gt(self, a: F, b: F) -> F {
        halves!(_mm_cmpgt_ps, a, b)
    }
    #[inline(always)]
    fn lt(self, a: F, b: F) -> F {
        halves!(_mm_cmplt_ps, a, b)
    }
    #[inline(always)]
    fn le(self, a: F, b: F) -> F {
        halves!(_mm_cmple_ps, a, b)
    }
    #[inline(always)]
    fn ge(self, a: F, b: F) -> F {
        halves!(_mm_cmpge_ps, a, b)
    }
    #[inline(always)]
    fn not_le(self, a: F, b: F) -> F {
        halves!(_mm_cmpnle_ps, a, b)
    }
    #[inline(always)]
    fn select(self, a: F, b: F, mask: F) -> F {
        unsafe {
            Pair(
                _mm_blendv_ps(a.0, b.0, mask.0),
                _mm_blendv_ps(a.1, b.1, mask.1),
            )
        }
    }
    #[inline(always)]
    fn bits(self, mask: F) -> u32 {
        unsafe { (_mm_movemask_ps(mask.0) | (_mm_movemask_ps(mask.1) << 4)) as u32 }
    }
    #[inline(always)]
    fn add_i(self, a: I, b: I) -> I {
        halves!(_mm_add_epi32, a, b)
    }
    #[inline(always)]
    fn mul_i(self, a: I, b: I) -> I {
        halves!(_mm_mullo_epi32, a, b)
    }
    #[inline(always)]
    fn and_i(self, a: I, b: I) -> I {
        halves!(_mm_and_si128, a, b)
    }
    #[inline(always)]
    fn or_i(self, a: I, b: I) -> I {
        halves!(_mm_or_si128, a, b)
    }
    #[inline(always)]
    fn min_i(self, a: I, b: I) -> I {
        halves!(_mm_min_epi32, a, b)
    }
    #[inline(always)]
    fn shr_i<const N: i32>(self, a: I) -> I {
        unsafe { Pair(_mm_srli_epi32::<N>(a.0), _mm_srli_epi32::<N>(a.1)) }
    }
    #[inline(always)]
    fn shr_signed_i<const N: i32>(self, a: I) -> I {
        unsafe { Pair(_mm_srai_epi32::<N>(a.0), _mm_srai_epi32::<N>(a.1)) }
    }
    #[inline(always)]
    fn shl_i<const N: i32>(self, a: I) -> I {
        unsafe { Pair(_mm_slli_epi32::<N>(a.0), _mm_slli_epi32::<N>(a.1)) }
    }
    #[inline(always)]
    fn eq_i(self, a: I, b: I) -> F {
        let m = halves!(_mm_cmpeq_epi32, a, b);
        unsafe { Pair(_mm_castsi128_ps(m.0), _mm_castsi128_ps(m.1)) }
    }
    #[inline(always)]
    fn gt_i(self, a: I, b: I) -> F {
        let m = halves!(_mm_cmpgt_epi32, a, b);
        unsafe { Pair(_mm_castsi128_ps(m.0), _mm_castsi128_ps(m.1)) }
    }
    #[inline(always)]
    fn trunc(self, a: F) -> I {
        halves!(_mm_cvttps_epi32, a)
    }
    #[inline(always)]
    fn to_f(self, a: I) -> F {
        halves!(_mm_cvtepi32_ps, a)
    }
    #[inline(always)]
    unsafe fn load(self, p: *const f32) -> F {
        unsafe { Pair(_mm_loadu_ps(p), _mm_loadu_ps(p.add(4))) }
    }
    #[inline(always)]
    unsafe fn load_i(self, p: *const i32) -> I {
        unsafe {
            Pair(
                _mm_loadu_si128(p as *const __m128i),
                _mm_loadu_si128(p.add(4) as *const __m128i),
            )
        }
    }
    #[inline(always)]
    unsafe fn store(self, p: *mut f32, a: F) {
        unsafe {
            _mm_storeu_ps(p, a.0);
            _mm_storeu_ps(p.add(4), a.1);
        }
    }
    #[inline(always)]
    unsafe fn store_i(self, p: *mut i32, a: I) {
        unsafe {
            _mm_storeu_si128(p as *mut __m128i, a.0);
            _mm_storeu_si128(p.add(4) as *mut __m128i, a.1);
        }
    }

    #[inline(always)]
    fn broadcast_first(self, a: F) -> F {
        let h = unsafe { _mm_shuffle_ps::<0>(a.0, a.0) };
        Pair(h, h)
    }
    #[inline(always)]
    fn first(self, a: F) -> f32 {
        unsafe { _mm_cvtss_f32(a.0) }
    }
    /// Halves against each other, then pairs, then neighbours.
    #[inline(always)]
    fn best_across(self, m: F, larger: bool) -> F {
        unsafe {
            let h = if larger {
                _mm_max_ps(m.0, m.1)
            } else {
                _mm_min_ps(m.0, m.1)
            };
            let pairs = _mm_shuffle_ps::<0b01_00_11_10>(h, h);
            let h = if larger {
                _mm_max_ps(h, pairs)
            } else {
                _mm_min_ps(h, pairs)
            };
            let next = _mm_shuffle_ps::<0b10_11_00_01>(h, h);
            let h = if larger {
                _mm_max_ps(h, next)
            } else {
                _mm_min_ps(h, next)
            };
            Pair(h, h)
        }
    }
    #[inline(always)]
    fn order(self, mask: u32) -> Order {
        let (lo, hi) = (mask as usize & 0xF, (mask as usize >> 4) & 0xF);
        // SAFETY (and SSE2): each row is sixteen bytes.
        unsafe {
            Order {
                lo: _mm_loadu_si128(PACK4[lo].as_ptr() as *const __m128i),
                hi: _mm_loadu_si128(PACK4[hi].as_ptr() as *const __m128i),
                kept_lo: lo.count_ones() as usize,
            }
        }
    }
    #[inline(always)]
    unsafe fn pack(self, dst: *mut f32, a: F, order: Order) {
        unsafe {
            let lo = _mm_shuffle_epi8(_mm_castps_si128(a.0), order.lo);
            let hi = _mm_shuffle_epi8(_mm_castps_si128(a.1), order.hi);
            _mm_storeu_ps(dst, _mm_castsi128_ps(lo));
            _mm_storeu_ps(dst.add(order.kept_lo), _mm_castsi128_ps(hi));
        }
    }
    #[inline(always)]
    unsafe fn pack_i(self, dst: *mut i32, a: I, order: Order) {
        unsafe {
            _mm_storeu_si128(dst as *mut __m128i, _mm_shuffle_epi8(a.0, order.lo));
            _mm_storeu_si128(
                dst.add(order.kept_lo) as *mut __m128i,
                _mm_shuffle_epi8(a.1, order.hi),
            );
        }
    }

    /// Only where the pair is: [`Simd::widen_pairs`] reads each half as it widens it.
    #[inline(always)]
    unsafe fn load_pair(self, p: *const u8) -> *const u8 {
        p
    }
    /// Each half from one of the pairs: `[a0 | b0]` is `a`'s low four and `b`'s low four, each
    /// four read as it is widened (`pmovsxwd` from memory: no load, no shift of its own).
    #[inline(always)]
    unsafe fn widen_pairs(self, a: *const u8, b: *const u8) -> (F, F) {
        // SAFETY: sixteen readable bytes at each (the caller's): two halves of eight.
        unsafe {
            let (a0, b0) = (widen4(a), widen4(b));
            let (a1, b1) = (widen4(a.add(8)), widen4(b.add(8)));
            (Pair(a0, b0), Pair(a1, b1))
        }
    }
    #[inline(always)]
    fn halves(self, a: F) -> (__m128, __m128) {
        (a.0, a.1)
    }
    #[inline(always)]
    fn lerp_h(self, a: __m128, b: __m128, t: f32) -> __m128 {
        unsafe { _mm_add_ps(a, _mm_mul_ps(_mm_sub_ps(b, a), _mm_set1_ps(t))) }
    }
    #[inline(always)]
    fn zero_h(self) -> __m128 {
        unsafe { _mm_setzero_ps() }
    }
    #[inline(always)]
    unsafe fn load_h(self, p: *const f32) -> __m128 {
        unsafe { _mm_loadu_ps(p) }
    }
    #[inline(always)]
    fn prefetch(self, p: *const u8) {
        unsafe { _mm_prefetch::<_MM_HINT_T0>(p as *const i8) }
    }
    #[inline(always)]
    fn columns(self, rows: [__m128; 8]) -> [F; 4] {
        let [r0, r1, r2, r3, r4, r5, r6, r7] = rows;
        super::pair_columns(transpose(r0, r1, r2, r3), transpose(r4, r5, r6, r7))
    }
}

/// Four rows of four as four columns.
#[inline(always)]
fn transpose(r0: __m128, r1: __m128, r2: __m128, r3: __m128) -> [__m128; 4] {
    // SAFETY: SSE, which every x86-64 has.
    unsafe {
        let t0 = _mm_unpacklo_ps(r0, r1);
        let t1 = _mm_unpackhi_ps(r0, r1);
        let t2 = _mm_unpacklo_ps(r2, r3);
        let t3 = _mm_unpackhi_ps(r2, r3);
        [
            _mm_movelh_ps(t0, t2),
            _mm_movehl_ps(t2, t0),
            _mm_movelh_ps(t1, t3),
            _mm_movehl_ps(t3, t1),
        ]
    }
}

/// Four `i16` at `p` as four `f32`.
///
/// # Safety
/// Eight readable bytes at `p`; SSE 4.1 (only ever inlined into a function compiled for it).
#[inline(always)]
unsafe fn widen4(p: *const u8) -> __m128 {
    unsafe { _mm_cvtepi32_ps(_mm_cvtepi16_epi32(_mm_loadl_epi64(p as *const __m128i))) }
}
