//! The ray inspector: the virtual camera's rays painted over the preview (before, inside and
//! after the volume, growing with the animation), the "Rays" window (while the virtual camera
//! is shown) with its image as a pixel grid (hover highlights a ray, click selects it), and the breakdown window that follows the
//! selected ray's calculation sample by sample — with the 8 corners of an opened sample drawn
//! in the scene — and exports it as JSON or CSV, the same text as `voxcast trace`.

use crate::sandbox::inspect::{InspectSettings, Inspection, RayAnimation, RaySelection, ray_pixel};
use crate::sandbox::overlay::Projector;
use crate::sandbox::state::{MainCamera, RenderState, View, VolumeState};
use crate::sandbox::virtual_camera::VirtualCamera;
use bevy::prelude::*;
use bevy_egui::EguiContexts;
use bevy_egui::egui::{self, Color32, Pos2, Sense, Stroke, pos2, vec2};
use voxcast_core::breakdown::{self, SampleRecord};
use voxcast_core::level::Control;
use voxcast_core::numbers::{sig, sig3};
use voxcast_core::trace::{RayTrace, Scene, trace_ray};
use voxcast_core::tunables as t;

/// The breakdown window's state: the selected ray's trace and the opened sample.
#[derive(Resource)]
pub(crate) struct BreakdownState {
    /// The pixel and the inspection generation the trace belongs to.
    key: Option<(UVec2, u64)>,
    pub trace: Option<RayTrace>,
    pub opened: Option<usize>,
    path: String,
    message: Option<Result<String, String>>,
}

impl Default for BreakdownState {
    fn default() -> Self {
        Self {
            key: None,
            trace: None,
            opened: None,
            path: "ray".into(),
            message: None,
        }
    }
}

/// The trace of the virtual camera's pixel `p`: the core's `trace_ray` of that pixel's ray.
pub fn pixel_trace(
    volume: &VolumeState,
    render: &RenderState,
    vc: &VirtualCamera,
    p: UVec2,
) -> Option<RayTrace> {
    let (w, h) = (vc.width.max(1), vc.height.max(1));
    let scene = Scene::new(
        &volume.volume,
        &render.transfer,
        &render.settings,
        vc.view.forward(),
    )
    .ok()?;
    Some(trace_ray(
        &scene,
        &vc.view.pixel_ray(p.x, p.y, w, h),
        [p.x, p.y],
    ))
}

/// Keeps the breakdown's trace in step with the selection and the settings.
pub(super) fn follow_selection(
    selection: Res<RaySelection>,
    inspection: Res<Inspection>,
    volume: Res<VolumeState>,
    render: Res<RenderState>,
    cameras: Query<&VirtualCamera>,
    mut state: ResMut<BreakdownState>,
) {
    let key = selection.selected.map(|p| (p, inspection.generation));
    if key == state.key {
        return;
    }
    state.key = key;
    state.message = None;
    let previous_len = state.trace.as_ref().map(|t| t.samples.len());
    state.trace = match (selection.selected, cameras.single()) {
        (Some(p), Ok(vc)) => {
            let index = selection.selected_index(inspection.size);
            inspection
                .traces
                .as_ref()
                .and_then(|ts| index.and_then(|i| ts.get(i)))
                .cloned()
                .or_else(|| pixel_trace(&volume, &render, vc, p))
        }
        _ => None,
    };
    if state.trace.as_ref().map(|t| t.samples.len()) != previous_len {
        state.opened = None;
    }
}

/// Display colour of linear-as-stored values (the core's values are display values).
fn color32(c: [f32; 3]) -> Color32 {
    let [r, g, b] = voxcast_core::image_out::to_u8(Vec3::from_array(c));
    Color32::from_rgb(r, g, b)
}

