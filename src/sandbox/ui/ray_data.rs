//! The Ray data section (RayVis's panel): where the rays come from, which of them are
//! counted, the grid with its memory estimate, Compute with progress and Cancel, what came of
//! it, and the views — the density volume, the ray mesh, the vector field and the scene.

use super::{Spot, combo, marked, tunable_slider};
use crate::sandbox::data::choices::ViewReport;
use crate::sandbox::data::choices::{RayChoices, ViewChoices};
use crate::sandbox::data::estimate::Estimator;
use crate::sandbox::data::loading::Loading;
use crate::sandbox::data::source::{RayScene, SourceKind};
use crate::sandbox::inspect::virtual_camera::VirtualCamera;
use crate::sandbox::shared::files;
use crate::sandbox::shared::state::{RenderState, VolumeState};
use bevy_egui::egui;
use voxcast_core::level::Control;
use voxcast_core::numbers::{count, sig};
use voxcast_core::rays::effects::Effect;
use voxcast_core::rays::field::{ArrowScale, cube_sizes};
use voxcast_core::rays::layered::SceneShading;
use voxcast_core::rays::set::Filter;
use voxcast_core::tunables as t;

/// What the section reads and edits.
pub(crate) struct RayPanel<'a> {
    pub choices: &'a mut RayChoices,
    pub rays: &'a RayScene,
    pub estimator: &'a Estimator,
    pub report: &'a ViewReport,
    pub volume: &'a VolumeState,
    pub render: &'a mut RenderState,
    pub loading: &'a mut Loading,
    pub virtual_camera: Option<&'a VirtualCamera>,
    /// The preview (the density volume's view) on or off.
    pub preview_on: &'a mut bool,
    /// Set when the volume before the densities is to come back.
    pub back: &'a mut bool,
    pub fit: &'a mut crate::sandbox::data::estimate::RangeFit,
    /// Name the box's traces by number only (a level asks which effect each holds).
    pub hide_effects: bool,
}

/// Bytes in words (KiB, MiB, GiB).
fn bytes(n: usize) -> String {
    let n = n as f64;
    match n {
        n if n >= (1u64 << 30) as f64 => format!("{} GiB", sig((n / (1u64 << 30) as f64) as f32)),
        n if n >= (1u64 << 20) as f64 => format!("{} MiB", sig((n / (1u64 << 20) as f64) as f32)),
        n => format!("{} KiB", sig((n / 1024.0) as f32)),
    }
}

pub(crate) fn ray_data_section(ui: &mut egui::Ui, mut p: RayPanel, spot: Spot) {
    let on_show = p.rays.on_show(p.volume).cloned();
    // The rays, their grid and Compute framed together: a level asks to choose and compute.
    marked(ui, spot, Control::RaySource, |ui| {
        source_controls(ui, &mut *p.choices, p.hide_effects);
        grid_controls(ui, &mut *p.choices, p.estimator);
        compute_row(ui, &mut p);
    });
    if let Some(e) = &p.loading.error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
    let Some(shown) = on_show else {
        ui.label(
            egui::RichText::new(
                "Compute to see the density; its scene, ray mesh and vector field are drawn \
                 around it.",
            )
            .small(),
        );
        return;
    };
    let d = &shown.computed.density;
    let r = &d.report;
    ui.label(
        egui::RichText::new(format!(
            "{} rays, {} cell visits; {} in {} chunks (a dense grid: {})",
            count(r.rays as u64),
            count(r.visits),
            bytes(d.memory_bytes()),
            d.chunks.len(),
            bytes(d.dense_bytes())
        ))
        .small(),
    );
    let skipped = r.malformed + r.out_of_range;
    if skipped + r.capped > 0 {
        ui.label(
            egui::RichText::new(format!(
                "{skipped} rays skipped as malformed or too far out, {} cut at {} cells",
                r.capped, d.params.max_cells_per_ray
            ))
            .small(),
        );
    }
    if p.rays.before.is_some() && ui.button("Back to the volume").clicked() {
        *p.back = true;
    }
    ui.separator();
    marked(ui, spot, Control::RayViews, |ui| {
        view_controls(ui, p.choices, p.preview_on, p.report, d.params.chunk)
    });
    ui.horizontal(|ui| {
        let busy = p.fit.busy();
        if ui
            .add_enabled(!busy, egui::Button::new("Fit the range to this view"))
            .on_hover_text(
                "Set Sum's range from 0 to what the densest twentieth of this view's rays \
                 gather (a 32 × 32 grid of them, stopped at the scene), so the picture spans \
                 inferno; done for every new density",
            )
            .clicked()
        {
            p.fit.asked = true;
        }
        if busy {
            ui.spinner();
        }
    });
    ui.label("Sum range and step per cell: Ray casting above.");
}

