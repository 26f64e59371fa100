//! The lights' controls: up to four lights, each with its kind (headlight, point, directional),
//! its position or direction (also dragged in the scene by its marker), colour, and a point
//! light's attenuation; lights are added and removed here; and the highlight's colour (white or
//! Levoy's).

use super::slider;
use bevy::prelude::Vec3;
use bevy_egui::egui;
use voxcast_core::marker::direction_from_marker;
use voxcast_core::shade::{Highlight, Light, LightSource, MAX_LIGHTS, Phong, SpecularModel, Spot};
use voxcast_core::tunables as t;

/// Where a newly chosen point light stands: above and to the side of the volume, outside it.
fn default_point(lo: Vec3, hi: Vec3) -> Vec3 {
    (lo + hi) * 0.5 + (hi - lo) * Vec3::new(0.8, 0.9, 0.7)
}

/// Draws the controls; `lo..hi` are the volume's bounds (for defaults and slider ranges).
pub(super) fn light_controls(ui: &mut egui::Ui, p: &mut Phong, lo: Vec3, hi: Vec3) {
    let mut remove = None;
    let count = p.lights.len();
    for (i, source) in p.lights.iter_mut().enumerate() {
        ui.push_id(("light", i), |ui| {
            egui::Frame::group(ui.style()).show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.strong(format!("Light {}", i + 1));
                    if ui
                        .small_button("Remove")
                        .on_hover_text(if count == 1 {
                            "With no light only the ambient term ka·c is left"
                        } else {
                            "Remove this light: its terms leave the sum over lights"
                        })
                        .clicked()
                    {
                        remove = Some(i);
                    }
                });
                one_light(ui, source, lo, hi);
            });
        });
    }
    if let Some(i) = remove {
        p.lights.remove(i);
    }
    if p.lights.is_empty() {
        ui.label("No light: every sample shows only its ambient colour ka·c.");
    }
    let room = p.lights.len() < MAX_LIGHTS;
    let add = ui
        .add_enabled(room, egui::Button::new("Add a light"))
        .on_hover_text(
            "Another light: the lecture's formula sums diffuse and specular over lights i, each \
             with its own colour and attenuation",
        )
        .on_disabled_hover_text(format!(
            "At most {MAX_LIGHTS} lights: the preview's shader holds that many"
        ));
    if add.clicked() {
        p.add_light();
    }
    super::combo(ui, "Highlight", p.highlight.label(), |ui| {
        for h in [Highlight::White, Highlight::Levoy] {
            ui.selectable_value(&mut p.highlight, h, h.label())
                .on_hover_text(h.doc());
        }
    })
    .response
    .on_hover_text(p.highlight.doc());
    depth_cue_controls(ui, p, (hi - lo).length());
    super::combo(ui, "Specular", p.model.label(), |ui| {
        for m in SpecularModel::ALL {
            ui.selectable_value(&mut p.model, m, m.label())
                .on_hover_text(SpecularModel::SPECULAR_DOC);
        }
    })
    .response
    .on_hover_text(SpecularModel::SPECULAR_DOC);
}

/// The four kinds of light: what each is called and what it does (the menu's tooltips).
const KINDS: [(&str, &str); 4] = [
    (
        "Headlight",
        "Shines along the view direction, wherever the camera goes",
    ),
    (
        "Point",
        "A point in the scene (drag its marker); its light falls off with distance",
    ),
    (
        "Directional",
        "Parallel light from far away along a fixed direction (drag its marker)",
    ),
    (
        "Spot",
        "A point light that shines in a cone only, brightest along its axis (the lecture's \
         spotlight factor s); drag its marker and it keeps aiming at the volume's centre",
    ),
];

