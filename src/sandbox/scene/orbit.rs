//! A small orbit camera: left drag orbits around a focus point, right or middle drag pans,
//! the wheel zooms — over the scene only. Input that egui wants (a window under the pointer, a
//! dragged slider) is left to egui, and so is the wheel over a docked panel (egui counts those
//! as background, not as something the pointer is over): it scrolls the panel and leaves the
//! view alone; a drag that starts on a panel does not turn the view either.
//!
//! A drag is read from raw mouse motion where it arrives, else from the cursor's positions:
//! remote desktops, VNC, Xvfb driven by xdotool and some touchpads move the cursor without
//! sending raw motion.

use crate::sandbox::shared::pointer::{MouseHeld, Pointer};
use crate::sandbox::shared::state::{MainCamera, View};
use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll, MouseScrollUnit};
use bevy::prelude::*;

/// Where the camera looks from: spherical coordinates around `focus`.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    pub focus: Vec3,
    pub distance: f32,
    /// Rotation about the up axis, radians.
    pub yaw: f32,
    /// Elevation above the horizontal plane, radians (kept short of the poles).
    pub pitch: f32,
    /// The world's up for this view.
    pub up: Vec3,
}

/// Orbit radians per pixel dragged.
const ORBIT_SPEED: f32 = 0.006;
/// Zoom factor per wheel line.
const ZOOM_STEP: f32 = 0.9;

impl Orbit {
    /// The orbit that puts the camera at `eye` looking at `focus` with `up`.
    pub fn looking_at(eye: Vec3, focus: Vec3, up: Vec3) -> Self {
        let up = up.normalize_or(Vec3::Y);
        let offset = eye - focus;
        let distance = offset.length().max(1e-3);
        let (right, forward) = basis(up);
        let pitch = (offset.dot(up) / distance).clamp(-1.0, 1.0).asin();
        let yaw = offset.dot(right).atan2(offset.dot(forward));
        Self {
            focus,
            distance,
            yaw,
            pitch,
            up,
        }
    }

    /// The camera's transform for this orbit.
    pub fn transform(&self) -> Transform {
        let (right, forward) = basis(self.up);
        let dir = (right * self.yaw.sin() + forward * self.yaw.cos()) * self.pitch.cos()
            + self.up * self.pitch.sin();
        Transform::from_translation(self.focus + dir * self.distance)
            .looking_at(self.focus, self.up)
    }

    /// Puts the main camera where this orbit says: its transform, and its view (kept as it
    /// was where the orbit makes no camera).
    pub fn place(&self, transform: &mut Transform, view: &mut Mut<View>) {
        *transform = self.transform();
        let eye = transform.translation;
        if let Ok(v) =
            voxcast_core::camera::Camera::new(eye, self.focus, self.up, view.0.projection)
        {
            view.0 = v;
        }
    }
}

/// Two axes perpendicular to `up`.
fn basis(up: Vec3) -> (Vec3, Vec3) {
    let forward = up.any_orthonormal_vector();
    (up.cross(forward), forward)
}

pub(crate) fn plugin(app: &mut App) {
    app.add_systems(
        Update,
        (
            orbit_camera.in_set(crate::sandbox::shared::schedule::Frame::Input),
            reframe_on_new_volume.in_set(crate::sandbox::shared::schedule::Frame::Rules),
        ),
    );
}

