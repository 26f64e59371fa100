//! The CPU live view's tests in a windowless app: frames, refinement, cost and depth views.

use super::*;
use crate::sandbox::shared::state::{MainCamera, View};

/// A windowless app with the live view on the CPU, a 64×48 window and the bunny.
fn app() -> App {
    let (volume, render) = crate::sandbox::inspect::rays::tests::scene("bunny");
    let (lo, hi) = volume.volume.bounds();
    let view = CoreCamera::framing(lo, hi, Vec3::new(1.0, 0.3, 0.8), Vec3::Y).unwrap();
    let mut app = App::new();
    app.add_plugins(MinimalPlugins)
        .insert_resource(volume)
        .insert_resource(render)
        .insert_resource(PreviewSettings {
            backend: Backend::Cpu,
            backend_chosen: true,
            ..default()
        })
        .init_resource::<Assets<StandardMaterial>>()
        .add_plugins((plugin, crate::sandbox::shared::render_change::plugin));
    crate::sandbox::shared::schedule::configure(&mut app);
    app.world_mut().spawn((MainCamera, View(view)));
    crate::sandbox::shared::viewport::spawn_test_window(app.world_mut(), 64, 48);
    app
}

fn until_exact(app: &mut App) -> u32 {
    for frame in 0..2000 {
        app.update();
        let live = app.world().resource::<LiveView>();
        if live.shown.as_ref().is_some_and(|f| f.full()) && live.job.is_none() {
            return frame;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    panic!("the live view never reached the full resolution");
}

/// At rest the live view refines to the exact render: the same pixels as Render image.
#[test]
fn at_rest_the_live_view_is_the_render() {
    let mut app = app();
    until_exact(&mut app);
    let live = app.world().resource::<LiveView>();
    let frame = live.shown.as_ref().unwrap();
    assert_eq!(frame.size, UVec2::new(64, 48));
    let key = &frame.key;
    let volume = app.world().resource::<VolumeState>().volume.clone();
    let scene = Scene::new(&volume, &key.transfer, &key.settings, key.camera.forward()).unwrap();
    let (image, _) = voxcast_core::render::render(
        &scene,
        &key.camera,
        64,
        48,
        &|_, _| {},
        &AtomicBool::new(false),
    )
    .unwrap();
    let expect: Vec<[u8; 3]> = image.to_rgb8().pixels().map(|p| p.0).collect();
    assert!(frame.rgb == expect, "the live view differs from the render");
    assert!(live.generation >= 2, "coarse first, then refined");
}

/// An image as the live view's display values.
fn displayed(image: &voxcast_core::image_out::LinearImage) -> Vec<[u8; 3]> {
    image.pixels.iter().map(|p| to_u8(*p)).collect()
}

/// The core's cost map of the live frame's view, at the window's 64×48.
fn cores_map(app: &App, key: &LiveKey) -> voxcast_core::cost::CostMap {
    let volume = app.world().resource::<VolumeState>().volume.clone();
    let scene = Scene::new(&volume, &key.transfer, &key.settings, key.camera.forward()).unwrap();
    let quiet = AtomicBool::new(false);
    voxcast_core::cost::render_cost(&scene, &key.camera, (64, 48), &|_, _| {}, &quiet).unwrap()
}

/// A cost view at rest is the core's cost map of the view, on its fixed scale, whichever
/// backend draws the picture; back to the picture, the render returns.
#[test]
fn the_cost_view_at_rest_is_the_cores_map() {
    let mut app = app();
    {
        let mut p = app.world_mut().resource_mut::<PreviewSettings>();
        p.backend = Backend::Gpu;
        p.cost_view = Some(CostView::Samples);
        assert!(
            p.cpu_live() && !p.gpu_live(),
            "the core counts, the GPU rests"
        );
    }
    until_exact(&mut app);
    let live = app.world().resource::<LiveView>();
    let frame = live.shown.as_ref().unwrap();
    let key = &frame.key;
    assert_eq!(key.cost_view, Some(CostView::Samples));
    let map = cores_map(&app, key);
    assert!(
        frame.rgb == displayed(&map.image(CostView::Samples)),
        "the live cost view differs from the core's map"
    );
    assert_eq!(
        frame.legend,
        Some(voxcast_core::cost::scale_words(
            map.full_scale,
            map.max(CostView::Samples)
        ))
    );
    assert!(live.status().contains("exact counts"), "{}", live.status());
    app.world_mut().resource_mut::<PreviewSettings>().cost_view = None;
    app.world_mut().resource_mut::<PreviewSettings>().backend = Backend::Cpu;
    until_exact(&mut app);
    let live = app.world().resource::<LiveView>();
    assert_eq!(live.shown.as_ref().unwrap().legend, None);
}

/// With First, the depth view: each pixel the core's depth image, and the scale in words.
#[test]
fn the_depth_view_is_firsts_depth_image() {
    let mut app = app();
    app.world_mut()
        .resource_mut::<RenderState>()
        .settings
        .method = voxcast_core::composite::Method::First;
    app.world_mut().resource_mut::<PreviewSettings>().cost_view = Some(CostView::Depth);
    until_exact(&mut app);
    let frame = app.world().resource::<LiveView>().shown.as_ref().unwrap();
    let key = &frame.key;
    let map = cores_map(&app, key);
    assert!(
        frame.rgb == displayed(&map.image(CostView::Depth)),
        "the live depth differs from the core's"
    );
    let depth = map.depth.expect("First keeps its depth");
    assert!(depth.range().is_some(), "the bunny is hit");
    assert_eq!(frame.legend, Some(depth.scale_words()));
}

/// A changed view leaves the old frame out of date and brings a new one for the new view.
#[test]
fn a_new_view_brings_a_new_frame() {
    let mut app = app();
    until_exact(&mut app);
    let mut q = app
        .world_mut()
        .query_filtered::<&mut View, With<MainCamera>>();
    let mut view = q.single_mut(app.world_mut()).unwrap();
    let moved = CoreCamera::new(
        view.0.eye + Vec3::new(5.0, 0.0, 0.0),
        view.0.target,
        view.0.up,
        view.0.projection,
    )
    .unwrap();
    view.0 = moved;
    app.update();
    let live = app.world().resource::<LiveView>();
    assert!(live.shown.as_ref().unwrap().key.camera != moved, "not yet");
    until_exact(&mut app);
    let live = app.world().resource::<LiveView>();
    assert_eq!(live.shown.as_ref().unwrap().key.camera, moved);
}

/// Once the view rests, a quick frame of the view it left is dropped (its render would
/// only delay the resting one); while it moves, quick frames finish; a refinement lasts
/// only as long as its view.
#[test]
fn a_resting_view_does_not_wait_for_a_quick_frame_of_another() {
    let mut app = app();
    until_exact(&mut app);
    let old = app
        .world()
        .resource::<LiveView>()
        .shown
        .as_ref()
        .unwrap()
        .key
        .clone();
    let mut new = old.clone();
    new.camera = CoreCamera::new(
        old.camera.eye + Vec3::X,
        old.camera.target,
        old.camera.up,
        old.camera.projection,
    )
    .unwrap();
    let volume = app.world().resource::<VolumeState>().volume.clone();
    let job = |key: &LiveKey, refine| start(key.clone(), UVec2::ONE, volume.clone(), refine, true);
    let quick = job(&old, false);
    assert!(keeps_job(&quick, &old, true), "its own view");
    assert!(
        keeps_job(&quick, &new, false),
        "the view moves on: it finishes"
    );
    assert!(
        !keeps_job(&quick, &new, true),
        "the view rests elsewhere: dropped"
    );
    let refining = job(&old, true);
    assert!(keeps_job(&refining, &old, true));
    assert!(!keeps_job(&refining, &new, false));
    assert!(!keeps_job(&refining, &new, true));
}

#[test]
fn software_rasterizers_get_the_cpu() {
    assert_eq!(
        Backend::for_adapter("llvmpipe (LLVM 15.0.6, 256 bits)", "Cpu"),
        Backend::Cpu
    );
    assert_eq!(
        Backend::for_adapter("Microsoft Basic Render Driver", "Other"),
        Backend::Cpu
    );
    assert_eq!(
        Backend::for_adapter("NVIDIA GeForce RTX 4070", "DiscreteGpu"),
        Backend::Gpu
    );
}

/// In a browser's WebGPU wgpu names no adapter: the browser's name for it is read, and its
/// fallback adapter (chromium's SwiftShader: "google swiftshader") is a software rasterizer.
#[test]
fn a_browsers_webgpu_fallback_adapter_gets_the_cpu() {
    use crate::sandbox::shared::quality::adapter_identity;
    let choose = |name: &str, browser: Option<(String, bool)>| {
        let (name, kind) = adapter_identity(name, "Other", browser.as_ref());
        Backend::for_adapter(&name, &kind)
    };
    assert_eq!(
        choose("", Some(("google swiftshader".into(), true))),
        Backend::Cpu
    );
    assert_eq!(
        choose("", Some(("".into(), true))),
        Backend::Cpu,
        "by the flag alone"
    );
    assert_eq!(
        choose("", Some(("nvidia ampere".into(), false))),
        Backend::Gpu
    );
    assert_eq!(
        choose("", None),
        Backend::Gpu,
        "nothing known: the GPU, as before"
    );
    // Where wgpu names the adapter (the desktop, WebGL2), its name is the one read.
    assert_eq!(
        adapter_identity("llvmpipe (LLVM 15.0.6, 256 bits)", "Cpu", None),
        ("llvmpipe (LLVM 15.0.6, 256 bits)".into(), "Cpu".into())
    );
    assert_eq!(
        choose("AMD Radeon", Some(("google swiftshader".into(), true))),
        Backend::Gpu
    );
}

/// A browser's SwiftShader is a software rasterizer too; and a GPU that refuses the
/// preview's pipeline hands the volume to the CPU, even where the GPU was asked for.
#[test]
fn a_gpu_that_cannot_run_the_preview_hands_it_to_the_cpu() {
    let swiftshader = "ANGLE (Google, Vulkan 1.3.0 (SwiftShader Device (Subzero) \
                       (0x0000C0DE)), SwiftShader driver)";
    assert_eq!(Backend::for_adapter(swiftshader, "Other"), Backend::Cpu);
    let mut app = App::new();
    app.insert_resource(PreviewSettings {
        backend: Backend::Gpu,
        backend_chosen: true,
        ..default()
    })
    .add_plugins(crate::sandbox::shared::render_change::plugin)
    .add_systems(
        Update,
        choose_backend.in_set(crate::sandbox::shared::schedule::Frame::Input),
    );
    crate::sandbox::shared::schedule::configure(&mut app);
    app.update();
    assert_eq!(
        app.world().resource::<PreviewSettings>().backend,
        Backend::Gpu
    );
    app.insert_resource(GpuFailed("WGSL `textureLoad` from depth textures".into()));
    app.update();
    assert_eq!(
        app.world().resource::<PreviewSettings>().backend,
        Backend::Cpu
    );
}

#[test]
fn a_quick_frame_fits_the_budget() {
    let full = UVec2::new(1280, 720);
    assert_eq!(quick_size(full, None), UVec2::new(160, 90));
    // 3 M pixels a second: 100 000 pixels in a thirtieth of a second.
    let s = quick_size(full, Some(3.0e6));
    let pixels = (s.x * s.y) as f64;
    assert!((pixels - 1.0e5).abs() < 2.0e3, "{s}");
    assert_eq!(quick_size(full, Some(1e12)), full);
    assert_eq!(quick_size(UVec2::ONE, Some(1.0)), UVec2::ONE);
}

#[test]
fn refinement_goes_to_full_when_it_is_quick() {
    let full = UVec2::new(1280, 720);
    let quick = UVec2::new(320, 180);
    assert_eq!(refined_size(quick, full, Some(1e7)), full);
    assert_eq!(refined_size(quick, full, Some(5e5)), UVec2::new(640, 360));
    assert_eq!(refined_size(quick, full, None), UVec2::new(640, 360));
    assert_eq!(refined_size(UVec2::new(1000, 600), full, None), full);
}

/// The live view's moving threads yield to the window's: they run at the lowest priority
/// (Linux), the resting pool's exact render at the window's own.
#[cfg(target_os = "linux")]
#[test]
fn the_moving_threads_run_below_the_window() {
    // SAFETY: getpriority on the calling thread reads its nice value and touches no memory.
    let nice = || unsafe { libc::getpriority(libc::PRIO_PROCESS, 0) };
    let window = nice();
    assert_eq!(moving_pool().install(nice), LIVE_NICE);
    assert_eq!(resting_pool().install(nice), window);
}
