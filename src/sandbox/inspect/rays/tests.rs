//! The inspection's tests (and the small scenes other modules' tests share).

use super::*;
use std::sync::Arc;
use voxcast_core::builtin::load_builtin;
use voxcast_core::settings::RenderSettings;

pub(crate) fn scene(name: &str) -> (VolumeState, RenderState) {
    let volume = load_builtin(name).unwrap().volume;
    let p = voxcast_core::preset::for_volume(volume.name()).unwrap();
    let render_state = RenderState {
        transfer: p.transfer.clone(),
        settings: p.settings_over(&RenderSettings::default()).unwrap(),
        depth_termination: true,
    };
    let volume = VolumeState {
        volume: Arc::new(volume.into()),
        source: format!("builtin:{name}"),
        preset: Some(p),
    };
    (volume, render_state)
}

/// On screen a ray's samples are step · sin θ apart: the sphere keeps 0.3 of that, with a
/// floor for rays seen end-on.
#[test]
fn spheres_shrink_with_the_rays_foreshortening() {
    let f = Vec3::NEG_Z;
    assert!((sphere_radius_seen(1.0, Vec3::X, f) - 1.0).abs() < 1e-6);
    let oblique = Vec3::new(1.0, 0.0, -1.0);
    assert!((sphere_radius_seen(1.0, oblique, f) - 0.5f32.sqrt()).abs() < 1e-6);
    assert_eq!(sphere_radius_seen(1.0, Vec3::NEG_Z, f), END_ON_FLOOR);
}

/// Neighbouring samples never merge: on every embedded volume at its own step (the
/// lecture's voxel once showed 14 samples as one "sausage") and at a tiny step.
#[test]
fn sample_spheres_leave_a_gap() {
    for (name, _) in voxcast_core::builtin::DATASETS {
        let (volume, mut render) = scene(name);
        for step in [None, Some(0.01)] {
            if let Some(s) = step {
                render.settings.step = voxcast_core::step::Length::Voxels(s);
            }
            let voxel = volume.volume.spacing().min_element();
            let spacing = render.settings.step.world(voxel);
            let r = sphere_radius(&volume, &render);
            assert!(
                r > 0.0 && 2.0 * r < 0.7 * spacing,
                "{name}: r {r}, step {spacing}"
            );
        }
    }
}

#[test]
fn every_pixel_gets_the_cores_trace_and_pixel() {
    let (volume, render_state) = scene("bucky");
    let mut vc = VirtualCamera::framing(&volume, None).unwrap();
    (vc.width, vc.height) = (8, 8);
    let mut inspection = Inspection::default();
    compute(&volume, &render_state, &vc, 1_000_000, &mut inspection);
    let traces = inspection.traces.as_ref().unwrap();
    assert_eq!(traces.len(), 64);
    let scene = Scene::new(
        &volume.volume,
        &render_state.transfer,
        &render_state.settings,
        vc.view.forward(),
    )
    .unwrap();
    let image = inspection.image.as_ref().unwrap();
    for (i, trace) in traces.iter().enumerate() {
        let (x, y) = (i as u32 % 8, i as u32 / 8);
        let want = trace_ray(&scene, &vc.view.pixel_ray(x, y, 8, 8), [x, y]);
        assert_eq!(*trace, want);
        assert_eq!(image.get(x, y).to_array(), trace.pixel, "pixel {x},{y}");
    }
    assert_eq!(
        inspection.samples,
        traces.iter().map(|t| t.samples.len()).sum::<usize>()
    );
}

#[test]
fn the_budget_drops_the_samples_with_a_message() {
    let (volume, render_state) = scene("bucky");
    let mut vc = VirtualCamera::framing(&volume, None).unwrap();
    (vc.width, vc.height) = (8, 8);
    let mut inspection = Inspection::default();
    compute(&volume, &render_state, &vc, 50, &mut inspection);
    assert!(inspection.traces.is_none());
    assert!(inspection.message.as_ref().unwrap().contains("50"));
    assert_eq!(inspection.paths.len(), 64, "the rays are still drawn");
}

/// The systems as the sandbox runs them, without rendering.
fn app(width: u32) -> App {
    let (volume, render_state) = scene("bucky");
    let mut vc = VirtualCamera::framing(&volume, None).unwrap();
    vc.width = width;
    vc.height = width;
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, AssetPlugin::default()))
        .init_asset::<Mesh>()
        .init_asset::<StandardMaterial>()
        .insert_resource(volume)
        .insert_resource(render_state)
        .add_plugins(plugin);
    app.world_mut().spawn(vc);
    app
}

/// Runs frames until the tracing started by the last change has arrived.
fn settle(app: &mut App) {
    for _ in 0..5000 {
        app.update();
        if app.world().resource::<InspectJob>().task.is_none() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(1));
    }
    panic!("the tracing never finished");
}

fn spheres(app: &mut App) -> (usize, usize) {
    let mut q = app.world_mut().query::<(&SampleSphere, &Visibility)>();
    let all: Vec<_> = q.iter(app.world()).map(|(_, v)| *v).collect();
    let shown = all.iter().filter(|v| **v == Visibility::Visible).count();
    (all.len(), shown)
}

#[test]
fn sphere_entities_follow_the_samples_and_the_animation() {
    let mut app = app(4);
    settle(&mut app);
    let expected = app.world().resource::<Inspection>().samples;
    assert!(expected > 0);
    let (n, shown) = spheres(&mut app);
    assert_eq!(n, expected);
    assert!(shown < n, "the rays have only just started");
    app.world_mut().resource_mut::<RayAnimation>().skip();
    app.update();
    assert_eq!(spheres(&mut app).1, expected);
    // More pixels: more spheres; fewer again: the spare ones leave the samples.
    for w in [6, 2] {
        let mut q = app.world_mut().query::<&mut VirtualCamera>();
        q.single_mut(app.world_mut()).unwrap().width = w;
        settle(&mut app);
        let want = app.world().resource::<Inspection>().samples;
        assert_eq!(spheres(&mut app).0, want, "{w} pixels across");
    }
}

#[test]
fn ray_indices_and_pixels_invert_each_other() {
    let size = UVec2::new(5, 3);
    for i in 0..15 {
        assert_eq!(ray_index(ray_pixel(i, size), size), i);
    }
    assert_eq!(ray_pixel(7, size), UVec2::new(2, 1));
}

#[test]
fn nothing_is_traced_again_unless_something_changed() {
    let mut app = app(4);
    settle(&mut app);
    let first = app.world().resource::<Inspection>().generation;
    for _ in 0..3 {
        app.update();
    }
    assert_eq!(app.world().resource::<Inspection>().generation, first);
    app.world_mut()
        .resource_mut::<RenderState>()
        .settings
        .cutoff = 0.5;
    settle(&mut app);
    assert_eq!(app.world().resource::<Inspection>().generation, first + 1);
}

#[test]
fn selecting_a_ray_shows_only_its_samples() {
    let mut app = app(4);
    settle(&mut app);
    app.world_mut().resource_mut::<RayAnimation>().skip();
    let pixel = UVec2::new(2, 1);
    app.world_mut().resource_mut::<RaySelection>().selected = Some(pixel);
    app.update();
    let own = app
        .world()
        .resource::<Inspection>()
        .traces
        .as_ref()
        .unwrap()[6]
        .samples
        .len();
    assert_eq!(spheres(&mut app).1, own);
}
