//! Invariants over random volumes, rays and settings (proptest), and the renderer's guarantees:
//! the same image for any thread count, skipping that changes nothing, breakdown equal to render.

mod common;

use common::*;
use proptest::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use voxcast_core::camera::Camera;
use voxcast_core::classify::Classification;
use voxcast_core::clip::{Clip, ClipPlane};
use voxcast_core::composite::{Method, Order};
use voxcast_core::glam::{UVec3, Vec3};
use voxcast_core::image_out::LinearImage;
use voxcast_core::ray::Ray;
use voxcast_core::render::{Cancelled, render, render_with_threads};
use voxcast_core::sample::Interpolation;
use voxcast_core::settings::RenderSettings;
use voxcast_core::shade::{Highlight, Light, LightSource};
use voxcast_core::step::Length;
use voxcast_core::trace::{Scene, trace_ray};
use voxcast_core::transfer::{ControlPoint, TransferFunction};
use voxcast_core::{Prepared, Volume, VoxelData};

fn volume() -> impl Strategy<Value = Prepared> {
    (
        1u32..7,
        1u32..7,
        1u32..7,
        0.2f32..4.0,
        0.2f32..4.0,
        0.2f32..4.0,
    )
        .prop_flat_map(|(x, y, z, sx, sy, sz)| {
            proptest::collection::vec(any::<u8>(), (x * y * z) as usize).prop_map(move |data| {
                Volume::new(
                    "random",
                    UVec3::new(x, y, z),
                    Vec3::new(sx, sy, sz),
                    VoxelData::U8(data),
                )
                .unwrap()
                .into()
            })
        })
}

/// A transfer function with transparent stretches (so skipping has work to do).
fn transfer() -> impl Strategy<Value = TransferFunction> {
    proptest::collection::vec(
        (
            0f32..255.0,
            0f32..1.0,
            0f32..1.0,
            0f32..1.0,
            prop_oneof![Just(0.0f32), 0f32..1.0],
        ),
        1..6,
    )
    .prop_map(|points| {
        let points = points
            .into_iter()
            .map(|(v, r, g, b, a)| ControlPoint::new(v, [r, g, b], a))
            .collect();
        TransferFunction::new("random", points).unwrap()
    })
}

/// No cut a third of the time, else a random crop box and maybe a clip plane.
fn clip() -> impl Strategy<Value = Clip> {
    (
        0u8..3,
        proptest::array::uniform3(0f32..=1.0),
        proptest::array::uniform3(0f32..=1.0),
        proptest::array::uniform3(-1f32..=1.0),
        -1f32..=1.0,
    )
        .prop_map(|(kind, a, b, n, position)| {
            if kind == 0 {
                return Clip::default();
            }
            let (a, b) = (Vec3::from(a), Vec3::from(b));
            let normal = Vec3::from(n);
            Clip {
                crop_lo: a.min(b),
                crop_hi: a.max(b),
                plane: (kind == 2 && normal.length_squared() > 1e-6)
                    .then_some(ClipPlane { normal, position }),
            }
        })
}

