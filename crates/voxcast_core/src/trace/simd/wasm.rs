//! [`Simd`] on WebAssembly's 128-bit SIMD (`simd128`, in every browser since 2021): each
//! vector two halves, lanes 0–3 and 4–7, as on SSE 4.1 (`sse41.rs`), with the x86
//! instructions' semantics where WebAssembly's differ: `min` and `max` are its `pmin` and
//! `pmax` with the operands swapped (`minps`'s `a < b ? a : b`; its `f32x4.min` would give NaN),
//! and `trunc` saturates where `cvttps2dq` gives `i32::MIN` (the lanes truncate only clamped,
//! finite values, where the two agree, as on NEON).
//!
//! The instructions are the module's, not the CPU's: a module built with `simd128` (the page's
//! build, `web/build.sh`) runs them or does not load, so the token always exists there.

use super::{Pair, Simd};
use std::arch::wasm32::*;

/// The WebAssembly SIMD backend: compiled in only where the module is built with `simd128`.
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) struct Simd128(());

impl Simd128 {
    /// The token: every engine that loaded this module runs its SIMD.
    pub(in crate::trace) fn detect() -> Option<Self> {
        Some(Self(()))
    }
}

/// How [`Simd::pack`] moves a vector's chosen lanes: each half's byte table, and how many
/// lanes the low half keeps.
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) struct Order {
    lo: v128,
    hi: v128,
    kept_lo: usize,
}

/// [`super::pack4`]'s table, the rest of each row 0xFF (out of range: `i8x16.swizzle` zeroes
/// such a byte).
const PACK4: [[u8; 16]; 16] = super::pack4(0xFF);

type F = Pair<v128>;
type I = Pair<v128>;

/// Applies a two-argument instruction to both halves.
macro_rules! halves {
    ($f:ident, $a:expr, $b:expr) => {{
        let (a, b) = ($a, $b);
        Pair($f(a.0, b.0), $f(a.1, b.1))
    }};
    ($f:ident, $a:expr) => {{
        let a = $a;
        Pair($f(a.0), $f(a.1))
    }};
}

/// `a < b ? a : b`, as `minps` (`pmin(x, y)` is `y < x ? y : x`).
#[inline(always)]
fn min4(a: v128, b: v128) -> v128 {
    f32x4_pmin(b, a)
}

/// `a > b ? a : b`, as `maxps` (`pmax(x, y)` is `x < y ? y : x`).
#[inline(always)]
fn max4(a: v128, b: v128) -> v128 {
    f32x4_pmax(b, a)
}

/// `!a & b`.
#[inline(always)]
fn and_not4(a: v128, b: v128) -> v128 {
    v128_andnot(b, a)
}

/// `!(a <= b)`.
#[inline(always)]
fn not_le4(a: v128, b: v128) -> v128 {
    v128_not(f32x4_le(a, b))
}

/// Four `i16` as four `f32`: the low four of eight, or the high four.
#[inline(always)]
fn widen_low(a: v128) -> v128 {
    f32x4_convert_i32x4(i32x4_extend_low_i16x8(a))
}
#[inline(always)]
fn widen_high(a: v128) -> v128 {
    f32x4_convert_i32x4(i32x4_extend_high_i16x8(a))
}

// The module is built with `simd128`, so its instructions are safe to call; the `unsafe`
// blocks below are memory reads and writes, whose pointers are the callers' to vouch for, as
// each method's contract says (WebAssembly's loads and stores need no alignment).
impl Simd for Simd128 {
    type F = F;
    type I = I;
    type Order = Order;
    type H = v128;
    type R = v128;

