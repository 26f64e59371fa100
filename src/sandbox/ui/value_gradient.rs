//! The value-and-gradient classification's editor: the volume's joint histogram of value ×
//! gradient magnitude (the core's `histogram2d`, log scale), with the rectangles drawn over it.
//! Drag on an empty part of the plot to draw a rectangle, drag a rectangle to move it, click one
//! to select it; the selected one's bounds and opacity are edited below the plot.

use bevy_egui::egui::{self, Color32, Pos2, Rect, Sense, Stroke, pos2, vec2};
use voxcast_core::classify::{MAX_REGIONS, Region};
use voxcast_core::histogram2d::JointHistogram;

/// Bins along value and along gradient magnitude.
const BINS: [usize; 2] = [128, 64];
/// The most lattice points the histogram reads (a stride is taken on larger volumes).
const MAX_POINTS: usize = 1 << 20;
const PLOT_HEIGHT: f32 = 150.0;
/// How near an edge of the plot (pixels) a pointer snaps onto it.
const SNAP: f32 = 6.0;
/// The opacity of a newly drawn rectangle.
const NEW_OPACITY: f32 = 0.6;

/// What the pointer is doing on the plot.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Drag {
    /// Drawing a new rectangle from this corner (value, gradient).
    Create([f32; 2]),
    /// Moving rectangle `i`, last seen at this (value, gradient).
    Move(usize, [f32; 2]),
}

/// The editor's state: the histogram of the volume it was made for, and the selection.
#[derive(Default)]
pub(super) struct RegionEditor {
    histogram: Option<(String, JointHistogram, egui::TextureHandle)>,
    selected: Option<usize>,
    drag: Option<Drag>,
}

/// The plot's axes: value across, gradient magnitude up.
struct Axes {
    rect: Rect,
    value: [f32; 2],
    gradient: [f32; 2],
}

impl Axes {
    fn screen_at(&self, [f, g]: [f32; 2]) -> Pos2 {
        let x = (f - self.value[0]) / (self.value[1] - self.value[0]);
        let y = (g - self.gradient[0]) / (self.gradient[1] - self.gradient[0]);
        pos2(
            self.rect.left() + x * self.rect.width(),
            self.rect.bottom() - y * self.rect.height(),
        )
    }

    /// The plot's (value, gradient) under `p`; within [`SNAP`] pixels of an edge, the edge's
    /// (so a rectangle drawn from near the bottom starts at gradient 0).
    fn plot_at(&self, p: Pos2) -> [f32; 2] {
        let snap = |t: f32, size: f32| {
            let edge = SNAP / size.max(1.0);
            if t < edge {
                0.0
            } else if t > 1.0 - edge {
                1.0
            } else {
                t
            }
        };
        let x = snap(
            (p.x - self.rect.left()) / self.rect.width(),
            self.rect.width(),
        );
        let y = snap(
            (self.rect.bottom() - p.y) / self.rect.height(),
            self.rect.height(),
        );
        [
            self.value[0] + x * (self.value[1] - self.value[0]),
            self.gradient[0] + y * (self.gradient[1] - self.gradient[0]),
        ]
    }

    fn screen_rect(&self, r: &Region) -> Rect {
        Rect::from_two_pos(
            self.screen_at([r.value[0], r.gradient[0]]),
            self.screen_at([r.value[1], r.gradient[1]]),
        )
    }
}

/// The rectangle spanned by two corners (value, gradient), in order.
fn spanned(a: [f32; 2], b: [f32; 2], opacity: f32) -> Region {
    Region {
        value: [a[0].min(b[0]), a[0].max(b[0])],
        gradient: [a[1].min(b[1]).max(0.0), a[1].max(b[1]).max(0.0)],
        opacity,
    }
}

/// The topmost (last drawn) rectangle holding `(f, g)`.
fn region_at(regions: &[Region], [f, g]: [f32; 2]) -> Option<usize> {
    regions.iter().rposition(|r| r.contains(f, g))
}

/// `r` moved by `(df, dg)`, its gradients kept at or above zero.
fn moved(r: &Region, df: f32, dg: f32) -> Region {
    let dg = dg.max(-r.gradient[0]);
    Region {
        value: [r.value[0] + df, r.value[1] + df],
        gradient: [r.gradient[0] + dg, r.gradient[1] + dg],
        opacity: r.opacity,
    }
}

/// What the plot's axes and shade mean for histogram `h`.
fn histogram_words(h: &JointHistogram) -> String {
    format!(
        "Across: value {} … {}; up: gradient magnitude 0 … {} per world unit; shade: how many \
         lattice points (log){}.",
        voxcast_core::numbers::sig(h.value[0]),
        voxcast_core::numbers::sig(h.value[1]),
        voxcast_core::numbers::sig(h.gradient[1]),
        if h.stride > 1 {
            format!(", every {}th along each axis", h.stride)
        } else {
            String::new()
        }
    )
}

