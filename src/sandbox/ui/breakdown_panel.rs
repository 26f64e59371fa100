//! The breakdown panel: the selected ray's calculation sample by sample — where it enters and
//! leaves, why it stopped, the method's formula with the numbers put in, a row per sample and
//! the 8 corners of an opened one — exported as JSON or CSV, the same text as `voxcast trace`.

use super::color32;
use crate::sandbox::inspect::breakdown::BreakdownState;
use crate::sandbox::inspect::rays::RaySelection;
use bevy::prelude::*;
use bevy_egui::EguiContexts;
use bevy_egui::egui::{self, Color32, Sense, vec2};
use voxcast_core::breakdown::{self, SampleRecord};
use voxcast_core::level::Control;
use voxcast_core::numbers::{sig, sig3};
use voxcast_core::trace::RayTrace;

/// The export's file name and the last save's outcome.
#[derive(Resource)]
pub(super) struct ExportState {
    path: String,
    message: Option<Result<String, String>>,
    /// The ray the message is about (a new ray clears it).
    key: Option<UVec2>,
}

impl Default for ExportState {
    fn default() -> Self {
        Self {
            path: "ray".into(),
            message: None,
            key: None,
        }
    }
}

/// The breakdown of the selected ray.
pub(super) fn breakdown_panel(
    mut contexts: EguiContexts,
    mut state: ResMut<BreakdownState>,
    mut export_state: ResMut<ExportState>,
    mut selection: ResMut<RaySelection>,
    mut place: super::Docked,
) -> Result {
    let Some(pixel) = selection.selected else {
        return Ok(());
    };
    if export_state.key != Some(pixel) {
        export_state.key = Some(pixel);
        export_state.message = None;
    }
    let spot = place.lessons.spot;
    // A prediction open in a level: its answer is not shown until the step is done.
    let hidden = place.lessons.hidden(*place.mode.get());
    let ctx = contexts.ctx_mut()?.clone();
    let mut open = true;
    // Docked below the scene, across the window; it scrolls, with its bars always shown.
    let most = place.layout.shares.breakdown_max;
    place.dock.show(&ctx, "breakdown", |dock_ui| {
        egui::Panel::bottom("breakdown")
            .resizable(true)
            .default_size(most)
            .max_size(most)
            .min_size(120.0f32.min(most))
            .show(dock_ui, |ui| {
                ui.horizontal(|ui| {
                    super::target(
                        ui.heading(format!("Ray through pixel ({}, {})", pixel.x, pixel.y)),
                        "breakdown",
                    );
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
                        contents(ui, &mut state, &mut export_state, hidden.as_ref(), spot)
                    });
            });
    });
    if !open {
        selection.selected = None;
    }
    Ok(())
}

/// The breakdown's body: the summary, the cells walked, the formula, the samples' table, the
/// sample opened and the export; what a prediction open in a level asks for is hidden.
fn contents(
    ui: &mut egui::Ui,
    state: &mut BreakdownState,
    export_state: &mut ExportState,
    hidden: Option<&crate::sandbox::levels::Hidden>,
    spot: super::Spot,
) {
    let Some(trace) = &state.trace else {
        ui.label("This ray cannot be traced with the current settings.");
        return;
    };
    summary(ui, trace, hidden);
    if let Some(walk) = &state.cells {
        let secret = hidden.is_some_and(|h| h.cells);
        if secret {
            state.show_cells = false;
        }
        cells_line(ui, walk, secret, &mut state.show_cells);
    }
    ui.separator();
    match hidden.filter(|h| h.hides_working()) {
        Some(_) => {
            ui.colored_label(Color32::YELLOW, HIDDEN_WORDS);
        }
        None => formula(ui, trace, state.opened),
    }
    ui.separator();
    let opened = super::marked(ui, spot, Control::Breakdown, |ui| {
        if hidden.is_some_and(|h| h.samples) {
            // Its rows would count the samples asked for.
            ui.colored_label(Color32::YELLOW, TABLE_HIDDEN_WORDS);
            return state.opened;
        }
        sample_table(ui, trace, state.opened, hidden)
    });
    if opened != state.opened {
        state.opened = opened;
    }
    if let Some(s) = state.opened.and_then(|k| trace.samples.get(k)) {
        ui.separator();
        let secret = hidden.is_some_and(|h| h.hides_sample(s.p_voxel));
        sample_detail(ui, s, secret);
    }
    ui.separator();
    if !hidden.is_some_and(|h| h.hides_working()) {
        export(ui, trace, &mut export_state.path, &mut export_state.message);
    }
}

