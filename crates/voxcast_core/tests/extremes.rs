//! Numerical stability at the extremes: axis-parallel, edge, corner and grazing rays, the camera
//! inside, degenerate and extreme volumes, tiny and huge steps, cutoffs 0 and 1, empty and fully
//! opaque transfer functions, and the extreme values of every scalar type.

mod common;

use common::*;
use std::sync::atomic::AtomicBool;
use voxcast_core::camera::{Camera, Projection};
use voxcast_core::composite::Method;
use voxcast_core::glam::{UVec3, Vec3};
use voxcast_core::render::render;
use voxcast_core::trace::{RayTrace, Scene, StopReason};
use voxcast_core::transfer::TransferFunction;
use voxcast_core::{Volume, VoxelData};

fn finite(t: &RayTrace) {
    assert!(
        t.pixel
            .iter()
            .all(|c| c.is_finite() && (0.0..=1.0).contains(c)),
        "pixel {:?}",
        t.pixel
    );
    assert!(t.opacity.is_finite() && (0.0..=1.0).contains(&t.opacity));
    for s in &t.samples {
        assert!(s.reconstruction.value.is_finite() && s.alpha_corrected.is_finite());
    }
}

#[test]
fn axis_parallel_rays_in_all_six_directions() {
    let v = field([16, 16, 16], Vec3::ONE, |p| p.x + 2.0 * p.y + 3.0 * p.z);
    let tf = grey(0.0, 90.0, 0.05);
    let centre = Vec3::splat(7.5);
    for dir in AXES {
        let t = trace(&v, &tf, &plain(0.5), centre - dir * 20.0, dir);
        finite(&t);
        let [a, b] = t.interval.unwrap();
        close(a, 12.5, 1e-5, "enters at the face");
        close(b, 27.5, 1e-5, "leaves at the opposite face");
        assert_eq!(
            t.samples.len(),
            31,
            "15 voxels at half a voxel, both ends included"
        );
        assert_eq!(t.stop, StopReason::LeftVolume);
    }
}

#[test]
fn rays_along_an_edge_through_a_corner_and_grazing_a_face() {
    let v = field([8, 8, 8], Vec3::ONE, |p| p.x * p.y + p.z);
    let tf = grey(0.0, 60.0, 0.1);
    // Along the edge y = 0, z = 0.
    let t = trace(&v, &tf, &plain(1.0), Vec3::new(-2.0, 0.0, 0.0), Vec3::X);
    finite(&t);
    assert_eq!(t.samples.len(), 8);
    assert!(
        t.samples.iter().all(|s| s.reconstruction.value == 0.0),
        "x·0 + 0 on the edge"
    );
    // Through the far corner (7, 7, 7) only: one sample, the corner's value.
    let t = trace(
        &v,
        &tf,
        &plain(1.0),
        Vec3::new(9.0, 9.0, 5.0),
        Vec3::new(-1.0, -1.0, 1.0),
    );
    finite(&t);
    assert_eq!(t.samples.len(), 1);
    close(
        t.samples[0].reconstruction.value,
        56.0,
        1e-3,
        "corner value",
    );
    // Grazing the face z = 7 and just missing it.
    let t = trace(&v, &tf, &plain(0.5), Vec3::new(-1.0, 3.0, 7.0), Vec3::X);
    finite(&t);
    assert_eq!(t.samples.len(), 15);
    let miss = trace(&v, &tf, &plain(0.5), Vec3::new(-1.0, 3.0, 7.0001), Vec3::X);
    assert_eq!(miss.stop, StopReason::Missed);
    assert_eq!(miss.pixel, [0.0; 3]);
}

