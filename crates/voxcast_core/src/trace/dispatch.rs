//! Which vectors the CPU renderer may use, and whether a scene's rays take the eight lanes:
//! the same images, bit for bit, whichever it takes.

use super::*;

/// The widest vectors the CPU renderer may use ([`Scene::simd`]): the same images, bit for bit,
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

/// [`Scene::simd`]'s default for scenes built from now on.
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

/// Whether Accumulate renders of `scene` take the eight-lane path (`lanes.rs`): the scene
/// allows it ([`Scene::simd`], Accumulate with skipping, trilinear, shading from precomputed
/// records, directional lights, a whole-number shininess) and this CPU has AVX2, SSE 4.1 or
/// NEON.
pub fn uses_lanes(scene: &Scene<'_>) -> bool {
    lane_instructions(scene).is_some()
}

/// The instructions Accumulate renders of `scene` take their eight lanes with ("AVX2",
/// "SSE 4.1" or "NEON"), if they take them ([`uses_lanes`]).
pub fn lane_instructions(scene: &Scene<'_>) -> Option<&'static str> {
    struct Probe<'s, 'a>(&'s Scene<'a>);
    impl GridVisitor for Probe<'_, '_> {
        type Output = Option<&'static str>;
        fn visit<T: Voxel>(self, grid: Grid<'_, T>) -> Option<&'static str> {
            #[cfg(any(target_arch = "x86_64", target_arch = "aarch64"))]
            return lanes::Lanes::new(self.0, &grid).map(|l| l.instructions());
            #[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
            {
                let _ = (self.0, grid);
                None
            }
        }
    }
    if scene.settings.method != Method::Accumulate {
        return None;
    }
    scene.volume.visit(Probe(scene))
}

/// Whether projection renders of `scene` (Maximum, Minimum, Average, Sum) read their samples
/// eight at a time (`value_lanes.rs`; with skipping on, Maximum and Minimum take the best
/// blocks first, `extreme.rs`): integer data, trilinear, [`Scene::simd`], and a CPU with AVX2,
/// SSE 4.1 or NEON.
pub fn uses_value_lanes(scene: &Scene<'_>) -> bool {
    value_lane_instructions(scene).is_some()
}

/// The instructions projection renders of `scene` read their samples eight at a time with
/// ("AVX2", "SSE 4.1" or "NEON"), if they do ([`uses_value_lanes`]).
pub fn value_lane_instructions(scene: &Scene<'_>) -> Option<&'static str> {
    struct Probe<'s, 'a>(&'s Scene<'a>);
    impl GridVisitor for Probe<'_, '_> {
        type Output = Option<&'static str>;
        fn visit<T: Voxel>(self, grid: Grid<'_, T>) -> Option<&'static str> {
            let m = Marcher::new(self.0, grid);
            #[cfg(any(target_arch = "x86_64", target_arch = "aarch64"))]
            return m.values.map(|v| v.instructions());
            #[cfg(not(any(target_arch = "x86_64", target_arch = "aarch64")))]
            {
                let _ = m;
                None
            }
        }
    }
    let projection = matches!(
        scene.settings.method,
        Method::Maximum | Method::Minimum | Method::Average | Method::Sum
    );
    if !projection {
        return None;
    }
    scene.volume.visit(Probe(scene))
}
