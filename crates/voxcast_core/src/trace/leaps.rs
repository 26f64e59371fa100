//! The lanes' look at a ray's next brick and their leap over empty bricks, with the three axes
//! in one SSE vector: the numbers of `Lanes::cell_lo`, `VisibleCells::brick_of`,
//! `VisibleCells::leap_exit_at` and `first_index_from`, operation for operation, in a third of
//! their instructions (glam's `Vec3` and the leap's loop over axes had been a fifth of a CT
//! render's instructions).
//!
//! Every number is the scalar one: the position `o + d·t` and its clamps are the same rounded
//! operations lane by lane; the brick's index is integer arithmetic; each face's `t` is the
//! same subtraction and product, and the least of them is exact whichever order it is taken
//! in (none is NaN: the faces and the origin are finite, and an axis the ray does not move
//! along has no face). `tests/lanes.rs` compares every pixel with the scalar march.

use crate::skip::{BRICK_MARGIN, VisibleCells};
use crate::step::{StepPlan, first_index_with};
use glam::Vec3;
use std::arch::x86_64::*;

/// One ray's constants for its looks and leaps (lane 3 unused: zero, and no face).
pub(super) struct Leaps {
    origin: __m128,
    dir: __m128,
    inv_d: __m128,
    last: __m128,
    max_lo: __m128,
    /// The index of brick `(x, y, z)` is the dot product with `(1, bricks_x, bricks_x·bricks_y)`.
    stride: __m128i,
    bricks: __m128i,
    /// Axes the ray moves up along, and down along (finite, non-zero inverse direction).
    up: __m128,
    down: __m128,
}

/// Where a position lies: its brick's coordinates and index in the visibility words.
pub(super) struct Look {
    brick: __m128i,
    pub(super) index: usize,
}

impl Leaps {
    /// SSE 4.1 and below (so every x86-64 backend of the lanes, `simd.rs`).
    #[target_feature(enable = "sse4.1")]
    pub(super) fn new(
        cells: &VisibleCells,
        (o_v, d_v, inv_d): (Vec3, Vec3, Vec3),
        (last, max_lo): (Vec3, Vec3),
    ) -> Self {
        let v = |a: Vec3| _mm_setr_ps(a.x, a.y, a.z, 0.0);
        let [bx, by, bz] = cells.bricks().map(|b| b as i32);
        let inv = v(inv_d);
        let inf = _mm_set1_ps(f32::INFINITY);
        let finite = _mm_cmplt_ps(_mm_andnot_ps(_mm_set1_ps(-0.0), inv), inf);
        Self {
            origin: v(o_v),
            dir: v(d_v),
            inv_d: inv,
            last: v(last),
            max_lo: v(max_lo),
            stride: _mm_setr_epi32(1, bx, bx * by, 0),
            bricks: _mm_setr_epi32(bx, by, bz, 0),
            up: _mm_and_ps(finite, _mm_cmpgt_ps(inv, _mm_setzero_ps())),
            down: _mm_and_ps(finite, _mm_cmplt_ps(inv, _mm_setzero_ps())),
        }
    }

    /// The brick of the cell holding the ray's position at `t` (`Lanes::cell_lo`, then
    /// `VisibleCells::brick_of`).
    #[inline]
    #[target_feature(enable = "sse4.1")]
    pub(super) fn look(&self, t: f32) -> Look {
        let p = _mm_add_ps(self.origin, _mm_mul_ps(self.dir, _mm_set1_ps(t)));
        // `max` with zero first: a NaN lane becomes 0, as `f32::max` makes it.
        let x = _mm_min_ps(
            _mm_min_ps(_mm_max_ps(p, _mm_setzero_ps()), self.last),
            self.max_lo,
        );
        let brick = _mm_srli_epi32::<2>(_mm_cvttps_epi32(x));
        let m = _mm_mullo_epi32(brick, self.stride);
        let s = _mm_add_epi32(m, _mm_shuffle_epi32::<0b01_00_11_10>(m));
        let s = _mm_add_epi32(s, _mm_shuffle_epi32::<0b10_11_00_01>(s));
        Look {
            brick,
            index: _mm_cvtsi128_si32(s) as usize,
        }
    }

    /// `VisibleCells::leap_exit_at` for the brick of `look`, `distance` its distance ahead: the
    /// least `t` at which the ray leaves the cube of empty bricks ahead of it.
    #[inline]
    #[target_feature(enable = "sse4.1")]
    pub(super) fn exit(&self, look: &Look, distance: u8) -> f32 {
        let b = look.brick;
        let reach = _mm_set1_epi32(i32::from(distance.max(1)) - 1);
        let above = _mm_add_epi32(_mm_add_epi32(b, reach), _mm_set1_epi32(1));
        let below = _mm_sub_epi32(b, reach);
        let margin = _mm_set1_ps(BRICK_MARGIN);
        let face_up = _mm_sub_ps(_mm_cvtepi32_ps(_mm_slli_epi32::<2>(above)), margin);
        let face_down = _mm_add_ps(_mm_cvtepi32_ps(_mm_slli_epi32::<2>(below)), margin);
        // A face only where the ray moves towards it and the cube does not reach the border.
        let open_up = _mm_castsi128_ps(_mm_cmplt_epi32(above, self.bricks));
        let open_down = _mm_castsi128_ps(_mm_cmpgt_epi32(b, reach));
        let open = _mm_or_ps(
            _mm_and_ps(self.up, open_up),
            _mm_and_ps(self.down, open_down),
        );
        let face = _mm_blendv_ps(face_down, face_up, self.up);
        let t = _mm_mul_ps(_mm_sub_ps(face, self.origin), self.inv_d);
        let t = _mm_blendv_ps(_mm_set1_ps(f32::INFINITY), t, open);
        let m = _mm_min_ps(t, _mm_shuffle_ps::<0b01_00_11_10>(t, t));
        let m = _mm_min_ps(m, _mm_shuffle_ps::<0b10_11_00_01>(m, m));
        _mm_cvtss_f32(m)
    }
}