/// What stands where a prediction's answer would: the level asks for it first.
const HIDDEN_WORDS: &str = "The numbers your prediction asks for are hidden until you check \
    it in the levels panel (the formula and the export come back then).";

/// What stands where the sample table would be while a level asks how many samples there are.
const TABLE_HIDDEN_WORDS: &str = "The sample table is hidden until you check your count in the \
    levels panel.";

/// What a hidden number shows.
const SECRET: &str = "?";

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

/// Where the ray enters and leaves in voxels, the cells it crosses (hidden while a level asks
/// for their number), and whether they are drawn in the scene.
fn cells_line(
    ui: &mut egui::Ui,
    walk: &voxcast_core::cells::CellsCrossed,
    secret: bool,
    show: &mut bool,
) {
    ui.horizontal_wrapped(|ui| {
        let count = if secret {
            SECRET.to_string()
        } else {
            walk.cells.len().to_string()
        };
        ui.label(format!(
            "In voxels: enters at {}, leaves at {}; crosses {count} cells",
            v3(walk.entry),
            v3(walk.exit)
        ))
        .on_hover_text(format!(
            "enters at {}, leaves at {}",
            v3_full(walk.entry),
            v3_full(walk.exit)
        ));
        ui.add_enabled(!secret, egui::Checkbox::new(show, "Draw them"))
            .on_hover_text(CELLS_TIP)
            .on_disabled_hover_text("Hidden until you check your count in the levels panel");
    });
}

/// What the cells are, as the checkbox's tooltip says.
const CELLS_TIP: &str = "A cell is the cube between 8 neighbouring voxels: every sample in it \
    reads the same 8. The ray walks them in order, from each into the one behind the face it \
    leaves by (Amanatides and Woo's walk, which the ray density also counts with); drawn \
    brightest where it enters.";

fn summary(ui: &mut egui::Ui, t: &RayTrace, hidden: Option<&crate::sandbox::levels::Hidden>) {
    let secret = hidden.is_some_and(|h| !h.points.is_empty() || h.composite);
    let count_secret = hidden.is_some_and(|h| h.samples);
    ui.label(format!(
        "origin {}  direction {}  method {}",
        v3(t.origin),
        v3(t.dir),
        t.method.title()
    ));
    match (t.interval, &t.plan) {
        (Some([a, b]), Some(p)) => ui.label(format!(
            "enters the volume at t = {}, leaves at t = {}; {} samples {} apart (first at t = {})",
            sig(a),
            sig(b),
            if count_secret {
                SECRET.to_string()
            } else {
                p.count.to_string()
            },
            sig(p.dt),
            sig(p.t_enter + p.jitter * p.dt)
        )),
        _ if t.stop == voxcast_core::trace::StopReason::CutAway => {
            ui.label("crosses the volume's box, but the cut leaves nothing of it to sample")
        }
        _ => ui.label("misses the volume's box"),
    };
    if let Some(cut) = t.cut_words() {
        ui.label(format!("Looking inside: {cut}."));
    }
    if secret {
        ui.label(format!(
            "stopped: {} · C = {SECRET} · O = {SECRET}",
            t.stop.words()
        ));
        return;
    }
    ui.horizontal(|ui| {
        ui.label(format!(
            "stopped: {} · C = {} · O = {} · pixel",
            t.stop.words(),
            v3(t.color),
            sig(t.opacity)
        ));
        let (rect, _) = ui.allocate_exact_size(vec2(14.0, 14.0), Sense::hover());
        ui.painter()
            .rect_filled(rect, 2.0, color32(Color::srgb_from_array(t.pixel)));
        ui.label(v3(t.pixel));
    });
}

/// The method's formula with the opened (else the last) sample's numbers put in, in the order
/// in use (`voxcast_core::explain`, the same text `voxcast trace` prints).
fn formula(ui: &mut egui::Ui, t: &RayTrace, opened: Option<usize>) {
    let text = voxcast_core::explain::formula(t, opened);
    ui.label(egui::RichText::new(text).monospace());
}

