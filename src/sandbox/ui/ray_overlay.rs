//! The virtual camera's rays painted over the preview — before, inside and after the volume,
//! growing with the animation — picked by a click near their line, and an opened sample's cell
//! with its 8 corners drawn in the scene.

use crate::sandbox::inspect::breakdown::BreakdownState;
use crate::sandbox::inspect::rays::{
    InspectSettings, Inspection, RayAnimation, RaySelection, ray_pixel,
};
use crate::sandbox::inspect::virtual_camera::VirtualCamera;
use crate::sandbox::scene::overlay::{Projector, scene_painter};
use crate::sandbox::shared::state::{MainCamera, View, VolumeState};
use bevy::prelude::*;
use bevy_egui::EguiContexts;
use bevy_egui::egui::{self, Color32, Pos2, Stroke, vec2};
use voxcast_core::breakdown::SampleRecord;

/// What the overlay draws the rays from: the inspection, how it is shown and animated, the
/// two cameras, the breakdown's ray, the volume and the viewport.
#[derive(bevy::ecs::system::SystemParam)]
pub(super) struct RaysShown<'w, 's> {
    inspection: Res<'w, Inspection>,
    settings: Res<'w, InspectSettings>,
    animation: Res<'w, RayAnimation>,
    views: Query<'w, 's, &'static View, With<MainCamera>>,
    cameras: Query<'w, 's, &'static VirtualCamera>,
    breakdown: Res<'w, BreakdownState>,
    volume: Res<'w, VolumeState>,
    viewport: Option<Res<'w, crate::sandbox::shared::viewport::Viewport>>,
}

/// Paints the rays (and an opened sample's cell) over the preview, beneath every window.
pub(super) fn ray_overlay(
    mut contexts: EguiContexts,
    mut selection: ResMut<RaySelection>,
    shown: RaysShown,
) -> Result {
    let RaysShown {
        inspection,
        settings,
        animation,
        views,
        cameras,
        breakdown,
        volume,
        viewport,
    } = shown;
    let (Ok(view), Ok(vc)) = (views.single(), cameras.single()) else {
        return Ok(());
    };
    if !settings.shown || !vc.shown {
        return Ok(());
    }
    let ctx = contexts.ctx_mut()?;
    let (projector, painter) = scene_painter(ctx, viewport.as_deref(), view);
    let reach =
        crate::sandbox::inspect::rays::reach(vc.view.eye, vc.view.target, volume.volume.bounds());
    let selected = selection.selected_index(inspection.size);
    let hovered = selection.hovered_index(inspection.size);
    let grown = animation.distance;
    // A click on the scene (not on a window) picks the ray drawn nearest to it.
    let (clicked, pointer) = ctx.input(|i| (i.pointer.primary_clicked(), i.pointer.interact_pos()));
    let pick_at = pointer.filter(|_| clicked && !ctx.is_pointer_over_egui());
    let mut nearest: Option<(f32, usize)> = None;
    for (i, path) in inspection.paths.iter().enumerate() {
        let (width, inside_color, alpha) = ray_style(i, selected, hovered);
        let fade = |c: Color32| Color32::from_rgba_unmultiplied(c.r(), c.g(), c.b(), alpha);
        let outside = fade(Color32::from_gray(130));
        let (t_in, t_out) = path.interval.unwrap_or((reach, reach));
        for (a, b, color, w) in [
            (0.0, t_in, outside, 1.0),
            (t_in, t_out, fade(inside_color), width),
            (t_out, reach, outside, 1.0),
        ] {
            let b = b.min(grown);
            if b <= a {
                continue;
            }
            if let Some(seg) =
                projector.segment(path.origin + path.dir * a, path.origin + path.dir * b)
            {
                painter.line_segment(seg, Stroke::new(w, color));
                if let Some(p) = pick_at {
                    let d = distance_to_segment(p, seg);
                    if d <= PICK_RADIUS && nearest.is_none_or(|(best, _)| d < best) {
                        nearest = Some((d, i));
                    }
                }
            }
        }
    }
    if let Some((_, i)) = nearest {
        let p = ray_pixel(i, inspection.size);
        selection.click(p);
    }
    // The opened sample's cell: its 12 edges and its 8 corners, sized by their weights.
    let opened = breakdown
        .trace
        .as_ref()
        .zip(breakdown.opened)
        .and_then(|(t, k)| t.samples.get(k));
    if let Some(s) = opened {
        draw_cell(&painter, &projector, s, volume.volume.spacing());
    }
    Ok(())
}

/// How ray `i` is drawn inside the volume: the selected one wide and yellow, the hovered one
/// cyan, the others white and, while another is selected, faded (width, colour, alpha).
fn ray_style(i: usize, selected: Option<usize>, hovered: Option<usize>) -> (f32, Color32, u8) {
    let alpha = if selected.is_some_and(|s| s != i) {
        35
    } else {
        255
    };
    if selected == Some(i) {
        (2.5, Color32::YELLOW, alpha)
    } else if hovered == Some(i) {
        (2.0, Color32::from_rgb(80, 220, 255), alpha)
    } else {
        (1.0, Color32::WHITE, alpha)
    }
}

/// How near (points) a click must fall to a ray's line to pick it.
const PICK_RADIUS: f32 = 6.0;

/// Distance from `p` to the segment `[a, b]`, in points.
fn distance_to_segment(p: Pos2, [a, b]: [Pos2; 2]) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_sq().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
    (a + ab * t - p).length()
}

fn draw_cell(painter: &egui::Painter, projector: &Projector, s: &SampleRecord, spacing: Vec3) {
    let r = &s.reconstruction;
    let world = |c: [u32; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) * spacing;
    let orange = Color32::from_rgb(255, 160, 40);
    for (a, b) in [
        (0, 1),
        (2, 3),
        (4, 5),
        (6, 7),
        (0, 2),
        (1, 3),
        (4, 6),
        (5, 7),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ] {
        if let Some(seg) = projector.segment(world(r.corners[a]), world(r.corners[b])) {
            painter.line_segment(seg, Stroke::new(1.5, orange));
        }
    }
    for i in 0..8 {
        if let Some(p) = projector.at(world(r.corners[i])) {
            painter.circle_filled(p, 2.0 + 8.0 * r.weights[i], orange);
            painter.text(
                p + vec2(6.0, -6.0),
                egui::Align2::LEFT_BOTTOM,
                format!("{} ×{:.3}", r.values[i], r.weights[i]),
                egui::FontId::proportional(11.0),
                Color32::WHITE,
            );
        }
    }
    if let Some(p) = projector.at(Vec3::from_array(s.p_world)) {
        painter.circle_stroke(p, 5.0, Stroke::new(2.0, Color32::YELLOW));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bevy_egui::egui::pos2;

    #[test]
    fn distance_to_a_segment() {
        let seg = [pos2(0.0, 0.0), pos2(10.0, 0.0)];
        assert_eq!(distance_to_segment(pos2(5.0, 3.0), seg), 3.0);
        assert_eq!(distance_to_segment(pos2(13.0, 4.0), seg), 5.0);
        assert_eq!(
            distance_to_segment(pos2(2.0, 0.0), [pos2(2.0, 0.0), pos2(2.0, 0.0)]),
            0.0
        );
    }
}
