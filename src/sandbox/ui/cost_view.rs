//! The preview's cost view: the choice between the picture and what its rays cost (or, with
//! First, its depth), and the legend — inferno's scale from none to the count drawn pale
//! yellow, the stops' colours, or the depth's greys.

use bevy_egui::egui;
use voxcast_core::colormap::inferno;
use voxcast_core::composite::Method;
use voxcast_core::cost::{CAPPED_COLOR, CostView, EARLY_COLOR, LEFT_COLOR};
use voxcast_core::depth::{FAR_SHADE, NEAR_SHADE};

/// What a cost-view choice shows: the preview, or Render image's render.
pub(super) struct Shown {
    /// "Show the preview as:".
    pub label: &'static str,
    /// The picture's tooltip.
    pub picture: &'static str,
    /// How to get the depth where the method is not First.
    pub to_first: &'static str,
}

/// The preview's choice.
pub(super) const PREVIEW: Shown = Shown {
    label: "Show the preview as:",
    picture: "The volume rendered",
    to_first: "Choose the method First to see it.",
};

/// The choice: the picture or one of the cost views (the depth only for `method` First; a
/// depth chosen before the method changed falls back to the picture).
pub(super) fn choice(
    ui: &mut egui::Ui,
    shown: &Shown,
    cost_view: &mut Option<CostView>,
    method: Method,
) {
    ui.horizontal_wrapped(|ui| {
        ui.label(shown.label);
        ui.selectable_value(cost_view, None, "picture")
            .on_hover_text(shown.picture);
        for view in CostView::ALL {
            let choice = ui
                .add_enabled(
                    view.shows_for(method),
                    egui::Button::selectable(*cost_view == Some(view), view.label()),
                )
                .on_hover_text(view.doc())
                .on_disabled_hover_text(format!("{} {}", view.doc(), shown.to_first));
            if choice.clicked() {
                *cost_view = Some(view);
            }
        }
    });
    if cost_view.is_some_and(|v| !v.shows_for(method)) {
        *cost_view = None;
    }
}

/// The legend of `view`: `words` is the scale of the frame on screen in words (`None` until
/// a frame of this view is drawn).
pub(super) fn legend(ui: &mut egui::Ui, view: CostView, words: Option<&str>) {
    let width = ui.available_width().clamp(80.0, 260.0);
    let (rect, _) = ui.allocate_exact_size(egui::vec2(width, 10.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    // The bar: `n` cells, each the colour at its middle's fraction of the scale.
    let bar = |n: usize, colour: &dyn Fn(f32) -> [f32; 3]| {
        let w = rect.width() / n as f32;
        for i in 0..n {
            let x = rect.left() + w * i as f32;
            let r = egui::Rect::from_min_size(egui::pos2(x, rect.top()), egui::vec2(w + 0.5, 10.0));
            let c = colour((i as f32 + 0.5) / n as f32);
            painter.rect_filled(
                r,
                0.0,
                super::color32(bevy::color::Color::srgb_from_array(c)),
            );
        }
    };
    match view {
        CostView::Stops => {
            let parts = [
                LEFT_COLOR,
                EARLY_COLOR,
                CAPPED_COLOR,
                voxcast_core::glam::Vec3::ZERO,
            ];
            bar(parts.len(), &|x| {
                parts[((x * parts.len() as f32) as usize).min(parts.len() - 1)].to_array()
            });
        }
        CostView::Depth | CostView::DepthOfHits => {
            bar(32, &|x| [NEAR_SHADE + (FAR_SHADE - NEAR_SHADE) * x; 3])
        }
        _ => bar(64, &|x| inferno(x).to_array()),
    }
    let words = match (view, words) {
        (CostView::Stops, _) => {
            "blue: left the volume · orange: stopped early · red: sample cap · black: missed"
                .to_string()
        }
        (_, Some(words)) => words.to_string(),
        (CostView::Depth | CostView::DepthOfHits, None) => "measuring…".to_string(),
        (_, None) => "counting…".to_string(),
    };
    ui.label(egui::RichText::new(words).small())
        .on_hover_text(view.doc());
}
