//! Looking inside, in the scene: the crop box's outline and the clip plane where it crosses the
//! volume, each with handles dragged by the mouse — the plane along its normal, a crop face along
//! its axis. The settings' [`voxcast_core::clip::Clip`] is the single truth: the handles are
//! drawn from it and a drag writes it, so the preview, the CPU render and the breakdown cut alike.

use crate::sandbox::shared::pointer::{MouseHeld, Pointer};
use crate::sandbox::shared::render_change::{Author, Change, RenderChanges};
use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeState};
use bevy::prelude::*;
use voxcast_core::clip::{Clip, ResolvedClip};
use voxcast_core::marker::light_marker_radius;
use voxcast_core::ray::Ray;
use voxcast_core::ray::box_edges;

/// Colour of the crop box and its handles.
const CROP_COLOR: Color = Color::srgb(1.0, 0.6, 0.2);
/// Colour of the clip plane and its handle.
const PLANE_COLOR: Color = Color::srgb(0.35, 1.0, 0.45);

/// What a handle moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Handle {
    /// The clip plane's position.
    Plane,
    /// A crop face: the axis and whether it is the upper side.
    Crop(usize, bool),
}

/// Whether the crop box's face handles are shown (the panel's "Crop box" switch); they are also
/// shown whenever the box is cropped.
#[derive(Resource, Default)]
pub struct CutHandles {
    pub crop: bool,
}

/// The drag under way: the handle, the line it moves along (through where it was grabbed), the
/// setting's value then, and world units per unit of the setting.
#[derive(Resource, Default)]
pub struct CutDrag {
    grab: Option<Grab>,
}

#[derive(Clone, Copy, Debug)]
struct Grab {
    handle: Handle,
    at: Vec3,
    axis: Vec3,
    start: f32,
    scale: f32,
}

impl CutDrag {
    pub fn active(&self) -> bool {
        self.grab.is_some()
    }

    fn holds(&self, h: Handle) -> bool {
        self.grab.is_some_and(|g| g.handle == h)
    }
}

pub(crate) fn plugin(app: &mut App) {
    app.init_resource::<CutDrag>()
        .init_resource::<MouseHeld>()
        .init_resource::<CutHandles>()
        .add_systems(
            Update,
            (
                (drag_cut, hold_mouse)
                    .chain()
                    .in_set(crate::sandbox::shared::schedule::Frame::Grab),
                draw_cut.in_set(crate::sandbox::shared::schedule::Frame::Show),
            ),
        );
}

/// The handles shown for `clip` (resolved as `resolved`, its plane crossing the box as
/// `polygon`) on a volume spanning `bounds`: where each stands, the axis it moves along, the
/// setting's value and world units per unit of it.
fn handles(
    clip: &Clip,
    resolved: &ResolvedClip,
    polygon: &[Vec3],
    bounds: (Vec3, Vec3),
    crop: bool,
) -> Vec<Grab> {
    let mut out = Vec::new();
    if let Some(plane) = clip.plane
        && !polygon.is_empty()
    {
        out.push(Grab {
            handle: Handle::Plane,
            at: polygon.iter().copied().sum::<Vec3>() / polygon.len() as f32,
            axis: resolved.normal,
            start: plane.position,
            scale: resolved.position_scale,
        });
    }
    if crop || clip.is_cropped() {
        let size = bounds.1 - bounds.0;
        let centre = 0.5 * (resolved.lo + resolved.hi);
        for a in 0..3 {
            for upper in [false, true] {
                let mut at = centre;
                at[a] = if upper {
                    resolved.hi[a]
                } else {
                    resolved.lo[a]
                };
                let start = if upper {
                    clip.crop_hi[a]
                } else {
                    clip.crop_lo[a]
                };
                out.push(Grab {
                    handle: Handle::Crop(a, upper),
                    at,
                    axis: Vec3::AXES[a],
                    start,
                    scale: size[a],
                });
            }
        }
    }
    out
}

