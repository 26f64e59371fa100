//! The volume as a layer (the sandbox's CPU live view): over a plain background it is exactly
//! the rendered image, and rays stop at opaque spheres as the GPU preview's depth prepass
//! stops them.

mod common;

use std::sync::atomic::AtomicBool;
use voxcast_core::builtin::load_builtin;
use voxcast_core::camera::Camera;
use voxcast_core::composite::Method;
use voxcast_core::glam::Vec3;
use voxcast_core::preset;
use voxcast_core::ray::Ray;
use voxcast_core::render::{Occluder, render, render_layer};
use voxcast_core::settings::RenderSettings;
use voxcast_core::trace::Scene;

#[test]
fn the_layer_over_the_background_is_the_render() {
    for name in ["bunny", "shells", "head"] {
        let volume = voxcast_core::Prepared::from(load_builtin(name).unwrap().volume);
        let p = preset::for_volume(volume.name()).unwrap();
        for (method, supersampling) in [
            (Method::Accumulate, 1),
            (Method::Maximum, 1),
            (Method::First, 1),
            (Method::Accumulate, 2),
        ] {
            let mut s = p.settings_over(&RenderSettings::default()).unwrap();
            s.method = method;
            s.supersampling = supersampling;
            s.background = Vec3::new(0.1, 0.2, 0.3);
            let view = p.view.unwrap();
            let (lo, hi) = volume.bounds();
            let camera = Camera::framing(lo, hi, view.from, view.up).unwrap();
            let scene = Scene::new(&volume, &p.transfer, &s, camera.forward()).unwrap();
            let stop = AtomicBool::new(false);
            let (image, a) = render(&scene, &camera, 64, 48, &|_, _| {}, &stop).unwrap();
            let (layer, b) =
                render_layer(&scene, &camera, (64, 48), &[], &|_, _| {}, &stop).unwrap();
            assert_eq!(a, b, "{name} {method:?}: the same work");
            let over = layer.over(s.background);
            let (x, y) = (image.to_rgb8(), over.to_rgb8());
            if supersampling == 1 {
                assert_eq!(x, y, "{name} {method:?}: bit for bit");
            } else {
                let worst = x
                    .pixels()
                    .zip(y.pixels())
                    .flat_map(|(p, q)| (0..3).map(move |c| p.0[c].abs_diff(q.0[c])))
                    .max()
                    .unwrap();
                assert!(worst <= 1, "{name} supersampled: {worst}/255");
            }
        }
    }
}

/// Every pixel whose ray meets a sphere lies in the sphere's screen bounds (so culling the
/// spheres per tile never loses a hit), for random spheres and cameras, perspective and
/// orthographic, the eye near or inside some spheres.
#[test]
fn a_spheres_screen_bounds_hold_every_pixel_that_sees_it() {
    use voxcast_core::camera::Projection;
    use voxcast_core::render::screen_bounds;
    let mut seed = 7u32;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        (seed % 10_000) as f32 / 10_000.0
    };
    let (w, h) = (48u32, 32u32);
    let mut checked = 0;
    for case in 0..40 {
        let eye = Vec3::new(
            rnd() * 40.0 - 20.0,
            rnd() * 40.0 - 20.0,
            30.0 + rnd() * 10.0,
        );
        let projection = if case % 3 == 0 {
            Projection::Orthographic { height: 30.0 }
        } else {
            Projection::Perspective {
                fov_y_deg: 20.0 + rnd() * 80.0,
            }
        };
        let camera = Camera::new(eye, Vec3::ZERO, Vec3::Y, projection).unwrap();
        for _ in 0..6 {
            let o = Occluder {
                centre: Vec3::new(
                    rnd() * 30.0 - 15.0,
                    rnd() * 30.0 - 15.0,
                    rnd() * 50.0 - 10.0,
                ),
                radius: 0.2 + rnd() * 6.0,
                color: Vec3::ONE,
            };
            let bounds = screen_bounds(&o, &camera, w, h);
            for py in 0..h {
                for px in 0..w {
                    let ray = camera.pixel_ray(px, py, w, h);
                    if o.hit(&ray).is_none() {
                        continue;
                    }
                    checked += 1;
                    if let Some([x0, y0, x1, y1]) = bounds {
                        let (x, y) = (px as f32 + 0.5, py as f32 + 0.5);
                        assert!(
                            x >= x0 - 0.5 && x <= x1 + 0.5 && y >= y0 - 0.5 && y <= y1 + 0.5,
                            "case {case}: pixel ({px}, {py}) sees {o:?} outside {bounds:?}"
                        );
                    }
                }
            }
        }
    }
    assert!(checked > 500, "only {checked} hits checked");
}

