//! Whether a scene's rays take the eight lanes, within the vectors the CPU renderer may use
//! (`crate::vectors`): the same images, bit for bit, whichever it takes.

use super::*;

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
            #[cfg(lanes)]
            return lanes::Lanes::new(self.0, &grid).map(|l| l.instructions());
            #[cfg(not(lanes))]
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
            #[cfg(lanes)]
            return m.values.map(|v| v.instructions());
            #[cfg(not(lanes))]
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