/// Paints the rays (and an opened sample's cell) over the preview, beneath every window.
#[allow(clippy::too_many_arguments)]
pub(super) fn ray_overlay(
    mut contexts: EguiContexts,
    inspection: Res<Inspection>,
    mut selection: ResMut<RaySelection>,
    settings: Res<InspectSettings>,
    animation: Res<RayAnimation>,
    views: Query<&View, With<MainCamera>>,
    cameras: Query<&VirtualCamera>,
    breakdown: Res<BreakdownState>,
    (volume, viewport): (
        Res<VolumeState>,
        Option<Res<crate::sandbox::preview::Viewport>>,
    ),
) -> Result {
    let (Ok(view), Ok(vc)) = (views.single(), cameras.single()) else {
        return Ok(());
    };
    if !settings.shown || !vc.shown {
        return Ok(());
    }
    let ctx = contexts.ctx_mut()?;
    let rect = viewport.map_or(ctx.viewport_rect(), |v| v.rect);
    let projector = Projector { view: view.0, rect };
    let painter = ctx
        .layer_painter(egui::LayerId::background())
        .with_clip_rect(rect);
    let (lo, hi) = volume.volume.bounds();
    let reach = (vc.view.target - vc.view.eye).length() + (hi - lo).length();
    let selected = selection.selected_index(inspection.size);
    let hovered = selection.hovered_index(inspection.size);
    let grown = animation.distance;
    // A click on the scene (not on a window) picks the ray drawn nearest to it.
    let (clicked, pointer) = ctx.input(|i| (i.pointer.primary_clicked(), i.pointer.interact_pos()));
    let pick_at = pointer.filter(|_| clicked && !ctx.is_pointer_over_egui());
    let mut nearest: Option<(f32, usize)> = None;
    for (i, path) in inspection.paths.iter().enumerate() {
        let dim = selected.is_some_and(|s| s != i);
        let (width, inside_color) = if selected == Some(i) {
            (2.5, Color32::YELLOW)
        } else if hovered == Some(i) {
            (2.0, Color32::from_rgb(80, 220, 255))
        } else {
            (1.0, Color32::WHITE)
        };
        let alpha = if dim { 35 } else { 255 };
        let fade = |c: Color32| Color32::from_rgba_unmultiplied(c.r(), c.g(), c.b(), alpha);
        let outside = fade(Color32::from_gray(130));
        let (t_in, t_out) = path.interval.unwrap_or((reach, reach));
        for (a, b, color, w) in [
            (0.0, t_in, outside, 1.0),
            (t_in, t_out, fade(inside_color), width),
            (t_out, reach, outside, 1.0),
        ] {
            let b = b.min(grown);
            if b <= a {
                continue;
            }
            if let Some(seg) =
                projector.segment(path.origin + path.dir * a, path.origin + path.dir * b)
            {
                painter.line_segment(seg, Stroke::new(w, color));
                if let Some(p) = pick_at {
                    let d = distance_to_segment(p, seg);
                    if d <= PICK_RADIUS && nearest.is_none_or(|(best, _)| d < best) {
                        nearest = Some((d, i));
                    }
                }
            }
        }
    }
    if let Some((_, i)) = nearest {
        let p = ray_pixel(i, inspection.size);
        selection.selected = if selection.selected == Some(p) {
            None
        } else {
            Some(p)
        };
    }
    // The opened sample's cell: its 12 edges and its 8 corners, sized by their weights.
    let opened = breakdown
        .trace
        .as_ref()
        .zip(breakdown.opened)
        .and_then(|(t, k)| t.samples.get(k));
    if let Some(s) = opened {
        draw_cell(&painter, &projector, s, volume.volume.spacing());
    }
    Ok(())
}

/// How near (points) a click must fall to a ray's line to pick it.
const PICK_RADIUS: f32 = 6.0;

/// Distance from `p` to the segment `[a, b]`, in points.
fn distance_to_segment(p: Pos2, [a, b]: [Pos2; 2]) -> f32 {
    let ab = b - a;
    let t = ((p - a).dot(ab) / ab.length_sq().max(f32::MIN_POSITIVE)).clamp(0.0, 1.0);
    (a + ab * t - p).length()
}