impl RegionEditor {
    /// Draws the editor for `regions` over the joint histogram of `volume` (from `source`).
    pub(super) fn show(
        &mut self,
        ui: &mut egui::Ui,
        regions: &mut Vec<Region>,
        volume: &voxcast_core::Volume,
        source: &str,
    ) {
        if self.histogram.as_ref().is_none_or(|(s, ..)| s != source) {
            let h = JointHistogram::of(volume, BINS, MAX_POINTS);
            let texture = ui.ctx().load_texture(
                "value-gradient histogram",
                image_of(&h),
                egui::TextureOptions::NEAREST,
            );
            self.histogram = Some((source.to_string(), h, texture));
            self.selected = None;
        }
        let Some((_, h, texture)) = &self.histogram else {
            return;
        };
        let (texture, legend) = (texture.id(), histogram_words(h));
        let width = ui.available_width().max(120.0);
        let (response, painter) =
            ui.allocate_painter(vec2(width, PLOT_HEIGHT), Sense::click_and_drag());
        let axes = Axes {
            rect: response.rect,
            value: h.value,
            gradient: h.gradient,
        };
        painter.image(
            texture,
            axes.rect,
            Rect::from_min_max(pos2(0.0, 0.0), pos2(1.0, 1.0)),
            Color32::WHITE,
        );
        let pointer = self.follow_pointer(ui, &response, &axes, regions);
        self.draw_regions(&painter, &axes, regions, pointer);
        ui.label(legend);
        ui.label(format!(
            "Drag on the plot to draw a rectangle (at most {MAX_REGIONS}), drag one to move it. \
             A sample inside a rectangle takes its opacity, elsewhere none; the colour stays the \
             transfer function's."
        ));
        self.selected_controls(ui, regions);
    }

    /// The pointer's edits: a drag on a rectangle moves it, a drag elsewhere draws a new one
    /// (added when the button comes up), a click selects the rectangle under it. Returns the
    /// pointer's place on the plot.
    fn follow_pointer(
        &mut self,
        ui: &egui::Ui,
        response: &egui::Response,
        axes: &Axes,
        regions: &mut Vec<Region>,
    ) -> Option<[f32; 2]> {
        let pointer = response.interact_pointer_pos().map(|p| axes.plot_at(p));
        // A drag starts where the button went down, not where it was seen to move.
        let origin = ui
            .input(|i| i.pointer.press_origin())
            .map(|p| axes.plot_at(p))
            .or(pointer);
        if response.drag_started()
            && let Some(at) = origin
        {
            self.drag = Some(match region_at(regions, at) {
                Some(i) => {
                    self.selected = Some(i);
                    Drag::Move(i, at)
                }
                None => Drag::Create(at),
            });
        }
        if let (Some(Drag::Move(i, last)), Some(at)) = (self.drag, pointer)
            && let Some(r) = regions.get_mut(i)
        {
            *r = moved(r, at[0] - last[0], at[1] - last[1]);
            self.drag = Some(Drag::Move(i, at));
        }
        if response.drag_stopped() {
            if let (Some(Drag::Create(a)), Some(b)) = (self.drag, pointer)
                && regions.len() < MAX_REGIONS
                && a != b
            {
                regions.push(spanned(a, b, NEW_OPACITY));
                self.selected = Some(regions.len() - 1);
            }
            self.drag = None;
        }
        if response.clicked() {
            self.selected = pointer.and_then(|at| region_at(regions, at));
        }
        pointer
    }

    /// The rectangles, numbered, shaded by their opacity, the selected one in yellow; and the
    /// one being drawn, outlined.
    fn draw_regions(
        &self,
        painter: &egui::Painter,
        axes: &Axes,
        regions: &[Region],
        pointer: Option<[f32; 2]>,
    ) {
        for (i, r) in regions.iter().enumerate() {
            let selected = self.selected == Some(i);
            let fill = Color32::from_rgba_unmultiplied(255, 200, 60, (r.opacity * 90.0) as u8);
            let stroke = if selected {
                Stroke::new(2.0, Color32::YELLOW)
            } else {
                Stroke::new(1.0, Color32::WHITE)
            };
            let rect = axes.screen_rect(r);
            painter.rect_filled(rect, 0.0, fill);
            painter.rect_stroke(rect, 0.0, stroke, egui::StrokeKind::Inside);
            painter.text(
                rect.left_top() + vec2(3.0, 2.0),
                egui::Align2::LEFT_TOP,
                (i + 1).to_string(),
                egui::FontId::proportional(11.0),
                Color32::WHITE,
            );
        }
        if let (Some(Drag::Create(a)), Some(b)) = (self.drag, pointer) {
            let r = spanned(a, b, NEW_OPACITY);
            painter.rect_stroke(
                axes.screen_rect(&r),
                0.0,
                Stroke::new(1.0, Color32::YELLOW),
                egui::StrokeKind::Inside,
            );
        }
    }

