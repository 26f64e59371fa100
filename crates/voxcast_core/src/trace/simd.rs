//! Eight `f32` lanes on four instruction sets: the operations the lanes (Accumulate's,
//! `lanes.rs`, and the projections', `value_lanes.rs`) are written in, once, over [`Simd`],
//! with one backend per instruction set —
//! [`Avx2`] (one 256-bit register a vector), [`Sse41`] (two 128-bit halves: the x86-64 CPUs
//! without AVX, as in most low-cost laptops: Intel's Celeron and Pentium Silver up to 2021),
//! `Neon` (two 128-bit halves: every 64-bit ARM CPU, Apple's among them) and `Simd128` (two
//! 128-bit halves: WebAssembly's SIMD, the web page's, in every browser since 2021).
//!
//! Every operation is lane-wise IEEE arithmetic, or moves bits, so the backends give the same
//! numbers bit for bit. A backend is a zero-sized token that exists only where its CPU
//! features were detected (`detect`): holding one is the proof that makes its operations safe
//! to call. They are `#[inline(always)]` and carry no target feature of their own; each march
//! is a [`Kernel`], which [`Backend::run`] instantiates per backend inside a function that
//! enables its instructions (`run_avx2` and its siblings), where the intrinsics inline. No closures in
//! that code: a closure is compiled without the backend's instructions, and one left out of
//! line makes every intrinsic in it a call (seen in the disassembly).

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "aarch64")]
mod neon;
#[cfg(target_arch = "x86_64")]
mod sse41;
#[cfg(target_arch = "wasm32")]
mod wasm;

#[cfg(target_arch = "x86_64")]
pub(super) use avx2::Avx2;
#[cfg(target_arch = "aarch64")]
pub(super) use neon::Neon;
#[cfg(target_arch = "x86_64")]
pub(super) use sse41::Sse41;
#[cfg(target_arch = "wasm32")]
pub(super) use wasm::Simd128;

use super::Vectors;
use crate::volume::ScalarType;

/// The instruction set the lanes run on: the widest the CPU has, up to the scene's
/// [`Vectors`] (each variant holding its token).
#[derive(Clone, Copy, Debug)]
pub(super) enum Backend {
    #[cfg(target_arch = "x86_64")]
    Avx2(Avx2),
    #[cfg(target_arch = "x86_64")]
    Sse41(Sse41),
    #[cfg(target_arch = "aarch64")]
    Neon(Neon),
    #[cfg(target_arch = "wasm32")]
    Simd128(Simd128),
}

impl Backend {
    /// The backend for the widest vectors this CPU has, up to `cap` (on ARM, NEON for both
    /// widths: it is the only one; in WebAssembly, its SIMD for both).
    pub(super) fn for_cpu(cap: Vectors) -> Option<Self> {
        if cap == Vectors::Off {
            return None;
        }
        #[cfg(target_arch = "x86_64")]
        return match cap {
            Vectors::Wide => Avx2::detect().map(Self::Avx2),
            _ => None,
        }
        .or_else(|| Sse41::detect().map(Self::Sse41));
        #[cfg(target_arch = "aarch64")]
        return Neon::detect().map(Self::Neon);
        #[cfg(target_arch = "wasm32")]
        return Simd128::detect().map(Self::Simd128);
    }

    /// Runs `kernel` with this backend's vectors, in a function compiled for them.
    #[inline]
    #[cfg_attr(target_arch = "wasm32", allow(unused_unsafe))]
    pub(super) fn run<K: Kernel>(self, kernel: K) -> K::Output {
        // SAFETY: each token exists only where its instructions do.
        unsafe {
            match self {
                #[cfg(target_arch = "x86_64")]
                Backend::Avx2(s) => run_avx2(s, kernel),
                #[cfg(target_arch = "x86_64")]
                Backend::Sse41(s) => run_sse41(s, kernel),
                #[cfg(target_arch = "aarch64")]
                Backend::Neon(s) => run_neon(s, kernel),
                #[cfg(target_arch = "wasm32")]
                // The whole module has the instructions: no function of its own needed.
                Backend::Simd128(s) => kernel.run(s),
            }
        }
    }

    /// The instruction set, in words.
    pub(super) fn name(self) -> &'static str {
        match self {
            #[cfg(target_arch = "x86_64")]
            Backend::Avx2(_) => "AVX2",
            #[cfg(target_arch = "x86_64")]
            Backend::Sse41(_) => "SSE 4.1",
            #[cfg(target_arch = "aarch64")]
            Backend::Neon(_) => "NEON",
            #[cfg(target_arch = "wasm32")]
            Backend::Simd128(_) => "WebAssembly SIMD",
        }
    }
}

