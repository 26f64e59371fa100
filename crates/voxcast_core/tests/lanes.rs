//! The eight-lane Accumulate march (`trace/lanes.rs`), with AVX2's vectors and with SSE 4.1's
//! (`--narrow-lanes`), renders the scalar march's pixels bit for bit, with the same sample counts: over random volumes of every integer type (with
//! and without a rescale), transfer functions, lights, shading models, steps and cameras —
//! outside, inside, axis-parallel — and at the extremes (thin volumes, huge and tiny steps,
//! empty and all-opaque tables, a light straight behind the viewer).
//!
//! On a CPU without AVX2 (or SSE 4.1) those renders take the narrower lanes (or the scalar
//! march); the tests then say so and compare what there is. On 64-bit ARM both widths are
//! NEON's (`.ci/run` runs this file there under qemu).

mod scenes;
// In WebAssembly (`.ci/run`), each `#[test]` is one of wasm-bindgen's, run under Node.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use proptest::prelude::*;
use scenes::{camera, instructions, volume};
use voxcast_core::camera::Camera;
use voxcast_core::composite::Method;
use voxcast_core::glam::{UVec3, Vec3};
use voxcast_core::render::{RenderStats, render_with_threads};
use voxcast_core::settings::RenderSettings;
use voxcast_core::shade::{Highlight, Light, LightSource, Phong, SpecularModel};
use voxcast_core::step::Length;
use voxcast_core::trace::{Scene, Vectors, lane_instructions, uses_lanes};
use voxcast_core::transfer::{ControlPoint, TransferFunction};
use voxcast_core::{Volume, VoxelData};

/// Renders `scene` with the widest lanes, the narrow ones and none; the images and stats.
fn renders(scene: &Scene<'_>, camera: &Camera, w: u32, h: u32) -> [(Vec<Vec3>, RenderStats); 3] {
    [Vectors::Wide, Vectors::Narrow, Vectors::Off].map(|v| {
        let mut s = scene.clone();
        s.simd = v;
        let (image, stats) = render_with_threads(&s, camera, w, h, 1).unwrap();
        (image.pixels, stats)
    })
}

/// Control points spread over the volume's value range, with transparent stretches.
fn transfer(v: &Volume, points: &[(f32, [f32; 3], f32)]) -> TransferFunction {
    let (lo, hi) = v.value_range();
    let points = points
        .iter()
        .map(|&(f, c, a)| ControlPoint::new(lo + f * (hi - lo), c, a))
        .collect();
    TransferFunction::new("random", points).unwrap()
}

fn points() -> impl Strategy<Value = Vec<(f32, [f32; 3], f32)>> {
    proptest::collection::vec(
        (
            0f32..=1.0,
            proptest::array::uniform3(0f32..=1.0),
            prop_oneof![Just(0.0f32), Just(1.0), 0f32..1.0],
        ),
        1..6,
    )
}

/// Shading as a user may set it: one to four lights, directional or the headlight (a point
/// light now and then, which the lanes leave to the scalar march), either model and highlight.
fn phong() -> impl Strategy<Value = Phong> {
    (
        proptest::collection::vec(
            (
                0u8..6,
                proptest::array::uniform3(-1f32..1.0),
                proptest::array::uniform3(0f32..=1.0),
            ),
            1..=4,
        ),
        proptest::array::uniform3(0f32..=1.0),
        prop_oneof![Just(1.0f32), Just(10.0), Just(64.0), 1f32..40.0],
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        prop_oneof![Just(0.0f32), 0f32..2.0],
    )
        .prop_map(
            |(lights, [ka, kd, ks], shininess, phong, levoy, two_sided, threshold)| Phong {
                ka,
                kd,
                ks,
                shininess,
                model: if phong {
                    SpecularModel::Phong
                } else {
                    SpecularModel::BlinnPhong
                },
                highlight: if levoy {
                    Highlight::Levoy
                } else {
                    Highlight::White
                },
                two_sided,
                gradient_threshold: threshold,
                lights: lights
                    .into_iter()
                    .map(|(kind, dir, color)| LightSource {
                        color: Vec3::from(color),
                        ..LightSource::new(match kind {
                            0 => Light::Point(Vec3::from(dir) * 50.0),
                            1 | 2 => Light::Headlight,
                            _ => Light::Directional(Vec3::from(dir)),
                        })
                    })
                    .filter(|l| match l.light {
                        Light::Directional(d) => d.length() > 1e-3,
                        _ => true,
                    })
                    .collect(),
                ..Phong::default()
            },
        )
}