/// Compute, and while it counts its progress and Cancel.
fn compute_row(ui: &mut egui::Ui, p: &mut RayPanel) {
    ui.horizontal(|ui| {
        let busy = p.loading.under_way().is_some();
        if ui
            .add_enabled(!busy, egui::Button::new("Compute"))
            .on_hover_text(
                "Count the chosen rays through the grid in the background and show the \
                 density as the volume (Sum, inferno)",
            )
            .clicked()
        {
            p.choices
                .compute(p.loading, p.rays, p.volume, p.render, p.virtual_camera);
        }
        if let Some((what, seconds)) = p.loading.under_way() {
            ui.spinner();
            let share = p.loading.fraction().map_or(String::new(), |f| {
                format!("{}, ", voxcast_core::numbers::percent(f))
            });
            ui.label(format!("{share}{seconds:.1} s"))
                .on_hover_text(what.to_string());
            if ui.button("Cancel").clicked() {
                p.loading.cancel();
            }
        }
    });
}

/// Source, path, trace and filter.
fn source_controls(ui: &mut egui::Ui, c: &mut RayChoices, hide_effects: bool) {
    combo(ui, "Rays", c.source.words(), |ui| {
        for s in SourceKind::ALL {
            ui.selectable_value(&mut c.source, s, s.words())
                .on_hover_text(s.doc());
        }
    })
    .response
    .on_hover_text(c.source.doc());
    source_details(ui, c, hide_effects);
    if c.source == SourceKind::File {
        ui.horizontal(|ui| {
            let mut every = c.trace.is_none();
            ui.checkbox(&mut every, "every trace")
                .on_hover_text("Count the rays of every trace in the file");
            let mut id = c.trace.unwrap_or(0);
            if !every {
                ui.add(egui::DragValue::new(&mut id).prefix("trace "))
                    .on_hover_text("The trace id (voxcast rays info lists them)");
            }
            c.trace = (!every).then_some(id);
        });
    }
    ui.horizontal(|ui| {
        for f in Filter::ALL {
            ui.radio_value(&mut c.params.filter, f, f.name())
                .on_hover_text(match f {
                    Filter::All => "Count every ray",
                    Filter::Hit => "Count the rays that hit something, up to the hit",
                    Filter::Miss => "Count the rays that hit nothing",
                });
        }
    });
    ui.add(
        egui::DragValue::new(&mut c.params.tolerance)
            .range(0.0..=f32::MAX)
            .speed(0.01)
            .prefix(format!("{}: ", t::MISS_TOLERANCE.label)),
    )
    .on_hover_text(t::MISS_TOLERANCE.doc);
}