    #[inline(always)]
    fn splat(self, x: f32) -> F {
        let h = f32x4_splat(x);
        Pair(h, h)
    }
    #[inline(always)]
    fn splat_i(self, x: i32) -> I {
        let h = i32x4_splat(x);
        Pair(h, h)
    }
    #[inline(always)]
    fn iota(self) -> I {
        Pair(i32x4(0, 1, 2, 3), i32x4(4, 5, 6, 7))
    }
    #[inline(always)]
    fn add(self, a: F, b: F) -> F {
        halves!(f32x4_add, a, b)
    }
    #[inline(always)]
    fn sub(self, a: F, b: F) -> F {
        halves!(f32x4_sub, a, b)
    }
    #[inline(always)]
    fn mul(self, a: F, b: F) -> F {
        halves!(f32x4_mul, a, b)
    }
    #[inline(always)]
    fn div(self, a: F, b: F) -> F {
        halves!(f32x4_div, a, b)
    }
    #[inline(always)]
    fn sqrt(self, a: F) -> F {
        halves!(f32x4_sqrt, a)
    }
    #[inline(always)]
    fn min(self, a: F, b: F) -> F {
        halves!(min4, a, b)
    }
    #[inline(always)]
    fn max(self, a: F, b: F) -> F {
        halves!(max4, a, b)
    }
    #[inline(always)]
    fn and(self, a: F, b: F) -> F {
        halves!(v128_and, a, b)
    }
    #[inline(always)]
    fn or(self, a: F, b: F) -> F {
        halves!(v128_or, a, b)
    }
    #[inline(always)]
    fn xor(self, a: F, b: F) -> F {
        halves!(v128_xor, a, b)
    }
    #[inline(always)]
    fn and_not(self, a: F, b: F) -> F {
        halves!(and_not4, a, b)
    }
    #[inline(always)]
    fn gt(self, a: F, b: F) -> F {
        halves!(f32x4_gt, a, b)
    }
    #[inline(always)]
    fn lt(self, a: F, b: F) -> F {
        halves!(f32x4_lt, a, b)
    }
    #[inline(always)]
    fn le(self, a: F, b: F) -> F {
        halves!(f32x4_le, a, b)
    }
    #[inline(always)]
    fn ge(self, a: F, b: F) -> F {
        halves!(f32x4_ge, a, b)
    }
    #[inline(always)]
    fn not_le(self, a: F, b: F) -> F {
        halves!(not_le4, a, b)
    }
    /// Every mask the lanes select by is whole (all bits of a lane alike), so a bitwise
    /// select is `blendv`'s sign-bit one.
    #[inline(always)]
    fn select(self, a: F, b: F, mask: F) -> F {
        Pair(
            v128_bitselect(b.0, a.0, mask.0),
            v128_bitselect(b.1, a.1, mask.1),
        )
    }
    #[inline(always)]
    fn bits(self, mask: F) -> u32 {
        i32x4_bitmask(mask.0) as u32 | ((i32x4_bitmask(mask.1) as u32) << 4)
    }
    #[inline(always)]
    fn add_i(self, a: I, b: I) -> I {
        halves!(i32x4_add, a, b)
    }
    #[inline(always)]
    fn mul_i(self, a: I, b: I) -> I {
        halves!(i32x4_mul, a, b)
    }
    #[inline(always)]
    fn and_i(self, a: I, b: I) -> I {
        halves!(v128_and, a, b)
    }
    #[inline(always)]
    fn or_i(self, a: I, b: I) -> I {
        halves!(v128_or, a, b)
    }
    #[inline(always)]
    fn min_i(self, a: I, b: I) -> I {
        halves!(i32x4_min, a, b)
    }
    /// Logical, as `psrld`.
    #[inline(always)]
    fn shr_i<const N: i32>(self, a: I) -> I {
        Pair(u32x4_shr(a.0, N as u32), u32x4_shr(a.1, N as u32))
    }
    #[inline(always)]
    fn shr_signed_i<const N: i32>(self, a: I) -> I {
        Pair(i32x4_shr(a.0, N as u32), i32x4_shr(a.1, N as u32))
    }
    #[inline(always)]
    fn shl_i<const N: i32>(self, a: I) -> I {
        Pair(i32x4_shl(a.0, N as u32), i32x4_shl(a.1, N as u32))
    }
    #[inline(always)]
    fn eq_i(self, a: I, b: I) -> F {
        halves!(i32x4_eq, a, b)
    }
    #[inline(always)]
    fn gt_i(self, a: I, b: I) -> F {
        halves!(i32x4_gt, a, b)
    }
    #[inline(always)]
    fn trunc(self, a: F) -> I {
        halves!(i32x4_trunc_sat_f32x4, a)
    }
    #[inline(always)]
    fn to_f(self, a: I) -> F {
        halves!(f32x4_convert_i32x4, a)
    }
    #[inline(always)]
    unsafe fn load(self, p: *const f32) -> F {
        unsafe {
            Pair(
                v128_load(p as *const v128),
                v128_load(p.add(4) as *const v128),
            )
        }
    }
    #[inline(always)]
    unsafe fn load_i(self, p: *const i32) -> I {
        // The same 32 bytes: `F` and `I` are both two `v128`.
        unsafe { self.load(p as *const f32) }
    }
    #[inline(always)]
    unsafe fn store(self, p: *mut f32, a: F) {
        unsafe {
            v128_store(p as *mut v128, a.0);
            v128_store(p.add(4) as *mut v128, a.1);
        }
    }
    #[inline(always)]
    unsafe fn store_i(self, p: *mut i32, a: I) {
        unsafe { self.store(p as *mut f32, a) }
    }

