//! The panel's small widgets: sections a level can open and mark, sliders and checkboxes whose
//! tooltips are the core's tunable docs, colours.

use super::*;

/// The one conversion of a colour to egui's (the core's values are display values: sRGB).
pub(super) use crate::sandbox::scene::overlay::color32;

/// The section's title in the panel.
pub(super) fn title(s: Section) -> &'static str {
    match s {
        Section::Dataset => "Dataset",
        Section::RayCasting => "Ray casting",
        Section::SpeedAccuracy => "Speed against accuracy",
        Section::ShadingAndLight => "Shading and light",
        Section::TransferFunction => "Transfer function",
        Section::VirtualCamera => "Virtual camera",
        Section::Preview => "Preview (slow hardware)",
        Section::LookingInside => "Looking inside (crop and clip)",
        Section::RayData => "Ray data (RayVis)",
    }
}

/// What the current level asks of the panel: the control its step is about and the sections
/// it shows (`None`: all).
#[derive(Clone, Copy)]
pub(super) struct Guide<'a> {
    pub(super) spot: Spot,
    pub(super) panel: Option<&'a [Section]>,
}

/// A collapsible section of the panel, drawn when the level shows it and opened when it holds
/// the control the step is about (`Control::section`).
pub(super) fn section(
    ui: &mut egui::Ui,
    s: Section,
    open: bool,
    guide: Guide,
    body: impl FnOnce(&mut egui::Ui),
) {
    if guide.panel.is_some_and(|p| !p.contains(&s)) {
        return;
    }
    let mut header = egui::CollapsingHeader::new(title(s)).default_open(open);
    if guide.spot.and_then(Control::section) == Some(s) {
        header = header.open(Some(true));
    }
    header.show(ui, body);
}

/// The control the current level step is about, if any.
pub(super) type Spot = Option<Control>;

/// Draws `add` and, when it is the control `spot` names, a frame around it.
pub(super) fn marked<R>(
    ui: &mut egui::Ui,
    spot: Spot,
    c: Control,
    add: impl FnOnce(&mut egui::Ui) -> R,
) -> R {
    let r = ui.scope(add);
    if spot == Some(c) {
        ui.painter().rect_stroke(
            r.response.rect.expand(2.0),
            3.0,
            egui::Stroke::new(2.0, egui::Color32::YELLOW),
            egui::StrokeKind::Outside,
        );
    }
    r.inner
}

/// Draws `add` enabled when `why_not` is `Ok`, else greyed out with the reason as tooltip.
pub(super) fn applies(
    ui: &mut egui::Ui,
    why_not: Result<(), &'static str>,
    add: impl FnOnce(&mut egui::Ui),
) {
    let response = ui.add_enabled_ui(why_not.is_ok(), add).response;
    if let Err(why) = why_not {
        response.on_disabled_hover_text(why);
    }
}

/// The decimals a linear slider over a range at most [`FINE_SPAN`] wide (a weight, a share,
/// a place across the box) shows at every value: hundredths, what such a slider is set to by
/// hand. egui's own choice follows the pointer's resolution at the slider's place, and showed
/// 0.000 at an end beside 0.70 between.
pub(super) const FINE_DECIMALS: usize = 2;
/// See [`FINE_DECIMALS`].
pub(super) const FINE_SPAN: f32 = 2.0;

