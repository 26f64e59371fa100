//! The Levels panel (docked at the top): the start screen's list of levels with progress and Free Play, or the
//! current step — its text, the control it is about, a prediction field where the step asks for
//! one, and Next, open once the objective is met. It only sends [`LevelCommand`]s; the logic is
//! in `levels`.

use crate::sandbox::levels::editor::EditorCommand;
use crate::sandbox::levels::{Lessons, LevelCommand};
use crate::sandbox::shared::mode::Mode;
use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};
use voxcast_core::level::{Control, Objective};
use voxcast_core::numbers::sig;
use voxcast_core::sample::SampleDetail;
use voxcast_core::tunables as t;

/// Where a step's control is, in the words of the panel: its section's title and, for a
/// tunable, the tunable's label, both as the panel draws them (tested in `tests.rs`).
pub(super) fn control_name(c: Control) -> String {
    let label = match c {
        Control::Method => "Method",
        Control::Step => t::STEP.label,
        Control::VirtualPixels => "pixels across and down",
        Control::PixelGrid => return "the Rays panel's image".into(),
        Control::Breakdown => return "the ray's breakdown panel".into(),
        Control::OpacityCorrection => t::OPACITY_CORRECTION.label,
        Control::EarlyTermination => t::EARLY_TERMINATION.label,
        Control::Target => t::TARGET.label,
        Control::SumRange => t::SUM_RANGE.label,
        Control::Shading => t::SHADING.label,
        Control::Classification => "Classification",
        Control::TransferFunction => "the editor",
        Control::RenderImage => return "the Render image… button".into(),
        Control::Light => "the lights",
        Control::Order => "Order",
        Control::StepTrade => "Measure",
        Control::Jitter => t::JITTER.label,
        Control::Interpolation => "Trilinear interpolation",
        Control::Supersampling => t::SUPERSAMPLING.label,
        Control::CropBox => t::CROP.label,
        Control::ClipPlane => t::CLIP_PLANE.label,
        Control::Skipping => t::SKIPPING.label,
        Control::PreviewScale => t::PREVIEW_SCALE.label,
        Control::PreviewOn => "Show the preview",
        Control::PreviewView => "Show the preview as",
        Control::RaySource => "Rays and Compute",
        Control::RayViews => "the views",
    };
    match c.section() {
        Some(s) => format!("Settings › {} › {label}", super::title(s)),
        None => label.into(),
    }
}

pub(super) fn levels_window(
    mut contexts: EguiContexts,
    mut lessons: ResMut<Lessons>,
    mode: Res<State<Mode>>,
    mut commands: MessageWriter<LevelCommand>,
    mut editor: MessageWriter<crate::sandbox::levels::editor::EditorCommand>,
    mut dock: ResMut<super::Dock>,
    mut layout: ResMut<super::layout::Layout>,
) -> Result {
    let ctx = contexts.ctx_mut()?.clone();
    let mut command = None;
    let mut edit = None;
    // Folded to a line where the window is low, unless the student unfolded it (or folded it).
    let mut folded = layout
        .level_text
        .map_or(layout.shares.fold_level_text, |open| !open);
    let was = folded;
    // Docked at the top: nothing covers the step's text, and Next is always in view.
    dock.show(&ctx, "levels", |dock_ui| {
        egui::Panel::top("levels")
            .resizable(false)
            .show(dock_ui, |ui| {
                command = levels_ui(ui, &mut lessons, *mode.get(), &mut folded, &mut edit)
            });
    });
    if folded != was {
        layout.level_text = Some(!folded);
    }
    if let Some(c) = command {
        commands.write(c);
    }
    if let Some(e) = edit {
        editor.write(e);
    }
    Ok(())
}