fn settings() -> impl Strategy<Value = RenderSettings> {
    (
        prop_oneof![
            Just(Method::Accumulate),
            Just(Method::First),
            Just(Method::Average),
            Just(Method::Maximum),
            Just(Method::Minimum)
        ],
        0.05f32..3.0,
        any::<bool>(),
        any::<bool>(),
        0f32..=1.0,
        any::<bool>(),
        any::<bool>(),
        prop_oneof![Just(Interpolation::Trilinear), Just(Interpolation::Nearest)],
        0f32..255.0,
        prop_oneof![Just(0u8), Just(1), Just(2)],
        clip(),
    )
        .prop_map(
            |(
                method,
                step,
                correction,
                early,
                cutoff,
                jitter,
                shading,
                interpolation,
                target,
                mode,
                clip,
            )| RenderSettings {
                method,
                step: Length::Voxels(step),
                opacity_correction: correction,
                early_termination: early,
                cutoff,
                jitter,
                shading,
                interpolation,
                target: Some(target),
                phong: voxcast_core::shade::Phong {
                    // Mode 2 lights with a coloured, attenuated point light beside the
                    // headlight, and Levoy's highlight: every light term is exercised.
                    lights: if mode == 2 {
                        vec![
                            LightSource::new(Light::Headlight),
                            LightSource {
                                color: Vec3::new(0.9, 0.3, 0.2),
                                kl: 0.05,
                                ..LightSource::new(Light::Point(Vec3::new(-3.0, 5.0, 9.0)))
                            },
                        ]
                    } else {
                        vec![LightSource::new(Light::Headlight)]
                    },
                    highlight: if mode == 2 {
                        Highlight::Levoy
                    } else {
                        Highlight::White
                    },
                    ..Default::default()
                },
                classification: match mode {
                    0 => Classification::Table,
                    1 => Classification::IsoContours {
                        isovalues: vec![target, 128.0],
                        thickness_voxels: 1.5,
                    },
                    _ => Classification::Boundaries {
                        full_gradient: None,
                    },
                },
                clip,
                ..RenderSettings::default()
            },
        )
}

/// A ray from a point around the volume towards a point inside or near it.
fn ray_for(v: &Volume, from: [f32; 3], to: [f32; 3]) -> Option<Ray> {
    let (lo, hi) = v.bounds();
    let size = (hi - lo).max(Vec3::ONE);
    let origin = lo + Vec3::from(from) * size * 3.0 - size;
    let target = lo + Vec3::from(to) * size;
    Ray::new(origin, target - origin)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn every_ray_gives_finite_colours_in_range_and_opacity_never_falls(
        v in volume(), tf in transfer(), s in settings(),
        from in proptest::array::uniform3(0f32..1.0), to in proptest::array::uniform3(-0.2f32..1.2),
    ) {
        let Some(ray) = ray_for(&v, from, to) else { return Ok(()) };
        let scene = Scene::new(&v, &tf, &s, ray.dir).unwrap();
        let t = trace_ray(&scene, &ray, [3, 5]);
        for c in t.pixel.iter().chain(&t.color).chain([&t.opacity]) {
            prop_assert!(c.is_finite() && (0.0..=1.0 + 1e-6).contains(c), "{:?}", t.pixel);
        }
        if s.method == Method::Accumulate {
            let mut last = 0.0f32;
            for rec in &t.samples {
                let o = rec.composite_after[3];
                prop_assert!(o >= last, "opacity fell from {} to {}", last, o);
                prop_assert!((0.0..=1.0).contains(&rec.alpha_corrected));
                last = o;
            }
        }
    }

    #[test]
    fn back_to_front_equals_front_to_back(
        v in volume(), tf in transfer(), mut s in settings(),
        from in proptest::array::uniform3(0f32..1.0), to in proptest::array::uniform3(0f32..1.0),
    ) {
        let Some(ray) = ray_for(&v, from, to) else { return Ok(()) };
        s.method = Method::Accumulate;
        s.early_termination = false;
        let front = trace_ray(&Scene::new(&v, &tf, &s, ray.dir).unwrap(), &ray, [0, 0]);
        s.order = Order::BackToFront;
        let back = trace_ray(&Scene::new(&v, &tf, &s, ray.dir).unwrap(), &ray, [0, 0]);
        for i in 0..3 {
            prop_assert!((front.color[i] - back.color[i]).abs() < 1e-5, "{:?} vs {:?}", front.color, back.color);
        }
        prop_assert!((front.opacity - back.opacity).abs() < 1e-5);
    }

    #[test]
    fn skipping_empty_space_changes_no_bit_and_the_breakdown_equals_the_render(
        v in volume(), tf in transfer(), mut s in settings(),
        from in proptest::array::uniform3(0.3f32..1.0),
    ) {
        s.method = Method::Accumulate;
        let (lo, hi) = v.bounds();
        let Ok(camera) = Camera::framing(lo, hi, Vec3::from(from) - 0.2, Vec3::Y) else { return Ok(()) };
        let skipping = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
        let iso = matches!(s.classification, Classification::IsoContours { .. });
        prop_assert!(skipping.empty.is_some() || iso);
        let mut plain_scene = skipping.clone();
        plain_scene.empty = None;
        let (a, _) = render_with_threads(&skipping, &camera, 12, 9, 1).unwrap();
        let (b, _) = render_with_threads(&plain_scene, &camera, 12, 9, 1).unwrap();
        prop_assert_eq!(&a.pixels, &b.pixels);
        // So does the one-sample-at-a-time skipping march (what a CPU without AVX2 takes).
        let mut scalar = skipping.clone();
        scalar.simd = voxcast_core::trace::Vectors::Off;
        let (d, _) = render_with_threads(&scalar, &camera, 12, 9, 1).unwrap();
        prop_assert_eq!(&a.pixels, &d.pixels);
        // The switch a user turns does the same.
        let off = RenderSettings { skipping: false, ..s.clone() };
        let unskipped = Scene::new(&v, &tf, &off, camera.forward()).unwrap();
        prop_assert!(unskipped.empty.is_none() && !unskipped.block_skipping);
        let (c, _) = render_with_threads(&unskipped, &camera, 12, 9, 1).unwrap();
        prop_assert_eq!(&a.pixels, &c.pixels);
        // The inspector's numbers are the renderer's.
        for (px, py) in [(0u32, 0u32), (6, 4), (11, 8), (3, 7)] {
            let t = trace_ray(&skipping, &camera.pixel_ray(px, py, 12, 9), [px, py]);
            prop_assert_eq!(Vec3::from(t.pixel), a.get(px, py));
        }
        // Maximum, Minimum and First skip blocks that cannot change them.
        for method in [Method::Maximum, Method::Minimum, Method::First] {
            s.method = method;
            let fast = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
            let mut slow = fast.clone();
            slow.block_skipping = false;
            let (a, _) = render_with_threads(&fast, &camera, 12, 9, 1).unwrap();
            let (b, _) = render_with_threads(&slow, &camera, 12, 9, 1).unwrap();
            prop_assert_eq!(&a.pixels, &b.pixels);
        }
    }
}

