//! Work done in slices (what a browser's page does, one thread drawing frames between them)
//! gives what one call gives, bit for bit: the picture, the layer with its spheres, the cost
//! map (and the picture with its cost map from one march) and the speed/accuracy trade, each
//! cut into as many slices as it has pieces.

use std::sync::atomic::AtomicBool;
use voxcast_core::builtin::load_builtin;
use voxcast_core::camera::Camera;
use voxcast_core::composite::Method;
use voxcast_core::cost::{render_cost, render_cost_in, render_with_cost_in};
use voxcast_core::glam::Vec3;
use voxcast_core::preset;
use voxcast_core::render::{
    Job, Occluder, TileSlices, render, render_in, render_layer_in, render_layer_with,
};
use voxcast_core::settings::RenderSettings;
use voxcast_core::slices::{Deadline, Duration, Step, until_done};
use voxcast_core::trace::Scene;

/// A slice that has passed its deadline before it starts: one tile a call.
const NOW: Duration = Duration::ZERO;

#[test]
fn a_render_in_slices_is_the_render() {
    let stop = AtomicBool::new(false);
    for (name, method, supersampling) in [
        ("bunny", Method::Accumulate, 1),
        ("head", Method::Maximum, 1),
        ("shells", Method::First, 2),
    ] {
        let volume = voxcast_core::Prepared::from(load_builtin(name).unwrap().volume);
        let p = preset::for_volume(volume.name()).unwrap();
        let mut s = p.settings_over(&RenderSettings::default()).unwrap();
        s.method = method;
        s.supersampling = supersampling;
        let (lo, hi) = volume.bounds();
        let view = p.view.unwrap();
        let camera = Camera::framing(lo, hi, view.from, view.up).unwrap();
        let scene = Scene::new(&volume, &p.transfer, &s, camera.forward()).unwrap();
        let size = (70, 45); // 5 × 3 tiles, the last row and column partial
        let tiles = 15;
        let job = Job::plain(&scene, &camera, size, &|_, _| {}, &stop);

        let whole = render(&scene, &camera, size.0, size.1, &|_, _| {}, &stop).unwrap();
        let mut state = TileSlices::default();
        let (sliced, calls) =
            until_done(NOW, |d| render_in(&job, &mut state, d)).expect("not cancelled");
        assert_eq!(calls, tiles, "{name}: one tile a call");
        assert_eq!(sliced, whole, "{name}: the picture and its counts");

        let spheres = [Occluder {
            centre: (lo + hi) * 0.5,
            radius: (hi - lo).length() * 0.1,
            color: Vec3::new(1.0, 0.5, 0.0),
        }];
        let layered = Job {
            occluders: &spheres,
            ..job
        };
        let whole =
            render_layer_with(&scene, &camera, size, &spheres, None, &|_, _| {}, &stop).unwrap();
        let mut state = TileSlices::default();
        let (sliced, _) = until_done(NOW, |d| render_layer_in(&layered, &mut state, d)).unwrap();
        assert_eq!(sliced, whole, "{name}: the layer with its sphere");

        let whole = render_cost(&scene, &camera, size, &|_, _| {}, &stop).unwrap();
        let mut state = TileSlices::default();
        let (sliced, _) = until_done(NOW, |d| render_cost_in(&job, &mut state, d)).unwrap();
        assert_eq!(sliced.pixels, whole.pixels, "{name}: the cost map");
        assert_eq!(sliced.stats, whole.stats);

        // Render image's one march: the picture and the cost map as the two marches give them.
        let picture = render(&scene, &camera, size.0, size.1, &|_, _| {}, &stop).unwrap();
        let mut state = TileSlices::default();
        let ((image, stats, cost), calls) =
            until_done(NOW, |d| render_with_cost_in(&job, &mut state, d)).unwrap();
        assert_eq!(calls, tiles, "{name}: one tile a call");
        assert_eq!(
            (image, stats),
            picture,
            "{name}: the picture, from one march"
        );
        assert_eq!(cost.pixels, whole.pixels, "{name}: its cost map");
        assert_eq!(cost.stats, whole.stats);
        assert_eq!(cost.full_scale, whole.full_scale);
        let bits = |d: &Option<voxcast_core::depth::DepthMap>| {
            d.as_ref()
                .map(|d| d.depth.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
        };
        assert_eq!(
            bits(&cost.depth),
            bits(&whole.depth),
            "{name}: First's depth"
        );
        assert_eq!(cost.depth.is_some(), method == Method::First);
    }
}

#[test]
fn slices_report_progress_and_stop_at_cancel() {
    let volume = voxcast_core::Prepared::from(load_builtin("bunny").unwrap().volume);
    let p = preset::for_volume(volume.name()).unwrap();
    let s = p.settings_over(&RenderSettings::default()).unwrap();
    let (lo, hi) = volume.bounds();
    let camera = Camera::framing(lo, hi, Vec3::Z, Vec3::Y).unwrap();
    let scene = Scene::new(&volume, &p.transfer, &s, camera.forward()).unwrap();
    let stop = AtomicBool::new(false);
    let seen = std::sync::Mutex::new(Vec::new());
    let progress = |done: usize, total: usize| seen.lock().unwrap().push((done, total));
    let job = Job::plain(&scene, &camera, (32, 32), &progress, &stop);
    let mut state = TileSlices::default();
    assert_eq!(
        render_in(&job, &mut state, Deadline::after(NOW)).unwrap(),
        Step::Paused
    );
    assert_eq!(state.fraction(), 0.25);
    assert_eq!(
        render_in(&job, &mut state, Deadline::after(NOW)).unwrap(),
        Step::Paused
    );
    assert_eq!(
        *seen.lock().unwrap(),
        [(1, 4), (2, 4)],
        "counted across slices"
    );
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    assert!(
        render_in(&job, &mut state, Deadline::NONE).is_err(),
        "cancelled"
    );
}