/// The window's contents, `folded` to a line (the list in a menu, the step's text to its first
/// line) or whole, with a toggle between; returns what the player asked for, and puts in
/// `edit` what the level editor is asked to do.
pub(super) fn levels_ui(
    ui: &mut egui::Ui,
    lessons: &mut Lessons,
    mode: Mode,
    folded: &mut bool,
    edit: &mut Option<EditorCommand>,
) -> Option<LevelCommand> {
    if let Some(m) = &lessons.message {
        ui.colored_label(egui::Color32::YELLOW, m);
    }
    match mode {
        Mode::FreePlay => level_list(ui, lessons, folded, edit),
        Mode::Level(l) => level_step(ui, lessons, l, folded, edit),
    }
}

/// The button that opens the level editor: on a new level from the view on screen (free
/// play), or on the level being played.
fn editor_button(ui: &mut egui::Ui, edit: &mut Option<EditorCommand>, command: EditorCommand) {
    let (label, tip) = match command {
        EditorCommand::NewFromView => (
            "New level from this view…",
            "Write a level of your own: it starts from the scene on screen (data set, settings, \
             transfer function, cameras), and each step you add keeps the view you set up",
        ),
        _ => (
            "Edit this level…",
            "Open this level in the level editor: change its words, steps and objectives, save \
             it as a file of your own or share it as a link",
        ),
    };
    if super::target(ui.small_button(label), "level editor")
        .on_hover_text(tip)
        .clicked()
    {
        *edit = Some(command);
    }
}

/// The button that folds the panel's text to a line or shows it whole.
fn fold_toggle(ui: &mut egui::Ui, folded: &mut bool) {
    let (label, tip) = if *folded {
        ("more", "Show all of it")
    } else {
        ("less", "Fold it to one line, for more of the scene")
    };
    if super::target(ui.small_button(label), "fold")
        .on_hover_text(tip)
        .clicked()
    {
        *folded = !*folded;
    }
}

fn level_list(
    ui: &mut egui::Ui,
    lessons: &mut Lessons,
    folded: &mut bool,
    edit: &mut Option<EditorCommand>,
) -> Option<LevelCommand> {
    let mut chosen = None;
    if *folded {
        ui.horizontal(|ui| {
            ui.label("Levels: one concept each (you are in free play).");
            let menu = ui.menu_button("Choose a level", |ui| {
                study_choice(ui, lessons);
                chosen = level_buttons(ui, lessons);
            });
            super::target(menu.response, "levels menu");
            fold_toggle(ui, folded);
        });
        return chosen;
    }
    ui.horizontal(|ui| {
        ui.label(
            "Levels: one concept each (free play, everything on, is where you are now). \
             Choose one to start:",
        );
        study_choice(ui, lessons);
        fold_toggle(ui, folded);
    });
    ui.horizontal_wrapped(|ui| {
        chosen = level_buttons(ui, lessons);
    });
    ui.horizontal_wrapped(|ui| {
        export_answers(ui, lessons);
        editor_button(ui, edit, EditorCommand::NewFromView);
        teachers_files(ui);
    });
    chosen
}

/// A teacher's files on the page, which cannot read paths: level files to add, a class's
/// answer files for a report. (On the desktop: `--levels`, `voxcast answers --class`, or a drop
/// on the window.)
fn teachers_files(ui: &mut egui::Ui) {
    use crate::sandbox::shared::files::{PICKS_FILES, Purpose, pick};
    if !PICKS_FILES {
        return;
    }
    let open = ui.button("Open levels…").on_hover_text(
        "Add level files to the list: choose each level (.json) together with the data sets \
         and transfer functions it names (a folder of them can be dropped on the page)",
    );
    if super::target(open, "open levels").clicked() {
        pick(Purpose::Levels);
    }
    let report = ui.button("Class report…").on_hover_text(
        "Choose your students' answer files (CSV, as Export answers writes them): one report \
         per level and step — right at the first try, tries, time, the commonest wrong answers \
         — downloaded as class_report.html",
    );
    if super::target(report, "class report").clicked() {
        pick(Purpose::Answers);
    }
}

/// Whether a level chosen starts as a study.
fn study_choice(ui: &mut egui::Ui, lessons: &mut Lessons) {
    let check = ui.checkbox(&mut lessons.study_next, "as a study");
    super::target(check, "study").on_hover_text(
        "Play the level you choose twice: first with the live preview off, then again with it \
         on, as the educational ray caster's user study did. Each run's answers are kept with \
         the run's name (Export answers).",
    );
}

