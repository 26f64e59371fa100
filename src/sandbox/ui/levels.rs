//! Guided levels: the "Levels" window lists the levels with the player's progress and Free
//! Play; a level sets up its scene (its volume, preview on or off, the virtual camera and its
//! pixels), shows one step at a time with the control it is about, and opens Next when the
//! step's objective — checked by the core's `Objective::met` against what the player did — is
//! met. Progress is saved to the config directory after every step (atomically); a damaged
//! file starts afresh with a message.

use super::inspector::BreakdownState;
use crate::sandbox::compare::Comparison;
use crate::sandbox::inspect::RaySelection;
use crate::sandbox::loading::Loading;
use crate::sandbox::preview::PreviewSettings;
use crate::sandbox::state::{MainCamera, RenderState, View, VolumeState};
use crate::sandbox::virtual_camera::VirtualCamera;
use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};
use std::path::PathBuf;
use voxcast_core::level::{Control, Level, Objective, Progress, Situation};

/// The levels, the one being played and the player's progress.
#[derive(Resource)]
pub struct Lessons {
    pub levels: Vec<Level>,
    /// `(level, step)` being played; `None` in free play.
    pub current: Option<(usize, usize)>,
    pub progress: Progress,
    /// Where progress is saved (`None`: not saved, as in tests).
    path: Option<PathBuf>,
    message: Option<String>,
    /// The scene still has to be set up for the level just chosen.
    pending_scene: bool,
    /// What the player typed as a prediction.
    pub prediction: String,
}

impl Lessons {
    /// The embedded levels with progress from `path` (or none).
    pub fn new(path: Option<PathBuf>) -> Self {
        let (progress, message) = match &path {
            Some(p) => Progress::load(p),
            None => (Progress::default(), None),
        };
        Self {
            levels: Level::all(),
            current: None,
            progress,
            path,
            message,
            pending_scene: false,
            prediction: String::new(),
        }
    }

    /// Starts level `i` at its first step.
    pub fn start(&mut self, i: usize) {
        if i < self.levels.len() {
            self.current = Some((i, 0));
            self.pending_scene = true;
        }
    }

    /// Back to free play (everything on).
    pub fn free_play(&mut self) {
        self.current = None;
        self.pending_scene = true;
    }

    /// The step being played.
    pub fn step(&self) -> Option<&voxcast_core::level::Step> {
        let (l, s) = self.current?;
        self.levels.get(l)?.steps.get(s)
    }

    /// Records the step as done, saves, and moves on (to free play after the last).
    pub fn next(&mut self) {
        let Some((l, s)) = self.current else { return };
        let id = self.levels[l].id.clone();
        self.progress.record(&id, s + 1);
        if let Some(path) = &self.path
            && let Err(e) = self.progress.save(path)
        {
            self.message = Some(format!("progress not saved: {e}"));
        }
        self.prediction.clear();
        self.current = if s + 1 < self.levels[l].steps.len() {
            Some((l, s + 1))
        } else {
            self.message = Some(format!("“{}” done!", self.levels[l].title));
            None
        };
        if self.current.is_none() {
            self.pending_scene = true;
        }
    }
}

/// `$XDG_CONFIG_HOME/voxcast/progress.json` (else `~/.config/…`); `VOXCAST_CONFIG_DIR`
/// overrides the folder.
pub fn progress_path() -> Option<PathBuf> {
    let dir = std::env::var_os("VOXCAST_CONFIG_DIR")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("XDG_CONFIG_HOME").map(|d| PathBuf::from(d).join("voxcast")))
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config/voxcast")))?;
    Some(dir.join("progress.json"))
}