fn draw_cell(painter: &egui::Painter, projector: &Projector, s: &SampleRecord, spacing: Vec3) {
    let r = &s.reconstruction;
    let world = |c: [u32; 3]| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32) * spacing;
    let orange = Color32::from_rgb(255, 160, 40);
    for (a, b) in [
        (0, 1),
        (2, 3),
        (4, 5),
        (6, 7),
        (0, 2),
        (1, 3),
        (4, 6),
        (5, 7),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ] {
        if let Some(seg) = projector.segment(world(r.corners[a]), world(r.corners[b])) {
            painter.line_segment(seg, Stroke::new(1.5, orange));
        }
    }
    for i in 0..8 {
        if let Some(p) = projector.at(world(r.corners[i])) {
            painter.circle_filled(p, 2.0 + 8.0 * r.weights[i], orange);
            painter.text(
                p + vec2(6.0, -6.0),
                egui::Align2::LEFT_BOTTOM,
                format!("{} ×{:.3}", r.values[i], r.weights[i]),
                egui::FontId::proportional(11.0),
                Color32::WHITE,
            );
        }
    }
    if let Some(p) = projector.at(Vec3::from_array(s.p_world)) {
        painter.circle_stroke(p, 5.0, Stroke::new(2.0, Color32::YELLOW));
    }
}