/// How far along the line `at + s·axis` (unit axis) the point nearest to `ray` lies; `None` when
/// the ray runs along the line (the drag would be undefined).
fn along(ray: &Ray, at: Vec3, axis: Vec3) -> Option<f32> {
    let b = axis.dot(ray.dir);
    let denom = 1.0 - b * b;
    if denom < 1e-4 {
        return None;
    }
    let w = at - ray.origin;
    Some((b * ray.dir.dot(w) - axis.dot(w)) / denom)
}

/// The settings after moving `handle` to `value` (clamped to what the cut allows).
fn apply(render: &mut RenderState, handle: Handle, value: f32) {
    let clip = &mut render.settings.clip;
    match handle {
        Handle::Plane => {
            if let Some(p) = &mut clip.plane {
                p.position = value.clamp(-1.0, 1.0);
            }
        }
        Handle::Crop(a, true) => clip.crop_hi[a] = value.clamp(clip.crop_lo[a], 1.0),
        Handle::Crop(a, false) => clip.crop_lo[a] = value.clamp(0.0, clip.crop_hi[a]),
    }
}

/// Grabs a handle under the cursor and moves it while the left button is held.
fn drag_cut(
    pointer: Pointer,
    views: Query<&View, With<MainCamera>>,
    volume: Res<VolumeState>,
    shown: Res<CutHandles>,
    mut render: RenderChanges,
    mut drag: ResMut<CutDrag>,
) {
    if !pointer.buttons.pressed(MouseButton::Left) {
        drag.grab = None;
        return;
    }
    let Ok(view) = views.single() else { return };
    let Some(ray) = pointer.ray(view) else { return };
    if pointer.buttons.just_pressed(MouseButton::Left) {
        if pointer.panel_has_it() {
            return;
        }
        let bounds = volume.volume.bounds();
        let radius = grab_radius(bounds.0, bounds.1);
        let clip = &render.now.settings.clip;
        let resolved = clip.resolve(bounds);
        let polygon = resolved.plane_polygon();
        // The nearest handle the cursor's ray passes within reach of.
        drag.grab = handles(clip, &resolved, &polygon, bounds, shown.crop)
            .into_iter()
            .filter_map(|g| {
                let t = (g.at - ray.origin).dot(ray.dir);
                let miss = (ray.origin + ray.dir * t).distance(g.at);
                (t > 0.0 && miss <= radius).then_some((t, g))
            })
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, g)| g);
    }
    let Some(g) = drag.grab else { return };
    let Some(s) = along(&ray, g.at, g.axis) else {
        return;
    };
    if g.scale > 0.0 {
        let mut edited = render.now.clone();
        apply(&mut edited, g.handle, g.start + s / g.scale);
        if edited.settings.clip != render.now.settings.clip {
            render.ask(Author::CutDrag, Change::Clip(edited.settings.clip));
        }
    }
}

/// Tells the orbit whether a handle of the cut is held.
fn hold_mouse(drag: Res<CutDrag>, mut held: ResMut<MouseHeld>) {
    held.hold("cut", drag.active());
}

/// Handles are rings this large (the light's marker size: easy to hit, small beside the volume).
fn grab_radius(lo: Vec3, hi: Vec3) -> f32 {
    1.8 * light_marker_radius(lo, hi)
}