/// One row per sample; clicking a row opens it. Returns the opened sample. What `hidden`
/// asks for shows as "?": an asked-for sample's value and what follows from it, and the
/// running colour while the composite is asked for.
fn sample_table(
    ui: &mut egui::Ui,
    t: &RayTrace,
    opened: Option<usize>,
    hidden: Option<&crate::sandbox::levels::Hidden>,
) -> Option<usize> {
    let mut opened = opened;
    egui::ScrollArea::both()
        .max_height(220.0)
        .scroll_bar_visibility(egui::scroll_area::ScrollBarVisibility::AlwaysVisible)
        .show(ui, |ui| {
            egui::Grid::new("samples").striped(true).show(ui, |ui| {
                super::header_row(
                    ui,
                    &[
                        "k",
                        "t",
                        "position (world)",
                        "value",
                        "TF rgba",
                        "α",
                        "α corrected",
                        "C after",
                        "O after",
                    ],
                );
                for (i, s) in t.samples.iter().enumerate() {
                    let chosen = opened == Some(i);
                    if ui.selectable_label(chosen, s.index.to_string()).clicked() {
                        opened = if chosen { None } else { Some(i) };
                    }
                    num(ui, s.t);
                    vec(ui, s.p_world);
                    if hidden.is_some_and(|h| h.hides_sample(s.p_voxel)) {
                        for _ in 0..4 {
                            ui.label(SECRET);
                        }
                    } else {
                        sample_values(ui, s);
                    }
                    if hidden.is_some_and(|h| h.composite) {
                        ui.label(SECRET);
                        ui.label(SECRET);
                    } else {
                        let c = s.composite_after;
                        vec(ui, [c[0], c[1], c[2]]);
                        num(ui, c[3]);
                    }
                    ui.end_row();
                }
                ui.strong("end");
                ui.label(t.stop.words());
                ui.end_row();
            });
        });
    opened
}

/// A sample's value, its colour and opacity from the transfer function, and the opacity
/// corrected for the step.
fn sample_values(ui: &mut egui::Ui, s: &SampleRecord) {
    num(ui, s.reconstruction.value);
    ui.horizontal(|ui| {
        let (rect, _) = ui.allocate_exact_size(vec2(10.0, 10.0), Sense::hover());
        ui.painter().rect_filled(
            rect,
            1.0,
            color32(Color::srgb(s.tf_rgba[0], s.tf_rgba[1], s.tf_rgba[2])),
        );
        let [r, g, b, a] = s.tf_rgba;
        ui.label(format!("{} {} {} {}", sig(r), sig(g), sig(b), sig(a)))
            .on_hover_text(format!("{r} {g} {b} {a}"));
    });
    num(ui, s.alpha);
    num(ui, s.alpha_corrected);
}

/// The opened sample: its 8 corners, weights and the interpolation, and its shading.
fn sample_detail(ui: &mut egui::Ui, s: &SampleRecord, secret: bool) {
    let r = &s.reconstruction;
    ui.label(format!(
        "sample {} at voxel {}; position in the cell (fx, fy, fz) = {}",
        s.index,
        v3(s.p_voxel),
        v3(r.frac)
    ));
    egui::Grid::new("corners").striped(true).show(ui, |ui| {
        super::header_row(
            ui,
            &[
                "corner (lecture's name)",
                "lattice point",
                "value",
                "weight",
                "weight × value",
            ],
        );
        for i in 0..8 {
            ui.label(format!(
                "{i} (f{})",
                voxcast_core::worked::lecture_corner(i)
            ))
            .on_hover_text(
                "The core numbers a cell's corners a + 2b + 4c; the lecture's worked \
                     example calls them f1 … f8 (f1 at the origin, f2 along x, f3 along x and \
                     y, f4 along y, then f5 … f8 one unit along z)",
            );
            let c = r.corners[i];
            ui.label(format!("({}, {}, {})", c[0], c[1], c[2]));
            num(ui, r.values[i]);
            num(ui, r.weights[i]);
            if secret {
                ui.label(SECRET);
            } else {
                num(ui, r.weights[i] * r.values[i]);
            }
            ui.end_row();
        }
    });
    if secret {
        ui.label(format!(
            "interpolated value Σ weight × value = {SECRET}: the value your prediction asks for"
        ));
        return;
    }
    ui.label(format!(
        "interpolated value Σ weight × value = {} (the renderer's value: {})",
        sig((0..8).map(|i| r.weights[i] * r.values[i]).sum::<f32>()),
        sig(r.value)
    ));
    if let Some(g) = s.gradient {
        ui.label(format!("gradient (central differences) {}", v3(g)));
    }
    if let Some(sh) = &s.shading {
        let [r, g, b, _] = s.tf_rgba;
        shading_terms(ui, sh, [r, g, b], s.color);
    }
}

