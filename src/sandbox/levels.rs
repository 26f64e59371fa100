//! Guided levels, the logic: the levels and the player's progress, the commands the Levels
//! window sends (start a level, Next, free play), the scene each mode sets up, and the check of
//! the current step's objective — the core's `Objective::met` against what the player did.
//! The mode itself is the [`Mode`] state; what a level spawned leaves with it. Progress is saved
//! after every step, to the config directory (atomically) or, in a browser, to its local
//! storage; a damaged file or entry starts afresh with a message.

use crate::sandbox::breakdown::BreakdownState;
use crate::sandbox::compare::Comparison;
use crate::sandbox::inspect::RaySelection;
use crate::sandbox::loading::{Loading, reset_to_defaults};
use crate::sandbox::mode::{FreePlay, Mode, Stage};
use crate::sandbox::preview::PreviewSettings;
use crate::sandbox::state::{MainCamera, RenderState, View, VolumeState};
use crate::sandbox::trade::StepTrade;
use crate::sandbox::virtual_camera::VirtualCamera;
use bevy::prelude::*;
use std::path::PathBuf;
use voxcast_core::level::{
    Answer, Control, Level, Objective, Progress, Section, Situation, Step, StudyRun,
};
use voxcast_core::sample::{Interpolation, SampleDetail, detail_at};

/// The levels, the step being played and the player's progress.
#[derive(Resource)]
pub struct Lessons {
    pub levels: Vec<Level>,
    /// The step being played in the current level (the level is the [`Mode`]).
    pub step: usize,
    pub progress: Progress,
    /// Where progress is kept.
    store: ProgressStore,
    pub message: Option<String>,
    /// What the player typed as a prediction.
    pub prediction: String,
    /// The effect (trace id) the player named.
    pub named_effect: Option<u32>,
    /// Whether the current step's objective is met (checked every frame; once met it stays
    /// met until the step changes, so closing a window or undoing a change never takes a
    /// finished step back).
    pub met: bool,
    /// The mode and step `met` was last found true for.
    met_for: Option<(Mode, usize)>,
    /// The control the current step is about (framed in the panel).
    pub spot: Option<Control>,
    /// For a prediction step: the core's reconstruction at the step's point.
    pub detail: Option<SampleDetail>,
    /// For a composite prediction step: the worked composite, point by point.
    pub composite: Option<Vec<voxcast_core::worked::WorkedPoint>>,
    /// The study question answered right in this step: its trace and key.
    pub studied: Option<(u32, String)>,
    /// The ray density on show (what a study question is asked about).
    pub on_show: Option<std::sync::Arc<super::raydata::Shown>>,
    /// The run of the study under way (the level played twice, preview off then on).
    pub study: Option<StudyRun>,
    /// The levels list's choice: a level clicked starts as a study.
    pub study_next: bool,
    /// The scene is set up again on the next frame (a study's second run, same mode).
    set_up_again: bool,
}

/// What the Levels panel asks for (a scripted run sends the same).
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub enum LevelCommand {
    /// Start level `i` at its first step.
    Start(usize),
    /// Start level `i` as a study: played to its end with the preview off, then again with
    /// it on, each run's answers kept with the run's name.
    Study(usize),
    /// The current step is done (refused unless its objective is met).
    Next,
    /// Leave the level for free play.
    FreePlay,
}

impl Lessons {
    /// The embedded levels with the progress kept in `store`.
    pub fn new(store: ProgressStore) -> Self {
        let (progress, message) = store.load();
        Self {
            met_for: None,
            levels: Level::all(),
            step: 0,
            progress,
            store,
            message,
            prediction: String::new(),
            named_effect: None,
            met: false,
            spot: None,
            detail: None,
            composite: None,
            studied: None,
            on_show: None,
            study: None,
            study_next: false,
            set_up_again: false,
        }
    }

    /// The step being played in `mode`.
    pub fn step_in(&self, mode: Mode) -> Option<&Step> {
        match mode {
            Mode::Level(l) => self.levels.get(l)?.steps.get(self.step),
            Mode::FreePlay => None,
        }
    }

    /// The panel sections `mode` shows (`None`: all, as in free play).
    pub fn panel_in(&self, mode: Mode) -> Option<&[Section]> {
        match mode {
            Mode::Level(l) => self.levels.get(l)?.scene.panel.as_deref(),
            Mode::FreePlay => None,
        }
    }

    /// Records the current step of level `l` as done, with its answer where it asked for one
    /// (the prediction it was done with), and saves.
    fn record(&mut self, l: usize) {
        let id = self.levels[l].id.clone();
        let step = self.levels[l]
            .steps
            .get(self.step)
            .map(|s| s.objective.clone());
        let truth = prediction_truth(self.detail.as_ref(), self.composite.as_deref());
        let question = match step {
            Some(Objective::PredictValue { point, .. }) => Some(format!(
                "the value at ({}, {}, {})",
                point[0], point[1], point[2]
            )),
            Some(Objective::PredictComposite { .. }) => {
                Some("the red of C after the last point".to_string())
            }
            _ => None,
        };
        if let (Some(question), Some(truth)) = (question, truth) {
            let answer = (
                self.prediction.trim().to_string(),
                voxcast_core::numbers::sig(truth),
                true,
            );
            let a = Answer::now(&id, self.step + 1, question, answer);
            self.keep(a);
        }
        self.progress.record(&id, self.step + 1);
        self.save();
    }