fn settings() -> impl Strategy<Value = RenderSettings> {
    (
        // Steps of ½, 1 and 2 reference steps: the lanes correct opacity a batch at a time.
        prop_oneof![
            3 => 0.1f32..3.0,
            1 => Just(0.02f32),
            1 => Just(40.0f32),
            2 => prop_oneof![Just(0.5f32), Just(1.0), Just(2.0)]
        ],
        any::<bool>(),
        any::<bool>(),
        prop_oneof![Just(0.99f32), 0f32..=1.0],
        any::<bool>(),
        phong(),
    )
        .prop_map(
            |(step, correction, early, cutoff, jitter, phong)| RenderSettings {
                method: Method::Accumulate,
                step: Length::Voxels(step),
                opacity_correction: correction,
                early_termination: early,
                cutoff,
                jitter,
                shading: true,
                phong,
                max_samples: 1 << 16,
                ..RenderSettings::default()
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn lanes_render_the_scalar_pixels_bit_for_bit(
        v in volume(),
        tf in points(),
        s in settings(),
        kind in 0u8..4,
        a in proptest::array::uniform3(0f32..1.0),
        b in proptest::array::uniform3(0f32..1.0),
    ) {
        let tf = transfer(&v, &tf);
        let Some(camera) = camera(&v, kind, Vec3::from(a), Vec3::from(b)) else { return Ok(()) };
        let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
        let [(lanes, ls), (narrow, ns), (scalar, ss)] = renders(&scene, &camera, 20, 15);
        prop_assert_eq!(&lanes, &scalar);
        prop_assert_eq!(&narrow, &scalar);
        prop_assert_eq!(ls, ss);
        prop_assert_eq!(ns, ss);
    }
}

/// The lanes are taken where they should be (else the test above compares the scalar march
/// with itself): the presets' scenes on a CPU with AVX2, and with SSE 4.1 when narrowed (on
/// ARM, NEON both ways).
#[test]
fn the_presets_take_the_lanes_where_the_cpu_has_avx2() {
    use voxcast_core::builtin::load_builtin;
    use voxcast_core::preset;
    let (wide, narrow) = instructions();
    if wide.is_none() {
        eprintln!("note: this CPU runs no lanes: they are not exercised here");
    }
    for name in ["bunny", "brainsmall", "head"] {
        let v = voxcast_core::Prepared::from(load_builtin(name).unwrap().volume);
        let p = preset::for_volume(v.name()).unwrap();
        let s = p.settings_over(&RenderSettings::default()).unwrap();
        let view = p.view.unwrap();
        let (lo, hi) = v.bounds();
        let camera = Camera::framing(lo, hi, view.from, view.up).unwrap();
        let scene = Scene::new(&v, &p.transfer, &s, camera.forward()).unwrap();
        if s.method == Method::Accumulate && s.shading {
            // The lanes read the precomputed records (integer volumes; the head is float).
            let records = scene.differences.is_some();
            assert_eq!(uses_lanes(&scene), wide.is_some() && records, "{name}");
            assert_eq!(records, name != "head", "{name}");
            assert_eq!(
                lane_instructions(&scene),
                wide.filter(|_| records),
                "{name}"
            );
            let mut narrowed = scene.clone();
            narrowed.simd = Vectors::Narrow;
            let taken = lane_instructions(&narrowed);
            assert_eq!(taken, narrow.filter(|_| records), "{name}");
        }
        let [(lanes, ls), (narrow, ns), (scalar, ss)] = renders(&scene, &camera, 96, 72);
        assert_eq!(lanes, scalar, "{name}");
        assert_eq!(narrow, scalar, "{name}");
        assert_eq!(ls, ss, "{name}");
        assert_eq!(ns, ss, "{name}");
        // Switched off, or for a point light, they are not.
        let mut off = scene.clone();
        off.simd = Vectors::Off;
        assert!(!uses_lanes(&off));
        let mut point = s.clone();
        point.phong.lights = vec![LightSource::new(Light::Point(hi * 2.0))];
        let scene = Scene::new(&v, &p.transfer, &point, camera.forward()).unwrap();
        assert!(!uses_lanes(&scene));
    }
}

/// The extremes: a one-voxel-thin slab, a 2×1×1 volume, a huge and a tiny step, a transparent
/// and an opaque table, and a headlight-opposite light (no half vector: the scalar march).
#[test]
fn extremes_agree() {
    let slab = voxcast_core::Prepared::from(
        Volume::new(
            "slab",
            UVec3::new(40, 30, 1),
            Vec3::ONE,
            VoxelData::U8((0..1200).map(|i| (i * 7 % 256) as u8).collect()),
        )
        .unwrap(),
    );
    let pair = voxcast_core::Prepared::from(
        Volume::new(
            "pair",
            UVec3::new(2, 1, 1),
            Vec3::ONE,
            VoxelData::U8(vec![10, 250]),
        )
        .unwrap(),
    );
    let ramp = TransferFunction::ramp(0.0, 255.0, 1.0).unwrap();
    let clear = TransferFunction::constant([1.0; 3], 0.0).unwrap();
    let opaque = TransferFunction::constant([0.8, 0.5, 0.2], 1.0).unwrap();
    for v in [&slab, &pair] {
        let (lo, hi) = v.bounds();
        for tf in [&ramp, &clear, &opaque] {
            for step in [1e-3, 0.5, 1e4] {
                for from in [Vec3::new(0.3, 0.5, 1.0), Vec3::Z, Vec3::X] {
                    let s = RenderSettings {
                        step: Length::Voxels(step),
                        max_samples: 1 << 20,
                        ..RenderSettings::default()
                    };
                    let up = if from == Vec3::X { Vec3::Z } else { Vec3::Y };
                    let camera = Camera::framing(lo, hi, from, up).unwrap();
                    let scene = Scene::new(v, tf, &s, camera.forward()).unwrap();
                    let [(a, sa), (n, sn), (b, sb)] = renders(&scene, &camera, 16, 12);
                    assert_eq!(a, b, "{} step {step} from {from}", v.name());
                    assert_eq!(n, b, "{} step {step} from {from}", v.name());
                    assert_eq!(sa, sb);
                    assert_eq!(sn, sb);
                }
            }
        }
    }
    // A light shining straight at the viewer: the scalar march derives its half vector.
    let (lo, hi) = slab.bounds();
    let camera = Camera::framing(lo, hi, Vec3::Z, Vec3::Y).unwrap();
    let mut s = RenderSettings::default();
    s.phong.lights = vec![LightSource::new(Light::Directional(camera.forward()))];
    let scene = Scene::new(&slab, &ramp, &s, camera.forward()).unwrap();
    let [(a, _), (n, _), (b, _)] = renders(&scene, &camera, 16, 12);
    assert_eq!(a, b);
    assert_eq!(n, b);
}
