//! Criterion benchmark of the ray-density view (`voxcast rays render`, the sandbox's density):
//! the Cornell box's shadow rays counted through 128 cells across the box, marched with Sum at
//! 2 samples per cell for a 256 × 256 view from the box's camera — over the grey scene (rays
//! stop at the walls: RayVis's shortened maxT), and with the scene hidden (rays cross the whole
//! grid) — and the range fit (a 32 × 32 grid of recorded rays). Reported per render; the
//! samples each render interpolates are printed once, for samples per second.
//!
//! Lives in the core so that it builds without the sandbox (`cargo bench -p voxcast_core`).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::sync::atomic::AtomicBool;
use voxcast_core::camera::{Camera, Projection};
use voxcast_core::colormap::inferno_transfer;
use voxcast_core::composite::Method;
use voxcast_core::glam::Vec3;
use voxcast_core::rays::cornell;
use voxcast_core::rays::density::{DensityParams, compute};
use voxcast_core::rays::grid::DenseDensity;
use voxcast_core::rays::layered::{DensityView, SceneShading};
use voxcast_core::rays::source::load;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::trace::Scene;

const SIZE: (u32, u32) = (256, 256);

fn bench(c: &mut Criterion) {
    let data = load("builtin:cornell").unwrap();
    let shadow = data.trace(1).unwrap();
    let p = DensityParams {
        cell: 560.0 / 128.0,
        ..DensityParams::default()
    };
    let never = AtomicBool::new(false);
    let density = compute(shadow, &p, &|_, _| {}, &never).unwrap();
    let dense = DenseDensity::new(&density).unwrap().unwrap();
    let volume = voxcast_core::Prepared::from(dense.to_volume().unwrap());
    let (lo, hi) = volume.value_range();
    let tf = inferno_transfer(lo, hi);
    let camera = Camera::new(
        cornell::CAMERA_EYE,
        cornell::CAMERA_TARGET,
        Vec3::Y,
        Projection::Perspective {
            fov_y_deg: cornell::CAMERA_FOV_Y_DEG,
        },
    )
    .unwrap();
    let settings = RenderSettings {
        method: Method::Sum,
        step: Length::Voxels(0.5),
        sum_range: Some((0.0, 3000.0)),
        early_termination: false,
        jitter: false,
        ..RenderSettings::default()
    };
    let scene = Scene::new(&volume, &tf, &settings, camera.forward()).unwrap();
    let origin = dense.origin();
    let mut g = c.benchmark_group("density_view");
    g.sample_size(10);
    g.throughput(Throughput::Elements(u64::from(SIZE.0 * SIZE.1)));
    for shading in [SceneShading::Grey, SceneShading::Hidden] {
        let view = DensityView {
            volume_scene: &scene,
            origin,
            triangles: &data.scene,
            shading,
            camera: &camera,
        };
        let run = || view.render(SIZE, &|_, _| {}, &never).unwrap();
        let (_, stats) = run();
        println!(
            "{} cells, {} scene: {} samples per 256² render",
            volume.voxel_count(),
            shading.name(),
            stats.samples
        );
        g.bench_function(format!("sum_256_{}", shading.name()), |b| b.iter(run));
    }
    let view = DensityView {
        volume_scene: &scene,
        origin,
        triangles: &data.scene,
        shading: SceneShading::Grey,
        camera: &camera,
    };
    g.bench_function("fit_range_32", |b| b.iter(|| view.fit_sum_range(SIZE)));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
