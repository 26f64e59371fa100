//! The Virtual Camera entity: the camera whose rays the student follows. It is drawn as a small
//! body at its eye with overlay lines for its frustum and its image plane divided into its pixels
//! (one ray per pixel, through the pixel's centre; the inspector traces them). Its view is a
//! core camera, so the grid drawn here is exactly where the core's rays pass.

use crate::sandbox::shared::state::VolumeState;
use bevy::prelude::*;
use voxcast_core::camera::{Camera as CoreCamera, Projection};
use voxcast_core::tunables as t;

/// The virtual camera: its view and image size in pixels.
#[derive(Component, Clone, Copy, Debug, PartialEq)]
pub struct VirtualCamera {
    pub view: CoreCamera,
    pub width: u32,
    pub height: u32,
    /// Whether its lines and body are drawn.
    pub shown: bool,
}

/// Where the image plane is drawn, as a fraction of the distance from the eye to the target.
const PLANE_FRACTION: f32 = 0.3;
/// The body's edge as a fraction of the volume's diagonal.
const BODY_SIZE: f32 = 0.04;
/// The default view when there is no main camera: the volume seen from this direction.
const DEFAULT_FROM: Vec3 = Vec3::new(-1.0, 0.5, 1.2);
/// Beside the main camera: turned this far about its up axis around the volume's centre…
const BESIDE_TURN_DEG: f32 = 12.0;
/// …and this much nearer to the centre, so the main camera sees it.
const BESIDE_DISTANCE: f32 = 0.45;

impl VirtualCamera {
    /// Frames the volume at the default resolution: beside `main` (turned and nearer, its
    /// field of view widened to keep the volume in view) so the main camera sees it, else
    /// from [`DEFAULT_FROM`].
    pub fn framing(volume: &VolumeState, main: Option<&CoreCamera>) -> Option<Self> {
        let (lo, hi) = volume.volume.bounds();
        let view = match main {
            Some(m) => {
                let centre = (lo + hi) * 0.5;
                let turn = Quat::from_axis_angle(m.up.normalize(), BESIDE_TURN_DEG.to_radians());
                let from = turn * (m.eye - centre);
                let framed = CoreCamera::framing(lo, hi, from, m.up).ok()?;
                let projection = match framed.projection {
                    Projection::Perspective { fov_y_deg } => {
                        let half = (fov_y_deg.to_radians() * 0.5).tan() / BESIDE_DISTANCE;
                        Projection::Perspective {
                            fov_y_deg: (2.0 * half.atan().to_degrees()).min(120.0),
                        }
                    }
                    p => p,
                };
                let eye = framed.target + (framed.eye - framed.target) * BESIDE_DISTANCE;
                CoreCamera::new(eye, framed.target, framed.up, projection).ok()?
            }
            None => CoreCamera::framing(lo, hi, DEFAULT_FROM, Vec3::Y).ok()?,
        };
        let n = t::VIRTUAL_RESOLUTION.default as u32;
        Some(Self {
            view,
            width: n,
            height: n,
            shown: true,
        })
    }

    /// The overlay's line segments: the pixel grid on the image plane (`width + 1` columns and
    /// `height + 1` rows), then the four frustum edges from the eye (perspective) or from the
    /// eye's plane (orthographic) to the plane's corners.
    pub fn lines(&self) -> Vec<(Vec3, Vec3)> {
        let (w, h) = (self.width.max(1), self.height.max(1));
        let d = PLANE_FRACTION * (self.view.target - self.view.eye).length();
        let p = |x: u32, y: u32| self.view.image_plane_point(x as f32, y as f32, w, h, d);
        let mut lines = Vec::with_capacity((w + h + 6) as usize);
        lines.extend((0..=w).map(|x| (p(x, 0), p(x, h))));
        lines.extend((0..=h).map(|y| (p(0, y), p(w, y))));
        for (x, y) in [(0, 0), (w, 0), (0, h), (w, h)] {
            let r = self.view.ray(x as f32, y as f32, w, h);
            lines.push((r.origin, p(x, y)));
        }
        lines
    }
}

/// Marks the virtual camera's body.
#[derive(Component)]
pub(crate) struct Body;

pub(crate) fn plugin(app: &mut App) {
    app.add_systems(
        Update,
        (
            // Beside the main camera as it is framed for the new volume or mode.
            (stage_camera, place_body)
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Follow),
            draw_lines.in_set(crate::sandbox::shared::schedule::Frame::Show),
        ),
    );
}

/// Spawns the camera when a mode whose scene has one starts (it leaves with the mode), and
/// frames each newly loaded volume.
pub(crate) fn stage_camera(
    mut commands: Commands,
    volume: Res<VolumeState>,
    staged: crate::sandbox::shared::mode::Staged,
    main: Query<
        &crate::sandbox::shared::state::View,
        With<crate::sandbox::shared::state::MainCamera>,
    >,
    mut cameras: Query<&mut VirtualCamera>,
    bodies: Query<Entity, With<Body>>,
    mut assets: crate::sandbox::shared::state::MeshAssets,
) {
    let (mode, stage) = (&staged.mode, &staged.stage);
    if !(volume.is_changed() || mode.is_changed()) {
        return;
    }
    let main = main.single().ok().map(|v| v.0);
    let Some(mut framed) = VirtualCamera::framing(&volume, main.as_ref()) else {
        return;
    };
    if stage.lecture_ray {
        framed.view = voxcast_core::worked::lecture_ray();
    }
    if let Ok(mut vc) = cameras.single_mut()
        && !mode.is_changed()
    {
        vc.view = framed.view;
    } else if mode.is_changed()
        && let Some(n) = stage.rays
    {
        (framed.width, framed.height) = (n, n);
        framed.shown = stage.rays_shown;
        commands.spawn((
            framed,
            Transform::default(),
            Visibility::default(),
            DespawnOnExit(*mode.get()),
        ));
    } else {
        return;
    }
    // The body's size follows the volume.
    for b in &bodies {
        commands.entity(b).despawn();
    }
    let (lo, hi) = volume.volume.bounds();
    let size = BODY_SIZE * (hi - lo).length();
    commands.spawn((
        Body,
        crate::sandbox::shared::layers::Solid,
        Mesh3d(assets.meshes.add(Cuboid::new(size, size, size * 1.5))),
        MeshMaterial3d(assets.materials.add(StandardMaterial {
            base_color: {
                let c = voxcast_core::marker::BODY_COLOR;
                Color::srgb(c.x, c.y, c.z)
            },
            unlit: true,
            ..default()
        })),
        Transform::default(),
        Visibility::Hidden,
        DespawnOnExit(*mode.get()),
    ));
}

