//! Maximum and Minimum with the best blocks first and eight lanes (`trace/extreme.rs`,
//! `trace/value_lanes.rs`; AVX2's and SSE 4.1's, or NEON's on ARM), and Average and Sum adding
//! their samples eight at a time, render the plain march's pixels bit for bit: over random scan-like
//! volumes of every integer type (a negative rescale slope among them, which turns the largest
//! raw value into the smallest), cameras outside, along an axis, inside and orthographic, and
//! steps from tiny to huge — and at the extremes (a one-voxel volume, a volume one voxel thin
//! along x, where the lanes do not apply, an 8-bit volume of three voxels, a constant one).

mod scenes;
// In WebAssembly (`.ci/run`), each `#[test]` is one of wasm-bindgen's, run under Node.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use proptest::prelude::*;
use scenes::{camera, instructions, volume};
use voxcast_core::camera::Camera;
use voxcast_core::composite::Method;
use voxcast_core::glam::{UVec3, Vec3};
use voxcast_core::render::render_with_threads;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::trace::{Scene, Vectors, value_lane_instructions};
use voxcast_core::transfer::TransferFunction;
use voxcast_core::{Prepared, Volume, VoxelData};

/// The image of `scene` as rendered (ordered blocks or zero blocks passed over, the widest
/// lanes), with the narrow lanes (SSE 4.1; NEON on ARM), with the lanes off, and by the plain
/// march (no skipping at all); with the sample counts of each.
fn four(scene: &Scene<'_>, camera: &Camera, w: u32, h: u32) -> [(Vec<Vec3>, u64); 4] {
    let mut narrow = scene.clone();
    narrow.simd = Vectors::Narrow;
    let mut scalar = scene.clone();
    scalar.simd = Vectors::Off;
    let mut plain = scene.clone();
    plain.block_skipping = false;
    plain.sum_skipping = false;
    plain.simd = Vectors::Off;
    [scene, &narrow, &scalar, &plain].map(|s| {
        let (image, stats) = render_with_threads(s, camera, w, h, 1).unwrap();
        (image.pixels, stats.samples)
    })
}

fn settings(method: Method, step: f32, jitter: bool) -> RenderSettings {
    RenderSettings {
        method,
        step: Length::Voxels(step),
        jitter,
        max_samples: 1 << 16,
        ..RenderSettings::default()
    }
}

