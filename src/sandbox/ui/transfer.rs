//! The transfer-function editor: the opacity curve and its control points drawn over the
//! volume's histogram (linear or log counts), the colour the function gives each value in a
//! strip beneath. Click to add a point on the curve, drag to move one, right-click to delete;
//! the selected point's value, opacity and colour are edited below. Save and load as JSON.
//!
//! Every edit goes through the core's `TransferFunction::with_point_*`, so the editor can only
//! produce a valid function.

use crate::sandbox::shared::files;
use bevy_egui::egui::{self, Color32, Pos2, Rect, Sense, Stroke, pos2, vec2};
use voxcast_core::error::io_words;
use voxcast_core::histogram::{Histogram, HistogramScale};
use voxcast_core::numbers::sig;
use voxcast_core::transfer::TransferFunction;

/// Histogram bins drawn under the curve.
const BINS: usize = 128;
/// Height of the curve's plot and of the colour strip, in points.
const PLOT_HEIGHT: f32 = 140.0;
const STRIP_HEIGHT: f32 = 14.0;
/// How near (points) the pointer must be to grab a control point.
const GRAB_RADIUS: f32 = 8.0;

/// The editor's own state.
pub(super) struct TransferEditor {
    /// The histogram and the volume source it was counted for.
    histogram: Option<(String, Histogram)>,
    log: bool,
    selected: Option<usize>,
    dragging: Option<usize>,
    path: String,
    message: Option<Result<String, String>>,
}

impl Default for TransferEditor {
    fn default() -> Self {
        Self {
            histogram: None,
            log: true,
            selected: None,
            dragging: None,
            path: "transfer.json".into(),
            message: None,
        }
    }
}

/// Maps between data values/opacities and the plot's points.
struct Plot {
    rect: Rect,
    lo: f32,
    hi: f32,
}

impl Plot {
    fn x(&self, value: f32) -> f32 {
        self.rect.left() + (value - self.lo) / (self.hi - self.lo) * self.rect.width()
    }
    fn y(&self, alpha: f32) -> f32 {
        self.rect.bottom() - alpha * self.rect.height()
    }
    fn at(&self, value: f32, alpha: f32) -> Pos2 {
        pos2(self.x(value), self.y(alpha))
    }
    /// Value and opacity under `p`, clamped to the plot.
    fn value_alpha(&self, p: Pos2) -> (f32, f32) {
        let fx = ((p.x - self.rect.left()) / self.rect.width()).clamp(0.0, 1.0);
        let fy = ((self.rect.bottom() - p.y) / self.rect.height()).clamp(0.0, 1.0);
        (self.lo + fx * (self.hi - self.lo), fy)
    }
    /// The point within reach of `p`.
    fn grab(&self, tf: &TransferFunction, p: Pos2) -> Option<usize> {
        let (v, a) = self.value_alpha(p);
        let h = self.rect.height();
        let scale = self.rect.width() / h / (self.hi - self.lo);
        tf.point_near(v, a, scale, GRAB_RADIUS / h)
    }
}