/// One light's kind, place, colour and attenuation.
fn one_light(ui: &mut egui::Ui, source: &mut LightSource, lo: Vec3, hi: Vec3) {
    choose_kind(ui, source, lo, hi);
    let diagonal = (hi - lo).length().max(f32::MIN_POSITIVE);
    match &mut source.light {
        Light::Headlight => {}
        Light::Point(q) => {
            ui.horizontal(|ui| {
                ui.label("at");
                for v in [&mut q.x, &mut q.y, &mut q.z] {
                    ui.add(egui::DragValue::new(v).speed(diagonal * 0.005));
                }
            })
            .response
            .on_hover_text("The point light's world position (or drag its marker in the scene)");
        }
        Light::Directional(d) => {
            let mut e = *d;
            ui.horizontal(|ui| {
                ui.label("along");
                for v in [&mut e.x, &mut e.y, &mut e.z] {
                    ui.add(egui::DragValue::new(v).speed(0.01));
                }
            })
            .response
            .on_hover_text("The direction the light shines along (or drag its marker)");
            if e != *d && e.length_squared() > 0.0 {
                *d = e;
            }
        }
        Light::Spot(spot) => spot_controls(ui, spot, diagonal),
    }
    let mut color = source.color.to_array();
    ui.horizontal(|ui| {
        ui.color_edit_button_rgb(&mut color)
            .on_hover_text("The light's colour and intensity (linear RGB)");
        ui.label("Colour");
    });
    source.color = Vec3::from_array(color);
    slider(ui, &mut source.ambient, &t::LIGHT_AMBIENT, 0.0..=1.0, false);
    if source.light.positional() {
        attenuation_controls(ui, source, diagonal);
    }
}

/// The light's kind; a new kind keeps the light's place (or takes one beside the volume, whose
/// corners are `lo` and `hi`), a spot aiming at the volume's centre.
fn choose_kind(ui: &mut egui::Ui, source: &mut LightSource, lo: Vec3, hi: Vec3) {
    let current = match source.light {
        Light::Headlight => 0,
        Light::Point(_) => 1,
        Light::Directional(_) => 2,
        Light::Spot(_) => 3,
    };
    let chosen = super::kind_menu(ui, "Kind", &KINDS, current);
    if chosen == current {
        return;
    }
    let point = source
        .light
        .position()
        .unwrap_or_else(|| default_point(lo, hi));
    source.light = match chosen {
        0 => Light::Headlight,
        1 => Light::Point(point),
        2 => Light::Directional(direction_from_marker(point, lo, hi).unwrap_or(Vec3::NEG_Y)),
        _ => Light::Spot(Spot {
            position: point,
            direction: (lo + hi) * 0.5 - point,
            ..Spot::default()
        }),
    };
}

/// A positional light's attenuation: constant, linear and quadratic, the last two on ranges
/// scaled to the volume's `diagonal`.
fn attenuation_controls(ui: &mut egui::Ui, source: &mut LightSource, diagonal: f32) {
    slider(
        ui,
        &mut source.kc,
        &t::ATTENUATION_CONSTANT,
        0.0..=4.0,
        false,
    );
    slider(
        ui,
        &mut source.kl,
        &t::ATTENUATION_LINEAR,
        0.0..=10.0 / diagonal,
        true,
    );
    slider(
        ui,
        &mut source.kq,
        &t::ATTENUATION_QUADRATIC,
        0.0..=100.0 / (diagonal * diagonal),
        true,
    );
}

/// A spot light's place, axis and cone.
fn spot_controls(ui: &mut egui::Ui, spot: &mut Spot, diagonal: f32) {
    ui.horizontal(|ui| {
        ui.label("at");
        for v in [
            &mut spot.position.x,
            &mut spot.position.y,
            &mut spot.position.z,
        ] {
            ui.add(egui::DragValue::new(v).speed(diagonal * 0.005));
        }
    })
    .response
    .on_hover_text("The spot light's world position (or drag its marker in the scene)");
    let mut e = spot.direction;
    ui.horizontal(|ui| {
        ui.label("along");
        for v in [&mut e.x, &mut e.y, &mut e.z] {
            ui.add(egui::DragValue::new(v).speed(0.01));
        }
    })
    .response
    .on_hover_text("The direction of the cone's axis (the way the spot shines)");
    if e != spot.direction && e.length_squared() > 0.0 {
        spot.direction = e;
    }
    slider(ui, &mut spot.cutoff, &t::SPOT_CUTOFF, 0.0..=90.0, false);
    slider(ui, &mut spot.exponent, &t::SPOT_EXPONENT, 0.0..=64.0, false);
}

/// Levoy's depth cue: on or off, and its two terms.
fn depth_cue_controls(ui: &mut egui::Ui, p: &mut Phong, diagonal: f32) {
    super::checkbox(ui, &mut p.depth_cue, &t::DEPTH_CUE);
    if p.depth_cue {
        slider(
            ui,
            &mut p.depth_kc,
            &t::DEPTH_CUE_CONSTANT,
            0.01..=4.0,
            true,
        );
        let top = 20.0 / diagonal.max(f32::MIN_POSITIVE);
        slider(ui, &mut p.depth_kl, &t::DEPTH_CUE_LINEAR, 0.0..=top, true);
    }
}