/// What the chosen source needs: a file (picked on a page, a path on the desktop), the
/// virtual camera's side, or which of the Cornell box's traces.
fn source_details(ui: &mut egui::Ui, c: &mut RayChoices, hide_effects: bool) {
    match c.source {
        // A page reads no paths: the browser's picker hands the file over, its density
        // computed at once (`data/handed_rays.rs`).
        SourceKind::File if files::PICKS_FILES => {
            ui.horizontal(|ui| {
                if super::target(ui.button("Open a .rayvis file…"), "Open a rayvis file")
                    .on_hover_text(SourceKind::File.doc())
                    .clicked()
                {
                    files::pick(files::Purpose::Rays);
                }
                let name = if c.path.is_empty() {
                    "none opened yet"
                } else {
                    &c.path
                };
                ui.label(name);
            });
        }
        SourceKind::File => {
            ui.add(egui::TextEdit::singleline(&mut c.path).desired_width(ui.available_width()))
                .on_hover_text(SourceKind::File.doc());
        }
        SourceKind::Camera => {
            let mut side = c.camera_side as f32;
            if tunable_slider(
                ui,
                egui::Slider::new(&mut side, 1.0..=t::RAY_CAMERA_SIDE.max)
                    .logarithmic(true)
                    .integer(),
                &t::RAY_CAMERA_SIDE,
            )
            .changed()
            {
                c.camera_side = side as u32;
            }
        }
        SourceKind::Cornell | SourceKind::CornellMillion => {
            let words = |id: Option<u32>| match (id, id.and_then(Effect::of)) {
                (None, _) => "every trace".to_string(),
                (Some(id), Some(e)) if !hide_effects => format!("trace {id}: {}", e.words()),
                (Some(id), _) => format!("trace {id}"),
            };
            combo(ui, "Trace", words(c.trace), |ui| {
                ui.selectable_value(&mut c.trace, None, words(None));
                for e in Effect::ALL {
                    ui.selectable_value(&mut c.trace, Some(e.id()), words(Some(e.id())));
                }
            })
            .response
            .on_hover_text("Which of the box's ray sets is counted");
        }
    }
}

/// Cell and chunk, with the memory estimate.
fn grid_controls(ui: &mut egui::Ui, c: &mut RayChoices, est: &Estimator) {
    est.want();
    ui.horizontal(|ui| {
        let mut auto = c.params.cell == 0.0;
        ui.checkbox(&mut auto, "automatic cell")
            .on_hover_text(t::RAY_CELL.doc);
        if auto {
            c.params.cell = 0.0;
        } else {
            if c.params.cell == 0.0 {
                c.params.cell = est
                    .result
                    .as_ref()
                    .and_then(|r| r.as_ref().ok())
                    .map_or(1.0, |e| e.cell);
            }
            ui.add(
                egui::DragValue::new(&mut c.params.cell)
                    .range(1e-3..=1e6)
                    .speed(0.05)
                    .custom_formatter(|v, _| sig(v as f32))
                    .prefix(format!("{}: ", t::RAY_CELL.label)),
            )
            .on_hover_text(t::RAY_CELL.doc);
        }
    });
    let mut chunk = c.params.chunk as f32;
    if tunable_slider(
        ui,
        egui::Slider::new(&mut chunk, t::RAY_CHUNK.min..=t::RAY_CHUNK.max).integer(),
        &t::RAY_CHUNK,
    )
    .changed()
    {
        c.params.chunk = chunk as u32;
    }
    let words = match (&est.result, c.source) {
        (_, SourceKind::Camera) => {
            "memory: known once computed (the rays come from the march)".to_string()
        }
        _ if est.busy() => "estimating the memory…".to_string(),
        (Some(Ok(e)), _) => format!(
            "{} rays through cells of {}: about {} in {} chunks",
            count(e.rays as u64),
            sig(e.cell),
            bytes(e.bytes),
            e.chunks
        ),
        (Some(Err(e)), _) => e.clone(),
        (None, _) => String::new(),
    };
    ui.label(egui::RichText::new(words).small());
}

