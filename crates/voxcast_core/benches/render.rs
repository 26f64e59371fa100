//! Criterion benchmarks of the CPU ray caster, reported as samples per second.
//!
//! * `one_ray`: one recorded ray (the inspector's breakdown) and one plain ray through the head.
//! * `ct_512`: the 512×512 render of ct_cranium with the peer's camera and the ct_skin_bone
//!   transfer function (or ct_gray for the projections, as the peer does), step 0.5 voxel, for
//!   every method. Throughput counts sample positions along the rays (skipped empty space
//!   included), so the figure is comparable with a caster that does not skip.
//!
//! * `render_image`: what the sandbox's Render image marches for the embedded bunny at the
//!   page's scene size (896×669, its preset): the picture alone, the picture and then its cost
//!   map (two marches, as before), and both from one march (`render_with_cost_in`).
//!
//! * `peer_scenes`: the four shared volumes as `voxcast bench --peer` renders them beside VTK
//!   (the peer's camera, the volume's own preset, 512×512, step 0.5 voxel, all cores) — the
//!   scenes issue 13's ratios are measured on; those absent are left out with a note. Each
//!   with the widest lanes this CPU has, with the narrow ones (`_narrow`: SSE 4.1, as an x86-64
//!   without AVX; NEON on ARM) and with none (`_one_at_a_time`).
//!
//! ct_cranium is read from `$VOXCAST_DATA` or `../shared/data`; without it the embedded
//! brainsmall volume stands in (and the benchmark names say so).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;
use voxcast_core::builtin::load_builtin;
use voxcast_core::camera::Camera;
use voxcast_core::composite::Method;
use voxcast_core::glam::Vec3;
use voxcast_core::io::load;
use voxcast_core::preset;
use voxcast_core::render::render;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::trace::{Scene, Vectors, trace_ray};
use voxcast_core::transfer::TransferFunction;

struct Inputs {
    name: &'static str,
    volume: voxcast_core::Prepared,
    camera: Camera,
    composite: (TransferFunction, RenderSettings),
    projection: TransferFunction,
}

