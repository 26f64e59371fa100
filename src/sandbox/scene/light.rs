//! The Light entities: one small opaque sphere per light, standing where a point light is (or
//! where a directional light comes from), ringed in the light's colour, and dragged with the
//! mouse in the plane facing the camera. The settings' lights are the single truth; each marker
//! follows its light, and a drag writes it, so the preview and the CPU render always shade with
//! the same lights.
//!
//! The marker is a real mesh: inside the volume it writes depth and the preview's rays stop at
//! it. It is hidden while a comparison captures the preview (the CPU render has no meshes).

use crate::sandbox::shared::pointer::{MouseHeld, Pointer};
use crate::sandbox::shared::quality::FullQuality;
use crate::sandbox::shared::render_change::{Author, Change, RenderChanges};
use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeState};
use bevy::prelude::*;
use voxcast_core::marker::{
    LIGHT_MARKER_COLOR, direction_from_marker, directional_marker_position, light_marker_radius,
};
use voxcast_core::ray::Ray;
use voxcast_core::shade::{Light, MAX_LIGHTS};

/// Marks the sphere of the light at this index of the settings' lights (one sphere per slot,
/// hidden while its slot is empty or holds a headlight).
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq)]
pub struct LightMarker(pub usize);

/// The drag under way: the plane the light moves in (through the marker, facing the camera),
/// and which light.
#[derive(Resource, Default)]
pub struct LightDrag {
    plane: Option<(Vec3, Vec3, usize)>,
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
    app.add_systems(
        Update,
        (spawn_marker, place_marker)
            .chain()
            .in_set(crate::sandbox::shared::schedule::Frame::Show),
    );
}

/// Dragging and the gizmo (window only).
pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<LightDrag>()
        .init_resource::<MouseHeld>()
        .add_systems(
            Update,
            (
                (drag_light, hold_mouse)
                    .chain()
                    .in_set(crate::sandbox::shared::schedule::Frame::Grab),
                draw_ring.in_set(crate::sandbox::shared::schedule::Frame::Show),
            ),
        );
}

/// Where the marker of light `i` stands, `None` for a headlight (it moves with the camera) or
/// an empty slot.
fn marker_of(render: &RenderState, i: usize, volume: &VolumeState) -> Option<Vec3> {
    marker_position(render.settings.phong.lights.get(i)?.light, volume)
}

/// Where the marker stands for `light`, `None` for the headlight (it moves with the camera).
fn marker_position(light: Light, volume: &VolumeState) -> Option<Vec3> {
    let (lo, hi) = volume.volume.bounds();
    match light {
        Light::Headlight => None,
        Light::Point(p) => Some(p),
        Light::Spot(spot) => Some(spot.position),
        Light::Directional(d) => directional_marker_position(d, lo, hi),
    }
}

/// (Re)spawns the spheres when the mode changes (if its scene has one; it leaves with the mode)
/// or a volume is loaded (its size follows the volume).
fn spawn_marker(
    mut commands: Commands,
    volume: Res<VolumeState>,
    staged: crate::sandbox::shared::mode::Staged,
    existing: Query<Entity, With<LightMarker>>,
    mut assets: crate::sandbox::shared::state::MeshAssets,
) {
    let (mode, stage) = (&staged.mode, &staged.stage);
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
    let mesh = assets.meshes.add(
        Sphere::new(light_marker_radius(lo, hi))
            .mesh()
            .ico(3)
            .unwrap(),
    );
    let material = assets.materials.add(StandardMaterial {
        base_color: Color::srgb(c.x, c.y, c.z),
        unlit: true,
        ..default()
    });
    for i in 0..MAX_LIGHTS {
        commands.spawn((
            LightMarker(i),
            crate::sandbox::shared::layers::Solid,
            crate::sandbox::shared::layers::Occluder {
                radius: light_marker_radius(lo, hi),
            },
            Mesh3d(mesh.clone()),
            MeshMaterial3d(material.clone()),
            Transform::default(),
            Visibility::Hidden,
            DespawnOnExit(*mode.get()),
            bevy::camera::visibility::RenderLayers::layer(
                crate::sandbox::shared::layers::OCCLUDER_LAYER,
            ),
        ));
    }
}