impl TransferEditor {
    /// Draws the editor for `tf` over the histogram of the volume `source`; returns true when
    /// `tf` was changed.
    pub fn show(
        &mut self,
        ui: &mut egui::Ui,
        tf: &mut TransferFunction,
        volume: &voxcast_core::Volume,
        source: &str,
    ) -> bool {
        if self.histogram.as_ref().is_none_or(|(s, _)| s != source) {
            self.histogram = Some((source.to_string(), Histogram::of(volume, BINS)));
            self.selected = None;
        }
        let mut changed = false;
        let mut edited = tf.clone();
        let (lo, hi) = volume.value_range();
        let hi = if hi > lo { hi } else { lo + 1.0 };
        let width = ui.available_width().max(120.0);
        let (response, painter) = ui.allocate_painter(
            vec2(width, PLOT_HEIGHT + STRIP_HEIGHT),
            Sense::click_and_drag(),
        );
        let full = response.rect;
        let plot = Plot {
            rect: Rect::from_min_max(full.min, pos2(full.max.x, full.max.y - STRIP_HEIGHT)),
            lo,
            hi,
        };
        painter.rect_filled(plot.rect, 0.0, Color32::from_gray(24));
        self.draw_histogram(&painter, &plot);
        self.follow_pointer(&response, &plot, &mut edited);
        self.draw_curve(&painter, &plot, &edited);
        draw_strip(&painter, full, &plot, &edited);
        response.on_hover_text(
            "Opacity (up) against value (across), over the histogram. Click: add a point · \
             drag: move it · right-click: delete it. The strip shows each value's colour.",
        );
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.log, "log counts")
                .on_hover_text("Histogram heights as ln(1 + count): rare values stay visible");
            ui.label(format!(
                "{} … {}",
                voxcast_core::numbers::sig(lo),
                voxcast_core::numbers::sig(hi)
            ));
        });
        changed |= self.selected_point(ui, &mut edited, lo, hi);
        changed |= self.save_load(ui, &mut edited);
        if edited != *tf {
            *tf = edited;
            changed = true;
        }
        changed
    }

    /// The volume's histogram as grey bars under the curve, linear or log as chosen.
    fn draw_histogram(&self, painter: &egui::Painter, plot: &Plot) {
        let Some((_, h)) = &self.histogram else {
            return;
        };
        let scale = if self.log {
            HistogramScale::Log
        } else {
            HistogramScale::Linear
        };
        let bar = plot.rect.width() / h.counts.len() as f32;
        for (i, height) in h.heights(scale).iter().enumerate() {
            let x = plot.rect.left() + i as f32 * bar;
            let top = plot.rect.bottom() - height * plot.rect.height();
            painter.rect_filled(
                Rect::from_min_max(pos2(x, top), pos2(x + bar, plot.rect.bottom())),
                0.0,
                Color32::from_gray(70),
            );
        }
    }

    /// The pointer's edits of `edited`: a drag moves the point grabbed, a click selects the
    /// point under it or adds one on the curve, a right-click deletes the point under it.
    fn follow_pointer(
        &mut self,
        response: &egui::Response,
        plot: &Plot,
        edited: &mut TransferFunction,
    ) {
        let pointer = response.interact_pointer_pos();
        if response.drag_started()
            && let Some(p) = pointer
        {
            self.dragging = plot.grab(edited, p);
            if self.dragging.is_some() {
                self.selected = self.dragging;
            }
        }
        if response.dragged()
            && let (Some(i), Some(p)) = (self.dragging, pointer)
        {
            let (v, a) = plot.value_alpha(p);
            if let Ok((moved, j)) = edited.with_point_moved(i, v, a) {
                *edited = moved;
                self.dragging = Some(j);
                self.selected = Some(j);
            }
        }
        if response.drag_stopped() {
            self.dragging = None;
        }
        if response.clicked()
            && let Some(p) = pointer
        {
            match plot.grab(edited, p) {
                Some(i) => self.selected = Some(i),
                None => {
                    let (v, a) = plot.value_alpha(p);
                    if let Ok((added, i)) = edited.with_point_added(v, a) {
                        *edited = added;
                        self.selected = Some(i);
                    }
                }
            }
        }
        if response.secondary_clicked()
            && let Some(i) = pointer.and_then(|p| plot.grab(edited, p))
        {
            match edited.with_point_removed(i) {
                Ok(removed) => {
                    *edited = removed;
                    self.selected = None;
                }
                Err(e) => self.message = Some(Err(e.to_string())),
            }
        }
    }

    /// The opacity curve across the value range and its points, the selected one ringed.
    fn draw_curve(&self, painter: &egui::Painter, plot: &Plot, edited: &TransferFunction) {
        let (lo, hi) = (plot.lo, plot.hi);
        let points = edited.points();
        let mut line = vec![plot.at(lo, points[0].alpha)];
        line.extend(
            points
                .iter()
                .map(|p| plot.at(p.value.clamp(lo, hi), p.alpha)),
        );
        line.push(plot.at(hi, points[points.len() - 1].alpha));
        painter.add(egui::Shape::line(line, Stroke::new(1.5, Color32::WHITE)));
        for (i, p) in points.iter().enumerate() {
            let selected = self.selected == Some(i);
            painter.circle(
                plot.at(p.value.clamp(lo, hi), p.alpha),
                if selected { 6.0 } else { 4.5 },
                super::color32(bevy::color::Color::srgb_from_array(p.color)),
                Stroke::new(
                    if selected { 2.5 } else { 1.0 },
                    if selected {
                        Color32::YELLOW
                    } else {
                        Color32::WHITE
                    },
                ),
            );
        }
    }

    /// The selected point's value, opacity and colour, and Delete.
    fn selected_point(
        &mut self,
        ui: &mut egui::Ui,
        tf: &mut TransferFunction,
        lo: f32,
        hi: f32,
    ) -> bool {
        let Some(i) = self.selected.filter(|&i| i < tf.points().len()) else {
            self.selected = None;
            return false;
        };
        let p = tf.points()[i];
        let (mut value, mut alpha, mut color) = (p.value, p.alpha, p.color);
        let mut delete = false;
        ui.horizontal(|ui| {
            ui.label(format!("point {}:", i + 1));
            ui.add(
                egui::DragValue::new(&mut value)
                    .speed((hi - lo) / 500.0)
                    .custom_formatter(|v, _| sig(v as f32))
                    .prefix("value "),
            )
            .on_hover_text("Where the point sits, in data units");
            ui.add(
                egui::DragValue::new(&mut alpha)
                    .speed(0.005)
                    .range(0.0..=1.0)
                    .custom_formatter(|v, _| sig(v as f32))
                    .prefix("opacity "),
            )
            .on_hover_text("Opacity per reference step at this value");
            ui.color_edit_button_rgb(&mut color)
                .on_hover_text("The colour at this value");
            delete = ui.button("Delete").clicked();
        });
        let mut next = tf.clone();
        if delete {
            match tf.with_point_removed(i) {
                Ok(t) => {
                    *tf = t;
                    self.selected = None;
                    return true;
                }
                Err(e) => self.message = Some(Err(e.to_string())),
            }
        }
        if (value, alpha) != (p.value, p.alpha)
            && let Ok((moved, j)) = next.with_point_moved(i, value, alpha)
        {
            next = moved;
            self.selected = Some(j);
        }
        if color != p.color
            && let Some(j) = self.selected
            && let Ok(t) = next.with_point_color(j, color.map(|c| c.clamp(0.0, 1.0)))
        {
            next = t;
        }
        let changed = next != *tf;
        *tf = next;
        changed
    }

    fn save_load(&mut self, ui: &mut egui::Ui, tf: &mut TransferFunction) -> bool {
        let mut changed = false;
        // Right to left: Load (or Open…), then Save, then the path field.
        let (field, (save_clicked, load_clicked)) = super::field_row(ui, &mut self.path, |ui| {
            let load_clicked = if files::PICKS_FILES {
                if ui
                    .button("Open…")
                    .on_hover_text("A transfer-function JSON file from this computer")
                    .clicked()
                {
                    files::pick(files::Purpose::Transfer);
                }
                false
            } else {
                ui.button("Load").clicked()
            };
            (ui.button("Save").clicked(), load_clicked)
        });
        field.on_hover_text("A transfer-function JSON file ({\"name\", \"points\": [...]})");
        if save_clicked {
            self.message = Some(save(tf, &self.path));
        }
        if load_clicked {
            match load(&self.path) {
                Ok(t) => changed |= self.take(t, &self.path.clone(), tf),
                Err(e) => self.message = Some(Err(e)),
            }
        }
        match &self.message {
            Some(Ok(m)) => {
                ui.label(m);
            }
            Some(Err(e)) => {
                ui.colored_label(Color32::LIGHT_RED, e);
            }
            None => {}
        }
        changed
    }
}