/// The answers given so far, as a CSV file for a teacher (a download in a browser).
fn export_answers(ui: &mut egui::Ui, lessons: &mut Lessons) {
    let count = lessons.progress.answers.len();
    let button = ui
        .add_enabled(count > 0, egui::Button::new("Export answers (CSV)"))
        .on_hover_text(
            "Every prediction and named effect so far, with the level, the step, what the code \
             computes, whether it was right and when: a file to hand to your teacher",
        )
        .on_disabled_hover_text("No answers yet: the prediction steps keep them");
    if super::target(button, "export answers").clicked() {
        let path = std::env::current_dir()
            .unwrap_or_default()
            .join(ANSWERS_FILE);
        let path = path.as_path();
        let csv = lessons.progress.answers_csv();
        lessons.message = Some(
            match crate::sandbox::shared::files::save(path, csv.as_bytes(), "text/csv") {
                Ok(done) => format!(
                    "{count} answer{}: {done}",
                    if count == 1 { "" } else { "s" }
                ),
                Err(e) => format!("answers not saved: {e}"),
            },
        );
    }
}

/// The answers' file: in the folder the sandbox was started from, or a download.
const ANSWERS_FILE: &str = "voxcast_answers.csv";

fn level_buttons(ui: &mut egui::Ui, lessons: &Lessons) -> Option<LevelCommand> {
    let mut chosen = None;
    for (i, level) in lessons.levels.iter().enumerate() {
        let added = level.origin != voxcast_core::level::Origin::Embedded;
        if added
            && lessons.levels[..i]
                .iter()
                .all(|l| l.origin == voxcast_core::level::Origin::Embedded)
        {
            ui.label(egui::RichText::new("Added:").strong())
                .on_hover_text(
                    "Levels given to the sandbox from files (--levels, or opened on the page)",
                );
        }
        let done = lessons
            .progress
            .completed
            .get(&level.id)
            .copied()
            .unwrap_or(0);
        let total = level.steps.len();
        let mark = if done >= total { "●" } else { " " };
        let button = ui.button(format!("{mark} {}. {}", i + 1, level.title));
        if super::target(button, &format!("level {}", i + 1))
            .on_hover_text(format!(
                "{} ({} of {} steps done){}",
                level.concept,
                done.min(total),
                total,
                if added {
                    format!(" · from {}", level.origin.words())
                } else {
                    String::new()
                }
            ))
            .clicked()
        {
            chosen = Some(if lessons.study_next {
                LevelCommand::Study(i)
            } else {
                LevelCommand::Start(i)
            });
        }
    }
    chosen
}

/// The level's current step: its heading and text, what to look at, the question it asks
/// (with the answer once met), and the row of buttons.
fn level_step(
    ui: &mut egui::Ui,
    lessons: &mut Lessons,
    l: usize,
    folded: &mut bool,
    edit: &mut Option<EditorCommand>,
) -> Option<LevelCommand> {
    let step = lessons.step_in(Mode::Level(l))?.clone();
    step_heading(ui, lessons, l, &step, folded);
    let look_at = step
        .control
        .map(|c| format!("Look at: {}, framed in yellow", control_name(c)));
    if !*folded && let Some(look_at) = &look_at {
        ui.colored_label(egui::Color32::LIGHT_BLUE, look_at);
    }
    step_questions(ui, lessons, l, &step);
    // One row: the buttons, whether the step is done and, folded, where to look.
    let (met, reading) = (lessons.met, step.objective == Objective::Read);
    let mut command = None;
    ui.horizontal_wrapped(|ui| {
        if super::target(ui.add_enabled(met, egui::Button::new("Next")), "next").clicked() {
            command = Some(LevelCommand::Next);
        }
        if super::target(ui.button("Free play"), "free play").clicked() {
            command = Some(LevelCommand::FreePlay);
        }
        if !reading {
            ui.label(if met { "● done" } else { "… not yet" });
        }
        if *folded && let Some(look_at) = &look_at {
            ui.colored_label(egui::Color32::LIGHT_BLUE, look_at);
        }
        if !*folded {
            editor_button(ui, edit, EditorCommand::Edit(l));
        }
    });
    command
}

