//! The Rays panel (while the virtual camera is shown): the rays' animation and sample budget,
//! and the virtual camera's image, rendered by the core, as a pixel grid — hover highlights a
//! ray, click selects it and opens its breakdown.

use super::color32;
use crate::sandbox::inspect::rays::{InspectSettings, Inspection, RayAnimation, RaySelection};
use crate::sandbox::inspect::virtual_camera::VirtualCamera;
use bevy::prelude::*;
use bevy_egui::EguiContexts;
use bevy_egui::egui::{self, Color32, Pos2, Sense, Stroke, pos2, vec2};
use voxcast_core::level::Control;
use voxcast_core::tunables as t;

/// The Rays panel: animation and budget controls, and the image as a pixel grid.
pub(super) fn rays_panel(
    mut contexts: EguiContexts,
    inspection: Res<Inspection>,
    mut selection: ResMut<RaySelection>,
    mut settings: ResMut<InspectSettings>,
    mut animation: ResMut<RayAnimation>,
    cameras: Query<&VirtualCamera>,
    mut place: super::Docked,
) -> Result {
    // No virtual camera shown (a level without one, or turned off in the panel), or the panel
    // hidden: no panel.
    if !cameras.single().is_ok_and(|c| c.shown) || !place.layout.rays {
        return Ok(());
    }
    let spot = place.lessons.spot;
    let ctx = contexts.ctx_mut()?.clone();
    let mut edited = settings.clone();
    let mut new_selection = *selection;
    let layout = &place.layout;
    place.dock.show(&ctx, "rays", |dock_ui| {
        egui::Panel::right("rays")
            .resizable(true)
            .default_size(layout.shares.side_width(super::layout::Side::Rays))
            .max_size(layout.shares.side_max(super::layout::Side::Rays))
            .show(dock_ui, |ui| {
                ui.heading("Rays");
                egui::ScrollArea::vertical().show(ui, |ui| {
                    contents(
                        ui,
                        &inspection,
                        &mut edited,
                        &mut animation,
                        spot,
                        &mut new_selection,
                    )
                });
            });
    });
    if edited != *settings {
        *settings = edited;
    }
    if new_selection != *selection {
        *selection = new_selection;
    }
    Ok(())
}

/// The panel's contents: animation and budget controls, the counts, and the pixel grid.
fn contents(
    ui: &mut egui::Ui,
    inspection: &Inspection,
    edited: &mut InspectSettings,
    animation: &mut RayAnimation,
    spot: Option<Control>,
    new_selection: &mut RaySelection,
) {
    ui.checkbox(&mut edited.shown, "Show rays and samples");
    // Labels above their sliders: the panel may be narrow (a small window, the breakdown open).
    ui.label(t::RAY_SPEED.label).on_hover_text(t::RAY_SPEED.doc);
    ui.add(
        egui::Slider::new(&mut edited.speed, t::RAY_SPEED.min..=t::RAY_SPEED.max).logarithmic(true),
    )
    .on_hover_text(t::RAY_SPEED.doc);
    ui.horizontal(|ui| {
        if ui
            .button("Replay")
            .on_hover_text("Grow the rays again")
            .clicked()
        {
            animation.replay();
        }
        if ui
            .button("Skip")
            .on_hover_text("Show the rays whole")
            .clicked()
        {
            animation.skip();
        }
    });
    ui.checkbox(&mut edited.show_opacity, "Sample opacity")
        .on_hover_text("Draw each sample as transparent as its opacity");
    ui.checkbox(&mut edited.show_blocks, "Skip blocks")
        .on_hover_text(
            "Draw the volume's 8³ blocks these rays crossed: orange where the march looked \
             inside, blue where empty-space skipping passed them (the transfer function shows \
             nothing there); the more rays crossed a block, the more opaque its lines",
        );
    if edited.show_blocks
        && let Some(traffic) = &inspection.blocks
    {
        ui.label(egui::RichText::new(crate::sandbox::inspect::blocks::summary(traffic)).small());
    }
    let mut budget = edited.budget as f32;
    ui.label(t::SAMPLE_BUDGET.label)
        .on_hover_text(t::SAMPLE_BUDGET.doc);
    if ui
        .add(
            egui::Slider::new(&mut budget, t::SAMPLE_BUDGET.min..=t::SAMPLE_BUDGET.max)
                .logarithmic(true),
        )
        .on_hover_text(t::SAMPLE_BUDGET.doc)
        .changed()
    {
        edited.budget = budget as usize;
    }
    let size = inspection.size;
    if size == UVec2::ZERO {
        // Before the first tracing comes back there is nothing to count.
        ui.label("Tracing the virtual camera's rays…");
    } else {
        ui.label(format!(
            "{}×{} rays, {} samples",
            size.x,
            size.y,
            if inspection.traces.is_some() {
                inspection.samples.to_string()
            } else {
                format!("more than {}", edited.budget)
            }
        ));
    }
    if let Some(m) = &inspection.message {
        ui.colored_label(Color32::YELLOW, m);
    }
    ui.label(
        egui::RichText::new(
            "The virtual camera's image, rendered by the core: one ray per pixel. \
     Hover to find a ray, click to open its calculation.",
        )
        .small(),
    );
    super::marked(ui, spot, Control::PixelGrid, |ui| {
        pixel_grid(ui, inspection, new_selection)
    });
}

