//! [`Simd`] on NEON (64-bit ARM): each vector two 128-bit halves, lanes 0–3 and 4–7, as on
//! SSE 4.1 (`sse41.rs`), with the x86 instructions' semantics where NEON's differ: `min` and
//! `max` give their second operand where either is NaN (NEON's give NaN), and a sign-bit mask
//! is gathered by shifts and an add across. `trunc` saturates where `cvttps2dq` gives
//! `i32::MIN`; the lanes truncate only clamped, finite values, where the two agree.

use super::{Pair, Simd};
use std::arch::aarch64::*;

/// The NEON backend: every 64-bit ARM CPU has it ([`Neon::detect`] asks all the same).
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) struct Neon(());

impl Neon {
    /// The token, if this CPU has NEON.
    pub(in crate::trace) fn detect() -> Option<Self> {
        std::arch::is_aarch64_feature_detected!("neon").then_some(Self(()))
    }
}

/// How [`Simd::pack`] moves a vector's chosen lanes: each half's byte table, and how many
/// lanes the low half keeps.
#[derive(Clone, Copy, Debug)]
pub(in crate::trace) struct Order {
    lo: uint8x16_t,
    hi: uint8x16_t,
    kept_lo: usize,
}

/// [`super::pack4`]'s table, the rest of each row 0xFF (out of range: `tbl` zeroes such a
/// byte).
const PACK4: [[u8; 16]; 16] = super::pack4(0xFF);

/// Each lane's weight in a mask's bits.
const WEIGHTS: [u32; 4] = [1, 2, 4, 8];

type F = Pair<float32x4_t>;
type I = Pair<int32x4_t>;

/// A float mask from a comparison's.
#[inline(always)]
fn mask(m: uint32x4_t) -> float32x4_t {
    // SAFETY: NEON, which every 64-bit ARM CPU has.
    unsafe { vreinterpretq_f32_u32(m) }
}

/// A float vector's bits.
#[inline(always)]
fn raw(a: float32x4_t) -> uint32x4_t {
    // SAFETY: as above.
    unsafe { vreinterpretq_u32_f32(a) }
}

// SAFETY (every `unsafe` block below): the token exists only where the CPU has NEON; pointers
// are the callers' to vouch for, as each method's contract says (a prefetch is a hint: it
// reads nothing and never faults). No closures, as in `avx2.rs`.
impl Simd for Neon {
    type F = F;
    type I = I;
    type Order = Order;
    type H = float32x4_t;
    type R = int16x8_t;

