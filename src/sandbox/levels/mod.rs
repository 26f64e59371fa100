//! Guided levels, the logic: the levels and the player's progress, the commands the Levels
//! window sends (start a level, Next, free play), the scene each mode sets up, and the check of
//! the current step's objective — the core's `Objective::met` against what the player did.
//! The mode itself is the [`Mode`] state; what a level spawned leaves with it. Progress is saved
//! after every step, to the config directory (atomically) or, in a browser, to its local
//! storage; a damaged file or entry starts afresh with a message.

pub mod editor;
pub mod files;
mod objective;
mod scene;
mod store;
pub(crate) use objective::check_objective;
use objective::prediction_truth;
pub use objective::{parse_typed, study_truth};
use scene::{Pending, open_scene, set_up_scene};
pub use store::ProgressStore;

use crate::sandbox::checks::compare::Comparison;
use crate::sandbox::checks::trade::StepTrade;
use crate::sandbox::data::loading::{Loading, reset_to_defaults};
use crate::sandbox::inspect::breakdown::BreakdownState;
use crate::sandbox::inspect::rays::RaySelection;
use crate::sandbox::inspect::virtual_camera::VirtualCamera;
use crate::sandbox::shared::mode::{FreePlay, Mode, Stage};
use crate::sandbox::shared::quality::PreviewSettings;
use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeState};
use bevy::prelude::*;
use std::path::PathBuf;
use voxcast_core::level::{
    Answer, Control, Level, Objective, Progress, Section, Situation, Step, StudyRun, now_seconds,
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
    /// What the player is typing as a prediction (judged only when submitted).
    pub prediction: String,
    /// The last prediction submitted in this step (Check, or Enter in the field): what the
    /// objective judges and the hint speaks of.
    pub tried: Option<f32>,
    /// When the current step opened, in seconds since 1970 (each answer keeps how long after
    /// it was given).
    opened_at: f64,
    /// The effect (trace id) the player named.
    pub named_effect: Option<u32>,
    /// Whether the current step's objective is met (checked every frame; once met it stays
    /// met until the step changes, so closing a window or undoing a change never takes a
    /// finished step back).
    pub met: bool,
    /// The mode and step `met` was last found true for.
    met_for: Option<(Mode, usize)>,
    /// The situation the current step opened in (its scene set up), with its mode and step:
    /// what the objectives that ask for a change compare against.
    at_open: Option<((Mode, usize), Situation)>,
    /// The control the current step is about (framed in the panel).
    pub spot: Option<Control>,
    /// For a prediction step: the core's reconstruction at the step's point.
    pub detail: Option<SampleDetail>,
    /// For a composite prediction step: the worked composite, point by point.
    pub composite: Option<Vec<voxcast_core::worked::WorkedPoint>>,
    /// For a step that asks about the selected ray: the code's answer for the ray selected
    /// now (`None` until one is).
    pub ray_answer: Option<voxcast_core::level::RayAnswer>,
    /// The study question answered right in this step: its trace and key.
    pub studied: Option<(u32, String)>,
    /// The ray density on show (what a study question is asked about).
    pub on_show: Option<std::sync::Arc<crate::sandbox::data::source::Shown>>,
    /// The run of the study under way (the level played twice, preview off then on).
    pub study: Option<StudyRun>,
    /// The levels list's choice: a level clicked starts as a study.
    pub study_next: bool,
    /// The scene is set up again on the next frame (a study's second run, same mode).
    set_up_again: bool,
    /// The level's or the step's scene waiting to be put on screen (its data set loading).
    pending: Option<Pending>,
    /// What the player has done, as the objectives see it, this frame (in every mode).
    pub now: Situation,
}

/// What the panels hide while a prediction is open: the values at these points (voxel
/// coordinates; and what follows from them: a sample's colour and opacity), and with
/// `composite` the ray's running colour and opacity.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Hidden {
    pub points: Vec<[f32; 3]>,
    pub composite: bool,
    /// The selected ray's sample count (and its sample table, whose rows would count them).
    pub samples: bool,
    /// The number of cells the selected ray crosses (and the cells drawn).
    pub cells: bool,
}

impl Hidden {
    /// Whether the ray's formula and export go too (they would show what is asked: a
    /// sample's value, the composite or the count); the cells' number alone leaves them.
    pub fn hides_working(&self) -> bool {
        !self.points.is_empty() || self.composite || self.samples
    }

