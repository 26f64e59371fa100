//! The "Speed against accuracy" section: pick a knob (the step, interpolation, the cutoff,
//! jitter, supersampling, the preview's resolution or step multiplier); Measure renders the view
//! at several of its settings and at its exact reference (`voxcast_core::knob`, in the
//! background: `sandbox::trade`) and shows time, samples and error as a table and a plot, so
//! the trade is read as numbers; the player's own step is the highlighted row.

use super::{Spot, combo, marked};
use crate::sandbox::checks::frame_trade::FrameTiming;
use crate::sandbox::checks::trade::{StepTrade, TRADE_SIZE};
use bevy_egui::egui;
use voxcast_core::knob::Knob;
use voxcast_core::level::Control;
use voxcast_core::trade::Trade;

/// The table's footnote on its error columns and speed-up ("faster": "speed-up" was clipped
/// at the settings panel's width).
const ERRORS: &str = "max err and RMSE in 8-bit steps (of 255) against the reference; \
                      faster: how many times faster than the reference";

/// `is_current`: the result matches what is on screen (any step).
pub(super) fn trade_section(
    ui: &mut egui::Ui,
    trade: &mut StepTrade,
    is_current: bool,
    step_voxels: f32,
    spot: Spot,
) {
    combo(ui, "Knob", trade.knob.label(), |ui| {
        for k in Knob::ALL {
            ui.selectable_value(&mut trade.knob, k, k.label())
                .on_hover_text(k.doc());
        }
    })
    .response
    .on_hover_text(trade.knob.doc());
    let intro = if trade.knob.is_preview() {
        format!(
            "The preview's own renderer (the GPU preview or the CPU live view) draws this \
             view at the window's size at each setting, timed; the errors are the core's \
             render of the view at {}×{} pixels against the exact reference. Keep the view \
             still while it measures.",
            TRADE_SIZE.0, TRADE_SIZE.1
        )
    } else {
        format!(
            "This view at {}×{} pixels, rendered by the core at several settings of the knob \
             and at its exact reference; the error is against the reference.",
            TRADE_SIZE.0, TRADE_SIZE.1
        )
    };
    ui.label(egui::RichText::new(intro).small());
    marked(ui, spot, Control::StepTrade, |ui| {
        ui.horizontal(|ui| match trade.progress() {
            Some((what, done, total)) => {
                ui.spinner();
                ui.label(format!("{what} {} of {total}", (done + 1).min(total)));
                if ui.button("Cancel").clicked() {
                    trade.cancel();
                }
            }
            None => {
                if ui
                    .button("Measure")
                    .on_hover_text("Render this view at each setting of the knob and compare")
                    .clicked()
                {
                    trade.request();
                }
            }
        })
    });
    if let Some(e) = &trade.error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
    if let Some((t, _)) = &trade.result {
        if !is_current {
            ui.colored_label(
                egui::Color32::YELLOW,
                "measured for another view or settings: measure again",
            );
        }
        if let Some(why) = trade.stand_in {
            ui.label(
                egui::RichText::new(why)
                    .small()
                    .color(egui::Color32::YELLOW),
            );
        }
        results(ui, t, step_voxels, trade.timed_frames.as_ref());
    }
}

/// A measured trade: its table and its plot.
fn results(ui: &mut egui::Ui, t: &Trade, step_voxels: f32, frames: Option<&FrameTiming>) {
    let seconds = Seconds::of(t, frames.is_none());
    // Six columns: in a narrow panel the table scrolls sideways rather than widen it.
    egui::ScrollArea::horizontal()
        .id_salt("trade table")
        .show(ui, |ui| table(ui, t, &seconds, step_voxels, frames));
    plot(ui, t, &seconds);
}