#[test]
fn camera_inside_the_volume() {
    let v = constant([16, 16, 16], 1.0);
    let tf = white(0.1);
    let s = plain(0.5);
    let camera = Camera::new(
        Vec3::splat(7.5),
        Vec3::new(15.0, 7.5, 7.5),
        Vec3::Y,
        Projection::Perspective { fov_y_deg: 60.0 },
    )
    .unwrap();
    let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let (img, stats) =
        render(&scene, &camera, 16, 16, &|_, _| {}, &AtomicBool::new(false)).unwrap();
    assert!(
        img.pixels
            .iter()
            .all(|p| p.is_finite() && p.min_element() > 0.0),
        "every ray starts inside"
    );
    assert!(stats.samples > 0);
    // The centre ray starts at the eye, t = 0, and travels 7.5 units: Beer–Lambert from there.
    let t = trace(&v, &tf, &s, Vec3::splat(7.5), Vec3::X);
    assert_eq!(t.interval.unwrap()[0], 0.0);
    close(
        t.opacity,
        1.0 - 0.9f32.powf(7.5),
        1e-5,
        "7.5 voxels of path",
    );
}

#[test]
fn one_voxel_volume() {
    let v = voxcast_core::Prepared::from(
        Volume::new(
            "one",
            UVec3::ONE,
            Vec3::splat(2.0),
            VoxelData::U8(vec![200]),
        )
        .unwrap(),
    );
    assert_eq!(v.bounds(), (Vec3::splat(-1.0), Vec3::splat(1.0)));
    let tf = white(0.5);
    let mut s = plain(0.25);
    s.reference_step = voxcast_core::step::Length::World(2.0);
    let t = trace(&v, &tf, &s, Vec3::new(-5.0, 0.3, -0.2), Vec3::X);
    finite(&t);
    assert!(t.samples.iter().all(|s| s.reconstruction.value == 200.0));
    // A path of 2 world units at 0.5 opacity per 2 units.
    close(t.opacity, 0.5, 1e-5, "one reference length of path");
    for method in [
        Method::Average,
        Method::Maximum,
        Method::Minimum,
        Method::First,
    ] {
        s.method = method;
        s.target = Some(200.0);
        finite(&trace(&v, &tf, &s, Vec3::new(-5.0, 0.3, -0.2), Vec3::X));
    }
}

#[test]
fn long_thin_volumes() {
    for (dims, axis) in [([4096u32, 1, 1], Vec3::X), ([1, 1, 4096], Vec3::Z)] {
        let v = field(dims, Vec3::ONE, |p| p.x + p.z);
        let tf = grey(0.0, 4095.0, 1.0);
        let mut s = plain(1.0);
        s.method = Method::Maximum;
        // Along the long axis: 4096 samples, the maximum at the far end.
        let t = trace(&v, &tf, &s, -axis * 10.0, axis);
        assert_eq!(t.samples.len(), 4096);
        close(t.projected_value.unwrap(), 4095.0, 1e-3, "maximum");
        // Across it: a path of one voxel through the one-point axes.
        let across = if axis == Vec3::X { Vec3::Y } else { Vec3::X };
        let t = trace(&v, &tf, &s, axis * 100.0 - across * 5.0, across);
        let [a, b] = t.interval.unwrap();
        close(b - a, 1.0, 1e-5, "one voxel thick");
        close(
            t.projected_value.unwrap(),
            100.0,
            1e-3,
            "value at the crossing",
        );
    }
}

#[test]
fn spacing_ratio_of_a_thousand() {
    // 1000 world units between x points, 1 between the others; steps are in voxels of the
    // smallest spacing, so a ray along x needs 4000 samples per lattice cell: the cap stops it.
    let v = voxcast_core::Prepared::from(
        Volume::new(
            "aniso",
            UVec3::new(4, 4, 4),
            Vec3::new(1000.0, 1.0, 1.0),
            VoxelData::U8((0..64).collect()),
        )
        .unwrap(),
    );
    let tf = grey(0.0, 63.0, 0.01);
    let mut s = plain(0.5);
    s.max_samples = 1000;
    let t = trace(&v, &tf, &s, Vec3::new(-10.0, 1.5, 1.5), Vec3::X);
    finite(&t);
    assert_eq!(t.stop, StopReason::SampleCap);
    assert_eq!(t.samples.len(), 1000);
    // Across x the ray is ordinary.
    let t = trace(&v, &tf, &s, Vec3::new(1500.0, -3.0, 1.5), Vec3::Y);
    finite(&t);
    assert_eq!(t.samples.len(), 7);
}