#[test]
fn a_sphere_hit_is_the_closed_form_distance() {
    let o = Occluder {
        centre: Vec3::new(10.0, 0.0, 0.0),
        radius: 2.0,
        color: Vec3::ONE,
    };
    let ray = |origin: Vec3, dir: Vec3| Ray::new(origin, dir).unwrap();
    assert_eq!(o.hit(&ray(Vec3::ZERO, Vec3::X)), Some(8.0));
    // Grazing: the tangent line touches at one point.
    let t = o.hit(&ray(Vec3::new(0.0, 2.0, 0.0), Vec3::X)).unwrap();
    assert!((t - 10.0).abs() < 1e-3, "{t}");
    assert_eq!(o.hit(&ray(Vec3::new(0.0, 2.01, 0.0), Vec3::X)), None);
    // Behind the origin, and from inside.
    assert_eq!(o.hit(&ray(Vec3::ZERO, Vec3::NEG_X)), None);
    assert_eq!(o.hit(&ray(Vec3::new(10.5, 0.0, 0.0), Vec3::Y)), Some(0.0));
}

/// A sphere in the middle of a constant fog: rays through it stop at its front and show its
/// colour through the fog in front (`C + (1 − O)·sphere`, with `C` and `O` the fog's up to the
/// sphere); the others are untouched.
#[test]
fn rays_stop_at_spheres() {
    let volume = common::constant([21, 21, 21], 1.0);
    let tf = common::white(0.05);
    let s = common::plain(0.5);
    let camera = Camera::new(
        Vec3::new(10.0, 10.0, 40.0),
        Vec3::new(10.0, 10.0, 10.0),
        Vec3::Y,
        voxcast_core::camera::Projection::Perspective { fov_y_deg: 30.0 },
    )
    .unwrap();
    let scene = Scene::new(&volume, &tf, &s, camera.forward()).unwrap();
    let stop = AtomicBool::new(false);
    let red = Vec3::new(1.0, 0.0, 0.0);
    let sphere = Occluder {
        centre: Vec3::splat(10.0),
        radius: 3.0,
        color: red,
    };
    let (free, _) = render_layer(&scene, &camera, (33, 33), &[], &|_, _| {}, &stop).unwrap();
    let (held, _) = render_layer(&scene, &camera, (33, 33), &[sphere], &|_, _| {}, &stop).unwrap();
    let centre = (16 * 33 + 16) as usize;
    let corner = 0usize;
    assert_eq!(held.pixels[corner], free.pixels[corner]);
    // The centre ray: fog from the box's face (z = 20) to the sphere's front (z = 13).
    let mut ray = Ray::new(Vec3::new(10.0, 10.0, 40.0), Vec3::NEG_Z).unwrap();
    ray.t_max = sphere.hit(&ray).unwrap();
    assert!((ray.t_max - 27.0).abs() < 1e-4, "{}", ray.t_max);
    let front = voxcast_core::trace::trace_ray(&scene, &ray, [0, 0]);
    assert!(front.opacity > 0.1 && front.opacity < free.pixels[centre].w);
    let expect = Vec3::from(front.color) + red * (1.0 - front.opacity);
    let got = held.pixels[centre];
    assert_eq!(got.w, 1.0);
    assert!(
        (got.truncate() - expect).abs().max_element() < 1e-6,
        "{got} vs {expect}"
    );
}
