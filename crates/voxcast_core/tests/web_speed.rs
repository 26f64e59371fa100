//! A measurement, not a check (ignored unless asked for; `benches/web.sh` runs it): the exact
//! render of the bunny's preset view at the page's scene size (896×669) on one thread, with the
//! widest lanes this target has and with none, the median of seven, and with the lanes in
//! slices of 20 ms as the page runs it (which costs nothing measurable). Built for wasm32 and run
//! under Node (V8, the engine of chromium's page) and built natively, it sets the page's core
//! beside the desktop's, the same code on the same view:
//!
//!     cargo test --release -p voxcast_core --test web_speed -- --ignored --nocapture
//!     CARGO_TARGET_WASM32_UNKNOWN_UNKNOWN_RUNNER=~/.cache/voxcast-tools/bin/wasm-bindgen-test-runner \
//!         cargo test --release -p voxcast_core --target wasm32-unknown-unknown --test web_speed -- --include-ignored --nocapture

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::{console_log as println, wasm_bindgen_test as test};

use std::sync::atomic::AtomicBool;
use voxcast_core::builtin::load_builtin;
use voxcast_core::camera::Camera;
use voxcast_core::render::{Job, TileSlices, on_threads, render_in, render_with_threads};
use voxcast_core::settings::RenderSettings;
use voxcast_core::slices::{Duration, until_done};
use voxcast_core::trace::{Scene, Vectors, lane_instructions};
use voxcast_core::{Prepared, preset};
use web_time::Instant;

/// The page's scene at 1280×720 in headless chromium (tests/browser.rs).
const SIZE: (u32, u32) = (896, 669);

#[test]
#[ignore = "a measurement: benches/web.sh runs it"]
fn the_bunny_on_one_thread() {
    let volume = Prepared::from(load_builtin("bunny").unwrap().volume);
    let p = preset::for_volume(volume.name()).unwrap();
    let settings = p.settings_over(&RenderSettings::default()).unwrap();
    let view = p.view.unwrap();
    let (lo, hi) = volume.bounds();
    let camera = Camera::framing(lo, hi, view.from, view.up).unwrap();
    let scene = Scene::new(&volume, &p.transfer, &settings, camera.forward()).unwrap();
    let target = if cfg!(target_arch = "wasm32") {
        "wasm32"
    } else {
        "native"
    };
    for vectors in [Vectors::Wide, Vectors::Off] {
        let mut s = scene.clone();
        s.simd = vectors;
        let lanes = lane_instructions(&s).unwrap_or("no lanes");
        let mut times = Vec::new();
        let mut samples = 0;
        for _ in 0..7 {
            let start = Instant::now();
            let (_, stats) = render_with_threads(&s, &camera, SIZE.0, SIZE.1, 1).unwrap();
            times.push(start.elapsed().as_secs_f64());
            samples = stats.positions;
        }
        let median = voxcast_core::numbers::median(&times).expect("seven renders");
        println!(
            "web_speed {target}, {lanes}: the bunny {}×{} in {:.1} ms (median of 7), {:.0} M sample positions/s",
            SIZE.0,
            SIZE.1,
            median * 1e3,
            samples as f64 / median / 1e6
        );
        if vectors == Vectors::Wide {
            sliced(&s, &camera, &format!("{target}, {lanes}"));
        }
    }
}

/// The same render as the page runs it: in slices of 20 ms (`tasks::SLICE`), each a call of
/// [`render_in`] that carries on where the last stopped, with nothing between them.
fn sliced(scene: &voxcast_core::trace::Scene<'_>, camera: &Camera, label: &str) {
    let cancel = AtomicBool::new(false);
    let job = Job::plain(scene, camera, SIZE, &|_, _| {}, &cancel);
    let mut times = Vec::new();
    let mut calls = 0;
    for _ in 0..7 {
        let mut tiles = TileSlices::default();
        let start = Instant::now();
        let run = || {
            until_done(Duration::from_millis(20), |d| {
                render_in(&job, &mut tiles, d)
            })
        };
        (_, calls) = on_threads(1, run).expect("not cancelled");
        times.push(start.elapsed().as_secs_f64());
    }
    let median = voxcast_core::numbers::median(&times).expect("seven renders");
    println!(
        "web_speed {label}, in {calls} slices of 20 ms: {:.1} ms (median of 7)",
        median * 1e3
    );
}
