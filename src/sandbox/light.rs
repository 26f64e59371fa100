//! The Light entity: a small opaque sphere standing where the point light is (or where a
//! directional light comes from), drawn with a gizmo, and dragged with the mouse in the plane
//! facing the camera. The settings' light is the single truth; the marker follows it, and a
//! drag writes it, so the preview and the CPU render always shade with the same light.
//!
//! The marker is a real mesh: inside the volume it writes depth and the preview's rays stop at
//! it. It is hidden while a comparison captures the preview (the CPU render has no meshes).

use super::mode::{Mode, Stage};
use super::preview::{FullQuality, Viewport};
use super::state::{MainCamera, RenderState, View, VolumeState};
use bevy::prelude::*;
use bevy::window::PrimaryWindow;
use bevy_egui::input::EguiWantsInput;
use voxcast_core::marker::{
    LIGHT_MARKER_COLOR, direction_from_marker, directional_marker_position, light_marker_radius,
};
use voxcast_core::ray::Ray;
use voxcast_core::shade::Light;

/// Marks the light's sphere.
#[derive(Component)]
pub struct LightMarker;

/// The drag under way: the plane the light moves in (through the marker, facing the camera).
#[derive(Resource, Default)]
pub struct LightDrag {
    plane: Option<(Vec3, Vec3)>,
}

impl LightDrag {
    pub fn active(&self) -> bool {
        self.plane.is_some()
    }
}

/// How much larger than the sphere the grab target is (a small sphere is hard to hit).
const GRAB_SLACK: f32 = 1.8;

/// The marker, in the window and headless alike.
pub(crate) fn marker_plugin(app: &mut App) {
    app.add_systems(Update, (spawn_marker, place_marker).chain());
}

/// Dragging and the gizmo (window only).
pub(super) fn plugin(app: &mut App) {
    app.init_resource::<LightDrag>().add_systems(
        Update,
        (
            drag_light.before(place_marker).in_set(super::Frame::Input),
            draw_ring.in_set(super::Frame::Show),
        ),
    );
}

/// Where the marker stands for `light`, `None` for the headlight (it moves with the camera).
fn marker_position(light: Light, volume: &VolumeState) -> Option<Vec3> {
    let (lo, hi) = volume.volume.bounds();
    match light {
        Light::Headlight => None,
        Light::Point(p) => Some(p),
        Light::Directional(d) => directional_marker_position(d, lo, hi),
    }
}

/// (Re)spawns the sphere when the mode changes (if its scene has one; it leaves with the mode)
/// or a volume is loaded (its size follows the volume).
fn spawn_marker(
    mut commands: Commands,
    volume: Res<VolumeState>,
    (mode, stage): (Res<State<Mode>>, Res<Stage>),
    existing: Query<Entity, With<LightMarker>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    if !(volume.is_changed() || mode.is_changed()) {
        return;
    }
    for e in &existing {
        commands.entity(e).despawn();
    }
    if !stage.light_marker {
        return;
    }
    let (lo, hi) = volume.volume.bounds();
    let c = LIGHT_MARKER_COLOR;
    commands.spawn((
        LightMarker,
        Mesh3d(
            meshes.add(
                Sphere::new(light_marker_radius(lo, hi))
                    .mesh()
                    .ico(3)
                    .unwrap(),
            ),
        ),
        MeshMaterial3d(materials.add(StandardMaterial {
            base_color: Color::srgb(c.x, c.y, c.z),
            unlit: true,
            ..default()
        })),
        Transform::default(),
        Visibility::Hidden,
        DespawnOnExit(*mode.get()),
        bevy::camera::visibility::RenderLayers::layer(super::live::OCCLUDER_LAYER),
    ));
}

/// Keeps the marker where the settings' light is.
fn place_marker(
    render: Res<RenderState>,
    volume: Res<VolumeState>,
    full: Option<Res<FullQuality>>,
    mut markers: Query<(&mut Transform, &mut Visibility), With<LightMarker>>,
) {
    let capturing = full.as_ref().is_some_and(|f| f.0);
    let at = marker_position(render.settings.phong.light, &volume);
    for (mut transform, mut visibility) in &mut markers {
        let want = match at {
            Some(_) if !capturing => Visibility::Visible,
            _ => Visibility::Hidden,
        };
        visibility.set_if_neq(want);
        if let Some(p) = at
            && transform.translation != p
        {
            transform.translation = p;
        }
    }
}

/// The ray under the cursor, from the main camera's view (shown in the viewport).
pub(super) fn cursor_ray(window: &Window, viewport: Option<&Viewport>, view: &View) -> Option<Ray> {
    let (min, size) = Viewport::of(viewport, window);
    let cursor = window.physical_cursor_position()? - min;
    let inside = cursor.cmpge(Vec2::ZERO).all() && cursor.cmplt(size.as_vec2()).all();
    inside.then(|| view.0.ray(cursor.x, cursor.y, size.x, size.y))
}