    /// The selected rectangle's bounds, opacity and removal.
    fn selected_controls(&mut self, ui: &mut egui::Ui, regions: &mut Vec<Region>) {
        let Some(i) = self.selected.filter(|&i| i < regions.len()) else {
            self.selected = None;
            return;
        };
        let r = &mut regions[i];
        // Four significant digits, as the breakdown prints numbers.
        fn number(v: &mut f32) -> egui::DragValue<'_> {
            egui::DragValue::new(v)
                .speed(0.1)
                .custom_formatter(|x, _| voxcast_core::numbers::sig(x as f32))
        }
        ui.horizontal(|ui| {
            ui.strong(format!("Rectangle {}", i + 1));
            ui.label("values");
            ui.add(number(&mut r.value[0]));
            ui.add(number(&mut r.value[1]));
        });
        ui.horizontal(|ui| {
            ui.label("gradients");
            ui.add(number(&mut r.gradient[0]).range(0.0..=f32::MAX));
            ui.add(number(&mut r.gradient[1]).range(0.0..=f32::MAX));
        });
        // Kept in order, so the rectangle is never empty by a typo.
        *r = spanned(
            [r.value[0], r.gradient[0]],
            [r.value[1], r.gradient[1]],
            r.opacity,
        );
        let slider = egui::Slider::new(&mut r.opacity, 0.0..=1.0);
        super::labelled(
            ui,
            super::shown_with(slider, super::FINE_DECIMALS),
            "opacity",
        )
        .on_hover_text("The opacity of a sample inside this rectangle");
        if ui.button("Remove this rectangle").clicked() {
            regions.remove(i);
            self.selected = None;
        }
    }
}

/// The histogram as an image: one texel a bin, the highest gradient at the top, grey by count.
fn image_of(h: &JointHistogram) -> egui::ColorImage {
    let [w, ht] = h.bins;
    let shades = h.shades();
    let mut pixels = Vec::with_capacity(w * ht);
    for row in (0..ht).rev() {
        for col in 0..w {
            let s = shades[row * w + col];
            let level = if s > 0.0 {
                (40.0 + 215.0 * s) as u8
            } else {
                18
            };
            pixels.push(Color32::from_gray(level));
        }
    }
    egui::ColorImage::new([w, ht], pixels)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drag_spans_a_rectangle_in_order_above_zero_gradient() {
        let r = spanned([30.0, 5.0], [10.0, -1.0], 0.5);
        assert_eq!(r.value, [10.0, 30.0]);
        assert_eq!(r.gradient, [0.0, 5.0]);
        assert_eq!(r.opacity, 0.5);
    }

    #[test]
    fn the_topmost_rectangle_is_picked_and_moves_stay_above_zero() {
        let a = spanned([0.0, 0.0], [10.0, 10.0], 0.5);
        let b = spanned([5.0, 5.0], [20.0, 20.0], 0.5);
        assert_eq!(region_at(&[a, b], [7.0, 7.0]), Some(1));
        assert_eq!(region_at(&[a, b], [2.0, 2.0]), Some(0));
        assert_eq!(region_at(&[a, b], [30.0, 2.0]), None);
        let m = moved(&b, 1.0, -10.0);
        assert_eq!(m.value, [6.0, 21.0]);
        assert_eq!(
            m.gradient,
            [0.0, 15.0],
            "down only as far as zero, the height kept"
        );
    }

    /// The selected rectangle's opacity shows hundredths at every value, its ends included,
    /// as the panel's other linear sliders over a short range do (`widgets::FINE_DECIMALS`).
    #[test]
    fn the_opacity_shows_the_decimals_it_means() {
        for (opacity, shown, wrong) in [(0.0, "0.00", "0.000"), (0.6, "0.60", "0.600")] {
            let mut regions = vec![spanned([0.0, 0.0], [10.0, 5.0], opacity)];
            let mut editor = RegionEditor {
                selected: Some(0),
                ..Default::default()
            };
            let text = super::super::drawn_text(|ui| editor.selected_controls(ui, &mut regions));
            let numbers: Vec<&str> = text.lines().filter(|l| l.parse::<f32>().is_ok()).collect();
            assert!(numbers.contains(&shown), "{shown} not among {numbers:?}");
            assert!(!numbers.contains(&wrong), "{wrong} among {numbers:?}");
            assert_eq!(regions[0].opacity, opacity, "drawing leaves the value");
        }
    }

    #[test]
    fn screen_and_plot_positions_round_trip() {
        let axes = Axes {
            rect: Rect::from_min_max(pos2(10.0, 20.0), pos2(110.0, 70.0)),
            value: [-5.0, 15.0],
            gradient: [0.0, 4.0],
        };
        let p = axes.screen_at([10.0, 1.0]);
        assert_eq!(p, pos2(85.0, 57.5));
        let back = axes.plot_at(p);
        assert!((back[0] - 10.0).abs() < 1e-5 && (back[1] - 1.0).abs() < 1e-5);
        // Near the edges: their values exactly; beyond them, clamped.
        assert_eq!(axes.plot_at(pos2(14.0, 66.0)), [-5.0, 0.0]);
        assert_eq!(axes.plot_at(pos2(200.0, 0.0)), [15.0, 4.0]);
    }
}
