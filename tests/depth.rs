//! Depth-prepass termination on real Vulkan (lavapipe): a point light's marker, an opaque
//! sphere, stands in the middle of a semi-transparent volume. With termination on, every
//! preview ray that meets the sphere composites only the samples in front of it and then shows
//! the sphere through what remains — exactly the core's ray clipped at the sphere
//! (`Ray::t_max`), blended over the marker's colour. Rays that miss the sphere are the plain
//! render's. With termination off the rays pass the sphere and the picture differs.
//!
//! Ignored without a Vulkan device unless `VOXCAST_REQUIRE_GPU=1` (as `.ci/run` sets it).

mod support;

use glam::Vec3;
use std::path::{Path, PathBuf};
use std::process::Command;
use voxcast_core::builtin::load_builtin;
use voxcast_core::camera::Camera;
use voxcast_core::composite::blend_background;
use voxcast_core::image_out::to_u8;
use voxcast_core::marker::{LIGHT_MARKER_COLOR, light_marker_radius};
use voxcast_core::render::Occluder;
use voxcast_core::settings::RenderSettings;
use voxcast_core::shade::Light;
use voxcast_core::trace::{Scene, trace_ray};
use voxcast_core::transfer::TransferFunction;

use support::{Completion, Outcome, skipped_for_want_of_a_gpu};

const SIZE: u32 = 256;

fn main() {
    support::run(&[(
        "the_lights_marker_stops_the_preview_rays",
        the_lights_marker_stops_the_preview_rays,
    )])
}

fn out_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/out/depth")
}

/// sRGB decoding and encoding of a display value (what the preview's target does).
fn to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}
fn to_srgb(l: f32) -> f32 {
    if l <= 0.0031308 {
        l * 12.92
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// Screenshot of the preview with the given extra flags.
fn screenshot(
    name: &str,
    tf: &Path,
    camera: &Path,
    light: Vec3,
    extra: &[&str],
) -> Result<image::RgbImage, Outcome> {
    let path = out_dir().join(name);
    let output = Command::new(env!("CARGO_BIN_EXE_voxcast"))
        .args(["--volume", "builtin:shells", "--shading", "off", "--size"])
        .arg(format!("{SIZE}x{SIZE}"))
        .arg("--tf")
        .arg(tf)
        .arg("--camera")
        .arg(camera)
        .arg("--light")
        .arg(format!("point:{},{},{}", light.x, light.y, light.z))
        .args(extra)
        .arg("--screenshot")
        .arg(&path)
        .output()
        .expect("the binary runs");
    if !output.status.success() {
        let err = String::from_utf8_lossy(&output.stderr);
        if let Some(skip) = skipped_for_want_of_a_gpu(&err) {
            return Err(skip);
        }
        panic!("the screenshot failed:\n{err}");
    }
    Ok(image::open(&path).unwrap().to_rgb8())
}

fn the_lights_marker_stops_the_preview_rays() -> Outcome {
    std::fs::create_dir_all(out_dir()).unwrap();
    let volume = voxcast_core::Prepared::from(load_builtin("shells").unwrap().volume);
    let (lo, hi) = volume.bounds();
    let transfer = TransferFunction::ramp(0.0, 255.0, 0.06).unwrap();
    let tf = out_dir().join("tf.json");
    std::fs::write(&tf, transfer.to_json()).unwrap();
    let camera = Camera::framing(lo, hi, Vec3::new(1.0, 0.6, 2.0), Vec3::Y).unwrap();
    let cam = out_dir().join("camera.json");
    std::fs::write(&cam, camera.to_json()).unwrap();
    // The light a little off the centre, so the sphere has volume in front and behind.
    let centre = (lo + hi) * 0.5 + Vec3::new(3.0, -2.0, 1.0);
    let on = match screenshot("on.png", &tf, &cam, centre, &[]) {
        Ok(on) => on,
        Err(skip) => return skip,
    };
    let Ok(off) = screenshot("off.png", &tf, &cam, centre, &["--no-depth-termination"]) else {
        panic!("the first screenshot worked, the second did not");
    };

    let settings = RenderSettings {
        shading: false,
        phong: voxcast_core::shade::Phong {
            lights: vec![voxcast_core::shade::LightSource::new(Light::Point(centre))],
            ..Default::default()
        },
        ..RenderSettings::default()
    };
    let scene = Scene::new(&volume, &transfer, &settings, camera.forward()).unwrap();
    let rays = camera.rays(SIZE, SIZE);
    let radius = light_marker_radius(lo, hi);
    let marker = LIGHT_MARKER_COLOR;
    let marker_sphere = Occluder {
        centre,
        radius,
        color: marker,
    };
    let (mut inside, mut inside_ok, mut worst_inside) = (0, 0, 0i32);
    let (mut outside, mut worst_outside, mut off_worst) = (0, 0i32, 0i32);
    for y in 0..SIZE {
        for x in 0..SIZE {
            let mut ray = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
            // The marker is a tessellated sphere: judge only pixels well inside or well outside
            // its silhouette.
            let miss = (ray.origin - centre).cross(ray.dir).length() / radius;
            let got = on.get_pixel(x, y).0.map(i32::from);
            if miss < 0.8 {
                ray.t_max = marker_sphere.hit(&ray).unwrap();
                let t = trace_ray(&scene, &ray, [x, y]);
                let (c, o) = (Vec3::from_array(t.color), t.opacity);
                let front = blend_background(c, o, settings.background);
                let want = to_u8(Vec3::from_array([0, 1, 2].map(|i| {
                    to_srgb(to_linear(front[i].min(1.0)) + (1.0 - o) * to_linear(marker[i]))
                })))
                .map(i32::from);
                let err = (0..3).map(|i| (got[i] - want[i]).abs()).max().unwrap();
                inside += 1;
                inside_ok += (err <= 2) as u32;
                worst_inside = worst_inside.max(err);
                let off_px = off.get_pixel(x, y).0.map(i32::from);
                off_worst =
                    off_worst.max((0..3).map(|i| (off_px[i] - want[i]).abs()).max().unwrap());
            } else if miss > 1.3 {
                let t = trace_ray(&scene, &ray, [x, y]);
                let want = to_u8(Vec3::from_array(t.pixel)).map(i32::from);
                let err = (0..3).map(|i| (got[i] - want[i]).abs()).max().unwrap();
                outside += 1;
                worst_outside = worst_outside.max(err);
            }
        }
    }
    println!(
        "sphere pixels: {inside} ({inside_ok} within 2/255, worst {worst_inside}/255); \
         others: {outside} (worst {worst_outside}/255); termination off: worst {off_worst}/255"
    );
    assert!(
        inside > 50,
        "the sphere covers too few pixels to judge: {inside}"
    );
    // A sample may fall on either side of a facet of the tessellated sphere.
    assert!(
        inside_ok as f32 >= 0.97 * inside as f32 && worst_inside <= 4,
        "sphere pixels"
    );
    assert!(
        worst_outside <= 2,
        "rays that miss the marker: {worst_outside}/255"
    );
    assert!(
        off_worst > 8,
        "without termination the picture should differ ({off_worst}/255)"
    );
    Ok(Completion::Completed)
}