    #[inline(always)]
    fn splat(self, x: f32) -> F {
        let h = unsafe { vdupq_n_f32(x) };
        Pair(h, h)
    }
    #[inline(always)]
    fn splat_i(self, x: i32) -> I {
        let h = unsafe { vdupq_n_s32(x) };
        Pair(h, h)
    }
    #[inline(always)]
    fn iota(self) -> I {
        let (lo, hi) = ([0, 1, 2, 3], [4, 5, 6, 7]);
        unsafe { Pair(vld1q_s32(lo.as_ptr()), vld1q_s32(hi.as_ptr())) }
    }
    #[inline(always)]
    fn add(self, a: F, b: F) -> F {
        unsafe { Pair(vaddq_f32(a.0, b.0), vaddq_f32(a.1, b.1)) }
    }
    #[inline(always)]
    fn sub(self, a: F, b: F) -> F {
        unsafe { Pair(vsubq_f32(a.0, b.0), vsubq_f32(a.1, b.1)) }
    }
    #[inline(always)]
    fn mul(self, a: F, b: F) -> F {
        unsafe { Pair(vmulq_f32(a.0, b.0), vmulq_f32(a.1, b.1)) }
    }
    #[inline(always)]
    fn div(self, a: F, b: F) -> F {
        unsafe { Pair(vdivq_f32(a.0, b.0), vdivq_f32(a.1, b.1)) }
    }
    #[inline(always)]
    fn sqrt(self, a: F) -> F {
        unsafe { Pair(vsqrtq_f32(a.0), vsqrtq_f32(a.1)) }
    }
    /// `a < b ? a : b`, as `minps` (NEON's `fmin` would give NaN).
    #[inline(always)]
    fn min(self, a: F, b: F) -> F {
        unsafe {
            Pair(
                vbslq_f32(vcltq_f32(a.0, b.0), a.0, b.0),
                vbslq_f32(vcltq_f32(a.1, b.1), a.1, b.1),
            )
        }
    }
    /// `a > b ? a : b`, as `maxps`.
    #[inline(always)]
    fn max(self, a: F, b: F) -> F {
        unsafe {
            Pair(
                vbslq_f32(vcgtq_f32(a.0, b.0), a.0, b.0),
                vbslq_f32(vcgtq_f32(a.1, b.1), a.1, b.1),
            )
        }
    }
    #[inline(always)]
    fn and(self, a: F, b: F) -> F {
        unsafe {
            Pair(
                mask(vandq_u32(raw(a.0), raw(b.0))),
                mask(vandq_u32(raw(a.1), raw(b.1))),
            )
        }
    }
    #[inline(always)]
    fn or(self, a: F, b: F) -> F {
        unsafe {
            Pair(
                mask(vorrq_u32(raw(a.0), raw(b.0))),
                mask(vorrq_u32(raw(a.1), raw(b.1))),
            )
        }
    }
    #[inline(always)]
    fn xor(self, a: F, b: F) -> F {
        unsafe {
            Pair(
                mask(veorq_u32(raw(a.0), raw(b.0))),
                mask(veorq_u32(raw(a.1), raw(b.1))),
            )
        }
    }
    /// `!a & b` (`bic` clears `b`'s bits that are set in `a`).
    #[inline(always)]
    fn and_not(self, a: F, b: F) -> F {
        unsafe {
            Pair(
                mask(vbicq_u32(raw(b.0), raw(a.0))),
                mask(vbicq_u32(raw(b.1), raw(a.1))),
            )
        }
    }
    #[inline(always)]
    fn gt(self, a: F, b: F) -> F {
        unsafe { Pair(mask(vcgtq_f32(a.0, b.0)), mask(vcgtq_f32(a.1, b.1))) }
    }
    #[inline(always)]
    fn lt(self, a: F, b: F) -> F {
        unsafe { Pair(mask(vcltq_f32(a.0, b.0)), mask(vcltq_f32(a.1, b.1))) }
    }
    #[inline(always)]
    fn le(self, a: F, b: F) -> F {
        unsafe { Pair(mask(vcleq_f32(a.0, b.0)), mask(vcleq_f32(a.1, b.1))) }
    }
    #[inline(always)]
    fn ge(self, a: F, b: F) -> F {
        unsafe { Pair(mask(vcgeq_f32(a.0, b.0)), mask(vcgeq_f32(a.1, b.1))) }
    }
    #[inline(always)]
    fn not_le(self, a: F, b: F) -> F {
        unsafe {
            Pair(
                mask(vmvnq_u32(vcleq_f32(a.0, b.0))),
                mask(vmvnq_u32(vcleq_f32(a.1, b.1))),
            )
        }
    }
    /// Every mask the lanes select by is whole (all bits of a lane alike), so a bitwise
    /// select is `blendv`'s sign-bit one.
    #[inline(always)]
    fn select(self, a: F, b: F, mask: F) -> F {
        unsafe {
            Pair(
                vbslq_f32(raw(mask.0), b.0, a.0),
                vbslq_f32(raw(mask.1), b.1, a.1),
            )
        }
    }
    #[inline(always)]
    fn bits(self, mask: F) -> u32 {
        unsafe {
            let w = vld1q_u32(WEIGHTS.as_ptr());
            let lo = vaddvq_u32(vmulq_u32(vshrq_n_u32::<31>(raw(mask.0)), w));
            let hi = vaddvq_u32(vmulq_u32(vshrq_n_u32::<31>(raw(mask.1)), w));
            lo | (hi << 4)
        }
    }
    #[inline(always)]
    fn add_i(self, a: I, b: I) -> I {
        unsafe { Pair(vaddq_s32(a.0, b.0), vaddq_s32(a.1, b.1)) }
    }
    #[inline(always)]
    fn mul_i(self, a: I, b: I) -> I {
        unsafe { Pair(vmulq_s32(a.0, b.0), vmulq_s32(a.1, b.1)) }
    }
    #[inline(always)]
    fn and_i(self, a: I, b: I) -> I {
        unsafe { Pair(vandq_s32(a.0, b.0), vandq_s32(a.1, b.1)) }
    }
    #[inline(always)]
    fn or_i(self, a: I, b: I) -> I {
        unsafe { Pair(vorrq_s32(a.0, b.0), vorrq_s32(a.1, b.1)) }
    }
    #[inline(always)]
    fn min_i(self, a: I, b: I) -> I {
        unsafe { Pair(vminq_s32(a.0, b.0), vminq_s32(a.1, b.1)) }
    }
    /// Logical, as `psrld`.
    #[inline(always)]
    fn shr_i<const N: i32>(self, a: I) -> I {
        unsafe {
            let (lo, hi) = (vreinterpretq_u32_s32(a.0), vreinterpretq_u32_s32(a.1));
            Pair(
                vreinterpretq_s32_u32(vshrq_n_u32::<N>(lo)),
                vreinterpretq_s32_u32(vshrq_n_u32::<N>(hi)),
            )
        }
    }
    #[inline(always)]
    fn shr_signed_i<const N: i32>(self, a: I) -> I {
        unsafe { Pair(vshrq_n_s32::<N>(a.0), vshrq_n_s32::<N>(a.1)) }
    }
    #[inline(always)]
    fn shl_i<const N: i32>(self, a: I) -> I {
        unsafe { Pair(vshlq_n_s32::<N>(a.0), vshlq_n_s32::<N>(a.1)) }
    }
    #[inline(always)]
    fn eq_i(self, a: I, b: I) -> F {
        unsafe { Pair(mask(vceqq_s32(a.0, b.0)), mask(vceqq_s32(a.1, b.1))) }
    }
    #[inline(always)]
    fn gt_i(self, a: I, b: I) -> F {
        unsafe { Pair(mask(vcgtq_s32(a.0, b.0)), mask(vcgtq_s32(a.1, b.1))) }
    }
    #[inline(always)]
    fn trunc(self, a: F) -> I {
        unsafe { Pair(vcvtq_s32_f32(a.0), vcvtq_s32_f32(a.1)) }
    }
    #[inline(always)]
    fn to_f(self, a: I) -> F {
        unsafe { Pair(vcvtq_f32_s32(a.0), vcvtq_f32_s32(a.1)) }
    }
    #[inline(always)]
    unsafe fn load(self, p: *const f32) -> F {
        unsafe { Pair(vld1q_f32(p), vld1q_f32(p.add(4))) }
    }
    #[inline(always)]
    unsafe fn load_i(self, p: *const i32) -> I {
        unsafe { Pair(vld1q_s32(p), vld1q_s32(p.add(4))) }
    }
    #[inline(always)]
    unsafe fn store(self, p: *mut f32, a: F) {
        unsafe {
            vst1q_f32(p, a.0);
            vst1q_f32(p.add(4), a.1);
        }
    }
    #[inline(always)]
    unsafe fn store_i(self, p: *mut i32, a: I) {
        unsafe {
            vst1q_s32(p, a.0);
            vst1q_s32(p.add(4), a.1);
        }
    }