/// `first_index_from` with its ceiling taken by `roundss` (SSE 4.1), which baseline x86-64
/// lacks: the same index for every `t` (a ceiling is exact; where it gives −0 for a value in
/// (−1, 0) the scalar one gives +0, and both are index 0).
#[inline]
#[target_feature(enable = "sse4.1")]
pub(super) fn first_index_from(plan: &StepPlan, t: f32, inv_dt: f32) -> u32 {
    first_index_with(plan, t, inv_dt, |x| {
        let v = _mm_set_ss(x);
        _mm_cvtss_f32(_mm_ceil_ss(v, v))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::step::StepPlan;
    use crate::transfer::TransferFunction;
    use crate::volume::{Volume, VoxelData};
    use glam::UVec3;
    use proptest::prelude::*;

    /// A component of a direction: often exactly zero (axis-parallel rays), else anything.
    fn component() -> impl Strategy<Value = f32> {
        prop_oneof![Just(0.0f32), Just(-0.0f32), -1f32..1.0]
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        /// `look` and `exit` give the scalar brick and leap for random volumes with sparse
        /// visible voxels, rays from inside and around them, and every distance a brick has.
        #[test]
        fn looks_and_leaps_agree_with_the_scalar_ones(
            dims in proptest::array::uniform3(1u32..40),
            seed in any::<u64>(),
            origin in proptest::array::uniform3(-10f32..50.0),
            dir in proptest::array::uniform3(component()),
            ts in proptest::collection::vec(-5f32..80.0, 16),
        ) {
            prop_assume!(std::arch::is_x86_feature_detected!("sse4.1"));
            let d_v = Vec3::from(dir);
            prop_assume!(d_v.length() > 1e-3);
            let n = (dims[0] * dims[1] * dims[2]) as usize;
            let mut state = seed | 1;
            let data = (0..n)
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    if state % 23 == 0 { 200u8 } else { 0 }
                })
                .collect();
            let v = Volume::new("t", UVec3::from(dims), Vec3::ONE, VoxelData::U8(data)).unwrap();
            let tf = TransferFunction::ramp(100.0, 200.0, 1.0).unwrap();
            let cells = VisibleCells::new(&v, &tf.bake(0.0, 255.0));
            let size = Vec3::from_array(dims.map(|n| n as f32));
            let (last, max_lo) = (size - 1.0, (size - 2.0).max(Vec3::ZERO));
            let (o_v, inv_d) = (Vec3::from(origin), 1.0 / d_v);
            let ahead = cells.forward_distances(crate::skip::octant(d_v));
            // SAFETY: SSE 4.1 checked above.
            let leaps = unsafe { Leaps::new(&cells, (o_v, d_v, inv_d), (last, max_lo)) };
            for t in ts {
                let x = (o_v + d_v * t).max(Vec3::ZERO).min(last).min(max_lo);
                let lo = [x.x as usize, x.y as usize, x.z as usize];
                // SAFETY: SSE 4.1.
                let look = unsafe { leaps.look(t) };
                prop_assert_eq!(look.index, cells.brick_of(lo));
                for distance in [ahead[look.index], 1, 2, 3, 7, 40, 255] {
                    // SAFETY: SSE 4.1.
                    let fast = unsafe { leaps.exit(&look, distance) };
                    let slow = cells.leap_exit_at(lo, distance, o_v, inv_d);
                    prop_assert_eq!(fast.to_bits(), slow.to_bits(), "{} {} {:?}", t, distance, lo);
                }
            }
        }
    }

    #[test]
    fn first_index_agrees_with_the_scalar_one() {
        if !std::arch::is_x86_feature_detected!("sse4.1") {
            return;
        }
        let plan = StepPlan {
            t_enter: 0.75,
            t_exit: 40.0,
            dt: 0.5,
            jitter: 0.25,
            count: 79,
            capped: false,
        };
        let inv_dt = 1.0 / plan.dt;
        let mut t = -3.0f32;
        while t < 45.0 {
            for t in [
                t,
                f32::from_bits(t.to_bits() + 1),
                -0.0,
                f32::NAN,
                f32::INFINITY,
            ] {
                // SAFETY: SSE 4.1 checked above.
                let fast = unsafe { first_index_from(&plan, t, inv_dt) };
                assert_eq!(fast, crate::step::first_index_from(&plan, t, inv_dt), "{t}");
            }
            t += 0.0625;
        }
    }
}