fn place_body(
    cameras: Query<Ref<VirtualCamera>>,
    full: Option<Res<crate::sandbox::shared::quality::FullQuality>>,
    mut bodies: Query<(Ref<Body>, &mut Transform, &mut Visibility)>,
) {
    let Ok(vc) = cameras.single() else { return };
    // Hidden while a comparison captures the preview: the CPU render has no meshes.
    let capturing = full.as_ref().is_some_and(|f| f.0);
    let full_changed = full.as_ref().is_some_and(|f| f.is_changed());
    let body_new = bodies.iter().any(|(b, _, _)| b.is_added());
    if !(vc.is_changed() || full_changed || body_new) {
        return;
    }
    let v = vc.view;
    for (_, mut transform, mut visibility) in &mut bodies {
        // The body sits just behind the eye so it never hides the first rays.
        let (_, _, forward) = v.basis();
        let back = (v.target - v.eye).length() * 0.02;
        *transform = Transform::from_translation(v.eye - forward * back).looking_at(v.target, v.up);
        visibility.set_if_neq(if vc.shown && !capturing {
            Visibility::Visible
        } else {
            Visibility::Hidden
        });
    }
}

fn draw_lines(
    mut overlay: ResMut<crate::sandbox::scene::overlay::OverlayLines>,
    cameras: Query<&VirtualCamera>,
) {
    let Ok(vc) = cameras.single() else { return };
    if !vc.shown {
        return;
    }
    let grid = Color::srgb(0.35, 0.85, 1.0);
    let frustum = Color::srgb(0.25, 0.55, 0.9);
    let lines = vc.lines();
    let grid_lines = (vc.width.max(1) + vc.height.max(1) + 2) as usize;
    for (i, (a, b)) in lines.into_iter().enumerate() {
        overlay.line(a, b, if i < grid_lines { grid } else { frustum }, 1.0);
    }
}

/// The perspective field of view of `view`, if it has one.
pub fn fov(view: &CoreCamera) -> Option<f32> {
    match view.projection {
        Projection::Perspective { fov_y_deg } => Some(fov_y_deg),
        Projection::Orthographic { .. } => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn vc(w: u32, h: u32, projection: Projection) -> VirtualCamera {
        VirtualCamera {
            view: CoreCamera::new(Vec3::new(0.0, 0.0, 10.0), Vec3::ZERO, Vec3::Y, projection)
                .unwrap(),
            width: w,
            height: h,
            shown: true,
        }
    }

    #[test]
    fn the_grid_has_a_line_per_pixel_edge_and_lies_on_the_plane() {
        for projection in [
            Projection::Perspective { fov_y_deg: 40.0 },
            Projection::Orthographic { height: 3.0 },
        ] {
            for (w, h) in [(1, 1), (8, 8), (64, 3)] {
                let c = vc(w, h, projection);
                let lines = c.lines();
                assert_eq!(lines.len() as u32, (w + 1) + (h + 1) + 4);
                let grid = (w + h + 2) as usize;
                // Plane at 0.3 × 10 in front of the eye (z = 7).
                for (a, b) in &lines[..grid] {
                    assert!((a.z - 7.0).abs() < 1e-4 && (b.z - 7.0).abs() < 1e-4);
                }
                // Each pixel centre's ray passes through the middle of its grid cell.
                let r = c.view.pixel_ray(0, 0, w, h);
                let (a, b) = (lines[0].0, lines[1].0); // top-left and the next column's top
                let mid_x = (a.x + b.x) * 0.5;
                let p = r.origin + r.dir * ((7.0 - r.origin.z) / r.dir.z);
                assert!((p.x - mid_x).abs() < 1e-4, "{p} vs {mid_x}");
            }
        }
    }

    #[test]
    fn frames_the_volume_at_the_default_resolution() {
        let (volume, _) = crate::sandbox::inspect::rays::tests::scene("bucky");
        let c = VirtualCamera::framing(&volume, None).unwrap();
        let n = t::VIRTUAL_RESOLUTION.default as u32;
        assert_eq!((c.width, c.height), (n, n));
        let (lo, hi) = volume.volume.bounds();
        assert!((c.view.target - (lo + hi) * 0.5).length() < 1e-3);
        // Beside a main camera: in front of it, within its view (turned sideways: within the
        // horizontal half-angle of a 4:3 window).
        let main = CoreCamera::framing(lo, hi, Vec3::Z, Vec3::Y).unwrap();
        let c = VirtualCamera::framing(&volume, Some(&main)).unwrap();
        let to = (c.view.eye - main.eye).normalize();
        let Projection::Perspective { fov_y_deg } = main.projection else {
            panic!()
        };
        let half_across = ((fov_y_deg.to_radians() * 0.5).tan() * 4.0 / 3.0).atan();
        assert!(to.dot(main.forward()).acos() < half_across);
    }
}