/// The level's title, the step's number and its text: on one line each when folded, with
/// the level's concept when not.
fn step_heading(
    ui: &mut egui::Ui,
    lessons: &Lessons,
    l: usize,
    step: &voxcast_core::level::Step,
    folded: &mut bool,
) {
    let level = &lessons.levels[l];
    let text = egui::RichText::new(&step.text).size(15.0);
    let number = format!("· step {} of {}", lessons.step + 1, level.steps.len());
    if *folded {
        ui.horizontal(|ui| {
            ui.strong(&level.title);
            ui.label(number);
            fold_toggle(ui, folded);
        });
        ui.add(egui::Label::new(text).truncate());
    } else {
        ui.horizontal_wrapped(|ui| {
            ui.strong(&level.title);
            ui.label(egui::RichText::new(&level.concept).italics());
            ui.label(number);
            fold_toggle(ui, folded);
        });
        ui.label(text);
    }
}

/// What the step asks the student to predict or name, each with its field or buttons, a
/// hint after a wrong try, and the worked answer once met.
fn step_questions(
    ui: &mut egui::Ui,
    lessons: &mut Lessons,
    l: usize,
    step: &voxcast_core::level::Step,
) {
    let met = lessons.met;
    if let Some(d) = lessons.detail.clone() {
        prediction_field(ui, lessons, l, "your value:", met);
        if !met && let Some(hint) = lessons.tried.and_then(|v| prediction_hint(v, &d)) {
            ui.colored_label(egui::Color32::YELLOW, hint);
        }
        if met {
            interpolation_table(ui, &d);
        }
    }
    if let Some(rows) = lessons.composite.clone() {
        prediction_field(ui, lessons, l, "your red component:", met);
        if !met && let Some(hint) = lessons.tried.and_then(|v| composite_hint(v, &rows)) {
            ui.colored_label(egui::Color32::YELLOW, hint);
        }
        if met {
            composite_table(ui, &rows);
        }
    }
    if let Some(asked) = ray_question(&step.objective) {
        match lessons.ray_answer.clone() {
            None => {
                ui.colored_label(
                    egui::Color32::YELLOW,
                    "Select a ray first: click a pixel of the virtual camera's image in the Rays \
                     panel. Its numbers appear in the breakdown.",
                );
            }
            Some(answer) => {
                prediction_field(ui, lessons, l, "your number:", met);
                if !met && let Some(tried) = lessons.tried {
                    ui.colored_label(egui::Color32::YELLOW, ray_hint(tried, answer.truth, asked));
                }
                if met {
                    ui.label(&answer.working);
                }
            }
        }
    }
    if let Objective::NameEffect { trace } = step.objective {
        name_effect(ui, lessons, (l, trace), met);
    }
    if let Objective::StudyQuestion { trace, question } = &step.objective {
        study_question(ui, lessons, l, *trace, question, met);
    }
}

/// The answers to "which effect cast these rays?": one button per effect, and what a wrong
/// choice should have shown.
fn name_effect(ui: &mut egui::Ui, lessons: &mut Lessons, (l, trace): (usize, u32), met: bool) {
    use voxcast_core::rays::effects::Effect;
    ui.horizontal_wrapped(|ui| {
        for e in Effect::KINDS {
            let chosen = lessons.named_effect == Some(e.id());
            if ui.selectable_label(chosen, e.kind()).clicked() && !met && !chosen {
                lessons.name_effect(l, e.id(), trace);
            }
        }
    });
    let hint = match lessons.named_effect.and_then(Effect::of) {
        Some(e) if !Effect::same_kind(e.id(), trace) => Some(match e {
            Effect::Primary | Effect::SecondPrimary => {
                "Not these: primary rays all start at one point, the camera's eye, outside the \
                 box's open front."
            }
            Effect::Shadow => {
                "Not these: shadow rays to a distant light are all parallel — look at the arrows."
            }
            Effect::Reflection => {
                "Not these: reflection rays leave every visible point, in the mirror direction."
            }
            Effect::AmbientOcclusion => {
                "Not these: ambient-occlusion rays are short and stay near the surfaces."
            }
        }),
        _ => None,
    };
    if let Some(h) = hint {
        ui.colored_label(egui::Color32::YELLOW, h);
    }
}