    /// Whether the sample at `p_voxel` is one whose value is asked for.
    pub fn hides_sample(&self, p_voxel: [f32; 3]) -> bool {
        self.points
            .iter()
            .any(|q| (0..3).all(|a| (q[a] - p_voxel[a]).abs() <= 1e-3))
    }
}

/// What the Levels panel asks for (a scripted run sends the same).
#[derive(Message, Clone, Copy, Debug, PartialEq, Eq)]
pub enum LevelCommand {
    /// Start level `i` at its first step.
    Start(usize),
    /// Start level `i` at step `k` (from 0): the editor's Play.
    StartAt(usize, usize),
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
            at_open: None,
            levels: Level::all(),
            step: 0,
            progress,
            store,
            message,
            prediction: String::new(),
            tried: None,
            opened_at: now_seconds(),
            named_effect: None,
            met: false,
            spot: None,
            detail: None,
            composite: None,
            ray_answer: None,
            studied: None,
            on_show: None,
            study: None,
            study_next: false,
            set_up_again: false,
            pending: None,
            now: Situation::default(),
        }
    }

    /// Puts `level` in the levels list — in place of a level of its id that is not built in,
    /// else after the others — and returns its index.
    pub fn keep_level(&mut self, level: Level) -> usize {
        let same =
            |l: &Level| l.id == level.id && l.origin != voxcast_core::level::Origin::Embedded;
        match self.levels.iter().position(same) {
            Some(i) => {
                self.levels[i] = level;
                i
            }
            None => {
                self.levels.push(level);
                self.levels.len() - 1
            }
        }
    }

    /// With the levels a teacher `added` after the built-in ones (and what the sandbox says of
    /// those left out).
    pub fn with_added(mut self, added: Option<Added>) -> Self {
        if let Some(added) = added {
            self.levels.extend(added.levels);
            if added.message.is_some() {
                self.message = added.message;
            }
        }
        self
    }

    /// The step being played in `mode`.
    pub fn step_in(&self, mode: Mode) -> Option<&Step> {
        match mode {
            Mode::Level(l) => self.levels.get(l)?.steps.get(self.step),
            Mode::FreePlay => None,
        }
    }

    /// Whether the current level's (or step's) scene is on screen: nothing waits to be
    /// opened.
    pub fn scene_ready(&self) -> bool {
        self.pending.is_none()
    }

    /// The situation the current step opened in (`None`: its scene is not ready yet).
    pub fn opened(&self) -> Option<&Situation> {
        self.at_open.as_ref().map(|(_, s)| s)
    }

    /// The ray clicks counted when the current step opened (`None`: its scene is not ready).
    pub fn clicks_at_open(&self) -> Option<u32> {
        self.opened().map(|s| s.ray_clicks)
    }

    /// The panel sections `mode` shows (`None`: all, as in free play).
    pub fn panel_in(&self, mode: Mode) -> Option<&[Section]> {
        match mode {
            Mode::Level(l) => self.levels.get(l)?.scene.panel.as_deref(),
            Mode::FreePlay => None,
        }
    }

    /// Records the current step of level `l` as done, and saves (its answers were kept as
    /// they were given).
    fn record(&mut self, l: usize) {
        let id = self.levels[l].id.clone();
        self.progress.record(&id, self.step + 1);
        self.save();
    }

    /// What the panels hide in `mode`: the answers of a prediction step until it is done (and
    /// the cells' number until the step that asks for it is).
    pub fn hidden(&self, mode: Mode) -> Option<Hidden> {
        let Mode::Level(l) = mode else {
            return None;
        };
        let steps = &self.levels.get(l)?.steps;
        let mut hidden = Hidden::default();
        // The cells a ray crosses do not change with the settings: a level that asks for them
        // hides their number from its first step on, not only while it asks.
        let open = self.step + usize::from(self.met);
        hidden.cells = steps.iter().skip(open).any(|s| {
            s.objective
                .parts()
                .iter()
                .any(|o| matches!(o, Objective::PredictCells))
        });
        let step = steps.get(self.step).filter(|_| !self.met);
        for o in step.map(|s| s.objective.parts()).unwrap_or_default() {
            match o {
                Objective::PredictValue { point, .. } => hidden.points.push(*point),
                Objective::PredictComposite { .. } => hidden.composite = true,
                Objective::PredictSamples => hidden.samples = true,
                _ => {}
            }
        }
        (hidden != Hidden::default()).then_some(hidden)
    }

    /// How many answers the current step of level `l` has kept so far (in this run).
    pub fn tries_here(&self, l: usize) -> usize {
        let run = self.study.map(|r| r.words().to_string());
        self.progress
            .answers
            .iter()
            .filter(|a| a.level == self.levels[l].id && a.step == self.step + 1 && a.run == run)
            .count()
    }

    /// Submits the typed prediction of the current step of level `l`: judged against the
    /// code's answer and kept as a try, right or wrong, with its time; a text that is no
    /// number is refused with a hint and kept as nothing. Returns whether it was right.
    pub fn submit_prediction(&mut self, l: usize) -> Option<bool> {
        let typed = self.prediction.trim().to_string();
        let value = match parse_typed(&typed) {
            Ok(v) if v.is_finite() => v,
            _ => {
                self.message = Some(format!(
                    "“{typed}” is not a number: type one, like 4.75 (a decimal comma works too)"
                ));
                return None;
            }
        };
        let truth = prediction_truth(
            self.detail.as_ref(),
            self.composite.as_deref(),
            self.ray_answer.as_ref(),
        )?;
        let tolerance = self.levels[l]
            .steps
            .get(self.step)?
            .objective
            .parts()
            .into_iter()
            .find_map(Objective::tolerance)?;
        let question = self.levels[l].steps[self.step]
            .objective
            .parts()
            .into_iter()
            .find_map(|o| match o {
                Objective::PredictValue { point, .. } => Some(format!(
                    "the value at ({}, {}, {})",
                    point[0], point[1], point[2]
                )),
                Objective::PredictComposite { .. } => {
                    Some("the red of C after the last point".to_string())
                }
                _ => None,
            })
            .or_else(|| self.ray_answer.as_ref().map(|r| r.question.clone()))?;
        let correct = (value - truth).abs() <= tolerance;
        let a = Answer::now(
            &self.levels[l].id,
            self.step + 1,
            question,
            (typed, voxcast_core::numbers::sig(truth), correct),
        );
        self.keep(a);
        self.tried = Some(value);
        self.message = None;
        self.save();
        Some(correct)
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
    ) -> Option<std::sync::Arc<crate::sandbox::data::source::Shown>> {
        self.on_show.clone().filter(|s| {
            let f = &s.computed.facts;
            f.source.starts_with("builtin:cornell")
                && f.trace == Some(trace)
                && q.density_filter()
                    .is_none_or(|f| s.computed.density.params.filter == f)
        })
    }

    /// Keeps an answer, with the study's run where one is under way, which try of its
    /// question it is, and how long after the step opened it came.
    fn keep(&mut self, mut a: Answer) {
        a.run = self.study.map(|r| r.words().to_string());
        let earlier = self
            .progress
            .answers
            .iter()
            .filter(|b| b.level == a.level && b.step == a.step && b.run == a.run)
            .count();
        a.attempt = Some(earlier as u32 + 1);
        a.seconds = Some(((now_seconds() - self.opened_at).max(0.0) * 10.0).round() / 10.0);
        self.progress.answers.push(a);
    }

    fn save(&mut self) {
        if let Err(e) = self.store.save(&self.progress) {
            self.message = Some(format!("progress not saved: {e}"));
        }
    }
}