/// A smooth field (two Gaussian blobs) for convergence measurements.
fn blobs() -> Prepared {
    field([24, 24, 24], Vec3::ONE, |p| {
        let a = (-(p - Vec3::new(9.0, 11.0, 12.0)).length_squared() / 30.0).exp();
        let b = (-(p - Vec3::new(15.0, 13.0, 10.0)).length_squared() / 20.0).exp();
        a + 0.7 * b
    })
}

#[test]
fn error_shrinks_as_the_step_halves() {
    let v = blobs();
    let tf = TransferFunction::new(
        "smooth",
        vec![
            ControlPoint::new(0.0, [0.1, 0.2, 0.9], 0.0),
            ControlPoint::new(1.2, [1.0, 0.8, 0.2], 0.5),
        ],
    )
    .unwrap();
    let camera = Camera::framing(
        Vec3::ZERO,
        Vec3::splat(23.0),
        Vec3::new(0.3, 0.5, 1.0),
        Vec3::Y,
    )
    .unwrap();
    let image = |step: f32, correction: bool| -> LinearImage {
        let mut s = plain(step);
        s.opacity_correction = correction;
        let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
        render_with_threads(&scene, &camera, 32, 32, 2).unwrap().0
    };
    for correction in [true, false] {
        let reference = image(1.0 / 64.0, correction);
        let errors: Vec<f64> = [2.0, 1.0, 0.5, 0.25, 0.125]
            .iter()
            .map(|&dt| image(dt, correction).diff(&reference).unwrap().rmse)
            .collect();
        for w in errors.windows(2) {
            assert!(
                w[1] < w[0],
                "correction {correction}: RMSE did not shrink: {errors:?}"
            );
        }
        // With correction the samples approximate one integral and the error falls at least in
        // proportion to the step; without it, each step size converges to its own, denser image,
        // and the error against the finest one shrinks only slowly (the lesson of the switch).
        if correction {
            assert!(
                errors[4] < 0.25 * errors[1],
                "at least first order: {errors:?}"
            );
        }
    }
}