/// Whether `ray` meets the sphere at `centre` of `radius` ahead of it (or starts inside it):
/// the core's ray–sphere test, as the live view stops rays at the marker.
fn hits_sphere(ray: &Ray, centre: Vec3, radius: f32) -> bool {
    let sphere = voxcast_core::render::Occluder {
        centre,
        radius,
        color: Vec3::ZERO,
    };
    sphere.hit(ray).is_some()
}

#[allow(clippy::too_many_arguments)]
pub(super) fn drag_light(
    buttons: Res<ButtonInput<MouseButton>>,
    (window, viewport): (Query<&Window, With<PrimaryWindow>>, Option<Res<Viewport>>),
    egui: Option<Res<EguiWantsInput>>,
    views: Query<&View, With<MainCamera>>,
    markers: Query<(&Transform, &Visibility), With<LightMarker>>,
    volume: Res<VolumeState>,
    mut render: ResMut<RenderState>,
    mut drag: ResMut<LightDrag>,
) {
    if !buttons.pressed(MouseButton::Left) {
        drag.plane = None;
        return;
    }
    let (Ok(window), Ok(view)) = (window.single(), views.single()) else {
        return;
    };
    let Some(ray) = cursor_ray(window, viewport.as_deref(), view) else {
        return;
    };
    let (lo, hi) = volume.volume.bounds();
    if buttons.just_pressed(MouseButton::Left) {
        if egui.is_some_and(|e| e.wants_any_pointer_input()) {
            return;
        }
        let radius = light_marker_radius(lo, hi) * GRAB_SLACK;
        for (t, v) in &markers {
            if *v != Visibility::Hidden && hits_sphere(&ray, t.translation, radius) {
                drag.plane = Some((t.translation, view.0.forward()));
            }
        }
    }
    let Some((point, normal)) = drag.plane else {
        return;
    };
    let denom = ray.dir.dot(normal);
    if denom.abs() < 1e-6 {
        return;
    }
    let t = (point - ray.origin).dot(normal) / denom;
    if t <= 0.0 {
        return;
    }
    let at = ray.origin + ray.dir * t;
    let light = match render.settings.phong.light {
        Light::Point(_) => Light::Point(at),
        Light::Directional(d) => Light::Directional(direction_from_marker(at, lo, hi).unwrap_or(d)),
        Light::Headlight => return,
    };
    if render.settings.phong.light != light {
        render.settings.phong.light = light;
    }
}

