//! Looking inside: the crop box and clip plane in closed form — what each method sees of a ramp
//! and a sphere once they are cut, the cut face a First hit lands on, the breakdown's account of
//! the cut, and the extremes (a camera inside the removed part, a one-point volume, a slice).

mod common;

use common::*;
use voxcast_core::camera::Camera;
use voxcast_core::clip::{Clip, ClipPlane};
use voxcast_core::composite::Method;
use voxcast_core::glam::Vec3;
use voxcast_core::ray::intersect_box;
use voxcast_core::render::render_with_threads;
use voxcast_core::trace::{Scene, StopReason};

fn plane(normal: Vec3, position: f32) -> Clip {
    Clip {
        plane: Some(ClipPlane { normal, position }),
        ..Clip::default()
    }
}

/// Value x on a 9×3×3 lattice: along x the box spans [0, 8].
fn ramp() -> voxcast_core::Prepared {
    field([9, 3, 3], Vec3::ONE, |p| p.x)
}

#[test]
fn projections_of_a_cut_ramp() {
    let v = ramp();
    let tf = grey(0.0, 8.0, 0.5);
    let mut s = plain(0.5);
    let along = (Vec3::new(-1.0, 1.0, 1.0), Vec3::X);
    let back = (Vec3::new(9.0, 1.0, 1.0), Vec3::NEG_X);
    // The plane x = 4 (through the centre, normal +x) removes x > 4.
    s.clip = plane(Vec3::X, 0.0);
    s.method = Method::Maximum;
    let t = trace(&v, &tf, &s, along.0, along.1);
    assert_eq!(t.projected_value, Some(4.0));
    assert_eq!(t.interval, Some([1.0, 5.0]));
    assert_eq!(t.box_interval, Some([1.0, 9.0]));
    let cut = t.cut_words().unwrap();
    assert!(cut.contains("t = 5 to 9 behind"), "{cut}");
    // From the other side the ray enters at the plane: its first sample is x = 4.
    s.method = Method::Minimum;
    let t = trace(&v, &tf, &s, back.0, back.1);
    assert_eq!(t.projected_value, Some(0.0));
    assert_eq!(t.interval, Some([5.0, 9.0]));
    assert_eq!(t.samples[0].p_world[0], 4.0);
    assert!(t.cut_words().unwrap().contains("in front"));
    // Average over x in [0, 4] at step ½: samples 0, 0.5, …, 4 average to 2.
    s.method = Method::Average;
    let t = trace(&v, &tf, &s, along.0, along.1);
    close(
        t.projected_value.unwrap(),
        2.0,
        1e-6,
        "average of the kept half",
    );
    // A crop box keeping x in [2, 6] (a quarter off each end).
    s.clip = Clip {
        crop_lo: Vec3::new(0.25, 0.0, 0.0),
        crop_hi: Vec3::new(0.75, 1.0, 1.0),
        plane: None,
    };
    s.method = Method::Minimum;
    assert_eq!(
        trace(&v, &tf, &s, along.0, along.1).projected_value,
        Some(2.0)
    );
    s.method = Method::Maximum;
    assert_eq!(
        trace(&v, &tf, &s, along.0, along.1).projected_value,
        Some(6.0)
    );
    // Both: crop to [2, 6], plane removes x > 4.
    s.clip.plane = Some(ClipPlane {
        normal: Vec3::X,
        position: 0.0,
    });
    assert_eq!(
        trace(&v, &tf, &s, along.0, along.1).projected_value,
        Some(4.0)
    );
}

#[test]
fn accumulate_through_a_cut_is_beer_lambert_over_the_kept_length() {
    // Constant density: with opacity correction the opacity over a length L is 1 − (1 − α)^L.
    let v = constant([17, 5, 5], 1.0);
    let tf = white(0.1);
    let mut s = plain(0.25);
    for (position, kept) in [(1.0f32, 16.0f32), (0.5, 12.0), (0.0, 8.0), (-0.75, 2.0)] {
        s.clip = plane(Vec3::X, position);
        let t = trace(&v, &tf, &s, Vec3::new(-3.0, 2.0, 2.0), Vec3::X);
        // The samples' segments add up to the kept length.
        let expect = 1.0 - 0.9f32.powf(kept);
        close(t.opacity, expect, 1e-4, &format!("position {position}"));
    }
}

#[test]
fn first_hit_lands_on_the_cut_face_of_a_solid_sphere() {
    let c = Vec3::splat(16.0);
    let v = field([33, 33, 33], Vec3::ONE, |p| 10.0 - (p - c).length());
    let tf = white(1.0);
    let mut s = plain(0.5);
    s.method = Method::First;
    s.target = Some(0.0);
    // Remove the half facing −z (normal −z through the centre): a ray along +z from in front
    // now enters at z = 16, inside the sphere (value 10 − r ≥ 0): it hits right at the cut.
    s.clip = plane(Vec3::NEG_Z, 0.0);
    for (x, y) in [(16.0, 16.0), (20.0, 14.0), (10.0, 17.0)] {
        let t = trace(&v, &tf, &s, Vec3::new(x, y, -5.0), Vec3::Z);
        assert_eq!(t.stop, StopReason::FirstHit, "({x}, {y})");
        let hit = t.first_hit.unwrap();
        close(hit.p_world[2], 16.0, 1e-5, "on the cut face");
        assert_eq!(hit.bracket[0], hit.bracket[1], "hit at the entry");
    }
    // Outside the sphere's disc on the cut the ray misses what is left.
    let t = trace(&v, &tf, &s, Vec3::new(16.0, 27.0, -5.0), Vec3::Z);
    assert_eq!(t.stop, StopReason::LeftVolume);
    // With the other half removed, the same ray finds the near hemisphere's surface.
    s.clip = plane(Vec3::Z, 0.0);
    let t = trace(&v, &tf, &s, Vec3::new(16.0, 16.0, -5.0), Vec3::Z);
    close(
        t.first_hit.unwrap().p_world[2],
        6.0,
        1e-2,
        "the sphere's surface",
    );
}

