//! Classification: the transfer function's own opacity, or Levoy's isovalue contours (opacity
//! from the distance to chosen values, scaled by the gradient) or region boundaries (opacity
//! scaled by the gradient magnitude), or rectangles over value × gradient magnitude (the
//! lecture's classification by value and gradient; editor in `value_gradient.rs`).

use super::slider;
use bevy_egui::egui;
use voxcast_core::classify::Classification;
use voxcast_core::tunables as t;

/// The panel's text for the isovalue list, kept while it does not parse, and the
/// value-and-gradient editor.
#[derive(Default)]
pub(super) struct ClassifyText {
    isovalues: String,
    error: Option<String>,
    regions: super::value_gradient::RegionEditor,
}

/// The four classifications: what each is called and what it does (the menu's tooltips).
const KINDS: [(&str, &str); 4] = [
    ("Transfer function", "Opacity is the transfer function's"),
    (
        "Iso-contours (Levoy)",
        "Opacity peaks at each isovalue and falls off with the distance to it, measured in \
         gradient steps: thin, even surfaces",
    ),
    (
        "Boundaries (Levoy)",
        "The table's opacity scaled by the gradient magnitude: region boundaries show, \
         homogeneous insides fade",
    ),
    (
        "Value and gradient (2-D)",
        "Opacity from rectangles you draw over the histogram of value × gradient magnitude: \
         a boundary (high gradient) can be kept apart from a material of the same value (low \
         gradient), which a transfer function of the value alone cannot",
    ),
];

/// Draws the controls for a volume (from `source`): the classification chosen, then its own.
pub(super) fn classification_controls(
    ui: &mut egui::Ui,
    c: &mut Classification,
    text: &mut ClassifyText,
    volume: &voxcast_core::Volume,
    source: &str,
) {
    let (lo, hi) = volume.value_range();
    choose_kind(ui, c, text, (lo, hi));
    match c {
        Classification::Table => {}
        Classification::IsoContours {
            isovalues,
            thickness_voxels,
        } => iso_controls(ui, isovalues, thickness_voxels, text),
        Classification::Boundaries { full_gradient } => {
            let mut auto = full_gradient.is_none();
            ui.checkbox(&mut auto, "automatic full-opacity gradient")
                .on_hover_text(t::BOUNDARY_GRADIENT.doc);
            if auto {
                *full_gradient = None;
            } else {
                let mut g = full_gradient.unwrap_or(0.1 * (hi - lo).max(1e-6));
                let top = (hi - lo).max(1e-6) * 2.0;
                slider(ui, &mut g, &t::BOUNDARY_GRADIENT, top * 1e-4..=top, true);
                *full_gradient = Some(g);
            }
        }
        Classification::ValueGradient { regions } => {
            text.regions.show(ui, regions, volume, source);
        }
    }
}

/// The classification menu; a new choice starts from its defaults (iso-contours at the middle
/// of the value range `lo`…`hi`).
fn choose_kind(
    ui: &mut egui::Ui,
    c: &mut Classification,
    text: &mut ClassifyText,
    (lo, hi): (f32, f32),
) {
    let current = match c {
        Classification::Table => 0,
        Classification::IsoContours { .. } => 1,
        Classification::Boundaries { .. } => 2,
        Classification::ValueGradient { .. } => 3,
    };
    let chosen = super::kind_menu(ui, "Classification", &KINDS, current);
    if chosen == current {
        return;
    }
    *c = match chosen {
        0 => Classification::Table,
        1 => {
            let mid = 0.5 * (lo + hi);
            text.isovalues = mid.to_string();
            text.error = None;
            Classification::IsoContours {
                isovalues: vec![mid],
                thickness_voxels: t::ISO_THICKNESS.default,
            }
        }
        2 => Classification::Boundaries {
            full_gradient: None,
        },
        _ => Classification::ValueGradient {
            regions: Vec::new(),
        },
    };
}

/// The isovalues, typed as a list (a list that does not read says why and changes nothing),
/// and the contours' thickness.
fn iso_controls(
    ui: &mut egui::Ui,
    isovalues: &mut Vec<f32>,
    thickness_voxels: &mut f32,
    text: &mut ClassifyText,
) {
    if text.isovalues.is_empty() {
        text.isovalues = join(isovalues);
    }
    ui.horizontal(|ui| {
        ui.label("isovalues");
        if ui
            .text_edit_singleline(&mut text.isovalues)
            .on_hover_text("Values (data units) to show as surfaces, separated by commas")
            .changed()
        {
            match parse(&text.isovalues) {
                Ok(v) => {
                    *isovalues = v;
                    text.error = None;
                }
                Err(e) => text.error = Some(e),
            }
        }
    });
    if let Some(e) = &text.error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
    slider(ui, thickness_voxels, &t::ISO_THICKNESS, 0.1..=8.0, true);
}

fn join(values: &[f32]) -> String {
    values
        .iter()
        .map(f32::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Comma-separated finite numbers, at least one.
fn parse(text: &str) -> Result<Vec<f32>, String> {
    let values = text
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<f32>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("'{s}' is not a number"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    if values.is_empty() {
        return Err("give at least one isovalue".into());
    }
    if values.len() > voxcast_core::classify::MAX_ISOVALUES {
        return Err(format!(
            "at most {} isovalues (the GPU preview's limit): remove {}",
            voxcast_core::classify::MAX_ISOVALUES,
            values.len() - voxcast_core::classify::MAX_ISOVALUES
        ));
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isovalue_lists_parse_or_say_why_not() {
        assert_eq!(parse("80, 120.5 ,200").unwrap(), vec![80.0, 120.5, 200.0]);
        assert!(parse("80, bone").unwrap_err().contains("bone"));
        assert!(parse(" , ").is_err());
        assert!(parse("inf").is_err());
        assert_eq!(parse("1, 2, 3, 4").unwrap().len(), 4);
        let five = parse("1, 2, 3, 4, 5").unwrap_err();
        assert!(
            five.contains("at most 4") && five.contains("remove 1"),
            "{five}"
        );
        assert_eq!(join(&[1.0, 2.5]), "1, 2.5");
    }
}