fn draw_ring(
    mut overlay: ResMut<super::overlay::OverlayLines>,
    render: Res<RenderState>,
    volume: Res<VolumeState>,
    drag: Res<LightDrag>,
    views: Query<&View, With<MainCamera>>,
) {
    let Ok(view) = views.single() else { return };
    let light = render.settings.phong.light;
    let Some(at) = marker_position(light, &volume) else {
        return;
    };
    let (lo, hi) = volume.volume.bounds();
    let r = light_marker_radius(lo, hi);
    let c = LIGHT_MARKER_COLOR;
    let color = Color::srgb(c.x, c.y, c.z);
    let ring = if drag.active() { Color::WHITE } else { color };
    overlay.ring(at, r * GRAB_SLACK, view, ring, 1.5);
    if let Light::Directional(_) = light {
        overlay.arrow(at, (lo + hi) * 0.5, view, color, 1.5);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_hits_in_front_and_misses_beside_or_behind() {
        let ray = Ray::new(Vec3::ZERO, Vec3::Z).unwrap();
        assert!(hits_sphere(&ray, Vec3::new(0.0, 0.5, 5.0), 1.0));
        assert!(!hits_sphere(&ray, Vec3::new(0.0, 1.5, 5.0), 1.0));
        assert!(!hits_sphere(&ray, Vec3::new(0.0, 0.0, -5.0), 1.0));
        // From inside the sphere the ray hits its far side.
        assert!(hits_sphere(&ray, Vec3::ZERO, 1.0));
    }

    use crate::sandbox::state::{MainCamera, RenderState, View, VolumeState};
    use bevy::window::WindowResolution;
    use std::sync::Arc;
    use voxcast_core::camera::Camera;
    use voxcast_core::settings::RenderSettings;

    const W: u32 = 400;
    const H: u32 = 300;

    /// The light systems with a window, the main camera's view and the marker, as the sandbox
    /// has them; the light starts as a point at `start`.
    fn app(start: Light) -> (App, Camera) {
        let volume = voxcast_core::builtin::load_builtin("bunny").unwrap().volume;
        let (lo, hi) = volume.bounds();
        let camera = Camera::framing(lo, hi, Vec3::new(0.3, 0.2, 1.0), Vec3::Y).unwrap();
        let mut settings = RenderSettings::default();
        settings.phong.light = start;
        let mut app = App::new();
        app.insert_resource(VolumeState {
            volume: Arc::new(volume),
            source: "builtin:bunny".into(),
            preset: None,
        })
        .insert_resource(RenderState {
            transfer: voxcast_core::transfer::TransferFunction::ramp(0.0, 1.0, 0.5).unwrap(),
            settings,
            depth_termination: true,
        })
        .init_resource::<LightDrag>()
        .init_resource::<ButtonInput<MouseButton>>()
        .add_systems(Update, (drag_light, place_marker).chain());
        app.world_mut().spawn((MainCamera, View(camera)));
        app.world_mut()
            .spawn((LightMarker, Transform::default(), Visibility::Hidden));
        app.world_mut().spawn((
            Window {
                resolution: WindowResolution::new(W, H).with_scale_factor_override(1.0),
                ..default()
            },
            PrimaryWindow,
        ));
        app.update(); // places the marker
        (app, camera)
    }

    /// The pixel whose ray passes closest to `p`.
    fn pixel_of(camera: &Camera, p: Vec3) -> Vec2 {
        let rays = camera.rays(W, H);
        let mut best = (f32::INFINITY, Vec2::ZERO);
        for y in 0..H {
            for x in 0..W {
                let r = rays.ray(x as f32 + 0.5, y as f32 + 0.5);
                let d = (p - r.origin).cross(r.dir).length();
                if d < best.0 {
                    best = (d, Vec2::new(x as f32 + 0.5, y as f32 + 0.5));
                }
            }
        }
        best.1
    }

    fn set_cursor(app: &mut App, at: Vec2) {
        let mut q = app.world_mut().query::<&mut Window>();
        let mut window = q.single_mut(app.world_mut()).unwrap();
        window.set_physical_cursor_position(Some(at.as_dvec2()));
    }

    fn press(app: &mut App, down: bool) {
        let mut buttons = app.world_mut().resource_mut::<ButtonInput<MouseButton>>();
        buttons.clear();
        if down {
            buttons.press(MouseButton::Left);
        } else {
            buttons.release(MouseButton::Left);
        }
    }

    fn light(app: &App) -> Light {
        app.world().resource::<RenderState>().settings.phong.light
    }

    fn marker(app: &mut App) -> Vec3 {
        let mut q = app
            .world_mut()
            .query_filtered::<&Transform, With<LightMarker>>();
        q.single(app.world()).unwrap().translation
    }

    #[test]
    fn dragging_the_marker_moves_the_point_light_in_the_facing_plane() {
        let start = Vec3::new(120.0, 130.0, 110.0);
        let (mut app, camera) = app(Light::Point(start));
        assert_eq!(marker(&mut app), start);
        let at = pixel_of(&camera, start);
        set_cursor(&mut app, at);
        press(&mut app, true);
        app.update();
        assert!(app.world().resource::<LightDrag>().active());
        set_cursor(&mut app, at + Vec2::new(60.0, -20.0));
        press(&mut app, true); // held: no longer just pressed
        app.update();
        let Light::Point(moved) = light(&app) else {
            panic!("still a point light")
        };
        let (right, up, forward) = camera.basis();
        let delta = moved - start;
        assert!(delta.dot(forward).abs() < 1e-2 * delta.length(), "{delta}");
        assert!(delta.dot(right) > 0.0 && delta.dot(up) > 0.0, "{delta}");
        // The light now lies under the cursor, and the marker stands there.
        assert!((pixel_of(&camera, moved) - (at + Vec2::new(60.0, -20.0))).length() <= 1.0);
        assert_eq!(marker(&mut app), moved);
        press(&mut app, false);
        app.update();
        assert!(!app.world().resource::<LightDrag>().active());
    }

    #[test]
    fn a_press_beside_the_marker_does_not_grab_it() {
        let start = Vec3::new(120.0, 130.0, 110.0);
        let (mut app, camera) = app(Light::Point(start));
        set_cursor(&mut app, pixel_of(&camera, start) + Vec2::new(80.0, 0.0));
        press(&mut app, true);
        app.update();
        assert!(!app.world().resource::<LightDrag>().active());
        assert_eq!(light(&app), Light::Point(start));
    }

    #[test]
    fn a_directional_lights_marker_turns_it() {
        // Shining back towards the camera's side, so the marker stands in view.
        let (mut app, camera) = app(Light::Directional(Vec3::new(-0.6, -0.3, -1.0)));
        let from = marker(&mut app);
        let at = pixel_of(&camera, from);
        set_cursor(&mut app, at);
        press(&mut app, true);
        app.update();
        assert!(app.world().resource::<LightDrag>().active());
        set_cursor(&mut app, at + Vec2::new(-50.0, 0.0));
        press(&mut app, true);
        app.update();
        let Light::Directional(d) = light(&app) else {
            panic!("still directional")
        };
        let (lo, hi) = app.world().resource::<VolumeState>().volume.bounds();
        let now = marker(&mut app);
        assert!((d - direction_from_marker(now, lo, hi).unwrap()).length() < 1e-5);
        assert!((now - from).dot(camera.basis().0) < 0.0);
    }
}