/// Work written once over any backend: [`Backend::run`] calls `run` inside a function compiled
/// for the backend's instructions. Implementations mark `run` `#[inline(always)]`, so that the
/// work (and every operation in it) inlines there.
pub(super) trait Kernel {
    type Output;
    fn run<S: Simd>(self, s: S) -> Self::Output;
}

/// [`Kernel::run`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_avx2<K: Kernel>(s: Avx2, kernel: K) -> K::Output {
    kernel.run(s)
}

/// [`Kernel::run`] compiled for SSE 4.1.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse4.1")]
fn run_sse41<K: Kernel>(s: Sse41, kernel: K) -> K::Output {
    kernel.run(s)
}

/// [`Kernel::run`] compiled for NEON.
#[cfg(target_arch = "aarch64")]
#[target_feature(enable = "neon")]
fn run_neon<K: Kernel>(s: Neon, kernel: K) -> K::Output {
    kernel.run(s)
}

/// Two halves of four lanes: lanes 0–3, lanes 4–7 (the SSE 4.1, NEON and WebAssembly
/// backends' vectors).
#[derive(Clone, Copy, Debug)]
pub(super) struct Pair<T>(T, T);

/// Two halves' four rows transposed (lanes 0–3's columns, lanes 4–7's) as four columns of
/// eight: [`Simd::columns`] of the backends with two halves.
#[inline(always)]
fn pair_columns<H: Copy>(lo: [H; 4], hi: [H; 4]) -> [Pair<H>; 4] {
    [
        Pair(lo[0], hi[0]),
        Pair(lo[1], hi[1]),
        Pair(lo[2], hi[2]),
        Pair(lo[3], hi[3]),
    ]
}

/// Per set of four lanes (a bit each), the byte shuffle that packs them to the front, the
/// rest of the sixteen bytes `fill` (a byte both backends' shuffles turn into zero).
const fn pack4(fill: u8) -> [[u8; 16]; 16] {
    let mut table = [[fill; 16]; 16];
    let mut mask = 0;
    while mask < 16 {
        let (mut lane, mut n) = (0, 0);
        while lane < 4 {
            if mask & (1 << lane) != 0 {
                let mut byte = 0;
                while byte < 4 {
                    table[mask][4 * n + byte] = (4 * lane + byte) as u8;
                    byte += 1;
                }
                n += 1;
            }
            lane += 1;
        }
        mask += 1;
    }
    table
}

/// `a + (b − a)·t`, lane by lane: the lanes' twin of [`crate::sample::lerp`] (a function, not a
/// closure, so it inlines into the backend's `#[target_feature]` code).
#[inline(always)]
pub(super) fn lerp<S: Simd>(s: S, a: S::F, b: S::F, t: S::F) -> S::F {
    s.add(a, s.mul(s.sub(b, a), t))
}

/// Eight lanes of `f32` and of `i32`, and what the lanes' march does with them. Every x86-64
/// backend's CPU has SSE 4.1 (AVX2 implies it), which code beside the lanes relies on
/// (`leaps.rs`).
///
/// Comparisons give masks (every bit of a lane set where true) in [`Simd::F`]; `select` takes
/// such a mask. Shifts and conversions are those of the x86 instructions: `trunc` rounds toward
/// zero and gives `i32::MIN` for what does not fit.
pub(super) trait Simd: Copy {
    /// Eight `f32`.
    type F: Copy;
    /// Eight `i32`.
    type I: Copy;
    /// The permutation that packs chosen lanes to the front ([`Simd::order`]).
    type Order: Copy;
    /// Four `f32`: one lane's four channels.
    type H: Copy;
    /// Two records side by side (eight `i16`): the sixteen bytes, or where they are (SSE 4.1
    /// widens each half straight from memory).
    type R: Copy;

    fn splat(self, x: f32) -> Self::F;
    fn splat_i(self, x: i32) -> Self::I;
    /// Lanes `0, 1, …, 7`.
    fn iota(self) -> Self::I;