/// Writes `tf` as JSON (through a temporary file and a rename, so a failed write loses
/// nothing; in a browser, a download).
fn save(tf: &TransferFunction, path: &str) -> Result<String, String> {
    files::save(
        std::path::Path::new(path.trim()),
        tf.to_json().as_bytes(),
        "application/json",
    )
}

impl TransferEditor {
    /// Makes `t` (read from `name`) the transfer function.
    fn take(&mut self, t: TransferFunction, name: &str, tf: &mut TransferFunction) -> bool {
        *tf = t;
        self.selected = None;
        self.message = Some(Ok(format!("loaded {name}")));
        true
    }

    /// A transfer function the browser handed over as `name`'s `bytes`: taken when it reads,
    /// else the reason shown. Whether `tf` changed.
    pub(super) fn receive(&mut self, name: &str, bytes: &[u8], tf: &mut TransferFunction) -> bool {
        let read = std::str::from_utf8(bytes)
            .map_err(|_| format!("{name}: not a text file"))
            .and_then(|text| TransferFunction::from_json(text).map_err(|e| format!("{name}: {e}")));
        match read {
            Ok(t) => self.take(t, name, tf),
            Err(e) => {
                self.message = Some(Err(e));
                false
            }
        }
    }
}

fn load(path: &str) -> Result<TransferFunction, String> {
    let path = path.trim();
    files::file_name(std::path::Path::new(path))?;
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {path}: {}", io_words(&e)))?;
    TransferFunction::from_json(&text).map_err(|e| format!("{path}: {e}"))
}