/// `slider` showing its value with `decimals` decimals, the value itself left as it is. (egui's
/// `fixed_decimals` rounds the value too, and did so merely by drawing it: a crop side dragged
/// in the scene, or a setting Measure was timing, was changed by the panel.)
pub(super) fn shown_with(slider: egui::Slider<'_>, decimals: usize) -> egui::Slider<'_> {
    slider.custom_formatter(move |v, _| format!("{v:.decimals$}"))
}

/// `slider` showing its value with four significant digits, as the breakdown prints numbers
/// (`voxcast_core::numbers::sig`): for logarithmic ranges, where egui showed 0 as "0.000000".
pub(super) fn significant(slider: egui::Slider<'_>) -> egui::Slider<'_> {
    slider.custom_formatter(|v, _| voxcast_core::numbers::sig(v as f32))
}

/// A slider of `f32` for a tunable ([`tunable_slider`]), showing [`FINE_DECIMALS`] where its
/// range is linear and at most [`FINE_SPAN`] wide, and [`significant`] digits where it is
/// logarithmic: whether it changed.
pub(super) fn slider(
    ui: &mut egui::Ui,
    value: &mut f32,
    tunable: &Tunable,
    range: std::ops::RangeInclusive<f32>,
    log: bool,
) -> bool {
    let fine = !log && range.end() - range.start() <= FINE_SPAN;
    let slider = egui::Slider::new(value, range).logarithmic(log);
    let slider = if fine {
        shown_with(slider, FINE_DECIMALS)
    } else if log {
        significant(slider)
    } else {
        slider
    };
    tunable_slider(ui, slider, tunable).changed()
}

/// `slider` for a tunable: its label beside it ([`labelled`]), its name and documentation as
/// tooltip (the name first: a narrow panel may have shortened it beside the slider).
pub(super) fn tunable_slider(
    ui: &mut egui::Ui,
    slider: egui::Slider<'_>,
    tunable: &Tunable,
) -> egui::Response {
    labelled(ui, slider, tunable.label).on_hover_ui(|ui| {
        ui.strong(tunable.label);
        ui.label(tunable.doc);
    })
}

/// A one-line text field that takes what its row leaves: `buttons` are drawn first at the row's
/// right end, right to left (the last one drawn stands leftmost), then the field fills the
/// rest. At its default width (280 points) a field with buttons beside it widened the panel.
pub(super) fn field_row<R>(
    ui: &mut egui::Ui,
    text: &mut String,
    buttons: impl FnOnce(&mut egui::Ui) -> R,
) -> (egui::Response, R) {
    // One row high: a right-to-left layout given the rest of the panel centres its row in it.
    let row = egui::vec2(ui.available_width(), ui.spacing().interact_size.y);
    ui.allocate_ui_with_layout(
        row,
        egui::Layout::right_to_left(egui::Align::Center),
        |ui| {
            let r = buttons(ui);
            let field =
                ui.add(egui::TextEdit::singleline(text).desired_width(ui.available_width()));
            (field, r)
        },
    )
    .inner
}

/// A drop-down of kinds, each a name with its tooltip, showing `current`'s: the index chosen
/// (`current` where none was).
pub(super) fn kind_menu(
    ui: &mut egui::Ui,
    label: &str,
    kinds: &[(&str, &str)],
    current: usize,
) -> usize {
    let mut chosen = current;
    combo(ui, label, kinds[current].0, |ui| {
        for (i, (name, doc)) in kinds.iter().enumerate() {
            ui.selectable_value(&mut chosen, i, *name)
                .on_hover_text(*doc);
        }
    });
    chosen
}

/// A drop-down with its label beside it, each shortened with "…" where the row is too narrow
/// (the drop-down takes at most [`COMBO_SHARE`] of it): egui's own drop-down label never
/// shortens, and a long choice ("White (OpenGL, VTK)") widened the panel.
pub(super) fn combo<R>(
    ui: &mut egui::Ui,
    label: &str,
    selected: impl Into<egui::WidgetText>,
    menu: impl FnOnce(&mut egui::Ui) -> R,
) -> egui::InnerResponse<Option<R>> {
    ui.horizontal(|ui| {
        let room = ui.available_width();
        let chosen = ui
            .scope(|ui| {
                ui.set_max_width(room * COMBO_SHARE);
                egui::ComboBox::from_id_salt(label)
                    .selected_text(selected)
                    .truncate()
                    .show_ui(ui, menu)
            })
            .inner;
        let response = name_beside(ui, chosen.response, label);
        egui::InnerResponse::new(chosen.inner, response)
    })
    .inner
}

/// The most of its row a drop-down takes, the rest left to its label.
pub(super) const COMBO_SHARE: f32 = 0.6;

/// A slider with its label beside it, shortened with "…" where the panel is narrower than the
/// row: egui's own slider label neither wraps nor shortens, so one long label widened the whole
/// panel past the window's edge and cut every row at the right. The response is the slider's and
/// the label's together (hovering either shows the tooltip).
pub(super) fn labelled(
    ui: &mut egui::Ui,
    slider: egui::Slider<'_>,
    label: impl Into<egui::WidgetText>,
) -> egui::Response {
    ui.horizontal(|ui| {
        let slider = ui.add(slider);
        name_beside(ui, slider, label)
    })
    .inner
}

/// `control`'s name drawn after it in its row, shortened with "…" where the row is too narrow
/// (the caller's tooltip says what it is); the response is the two together, the control
/// named by the label for screen readers.
fn name_beside(
    ui: &mut egui::Ui,
    control: egui::Response,
    label: impl Into<egui::WidgetText>,
) -> egui::Response {
    let name = ui.add(
        egui::Label::new(label)
            .truncate()
            .show_tooltip_when_elided(false),
    );
    control.labelled_by(name.id).union(name)
}

/// A grid's header row: each title in bold, then the row's end.
pub(super) fn header_row(ui: &mut egui::Ui, titles: &[&str]) {
    for title in titles {
        ui.strong(*title);
    }
    ui.end_row();
}

pub(super) fn checkbox(ui: &mut egui::Ui, value: &mut bool, tunable: &Tunable) -> bool {
    ui.checkbox(value, tunable.label)
        .on_hover_text(tunable.doc)
        .changed()
}