    /// Names effect `chosen` as the one that cast trace `trace` (step of level `l`): kept as an
    /// answer, right or wrong, and saved.
    pub fn name_effect(&mut self, l: usize, chosen: u32, trace: u32) {
        use voxcast_core::rays::effects::Effect;
        self.named_effect = Some(chosen);
        let words = |id: u32| Effect::of(id).map_or("?", |e| e.kind());
        let answer = (
            words(chosen).to_string(),
            words(trace).to_string(),
            Effect::same_kind(chosen, trace),
        );
        let question = format!("which effect cast trace {trace}");
        let a = Answer::now(&self.levels[l].id, self.step + 1, question, answer);
        self.keep(a);
        self.save();
    }

    /// Answers study question `key` about `trace` (step of level `l`) with `chosen`, against
    /// what the code finds in the trace on show (`truth`): kept as an answer, right or wrong.
    pub fn answer_study(&mut self, l: usize, (trace, key): (u32, &str), chosen: &str, truth: &str) {
        let question = voxcast_core::rays::study::Question::parse(key)
            .map_or(key.to_string(), |q| q.words(trace));
        let correct = chosen == truth;
        if correct {
            self.studied = Some((trace, key.to_string()));
        }
        let answer = (chosen.to_string(), truth.to_string(), correct);
        let a = Answer::now(&self.levels[l].id, self.step + 1, question, answer);
        self.keep(a);
        self.save();
    }

    /// The ray density on show, if it is the one study question `q` about `trace` is asked
    /// of: that trace of the Cornell box, its hitting rays only where `q` reads them.
    pub fn study_shown(
        &self,
        trace: u32,
        q: voxcast_core::rays::study::Question,
    ) -> Option<std::sync::Arc<super::raydata::Shown>> {
        self.on_show.clone().filter(|s| {
            let f = &s.computed.facts;
            f.source.starts_with("builtin:cornell")
                && f.trace == Some(trace)
                && q.density_filter()
                    .is_none_or(|f| s.computed.density.params.filter == f)
        })
    }

    /// Keeps an answer, with the study's run where one is under way.
    fn keep(&mut self, mut a: Answer) {
        a.run = self.study.map(|r| r.words().to_string());
        self.progress.answers.push(a);
    }

    fn save(&mut self) {
        if let Err(e) = self.store.save(&self.progress) {
            self.message = Some(format!("progress not saved: {e}"));
        }
    }
}

/// Where the levels' progress is kept.
#[derive(Clone, Debug, PartialEq)]
pub enum ProgressStore {
    /// Not kept (tests).
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    Nowhere,
    /// A JSON file, written atomically (the desktop).
    File(PathBuf),
    /// The browser's local storage of the page's origin, under this key.
    #[cfg(target_arch = "wasm32")]
    Browser(&'static str),
}

impl ProgressStore {
    /// The player's own: `$XDG_CONFIG_HOME/voxcast/progress.json` (else `~/.config/…`;
    /// `VOXCAST_CONFIG_DIR` overrides the folder), or in a browser its local storage.
    pub fn players() -> Self {
        #[cfg(target_arch = "wasm32")]
        return Self::Browser("voxcast-progress");
        #[cfg(not(target_arch = "wasm32"))]
        voxcast_core::level::players_progress_path().map_or(Self::Nowhere, Self::File)
    }

    /// The progress kept here: a fresh start where there is none, and with a message where
    /// what is kept is damaged or cannot be read.
    pub fn load(&self) -> (Progress, Option<String>) {
        match self {
            Self::Nowhere => (Progress::default(), None),
            Self::File(path) => Progress::load(path),
            #[cfg(target_arch = "wasm32")]
            Self::Browser(key) => match super::web::stored(key) {
                None => (Progress::default(), None),
                Some(text) => Progress::from_text(
                    &text,
                    &format!("The progress kept in this browser (\"{key}\")"),
                ),
            },
        }
    }