/// The views and their settings.
fn view_controls(
    ui: &mut egui::Ui,
    c: &mut RayChoices,
    preview_on: &mut bool,
    report: &ViewReport,
    chunk: u32,
) {
    let v = &mut c.view;
    ui.checkbox(preview_on, "Density volume")
        .on_hover_text("The density ray-marched with Sum (the live preview)");
    ui.checkbox(&mut v.mesh, "Ray mesh")
        .on_hover_text("Every counted ray as a line from its start to its hit or end");
    if v.mesh {
        ui.indent("mesh", |ui| mesh_controls(ui, v, report));
    }
    ui.checkbox(&mut v.field, "Vector field")
        .on_hover_text("An arrow per sample cube along the rays' mean direction");
    ui.label(egui::RichText::new(crate::sandbox::data::shortcuts::SHORTCUTS).small())
        .on_hover_text("Over the scene (not while typing in a field)");
    if v.field {
        ui.indent("field", |ui| field_controls(ui, v, report, chunk));
    }
    if let Some(n) = report.moving_every.filter(|_| v.mesh || v.field) {
        ui.label(
            egui::RichText::new(format!("moving with the CPU live view: 1 in {n} drawn")).small(),
        )
        .on_hover_text(
            "The CPU draws the live view and the lines over it: while the view moves only a \
             share of the rays and arrows is drawn, sized to take about a hundredth of a \
             second, so the window keeps answering; at rest all of them",
        );
    }
    if report.building {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label("building the lines…");
        });
    }
    // Wrapped: five choices do not fit one row of the panel ("barycentric" was cut off).
    ui.horizontal_wrapped(|ui| {
        ui.label("Scene");
        for s in SceneShading::ALL {
            ui.radio_value(&mut v.shading, s, s.name())
                .on_hover_text(s.doc());
        }
    });
}

/// The ray mesh's settings: which rays, the glyphs, the colours, and how many lines are drawn.
fn mesh_controls(ui: &mut egui::Ui, v: &mut ViewChoices, report: &ViewReport) {
    let mut stride = v.stride as f32;
    if tunable_slider(
        ui,
        egui::Slider::new(&mut stride, 1.0..=4096.0)
            .logarithmic(true)
            .integer(),
        &t::RAY_STRIDE,
    )
    .changed()
    {
        v.stride = stride as usize;
    }
    ui.checkbox(&mut v.glyphs, "Start and end glyphs")
        .on_hover_text("A cross where each ray starts and an arrowhead where it hit or ended (G)");
    ui.horizontal(|ui| {
        ui.color_edit_button_rgb(&mut v.hit_colour)
            .on_hover_text("The colour of rays that hit");
        ui.label("hit");
        ui.color_edit_button_rgb(&mut v.miss_colour)
            .on_hover_text("The colour of rays that missed");
        ui.label("miss");
    });
    let left_out = if report.left_out > 0 {
        format!(
            " ({} rays outside the drawn box)",
            count(report.left_out as u64)
        )
    } else {
        String::new()
    };
    ui.label(
        egui::RichText::new(format!("{} lines{left_out}", count(report.lines as u64))).small(),
    );
}

/// The vector field's settings: the sample cube (one the chunk divides), the arrows' scale,
/// the fewest rays a cube needs, and how many arrows are drawn.
fn field_controls(ui: &mut egui::Ui, v: &mut ViewChoices, report: &ViewReport, chunk: u32) {
    let sizes = cube_sizes(chunk);
    if !sizes.contains(&v.cube) {
        v.cube = *sizes.iter().rfind(|k| **k <= v.cube).unwrap_or(&1);
    }
    combo(ui, t::SAMPLE_CUBE.label, v.cube.to_string(), |ui| {
        for k in sizes {
            ui.selectable_value(&mut v.cube, k, k.to_string());
        }
    })
    .response
    .on_hover_text(t::SAMPLE_CUBE.doc);
    ui.horizontal(|ui| {
        for s in ArrowScale::ALL {
            ui.radio_value(&mut v.arrow_scale, s, s.name())
                .on_hover_text(s.doc());
        }
    });
    ui.horizontal(|ui| {
        ui.add(egui::DragValue::new(&mut v.min_count).speed(1.0))
            .on_hover_text(t::FIELD_MIN_COUNT.doc);
        ui.label(t::FIELD_MIN_COUNT.label)
            .on_hover_text(t::FIELD_MIN_COUNT.doc);
    });
    let words = match &report.field_error {
        Some(e) => e.clone(),
        None => format!(
            "{} arrows, coloured by count (inferno)",
            count(report.arrows as u64)
        ),
    };
    ui.label(egui::RichText::new(words).small());
}
