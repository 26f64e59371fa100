//! Random scenes shared by the tests that compare a fast march with the plain one: volumes
//! shaped like scans (structure in empty space) of every integer type, and cameras outside,
//! along an axis, inside and orthographic.
#![allow(dead_code)]

use proptest::prelude::*;
use voxcast_core::camera::{Camera, Projection};
use voxcast_core::glam::{UVec3, Vec3};
use voxcast_core::{Volume, VoxelData};

/// Blobs of high values on a low, noisy background, as one of the integer types, maybe
/// rescaled: empty space around structure, as in a scan.
pub fn volume() -> impl Strategy<Value = voxcast_core::Prepared> {
    (
        (2u32..40, 1u32..40, 1u32..40),
        proptest::collection::vec((0f32..1.0, 0f32..1.0, 0f32..1.0, 1f32..12.0), 0..4),
        0u8..3,
        prop_oneof![
            Just((1.0f32, 0.0f32)),
            Just((0.5, -20.0)),
            Just((-2.0, 100.0))
        ],
        proptest::array::uniform3(0.3f32..3.0),
        any::<u64>(),
    )
        .prop_map(
            |((x, y, z), blobs, kind, (slope, intercept), spacing, seed)| {
                let mut noise = seed | 1;
                let mut values = Vec::with_capacity((x * y * z) as usize);
                for k in 0..z {
                    for j in 0..y {
                        for i in 0..x {
                            noise ^= noise << 13;
                            noise ^= noise >> 7;
                            noise ^= noise << 17;
                            let p = Vec3::new(i as f32, j as f32, k as f32);
                            let mut v = (noise % 20) as f32;
                            for &(a, b, c, r) in &blobs {
                                let centre = Vec3::new(a * x as f32, b * y as f32, c * z as f32);
                                let d = (p - centre).length() / r;
                                v += 200.0 * (1.0 - d).max(0.0);
                            }
                            values.push(v);
                        }
                    }
                }
                let data = match kind {
                    0 => VoxelData::U8(values.iter().map(|v| v.min(255.0) as u8).collect()),
                    1 => VoxelData::I16(values.iter().map(|v| (v * 9.0 - 900.0) as i16).collect()),
                    _ => VoxelData::U16(values.iter().map(|v| (v * 5.0) as u16).collect()),
                };
                Volume::with_rescale(
                    "blobs",
                    UVec3::new(x, y, z),
                    Vec3::from(spacing),
                    data,
                    slope,
                    intercept,
                )
                .unwrap()
                .into()
            },
        )
}

/// A camera around the volume (from an axis now and then: axis-parallel rays), inside it, or
/// orthographic from anywhere (its image plane may cut the volume).
pub fn camera(v: &Volume, kind: u8, a: Vec3, b: Vec3) -> Option<Camera> {
    let (lo, hi) = v.bounds();
    match kind {
        3 => Camera::new(
            lo + (hi - lo) * (a * 3.0 - 1.0),
            lo + (hi - lo) * b,
            Vec3::Y,
            Projection::Orthographic {
                height: (hi - lo).length(),
            },
        )
        .ok(),
        0 => Camera::framing(lo, hi, a - 0.5, Vec3::Y).ok(),
        1 => {
            let axis = [Vec3::X, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_X][(a.x * 3.99) as usize];
            let up = if axis.y != 0.0 { Vec3::Z } else { Vec3::Y };
            Camera::framing(lo, hi, axis, up).ok()
        }
        _ => {
            let eye = lo + (hi - lo) * a;
            let target = lo + (hi - lo) * b;
            Camera::new(
                eye,
                target,
                Vec3::Y,
                Projection::Perspective { fov_y_deg: 70.0 },
            )
            .ok()
        }
    }
}

/// The instructions this CPU runs the lanes with, at their widest and narrowed
/// (`Vectors::Narrow`); `None` where it runs none.
pub fn instructions() -> (Option<&'static str>, Option<&'static str>) {
    #[cfg(target_arch = "x86_64")]
    {
        let narrow = std::arch::is_x86_feature_detected!("sse4.1").then_some("SSE 4.1");
        let wide = std::arch::is_x86_feature_detected!("avx2").then_some("AVX2");
        (wide.or(narrow), narrow)
    }
    #[cfg(target_arch = "aarch64")]
    return (Some("NEON"), Some("NEON"));
    #[cfg(all(lanes, target_arch = "wasm32"))]
    return (Some("WebAssembly SIMD"), Some("WebAssembly SIMD"));
    #[cfg(not(lanes))]
    (None, None)
}