/// What the player has done, as the objectives see it.
pub(super) fn situation(
    render: &RenderState,
    volume: &VolumeState,
    vc: Option<&VirtualCamera>,
    selection: &RaySelection,
    breakdown: &BreakdownState,
    (comparison, view): (&Comparison, Option<&View>),
) -> Situation {
    let voxel = volume.volume.spacing().min_element();
    let (lo, hi) = volume.volume.bounds();
    let compared_max = comparison
        .result
        .as_ref()
        .filter(|r| super::compare::is_current(&r.snapshot, view, render, volume))
        .and_then(|r| r.diff.as_ref().map(|(d, _)| d.max_abs * 255.0));
    let light_inside_volume = matches!(render.settings.phong.light,
        voxcast_core::shade::Light::Point(p) if p.cmpge(lo).all() && p.cmple(hi).all());
    Situation {
        method: Some(render.settings.method),
        step_voxels: render.settings.step.voxels(voxel),
        virtual_pixels: vc.map_or(0, |v| v.width.min(v.height)),
        ray_selected: selection.selected.is_some(),
        ray_values: breakdown
            .trace
            .as_ref()
            .map(|t| t.samples.iter().map(|s| s.reconstruction.value).collect())
            .unwrap_or_default(),
        opened_sample: breakdown.opened,
        early_termination: render.settings.early_termination,
        opacity_correction: render.settings.opacity_correction,
        shading: render.settings.shading,
        target: render.settings.target,
        classification: voxcast_core::level::classification_mode(&render.settings.classification),
        transfer: Some(render.transfer.clone()),
        compared_max,
        light_inside_volume,
        prediction: None,
        back_to_front: render.settings.order == voxcast_core::composite::Order::BackToFront,
        light_kind: voxcast_core::level::light_kind(&render.settings.phong.light),
        attenuated: render.settings.phong.kl > 0.0 || render.settings.phong.kq > 0.0,
    }
}

/// Sets up the scene a level asks for (or free play's) once, when it is chosen.
pub(super) fn set_up_scene(
    mut lessons: ResMut<Lessons>,
    volume: Res<VolumeState>,
    mut loading: ResMut<Loading>,
    mut preview: ResMut<PreviewSettings>,
    mut cameras: Query<&mut VirtualCamera>,
) {
    // The virtual camera is spawned with the first volume: wait for it.
    if !lessons.pending_scene || cameras.is_empty() {
        return;
    }
    lessons.pending_scene = false;
    let scene = lessons
        .current
        .and_then(|(l, _)| lessons.levels.get(l))
        .map(|l| l.scene.clone());
    let (preview_on, rays) = match &scene {
        Some(s) => {
            if s.volume != volume.source {
                loading.start(s.volume.clone());
            }
            (s.preview, s.rays)
        }
        None => (true, None),
    };
    preview.enabled = preview_on;
    if let Ok(mut vc) = cameras.single_mut() {
        match (&scene, rays) {
            (Some(_), Some(n)) => {
                vc.shown = true;
                (vc.width, vc.height) = (n, n);
            }
            (Some(_), None) => vc.shown = false,
            (None, _) => vc.shown = true,
        }
    }
}

fn control_name(c: Control) -> &'static str {
    match c {
        Control::Method => "Settings › Ray casting › Method",
        Control::Step => "Settings › Ray casting › Step size",
        Control::VirtualPixels => "Settings › Virtual camera › pixels",
        Control::PixelGrid => "the Rays window's image",
        Control::Breakdown => "the ray's breakdown window",
        Control::OpacityCorrection => "Settings › Ray casting › Opacity correction",
        Control::EarlyTermination => "Settings › Ray casting › Early ray termination",
        Control::Target => "Settings › Ray casting › Target value (First)",
        Control::Shading => "Settings › Shading and light › Shading",
        Control::Classification => "Settings › Transfer function › Classification",
        Control::TransferFunction => "Settings › Transfer function (the editor)",
        Control::RenderImage => "the Render image… button",
        Control::Light => "Settings › Shading and light › Light",
        Control::Order => "Settings › Ray casting › Order",
    }
}

