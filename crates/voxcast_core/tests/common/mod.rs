//! Shared builders for the core's integration tests: small volumes, transfer functions, scenes.
#![allow(dead_code)]

use voxcast_core::glam::{UVec3, Vec3};
use voxcast_core::ray::Ray;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::trace::{RayTrace, Scene, trace_ray};
use voxcast_core::transfer::{ControlPoint, TransferFunction};
use voxcast_core::{Prepared, Volume, VoxelData};

/// The six axis directions.
pub const AXES: [Vec3; 6] = [
    Vec3::X,
    Vec3::NEG_X,
    Vec3::Y,
    Vec3::NEG_Y,
    Vec3::Z,
    Vec3::NEG_Z,
];

/// A float volume of `dims` with unit spacing whose value at lattice point `(i, j, k)` is `f`,
/// ready to render.
pub fn field(dims: [u32; 3], spacing: Vec3, f: impl Fn(Vec3) -> f32) -> Prepared {
    let mut data = Vec::with_capacity((dims[0] * dims[1] * dims[2]) as usize);
    for k in 0..dims[2] {
        for j in 0..dims[1] {
            for i in 0..dims[0] {
                data.push(f(Vec3::new(i as f32, j as f32, k as f32)));
            }
        }
    }
    Volume::new("field", UVec3::from(dims), spacing, VoxelData::F32(data))
        .unwrap()
        .into()
}

/// A constant volume.
pub fn constant(dims: [u32; 3], value: f32) -> Prepared {
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
    volume: &Prepared,
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

/// Cut, corrupted and lengthened copies of each file (name, bytes) load with an error (or, for
/// trailing data gzip allows, at least without a panic).
pub fn damaged_copies_fail_cleanly(files: Vec<(String, Vec<u8>)>) {
    let dir = std::env::temp_dir().join(format!("voxcast-damaged-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, bytes: &[u8]| {
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    };
    for (name, bytes) in files {
        for cut in [10, 200, bytes.len() / 2, bytes.len() - 9] {
            let p = write(&format!("cut{cut}_{name}"), &bytes[..cut]);
            assert!(
                voxcast_core::io::load(&p).is_err(),
                "{name} cut at {cut} bytes loaded"
            );
        }
        // Flipped bytes in the compressed stream: an error or (if the checksum is all that
        // breaks) an error too, never a panic.
        let mut bad = bytes.clone();
        let n = bad.len();
        for i in (n / 2..n / 2 + 64).step_by(7) {
            bad[i] ^= 0x5a;
        }
        let p = write(&format!("flipped_{name}"), &bad);
        assert!(
            voxcast_core::io::load(&p).is_err(),
            "{name} with corrupt data loaded"
        );
        // Appended garbage.
        let mut long = bytes.clone();
        long.extend_from_slice(&[1, 2, 3, 4]);
        let p = write(&format!("long_{name}"), &long);
        let _ = voxcast_core::io::load(&p); // gzip allows trailing data; what matters is no panic
    }
}
