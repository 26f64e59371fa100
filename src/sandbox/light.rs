//! The Light entity: a small opaque sphere standing where the point light is (or where a
//! directional light comes from), drawn with a gizmo, and dragged with the mouse in the plane
//! facing the camera. The settings' light is the single truth; the marker follows it, and a
//! drag writes it, so the preview and the CPU render always shade with the same light.
//!
//! The marker is a real mesh: inside the volume it writes depth and the preview's rays stop at
//! it. It is hidden while a comparison captures the preview (the CPU render has no meshes).

use super::preview::FullQuality;
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
pub(super) fn marker_plugin(app: &mut App) {
    app.add_systems(Update, (spawn_marker, place_marker).chain());
}

/// Dragging and the gizmo (window only).
pub(super) fn plugin(app: &mut App) {
    app.init_resource::<LightDrag>()
        .add_systems(Update, (drag_light.before(place_marker), draw_gizmo));
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

/// (Re)spawns the sphere when a volume is loaded (its size follows the volume).
fn spawn_marker(
    mut commands: Commands,
    volume: Res<VolumeState>,
    existing: Query<Entity, With<LightMarker>>,
    mut meshes: ResMut<Assets<Mesh>>,
    mut materials: ResMut<Assets<StandardMaterial>>,
) {
    if !volume.is_changed() {
        return;
    }
    for e in &existing {
        commands.entity(e).despawn();
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

/// The ray under the cursor, from the main camera's view (the window shows the whole view).
fn cursor_ray(window: &Window, view: &View) -> Option<Ray> {
    let cursor = window.physical_cursor_position()?;
    let (w, h) = (window.physical_width(), window.physical_height());
    (w > 0 && h > 0).then(|| view.0.ray(cursor.x, cursor.y, w, h))
}

/// Where `ray` first meets the sphere at `centre` of `radius`, if it does.
fn hits_sphere(ray: &Ray, centre: Vec3, radius: f32) -> bool {
    let oc = ray.origin - centre;
    let b = oc.dot(ray.dir);
    let c = oc.length_squared() - radius * radius;
    let disc = b * b - c;
    disc >= 0.0 && (-b + disc.sqrt()) >= 0.0
}

#[allow(clippy::too_many_arguments)]
pub(super) fn drag_light(
    buttons: Res<ButtonInput<MouseButton>>,
    window: Query<&Window, With<PrimaryWindow>>,
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
    let Some(ray) = cursor_ray(window, view) else {
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

fn draw_gizmo(
    mut gizmos: Gizmos,
    render: Res<RenderState>,
    volume: Res<VolumeState>,
    drag: Res<LightDrag>,
) {
    let light = render.settings.phong.light;
    let Some(at) = marker_position(light, &volume) else {
        return;
    };
    let (lo, hi) = volume.volume.bounds();
    let r = light_marker_radius(lo, hi);
    let c = LIGHT_MARKER_COLOR;
    let color = Color::srgb(c.x, c.y, c.z);
    let ring = if drag.active() { Color::WHITE } else { color };
    gizmos.sphere(Isometry3d::from_translation(at), r * GRAB_SLACK, ring);
    if let Light::Directional(_) = light {
        gizmos.arrow(at, (lo + hi) * 0.5, color);
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
}
