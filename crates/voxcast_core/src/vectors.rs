//! Which vectors the CPU renderer may use — AVX2, SSE 4.1 or NEON, or none — for scenes built
//! from now on: the same images, bit for bit, whichever it takes. Whether a scene's rays take
//! them is `trace::uses_lanes`.

use serde::Serialize;

/// The widest vectors the CPU renderer may use (`Scene::simd`): the same images, bit for bit,
/// whichever it takes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub enum Vectors {
    /// The widest the CPU has: AVX2 (eight lanes in one register), else SSE 4.1; on 64-bit
    /// ARM, NEON.
    #[default]
    Wide,
    /// SSE 4.1 at most (eight lanes in two registers of four), as on an x86-64 without AVX —
    /// most low-cost laptops' Celeron and Pentium Silver CPUs up to 2021 (on ARM, NEON as
    /// ever).
    Narrow,
    /// None: every sample one at a time, as on an x86-64 without SSE 4.1 or a CPU neither
    /// x86-64 nor 64-bit ARM.
    Off,
}

/// [`crate::scene::Scene::simd`]'s default for scenes built from now on.
static VECTORS: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(0);

/// Lets a measurement render as a CPU with narrower vectors, or none, does: scenes built
/// afterwards take [`Vectors`] at most — the same images, bit for bit. For the whole process
/// (the command line's `--no-lanes` and `--narrow-lanes`).
pub fn set_vectors(v: Vectors) {
    VECTORS.store(v as u8, std::sync::atomic::Ordering::Relaxed);
}

/// The widest vectors scenes built now may use ([`set_vectors`]).
pub fn vectors() -> Vectors {
    match VECTORS.load(std::sync::atomic::Ordering::Relaxed) {
        0 => Vectors::Wide,
        1 => Vectors::Narrow,
        _ => Vectors::Off,
    }
}