/// Error against time, one point per row (the reference at zero error): the trade's curve.
/// Time on a logarithmic axis, as the settings' costs span orders of magnitude.
fn plot(ui: &mut egui::Ui, t: &Trade, seconds: &Seconds) {
    let points: Vec<(f64, f32, &str)> = t
        .rows
        .iter()
        .zip(&seconds.rows)
        .map(|(r, &s)| (s, r.rmse * 255.0, r.label.as_str()))
        .chain([(seconds.reference, 0.0, "ref.")])
        .collect();
    let (lo, hi) = points.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), p| {
        (lo.min(p.0.max(1e-6)), hi.max(p.0))
    });
    let top = points.iter().map(|p| p.1).fold(0.0f32, f32::max).max(1e-3);
    let (rect, _) = ui.allocate_exact_size(
        egui::vec2(ui.available_width().min(320.0), 120.0),
        egui::Sense::hover(),
    );
    let painter = ui.painter_at(rect);
    let frame = rect.shrink2(egui::vec2(28.0, 14.0));
    let stroke = egui::Stroke::new(1.0, egui::Color32::GRAY);
    painter.line_segment([frame.left_bottom(), frame.right_bottom()], stroke);
    painter.line_segment([frame.left_bottom(), frame.left_top()], stroke);
    let span = (hi / lo).ln().max(1e-9);
    let at = |(s, e): (f64, f32)| {
        let x = ((s.max(1e-6) / lo).ln() / span) as f32;
        egui::pos2(
            frame.left() + x * frame.width(),
            frame.bottom() - e / top * frame.height(),
        )
    };
    let mut sorted = points.clone();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let line: Vec<egui::Pos2> = sorted.iter().map(|p| at((p.0, p.1))).collect();
    painter.add(egui::Shape::line(
        line,
        egui::Stroke::new(1.5, egui::Color32::LIGHT_BLUE),
    ));
    let font = egui::FontId::proportional(10.0);
    let mut placed = Vec::new();
    for p in &points {
        let c = at((p.0, p.1));
        painter.circle_filled(c, 3.0, egui::Color32::LIGHT_BLUE);
        let galley = painter.layout_no_wrap(p.2.to_string(), font.clone(), egui::Color32::WHITE);
        let spot = label_spot(c, galley.size(), &placed);
        placed.push(spot);
        painter.galley(spot.min, galley, egui::Color32::WHITE);
    }
    painter.text(
        frame.left_top() - egui::vec2(2.0, 2.0),
        egui::Align2::RIGHT_TOP,
        format!("{top:.1}"),
        font.clone(),
        egui::Color32::GRAY,
    );
    painter.text(
        frame.left_bottom() + egui::vec2(0.0, 2.0),
        egui::Align2::LEFT_TOP,
        format!("{:.1} ms", lo * 1e3),
        font.clone(),
        egui::Color32::GRAY,
    );
    painter.text(
        frame.right_bottom() + egui::vec2(0.0, 2.0),
        egui::Align2::RIGHT_TOP,
        format!("{:.1} ms   RMSE /255 against time", hi * 1e3),
        font,
        egui::Color32::GRAY,
    );
}

/// Where a point's label goes: above and right of `point` unless that covers a label already
/// placed (two settings that take about the same time and error, as ½ and ¼ voxel on a small
/// view, printed "0.250.5"), then below right, above left, below left; above right if all do.
fn label_spot(point: egui::Pos2, size: egui::Vec2, placed: &[egui::Rect]) -> egui::Rect {
    let (dx, dy) = (4.0, 2.0);
    let corners = [
        point + egui::vec2(dx, -dy - size.y),
        point + egui::vec2(dx, dy),
        point + egui::vec2(-dx - size.x, -dy - size.y),
        point + egui::vec2(-dx - size.x, dy),
    ];
    let rects = corners.map(|min| egui::Rect::from_min_size(min, size));
    rects
        .into_iter()
        .find(|r| !placed.iter().any(|p| p.intersects(*r)))
        .unwrap_or(rects[0])
}

/// The times the table and the plot show: each setting's fastest run where the core's renders
/// were timed in this window (the window draws all the while on the same computer, and the
/// fastest run is the one it disturbed least: medians of 2-ms renders came out in any order),
/// else the medians (the preview's timed frames, which are the window's own).
struct Seconds {
    reference: f64,
    rows: Vec<f64>,
}

impl Seconds {
    fn of(t: &Trade, fastest: bool) -> Self {
        let pick = |timing: &voxcast_core::trade::Timing, median: f64| {
            if fastest { timing.fastest } else { median }
        };
        Self {
            reference: pick(&t.reference_timing, t.reference_seconds),
            rows: t.rows.iter().map(|r| pick(&r.timing, r.seconds)).collect(),
        }
    }
}