/// The colour strip under the plot: each value's colour from `edited`, in 2-point columns.
fn draw_strip(painter: &egui::Painter, full: Rect, plot: &Plot, edited: &TransferFunction) {
    let strip_top = plot.rect.bottom();
    let columns = (full.width() / 2.0).ceil() as usize;
    for c in 0..columns {
        let x0 = full.left() + c as f32 * 2.0;
        let v = plot.lo + (c as f32 + 0.5) / columns as f32 * (plot.hi - plot.lo);
        let rgba = edited.evaluate(v);
        painter.rect_filled(
            Rect::from_min_max(pos2(x0, strip_top), pos2(x0 + 2.0, full.bottom())),
            0.0,
            super::color32(bevy::color::Color::srgb(rgba.x, rgba.y, rgba.z)),
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn save_and_load_round_trip_and_errors_are_reported() {
        let dir = std::env::temp_dir().join(format!("voxcast-tf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.json");
        let tf = TransferFunction::ramp(0.0, 10.0, 0.3).unwrap();
        save(&tf, path.to_str().unwrap()).unwrap();
        assert_eq!(load(path.to_str().unwrap()).unwrap(), tf);
        std::fs::write(&path, "{\"points\": []}").unwrap();
        assert!(
            load(path.to_str().unwrap())
                .unwrap_err()
                .contains("at least one")
        );
        assert!(load(dir.join("none.json").to_str().unwrap()).is_err());
        // A blank field asks for a name, as Save does, not "cannot read : …".
        assert_eq!(load("  ").unwrap_err(), "give a file name");
        assert_eq!(save(&tf, "").unwrap_err(), "give a file name");
        assert!(save(&tf, dir.join("no/such/dir.json").to_str().unwrap()).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The selected point's value and opacity show four significant digits (the numbers
    /// rule), not egui's own choice (a dragged point showed "value 33.358 opacity 0.78571").
    #[test]
    fn the_selected_point_shows_its_numbers_rounded() {
        use voxcast_core::transfer::ControlPoint;
        let points = vec![
            ControlPoint::new(0.0, [1.0; 3], 0.0),
            ControlPoint::new(33.3578, [1.0; 3], 0.785_714),
        ];
        let mut tf = TransferFunction::new("t", points).unwrap();
        let before = tf.clone();
        let mut editor = TransferEditor {
            selected: Some(1),
            ..Default::default()
        };
        let text =
            super::super::drawn_text(|ui| _ = editor.selected_point(ui, &mut tf, 0.0, 100.0));
        let lines: Vec<&str> = text.lines().map(str::trim).collect();
        let after = |prefix: &str| {
            lines
                .iter()
                .position(|l| *l == prefix)
                .map(|i| lines[i + 1])
        };
        assert_eq!(after("value"), Some("33.36"), "{text}");
        assert_eq!(after("opacity"), Some("0.7857"), "{text}");
        assert_eq!(tf, before, "drawing leaves the point");
    }

    #[test]
    fn the_plot_maps_both_ways_and_grabs_nearby_points() {
        let plot = Plot {
            rect: Rect::from_min_size(pos2(10.0, 20.0), vec2(200.0, 100.0)),
            lo: 0.0,
            hi: 100.0,
        };
        let p = plot.at(25.0, 0.5);
        assert_eq!(p, pos2(60.0, 70.0));
        assert_eq!(plot.value_alpha(p), (25.0, 0.5));
        assert_eq!(plot.value_alpha(pos2(-50.0, 500.0)), (0.0, 0.0));
        let tf = TransferFunction::ramp(0.0, 100.0, 1.0).unwrap();
        assert_eq!(
            plot.grab(&tf, plot.at(100.0, 1.0) + vec2(-5.0, 3.0)),
            Some(1)
        );
        assert_eq!(plot.grab(&tf, plot.at(50.0, 0.5)), None);
    }
}