    /// Keeps `progress` here.
    pub fn save(&self, progress: &Progress) -> Result<(), String> {
        match self {
            Self::Nowhere => Ok(()),
            Self::File(path) => progress.save(path).map_err(|e| e.to_string()),
            #[cfg(target_arch = "wasm32")]
            Self::Browser(key) => super::web::store(key, &progress.to_text()),
        }
    }
}

/// The logic, without the window: commands, scene set-up and the objective check.
pub(crate) fn plugin(app: &mut App) {
    app.add_message::<LevelCommand>().add_systems(
        Update,
        (
            apply_commands,
            set_up_scene,
            level_preset_after_load.after(crate::sandbox::loading::finish_loading),
            check_objective.after(crate::sandbox::breakdown::follow_selection),
        )
            .chain()
            .in_set(crate::sandbox::Frame::Rules),
    );
}

/// Carries out the window's commands: the next mode and its stage, progress.
fn apply_commands(
    mut commands: MessageReader<LevelCommand>,
    mut lessons: ResMut<Lessons>,
    mode: Res<State<Mode>>,
    (mut next, mut stage, free): (ResMut<NextState<Mode>>, ResMut<Stage>, Res<FreePlay>),
) {
    for command in commands.read() {
        match *command {
            LevelCommand::Start(i) | LevelCommand::Study(i) => {
                let Some(level) = lessons.levels.get(i) else {
                    continue;
                };
                *stage = Stage::of(&level.scene);
                let title = level.title.clone();
                lessons.step = 0;
                lessons.met = false;
                lessons.met_for = None;
                lessons.study =
                    matches!(command, LevelCommand::Study(_)).then_some(StudyRun::PreviewOff);
                lessons.message = lessons.study.map(|r| study_words(r, &title));
                // Set up afresh even when this level is already the mode.
                lessons.set_up_again = *mode.get() == Mode::Level(i);
                next.set(Mode::Level(i));
            }
            LevelCommand::Next => {
                let Mode::Level(l) = *mode.get() else {
                    continue;
                };
                if !lessons.met || lessons.step >= lessons.levels[l].steps.len() {
                    continue;
                }
                lessons.record(l);
                lessons.met = false;
                lessons.met_for = None;
                lessons.step += 1;
                if lessons.step == lessons.levels[l].steps.len() {
                    let title = lessons.levels[l].title.clone();
                    match lessons.study.and_then(StudyRun::next) {
                        // The study's next run: the same level from its first step.
                        Some(run) => {
                            lessons.study = Some(run);
                            lessons.step = 0;
                            lessons.set_up_again = true;
                            lessons.message = Some(study_words(run, &title));
                        }
                        None => {
                            lessons.message = Some(if lessons.study.take().is_some() {
                                format!(
                                    "“{title}” studied: both runs' answers are kept (Export \
                                     answers)"
                                )
                            } else {
                                format!("“{title}” done!")
                            });
                            *stage = free.0;
                            next.set(Mode::FreePlay);
                        }
                    }
                }
            }
            LevelCommand::FreePlay => {
                lessons.study = None;
                *stage = free.0;
                next.set(Mode::FreePlay);
            }
        }
        lessons.prediction.clear();
        lessons.named_effect = None;
        lessons.studied = None;
    }
}

/// A study to start once the window runs (`--study`).
#[derive(Resource)]
pub struct StartStudy(pub Option<usize>);

/// Starts the study `--study` asked for, on the first frame.
pub fn start_study(mut start: ResMut<StartStudy>, mut commands: MessageWriter<LevelCommand>) {
    if let Some(i) = start.0.take() {
        commands.write(LevelCommand::Study(i));
    }
}

/// The index of the level `name` names: its id, or its number in the list (from 1).
pub fn level_named(name: &str) -> Result<usize, String> {
    let levels = Level::all();
    let by_number = name
        .parse::<usize>()
        .ok()
        .filter(|&n| (1..=levels.len()).contains(&n))
        .map(|n| n - 1);
    by_number
        .or_else(|| levels.iter().position(|l| l.id == name))
        .ok_or_else(|| {
            let ids: Vec<&str> = levels.iter().map(|l| l.id.as_str()).collect();
            format!(
                "--study {name}: no such level; give a number from 1 to {} or one of: {}",
                levels.len(),
                ids.join(", ")
            )
        })
}

/// What the player reads as a study's run begins.
fn study_words(run: StudyRun, title: &str) -> String {
    format!(
        "Study of “{title}”, run {} of 2: the preview is {} for this run{}",
        run.number(),
        if run.preview() { "on" } else { "off" },
        if run.preview() {
            "; the same steps again"
        } else {
            "; then the same level again with it on. Where a step asks you to look at the \
             volume, press Render image at the top of the settings: the exact picture, drawn \
             by the CPU"
        }
    )
}

/// Sets up the scene of the mode just entered (or of a study's next run): the preview on or
/// off, and a level's volume with its default settings (so no objective is met before the
/// player acts). The virtual camera and the light marker are spawned by their own plugins from
/// the [`Stage`]. A study's run holds the preview on or off whatever the player does.
fn set_up_scene(
    mode: Res<State<Mode>>,
    mut lessons: ResMut<Lessons>,
    stage: Res<Stage>,
    (volume, mut render): (Res<VolumeState>, ResMut<RenderState>),
    (mut loading, mut preview): (ResMut<Loading>, ResMut<PreviewSettings>),
    (ray_choices, inspect): (
        Option<ResMut<super::raydata::RayChoices>>,
        Option<ResMut<super::inspect::InspectSettings>>,
    ),
) {
    if let Some(run) = lessons.study
        && preview.enabled != run.preview()
    {
        preview.enabled = run.preview();
    }
    let again = std::mem::take(&mut lessons.set_up_again);
    if !mode.is_changed() && !again {
        return;
    }
    preview.enabled = lessons.study.map_or(stage.preview, StudyRun::preview);
    let Mode::Level(l) = *mode.get() else { return };
    // The Ray data section starts afresh too (no ray mesh left over from another level).
    if let Some(mut c) = ray_choices {
        *c = default();
    }
    // So do the skip blocks a level may have turned on.
    if let Some(mut i) = inspect
        && i.show_blocks
    {
        i.show_blocks = false;
    }
    let Some(level) = lessons.levels.get(l) else {
        return;
    };
    if let Some(scale) = level.scene.preview_scale {
        preview.scale = scale;
    }
    // The preview shows the picture: a cost view a level before asked for is not this one's.
    preview.cost_view = None;
    if level.scene.volume != volume.source {
        // The load brings the volume's defaults with it.
        loading.start(level.scene.volume.clone());
    } else {
        loading.cancel();
        reset_to_defaults(&volume.volume, &mut render);
        apply_level_preset(&level.scene, &mut render);
    }
}

/// The level's own preset over its volume's defaults, where its scene names one, and the
/// lecture's ray's settings where it shoots that ray.
fn apply_level_preset(scene: &voxcast_core::level::LevelScene, render: &mut RenderState) {
    if let Some(p) = scene
        .preset
        .as_deref()
        .and_then(voxcast_core::preset::by_name)
    {
        render.transfer = p.transfer.clone();
        if let Ok(s) = p.settings_over(&render.settings) {
            render.settings = s;
        }
    }
    if scene.lecture_ray {
        render.settings = voxcast_core::worked::lecture_ray_settings(&render.settings);
    }
}

/// A level's volume that has just loaded (with its defaults): the level's preset over them.
fn level_preset_after_load(
    mode: Res<State<Mode>>,
    lessons: Res<Lessons>,
    volume: Res<VolumeState>,
    mut render: ResMut<RenderState>,
) {
    if !volume.is_changed() || volume.is_added() {
        return;
    }
    let Mode::Level(l) = *mode.get() else { return };
    if let Some(level) = lessons.levels.get(l)
        && level.scene.volume == volume.source
    {
        apply_level_preset(&level.scene, &mut render);
    }
}

/// The ray data the objectives read (absent in tests without the Ray data plugins).
type RayState<'w> = (
    Option<Res<'w, super::raydata::RayScene>>,
    Option<Res<'w, super::raydata::RayChoices>>,
    Option<Res<'w, super::rayviews::ViewReport>>,
);