#[test]
fn the_image_is_the_same_for_any_thread_count() {
    let v = blobs();
    let tf = TransferFunction::ramp(0.0, 1.2, 0.4).unwrap();
    let mut s = plain(0.5);
    s.shading = true;
    s.jitter = true;
    let camera = Camera::framing(
        Vec3::ZERO,
        Vec3::splat(23.0),
        Vec3::new(1.0, 0.5, 0.3),
        Vec3::Y,
    )
    .unwrap();
    let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let (one, stats) = render_with_threads(&scene, &camera, 40, 30, 1).unwrap();
    for threads in [2, 3, 8] {
        let (other, other_stats) = render_with_threads(&scene, &camera, 40, 30, threads).unwrap();
        assert_eq!(one.pixels, other.pixels, "{threads} threads");
        assert_eq!(stats, other_stats);
    }
}

#[test]
fn progress_reaches_the_end_and_cancel_stops_the_render() {
    let v = blobs();
    let tf = TransferFunction::ramp(0.0, 1.2, 0.4).unwrap();
    let s = plain(0.5);
    let camera = Camera::framing(Vec3::ZERO, Vec3::splat(23.0), Vec3::Z, Vec3::Y).unwrap();
    let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let seen = AtomicUsize::new(0);
    let total = AtomicUsize::new(0);
    let report = |d: usize, t: usize| {
        seen.fetch_max(d, Ordering::Relaxed);
        total.store(t, Ordering::Relaxed);
    };
    render(&scene, &camera, 64, 48, &report, &AtomicBool::new(false)).unwrap();
    assert_eq!(seen.load(Ordering::Relaxed), total.load(Ordering::Relaxed));
    assert_eq!(total.load(Ordering::Relaxed), 4 * 3, "16-pixel tiles");
    let cancel = AtomicBool::new(false);
    let result = render(
        &scene,
        &camera,
        64,
        48,
        &|_, _| cancel.store(true, Ordering::Relaxed),
        &cancel,
    );
    assert_eq!(result.err(), Some(Cancelled));
}

#[test]
fn supersampling_averages_sub_rays() {
    let v = blobs();
    let tf = TransferFunction::ramp(0.0, 1.2, 0.4).unwrap();
    let mut s: RenderSettings = plain(0.5);
    s.supersampling = 2;
    let camera = Camera::framing(Vec3::ZERO, Vec3::splat(23.0), Vec3::Z, Vec3::Y).unwrap();
    let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let (img, stats) = render_with_threads(&scene, &camera, 5, 4, 1).unwrap();
    assert_eq!(stats.rays, 5 * 4 * 4);
    // Pixel (2, 1) is the mean of the four rays of the 10×8 image's pixels (4..=5, 2..=3).
    let mut fine = s.clone();
    fine.supersampling = 1;
    let fine_scene = Scene::new(&v, &tf, &fine, camera.forward()).unwrap();
    let (big, _) = render_with_threads(&fine_scene, &camera, 10, 8, 1).unwrap();
    let mean = (big.get(4, 2) + big.get(5, 2) + big.get(4, 3) + big.get(5, 3)) / 4.0;
    assert!((img.get(2, 1) - mean).abs().max_element() < 1e-6);
}