#[test]
fn tiny_step_hits_the_cap_and_huge_step_takes_one_sample() {
    let v = constant([8, 8, 8], 1.0);
    let tf = white(0.01);
    let mut s = plain(1e-6);
    s.max_samples = 5000;
    let t = trace(&v, &tf, &s, Vec3::new(-1.0, 3.5, 3.5), Vec3::X);
    assert_eq!((t.stop, t.samples.len()), (StopReason::SampleCap, 5000));
    finite(&t);
    let t = trace(&v, &tf, &plain(1e3), Vec3::new(-1.0, 3.5, 3.5), Vec3::X);
    assert_eq!(t.samples.len(), 1);
    // The one sample stands for the whole path: still Beer–Lambert with correction.
    close(
        t.opacity,
        1.0 - 0.99f32.powf(7.0),
        1e-5,
        "one sample, whole path",
    );
}

/// A step of 1e-6 voxel: the cap cuts every ray in the empty space before a sphere in the
/// middle, the image is the background — and the render counts the rays it cut and says so in
/// words, as the settings predict before rendering; at a usual step neither warns.
#[test]
fn a_step_too_small_for_the_cap_is_counted_and_warned_about() {
    let c = Vec3::splat(15.5);
    let v = field([32, 32, 32], Vec3::ONE, |p| {
        (8.0 - (p - c).length()).max(0.0)
    });
    let tf = white(1.0);
    let camera = Camera::framing(Vec3::ZERO, Vec3::splat(31.0), Vec3::Z, Vec3::Y).unwrap();
    let never = AtomicBool::new(false);
    let mut s = plain(1e-6);
    s.max_samples = 1000;
    let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let (_, stats) = render(&scene, &camera, 16, 16, &|_, _| {}, &never).unwrap();
    assert!(stats.capped > 0 && stats.capped <= stats.rays, "{stats:?}");
    let words = stats.cap_warning(s.max_samples).unwrap();
    assert!(
        words.contains(&format!("{} of 256 rays", stats.capped)),
        "{words}"
    );
    let ahead = s.cap_warning(&v).expect("predicted before rendering");
    assert!(ahead.contains("more than the cap (1000)"), "{ahead}");
    s = plain(0.5);
    let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let (_, stats) = render(&scene, &camera, 16, 16, &|_, _| {}, &never).unwrap();
    assert_eq!(stats.capped, 0);
    assert!(stats.cap_warning(s.max_samples).is_none());
    assert!(s.cap_warning(&v).is_none());
}

#[test]
fn cutoffs_zero_and_one() {
    let v = constant([8, 8, 8], 1.0);
    let tf = white(0.3);
    let mut s = plain(0.5);
    s.early_termination = true;
    s.cutoff = 0.0;
    let t = trace(&v, &tf, &s, Vec3::new(-1.0, 3.5, 3.5), Vec3::X);
    assert_eq!(
        (t.stop, t.samples.len()),
        (StopReason::Cutoff, 1),
        "O ≥ 0 after the first sample"
    );
    s.cutoff = 1.0;
    let with = trace(&v, &tf, &s, Vec3::new(-1.0, 3.5, 3.5), Vec3::X);
    s.early_termination = false;
    let without = trace(&v, &tf, &s, Vec3::new(-1.0, 3.5, 3.5), Vec3::X);
    assert_eq!(
        with.pixel, without.pixel,
        "cutoff 1 never stops a ray that is not opaque"
    );
    assert_eq!(with.stop, StopReason::LeftVolume);
}