fn draw_cut(
    mut overlay: ResMut<crate::sandbox::scene::overlay::OverlayLines>,
    render: Res<RenderState>,
    volume: Res<VolumeState>,
    shown: Res<CutHandles>,
    drag: Res<CutDrag>,
    views: Query<&View, With<MainCamera>>,
) {
    let Ok(view) = views.single() else { return };
    let clip = &render.settings.clip;
    let bounds = volume.volume.bounds();
    let resolved = clip.resolve(bounds);
    if clip.is_cropped() || shown.crop {
        for (a, b) in box_edges(resolved.lo, resolved.hi) {
            overlay.line(a, b, CROP_COLOR, 1.5);
        }
    }
    let polygon = resolved.plane_polygon();
    for (i, &p) in polygon.iter().enumerate() {
        overlay.line(p, polygon[(i + 1) % polygon.len()], PLANE_COLOR, 1.5);
    }
    let radius = grab_radius(bounds.0, bounds.1);
    for g in handles(clip, &resolved, &polygon, bounds, shown.crop) {
        let color = if drag.holds(g.handle) {
            Color::WHITE
        } else if g.handle == Handle::Plane {
            PLANE_COLOR
        } else {
            CROP_COLOR
        };
        overlay.ring(g.at, radius, view, color, 1.5);
        if g.handle == Handle::Plane {
            // The arrow points to the side the plane removes.
            overlay.arrow(g.at, g.at + g.axis * 4.0 * radius, view, color, 1.5);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use voxcast_core::clip::ClipPlane;

    /// The handles shown for the state's cut, as the systems compute them.
    fn shown(render: &RenderState, volume: &VolumeState, crop: bool) -> Vec<Grab> {
        let clip = &render.settings.clip;
        let bounds = volume.volume.bounds();
        let resolved = clip.resolve(bounds);
        handles(clip, &resolved, &resolved.plane_polygon(), bounds, crop)
    }
    use voxcast_core::settings::RenderSettings;

    fn state(clip: Clip) -> (RenderState, VolumeState) {
        let volume = voxcast_core::builtin::load_builtin("head").unwrap().volume;
        (
            RenderState {
                transfer: voxcast_core::transfer::TransferFunction::ramp(0.0, 1.0, 0.5).unwrap(),
                settings: RenderSettings {
                    clip,
                    ..Default::default()
                },
                depth_termination: true,
            },
            VolumeState {
                volume: Arc::new(volume.into()),
                source: "builtin:head".into(),
                preset: None,
            },
        )
    }

    #[test]
    fn the_nearest_point_on_a_handle_line() {
        // A ray along −z through (2, 0, ·) and the x axis: nearest at x = 2.
        let ray = Ray::new(Vec3::new(2.0, 0.0, 5.0), Vec3::NEG_Z).unwrap();
        assert_eq!(along(&ray, Vec3::ZERO, Vec3::X), Some(2.0));
        // Looking straight down the line: no drag.
        let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z).unwrap();
        assert_eq!(along(&ray, Vec3::ZERO, Vec3::Z), None);
    }

    #[test]
    fn handles_follow_the_cut_and_moving_one_writes_the_setting() {
        let (mut render, volume) = state(Clip {
            plane: Some(ClipPlane {
                normal: Vec3::X,
                position: 0.0,
            }),
            ..Clip::default()
        });
        let first = shown(&render, &volume, false);
        assert_eq!(
            first.len(),
            1,
            "the plane's handle only, until the crop is shown"
        );
        let (lo, hi) = volume.volume.bounds();
        let plane = first[0];
        assert!((plane.at.x - 0.5 * (lo.x + hi.x)).abs() < 1e-3);
        // Half the box along x further: position 1.
        apply(
            &mut render,
            Handle::Plane,
            plane.start + plane.scale / plane.scale,
        );
        assert_eq!(render.settings.clip.plane.unwrap().position, 1.0);
        apply(&mut render, Handle::Plane, -7.0);
        assert_eq!(render.settings.clip.plane.unwrap().position, -1.0);
        // Crop faces never cross.
        assert_eq!(shown(&render, &volume, true).len(), 7);
        apply(&mut render, Handle::Crop(2, false), 0.7);
        apply(&mut render, Handle::Crop(2, true), 0.4);
        let clip = &render.settings.clip;
        assert_eq!((clip.crop_lo.z, clip.crop_hi.z), (0.7, 0.7));
        assert!(render.settings.validate().is_ok());
        // A cropped box shows its handles without the switch; the plane's handle goes where
        // the plane misses what is left (here a slice of zero thickness it does not cross).
        assert_eq!(shown(&render, &volume, false).len(), 6);
        apply(&mut render, Handle::Crop(2, false), 0.2);
        apply(&mut render, Handle::Plane, 0.0);
        assert_eq!(shown(&render, &volume, false).len(), 7);
    }
}