/// A study question's options, once the trace it asks about is on show; the answer is checked
/// against what the code finds in that trace.
fn study_question(
    ui: &mut egui::Ui,
    lessons: &mut Lessons,
    l: usize,
    trace: u32,
    key: &str,
    met: bool,
) {
    use voxcast_core::rays::set::Filter;
    use voxcast_core::rays::study::Question;
    let Some(q) = Question::parse(key) else {
        return;
    };
    let Some(shown) = lessons.study_shown(trace, q) else {
        ui.colored_label(
            egui::Color32::YELLOW,
            format!(
                "In Ray data, choose trace {trace} of the Cornell box{} and Compute first.",
                match q.density_filter() {
                    Some(Filter::Hit) => ", set the filter to the rays that hit,",
                    Some(Filter::Miss) => ", set the filter to the rays that miss,",
                    _ => "",
                }
            ),
        );
        return;
    };
    let mut chosen = None;
    ui.horizontal_wrapped(|ui| {
        for option in q.options(&shown.computed.data.scene) {
            if ui.selectable_label(false, &option).clicked() && !met {
                chosen = Some(option);
            }
        }
    });
    // The code's answer, worked out when the player answers (not every frame).
    if let Some(c) = chosen
        && let Some(t) = crate::sandbox::levels::study_truth(&shown, q)
    {
        lessons.answer_study(l, (trace, key), &c, &t);
        if c != t {
            lessons.message = Some(format!("Not {c}: look again at where the rays run."));
        }
    }
}

/// The field a prediction is typed into, and Check: Enter in the field or the button submits
/// it (judged and kept as a try); nothing is judged while it is typed.
fn prediction_field(ui: &mut egui::Ui, lessons: &mut Lessons, l: usize, label: &str, met: bool) {
    ui.horizontal(|ui| {
        ui.label(label);
        let field = ui.add_enabled(!met, egui::TextEdit::singleline(&mut lessons.prediction));
        let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
        let typed = !lessons.prediction.trim().is_empty();
        let check = ui
            .add_enabled(typed && !met, egui::Button::new("Check"))
            .on_hover_text(
                "Judge this answer (Enter does the same). Every try is kept with its time for \
                 your teacher, and the first one counts: work it out before you check.",
            )
            .on_disabled_hover_text(if met {
                "Done: your answer was right"
            } else {
                "Type a number first"
            });
        if (super::target(check, "check").clicked() || entered && typed) && !met {
            lessons.submit_prediction(l);
        }
        let tries = lessons.tries_here(l);
        if tries > 0 {
            ui.label(format!(
                "{tries} tr{} so far",
                if tries == 1 { "y" } else { "ies" }
            ));
        }
    });
}

/// The question a step asks about the selected ray, if it asks one.
fn ray_question(objective: &Objective) -> Option<&Objective> {
    objective.parts().into_iter().find(|o| o.asks_about_ray())
}

/// For a submitted number about the selected ray that is not right: too high or too low, and
/// how the number comes about (without giving it).
pub(super) fn ray_hint(tried: f32, truth: f32, asked: &Objective) -> String {
    let how = match asked {
        Objective::PredictSamples => {
            "The first sample sits where the ray enters, then one every step while t stays at \
             or before where it leaves: how many whole steps fit in t_exit − t_enter, plus one \
             for the first."
        }
        Objective::PredictCells => {
            "The ray starts in the cell that holds its entry point; each whole x, y or z \
             coordinate it passes on the way to its exit point takes it into the next cell."
        }
        _ => "Divide the ray's length in the volume, t_exit − t_enter, by the count.",
    };
    format!(
        "Not yet: your try, {}, is {}. {how}",
        sig(tried),
        side(tried, truth)
    )
}