/// The logic, without the window: commands, scene set-up and the objective check.
pub(crate) fn plugin(app: &mut App) {
    app.add_plugins(editor::plugin);
    app.init_resource::<files::LevelFiles>()
        .init_resource::<files::OpenLink>();
    app.add_message::<LevelCommand>().add_systems(
        Update,
        (
            (
                (files::take_dropped, files::open_link),
                files::receive_files,
                apply_commands,
                set_up_scene,
                open_scene,
            )
                .chain()
                .in_set(crate::sandbox::shared::schedule::Frame::Rules),
            check_objective.in_set(crate::sandbox::shared::schedule::Frame::Check),
        ),
    );
}

/// Carries out the window's commands: the next mode and its stage, progress.
fn apply_commands(
    mut commands: MessageReader<LevelCommand>,
    mut lessons: ResMut<Lessons>,
    mode: Res<State<Mode>>,
    mut next: ResMut<NextState<Mode>>,
    mut stage: ResMut<Stage>,
    free: Res<FreePlay>,
) {
    for command in commands.read() {
        match *command {
            LevelCommand::Start(i) | LevelCommand::Study(i) | LevelCommand::StartAt(i, _) => {
                let Some(level) = lessons.levels.get(i) else {
                    continue;
                };
                *stage = Stage::of(&level.scene);
                let title = level.title.clone();
                let first = match *command {
                    LevelCommand::StartAt(_, k) => k.min(level.steps.len().saturating_sub(1)),
                    _ => 0,
                };
                lessons.step = first;
                lessons.met = false;
                lessons.met_for = None;
                lessons.at_open = None;
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
                lessons.at_open = None;
                lessons.step += 1;
                lessons.pending = lessons.levels[l]
                    .steps
                    .get(lessons.step)
                    .and_then(|s| s.scene.as_ref())
                    .map(Pending::of_step);
                if lessons.step == lessons.levels[l].steps.len() && lessons.finish_level(l) {
                    *stage = free.0;
                    next.set(Mode::FreePlay);
                }
            }
            LevelCommand::FreePlay => {
                lessons.study = None;
                *stage = free.0;
                next.set(Mode::FreePlay);
            }
        }
        lessons.prediction.clear();
        lessons.tried = None;
        lessons.opened_at = now_seconds();
        lessons.named_effect = None;
        lessons.studied = None;
    }
}