/// Checks the current step's objective against what the player has done.
#[allow(clippy::too_many_arguments)]
pub(crate) fn check_objective(
    mode: Res<State<Mode>>,
    mut lessons: ResMut<Lessons>,
    (render, volume): (Res<RenderState>, Res<VolumeState>),
    cameras: Query<&VirtualCamera>,
    (selection, breakdown): (Res<RaySelection>, Res<BreakdownState>),
    (comparison, views): (Res<Comparison>, Query<&View, With<MainCamera>>),
    (mut trade, preview, inspect): (
        ResMut<StepTrade>,
        Option<Res<PreviewSettings>>,
        Option<Res<super::inspect::InspectSettings>>,
    ),
    (rays, ray_choices, ray_report): RayState,
) {
    let step = lessons.step_in(*mode.get()).cloned();
    // A step about the step's trade measures the step, whatever knob was picked before.
    if step
        .as_ref()
        .is_some_and(|s| s.objective == Objective::TradeMeasured)
        && trade.knob != voxcast_core::knob::Knob::Step
        && trade.progress().is_none()
    {
        trade.knob = voxcast_core::knob::Knob::Step;
    }
    let spot = step.as_ref().and_then(|s| s.control);
    // A prediction step's answer: the reconstruction at its point, or the worked composite.
    let (detail, composite) = match step.as_ref().map(|s| &s.objective) {
        Some(Objective::PredictValue { point, .. }) => (
            Some(detail_at(
                &volume.volume,
                Vec3::from_array(*point),
                Interpolation::Trilinear,
            )),
            None,
        ),
        Some(Objective::PredictComposite { points, .. }) => (
            None,
            Some(voxcast_core::worked::back_to_front(
                &volume.volume,
                &render.transfer,
                points,
            )),
        ),
        _ => (None, None),
    };
    let met = step.is_some_and(|step| {
        let mut sit = situation(
            &render,
            &volume,
            cameras.single().ok(),
            &selection,
            &breakdown,
            (&comparison, views.single().ok()),
            (&trade, preview.as_deref(), inspect.as_deref()),
        );
        let truth = prediction_truth(detail.as_ref(), composite.as_deref());
        if let (Some(truth), Ok(typed)) = (truth, parse_typed(&lessons.prediction)) {
            sit.prediction = Some((typed, truth));
        }
        let shown = rays.as_ref().and_then(|r| r.on_show(&volume));
        sit.ray_density = shown.map(|s| s.computed.facts.clone());
        if shown.is_some() {
            let drawn = ray_report.as_ref().is_some_and(|r| r.drawn);
            let view = ray_choices
                .as_ref()
                .map(|c| c.view.clone())
                .unwrap_or_default();
            sit.ray_views = [
                ("volume", sit.preview_on),
                ("mesh", view.mesh && drawn),
                ("field", view.field && drawn),
            ]
            .into_iter()
            .filter_map(|(name, on)| on.then_some(name))
            .collect();
        }
        sit.named_effect = lessons.named_effect;
        sit.studied = lessons.studied.clone();
        step.objective.met(&sit)
    });
    lessons.on_show = rays.as_ref().and_then(|r| r.on_show(&volume)).cloned();
    let here = Some((*mode.get(), lessons.step));
    let met = met || (lessons.met_for == here && lessons.met);
    if met {
        lessons.met_for = here;
    }
    (lessons.met, lessons.spot) = (met, spot);
    (lessons.detail, lessons.composite) = (detail, composite);
}

/// The code's answer to study question `q` from the density on show (see
/// [`Lessons::study_shown`]).
pub fn study_truth(
    shown: &super::raydata::Shown,
    q: voxcast_core::rays::study::Question,
) -> Option<String> {
    let c = &shown.computed;
    q.answer(&c.data.scene, &c.set, Some(&c.density))
}

/// What a prediction step's answer should be: the reconstructed value at its point, or the
/// red of the worked composite after its last point.
fn prediction_truth(
    detail: Option<&SampleDetail>,
    composite: Option<&[voxcast_core::worked::WorkedPoint]>,
) -> Option<f32> {
    detail
        .map(|d| d.value)
        .or_else(|| composite?.last().map(|r| r.after[0]))
}

/// A number as a player types it: spaces around it and a decimal comma allowed.
pub fn parse_typed(typed: &str) -> Result<f32, std::num::ParseFloatError> {
    typed.trim().replace(',', ".").parse::<f32>()
}