fn inputs() -> Inputs {
    // The clone's root, two folders above this crate.
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let data = std::env::var_os("VOXCAST_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("../shared/data"));
    let cams = root.join("../shared/tools/peer/cams");
    let ct = data.join("ct_cranium.nrrd");
    let (name, volume, camera) = if ct.exists() {
        let camera =
            Camera::from_json(&std::fs::read_to_string(cams.join("ct_cranium.json")).unwrap())
                .unwrap();
        ("ct_cranium", load(&ct).unwrap().volume, camera)
    } else {
        eprintln!(
            "note: {} not found; benchmarking the embedded brainsmall instead",
            ct.display()
        );
        let v = load_builtin("brainsmall").unwrap().volume;
        let (lo, hi) = v.bounds();
        let camera =
            Camera::framing(lo, hi, Vec3::new(-138.5, -166.0, 166.0), Vec3::NEG_Y).unwrap();
        ("brainsmall", v, camera)
    };
    let p = preset::for_volume(volume.name()).unwrap();
    let mut settings = p.settings_over(&RenderSettings::default()).unwrap();
    settings.step = Length::Voxels(0.5);
    let (lo, hi) = volume.value_range();
    // The peer's grey ramp for projections (ct_gray: black at −200, white at 1500, opaque).
    let projection = if name == "ct_cranium" {
        TransferFunction::new(
            "ct_gray",
            vec![
                voxcast_core::transfer::ControlPoint::new(-200.0, [0.0; 3], 1.0),
                voxcast_core::transfer::ControlPoint::new(1500.0, [1.0; 3], 1.0),
            ],
        )
        .unwrap()
    } else {
        TransferFunction::ramp(lo, hi, 1.0).unwrap()
    };
    Inputs {
        name,
        volume: volume.into(),
        camera,
        composite: (p.transfer, settings),
        projection,
    }
}

fn benches(c: &mut Criterion) {
    let inp = inputs();
    let (tf, base) = &inp.composite;
    let (w, h) = (512, 512);

    let mut g = c.benchmark_group("one_ray");
    let scene = Scene::new(&inp.volume, tf, base, inp.camera.forward()).unwrap();
    let ray = inp.camera.pixel_ray(w / 2, h / 2, w, h);
    let positions = trace_ray(&scene, &ray, [0, 0]).samples.len() as u64;
    g.throughput(Throughput::Elements(positions.max(1)));
    g.bench_function(format!("{}_recorded", inp.name), |b| {
        b.iter(|| trace_ray(&scene, &ray, [0, 0]))
    });
    g.finish();

    let mut g = c.benchmark_group("ct_512");
    g.sample_size(10);
    for method in Method::ALL {
        let mut s = base.clone();
        s.method = method;
        let transfer = if matches!(method, Method::Average | Method::Maximum | Method::Minimum) {
            &inp.projection
        } else {
            tf
        };
        if matches!(method, Method::Average | Method::Maximum | Method::Minimum) {
            s.shading = false;
        }
        let scene = Scene::new(&inp.volume, transfer, &s, inp.camera.forward()).unwrap();
        let cancel = AtomicBool::new(false);
        let (_, stats) = render(&scene, &inp.camera, w, h, &|_, _| {}, &cancel).unwrap();
        g.throughput(Throughput::Elements(stats.positions));
        g.bench_function(format!("{}_{}", inp.name, method.name()), |b| {
            b.iter(|| render(&scene, &inp.camera, w, h, &|_, _| {}, &cancel).unwrap())
        });
    }
    g.finish();
}

fn render_image(c: &mut Criterion) {
    use voxcast_core::cost::{render_cost, render_with_cost_in};
    use voxcast_core::render::{Job, TileSlices};
    use voxcast_core::slices::{Deadline, Step};
    let volume = voxcast_core::Prepared::from(load_builtin("bunny").unwrap().volume);
    let p = preset::for_volume(volume.name()).unwrap();
    let s = p.settings_over(&RenderSettings::default()).unwrap();
    let view = p.view.unwrap();
    let (lo, hi) = volume.bounds();
    let camera = Camera::framing(lo, hi, view.from, view.up).unwrap();
    let scene = Scene::new(&volume, &p.transfer, &s, camera.forward()).unwrap();
    let (w, h) = (896, 669);
    let cancel = AtomicBool::new(false);
    let (_, stats) = render(&scene, &camera, w, h, &|_, _| {}, &cancel).unwrap();
    let mut g = c.benchmark_group("render_image");
    g.sample_size(10);
    // The picture's positions, whatever else is kept of them.
    g.throughput(Throughput::Elements(stats.positions));
    g.bench_function("bunny_picture", |b| {
        b.iter(|| render(&scene, &camera, w, h, &|_, _| {}, &cancel).unwrap())
    });
    g.bench_function("bunny_picture_then_cost_map", |b| {
        b.iter(|| {
            let picture = render(&scene, &camera, w, h, &|_, _| {}, &cancel).unwrap();
            let cost = render_cost(&scene, &camera, (w, h), &|_, _| {}, &cancel).unwrap();
            (picture, cost)
        })
    });
    g.bench_function("bunny_picture_and_cost_map_one_march", |b| {
        b.iter(|| {
            let job = Job::plain(&scene, &camera, (w, h), &|_, _| {}, &cancel);
            render_with_cost_in(&job, &mut TileSlices::default(), Deadline::NONE)
                .map(Step::whole)
                .unwrap()
        })
    });
    g.finish();
}

/// The shared volumes with their peer camera files.
const PEER_SCENES: [(&str, &str); 4] = [
    ("ct_cranium", "ct_cranium.nrrd"),
    ("mri_mni152", "mri_mni152.nii.gz"),
    ("mri_brainsmall", "mri_brainsmall.nrrd"),
    ("bunny_sdf", "bunny_sdf.nrrd"),
];

fn peer_scenes(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let data = std::env::var_os("VOXCAST_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("../shared/data"));
    let cams = root.join("../shared/tools/peer/cams");
    let mut g = c.benchmark_group("peer_scenes");
    g.sample_size(10);
    for (name, file) in PEER_SCENES {
        let (path, cam) = (data.join(file), cams.join(format!("{name}.json")));
        if !path.exists() || !cam.exists() {
            eprintln!(
                "note: {} or {} not found; {name} left out",
                path.display(),
                cam.display()
            );
            continue;
        }
        let volume = voxcast_core::Prepared::from(load(&path).unwrap().volume);
        let camera = Camera::from_json(&std::fs::read_to_string(cam).unwrap()).unwrap();
        let p = preset::for_volume(volume.name()).unwrap();
        let mut settings = p.settings_over(&RenderSettings::default()).unwrap();
        settings.step = Length::Voxels(0.5);
        let mut scene = Scene::new(&volume, &p.transfer, &settings, camera.forward()).unwrap();
        let cancel = AtomicBool::new(false);
        let (_, stats) = render(&scene, &camera, 512, 512, &|_, _| {}, &cancel).unwrap();
        g.throughput(Throughput::Elements(stats.samples));
        for (vectors, suffix) in [
            (Vectors::Wide, ""),
            (Vectors::Narrow, "_narrow"),
            (Vectors::Off, "_one_at_a_time"),
        ] {
            scene.simd = vectors;
            let id = format!("{name}_{}{suffix}", settings.method.name());
            g.bench_function(id, |b| {
                b.iter(|| render(&scene, &camera, 512, 512, &|_, _| {}, &cancel).unwrap())
            });
        }
    }
    g.finish();
}

criterion_group!(render_benches, benches, render_image, peer_scenes);
criterion_main!(render_benches);