impl Lessons {
    /// Level `l`'s last step is met: a study's next run starts (the same level from its first
    /// step), or the level is done and said so; `true` where play goes back to free play.
    fn finish_level(&mut self, l: usize) -> bool {
        let title = self.levels[l].title.clone();
        if let Some(run) = self.study.and_then(StudyRun::next) {
            self.study = Some(run);
            self.step = 0;
            self.set_up_again = true;
            self.message = Some(study_words(run, &title));
            return false;
        }
        self.message = Some(if self.study.take().is_some() {
            format!("“{title}” studied: both runs' answers are kept (Export answers)")
        } else {
            format!("“{title}” done!")
        });
        true
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

/// Levels a teacher added (`--levels PATH`): those that read, and what the sandbox says of the
/// rest.
pub struct Added {
    pub levels: Vec<Level>,
    pub message: Option<String>,
}

/// The levels in the file or folder at `path`, read as `voxcast levels check` reads them; each
/// file's problems printed on the terminal, and a line for the levels panel.
#[cfg(not(target_arch = "wasm32"))]
pub fn added_from_path(path: &std::path::Path) -> Added {
    use voxcast_core::level::check;
    let found = match voxcast_core::level::files_at(path) {
        Ok(found) => found,
        Err(e) => {
            eprintln!("error: --levels {e}");
            return Added {
                levels: Vec::new(),
                message: Some(format!("No levels added: {e}")),
            };
        }
    };
    let mut texts = Vec::new();
    let mut left_out = 0;
    for (origin, text) in found {
        match text {
            Ok(text) => texts.push((origin, text)),
            Err(e) => {
                eprintln!("error: {}: {e}", origin.words());
                left_out += 1;
            }
        }
    }
    let mut levels = Vec::new();
    for (origin, checked) in check::read_all(&texts, &check::OnDisk) {
        for p in &checked.problems {
            eprintln!("{}: {p}", origin.words());
        }
        match checked.level {
            Some(level) => levels.push(level),
            None => left_out += 1,
        }
    }
    let added = levels.len();
    let message = (left_out > 0).then(|| {
        format!(
            "{added} level{} added from {}; {left_out} file{} left out for errors (voxcast              levels check {} says what they are)",
            if added == 1 { "" } else { "s" },
            path.display(),
            if left_out == 1 { "" } else { "s" },
            path.display()
        )
    });
    Added { levels, message }
}

/// In a browser the page's loader fetches `?levels=URL` itself and hands the files over
/// (`web/voxcast.js`), as it hands over files a student opens: nothing to read here.
#[cfg(target_arch = "wasm32")]
pub fn added_from_path(_: &std::path::Path) -> Added {
    Added {
        levels: Vec::new(),
        message: None,
    }
}

/// The index of the level `name` names among `levels`: its id, or its number in the list
/// (from 1).
pub fn level_named(levels: &[Level], name: &str) -> Result<usize, String> {
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

#[cfg(test)]
mod tests;
