//! The "Speed against accuracy" section: Measure renders the view at several steps and a fine
//! reference (`sandbox::trade`) and tabulates time, samples and error, so the step size's trade
//! is read as numbers; the player's own step is the highlighted row.

use super::{Spot, marked};
use crate::sandbox::trade::{StepTrade, TRADE_SIZE};
use bevy_egui::egui;
use voxcast_core::level::Control;
use voxcast_core::trade::Trade;

/// `is_current`: the result matches what is on screen (any step).
pub(super) fn trade_section(
    ui: &mut egui::Ui,
    trade: &mut StepTrade,
    is_current: bool,
    step_voxels: f32,
    spot: Spot,
) {
    ui.label(
        egui::RichText::new(format!(
            "This view at {}×{} pixels, rendered by the core at several steps and at a fine \
             reference step (always trilinear); the error is against the reference.",
            TRADE_SIZE.0, TRADE_SIZE.1
        ))
        .small(),
    );
    marked(ui, spot, Control::StepTrade, |ui| {
        ui.horizontal(|ui| match trade.progress() {
            Some((done, total)) => {
                ui.spinner();
                ui.label(format!("render {} of {total}", (done + 1).min(total)));
                if ui.button("Cancel").clicked() {
                    trade.cancel();
                }
            }
            None => {
                if ui
                    .button("Measure")
                    .on_hover_text("Render this view at each step and compare")
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
        table(ui, t, step_voxels);
    }
}

fn table(ui: &mut egui::Ui, t: &Trade, step_voxels: f32) {
    egui::Grid::new("trade").striped(true).show(ui, |ui| {
        super::header_row(
            ui,
            &["step", "time", "samples", "max err", "RMSE", "speed-up"],
        );
        let ms = |s: f64| format!("{:.1} ms", s * 1e3);
        for r in &t.rows {
            let text = |s: String| {
                let rich = egui::RichText::new(s);
                if (r.step_voxels - step_voxels).abs() < 1e-4 {
                    rich.color(egui::Color32::LIGHT_BLUE)
                } else {
                    rich
                }
            };
            ui.label(text(format!("{}", r.step_voxels)));
            ui.label(text(ms(r.seconds)));
            ui.label(text(r.samples.to_string()));
            ui.label(text(format!("{:.1}/255", r.max_error * 255.0)));
            ui.label(text(format!("{:.2}/255", r.rmse * 255.0)));
            ui.label(text(format!(
                "×{:.1}",
                t.reference_seconds / r.seconds.max(1e-9)
            )));
            ui.end_row();
        }
        ui.label(format!("{} (ref.)", t.reference_voxels));
        ui.label(ms(t.reference_seconds));
        ui.label(t.reference_samples.to_string());
        ui.label("0");
        ui.label("0");
        ui.label("×1");
        ui.end_row();
    });
    ui.label(
        egui::RichText::new("step in voxels; your step is in blue; speed-up against the reference")
            .small(),
    );
}