/// A ramp over the volume's values, so every value has its own colour.
fn ramp(v: &Volume) -> TransferFunction {
    let (lo, hi) = v.value_range();
    TransferFunction::ramp(lo, hi.max(lo + 1.0), 1.0).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(192))]

    #[test]
    fn ordered_projections_render_the_plain_pixels_bit_for_bit(
        v in volume(),
        maximum in any::<bool>(),
        step in prop_oneof![3 => 0.1f32..3.0, 1 => Just(0.02f32), 1 => Just(40.0f32)],
        jitter in any::<bool>(),
        kind in 0u8..4,
        a in proptest::array::uniform3(0f32..1.0),
        b in proptest::array::uniform3(0f32..1.0),
    ) {
        let method = if maximum { Method::Maximum } else { Method::Minimum };
        let Some(camera) = camera(&v, kind, Vec3::from(a), Vec3::from(b)) else { return Ok(()) };
        let tf = ramp(&v);
        let scene = Scene::new(&v, &tf, &settings(method, step, jitter), camera.forward()).unwrap();
        prop_assert!(scene.block_skipping);
        let [(fast, taken), (narrow, _), (scalar, _), (plain, all)] = four(&scene, &camera, 20, 15);
        prop_assert_eq!(&fast, &plain);
        prop_assert_eq!(&scalar, &plain);
        prop_assert_eq!(&narrow, &plain);
        prop_assert!(taken <= all);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Average and Sum add every sample: eight at a time, the same sums to the last bit (these
    /// volumes are noisy, without zero blocks: Sum's passing over them is tested on the ball
    /// below and on sparse volumes in `tests/properties.rs`).
    #[test]
    fn averages_and_sums_in_lanes_are_the_scalar_ones_bit_for_bit(
        v in volume(),
        sum in any::<bool>(),
        step in prop_oneof![3 => 0.1f32..3.0, 1 => Just(0.02f32), 1 => Just(40.0f32)],
        jitter in any::<bool>(),
        kind in 0u8..4,
        a in proptest::array::uniform3(0f32..1.0),
        b in proptest::array::uniform3(0f32..1.0),
    ) {
        let method = if sum { Method::Sum } else { Method::Average };
        let Some(camera) = camera(&v, kind, Vec3::from(a), Vec3::from(b)) else { return Ok(()) };
        let tf = ramp(&v);
        let scene = Scene::new(&v, &tf, &settings(method, step, jitter), camera.forward()).unwrap();
        let [(fast, _), (narrow, _), (scalar, _), (plain, _)] = four(&scene, &camera, 20, 15);
        prop_assert_eq!(&fast, &plain);
        prop_assert_eq!(&scalar, &plain);
        prop_assert_eq!(&narrow, &plain);
    }
}

/// On real volumes blocks are passed over: fewer samples, the same pixels.
#[test]
fn real_volumes_take_fewer_samples_for_the_same_pixels() {
    use voxcast_core::builtin::load_builtin;
    for name in ["bunny", "brainsmall"] {
        let v = Prepared::from(load_builtin(name).unwrap().volume);
        let (lo, hi) = v.bounds();
        let camera = Camera::framing(lo, hi, Vec3::new(0.4, 0.3, 1.0), Vec3::Y).unwrap();
        let tf = ramp(&v);
        for method in [Method::Maximum, Method::Minimum] {
            let scene =
                Scene::new(&v, &tf, &settings(method, 0.5, false), camera.forward()).unwrap();
            let [(fast, taken), (narrow, _), (scalar, _), (plain, all)] =
                four(&scene, &camera, 64, 48);
            assert_eq!(fast, plain, "{name} {method:?}");
            assert_eq!(scalar, plain, "{name} {method:?}");
            assert_eq!(narrow, plain, "{name} {method:?}");
            eprintln!("{name} {method:?}: {taken} of {all} samples");
            // The lanes are taken (else the comparisons above are of the scalar march with
            // itself), narrowed too.
            let mut narrowed = scene.clone();
            narrowed.simd = Vectors::Narrow;
            let (wide, narrow) = instructions();
            assert_eq!(value_lane_instructions(&scene), wide, "{name}");
            assert_eq!(value_lane_instructions(&narrowed), narrow, "{name}");
            assert!(taken < all, "{name} {method:?}: {taken} of {all} samples");
        }
    }
}

/// Sum passes over blocks of zeros around an object: every run of samples between them ends
/// exactly where the scalar march's does (a sample lost or added at a block's margin would
/// change the sum), eight at a time or one by one.
#[test]
fn sums_around_zero_blocks_agree() {
    let n = 40u32;
    let data = (0..n * n * n)
        .map(|i| {
            let p = Vec3::new((i % n) as f32, (i / n % n) as f32, (i / (n * n)) as f32);
            let r = (p - Vec3::splat(19.5)).length();
            if r < 11.0 { (200.0 - 9.0 * r) as u8 } else { 0 }
        })
        .collect();
    let v = Prepared::from(
        Volume::new("ball", UVec3::splat(n), Vec3::ONE, VoxelData::U8(data)).unwrap(),
    );
    let (lo, hi) = v.bounds();
    let tf = ramp(&v);
    let mut passed = false;
    for (i, from) in [Vec3::new(0.3, 0.5, 1.0), Vec3::Z, Vec3::new(-1.0, 0.2, 0.1)]
        .into_iter()
        .enumerate()
    {
        for step in [0.13, 0.5, 0.77, 2.0] {
            let camera = Camera::framing(lo, hi, from, Vec3::Y).unwrap();
            let s = settings(Method::Sum, step, i == 1);
            let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
            assert!(scene.sum_skipping);
            let [(fast, taken), (narrow, _), (scalar, _), (plain, all)] =
                four(&scene, &camera, 31, 23);
            assert_eq!(fast, plain, "from {from} step {step}");
            assert_eq!(scalar, plain, "from {from} step {step}");
            assert_eq!(narrow, plain, "from {from} step {step}");
            passed |= taken < all;
        }
    }
    assert!(passed, "zero blocks were passed over");
}

/// The extremes: one voxel, one voxel thin along x (no lanes: a cell's x corners are one
/// point), three 8-bit voxels (fewer than a lane's four-byte read), a constant volume (every
/// block ties), huge and tiny steps.
#[test]
fn extremes_agree() {
    let make = |dims: [u32; 3], data: VoxelData| {
        Prepared::from(Volume::new("extreme", UVec3::from(dims), Vec3::ONE, data).unwrap())
    };
    let n = |d: [u32; 3]| (d[0] * d[1] * d[2]) as usize;
    let volumes = [
        make([1, 1, 1], VoxelData::U8(vec![77])),
        make(
            [1, 20, 30],
            VoxelData::U16((0..600).map(|i| (i * 37 % 1000) as u16).collect()),
        ),
        make([3, 1, 1], VoxelData::U8(vec![5, 250, 9])),
        make([2, 2, 1], VoxelData::I16(vec![-300, 12, 7, -5])),
        make([17, 9, 21], VoxelData::U8(vec![42; n([17, 9, 21])])),
        make(
            [33, 17, 9],
            VoxelData::I16(
                (0..n([33, 17, 9]))
                    .map(|i| ((i * 7919) % 4001) as i16 - 2000)
                    .collect(),
            ),
        ),
    ];
    for v in &volumes {
        let (lo, hi) = v.bounds();
        let tf = ramp(v);
        for method in [
            Method::Maximum,
            Method::Minimum,
            Method::Average,
            Method::Sum,
        ] {
            for step in [1e-3, 0.5, 1e4] {
                for from in [Vec3::new(0.3, 0.5, 1.0), Vec3::Z, Vec3::X, Vec3::NEG_Y] {
                    let up = if from.y != 0.0 || from == Vec3::X {
                        Vec3::Z
                    } else {
                        Vec3::Y
                    };
                    let camera = Camera::framing(lo, hi, from, up).unwrap();
                    let s = RenderSettings {
                        max_samples: 1 << 20,
                        ..settings(method, step, false)
                    };
                    let scene = Scene::new(v, &tf, &s, camera.forward()).unwrap();
                    let [(fast, _), (narrow, _), (scalar, _), (plain, _)] =
                        four(&scene, &camera, 9, 7);
                    assert_eq!(
                        fast,
                        plain,
                        "{:?} {method:?} step {step} from {from}",
                        v.dims()
                    );
                    let at = format!("{:?} {method:?} step {step} from {from}", v.dims());
                    assert_eq!(narrow, plain, "{at}");
                    assert_eq!(scalar, plain, "{at}");
                }
            }
        }
    }
}
