//! The preview's cost view: the choice between the picture and what its rays cost, and the
//! legend — inferno's scale from none to the count drawn pale yellow, or the stops' colours.

use bevy_egui::egui;
use voxcast_core::colormap::inferno;
use voxcast_core::cost::{CAPPED_COLOR, CostView, EARLY_COLOR, LEFT_COLOR};

/// The choice: the picture or one of the cost views.
pub(super) fn choice(ui: &mut egui::Ui, cost_view: &mut Option<CostView>) {
    ui.horizontal_wrapped(|ui| {
        ui.label("Show the preview as:");
        ui.selectable_value(cost_view, None, "picture")
            .on_hover_text("The volume rendered");
        for view in CostView::ALL {
            ui.selectable_value(cost_view, Some(view), view.name())
                .on_hover_text(view.doc());
        }
    });
}

/// The legend of `view`: `scale` is the count drawn pale yellow and the busiest pixel's count
/// in the frame on screen (`None` until a frame of this view is drawn).
pub(super) fn legend(ui: &mut egui::Ui, view: CostView, scale: Option<(u32, u32)>) {
    let width = ui.available_width().clamp(80.0, 260.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 10.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    match view {
        CostView::Stops => {
            let parts = [
                LEFT_COLOR,
                EARLY_COLOR,
                CAPPED_COLOR,
                voxcast_core::glam::Vec3::ZERO,
            ];
            let w = rect.width() / parts.len() as f32;
            for (i, c) in parts.into_iter().enumerate() {
                let x = rect.left() + w * i as f32;
                let r = egui::Rect::from_min_size(egui::pos2(x, rect.top()), egui::vec2(w, 10.0));
                painter.rect_filled(r, 0.0, super::color32(c.to_array()));
            }
        }
        _ => {
            let n = 64;
            let w = rect.width() / n as f32;
            for i in 0..n {
                let x = rect.left() + w * i as f32;
                let r =
                    egui::Rect::from_min_size(egui::pos2(x, rect.top()), egui::vec2(w + 0.5, 10.0));
                painter.rect_filled(
                    r,
                    0.0,
                    super::color32(inferno((i as f32 + 0.5) / n as f32).to_array()),
                );
            }
        }
    }
    let words = match (view, scale) {
        (CostView::Stops, _) => {
            "blue: left the volume · orange: stopped early · red: sample cap · \
                                 black: missed"
                .to_string()
        }
        (_, Some((full, busiest))) => voxcast_core::cost::scale_words(full, busiest),
        (_, None) => "counting…".to_string(),
    };
    ui.label(egui::RichText::new(words).small())
        .on_hover_text(view.doc());
}