    #[inline(always)]
    fn broadcast_first(self, a: F) -> F {
        let h = i32x4_shuffle::<0, 0, 0, 0>(a.0, a.0);
        Pair(h, h)
    }
    #[inline(always)]
    fn first(self, a: F) -> f32 {
        f32x4_extract_lane::<0>(a.0)
    }
    /// Halves against each other, then pairs, then neighbours, by x86's `min` or `max`.
    #[inline(always)]
    fn best_across(self, m: F, larger: bool) -> F {
        let best = if larger { max4 } else { min4 };
        let h = best(m.0, m.1);
        let h = best(h, i32x4_shuffle::<2, 3, 0, 1>(h, h));
        let h = best(h, i32x4_shuffle::<1, 0, 3, 2>(h, h));
        Pair(h, h)
    }
    #[inline(always)]
    fn order(self, mask: u32) -> Order {
        let (lo, hi) = (mask as usize & 0xF, (mask as usize >> 4) & 0xF);
        // SAFETY: each row is sixteen bytes.
        unsafe {
            Order {
                lo: v128_load(PACK4[lo].as_ptr() as *const v128),
                hi: v128_load(PACK4[hi].as_ptr() as *const v128),
                kept_lo: lo.count_ones() as usize,
            }
        }
    }
    #[inline(always)]
    unsafe fn pack(self, dst: *mut f32, a: F, order: Order) {
        unsafe {
            v128_store(dst as *mut v128, i8x16_swizzle(a.0, order.lo));
            v128_store(
                dst.add(order.kept_lo) as *mut v128,
                i8x16_swizzle(a.1, order.hi),
            );
        }
    }
    #[inline(always)]
    unsafe fn pack_i(self, dst: *mut i32, a: I, order: Order) {
        unsafe { self.pack(dst as *mut f32, a, order) }
    }

    #[inline(always)]
    unsafe fn load_pair(self, p: *const u8) -> v128 {
        unsafe { v128_load(p as *const v128) }
    }
    /// Each half from one of the pairs: `[a0 | b0]` is `a`'s low four and `b`'s low four.
    #[inline(always)]
    unsafe fn widen_pairs(self, a: v128, b: v128) -> (F, F) {
        (
            Pair(widen_low(a), widen_low(b)),
            Pair(widen_high(a), widen_high(b)),
        )
    }
    #[inline(always)]
    fn halves(self, a: F) -> (v128, v128) {
        (a.0, a.1)
    }
    #[inline(always)]
    fn lerp_h(self, a: v128, b: v128, t: f32) -> v128 {
        f32x4_add(a, f32x4_mul(f32x4_sub(b, a), f32x4_splat(t)))
    }
    #[inline(always)]
    fn zero_h(self) -> v128 {
        f32x4_splat(0.0)
    }
    #[inline(always)]
    unsafe fn load_h(self, p: *const f32) -> v128 {
        unsafe { v128_load(p as *const v128) }
    }
    #[inline(always)]
    fn columns(self, rows: [v128; 8]) -> [F; 4] {
        let [r0, r1, r2, r3, r4, r5, r6, r7] = rows;
        super::pair_columns(transpose(r0, r1, r2, r3), transpose(r4, r5, r6, r7))
    }
    /// WebAssembly has no prefetch: nothing.
    #[inline(always)]
    fn prefetch(self, _: *const u8) {}
}

/// Four rows of four as four columns (SSE's unpacks and moves, as shuffles).
#[inline(always)]
fn transpose(r0: v128, r1: v128, r2: v128, r3: v128) -> [v128; 4] {
    let t0 = i32x4_shuffle::<0, 4, 1, 5>(r0, r1);
    let t1 = i32x4_shuffle::<2, 6, 3, 7>(r0, r1);
    let t2 = i32x4_shuffle::<0, 4, 1, 5>(r2, r3);
    let t3 = i32x4_shuffle::<2, 6, 3, 7>(r2, r3);
    [
        i32x4_shuffle::<0, 1, 4, 5>(t0, t2),
        i32x4_shuffle::<2, 3, 6, 7>(t0, t2),
        i32x4_shuffle::<0, 1, 4, 5>(t1, t3),
        i32x4_shuffle::<2, 3, 6, 7>(t1, t3),
    ]
}