    fn add(self, a: Self::F, b: Self::F) -> Self::F;
    fn sub(self, a: Self::F, b: Self::F) -> Self::F;
    fn mul(self, a: Self::F, b: Self::F) -> Self::F;
    fn div(self, a: Self::F, b: Self::F) -> Self::F;
    fn sqrt(self, a: Self::F) -> Self::F;
    /// `a < b ? a : b` per lane (`b` where either is NaN), as `minps`.
    fn min(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a > b ? a : b` per lane (`b` where either is NaN), as `maxps`.
    fn max(self, a: Self::F, b: Self::F) -> Self::F;
    fn and(self, a: Self::F, b: Self::F) -> Self::F;
    fn or(self, a: Self::F, b: Self::F) -> Self::F;
    fn xor(self, a: Self::F, b: Self::F) -> Self::F;
    /// `!a & b`.
    fn and_not(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a > b` (false where either is NaN).
    fn gt(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a < b` (false where either is NaN).
    fn lt(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a <= b` (false where either is NaN).
    fn le(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a >= b` (false where either is NaN).
    fn ge(self, a: Self::F, b: Self::F) -> Self::F;
    /// `!(a <= b)` (true where either is NaN).
    fn not_le(self, a: Self::F, b: Self::F) -> Self::F;
    /// `b` where `mask`, else `a`.
    fn select(self, a: Self::F, b: Self::F, mask: Self::F) -> Self::F;
    /// The lanes' sign bits as bits 0–7.
    fn bits(self, mask: Self::F) -> u32;

    fn add_i(self, a: Self::I, b: Self::I) -> Self::I;
    fn mul_i(self, a: Self::I, b: Self::I) -> Self::I;
    fn and_i(self, a: Self::I, b: Self::I) -> Self::I;
    fn or_i(self, a: Self::I, b: Self::I) -> Self::I;
    fn min_i(self, a: Self::I, b: Self::I) -> Self::I;
    /// Logical: zeros shifted in.
    fn shr_i<const N: i32>(self, a: Self::I) -> Self::I;
    /// Arithmetic: the sign shifted in.
    fn shr_signed_i<const N: i32>(self, a: Self::I) -> Self::I;
    fn shl_i<const N: i32>(self, a: Self::I) -> Self::I;
    /// `a == b` as a mask.
    fn eq_i(self, a: Self::I, b: Self::I) -> Self::F;
    /// `a > b` (signed) as a mask.
    fn gt_i(self, a: Self::I, b: Self::I) -> Self::F;
    /// Rounded toward zero (`cvttps2dq`).
    fn trunc(self, a: Self::F) -> Self::I;
    fn to_f(self, a: Self::I) -> Self::F;

    /// # Safety
    /// `p` points at eight readable `f32`.
    unsafe fn load(self, p: *const f32) -> Self::F;
    /// # Safety
    /// `p` points at eight readable `i32`.
    unsafe fn load_i(self, p: *const i32) -> Self::I;
    /// # Safety
    /// `p` points at eight writable `f32`.
    unsafe fn store(self, p: *mut f32, a: Self::F);
    /// # Safety
    /// `p` points at eight writable `i32`.
    unsafe fn store_i(self, p: *mut i32, a: Self::I);

    /// Lane 0 in every lane.
    fn broadcast_first(self, a: Self::F) -> Self::F;
    /// Lane 0.
    fn first(self, a: Self::F) -> f32;
    /// The largest lane (`larger`) or the smallest, in every lane, taken by [`Simd::max`] or
    /// [`Simd::min`] (no lane may be NaN: the order they are taken in differs by backend).
    fn best_across(self, a: Self::F, larger: bool) -> Self::F;
    /// `p[idx]` per lane: lane by lane, but where the backend has a gather (AVX2).
    ///
    /// # Safety
    /// Every lane's `idx` indexes the `f32`s at `p`.
    #[inline(always)]
    unsafe fn gather(self, p: *const f32, idx: Self::I) -> Self::F {
        let mut at = [0i32; 8];
        // SAFETY: eight lanes into eight slots.
        unsafe { self.store_i(at.as_mut_ptr(), idx) };
        let mut v = [0f32; 8];
        for (v, &at) in v.iter_mut().zip(&at) {
            // SAFETY: the caller's bound.
            *v = unsafe { *p.add(at as usize) };
        }
        // SAFETY: eight lanes.
        unsafe { self.load(v.as_ptr()) }
    }

    /// Per lane, elements `at` and `at + 1` of `data` (of `kind`, 8 or 16 bits) in the low 16
    /// or 32 bits of a 32-bit word, element `at` lowest: each lane's pair read on its own and
    /// the eight put together — or, with `gather` where the backend has a gather worth taking
    /// (AVX2 on CPUs with AVX-512: `avx2.rs`), gathered. The same words' pairs either way.
    ///
    /// # Safety
    /// `at + 1` is an element of the data in every lane; 8-bit data has at least four bytes.
    #[inline(always)]
    unsafe fn pairs(self, data: *const u8, kind: ScalarType, at: Self::I, gather: bool) -> Self::I {
        let _ = gather;
        // SAFETY: the caller's.
        unsafe { read_pairs(self, data, kind, at) }
    }

    /// Which lanes' bit `bit & 31` is set in the 32-bit word `words[word]`, as bits 0–7: lane
    /// by lane, eight loads and shifts, but where the backend has a gather and variable shifts
    /// (AVX2).
    ///
    /// # Safety
    /// Every lane's `word` indexes `words`.
    #[inline(always)]
    unsafe fn bit_set(self, words: *const i32, word: Self::I, bit: Self::I) -> u32 {
        let (mut w, mut b) = ([0i32; 8], [0i32; 8]);
        // SAFETY: eight lanes into eight slots each.
        unsafe {
            self.store_i(w.as_mut_ptr(), word);
            self.store_i(b.as_mut_ptr(), bit);
        }
        let mut set = 0;
        for lane in 0..8 {
            // SAFETY: the caller's bound.
            let x = unsafe { *words.add(w[lane] as usize) } as u32;
            set |= ((x >> (b[lane] & 31)) & 1) << lane;
        }
        set
    }

    /// The permutation that moves the lanes set in `mask` (bits 0–7) to the front, in order.
    fn order(self, mask: u32) -> Self::Order;
    /// Writes the lanes of `a` chosen by `order` to `dst[0..]`, in order; what follows them up
    /// to `dst[8]` is overwritten with anything.
    ///
    /// # Safety
    /// `p` points at eight writable `f32`.
    unsafe fn pack(self, dst: *mut f32, a: Self::F, order: Self::Order);
    /// [`Simd::pack`] for `i32`.
    ///
    /// # Safety
    /// `p` points at eight writable `i32`.
    unsafe fn pack_i(self, dst: *mut i32, a: Self::I, order: Self::Order);

    /// # Safety
    /// `p` points at sixteen readable bytes, which stay unchanged until the pair is widened.
    unsafe fn load_pair(self, p: *const u8) -> Self::R;
    /// Two pairs of records `a = [a0 | a1]` and `b = [b0 | b1]` (four `i16` each) as eight
    /// `f32`: `[a0 | b0]` and `[a1 | b1]`.
    ///
    /// # Safety
    /// `a` and `b` are from [`Simd::load_pair`], whose contract still holds.
    unsafe fn widen_pairs(self, a: Self::R, b: Self::R) -> (Self::F, Self::F);
    /// Lanes 0–3 and 4–7.
    fn halves(self, a: Self::F) -> (Self::H, Self::H);
    /// `a + (b − a)·t` in four lanes.
    fn lerp_h(self, a: Self::H, b: Self::H, t: f32) -> Self::H;
    fn zero_h(self) -> Self::H;
    /// # Safety
    /// `p` points at four readable `f32`.
    unsafe fn load_h(self, p: *const f32) -> Self::H;
    /// Eight rows of four (one lane's four channels each) as four columns of eight.
    fn columns(self, rows: [Self::H; 8]) -> [Self::F; 4];
    /// Asks for the cache line at `p` (a hint: never a read, any address).
    fn prefetch(self, p: *const u8);
}

/// [`Simd::pairs`] lane by lane: each lane's pair read on its own, the eight put together.
/// Cheaper than a gather where a gather of eight is some twenty micro-operations (Zen 1: the
/// gathers were 18 % of a Maximum render).
///
/// # Safety
/// As [`Simd::pairs`].
#[inline(always)]
pub(super) unsafe fn read_pairs<S: Simd>(
    s: S,
    data: *const u8,
    kind: ScalarType,
    at: S::I,
) -> S::I {
    let mut lanes = [0i32; 8];
    // SAFETY: eight lanes into eight slots.
    unsafe { s.store_i(lanes.as_mut_ptr(), at) };
    let byte = kind == ScalarType::U8;
    let mut words = [0i32; 8];
    for (word, &at) in words.iter_mut().zip(&lanes) {
        // SAFETY: elements `at` and `at + 1` lie in the data; unaligned reads.
        *word = unsafe {
            if byte {
                (data.add(at as usize) as *const u16).read_unaligned() as i32
            } else {
                (data.add(at as usize * 2) as *const i32).read_unaligned()
            }
        };
    }
    // SAFETY: eight lanes.
    unsafe { s.load_i(words.as_ptr()) }
}
