//! Criterion benchmark of the ray-density grid (issue 12's goal: a million rays through a
//! 128³-cell grid in under a second on 2 cores), reported as rays per second; the cell visits
//! a run makes are printed once, for cell visits per second. Two sets: random rays in a box
//! (below), and the Cornell box's five traces at 400 × 400 primary rays per camera (about 1.2
//! million rays in all), traced by the brute-force triangle tracer (measured too, in rays per second)
//! and counted through cells of 560/128 mm — 128 cells across the box.
//!
//! The rays are seeded and reproducible: origins uniform in a 128-unit box, directions uniform
//! on the sphere, each ray hitting after a uniform fraction of the box's diagonal or missing at
//! the box's far side — segments of about 60 cells of edge 1 on average.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::sync::atomic::AtomicBool;
use voxcast_core::glam::Vec3;
use voxcast_core::rays::density::{Density, DensityParams, compute};
use voxcast_core::rays::set::{RayRecord, RaySet};

const RAYS: u32 = 1_000_000;
const EDGE: f32 = 128.0;

fn rays() -> RaySet {
    let mut s = 0x9e37_79b9u32;
    let mut next = || {
        s ^= s << 13;
        s ^= s >> 17;
        s ^= s << 5;
        (s >> 8) as f32 / (1u32 << 24) as f32
    };
    let rays = (0..RAYS)
        .map(|id| {
            let origin = Vec3::new(next(), next(), next()) * EDGE;
            let z = 2.0 * next() - 1.0;
            let a = std::f32::consts::TAU * next();
            let r = (1.0 - z * z).max(0.0).sqrt();
            let direction = Vec3::new(r * a.cos(), r * a.sin(), z);
            // Where the ray leaves the box: the miss's t_max.
            let exit = (0..3)
                .map(|i| {
                    let d = direction[i];
                    if d > 0.0 {
                        (EDGE - origin[i]) / d
                    } else if d < 0.0 {
                        -origin[i] / d
                    } else {
                        f32::INFINITY
                    }
                })
                .fold(f32::INFINITY, f32::min);
            let hit = next() < 0.6;
            RayRecord {
                id,
                origin,
                direction,
                t_min: 0.0,
                t_max: exit,
                t_hit: if hit { exit * next() } else { -1.0 },
            }
        })
        .collect();
    RaySet { trace_id: 0, rays }
}

/// Prints what one computation made, once: for cell visits per second and the memory.
fn report(group: &str, what: &str, rays: u64, d: &Density) {
    println!(
        "{group}: {rays} {what}, {} cell visits, {} chunks stored ({} MiB; dense {} MiB)",
        d.report.visits,
        d.chunks.len(),
        d.memory_bytes() >> 20,
        d.dense_bytes() >> 20
    );
}

fn density(c: &mut Criterion) {
    let set = rays();
    let params = DensityParams {
        cell: 1.0,
        chunk: 16,
        ..Default::default()
    };
    let once = compute(&set, &params, &|_, _| {}, &AtomicBool::new(false)).unwrap();
    report("ray density", "rays", once.report.rays as u64, &once);
    let mut g = c.benchmark_group("ray_density");
    g.sample_size(10);
    g.throughput(Throughput::Elements(u64::from(RAYS)));
    g.bench_function("1M rays, 128³ cells of 1, chunks of 16", |b| {
        b.iter(|| compute(&set, &params, &|_, _| {}, &AtomicBool::new(false)).unwrap())
    });
    g.finish();
}

fn cornell(c: &mut Criterion) {
    use voxcast_core::rays::cornell;
    use voxcast_core::rays::data::RayData;
    use voxcast_core::rays::effects::{camera, trace_effects};
    use voxcast_core::rays::source::CORNELL_1M;
    let scene = cornell::scene();
    let cam = camera(
        cornell::CAMERA_EYE,
        cornell::CAMERA_TARGET,
        cornell::CAMERA_FOV_Y_DEG,
    )
    .unwrap();
    let p = CORNELL_1M;
    let second = cornell::second_camera();
    let traces = trace_effects(&scene, [&cam, &second], &p);
    let data = RayData {
        description: String::new(),
        scene: scene.clone(),
        traces,
    };
    let all = data.all_rays();
    let rays = all.rays.len() as u64;
    let params = DensityParams {
        cell: 560.0 / 128.0,
        chunk: 16,
        ..Default::default()
    };
    let once = compute(&all, &params, &|_, _| {}, &AtomicBool::new(false)).unwrap();
    report("cornell", "rays traced and counted", rays, &once);
    let mut g = c.benchmark_group("cornell");
    g.sample_size(10);
    g.throughput(Throughput::Elements(rays));
    g.bench_function(
        "trace the study's 5 traces, 2 x 400x400 primary rays, 30 triangles",
        |b| b.iter(|| trace_effects(&scene, [&cam, &second], &p)),
    );
    g.bench_function("density of every trace, 128 cells across the box", |b| {
        b.iter(|| compute(&all, &params, &|_, _| {}, &AtomicBool::new(false)).unwrap())
    });
    // The ray mesh of every ray, drawn on the CPU as the CPU live view draws it, from the
    // box's camera, at the viewports of a 640×360 and a 1280×720 window.
    use voxcast_core::rays::lines::{LineParams, padded, ray_lines};
    use voxcast_core::rays::raster::{LineImage, Lines, draw_lines};
    use voxcast_core::rays::set::Filter;
    let lines = ray_lines(
        &all,
        &LineParams {
            filter: Filter::All,
            tolerance: 0.0,
            stride: 1,
            clip: padded(scene.bounds().unwrap(), 0.5),
        },
    );
    let positions: Vec<[f32; 3]> = lines
        .lines
        .iter()
        .flat_map(|l| [l.from.to_array(), l.to.to_array()])
        .collect();
    let colours = vec![[1.0, 0.6, 0.2, 1.0]; positions.len()];
    let view = voxcast_core::camera::Camera::new(
        cornell::CAMERA_EYE,
        cornell::CAMERA_TARGET,
        voxcast_core::glam::Vec3::Y,
        voxcast_core::camera::Projection::Perspective {
            fov_y_deg: cornell::CAMERA_FOV_Y_DEG,
        },
    )
    .unwrap();
    let list = Lines {
        positions: &positions,
        colours: &colours,
        offset: voxcast_core::glam::Vec3::ZERO,
        every: 1,
    };
    g.throughput(Throughput::Elements(lines.lines.len() as u64));
    for (w, h) in [(300, 200), (880, 620)] {
        g.bench_function(format!("ray mesh, every ray, drawn at {w}x{h}"), |b| {
            b.iter(|| {
                let mut image = LineImage::new(w, h);
                draw_lines(&mut image, &view, &list)
            })
        });
    }
    g.finish();
}

criterion_group!(benches, density, cornell);
criterion_main!(benches);