/// The shading of one sample, every term that is on with its numbers (the core's
/// `explain::shading`, which a test recomputes).
fn shading_terms(
    ui: &mut egui::Ui,
    sh: &voxcast_core::shade::ShadeTerms,
    c: [f32; 3],
    shaded: [f32; 3],
) {
    ui.label(egui::RichText::new(voxcast_core::explain::shading(sh, c, shaded)).monospace());
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

/// Writes the breakdown (through a temporary file and a rename; in a browser, a download).
fn save(t: &RayTrace, path: &str, ext: &str) -> Result<String, String> {
    let base = std::path::Path::new(path.trim());
    if base.file_name().is_none() {
        return Err("give a file name".into());
    }
    let (text, mime) = if ext == "json" {
        (breakdown::to_json(t), "application/json")
    } else {
        (breakdown::to_csv(t), "text/csv")
    };
    crate::sandbox::shared::files::save(&base.with_extension(ext), text.as_bytes(), mime)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox::inspect::breakdown::pixel_trace;
    use crate::sandbox::inspect::rays::{Inspection, compute};
    use crate::sandbox::inspect::virtual_camera::VirtualCamera;

    /// Every string the breakdown draws — summary, formula, the sample table and an opened
    /// sample — has a glyph in the window's font, for every method and both orders.
    #[test]
    fn every_breakdown_string_can_be_drawn() {
        let (volume, render) = crate::sandbox::inspect::rays::tests::scene("bucky");
        let vc = VirtualCamera::framing(&volume, None).unwrap();
        for method in voxcast_core::composite::Method::ALL {
            for order in [
                voxcast_core::composite::Order::FrontToBack,
                voxcast_core::composite::Order::BackToFront,
            ] {
                let mut r = render.clone();
                (r.settings.method, r.settings.order, r.settings.shading) = (method, order, true);
                let t = pixel_trace(&volume, &r, &vc, UVec2::new(2, 2)).unwrap();
                let opened = t.samples.len().checked_sub(1);
                let hidden = crate::sandbox::levels::Hidden {
                    composite: true,
                    ..Default::default()
                };
                let cells = t.interval.map(|i| {
                    voxcast_core::cells::cells_crossed(
                        &volume.volume,
                        Vec3::from(t.origin),
                        Vec3::from(t.dir),
                        i,
                    )
                });
                let missing = super::super::missing_glyphs(|ui| {
                    summary(ui, &t, None);
                    if let Some(walk) = &cells {
                        cells_line(ui, walk, false, &mut false);
                        cells_line(ui, walk, true, &mut false);
                    }
                    ui.label(CELLS_TIP);
                    ui.label(TABLE_HIDDEN_WORDS);
                    formula(ui, &t, opened);
                    sample_table(ui, &t, opened, None);
                    ui.push_id("hidden", |ui| sample_table(ui, &t, opened, Some(&hidden)));
                    ui.label(HIDDEN_WORDS);
                    if let Some(s) = opened.and_then(|k| t.samples.get(k)) {
                        sample_detail(ui, s, false);
                        ui.push_id("hidden", |ui| sample_detail(ui, s, true));
                    }
                });
                assert!(
                    missing.is_empty(),
                    "{method:?} {order:?}: no glyph for {missing:?}"
                );
            }
        }
    }

    #[test]
    fn the_breakdown_is_the_cores_trace_and_exports_as_the_cli_does() {
        let (volume, render) = crate::sandbox::inspect::rays::tests::scene("bucky");
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

    /// While the trilinear level asks for P2's value, the breakdown of the lecture's ray
    /// shows "?" for it (and for what follows from it) and keeps the other samples; while it
    /// asks for the composite, the running colour goes; the formula and the export wait.
    #[test]
    fn a_prediction_s_answer_is_hidden_until_it_is_checked() {
        use crate::sandbox::levels::Hidden;
        let v = voxcast_core::Prepared::from(voxcast_core::builtin::worked_voxel());
        let tf = voxcast_core::preset::for_volume("voxel").unwrap().transfer;
        let mut s = voxcast_core::worked::lecture_ray_settings(&Default::default());
        s.order = voxcast_core::composite::Order::BackToFront;
        let cam = voxcast_core::worked::lecture_ray();
        let ray = cam.ray(0.5, 0.5, 1, 1);
        let scene = voxcast_core::trace::Scene::new(&v, &tf, &s, ray.dir).unwrap();
        let t = voxcast_core::trace::trace_ray(&scene, &ray, [0, 0]);
        let at = |p: [f32; 3]| {
            t.samples
                .iter()
                .position(|s| {
                    Hidden {
                        points: vec![p],
                        ..Default::default()
                    }
                    .hides_sample(s.p_voxel)
                })
                .unwrap()
        };
        let (p2, p1) = (at([0.5, 0.5, 0.5]), at([0.2, 0.3, 0.8]));
        let value = |k: usize| sig(t.samples[k].reconstruction.value);
        let table = |hidden: Option<&Hidden>| {
            crate::sandbox::ui::drawn_text(|ui| {
                sample_table(ui, &t, None, hidden);
            })
        };
        let shown = table(None);
        assert!(
            shown.contains(&value(p2)) && shown.contains(&value(p1)),
            "{shown}"
        );
        let h = Hidden {
            points: vec![[0.5, 0.5, 0.5]],
            ..Default::default()
        };
        let text = table(Some(&h));
        assert!(
            !text.lines().any(|l| l == value(p2)),
            "P2's value shows: {text}"
        );
        assert!(text.contains(&value(p1)), "P1's stays");
        assert_eq!(text.lines().filter(|l| *l == SECRET).count(), 4);
        let red = sig(t.color[0]);
        assert!(shown.contains(&red));
        let h = Hidden {
            composite: true,
            ..Default::default()
        };
        let text = table(Some(&h));
        assert_eq!(
            text.lines().filter(|l| *l == SECRET).count(),
            2 * t.samples.len()
        );
        assert!(text.contains(&value(p2)));
        let detail = crate::sandbox::ui::drawn_text(|ui| sample_detail(ui, &t.samples[p2], true));
        assert!(!detail.contains(&value(p2)), "{detail}");
        let summary_text = crate::sandbox::ui::drawn_text(|ui| summary(ui, &t, Some(&h)));
        assert!(!summary_text.contains(&red), "{summary_text}");
    }

    /// While a level asks how many samples the selected ray takes, the summary shows "?" for
    /// the count (the colour stays); while it asks for the cells, their count goes and they
    /// cannot be drawn; otherwise both show.
    #[test]
    fn a_ray_question_s_count_is_hidden_until_it_is_checked() {
        use crate::sandbox::levels::Hidden;
        let (volume, render) = crate::sandbox::inspect::rays::tests::scene("blobs");
        let vc = VirtualCamera::framing(&volume, None).unwrap();
        let t = pixel_trace(&volume, &render, &vc, UVec2::new(1, 1)).unwrap();
        let n = t.plan.unwrap().count;
        let said = format!("; {n} samples");
        let text = |h: Option<&Hidden>| crate::sandbox::ui::drawn_text(|ui| summary(ui, &t, h));
        assert!(text(None).contains(&said), "{}", text(None));
        let asked = Hidden {
            samples: true,
            ..Default::default()
        };
        let hidden = text(Some(&asked));
        assert!(
            !hidden.contains(&said) && hidden.contains("; ? samples"),
            "{hidden}"
        );
        assert!(
            hidden.contains(&sig(t.color[0])),
            "the colour is not asked for"
        );
        let walk = voxcast_core::cells::cells_crossed(
            &volume.volume,
            Vec3::from(t.origin),
            Vec3::from(t.dir),
            t.interval.unwrap(),
        );
        let crosses = format!("crosses {} cells", walk.cells.len());
        let line = |secret: bool| {
            let mut show = true;
            let text =
                crate::sandbox::ui::drawn_text(|ui| cells_line(ui, &walk, secret, &mut show));
            (text, show)
        };
        assert!(line(false).0.contains(&crosses));
        let (text, _) = line(true);
        assert!(
            !text.contains(&crosses) && text.contains("crosses ? cells"),
            "{text}"
        );
    }
}
