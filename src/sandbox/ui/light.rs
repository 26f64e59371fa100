//! The lights' controls: up to four lights, each with its kind (headlight, point, directional),
//! its position or direction (also dragged in the scene by its marker), colour, and a point
//! light's attenuation; lights are added and removed here; and the highlight's colour (white or
//! Levoy's).

use super::slider;
use bevy::prelude::Vec3;
use bevy_egui::egui;
use voxcast_core::marker::direction_from_marker;
use voxcast_core::shade::{Highlight, Light, LightSource, MAX_LIGHTS, Phong, SpecularModel};
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
    egui::ComboBox::from_label("Highlight")
        .selected_text(p.highlight.label())
        .show_ui(ui, |ui| {
            for h in [Highlight::White, Highlight::Levoy] {
                ui.selectable_value(&mut p.highlight, h, h.label())
                    .on_hover_text(h.doc());
            }
        })
        .response
        .on_hover_text(p.highlight.doc());
    egui::ComboBox::from_label("Specular")
        .selected_text(p.model.label())
        .show_ui(ui, |ui| {
            for m in SpecularModel::ALL {
                ui.selectable_value(&mut p.model, m, m.label())
                    .on_hover_text(SpecularModel::SPECULAR_DOC);
            }
        })
        .response
        .on_hover_text(SpecularModel::SPECULAR_DOC);
}

/// One light's kind, place, colour and attenuation.
fn one_light(ui: &mut egui::Ui, source: &mut LightSource, lo: Vec3, hi: Vec3) {
    let names = ["Headlight", "Point", "Directional"];
    let current = match source.light {
        Light::Headlight => 0,
        Light::Point(_) => 1,
        Light::Directional(_) => 2,
    };
    let mut chosen = current;
    egui::ComboBox::from_label("Kind")
        .selected_text(names[current])
        .show_ui(ui, |ui| {
            let docs = [
                "Shines along the view direction, wherever the camera goes",
                "A point in the scene (drag its marker); its light falls off with distance",
                "Parallel light from far away along a fixed direction (drag its marker)",
            ];
            for (i, (name, doc)) in names.iter().zip(docs).enumerate() {
                ui.selectable_value(&mut chosen, i, *name)
                    .on_hover_text(doc);
            }
        });
    if chosen != current {
        let point = match source.light {
            Light::Point(q) => q,
            _ => default_point(lo, hi),
        };
        source.light = match chosen {
            0 => Light::Headlight,
            1 => Light::Point(point),
            _ => Light::Directional(direction_from_marker(point, lo, hi).unwrap_or(Vec3::NEG_Y)),
        };
    }
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
    }
    let mut color = source.color.to_array();
    ui.horizontal(|ui| {
        ui.color_edit_button_rgb(&mut color)
            .on_hover_text("The light's colour and intensity (linear RGB)");
        ui.label("Colour");
    });
    source.color = Vec3::from_array(color);
    if let Light::Point(_) = source.light {
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
}