    #[inline(always)]
    fn broadcast_first(self, a: F) -> F {
        let h = unsafe { vdupq_laneq_f32::<0>(a.0) };
        Pair(h, h)
    }
    #[inline(always)]
    fn first(self, a: F) -> f32 {
        unsafe { vgetq_lane_f32::<0>(a.0) }
    }
    /// Halves against each other, then pairs, then neighbours, by [`Simd::max`] or
    /// [`Simd::min`] (x86's semantics).
    #[inline(always)]
    fn best_across(self, m: F, larger: bool) -> F {
        let swapped = Pair(m.1, m.0);
        let h = if larger {
            self.max(m, swapped)
        } else {
            self.min(m, swapped)
        };
        let pairs = unsafe { Pair(vextq_f32::<2>(h.0, h.0), vextq_f32::<2>(h.1, h.1)) };
        let h = if larger {
            self.max(h, pairs)
        } else {
            self.min(h, pairs)
        };
        let next = unsafe { Pair(vrev64q_f32(h.0), vrev64q_f32(h.1)) };
        if larger {
            self.max(h, next)
        } else {
            self.min(h, next)
        }
    }
    #[inline(always)]
    fn order(self, mask: u32) -> Order {
        let (lo, hi) = (mask as usize & 0xF, (mask as usize >> 4) & 0xF);
        unsafe {
            Order {
                lo: vld1q_u8(PACK4[lo].as_ptr()),
                hi: vld1q_u8(PACK4[hi].as_ptr()),
                kept_lo: lo.count_ones() as usize,
            }
        }
    }
    #[inline(always)]
    unsafe fn pack(self, dst: *mut f32, a: F, order: Order) {
        unsafe {
            let lo = vqtbl1q_u8(vreinterpretq_u8_f32(a.0), order.lo);
            let hi = vqtbl1q_u8(vreinterpretq_u8_f32(a.1), order.hi);
            vst1q_f32(dst, vreinterpretq_f32_u8(lo));
            vst1q_f32(dst.add(order.kept_lo), vreinterpretq_f32_u8(hi));
        }
    }
    #[inline(always)]
    unsafe fn pack_i(self, dst: *mut i32, a: I, order: Order) {
        unsafe {
            let lo = vqtbl1q_u8(vreinterpretq_u8_s32(a.0), order.lo);
            let hi = vqtbl1q_u8(vreinterpretq_u8_s32(a.1), order.hi);
            vst1q_s32(dst, vreinterpretq_s32_u8(lo));
            vst1q_s32(dst.add(order.kept_lo), vreinterpretq_s32_u8(hi));
        }
    }

