//! Shared builders for the core's integration tests: small volumes, transfer functions, scenes.
#![allow(dead_code)]

use voxcast_core::glam::{UVec3, Vec3};
use voxcast_core::ray::Ray;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::trace::{RayTrace, Scene, trace_ray};
use voxcast_core::transfer::{ControlPoint, TransferFunction};
use voxcast_core::{Volume, VoxelData};

/// The six axis directions.
pub const AXES: [Vec3; 6] = [
    Vec3::X,
    Vec3::NEG_X,
    Vec3::Y,
    Vec3::NEG_Y,
    Vec3::Z,
    Vec3::NEG_Z,
];

/// A float volume of `dims` with unit spacing whose value at lattice point `(i, j, k)` is `f`.
pub fn field(dims: [u32; 3], spacing: Vec3, f: impl Fn(Vec3) -> f32) -> Volume {
    let mut data = Vec::with_capacity((dims[0] * dims[1] * dims[2]) as usize);
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                data.push(f(Vec3::new(i as f32, j as f32, k as f32)));
            }
        }
    }
    Volume::new("field", UVec3::from(dims), spacing, VoxelData::F32(data)).unwrap()
}

/// A constant volume.
pub fn constant(dims: [u32; 3], value: f32) -> Volume {
    field(dims, Vec3::ONE, |_| value)
}

/// White everywhere with opacity `alpha` per reference step.
pub fn white(alpha: f32) -> TransferFunction {
    TransferFunction::constant([1.0; 3], alpha).unwrap()
}

/// Grey ramp: value `lo` → black, `hi` → white, opacity `alpha` everywhere.
pub fn grey(lo: f32, hi: f32, alpha: f32) -> TransferFunction {
    TransferFunction::new(
        "grey",
        vec![
            ControlPoint::new(lo, [0.0; 3], alpha),
            ControlPoint::new(hi, [1.0; 3], alpha),
        ],
    )
    .unwrap()
}

/// Settings for closed-form checks: no early termination, no jitter, no shading, black
/// background, and the given step in voxels.
pub fn plain(step_voxels: f32) -> RenderSettings {
    RenderSettings {
        step: Length::Voxels(step_voxels),
        early_termination: false,
        shading: false,
        ..RenderSettings::default()
    }
}

/// Traces one ray from `origin` along `dir` (world units).
pub fn trace(
    volume: &Volume,
    tf: &TransferFunction,
    settings: &RenderSettings,
    origin: Vec3,
    dir: Vec3,
) -> RayTrace {
    let ray = Ray::new(origin, dir).expect("valid ray");
    let scene = Scene::new(volume, tf, settings, ray.dir).expect("valid settings");
    trace_ray(&scene, &ray, [0, 0])
}

/// `|a − b| ≤ tol`, with a message.
#[track_caller]
pub fn close(a: f32, b: f32, tol: f32, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b} (tolerance {tol})");
}