fn table(
    ui: &mut egui::Ui,
    t: &Trade,
    seconds: &Seconds,
    step_voxels: f32,
    frames: Option<&FrameTiming>,
) {
    egui::Grid::new("trade").striped(true).show(ui, |ui| {
        let knob = match t.knob {
            Knob::Step => "step",
            Knob::PreviewScale => "resolution",
            Knob::PreviewStepMultiplier => "step ×",
            Knob::AdaptiveQuality => "resolution and step ×",
            _ => t.knob.label(),
        };
        super::header_row(ui, &[knob, "time", "samples", "max err", "RMSE", "faster"]);
        let ms = |s: f64| format!("{:.1} ms", s * 1e3);
        let reference_seconds = seconds.reference;
        for (r, &seconds) in t.rows.iter().zip(&seconds.rows) {
            let text = |s: String| {
                let rich = egui::RichText::new(s);
                if t.knob == Knob::Step && (r.step_voxels - step_voxels).abs() < 1e-4 {
                    rich.color(egui::Color32::LIGHT_BLUE)
                } else {
                    rich
                }
            };
            ui.label(text(r.label.clone()));
            ui.label(text(ms(seconds))).on_hover_text(spread(&r.timing));
            ui.label(text(r.samples.to_string()));
            // In 8-bit steps, the unit said once below: "/255" in every cell widened the panel.
            ui.label(text(format!("{:.1}", r.max_error * 255.0)));
            ui.label(text(format!("{:.2}", r.rmse * 255.0)));
            ui.label(text(format!(
                "×{:.1}",
                reference_seconds / seconds.max(1e-9)
            )));
            ui.end_row();
        }
        // The reference's setting is spelt out below the table: in its first column it
        // widened the side panel past the window's room.
        ui.label("reference").on_hover_text(format!(
            "{}: the exact setting every row is measured against",
            t.reference
        ));
        ui.label(ms(reference_seconds))
            .on_hover_text(spread(&t.reference_timing));
        ui.label(t.reference_samples.to_string());
        ui.label("0");
        ui.label("0");
        ui.label("×1");
        ui.end_row();
    });
    let words = match frames {
        Some(f) => format!(
            "{} (hover a time for the fastest and slowest); {ERRORS}",
            f.words(t.runs)
        ),
        None => format!(
            "{}time: the fastest of {} renders after an untimed one, the settings taken in turn \
             (hover a time for the median and the slowest), each on {} thread{}; the window \
             draws all the while on the same computer, and the fastest run is the one it \
             disturbed least; {ERRORS}",
            if t.knob == Knob::Step {
                "step in voxels; your step is in blue; "
            } else {
                ""
            },
            t.runs,
            t.threads,
            if t.threads == 1 { "" } else { "s" }
        ),
    };
    ui.label(egui::RichText::new(format!("reference: {}; {words}", t.reference)).small());
}

/// A timing's spread, in words.
fn spread(t: &voxcast_core::trade::Timing) -> String {
    format!(
        "fastest {:.1} ms, median {:.1} ms, slowest {:.1} ms",
        t.fastest * 1e3,
        t.median * 1e3,
        t.slowest * 1e3
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxcast_core::trade::{Timing, TradeRow};

    #[test]
    fn labels_of_neighbouring_points_do_not_overlap() {
        let size = egui::vec2(16.0, 10.0);
        let mut placed = Vec::new();
        // Three points a few pixels apart, as close settings plot.
        for x in [100.0, 104.0, 108.0] {
            let spot = label_spot(egui::pos2(x, 50.0), size, &placed);
            assert!(
                !placed.iter().any(|p: &egui::Rect| p.intersects(spot)),
                "{spot:?}"
            );
            placed.push(spot);
        }
        // Alone, a label sits above and to the right of its point.
        let alone = label_spot(egui::pos2(10.0, 50.0), size, &[]);
        assert!(alone.left() > 10.0 && alone.bottom() < 50.0, "{alone:?}");
    }

    fn timing(fastest: f64) -> Timing {
        Timing {
            median: 2.0 * fastest,
            fastest,
            slowest: 3.0 * fastest,
        }
    }

    /// A step trade with a row for each of `fastest` seconds.
    fn trade(fastest: &[f64]) -> Trade {
        let row = |fastest: f64| TradeRow {
            label: "0.25".into(),
            step_voxels: 0.25,
            seconds: 2.0 * fastest,
            timing: timing(fastest),
            samples: 161232,
            max_error: 86.7 / 255.0,
            rmse: 1.64 / 255.0,
        };
        Trade {
            knob: Knob::Step,
            reference: "step 0.0625 voxel".into(),
            reference_voxels: 0.0625,
            reference_seconds: 0.016,
            reference_timing: timing(0.008),
            reference_samples: 8,
            rows: fastest.iter().map(|&f| row(f)).collect(),
            runs: 5,
            threads: 2,
        }
    }

    #[test]
    fn the_core_s_renders_show_their_fastest_run_and_the_window_s_frames_their_median() {
        let t = trade(&[0.001, 0.002]);
        let fastest = Seconds::of(&t, true);
        assert_eq!(
            (fastest.reference, fastest.rows),
            (0.008, vec![0.001, 0.002])
        );
        let medians = Seconds::of(&t, false);
        assert_eq!(
            (medians.reference, medians.rows),
            (0.016, vec![0.002, 0.004])
        );
    }

    /// The measured section fits the settings panel at its narrowest (its table scrolls
    /// sideways there).
    #[test]
    fn the_measured_section_fits_the_narrowest_panel() {
        let t = trade(&[0.0021, 0.0123]);
        let room = super::super::narrowest_section_room();
        let size = super::super::size_in(room, |ui| {
            let mut step_trade = StepTrade::default();
            trade_section(ui, &mut step_trade, true, 0.25, None);
            results(ui, &t, 0.25, None);
        });
        assert!(size.x <= room + 0.5, "{} points wide in {room}", size.x);
    }
}