/// On the embedded real volumes with their presets (shaded): skipping empty space and reading
/// precomputed gradients change no pixel, and the breakdown matches the render.
#[test]
fn accelerations_are_exact_on_real_volumes() {
    use voxcast_core::builtin::load_builtin;
    use voxcast_core::preset;
    for name in ["bunny", "brainsmall", "bucky"] {
        let v = Prepared::from(load_builtin(name).unwrap().volume);
        let p = preset::for_volume(v.name()).unwrap();
        let s = p.settings_over(&RenderSettings::default()).unwrap();
        let view = p.view.unwrap();
        let (lo, hi) = v.bounds();
        let camera = Camera::framing(lo, hi, view.from, view.up).unwrap();
        let fast = Scene::new(&v, &p.transfer, &s, camera.forward()).unwrap();
        assert!(fast.empty.is_some() && fast.differences.is_some(), "{name}");
        let mut slow = fast.clone();
        slow.empty = None;
        slow.differences = None;
        let (a, sa) = render_with_threads(&fast, &camera, 64, 48, 2).unwrap();
        let (b, sb) = render_with_threads(&slow, &camera, 64, 48, 2).unwrap();
        assert_eq!(a.pixels, b.pixels, "{name}");
        assert_eq!(sa.positions, sb.positions, "{name}");
        assert!(sa.samples <= sb.samples, "{name}");
        if name != "bucky" {
            assert!(sa.samples < sb.samples, "{name}: something was skipped");
        }
        for (x, y) in [(32, 24), (10, 30), (50, 12)] {
            let t = trace_ray(&fast, &camera.pixel_ray(x, y, 64, 48), [x, y]);
            assert_eq!(Vec3::from(t.pixel), a.get(x, y), "{name} pixel {x},{y}");
        }
        // Maximum, Minimum and First skip blocks that cannot change their result.
        for method in [Method::Maximum, Method::Minimum, Method::First] {
            let s = RenderSettings {
                method,
                ..s.clone()
            };
            let fast = Scene::new(&v, &p.transfer, &s, camera.forward()).unwrap();
            assert!(fast.block_skipping);
            let mut slow = fast.clone();
            slow.block_skipping = false;
            let (a, sa) = render_with_threads(&fast, &camera, 64, 48, 2).unwrap();
            let (b, sb) = render_with_threads(&slow, &camera, 64, 48, 2).unwrap();
            assert_eq!(a.pixels, b.pixels, "{name} {method:?}");
            assert!(
                sa.samples <= sb.samples && sa.positions == sb.positions,
                "{name} {method:?}"
            );
        }
    }
}

/// A volume of zeros with a few non-zero voxels (u8 or float): a ray density's kind of data.
fn sparse_volume() -> impl Strategy<Value = Prepared> {
    (
        (1u32..40, 1u32..40, 1u32..40),
        proptest::collection::vec((0f32..1.0, 0f32..1.0, 0f32..1.0, 1u8..=255), 0..6),
        any::<bool>(),
        0.3f32..3.0,
    )
        .prop_map(|((x, y, z), dots, float, spacing)| {
            let n = (x * y * z) as usize;
            let mut data = vec![0u8; n];
            for (a, b, c, v) in dots {
                let i = (a * x as f32) as u32 % x;
                let j = (b * y as f32) as u32 % y;
                let k = (c * z as f32) as u32 % z;
                data[(i + x * (j + y * k)) as usize] = v;
            }
            let voxels = match float {
                true => VoxelData::F32(data.iter().map(|&v| v as f32 * 0.37).collect()),
                false => VoxelData::U8(data),
            };
            Volume::new("sparse", UVec3::new(x, y, z), Vec3::splat(spacing), voxels)
                .unwrap()
                .into()
        })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Sum passing over blocks of zeros changes no bit of the image, at any step, view or
    /// interpolation; the switch a user turns does the same.
    #[test]
    fn sum_skipping_zero_blocks_changes_no_bit(
        v in sparse_volume(),
        from in proptest::array::uniform3(-1f32..1.0),
        step in 0.1f32..2.0,
        nearest in any::<bool>(),
        jitter in any::<bool>(),
    ) {
        let tf = voxcast_core::colormap::inferno_transfer(0.0, 255.0);
        let s = RenderSettings {
            method: Method::Sum,
            step: Length::Voxels(step),
            interpolation: if nearest { Interpolation::Nearest } else { Interpolation::Trilinear },
            jitter,
            ..RenderSettings::default()
        };
        let (lo, hi) = v.bounds();
        let dir = Vec3::from(from);
        if dir.length() < 0.1 { return Ok(()) }
        let Ok(camera) = Camera::framing(lo, hi, dir, Vec3::Y) else { return Ok(()) };
        // Skipping forced on, whatever share of the blocks holds zeros.
        let mut fast = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
        prop_assert!(fast.may_skip_zeros());
        fast.sum_skipping = true;
        fast.blocks = Some(v.block_ranges());
        let mut slow = fast.clone();
        slow.sum_skipping = false;
        let (a, fast_stats) = render_with_threads(&fast, &camera, 14, 10, 1).unwrap();
        let (b, slow_stats) = render_with_threads(&slow, &camera, 14, 10, 1).unwrap();
        prop_assert_eq!(&a.pixels, &b.pixels);
        prop_assert!(fast_stats.samples <= slow_stats.samples);
        let off = RenderSettings { skipping: false, ..s };
        let unskipped = Scene::new(&v, &tf, &off, camera.forward()).unwrap();
        prop_assert!(!unskipped.may_skip_zeros() && !unskipped.sum_skipping);
        let (c, _) = render_with_threads(&unskipped, &camera, 14, 10, 1).unwrap();
        prop_assert_eq!(&a.pixels, &c.pixels);
    }
}

