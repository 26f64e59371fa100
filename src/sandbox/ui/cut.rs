//! The panel's "Looking inside" section: the crop box (a lower and an upper side per axis) and
//! the clip plane (orientation, flip, position); the same cut is dragged in the scene
//! (`crate::sandbox::scene::cut`).

use super::{FINE_DECIMALS, Spot, combo, labelled, marked, shown_with, slider};
use crate::sandbox::scene::cut::CutHandles;
use bevy::math::Vec3;
use bevy_egui::egui;
use voxcast_core::clip::{Clip, ClipPlane};
use voxcast_core::level::Control;
use voxcast_core::tunables as t;

/// The plane's orientations offered by name: the normal (the side removed) and its words.
const ORIENTATIONS: [(Vec3, &str); 3] = [
    (Vec3::X, "across x (removes +x)"),
    (Vec3::Y, "across y (removes +y)"),
    (Vec3::Z, "across z (removes +z)"),
];

/// The crop box and clip plane controls. `forward` is the main camera's view direction (for
/// "Face the camera").
pub(super) fn cut_section(
    ui: &mut egui::Ui,
    clip: &mut Clip,
    handles: &mut CutHandles,
    forward: Option<Vec3>,
    spot: Spot,
) {
    marked(ui, spot, Control::CropBox, |ui| {
        crop_controls(ui, clip, handles)
    });
    ui.separator();
    marked(ui, spot, Control::ClipPlane, |ui| {
        plane_controls(ui, clip, forward)
    });
}

/// The crop box: on or off (off puts every side back), and each side's two sliders.
fn crop_controls(ui: &mut egui::Ui, clip: &mut Clip, handles: &mut CutHandles) {
    let mut on = handles.crop || clip.is_cropped();
    if ui
        .checkbox(&mut on, t::CROP.label)
        .on_hover_text(t::CROP.doc)
        .changed()
    {
        handles.crop = on;
        if !on {
            clip.crop_lo = Vec3::ZERO;
            clip.crop_hi = Vec3::ONE;
        }
    }
    if !on {
        return;
    }
    ui.label(egui::RichText::new("Drag the orange rings in the scene, or set each side:").small());
    // A row a side (two a row widened the panel past a narrow window).
    for (a, axis) in ["x", "y", "z"].into_iter().enumerate() {
        let (mut lo, mut hi) = (clip.crop_lo[a], clip.crop_hi[a]);
        let from = labelled(
            ui,
            shown_with(egui::Slider::new(&mut lo, 0.0..=1.0), FINE_DECIMALS),
            format!("{axis} from"),
        )
        .on_hover_text(t::CROP.doc);
        let to = labelled(
            ui,
            shown_with(egui::Slider::new(&mut hi, 0.0..=1.0), FINE_DECIMALS),
            format!("{axis} to"),
        )
        .on_hover_text(t::CROP.doc);
        // The side moved pushes the other along: the box never turns inside out.
        if from.changed() {
            clip.crop_lo[a] = lo;
            clip.crop_hi[a] = hi.max(lo);
        } else if to.changed() {
            clip.crop_hi[a] = hi;
            clip.crop_lo[a] = lo.min(hi);
        }
    }
}

/// The clip plane: on or off, its orientation (an axis, flipped, or facing the camera) and
/// its position.
fn plane_controls(ui: &mut egui::Ui, clip: &mut Clip, forward: Option<Vec3>) {
    let mut on = clip.plane.is_some();
    if ui
        .checkbox(&mut on, t::CLIP_PLANE.label)
        .on_hover_text(t::CLIP_PLANE.doc)
        .changed()
    {
        clip.plane = on.then_some(ClipPlane {
            normal: Vec3::X,
            position: 0.0,
        });
    }
    let Some(plane) = &mut clip.plane else {
        return;
    };
    let current = ORIENTATIONS
        .iter()
        .find(|(n, _)| plane.normal.normalize_or_zero() == *n)
        .map_or("oblique (set by the camera)", |(_, words)| words);
    combo(ui, "Orientation", current, |ui| {
        for (n, words) in ORIENTATIONS {
            if ui.selectable_label(plane.normal == n, words).clicked() {
                plane.normal = n;
            }
        }
    });
    ui.horizontal(|ui| {
        if ui
            .button("Flip")
            .on_hover_text("Remove the other side instead")
            .clicked()
        {
            plane.normal = -plane.normal;
            plane.position = -plane.position;
        }
        let face = ui
            .add_enabled(forward.is_some(), egui::Button::new("Face the camera"))
            .on_hover_text(
                "Turn the plane to face the main camera, removing the half nearest to it",
            );
        if face.clicked()
            && let Some(f) = forward
            && f.length_squared() > 0.0
        {
            plane.normal = -f.normalize();
        }
    });
    slider(
        ui,
        &mut plane.position,
        &t::CLIP_POSITION,
        -1.0..=1.0,
        false,
    );
    ui.label(
        egui::RichText::new(
            "Or drag the green ring in the scene; its arrow points to the side removed.",
        )
        .small(),
    );
}