/// The Levels window: the list with progress and Free Play, or the current step.
#[allow(clippy::too_many_arguments)]
pub(super) fn levels_window(
    mut contexts: EguiContexts,
    mut lessons: ResMut<Lessons>,
    render: Res<RenderState>,
    volume: Res<VolumeState>,
    cameras: Query<&VirtualCamera>,
    (selection, breakdown): (Res<RaySelection>, Res<BreakdownState>),
    (comparison, views): (Res<Comparison>, Query<&View, With<MainCamera>>),
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let mut sit = situation(
        &render,
        &volume,
        cameras.single().ok(),
        &selection,
        &breakdown,
        (&comparison, views.single().ok()),
    );
    // A prediction step: the typed value against the core's value at the step's point.
    let point = match lessons.step().map(|s| &s.objective) {
        Some(Objective::PredictValue { point, .. }) => Some(Vec3::from_array(*point)),
        _ => None,
    };
    let detail = point.map(|p| {
        voxcast_core::sample::detail_at(
            &volume.volume,
            p,
            voxcast_core::sample::Interpolation::Trilinear,
        )
    });
    if let (Some(d), Ok(typed)) = (&detail, lessons.prediction.trim().parse::<f32>()) {
        sit.prediction = Some((typed, d.value));
    }
    let lessons = &mut *lessons;
    egui::Window::new("Levels")
        .default_pos(egui::pos2(ctx.viewport_rect().center().x - 200.0, 20.0))
        .default_width(400.0)
        .show(ctx, |ui| {
            if let Some(m) = &lessons.message {
                ui.colored_label(egui::Color32::YELLOW, m);
            }
            match lessons.current {
                None => level_list(ui, lessons),
                Some((l, s)) => level_step(ui, lessons, l, s, &sit, detail.as_ref()),
            }
        });
    Ok(())
}

fn level_list(ui: &mut egui::Ui, lessons: &mut Lessons) {
    ui.label("One concept per level. Free play: everything on, as it is now.");
    let mut chosen = None;
    for (i, level) in lessons.levels.iter().enumerate() {
        let done = lessons
            .progress
            .completed
            .get(&level.id)
            .copied()
            .unwrap_or(0);
        let total = level.steps.len();
        ui.horizontal(|ui| {
            let mark = if done >= total { "✔" } else { " " };
            if ui
                .button(format!("{mark} {}. {}", i + 1, level.title))
                .on_hover_text(&level.concept)
                .clicked()
            {
                chosen = Some(i);
            }
            ui.label(format!("{}/{} steps", done.min(total), total));
        });
    }
    if let Some(i) = chosen {
        lessons.message = None;
        lessons.start(i);
    }
}