/// On a sparse volume Sum takes far fewer samples with skipping, and a volume with no-data
/// voxels or an intercept is never skipped (its zeros would not interpolate to zero).
#[test]
fn sum_skipping_pays_and_only_where_exact() {
    let v = field([48, 48, 48], Vec3::ONE, |p| {
        if (p - Vec3::splat(24.0)).length() < 4.0 {
            10.0
        } else {
            0.0
        }
    });
    let tf = voxcast_core::colormap::inferno_transfer(0.0, 10.0);
    let s = RenderSettings {
        method: Method::Sum,
        ..RenderSettings::default()
    };
    let camera = Camera::framing(
        Vec3::ZERO,
        Vec3::splat(47.0),
        Vec3::new(0.3, 0.4, 1.0),
        Vec3::Y,
    )
    .unwrap();
    let fast = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let mut slow = fast.clone();
    slow.sum_skipping = false;
    let (a, fs) = render_with_threads(&fast, &camera, 32, 32, 1).unwrap();
    let (b, ss) = render_with_threads(&slow, &camera, 32, 32, 1).unwrap();
    assert_eq!(a.pixels, b.pixels);
    assert!(
        fs.samples * 4 < ss.samples,
        "{} vs {}",
        fs.samples,
        ss.samples
    );
    let mut nan = vec![0.0f32; 27];
    nan[13] = f32::NAN;
    let with_nan = voxcast_core::Prepared::from(
        Volume::new("nan", UVec3::splat(3), Vec3::ONE, VoxelData::F32(nan)).unwrap(),
    );
    assert!(
        !Scene::new(&with_nan, &tf, &s, Vec3::Z)
            .unwrap()
            .sum_skipping
    );
    let shifted = voxcast_core::Prepared::from(
        Volume::with_rescale(
            "shifted",
            UVec3::splat(3),
            Vec3::ONE,
            VoxelData::U8(vec![0; 27]),
            1.0,
            -5.0,
        )
        .unwrap(),
    );
    assert!(!Scene::new(&shifted, &tf, &s, Vec3::Z).unwrap().sum_skipping);
    // Where fewer than half the blocks are zeros the walk would cost more than it passes over.
    let mut data = vec![0u8; 48 * 48 * 48];
    data[..48 * 48 * 30].fill(3);
    let dense = voxcast_core::Prepared::from(
        Volume::new("dense", UVec3::splat(48), Vec3::ONE, VoxelData::U8(data)).unwrap(),
    );
    let scene = Scene::new(&dense, &tf, &s, Vec3::Z).unwrap();
    assert!(scene.may_skip_zeros() && !scene.sum_skipping);
    assert!(Scene::new(&v, &tf, &s, Vec3::Z).unwrap().sum_skipping);
}