/// A submitted prediction judged against `truth`: too high or too low (`None`: right).
fn side(tried: f32, truth: f32) -> &'static str {
    if tried > truth { "too high" } else { "too low" }
}

/// For a submitted prediction that is not right: too high or too low, and how to get there.
pub(super) fn prediction_hint(tried: f32, d: &SampleDetail) -> Option<String> {
    let [fx, fy, fz] = d.frac;
    Some(format!(
        "Not yet: your try, {}, is {}. The point sits at ({}, {}, {}) inside its cell; each \
         corner's weight is the product, per axis, of that fraction (towards the corner) or 1 \
         minus it, and the value is the sum of weight × value over the 8 corners.",
        sig(tried),
        side(tried, d.value),
        sig(fx),
        sig(fy),
        sig(fz)
    ))
}

/// For a submitted composite that is not right: too high or too low, the values the points
/// hold (the earlier steps' answers) and the formula to apply in turn.
pub(super) fn composite_hint(
    tried: f32,
    rows: &[voxcast_core::worked::WorkedPoint],
) -> Option<String> {
    let truth = rows.last()?.after[0];
    let values: Vec<String> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| format!("P{} = {}", i + 1, sig(r.value)))
        .collect();
    Some(format!(
        "Not yet: your try, {}, is {}. The points hold {}; read each one's colour and opacity \
         off the ramp, then from C = 0 apply C_out = C_in·(1 − α) + c·α for P1, P2 and P3 in \
         turn (red only).",
        sig(tried),
        side(tried, truth),
        values.join(", ")
    ))
}

/// The worked interpolation: each corner (the lecture's name beside the core's), its value,
/// its weight and its share, in the lecture's order f1 … f8, and the value they make.
fn interpolation_table(ui: &mut egui::Ui, d: &voxcast_core::sample::SampleDetail) {
    egui::Grid::new("prediction").striped(true).show(ui, |ui| {
        super::header_row(ui, &["corner", "value", "weight", "weight × value"]);
        let mut order: Vec<usize> = (0..8).collect();
        order.sort_by_key(|&i| voxcast_core::worked::lecture_corner(i));
        for i in order {
            let c = d.corners[i];
            ui.label(format!(
                "f{} ({}, {}, {})",
                voxcast_core::worked::lecture_corner(i),
                c[0],
                c[1],
                c[2]
            ));
            ui.label(sig(d.values[i]));
            ui.label(sig(d.weights[i]));
            ui.label(sig(d.values[i] * d.weights[i]));
            ui.end_row();
        }
    });
    ui.label(format!("value = {}", sig(d.value)));
}

/// The worked composite, point by point: value, colour and opacity looked up, and the ray's
/// colour and opacity after it.
fn composite_table(ui: &mut egui::Ui, rows: &[voxcast_core::worked::WorkedPoint]) {
    egui::Grid::new("composite").striped(true).show(ui, |ui| {
        super::header_row(
            ui,
            &[
                "point",
                "value",
                "colour c",
                "opacity α",
                "C after",
                "O after",
            ],
        );
        for (i, r) in rows.iter().enumerate() {
            let [x, y, z] = r.point;
            ui.label(format!("P{} ({x}, {y}, {z})", i + 1));
            ui.label(sig(r.value));
            ui.label(voxcast_core::numbers::sig3([
                r.rgba[0], r.rgba[1], r.rgba[2],
            ]));
            ui.label(sig(r.rgba[3]));
            ui.label(voxcast_core::numbers::sig3([
                r.after[0], r.after[1], r.after[2],
            ]));
            ui.label(sig(r.after[3]));
            ui.end_row();
        }
    });
}

// egui keeps its debug options (used to find buttons by their label) only in debug builds, so
// these tests run where they can: `cargo test`, not `cargo test --release`.
#[cfg(all(test, debug_assertions))]
mod tests;