/// Frames a newly loaded volume (and the volume again when a level or free play starts) from
/// the direction the camera looked from, so a small volume after a large one (or the reverse)
/// fills the view, whatever the player zoomed or panned to before.
pub(crate) fn reframe_on_new_volume(
    volume: Res<crate::sandbox::shared::state::VolumeState>,
    mode: Option<Res<State<crate::sandbox::shared::mode::Mode>>>,
    mut cameras: Query<(&mut Orbit, &mut Transform, &mut View), With<MainCamera>>,
) {
    let new_mode = mode.is_some_and(|m| m.is_changed() && !m.is_added());
    if !(volume.is_changed() && !volume.is_added() || new_mode) {
        return;
    }
    let (lo, hi) = volume.volume.bounds();
    // A ray density is seen as RayVis shows its scene: from its preset's side (the front).
    let density_view = voxcast_core::rays::as_volume::is_density(&volume.volume)
        .then(|| volume.preset.as_ref().and_then(|p| p.view))
        .flatten();
    for (mut orbit, mut transform, mut view) in &mut cameras {
        let v = view.0;
        let (from, up) = density_view.map_or((v.eye - v.target, v.up), |d| (d.from, d.up));
        let Ok(framed) = voxcast_core::camera::Camera::framing(lo, hi, from, up) else {
            continue;
        };
        *orbit = Orbit::looking_at(framed.eye, framed.target, framed.up);
        *transform = orbit.transform();
        view.0 = framed;
    }
}