fn level_step(
    ui: &mut egui::Ui,
    lessons: &mut Lessons,
    l: usize,
    s: usize,
    sit: &Situation,
    detail: Option<&voxcast_core::sample::SampleDetail>,
) {
    let Some(step) = lessons.step().cloned() else {
        return;
    };
    let level = &lessons.levels[l];
    ui.heading(&level.title);
    ui.label(egui::RichText::new(&level.concept).italics());
    ui.separator();
    ui.label(format!("Step {} of {}", s + 1, level.steps.len()));
    ui.label(&step.text);
    if let Some(c) = step.control {
        ui.colored_label(
            egui::Color32::LIGHT_BLUE,
            format!("Look at: {} (framed in yellow)", control_name(c)),
        );
    }
    let met = step.objective.met(sit);
    let reading = step.objective == Objective::Read;
    if let Some(d) = detail {
        ui.horizontal(|ui| {
            ui.label("your value:");
            ui.text_edit_singleline(&mut lessons.prediction);
        });
        if met {
            // The answer: each corner, its weight and its share.
            egui::Grid::new("prediction").striped(true).show(ui, |ui| {
                for h in ["corner", "value", "weight", "weight × value"] {
                    ui.strong(h);
                }
                ui.end_row();
                for i in 0..8 {
                    let c = d.corners[i];
                    ui.label(format!("({}, {}, {})", c[0], c[1], c[2]));
                    ui.label(d.values[i].to_string());
                    ui.label(d.weights[i].to_string());
                    ui.label((d.values[i] * d.weights[i]).to_string());
                    ui.end_row();
                }
            });
            ui.label(format!("value = {}", d.value));
        }
    }
    if !reading {
        ui.label(if met { "✔ done" } else { "… not yet" });
    }
    let mut next = false;
    let mut leave = false;
    ui.horizontal(|ui| {
        next = ui
            .add_enabled(
                met,
                egui::Button::new(if reading { "Next" } else { "Next ✔" }),
            )
            .clicked();
        leave = ui.button("Free play").clicked();
    });
    if next {
        lessons.next();
    } else if leave {
        lessons.free_play();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every level played through: each objective met by doing what it asks in the state a
    /// user's controls change, and Next then moves on; progress is recorded per step.
    #[test]
    fn every_level_can_be_completed() {
        let dir = std::env::temp_dir().join(format!("voxcast-levels-{}", std::process::id()));
        let path = dir.join("progress.json");
        let mut lessons = Lessons::new(Some(path.clone()));
        for l in 0..lessons.levels.len() {
            lessons.start(l);
            let mut sit = Situation {
                step_voxels: 0.5,
                virtual_pixels: 4,
                ..Default::default()
            };
            while let Some(step) = lessons.step().cloned() {
                match step.objective {
                    Objective::Read => {}
                    Objective::SelectRay => sit.ray_selected = true,
                    Objective::VirtualPixelsAtLeast { pixels } => sit.virtual_pixels = pixels,
                    Objective::StepAtMost { voxels } => sit.step_voxels = voxels,
                    Objective::Method { method } => sit.method = Some(method),
                    Objective::OpenHighestSample => {
                        sit.ray_selected = true;
                        sit.ray_values = vec![3.0, 9.0, 1.0];
                        sit.opened_sample = Some(1);
                    }
                    Objective::EarlyTermination { on } => sit.early_termination = on,
                    Objective::OpacityCorrection { on } => sit.opacity_correction = on,
                    Objective::Shading { on } => sit.shading = on,
                    Objective::TargetBetween { lo, hi } => sit.target = Some(0.5 * (lo + hi)),
                    Objective::TfAlphaAtMost { value, alpha } => {
                        let t = sit.transfer.take().unwrap_or_else(|| {
                            voxcast_core::transfer::TransferFunction::ramp(0.0, 255.0, 1.0).unwrap()
                        });
                        let (t, _) = t.with_point_added(value, alpha).unwrap();
                        sit.transfer = Some(t);
                    }
                    Objective::TfColorNear {
                        value,
                        color,
                        alpha,
                        ..
                    } => {
                        let t = sit.transfer.take().unwrap_or_else(|| {
                            voxcast_core::transfer::TransferFunction::ramp(0.0, 255.0, 1.0).unwrap()
                        });
                        let (t, i) = t.with_point_added(value, alpha).unwrap();
                        sit.transfer = Some(t.with_point_color(i, color).unwrap());
                    }
                    Objective::Compared { max } => sit.compared_max = Some(max * 0.5),
                    Objective::LightInsideVolume => sit.light_inside_volume = true,
                    Objective::BackToFront { on } => sit.back_to_front = on,
                    Objective::LightKind { ref light } => {
                        sit.light_kind = if light == "point" {
                            "point"
                        } else {
                            "directional"
                        }
                    }
                    Objective::Attenuated => sit.attenuated = true,
                    Objective::PredictValue { point, .. } => {
                        // The player types the value the core computes (its agreement with
                        // the lecture's formula is tested in voxcast_core::builtin).
                        let v = voxcast_core::builtin::worked_voxel();
                        let truth = voxcast_core::sample::detail_at(
                            &v,
                            Vec3::from_array(point),
                            voxcast_core::sample::Interpolation::Trilinear,
                        )
                        .value;
                        sit.prediction = Some((truth, truth));
                    }
                    Objective::Classification { ref mode } => {
                        sit.classification = match mode.as_str() {
                            "iso-contours" => "iso-contours",
                            "boundaries" => "boundaries",
                            _ => "table",
                        }
                    }
                }
                assert!(step.objective.met(&sit), "{:?}", step.objective);
                lessons.next();
            }
            let id = &lessons.levels[l].id;
            assert_eq!(
                lessons.progress.completed[id],
                lessons.levels[l].steps.len()
            );
        }
        // Saved: a new session sees the same progress.
        assert_eq!(Lessons::new(Some(path)).progress, lessons.progress);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