    #[inline(always)]
    unsafe fn load_pair(self, p: *const u8) -> int16x8_t {
        unsafe { vld1q_s16(p as *const i16) }
    }
    /// Each half from one of the pairs: `[a0 | b0]` is `a`'s low four and `b`'s low four.
    #[inline(always)]
    unsafe fn widen_pairs(self, a: int16x8_t, b: int16x8_t) -> (F, F) {
        unsafe {
            let (a0, b0) = (vmovl_s16(vget_low_s16(a)), vmovl_s16(vget_low_s16(b)));
            let (a1, b1) = (vmovl_high_s16(a), vmovl_high_s16(b));
            (
                Pair(vcvtq_f32_s32(a0), vcvtq_f32_s32(b0)),
                Pair(vcvtq_f32_s32(a1), vcvtq_f32_s32(b1)),
            )
        }
    }
    #[inline(always)]
    fn halves(self, a: F) -> (float32x4_t, float32x4_t) {
        (a.0, a.1)
    }
    #[inline(always)]
    fn lerp_h(self, a: float32x4_t, b: float32x4_t, t: f32) -> float32x4_t {
        unsafe { vaddq_f32(a, vmulq_f32(vsubq_f32(b, a), vdupq_n_f32(t))) }
    }
    #[inline(always)]
    fn zero_h(self) -> float32x4_t {
        unsafe { vdupq_n_f32(0.0) }
    }
    #[inline(always)]
    unsafe fn load_h(self, p: *const f32) -> float32x4_t {
        unsafe { vld1q_f32(p) }
    }
    #[inline(always)]
    fn columns(self, rows: [float32x4_t; 8]) -> [F; 4] {
        let [r0, r1, r2, r3, r4, r5, r6, r7] = rows;
        super::pair_columns(transpose(r0, r1, r2, r3), transpose(r4, r5, r6, r7))
    }
    #[inline(always)]
    fn prefetch(self, p: *const u8) {
        // SAFETY: a hint: it reads nothing, writes nothing and never faults.
        unsafe {
            std::arch::asm!(
                "prfm pldl1keep, [{0}]",
                in(reg) p,
                options(nostack, preserves_flags, readonly)
            );
        }
    }
}

/// Four rows of four as four columns.
#[inline(always)]
fn transpose(
    r0: float32x4_t,
    r1: float32x4_t,
    r2: float32x4_t,
    r3: float32x4_t,
) -> [float32x4_t; 4] {
    // SAFETY: NEON, which every 64-bit ARM CPU has.
    unsafe {
        let (t0, t1) = (vzip1q_f32(r0, r1), vzip2q_f32(r0, r1));
        let (t2, t3) = (vzip1q_f32(r2, r3), vzip2q_f32(r2, r3));
        let (t0, t1) = (vreinterpretq_f64_f32(t0), vreinterpretq_f64_f32(t1));
        let (t2, t3) = (vreinterpretq_f64_f32(t2), vreinterpretq_f64_f32(t3));
        [
            vreinterpretq_f32_f64(vzip1q_f64(t0, t2)),
            vreinterpretq_f32_f64(vzip2q_f64(t0, t2)),
            vreinterpretq_f32_f64(vzip1q_f64(t1, t3)),
            vreinterpretq_f32_f64(vzip2q_f64(t1, t3)),
        ]
    }
}