#[test]
fn a_ray_whose_part_is_all_cut_away_says_so() {
    let v = ramp();
    let tf = grey(0.0, 8.0, 0.5);
    let mut s = plain(0.5);
    s.clip = plane(Vec3::X, -1.0);
    let t = trace(&v, &tf, &s, Vec3::new(-1.0, 1.0, 1.0), Vec3::X);
    // Position −1 touches the nearest corners: at most a point is left, never a sample with
    // colour beyond it.
    assert!(t.samples.len() <= 1, "{} samples", t.samples.len());
    let t = trace(&v, &tf, &s, Vec3::new(4.0, -1.0, 1.0), Vec3::Y);
    assert_eq!(t.stop, StopReason::CutAway);
    assert_eq!(t.pixel, [0.0; 3]);
    assert!(t.cut_words().unwrap().contains("removed all"));
    let miss = trace(&v, &tf, &s, Vec3::new(4.0, -1.0, 9.0), Vec3::Y);
    assert_eq!(miss.stop, StopReason::Missed);
    assert!(miss.cut_words().is_none());
    // A crop box alone (no plane) cuts away too; with no cut at all a ray outside missed.
    s.clip = Clip {
        crop_lo: Vec3::new(0.0, 0.0, 0.5),
        ..Clip::default()
    };
    let t = trace(&v, &tf, &s, Vec3::new(4.0, -1.0, 0.5), Vec3::Y);
    assert_eq!(t.stop, StopReason::CutAway);
    s.clip = Clip::default();
    let t = trace(&v, &tf, &s, Vec3::new(4.0, -1.0, 1.0), Vec3::Y);
    assert_ne!(t.stop, StopReason::CutAway);
    let miss = trace(&v, &tf, &s, Vec3::new(4.0, -1.0, 9.0), Vec3::Y);
    assert_eq!(miss.stop, StopReason::Missed);
}

#[test]
fn camera_inside_the_volume_and_in_the_removed_part() {
    let v = ramp();
    let tf = grey(0.0, 8.0, 0.5);
    let mut s = plain(0.5);
    s.method = Method::Maximum;
    // Eye at x = 1, inside; the plane (normal −x, position 0) removes x < 4: sampling starts at
    // the plane, not at the eye.
    s.clip = plane(Vec3::NEG_X, 0.0);
    let t = trace(&v, &tf, &s, Vec3::new(1.0, 1.0, 1.0), Vec3::X);
    assert_eq!(t.interval, Some([3.0, 7.0]));
    assert_eq!(t.box_interval, Some([0.0, 7.0]));
    assert_eq!(t.projected_value, Some(8.0));
    assert_eq!(t.samples[0].p_world[0], 4.0);
}

#[test]
fn thin_volumes_and_slices() {
    // A one-point volume: its box is one spacing wide; cropping its upper half keeps the lower.
    let v = constant([1, 1, 1], 1.0);
    let tf = white(0.5);
    let mut s = plain(0.1);
    s.clip.crop_hi = Vec3::new(0.5, 1.0, 1.0);
    let t = trace(&v, &tf, &s, Vec3::new(-2.0, 0.0, 0.0), Vec3::X);
    assert_eq!(t.interval, Some([1.5, 2.0]));
    // A crop of zero thickness is a slice: one sample where the ray crosses it.
    let v = ramp();
    s.clip = Clip {
        crop_lo: Vec3::new(0.5, 0.0, 0.0),
        crop_hi: Vec3::new(0.5, 1.0, 1.0),
        plane: None,
    };
    s.method = Method::Maximum;
    let t = trace(&v, &tf, &s, Vec3::new(-1.0, 1.0, 1.0), Vec3::X);
    assert_eq!(t.samples.len(), 1);
    assert_eq!(t.projected_value, Some(4.0));
}

/// The image of a cut volume: what the cut removes is background, the rest is the uncut image
/// wherever a ray's interval was not changed.
#[test]
fn a_cut_image_keeps_pixels_whose_rays_it_does_not_touch() {
    let v = ramp();
    let tf = grey(0.0, 8.0, 0.8);
    let (lo, hi) = v.bounds();
    let camera = Camera::framing(lo, hi, Vec3::new(0.0, 0.0, 1.0), Vec3::Y).unwrap();
    let mut s = plain(0.5);
    let full = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let (a, _) = render_with_threads(&full, &camera, 32, 16, 2).unwrap();
    // Keep x ≤ 4 (the left half as the camera sees it, looking along −z with +x right).
    s.clip = plane(Vec3::X, 0.0);
    let cut = Scene::new(&v, &tf, &s, camera.forward()).unwrap();
    let (b, _) = render_with_threads(&cut, &camera, 32, 16, 2).unwrap();
    let (mut same, mut gone) = (0, 0);
    for y in 0..16 {
        for x in 0..32 {
            let ray = camera.pixel_ray(x, y, 32, 16);
            let Some((t0, t1)) = intersect_box(&ray, lo, hi) else {
                continue;
            };
            let (x0, x1) = (ray.at(t0).x, ray.at(t1).x);
            let keep_all = x0.max(x1) < 3.9;
            let lose_all = x0.min(x1) > 4.1;
            if keep_all {
                assert_eq!(a.get(x, y), b.get(x, y));
                same += 1;
            } else if lose_all {
                assert_eq!(b.get(x, y), Vec3::ZERO);
                gone += 1;
            }
        }
    }
    assert!(same >= 20 && gone >= 20, "{same} kept, {gone} removed");
}