#[test]
fn empty_and_fully_opaque_transfer_functions() {
    let v = field([8, 8, 8], Vec3::ONE, |p| p.x);
    let mut s = plain(0.5);
    s.background = Vec3::new(0.2, 0.4, 0.6);
    s.early_termination = true;
    let t = trace(
        &v,
        &TransferFunction::constant([1.0, 0.0, 0.0], 0.0).unwrap(),
        &s,
        Vec3::new(-1.0, 3.5, 3.5),
        Vec3::X,
    );
    assert_eq!(t.pixel, [0.2, 0.4, 0.6], "nothing visible: the background");
    assert_eq!(t.opacity, 0.0);
    let t = trace(
        &v,
        &TransferFunction::constant([1.0, 0.0, 0.0], 1.0).unwrap(),
        &s,
        Vec3::new(-1.0, 3.5, 3.5),
        Vec3::X,
    );
    assert_eq!((t.stop, t.samples.len()), (StopReason::Cutoff, 1));
    assert_eq!(t.pixel, [1.0, 0.0, 0.0], "the first sample is all there is");
    // The same through the renderer, which skips empty space.
    let camera = Camera::framing(
        Vec3::ZERO,
        Vec3::splat(7.0),
        Vec3::new(1.0, 0.5, 2.0),
        Vec3::Y,
    )
    .unwrap();
    let tf = TransferFunction::constant([1.0, 0.0, 0.0], 0.0).unwrap();
    let scene = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let (img, stats) = render(&scene, &camera, 8, 8, &|_, _| {}, &AtomicBool::new(false)).unwrap();
    assert!(img.pixels.iter().all(|p| *p == Vec3::new(0.2, 0.4, 0.6)));
    assert_eq!(stats.samples, 0, "every block is skipped");
    assert!(stats.positions > 0);
}

#[test]
fn extreme_values_of_every_type() {
    let dims = UVec3::new(2, 1, 1);
    let cases = [
        VoxelData::U8(vec![0, 255]),
        VoxelData::I16(vec![i16::MIN, i16::MAX]),
        VoxelData::U16(vec![0, u16::MAX]),
        VoxelData::F32(vec![-1e30, 1e30]),
        VoxelData::F32(vec![1.0, 1.0 + 1e-6]),
    ];
    for data in cases {
        let v = voxcast_core::Prepared::from(Volume::new("x", dims, Vec3::ONE, data).unwrap());
        let (lo, hi) = v.value_range();
        let tf = grey(lo, hi, 0.5);
        for method in voxcast_core::composite::Method::ALL {
            let mut s = plain(0.1);
            s.method = method;
            s.shading = true;
            let t = trace(&v, &tf, &s, Vec3::new(-1.0, 0.0, 0.0), Vec3::X);
            finite(&t);
            if method == Method::Maximum {
                close(
                    t.projected_value.unwrap(),
                    hi,
                    hi.abs() * 1e-6,
                    "maximum is the top value",
                );
            }
        }
    }
}

#[test]
fn degenerate_settings_are_rejected_not_rendered() {
    let v = constant([4, 4, 4], 1.0);
    for bad in [0.0f32, -1.0, f32::NAN, f32::INFINITY] {
        let s = voxcast_core::settings::RenderSettings {
            step: voxcast_core::step::Length::Voxels(bad),
            ..Default::default()
        };
        assert!(
            Scene::new(&v, &white(0.5), &s, Vec3::X).is_err(),
            "step {bad}"
        );
    }
    assert!(voxcast_core::render::validate_size(0, 10).is_err());
}

/// A float volume whose voxels are all NaN or ±∞ ("no data") loads and renders the
/// background with every method, without a NaN anywhere in the pixel.
#[test]
fn a_volume_of_no_data_renders_the_background() {
    let data = (0..27)
        .map(|i| [f32::NAN, f32::INFINITY, f32::NEG_INFINITY][i % 3])
        .collect();
    let v = voxcast_core::Prepared::from(
        Volume::new("none", UVec3::splat(3), Vec3::ONE, VoxelData::F32(data)).unwrap(),
    );
    assert_eq!(v.no_data_count(), 27);
    let tf = white(1.0);
    for method in Method::ALL {
        for shading in [false, true] {
            let mut s = plain(0.5);
            (s.method, s.shading, s.background) = (method, shading, Vec3::new(0.1, 0.2, 0.3));
            let t = trace(
                &v,
                &tf,
                &s,
                Vec3::new(-2.0, 1.2, 0.7),
                Vec3::new(1.0, 0.1, 0.2),
            );
            assert_eq!(t.pixel, s.background.to_array(), "{method:?}");
            assert_eq!(t.opacity, 0.0);
            assert!(t.first_hit.is_none() && t.projected_value.is_none());
        }
    }
}