pub(crate) fn orbit_camera(
    pointer: Pointer,
    motion: Res<AccumulatedMouseMotion>,
    scroll: Res<AccumulatedMouseScroll>,
    mut last_cursor: Local<Option<Vec2>>,
    mut grabbed: Local<bool>,
    held: Option<Res<MouseHeld>>,
    mut cameras: Query<(&mut Orbit, &mut Transform, &mut View), With<MainCamera>>,
) {
    let buttons = &pointer.buttons;
    let cursor = pointer.cursor();
    let cursor_delta = match (*last_cursor, cursor) {
        (Some(a), Some(b)) => b - a,
        _ => Vec2::ZERO,
    };
    *last_cursor = cursor;
    let over_scene = pointer.over_scene();
    let buttons_held = [MouseButton::Left, MouseButton::Right, MouseButton::Middle];
    if buttons.any_just_pressed(buttons_held) {
        *grabbed = over_scene;
    } else if !buttons.any_pressed(buttons_held) {
        *grabbed = false;
    }
    if pointer.panel_has_it() || held.is_some_and(|h| h.by_anyone()) {
        return;
    }
    // Raw motion where it arrives; the cursor's own movement where it does not.
    let delta = if motion.delta != Vec2::ZERO {
        motion.delta
    } else {
        cursor_delta
    };
    for (mut orbit, mut transform, mut view) in &mut cameras {
        let mut changed = false;
        let dragging = *grabbed && delta != Vec2::ZERO;
        if buttons.pressed(MouseButton::Left) && dragging {
            orbit.yaw -= delta.x * ORBIT_SPEED;
            orbit.pitch = (orbit.pitch + delta.y * ORBIT_SPEED).clamp(-1.55, 1.55);
            changed = true;
        }
        if (buttons.pressed(MouseButton::Right) || buttons.pressed(MouseButton::Middle)) && dragging
        {
            let scale = orbit.distance * 0.0015;
            let pan = transform.right() * -delta.x * scale + transform.up() * delta.y * scale;
            orbit.focus += pan;
            changed = true;
        }
        let lines = match scroll.unit {
            MouseScrollUnit::Line => scroll.delta.y,
            MouseScrollUnit::Pixel => scroll.delta.y / 40.0,
        };
        if lines != 0.0 && over_scene {
            orbit.distance = (orbit.distance * ZOOM_STEP.powf(lines)).max(1e-3);
            changed = true;
        }
        if changed {
            orbit.place(&mut transform, &mut view);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox::shared::state::VolumeState;
    use std::sync::Arc;

    fn state(name: &str) -> VolumeState {
        VolumeState {
            volume: Arc::new(
                voxcast_core::builtin::load_builtin(name)
                    .unwrap()
                    .volume
                    .into(),
            ),
            source: format!("builtin:{name}"),
            preset: None,
        }
    }

    #[test]
    fn a_new_volume_is_framed_from_the_same_side() {
        let bunny = state("bunny");
        let (lo, hi) = bunny.volume.bounds();
        let view = voxcast_core::camera::Camera::framing(lo, hi, Vec3::X, Vec3::Y).unwrap();
        let mut app = App::new();
        app.insert_resource(bunny)
            .add_systems(Update, reframe_on_new_volume);
        app.world_mut().spawn((
            MainCamera,
            View(view),
            Orbit::looking_at(view.eye, view.target, view.up),
            Transform::default(),
        ));
        app.update();
        *app.world_mut().resource_mut::<VolumeState>() = state("bucky");
        app.update();
        let (lo, hi) = app.world().resource::<VolumeState>().volume.bounds();
        let mut q = app.world_mut().query::<&View>();
        let v = q.single(app.world()).unwrap().0;
        let want = voxcast_core::camera::Camera::framing(lo, hi, Vec3::X, Vec3::Y).unwrap();
        assert!(
            (v.eye - want.eye).length() < 1e-3,
            "{} vs {}",
            v.eye,
            want.eye
        );
        assert!((v.target - (lo + hi) * 0.5).length() < 1e-3);
    }

    /// An app with only the orbit camera, a 400×300 window (its scene in `viewport`, or all
    /// of it) and a camera framing a 10-unit cube; and the camera's orbit.
    fn orbit_app(viewport: Option<crate::sandbox::shared::viewport::Viewport>) -> (App, Orbit) {
        use bevy::input::mouse::{AccumulatedMouseMotion, AccumulatedMouseScroll};
        let mut app = App::new();
        app.init_resource::<ButtonInput<MouseButton>>()
            .init_resource::<AccumulatedMouseMotion>()
            .init_resource::<AccumulatedMouseScroll>()
            .add_systems(Update, orbit_camera);
        if let Some(v) = viewport {
            app.insert_resource(v);
        }
        let view =
            voxcast_core::camera::Camera::framing(Vec3::ZERO, Vec3::splat(10.0), Vec3::Z, Vec3::Y)
                .unwrap();
        let start = Orbit::looking_at(view.eye, view.target, view.up);
        app.world_mut()
            .spawn((MainCamera, View(view), start, start.transform()));
        crate::sandbox::shared::viewport::spawn_test_window(app.world_mut(), 400, 300);
        (app, start)
    }

    /// Puts the cursor at `(x, 150)` and runs a frame.
    fn move_to(app: &mut App, x: f64) {
        let mut q = app.world_mut().query::<&mut Window>();
        let mut w = q.single_mut(app.world_mut()).unwrap();
        w.set_physical_cursor_position(Some(bevy::math::DVec2::new(x, 150.0)));
        app.update();
    }

    fn orbit(app: &mut App) -> Orbit {
        *app.world_mut()
            .query::<&Orbit>()
            .single(app.world())
            .unwrap()
    }

    /// A drag that moves only the cursor (no raw motion, as xdotool and VNC send) orbits.
    #[test]
    fn a_drag_of_the_cursor_alone_orbits() {
        let (mut app, start) = orbit_app(None);
        move_to(&mut app, 100.0);
        app.world_mut()
            .resource_mut::<ButtonInput<MouseButton>>()
            .press(MouseButton::Left);
        for x in [120.0, 140.0, 160.0] {
            move_to(&mut app, x);
        }
        let o = orbit(&mut app);
        let expect = start.yaw - 60.0 * ORBIT_SPEED;
        assert!((o.yaw - expect).abs() < 1e-4, "yaw {} vs {expect}", o.yaw);
        assert!((o.pitch - start.pitch).abs() < 1e-6);
        // Without the button, moving does nothing.
        app.world_mut()
            .resource_mut::<ButtonInput<MouseButton>>()
            .release(MouseButton::Left);
        move_to(&mut app, 300.0);
        assert_eq!(orbit(&mut app).yaw, o.yaw);
    }

    /// The wheel over a docked panel scrolls the panel, not the view, and a drag that starts
    /// there does not turn it; over the scene both do.
    #[test]
    fn the_wheel_and_drags_over_a_panel_leave_the_view_alone() {
        use bevy::input::mouse::AccumulatedMouseScroll;
        use bevy_egui::egui;
        // A panel takes the left half: the scene is x in [200, 400).
        let (mut app, start) = orbit_app(Some(crate::sandbox::shared::viewport::Viewport {
            rect: egui::Rect::from_min_max(egui::pos2(200.0, 0.0), egui::pos2(400.0, 300.0)),
            pixels_per_point: 1.0,
        }));
        let wheel = |app: &mut App, x: f64| {
            app.world_mut()
                .resource_mut::<AccumulatedMouseScroll>()
                .delta = Vec2::new(0.0, 3.0);
            move_to(app, x);
            app.world_mut()
                .resource_mut::<AccumulatedMouseScroll>()
                .delta = Vec2::ZERO;
        };
        wheel(&mut app, 100.0);
        assert_eq!(orbit(&mut app), start, "the wheel over the panel zoomed");
        wheel(&mut app, 300.0);
        assert!(
            orbit(&mut app).distance < start.distance,
            "the wheel over the scene did not zoom"
        );
        let zoomed = orbit(&mut app);
        // A drag from the panel into the scene: nothing. (Input is cleared after each frame
        // here as the input plugin clears it: "just pressed" lasts one frame.)
        move_to(&mut app, 100.0);
        app.world_mut()
            .resource_mut::<ButtonInput<MouseButton>>()
            .press(MouseButton::Left);
        move_to(&mut app, 110.0);
        app.world_mut()
            .resource_mut::<ButtonInput<MouseButton>>()
            .clear();
        for x in [150.0, 250.0, 350.0] {
            move_to(&mut app, x);
        }
        assert_eq!(
            orbit(&mut app),
            zoomed,
            "a drag from the panel turned the view"
        );
        // Released, then pressed in the scene: it turns.
        let mut input = app.world_mut().resource_mut::<ButtonInput<MouseButton>>();
        input.release(MouseButton::Left);
        input.clear();
        move_to(&mut app, 300.0);
        app.world_mut()
            .resource_mut::<ButtonInput<MouseButton>>()
            .press(MouseButton::Left);
        for x in [320.0, 340.0] {
            move_to(&mut app, x);
        }
        assert!(
            orbit(&mut app).yaw < zoomed.yaw,
            "a drag in the scene did not turn the view"
        );
    }

    #[test]
    fn looking_at_round_trips() {
        let eye = Vec3::new(3.0, 4.0, 5.0);
        let focus = Vec3::new(1.0, 0.5, -1.0);
        for up in [Vec3::Y, Vec3::Z, Vec3::NEG_Y] {
            let o = Orbit::looking_at(eye, focus, up);
            let t = o.transform();
            assert!(
                (t.translation - eye).length() < 1e-4,
                "{up}: {}",
                t.translation
            );
        }
    }

    proptest::proptest! {
        /// For any eye, focus and up (not along the line of sight, not at the poles the
        /// pitch is kept short of), the orbit puts the camera back at the eye, looking at the
        /// focus.
        #[test]
        fn any_view_round_trips(
            eye in proptest::array::uniform3(-50.0f32..50.0),
            focus in proptest::array::uniform3(-50.0f32..50.0),
            up in proptest::array::uniform3(-1.0f32..1.0),
        ) {
            let (eye, focus, up) = (Vec3::from(eye), Vec3::from(focus), Vec3::from(up));
            let offset = eye - focus;
            proptest::prop_assume!(offset.length() > 1e-2 && up.length() > 0.1);
            // Within 1.55 rad of the horizon (the orbit's pitch limit), with margin.
            let sin = (offset.normalize().dot(up.normalize())).abs();
            proptest::prop_assume!(sin < 0.99);
            let t = Orbit::looking_at(eye, focus, up).transform();
            let scale = offset.length().max(1.0);
            proptest::prop_assert!((t.translation - eye).length() < 1e-3 * scale);
            let forward = t.forward().as_vec3();
            proptest::prop_assert!(forward.dot((focus - eye).normalize()) > 0.9999);
        }
    }
}