/// The "Rays" window: animation and budget controls, and the image as a pixel grid.
pub(super) fn rays_window(
    mut contexts: EguiContexts,
    inspection: Res<Inspection>,
    mut selection: ResMut<RaySelection>,
    mut settings: ResMut<InspectSettings>,
    (mut animation, lessons): (ResMut<RayAnimation>, Res<super::levels::Lessons>),
    cameras: Query<&VirtualCamera>,
    mut dock: ResMut<super::Dock>,
) -> Result {
    // No virtual camera shown (a level without one, or turned off in the panel): no window.
    if !cameras.single().is_ok_and(|c| c.shown) {
        return Ok(());
    }
    let spot = lessons.spot;
    let ctx = contexts.ctx_mut()?;
    let mut edited = settings.clone();
    let mut new_selection = *selection;
    let ctx = ctx.clone();
    dock.show(&ctx, "rays", |dock_ui| {
        egui::Panel::right("rays")
            .resizable(true)
            .default_size(240.0)
            .show(dock_ui, |ui| {
                ui.heading("Rays");
                egui::ScrollArea::vertical().show(ui, |ui| {
                    ui.checkbox(&mut edited.shown, "Show rays and samples");
                    ui.add(
                        egui::Slider::new(&mut edited.speed, t::RAY_SPEED.min..=t::RAY_SPEED.max)
                            .logarithmic(true)
                            .text(t::RAY_SPEED.label),
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
                    let mut budget = edited.budget as f32;
                    if ui
                        .add(
                            egui::Slider::new(
                                &mut budget,
                                t::SAMPLE_BUDGET.min..=t::SAMPLE_BUDGET.max,
                            )
                            .logarithmic(true)
                            .text(t::SAMPLE_BUDGET.label),
                        )
                        .on_hover_text(t::SAMPLE_BUDGET.doc)
                        .changed()
                    {
                        edited.budget = budget as usize;
                    }
                    let size = inspection.size;
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
                        pixel_grid(ui, &inspection, &mut new_selection)
                    });
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

fn pixel_grid(ui: &mut egui::Ui, inspection: &Inspection, selection: &mut RaySelection) {
    let Some(image) = &inspection.image else {
        return;
    };
    let (w, h) = (image.width.max(1), image.height.max(1));
    // As wide as the panel allows, up to 256 points.
    let cell = (ui.available_width().clamp(64.0, 256.0) / w.max(h) as f32).max(3.0);
    let (response, painter) =
        ui.allocate_painter(vec2(cell * w as f32, cell * h as f32), Sense::click());
    let origin = response.rect.min;
    let at = |x: u32, y: u32| {
        egui::Rect::from_min_size(origin + vec2(x as f32, y as f32) * cell, vec2(cell, cell))
    };
    for y in 0..h {
        for x in 0..w {
            let c = image.get(x, y).to_array();
            painter.rect_filled(at(x, y), 0.0, color32(c));
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
        selection.selected = if selection.selected == Some(p) {
            None
        } else {
            Some(p)
        };
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

/// The breakdown of the selected ray.
pub(super) fn breakdown_window(
    mut contexts: EguiContexts,
    mut state: ResMut<BreakdownState>,
    mut selection: ResMut<RaySelection>,
    lessons: Res<super::levels::Lessons>,
    mut dock: ResMut<super::Dock>,
) -> Result {
    let Some(pixel) = selection.selected else {
        return Ok(());
    };
    let spot = lessons.spot;
    let ctx = contexts.ctx_mut()?;
    let mut open = true;
    let state = &mut *state;
    // Docked below the scene, across the window; it scrolls, with its bars always shown.
    let ctx = ctx.clone();
    let height = ctx.viewport_rect().height() * 0.4;
    dock.show(&ctx, "breakdown", |dock_ui| {
        egui::Panel::bottom("breakdown")
            .resizable(true)
            .default_size(height)
            .min_size(120.0)
            .show(dock_ui, |ui| {
                ui.horizontal(|ui| {
                    ui.heading(format!("Ray through pixel ({}, {})", pixel.x, pixel.y));
                    if ui
                        .button("Close")
                        .on_hover_text("Close the breakdown (the ray is deselected)")
                        .clicked()
                    {
                        open = false;
                    }
                });
                egui::ScrollArea::vertical()
                    .scroll_bar_visibility(egui::scroll_area::ScrollBarVisibility::AlwaysVisible)
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        let Some(trace) = &state.trace else {
                            ui.label("This ray cannot be traced with the current settings.");
                            return;
                        };
                        summary(ui, trace);
                        ui.separator();
                        formula(ui, trace, state.opened);
                        ui.separator();
                        let opened = super::marked(ui, spot, Control::Breakdown, |ui| {
                            sample_table(ui, trace, state.opened)
                        });
                        if opened != state.opened {
                            state.opened = opened;
                        }
                        if let Some(s) = state.opened.and_then(|k| trace.samples.get(k)) {
                            ui.separator();
                            sample_detail(ui, s);
                        }
                        ui.separator();
                        export(ui, trace, &mut state.path, &mut state.message);
                    });
            });
    });
    if !open {
        selection.selected = None;
    }
    Ok(())
}

/// A 3-vector rounded for reading (`voxcast_core::numbers`).
fn v3(v: [f32; 3]) -> String {
    sig3(v)
}

/// Every digit of a 3-vector, for a tooltip and the exports.
fn v3_full(v: [f32; 3]) -> String {
    format!("({}, {}, {})", v[0], v[1], v[2])
}

/// A number rounded for reading, with its every digit in the tooltip.
fn num(ui: &mut egui::Ui, x: f32) {
    ui.label(sig(x)).on_hover_text(x.to_string());
}

/// A 3-vector rounded for reading, with its every digit in the tooltip.
fn vec(ui: &mut egui::Ui, v: [f32; 3]) {
    ui.label(v3(v)).on_hover_text(v3_full(v));
}

fn summary(ui: &mut egui::Ui, t: &RayTrace) {
    ui.label(format!(
        "origin {}  direction {}  method {}",
        v3(t.origin),
        v3(t.dir),
        t.method.name()
    ));
    match (t.interval, &t.plan) {
        (Some([a, b]), Some(p)) => ui.label(format!(
            "enters the box at t = {}, leaves at t = {}; {} samples {} apart (first at t = {})",
            sig(a),
            sig(b),
            p.count,
            sig(p.dt),
            sig(p.t_enter + p.jitter * p.dt)
        )),
        _ => ui.label("misses the volume's box"),
    };
    ui.horizontal(|ui| {
        ui.label(format!(
            "stopped: {} · C = {} · O = {} · pixel",
            t.stop.words(),
            v3(t.color),
            sig(t.opacity)
        ));
        let (rect, _) = ui.allocate_exact_size(vec2(14.0, 14.0), Sense::hover());
        ui.painter().rect_filled(rect, 2.0, color32(t.pixel));
        ui.label(v3(t.pixel));
    });
}

/// The method's formula with the opened (else the last) sample's numbers put in, in the order
/// in use (`voxcast_core::explain`, the same text `voxcast trace` prints).
fn formula(ui: &mut egui::Ui, t: &RayTrace, opened: Option<usize>) {
    let text = voxcast_core::explain::formula(t, opened);
    ui.label(egui::RichText::new(text).monospace());
}

/// One row per sample; clicking a row opens it. Returns the opened sample.
fn sample_table(ui: &mut egui::Ui, t: &RayTrace, opened: Option<usize>) -> Option<usize> {
    let mut opened = opened;
    egui::ScrollArea::both()
        .max_height(220.0)
        .scroll_bar_visibility(egui::scroll_area::ScrollBarVisibility::AlwaysVisible)
        .show(ui, |ui| {
            egui::Grid::new("samples").striped(true).show(ui, |ui| {
                for h in [
                    "k",
                    "t",
                    "position (world)",
                    "value",
                    "TF rgba",
                    "α",
                    "α corrected",
                    "C after",
                    "O after",
                ] {
                    ui.strong(h);
                }
                ui.end_row();
                for (i, s) in t.samples.iter().enumerate() {
                    let chosen = opened == Some(i);
                    if ui.selectable_label(chosen, s.index.to_string()).clicked() {
                        opened = if chosen { None } else { Some(i) };
                    }
                    num(ui, s.t);
                    vec(ui, s.p_world);
                    num(ui, s.reconstruction.value);
                    ui.horizontal(|ui| {
                        let (rect, _) = ui.allocate_exact_size(vec2(10.0, 10.0), Sense::hover());
                        ui.painter().rect_filled(
                            rect,
                            1.0,
                            color32([s.tf_rgba[0], s.tf_rgba[1], s.tf_rgba[2]]),
                        );
                        let [r, g, b, a] = s.tf_rgba;
                        ui.label(format!("{} {} {} {}", sig(r), sig(g), sig(b), sig(a)))
                            .on_hover_text(format!("{r} {g} {b} {a}"));
                    });
                    num(ui, s.alpha);
                    num(ui, s.alpha_corrected);
                    let c = s.composite_after;
                    vec(ui, [c[0], c[1], c[2]]);
                    num(ui, c[3]);
                    ui.end_row();
                }
                ui.strong("end");
                ui.label(t.stop.words());
                ui.end_row();
            });
        });
    opened
}

/// The opened sample: its 8 corners, weights and the interpolation, and its shading.
fn sample_detail(ui: &mut egui::Ui, s: &SampleRecord) {
    let r = &s.reconstruction;
    ui.label(format!(
        "sample {} at voxel {}; position in the cell (fx, fy, fz) = {}",
        s.index,
        v3(s.p_voxel),
        v3(r.frac)
    ));
    egui::Grid::new("corners").striped(true).show(ui, |ui| {
        for h in [
            "corner",
            "lattice point",
            "value",
            "weight",
            "weight × value",
        ] {
            ui.strong(h);
        }
        ui.end_row();
        for i in 0..8 {
            ui.label(format!("{i}"));
            let c = r.corners[i];
            ui.label(format!("({}, {}, {})", c[0], c[1], c[2]));
            num(ui, r.values[i]);
            num(ui, r.weights[i]);
            num(ui, r.weights[i] * r.values[i]);
            ui.end_row();
        }
    });
    ui.label(format!(
        "interpolated value Σ weight × value = {} (the renderer's value: {})",
        sig((0..8).map(|i| r.weights[i] * r.values[i]).sum::<f32>()),
        sig(r.value)
    ));
    if let Some(g) = s.gradient {
        ui.label(format!("gradient (central differences) {}", v3(g)));
    }
    if let Some(sh) = &s.shading {
        ui.label(format!(
            "shading: N·L = {}, ambient {}, diffuse {}, specular {}, so the colour is {}",
            sig(sh.n_dot_l),
            v3(sh.ambient),
            v3(sh.diffuse),
            v3(sh.specular),
            v3(s.color)
        ));
    }
}

fn export(
    ui: &mut egui::Ui,
    t: &RayTrace,
    path: &mut String,
    message: &mut Option<Result<String, String>>,
) {
    ui.horizontal(|ui| {
        ui.text_edit_singleline(path)
            .on_hover_text("File name without extension: .json and .csv are added");
        for (label, ext) in [("Save JSON", "json"), ("Save CSV", "csv")] {
            if ui
                .button(label)
                .on_hover_text("The same text as `voxcast trace --json` / `--csv` for this ray")
                .clicked()
            {
                *message = Some(save(t, path, ext));
            }
        }
    });
    match message {
        Some(Ok(m)) => {
            ui.label(m.as_str());
        }
        Some(Err(e)) => {
            ui.colored_label(Color32::LIGHT_RED, e.as_str());
        }
        None => {}
    }
}

/// Writes the breakdown (through a temporary file and a rename).
fn save(t: &RayTrace, path: &str, ext: &str) -> Result<String, String> {
    let base = std::path::Path::new(path.trim());
    if base.file_name().is_none() {
        return Err("give a file name".into());
    }
    let file = base.with_extension(ext);
    let text = if ext == "json" {
        breakdown::to_json(t)
    } else {
        breakdown::to_csv(t)
    };
    let tmp = file.with_extension(format!("{ext}.tmp"));
    std::fs::write(&tmp, text)
        .and_then(|_| std::fs::rename(&tmp, &file))
        .map_err(|e| {
            format!(
                "cannot save {}: {}",
                file.display(),
                voxcast_core::error::io_words(&e)
            )
        })?;
    Ok(format!("saved {}", file.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox::inspect::compute;

    #[test]
    fn distance_to_a_segment() {
        let seg = [pos2(0.0, 0.0), pos2(10.0, 0.0)];
        assert_eq!(distance_to_segment(pos2(5.0, 3.0), seg), 3.0);
        assert_eq!(distance_to_segment(pos2(13.0, 4.0), seg), 5.0);
        assert_eq!(
            distance_to_segment(pos2(2.0, 0.0), [pos2(2.0, 0.0), pos2(2.0, 0.0)]),
            0.0
        );
    }

    /// The pixel grid driven by the pointer events egui receives from a user: moving over a
    /// pixel hovers its ray, a click selects it, a second click lets it go.
    #[test]
    fn pointer_events_on_the_pixel_grid_hover_and_select_rays() {
        let volume = VolumeState {
            volume: std::sync::Arc::new(
                voxcast_core::builtin::load_builtin("bucky").unwrap().volume,
            ),
            source: "builtin:bucky".into(),
            preset: None,
        };
        let render = RenderState {
            transfer: voxcast_core::transfer::TransferFunction::ramp(0.0, 255.0, 0.5).unwrap(),
            settings: voxcast_core::settings::RenderSettings::default(),
            depth_termination: true,
        };
        let mut vc = VirtualCamera::framing(&volume, None).unwrap();
        (vc.width, vc.height) = (8, 8);
        let mut inspection = Inspection::default();
        compute(&volume, &render, &vc, 1_000_000, &mut inspection);
        let ctx = egui::Context::default();
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

    #[test]
    fn the_breakdown_is_the_cores_trace_and_exports_as_the_cli_does() {
        let volume = VolumeState {
            volume: std::sync::Arc::new(
                voxcast_core::builtin::load_builtin("bucky").unwrap().volume,
            ),
            source: "builtin:bucky".into(),
            preset: None,
        };
        let p = voxcast_core::preset::for_volume(volume.volume.name()).unwrap();
        let render = RenderState {
            transfer: p.transfer.clone(),
            settings: p
                .settings_over(&voxcast_core::settings::RenderSettings::default())
                .unwrap(),
            depth_termination: true,
        };
        let mut vc = VirtualCamera::framing(&volume, None).unwrap();
        (vc.width, vc.height) = (8, 8);
        let mut inspection = Inspection::default();
        compute(&volume, &render, &vc, 1_000_000, &mut inspection);
        let pixel = UVec2::new(4, 3);
        let shown = pixel_trace(&volume, &render, &vc, pixel).unwrap();
        assert_eq!(&shown, &inspection.traces.as_ref().unwrap()[3 * 8 + 4]);
        let dir = std::env::temp_dir().join(format!("voxcast-ray-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let base = dir.join("ray");
        for ext in ["json", "csv"] {
            save(&shown, base.to_str().unwrap(), ext).unwrap();
            let text = std::fs::read_to_string(base.with_extension(ext)).unwrap();
            let want = if ext == "json" {
                breakdown::to_json(&shown)
            } else {
                breakdown::to_csv(&shown)
            };
            assert_eq!(text, want);
        }
        assert!(save(&shown, dir.join("no/dir/ray").to_str().unwrap(), "json").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