/// What the player has done, as the objectives see it.
pub(super) fn situation(
    render: &RenderState,
    volume: &VolumeState,
    vc: Option<&VirtualCamera>,
    selection: &RaySelection,
    breakdown: &BreakdownState,
    (comparison, view): (&Comparison, Option<&View>),
    (trade, preview, inspect): (
        &StepTrade,
        Option<&PreviewSettings>,
        Option<&super::inspect::InspectSettings>,
    ),
) -> Situation {
    let voxel = volume.volume.spacing().min_element();
    let (lo, hi) = volume.volume.bounds();
    let compared_max = comparison
        .result
        .as_ref()
        .filter(|r| r.snapshot.is_current(view, render, volume))
        .and_then(|r| r.diff.as_ref().map(|(d, _)| d.max_abs * 255.0));
    let measured = trade.current(view, render, volume).map(|t| t.knob);
    let lights = &render.settings.phong.lights;
    let light_inside_volume = lights.iter().any(|l| {
        matches!(l.light,
            voxcast_core::shade::Light::Point(p) if p.cmpge(lo).all() && p.cmple(hi).all())
    });
    let opened_sample_lights = breakdown
        .opened
        .and_then(|i| breakdown.trace.as_ref()?.samples.get(i)?.shading)
        .filter(|t| t.lit)
        .map(|t| t.light_count);
    Situation {
        method: Some(render.settings.method),
        step_voxels: render.settings.step.voxels(voxel),
        virtual_pixels_across: vc.map_or(0, |v| v.width),
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
        regions: match &render.settings.classification {
            voxcast_core::classify::Classification::ValueGradient { regions } => regions.clone(),
            _ => Vec::new(),
        },
        transfer: Some(render.transfer.clone()),
        compared_max,
        light_inside_volume,
        prediction: None,
        back_to_front: render.settings.order == voxcast_core::composite::Order::BackToFront,
        light_kinds: lights.iter().map(|l| l.light.kind_label()).collect(),
        spot_ambient: lights
            .iter()
            .any(|l| matches!(l.light, voxcast_core::shade::Light::Spot(_)) && l.ambient > 0.0),
        emission: render.settings.phong.ke,
        ka: render.settings.phong.ka,
        depth_cue: render.settings.phong.depth_cue,
        light_colors: lights.iter().map(|l| l.color.to_array()).collect(),
        attenuated: lights.iter().any(|l| l.attenuated()),
        levoy_highlight: render.settings.phong.highlight == voxcast_core::shade::Highlight::Levoy,
        opened_sample_lights,
        // The sampling levels measure the step's trade.
        trade_measured: measured == Some(voxcast_core::knob::Knob::Step),
        measured_knob: measured.map(|k| k.name()),
        preview_on: preview.is_some_and(|p| p.enabled),
        preview_scale: preview.map_or(1.0, |p| p.scale),
        preview_cost_view: preview.and_then(|p| p.cost_view).map(|v| v.name()),
        skip_blocks_shown: inspect.is_some_and(|i| i.show_blocks),
        jitter: render.settings.jitter,
        trilinear: render.settings.interpolation == voxcast_core::sample::Interpolation::Trilinear,
        supersampling: render.settings.supersampling,
        clip: render.settings.clip.clone(),
        skipping: render.settings.skipping,
        cost_view: comparison
            .result
            .as_ref()
            .filter(|r| r.snapshot.is_current(view, render, volume))
            .and(comparison.cost_view)
            .map(|v| v.name()),
        ray_cut: breakdown
            .trace
            .as_ref()
            .is_some_and(|t| t.cut_words().is_some()),
        // Filled in by the caller, which sees the ray data.
        ray_density: None,
        ray_views: Vec::new(),
        named_effect: None,
        studied: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sandbox::inspect::{Inspection, SampleSphere};
    use crate::sandbox::light::LightMarker;
    use bevy::tasks::{AsyncComputeTaskPool, TaskPool};
    use bevy::window::FileDragAndDrop;
    use voxcast_core::composite::Method;

    /// The sandbox's level logic and spawners without a window or a GPU.
    fn app(progress: PathBuf) -> App {
        AsyncComputeTaskPool::get_or_init(TaskPool::new);
        let (volume, render) = crate::sandbox::inspect::tests::scene("bucky");
        let mut app = App::new();
        app.add_plugins((MinimalPlugins, bevy::state::app::StatesPlugin))
            .insert_resource(volume)
            .insert_resource(render)
            .init_resource::<Assets<Mesh>>()
            .init_resource::<Assets<StandardMaterial>>()
            .add_message::<FileDragAndDrop>()
            .init_resource::<PreviewSettings>()
            .init_resource::<BreakdownState>()
            .init_resource::<Comparison>()
            .insert_resource(Lessons::new(ProgressStore::File(progress)))
            .add_plugins((
                crate::sandbox::mode::plugin,
                crate::sandbox::loading::plugin,
                crate::sandbox::inspect::plugin,
                crate::sandbox::light::marker_plugin,
                crate::sandbox::trade::plugin,
                plugin,
            ))
            .add_systems(Update, crate::sandbox::virtual_camera::stage_camera);
        app
    }

    /// Runs frames until `done` holds (a level's volume loads on the task pool).
    fn until(app: &mut App, done: impl Fn(&mut App) -> bool) {
        for _ in 0..500 {
            app.update();
            if done(app) {
                return;
            }
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
        panic!("not reached");
    }

    fn entities<C: Component>(app: &mut App) -> Vec<Entity> {
        let mut q = app.world_mut().query_filtered::<Entity, With<C>>();
        q.iter(app.world()).collect()
    }

    fn mode(app: &App) -> Mode {
        *app.world().resource::<State<Mode>>().get()
    }

    fn level(app: &App, id: &str) -> usize {
        let lessons = app.world().resource::<Lessons>();
        lessons.levels.iter().position(|l| l.id == id).unwrap()
    }

    fn send(app: &mut App, c: LevelCommand) {
        app.world_mut().write_message(c);
        app.update();
        app.update();
    }

    /// A prediction done and an effect named are kept as answers, with what the code
    /// computes, saved with the progress and exported as CSV.
    #[test]
    fn answers_are_kept_with_the_progress() {
        let dir = std::env::temp_dir().join(format!("voxcast-answers-{}", std::process::id()));
        let path = dir.join("progress.json");
        let mut app = app(path.clone());
        let trilinear = level(&app, "trilinear");
        send(&mut app, LevelCommand::Start(trilinear));
        until(&mut app, |a| {
            a.world().resource::<VolumeState>().source == "builtin:voxel"
        });
        send(&mut app, LevelCommand::Next); // step 1 is read
        app.world_mut().resource_mut::<Lessons>().prediction = "4,99".into();
        until(&mut app, |a| a.world().resource::<Lessons>().met);
        send(&mut app, LevelCommand::Next);
        let lessons = app.world().resource::<Lessons>();
        let [a] = &lessons.progress.answers[..] else {
            panic!("{:?}", lessons.progress.answers)
        };
        assert_eq!((a.level.as_str(), a.step), ("trilinear", 2));
        assert_eq!(a.question, "the value at (0.5, 0.5, 0.5)");
        assert_eq!(
            (a.answer.as_str(), a.expected.as_str(), a.correct),
            ("4,99", "4.988", true)
        );
        // Naming an effect: a wrong choice and the right one, both kept.
        let mut lessons = app.world_mut().resource_mut::<Lessons>();
        lessons.name_effect(trilinear, 2, 1);
        lessons.name_effect(trilinear, 1, 1);
        let kept = &lessons.progress.answers;
        assert_eq!(kept.len(), 3);
        assert!(!kept[1].correct && kept[2].correct);
        assert_eq!(kept[1].answer, "reflection rays");
        assert_eq!(kept[1].expected, "primary rays");
        let (saved, _) = Progress::load(&path);
        assert_eq!(&saved.answers, kept);
        let csv = saved.answers_csv();
        assert_eq!(csv.lines().count(), 4, "{csv}");
        let first = csv.lines().nth(1).unwrap();
        let quoted = "trilinear,2,\"the value at (0.5, 0.5, 0.5)\",\"4,99\",4.988,yes,";
        assert!(first.starts_with(quoted), "{csv}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A study plays the level twice: the preview held off in the first run (whatever the
    /// player turns on), on in the second, from the first step again; each answer is kept
    /// with its run's name; after the second run, free play. `--study` names a level by id or
    /// number.
    #[test]
    fn a_study_plays_the_level_with_the_preview_off_then_on() {
        use voxcast_core::classify::{Classification, Region};
        let dir = std::env::temp_dir().join(format!("voxcast-study-{}", std::process::id()));
        let mut app = app(dir.join("progress.json"));
        let l = level(&app, "value-gradient");
        assert_eq!(level_named("value-gradient"), Ok(l));
        assert_eq!(level_named(&(l + 1).to_string()), Ok(l));
        assert!(level_named("nope").unwrap_err().contains("value-gradient"));
        send(&mut app, LevelCommand::Study(l));
        until(&mut app, |a| {
            a.world().resource::<VolumeState>().source == "builtin:head"
        });
        let preview = |app: &App| app.world().resource::<PreviewSettings>().enabled;
        let play_through = |app: &mut App| {
            send(app, LevelCommand::Next); // read
            app.world_mut()
                .resource_mut::<RenderState>()
                .settings
                .classification = Classification::ValueGradient { regions: vec![] };
            until(app, |a| a.world().resource::<Lessons>().met);
            send(app, LevelCommand::Next);
            app.world_mut()
                .resource_mut::<RenderState>()
                .settings
                .classification = Classification::ValueGradient {
                regions: vec![Region {
                    value: [100.0, 120.0],
                    gradient: [0.0, 30.0],
                    opacity: 0.6,
                }],
            };
            until(app, |a| a.world().resource::<Lessons>().met);
            app.world_mut()
                .resource_mut::<Lessons>()
                .name_effect(l, 1, 1);
            send(app, LevelCommand::Next);
        };
        assert!(!preview(&app));
        app.world_mut().resource_mut::<PreviewSettings>().enabled = true;
        app.update();
        assert!(!preview(&app), "held off in the first run");
        play_through(&mut app);
        let lessons = app.world().resource::<Lessons>();
        assert_eq!(lessons.study, Some(StudyRun::PreviewOn));
        assert_eq!((mode(&app), lessons.step), (Mode::Level(l), 0));
        assert!(lessons.message.as_deref().unwrap().contains("run 2 of 2"));
        assert!(preview(&app), "on in the second");
        play_through(&mut app);
        let lessons = app.world().resource::<Lessons>();
        assert_eq!(mode(&app), Mode::FreePlay);
        assert_eq!(lessons.study, None);
        assert!(lessons.message.as_deref().unwrap().contains("both runs"));
        let runs: Vec<Option<&str>> = lessons
            .progress
            .answers
            .iter()
            .map(|a| a.run.as_deref())
            .collect();
        assert_eq!(runs, [Some("preview off"), Some("preview on")]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A study question answered wrong, then right: both kept, and only the right one meets
    /// the step.
    #[test]
    fn study_answers_are_kept_and_only_the_right_one_counts() {
        let mut lessons = Lessons::new(ProgressStore::Nowhere);
        let l = lessons
            .levels
            .iter()
            .position(|l| l.id == "which-effect")
            .unwrap();
        let camera = voxcast_core::rays::study::CameraPlace::FrontHigher.words();
        lessons.answer_study(l, (1, "camera"), "inside the box", camera);
        assert_eq!(lessons.studied, None);
        lessons.answer_study(l, (1, "camera"), camera, camera);
        assert_eq!(lessons.studied, Some((1, "camera".to_string())));
        let kept: Vec<(bool, &str)> = lessons
            .progress
            .answers
            .iter()
            .map(|a| (a.correct, a.question.as_str()))
            .collect();
        let q = "where was the camera of trace 1";
        assert_eq!(kept, [(false, q), (true, q)]);
        let objective = Objective::StudyQuestion {
            trace: 1,
            question: "camera".into(),
        };
        let sit = Situation {
            studied: lessons.studied.clone(),
            ..Situation::default()
        };
        assert!(objective.met(&sit));
    }

    /// Levels are states: starting one spawns only what its scene holds, and what free play
    /// spawned (virtual camera, body, sample spheres, light marker) leaves; Next is refused
    /// until the objective is met by the state a control edits; the last Next records the
    /// progress on disk and returns to free play, which spawns its own scene again.
    #[test]
    fn a_level_spawns_its_scene_and_everything_leaves_with_it() {
        let dir = std::env::temp_dir().join(format!("voxcast-levels-{}", std::process::id()));
        let path = dir.join("progress.json");
        let mut app = app(path.clone());
        until(&mut app, |a| !entities::<SampleSphere>(a).is_empty());
        assert_eq!(mode(&app), Mode::FreePlay);
        let free: Vec<Entity> = [
            entities::<VirtualCamera>(&mut app),
            entities::<LightMarker>(&mut app),
            entities::<SampleSphere>(&mut app),
        ]
        .concat();
        assert_eq!(entities::<VirtualCamera>(&mut app).len(), 1);
        assert_eq!(
            entities::<LightMarker>(&mut app).len(),
            voxcast_core::shade::MAX_LIGHTS
        );

        // The trilinear level: the 2³ voxel, one ray, no preview, no light marker.
        let trilinear = level(&app, "trilinear");
        send(&mut app, LevelCommand::Start(trilinear));
        until(&mut app, |a| {
            a.world().resource::<VolumeState>().source == "builtin:voxel"
                && !entities::<SampleSphere>(a).is_empty()
        });
        assert_eq!(mode(&app), Mode::Level(trilinear));
        for e in &free {
            assert!(
                app.world().get_entity(*e).is_err(),
                "{e} left with free play"
            );
        }
        let vcs = entities::<VirtualCamera>(&mut app);
        assert_eq!(vcs.len(), 1);
        let vc = *app.world().get::<VirtualCamera>(vcs[0]).unwrap();
        assert_eq!((vc.width, vc.height), (1, 1));
        // It shoots the lecture's ray under the level's settings: one sample on each of P3,
        // P2 and P1 and, composited back to front, the lecture's colour (0.540, 0.397, 0.375)
        // and opacity 0.813.
        assert_eq!(vc.view, voxcast_core::worked::lecture_ray());
        let mut render = app.world().resource::<RenderState>().clone();
        render.settings.order = voxcast_core::composite::Order::BackToFront;
        let volume = app.world().resource::<VolumeState>().volume.clone();
        let ray = vc.view.ray(0.5, 0.5, 1, 1);
        let scene =
            voxcast_core::trace::Scene::new(&volume, &render.transfer, &render.settings, ray.dir)
                .unwrap();
        let traced = voxcast_core::trace::trace_ray(&scene, &ray, [0, 0]);
        // Back to front visits them from the far end: P1, P2, P3.
        let at: Vec<Vec3> = traced
            .samples
            .iter()
            .map(|s| Vec3::from(s.p_voxel))
            .collect();
        let lecture = voxcast_core::worked::LECTURE_POINTS.map(Vec3::from_array);
        assert_eq!(at.len(), 3, "{at:?}");
        assert!(at.iter().zip(lecture).all(|(a, p)| a.distance(p) < 1e-5));
        let got = [
            traced.color[0],
            traced.color[1],
            traced.color[2],
            traced.opacity,
        ];
        for (g, quoted) in got.iter().zip([0.540, 0.397, 0.375, 0.813]) {
            assert!((g - quoted).abs() < 2e-3, "{got:?}");
        }
        assert!(entities::<LightMarker>(&mut app).is_empty());
        assert!(!app.world().resource::<PreviewSettings>().enabled);
        assert_eq!(app.world().resource::<Inspection>().size, UVec2::ONE);
        // Its panel: only the sections it names.
        let lessons = app.world().resource::<Lessons>();
        assert_eq!(
            lessons.panel_in(mode(&app)),
            Some(&[voxcast_core::level::Section::RayCasting][..])
        );

        // The methods level: no virtual camera at all, so nothing is inspected.
        let methods = level(&app, "methods");
        send(&mut app, LevelCommand::Start(methods));
        until(&mut app, |a| {
            a.world().resource::<VolumeState>().source == "builtin:brainsmall"
        });
        app.update();
        assert!(entities::<VirtualCamera>(&mut app).is_empty());
        assert!(entities::<SampleSphere>(&mut app).is_empty());
        // Its own preset, over the volume's defaults: every method it teaches shows.
        assert_eq!(
            app.world().resource::<RenderState>().transfer.name,
            "brainsmall-projections"
        );
        assert_eq!(app.world().resource::<Inspection>().size, UVec2::ZERO);
        assert!(app.world().resource::<PreviewSettings>().enabled);
        // Its steps: Next is refused until the method is chosen, as the panel's menu does.
        let steps = app.world().resource::<Lessons>().levels[methods]
            .steps
            .clone();
        let mut last = Method::Accumulate;
        for (k, step) in steps.iter().enumerate() {
            let method = match step.objective {
                Objective::Read => {
                    send(&mut app, LevelCommand::Next);
                    assert_eq!(app.world().resource::<Lessons>().step, k + 1, "read on");
                    continue;
                }
                Objective::Method { method } => method,
                _ => panic!("the methods level asks for methods"),
            };
            last = method;
            assert!(
                !app.world().resource::<Lessons>().met,
                "step {k} met at once"
            );
            send(&mut app, LevelCommand::Next);
            assert_eq!(app.world().resource::<Lessons>().step, k, "Next refused");
            app.world_mut()
                .resource_mut::<RenderState>()
                .settings
                .method = method;
            app.update();
            assert!(app.world().resource::<Lessons>().met);
            send(&mut app, LevelCommand::Next);
        }
        // Done: back in free play, with its scene, and the progress saved.
        assert_eq!(mode(&app), Mode::FreePlay);
        assert_eq!(app.world().resource::<RenderState>().settings.method, last);
        until(&mut app, |a| !entities::<SampleSphere>(a).is_empty());
        assert_eq!(entities::<VirtualCamera>(&mut app).len(), 1);
        assert_eq!(
            entities::<LightMarker>(&mut app).len(),
            voxcast_core::shade::MAX_LIGHTS
        );
        assert_eq!(
            app.world().resource::<Lessons>().panel_in(mode(&app)),
            None,
            "free play shows all"
        );
        let saved = Progress::load(&path).0;
        assert_eq!(saved.completed["methods"], steps.len());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// "At least 8 pixels across" reads the image's width: 12×4 meets it, 4×12 does not; once
    /// met, the step stays met.
    #[test]
    fn pixels_across_is_the_image_width() {
        let dir = std::env::temp_dir().join(format!("voxcast-across-{}", std::process::id()));
        let mut app = app(dir.join("progress.json"));
        app.update();
        let rays = level(&app, "rays");
        send(&mut app, LevelCommand::Start(rays));
        let k = app.world().resource::<Lessons>().levels[rays]
            .steps
            .iter()
            .position(|s| matches!(s.objective, Objective::VirtualPixelsAtLeast { pixels: 8 }))
            .expect("the rays level asks for 8 pixels across");
        app.world_mut().resource_mut::<Lessons>().step = k;
        until(&mut app, |a| !entities::<VirtualCamera>(a).is_empty());
        // 4×12 is not 8 across; 12×4 is; shrinking it again does not take the step back.
        for ((w, h), met) in [((4, 12), false), ((12, 4), true), ((4, 4), true)] {
            let vc = entities::<VirtualCamera>(&mut app)[0];
            let mut cam = app.world_mut().get_mut::<VirtualCamera>(vc).unwrap();
            (cam.width, cam.height) = (w, h);
            app.update();
            assert_eq!(app.world().resource::<Lessons>().met, met, "{w}×{h}");
        }
        assert!(!dir.exists(), "nothing saved before a step is done");
    }

    /// A step about the step's trade picks the step knob, whatever was picked before.
    #[test]
    fn a_step_trade_step_measures_the_step() {
        let dir = std::env::temp_dir().join(format!("voxcast-knob-{}", std::process::id()));
        let mut app = app(dir.join("progress.json"));
        app.update();
        app.world_mut().resource_mut::<StepTrade>().knob = voxcast_core::knob::Knob::Cutoff;
        let sampling = level(&app, "sampling");
        send(&mut app, LevelCommand::Start(sampling));
        let k = app.world().resource::<Lessons>().levels[sampling]
            .steps
            .iter()
            .position(|s| s.objective == Objective::TradeMeasured)
            .expect("the sampling level measures the step's trade");
        app.world_mut().resource_mut::<Lessons>().step = k;
        app.update();
        assert_eq!(
            app.world().resource::<StepTrade>().knob,
            voxcast_core::knob::Knob::Step
        );
    }

    /// Entering a level resets the settings to its volume's defaults, so a choice made in free
    /// play does not meet its objectives before the player acts.
    #[test]
    fn a_level_starts_from_its_volumes_defaults() {
        let dir = std::env::temp_dir().join(format!("voxcast-reset-{}", std::process::id()));
        let mut app = app(dir.join("progress.json"));
        app.update();
        app.world_mut()
            .resource_mut::<RenderState>()
            .settings
            .method = Method::Maximum;
        // The rays level shows the volume already loaded: reset at once.
        let rays = level(&app, "rays");
        assert_eq!(
            app.world().resource::<Lessons>().levels[rays].scene.volume,
            "builtin:bucky"
        );
        send(&mut app, LevelCommand::Start(rays));
        let s = &app.world().resource::<RenderState>().settings;
        assert_eq!(s.method, Method::Accumulate);
        // Another volume: its load brings its defaults.
        app.world_mut()
            .resource_mut::<RenderState>()
            .settings
            .method = Method::Maximum;
        let sampling = level(&app, "sampling");
        send(&mut app, LevelCommand::Start(sampling));
        until(&mut app, |a| {
            a.world().resource::<VolumeState>().source == "builtin:blobs"
        });
        let s = &app.world().resource::<RenderState>().settings;
        assert_eq!(s.method, Method::Accumulate);
        assert!(!dir.exists(), "nothing saved before a step is done");
    }
}