/// One finite voxel among no data: every trilinear sample has a corner without data, so
/// nothing shows; nearest interpolation shows the voxel's own region.
#[test]
fn one_finite_voxel_among_no_data() {
    let mut data = vec![f32::NAN; 27];
    data[13] = 5.0; // the centre (1, 1, 1)
    let v = voxcast_core::Prepared::from(
        Volume::new("one", UVec3::splat(3), Vec3::ONE, VoxelData::F32(data)).unwrap(),
    );
    assert_eq!((v.no_data_count(), v.value_range()), (26, (5.0, 5.0)));
    let tf = white(0.5);
    let mut s = plain(0.25);
    let ray = (Vec3::new(-1.0, 1.0, 1.0), Vec3::X);
    let t = trace(&v, &tf, &s, ray.0, ray.1);
    assert_eq!(t.opacity, 0.0, "trilinear: no sample has all 8 corners");
    assert!(t.samples.iter().all(|r| r.alpha_corrected == 0.0));
    s.interpolation = voxcast_core::sample::Interpolation::Nearest;
    let t = trace(&v, &tf, &s, ray.0, ray.1);
    finite(&RayTrace {
        samples: vec![],
        ..t.clone()
    });
    assert!(
        t.opacity > 0.0,
        "nearest: the voxel's own cube of space shows"
    );
}

/// Values rising along x with a plane of no data at x = 3: First at 2.5 does not refine into
/// the gap — the first sample with data at or above the target (past the gap) is the hit, on
/// its own; Average and Maximum leave the gap out.
#[test]
fn no_data_next_to_the_first_target_and_in_the_projections() {
    let v = field([8, 3, 3], Vec3::ONE, |p| {
        if p.x == 3.0 { f32::NAN } else { p.x }
    });
    let tf = white(1.0);
    let mut s = plain(0.5);
    s.method = Method::First;
    s.target = Some(2.5);
    let ray = (Vec3::new(-1.0, 1.2, 1.1), Vec3::X);
    let t = trace(&v, &tf, &s, ray.0, ray.1);
    let h = t.first_hit.expect("a hit past the gap");
    assert_eq!(h.bracket[0], h.bracket[1], "no bracket across the gap");
    assert!(h.value >= 2.5 && h.p_voxel[0] >= 4.0, "{h:?}");
    assert!(t.pixel.iter().all(|c| c.is_finite()));
    // The samples in cells touching x = 3 have no value; the projections ignore them.
    for method in [Method::Average, Method::Maximum, Method::Minimum] {
        s.method = method;
        let t = trace(&v, &tf, &s, ray.0, ray.1);
        let data: Vec<f32> = t
            .samples
            .iter()
            .map(|r| r.reconstruction.value)
            .filter(|v| v.is_finite())
            .collect();
        assert!(data.len() < t.samples.len(), "some samples fell in the gap");
        let expect = match method {
            Method::Average => data.iter().sum::<f32>() / data.len() as f32,
            Method::Maximum => data.iter().copied().fold(f32::MIN, f32::max),
            _ => data.iter().copied().fold(f32::MAX, f32::min),
        };
        close(
            t.projected_value.unwrap(),
            expect,
            1e-5,
            &format!("{method:?}"),
        );
    }
    // Shaded Accumulate next to the gap: the gradient there is zero, never NaN.
    s.method = Method::Accumulate;
    s.shading = true;
    let t = trace(&v, &white(0.3), &s, ray.0, ray.1);
    assert!(t.pixel.iter().all(|c| c.is_finite()) && t.opacity > 0.0);
}