fn pixel_grid(ui: &mut egui::Ui, inspection: &Inspection, selection: &mut RaySelection) {
    let Some(image) = &inspection.image else {
        return;
    };
    let (w, h) = (image.width.max(1), image.height.max(1));
    // As wide as the panel allows, up to 256 points.
    let cell = (ui.available_width().clamp(64.0, 256.0) / w.max(h) as f32).max(3.0);
    let (response, painter) =
        ui.allocate_painter(vec2(cell * w as f32, cell * h as f32), Sense::click());
    let response = super::target(response, "pixel grid");
    let origin = response.rect.min;
    let at = |x: u32, y: u32| {
        egui::Rect::from_min_size(origin + vec2(x as f32, y as f32) * cell, vec2(cell, cell))
    };
    for y in 0..h {
        for x in 0..w {
            let c = image.get(x, y).to_array();
            painter.rect_filled(at(x, y), 0.0, color32(Color::srgb_from_array(c)));
        }
    }
    if cell >= 6.0 {
        let grid = Stroke::new(1.0, Color32::from_gray(60));
        for x in 0..=w {
            let px = origin.x + x as f32 * cell;
            painter.line_segment([pos2(px, origin.y), pos2(px, response.rect.max.y)], grid);
        }
        for y in 0..=h {
            let py = origin.y + y as f32 * cell;
            painter.line_segment([pos2(origin.x, py), pos2(response.rect.max.x, py)], grid);
        }
    }
    let pixel_under = |p: Pos2| {
        let v = (p - origin) / cell;
        (v.x >= 0.0 && v.y >= 0.0 && (v.x as u32) < w && (v.y as u32) < h)
            .then(|| UVec2::new(v.x as u32, v.y as u32))
    };
    selection.hovered = response.hover_pos().and_then(pixel_under);
    if response.clicked()
        && let Some(p) = response.interact_pointer_pos().and_then(pixel_under)
    {
        selection.click(p);
    }
    for (p, color) in [
        (selection.hovered, Color32::from_rgb(80, 220, 255)),
        (selection.selected, Color32::YELLOW),
    ] {
        if let Some(p) = p {
            painter.rect_stroke(
                at(p.x, p.y),
                0.0,
                Stroke::new(2.0, color),
                egui::StrokeKind::Inside,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox::inspect::rays::compute;

    /// The pixel grid driven by the pointer events egui receives from a user: moving over a
    /// pixel hovers its ray, a click selects it, a second click lets it go.
    #[test]
    fn pointer_events_on_the_pixel_grid_hover_and_select_rays() {
        let (volume, render) = crate::sandbox::inspect::rays::tests::scene("bucky");
        let mut vc = VirtualCamera::framing(&volume, None).unwrap();
        (vc.width, vc.height) = (8, 8);
        let mut inspection = Inspection::default();
        compute(&volume, &render, &vc, 1_000_000, &mut inspection);
        let ctx = crate::sandbox::ui::fonts::context();
        let mut selection = RaySelection::default();
        let origin = std::cell::Cell::new(Pos2::ZERO);
        let frame = |events: Vec<egui::Event>, selection: &mut RaySelection| {
            let input = egui::RawInput {
                events,
                screen_rect: Some(egui::Rect::from_min_size(Pos2::ZERO, vec2(800.0, 600.0))),
                ..Default::default()
            };
            let output = ctx.run_ui(input, |ui| {
                origin.set(ui.cursor().min);
                pixel_grid(ui, &inspection, selection);
            });
            output.drop_without_applying_deltas();
        };
        frame(vec![], &mut selection);
        let cell = 256.0 / 8.0;
        let at = origin.get() + vec2(2.5, 5.5) * cell;
        let click = |pressed| egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Default::default(),
        };
        frame(vec![egui::Event::PointerMoved(at)], &mut selection);
        assert_eq!(selection.hovered, Some(UVec2::new(2, 5)));
        assert_eq!(selection.selected, None);
        frame(vec![click(true)], &mut selection);
        frame(vec![click(false)], &mut selection);
        assert_eq!(selection.selected, Some(UVec2::new(2, 5)));
        assert_eq!(selection.selected_index(inspection.size), Some(5 * 8 + 2));
        frame(vec![click(true)], &mut selection);
        frame(vec![click(false)], &mut selection);
        assert_eq!(selection.selected, None, "a second click lets the ray go");
    }

    /// Every string the panel draws — with the rays traced, and over budget with a message —
    /// has a glyph in the window's font.
    #[test]
    fn every_rays_panel_string_can_be_drawn() {
        let (volume, render) = crate::sandbox::inspect::rays::tests::scene("head");
        let mut vc = VirtualCamera::framing(&volume, None).unwrap();
        (vc.width, vc.height) = (6, 4);
        for budget in [1_000_000, 10] {
            let mut inspection = Inspection::default();
            compute(&volume, &render, &vc, budget, &mut inspection);
            let mut settings = InspectSettings {
                budget,
                ..Default::default()
            };
            let mut selection = RaySelection {
                selected: Some(UVec2::new(1, 1)),
                ..Default::default()
            };
            let missing = crate::sandbox::ui::missing_glyphs(|ui| {
                contents(
                    ui,
                    &inspection,
                    &mut settings,
                    &mut RayAnimation::default(),
                    Some(Control::PixelGrid),
                    &mut selection,
                )
            });
            assert!(
                missing.is_empty(),
                "budget {budget}: no glyph for {missing:?}"
            );
        }
    }
}