/// Keeps each marker where its light is.
fn place_marker(
    render: Res<RenderState>,
    volume: Res<VolumeState>,
    full: Option<Res<FullQuality>>,
    mut markers: Query<(&LightMarker, &mut Transform, &mut Visibility)>,
) {
    let capturing = full.as_ref().is_some_and(|f| f.0);
    for (marker, mut transform, mut visibility) in &mut markers {
        let at = marker_of(&render, marker.0, &volume);
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

/// Tells the orbit whether the light's marker is held.
fn hold_mouse(drag: Res<LightDrag>, mut held: ResMut<MouseHeld>) {
    held.hold("light", drag.active());
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

fn drag_light(
    pointer: Pointer,
    views: Query<&View, With<MainCamera>>,
    markers: Query<(&LightMarker, &Transform, &Visibility)>,
    volume: Res<VolumeState>,
    mut render: RenderChanges,
    mut drag: ResMut<LightDrag>,
) {
    if !pointer.buttons.pressed(MouseButton::Left) {
        drag.plane = None;
        return;
    }
    let Ok(view) = views.single() else { return };
    let Some(ray) = pointer.ray(view) else { return };
    let (lo, hi) = volume.volume.bounds();
    if pointer.buttons.just_pressed(MouseButton::Left) {
        if pointer.panel_has_it() {
            return;
        }
        let radius = light_marker_radius(lo, hi) * GRAB_SLACK;
        // The nearest marker under the cursor is grabbed.
        let mut best: Option<(f32, Vec3, usize)> = None;
        for (m, t, v) in &markers {
            let d = (t.translation - ray.origin).dot(ray.dir);
            if *v != Visibility::Hidden
                && hits_sphere(&ray, t.translation, radius)
                && best.is_none_or(|b| d < b.0)
            {
                best = Some((d, t.translation, m.0));
            }
        }
        drag.plane = best.map(|(_, at, i)| (at, view.0.forward(), i));
    }
    let Some((point, normal, index)) = drag.plane else {
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
    let Some(current) = render.now.settings.phong.lights.get(index).map(|l| l.light) else {
        drag.plane = None; // the light was removed while held
        return;
    };
    let light = match current {
        Light::Point(_) => Light::Point(at),
        // Moved, a spot keeps aiming at the volume's centre.
        Light::Spot(spot) => Light::Spot(voxcast_core::shade::Spot {
            position: at,
            direction: ((lo + hi) * 0.5 - at)
                .try_normalize()
                .unwrap_or(spot.direction),
            ..spot
        }),
        Light::Directional(d) => Light::Directional(direction_from_marker(at, lo, hi).unwrap_or(d)),
        Light::Headlight => return,
    };
    if current != light {
        render.ask(Author::LightDrag, Change::Light(index, light));
    }
}

fn draw_ring(
    mut overlay: ResMut<crate::sandbox::scene::overlay::OverlayLines>,
    render: Res<RenderState>,
    volume: Res<VolumeState>,
    drag: Res<LightDrag>,
    views: Query<&View, With<MainCamera>>,
) {
    let Ok(view) = views.single() else { return };
    let (lo, hi) = volume.volume.bounds();
    let r = light_marker_radius(lo, hi);
    for (i, source) in render.settings.phong.lights.iter().enumerate() {
        let Some(at) = marker_position(source.light, &volume) else {
            continue;
        };
        // The ring and arrow in the light's own colour (scaled to full brightness), so several
        // lights are told apart; white while held.
        let c = source.color / source.color.max_element().max(1e-6);
        let color = Color::srgb(c.x, c.y, c.z);
        let held = drag.plane.is_some_and(|(_, _, k)| k == i);
        let ring = if held { Color::WHITE } else { color };
        overlay.ring(at, r * GRAB_SLACK, view, ring, 1.5);
        match source.light {
            Light::Directional(_) => overlay.arrow(at, (lo + hi) * 0.5, view, color, 1.5),
            // A spot's arrow runs along its axis, as far as the volume's centre is from it.
            Light::Spot(spot) => {
                let reach = ((lo + hi) * 0.5 - at).length();
                let axis = spot.direction.normalize_or(Vec3::NEG_Z);
                overlay.arrow(at, at + axis * reach, view, color, 1.5);
            }
            Light::Headlight | Light::Point(_) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox::shared::schedule::Frame;

    #[test]
    fn sphere_hits_in_front_and_misses_beside_or_behind() {
        let ray = Ray::new(Vec3::ZERO, Vec3::Z).unwrap();
        assert!(hits_sphere(&ray, Vec3::new(0.0, 0.5, 5.0), 1.0));
        assert!(!hits_sphere(&ray, Vec3::new(0.0, 1.5, 5.0), 1.0));
        assert!(!hits_sphere(&ray, Vec3::new(0.0, 0.0, -5.0), 1.0));
        // From inside the sphere the ray hits its far side.
        assert!(hits_sphere(&ray, Vec3::ZERO, 1.0));
    }

    use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeState};
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
        settings.phong.lights = vec![voxcast_core::shade::LightSource::new(start)];
        let mut app = App::new();
        app.insert_resource(VolumeState {
            volume: Arc::new(volume.into()),
            source: "builtin:bunny".into(),
            preset: None,
        })
        .insert_resource(RenderState {
            transfer: voxcast_core::transfer::TransferFunction::ramp(0.0, 1.0, 0.5).unwrap(),
            settings,
            depth_termination: true,
        })
        .init_resource::<LightDrag>()
        .init_resource::<MouseHeld>()
        .init_resource::<ButtonInput<MouseButton>>()
        .add_plugins(crate::sandbox::shared::render_change::plugin)
        .add_systems(
            Update,
            (
                drag_light.in_set(Frame::Grab),
                place_marker.in_set(Frame::Show),
            ),
        );
        crate::sandbox::shared::schedule::configure(&mut app);
        app.world_mut().spawn((MainCamera, View(camera)));
        for i in 0..MAX_LIGHTS {
            app.world_mut()
                .spawn((LightMarker(i), Transform::default(), Visibility::Hidden));
        }
        crate::sandbox::shared::viewport::spawn_test_window(app.world_mut(), W, H);
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
        app.world().resource::<RenderState>().settings.phong.lights[0].light
    }

    /// Where light `i`'s marker stands, if shown.
    fn marker_at(app: &mut App, i: usize) -> Option<Vec3> {
        let mut q = app
            .world_mut()
            .query::<(&LightMarker, &Transform, &Visibility)>();
        q.iter(app.world())
            .find(|(m, _, v)| m.0 == i && **v != Visibility::Hidden)
            .map(|(_, t, _)| t.translation)
    }

    fn marker(app: &mut App) -> Vec3 {
        marker_at(app, 0).expect("the first light's marker is shown")
    }

    fn main_view(app: &mut App) -> View {
        let mut q = app.world_mut().query_filtered::<&View, With<MainCamera>>();
        *q.single(app.world()).unwrap()
    }

    fn drag(app: &mut App, from: Vec2, by: Vec2) {
        set_cursor(app, from);
        press(app, true);
        app.update();
        app.world_mut()
            .resource_mut::<bevy::input::mouse::AccumulatedMouseMotion>()
            .delta = by;
        set_cursor(app, from + by);
        press(app, true); // held: no longer just pressed
        app.update();
        app.world_mut()
            .resource_mut::<bevy::input::mouse::AccumulatedMouseMotion>()
            .delta = Vec2::ZERO;
        press(app, false);
        app.update();
    }

    /// While the light's marker is dragged the orbit leaves the view alone: it reads who holds
    /// the mouse (`MouseHeld`), not the light's state. A drag that starts off the marker turns
    /// the view.
    #[test]
    fn dragging_the_marker_does_not_orbit_the_view() {
        use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
        let start = Vec3::new(120.0, 130.0, 110.0);
        let (mut app, camera) = app(Light::Point(start));
        app.init_resource::<AccumulatedMouseMotion>()
            .init_resource::<AccumulatedMouseScroll>()
            .add_systems(
                Update,
                (hold_mouse, crate::sandbox::scene::orbit::orbit_camera)
                    .chain()
                    .after(drag_light),
            );
        let mut q = app.world_mut().query_filtered::<Entity, With<MainCamera>>();
        let main = q.single(app.world()).unwrap();
        app.world_mut().entity_mut(main).insert((
            crate::sandbox::scene::orbit::Orbit::looking_at(camera.eye, camera.target, camera.up),
            Transform::default(),
        ));
        let before = main_view(&mut app);
        drag(&mut app, pixel_of(&camera, start), Vec2::new(40.0, 0.0));
        assert_ne!(light(&app), Light::Point(start), "the marker was dragged");
        assert_eq!(
            main_view(&mut app),
            before,
            "the view stayed while the marker was held"
        );
        drag(&mut app, Vec2::new(5.0, 5.0), Vec2::new(40.0, 0.0));
        assert_ne!(main_view(&mut app), before, "a drag off the marker orbits");
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

    #[test]
    fn each_light_has_its_marker_and_a_drag_moves_only_the_one_held() {
        let first = Vec3::new(120.0, 130.0, 110.0);
        let second = Vec3::new(-30.0, 40.0, 60.0);
        let (mut app, camera) = app(Light::Point(first));
        {
            let mut render = app.world_mut().resource_mut::<RenderState>();
            let lights = &mut render.settings.phong.lights;
            lights.push(voxcast_core::shade::LightSource::new(Light::Headlight));
            lights.push(voxcast_core::shade::LightSource::new(Light::Point(second)));
        }
        app.update();
        assert_eq!(marker_at(&mut app, 0), Some(first));
        assert_eq!(marker_at(&mut app, 1), None, "a headlight has no marker");
        assert_eq!(marker_at(&mut app, 2), Some(second));
        assert_eq!(marker_at(&mut app, 3), None, "an empty slot has no marker");
        let at = pixel_of(&camera, second);
        set_cursor(&mut app, at);
        press(&mut app, true);
        app.update();
        set_cursor(&mut app, at + Vec2::new(-40.0, 30.0));
        press(&mut app, true);
        app.update();
        let lights = app
            .world()
            .resource::<RenderState>()
            .settings
            .phong
            .lights
            .clone();
        assert_eq!(
            lights[0].light,
            Light::Point(first),
            "the other light stays"
        );
        let Light::Point(moved) = lights[2].light else {
            panic!("still a point light")
        };
        assert!((pixel_of(&camera, moved) - (at + Vec2::new(-40.0, 30.0))).length() <= 1.0);
        // The held light removed mid-drag: the drag ends, nothing panics.
        app.world_mut()
            .resource_mut::<RenderState>()
            .settings
            .phong
            .lights
            .truncate(1);
        press(&mut app, true);
        app.update();
        assert!(!app.world().resource::<LightDrag>().active());
        assert_eq!(marker_at(&mut app, 2), None);
    }
}
