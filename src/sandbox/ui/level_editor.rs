//! The level editor's window: a draft level's words, its steps (each with the view it opens
//! on, its text, the control it frames and its objective, judged live against what is on
//! screen), and Save, Copy link and Play. Structural changes go to the editor's logic as
//! [`EditorCommand`]s (`levels/editor.rs`); the words are edited here, in the draft itself.

use crate::sandbox::levels::Lessons;
use crate::sandbox::levels::editor::{Draft, EditorCommand};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, egui};
use voxcast_core::level::{Control, Objective, Section};

/// What the window keeps between frames: the selected step's objective as the teacher types
/// it, and whether it reads.
#[derive(Resource, Default)]
pub(super) struct EditorText {
    /// The step whose objective `objective` holds, and the draft it came from.
    for_step: Option<(usize, String)>,
    objective: String,
    error: Option<String>,
    /// Where a link is made for (the page's address; on the page, the page itself).
    page: String,
}

/// The page a desktop's link opens (`VOXCAST_PAGE_URL`, else the README's local address).
#[cfg(not(target_arch = "wasm32"))]
fn default_page() -> String {
    std::env::var("VOXCAST_PAGE_URL").unwrap_or_else(|_| "http://127.0.0.1:8000/".into())
}

pub(super) fn editor_window(
    mut contexts: EguiContexts,
    mut draft: ResMut<Draft>,
    lessons: Res<Lessons>,
    mut text: ResMut<EditorText>,
    mut commands: MessageWriter<EditorCommand>,
) -> Result {
    if !draft.open || draft.level.is_none() {
        return Ok(());
    }
    let ctx = contexts.ctx_mut()?.clone();
    let mut open = true;
    let mut sent = Vec::new();
    egui::Window::new("Level editor")
        .open(&mut open)
        .default_width(430.0)
        .default_height(560.0)
        .vscroll(true)
        .show(&ctx, |ui| {
            sent = editor_ui(ui, &mut draft, &lessons, &mut text);
        });
    if !open {
        draft.open = false;
    }
    for c in sent {
        commands.write(c);
    }
    Ok(())
}

/// The editor's contents; returns the commands its buttons sent.
pub(super) fn editor_ui(
    ui: &mut egui::Ui,
    draft: &mut Draft,
    lessons: &Lessons,
    text: &mut EditorText,
) -> Vec<EditorCommand> {
    let mut sent = Vec::new();
    if text.page.is_empty() {
        #[cfg(target_arch = "wasm32")]
        {
            text.page = crate::sandbox::shared::web::page_address();
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            text.page = default_page();
        }
    }
    let met_now = draft.met_now(&lessons.now);
    let selected = draft.step;
    let Some(level) = draft.level.as_mut() else {
        return sent;
    };
    level_words(ui, level);
    ui.separator();
    step_list(ui, level, selected, &mut sent);
    if let Some(step) = level.steps.get_mut(selected) {
        ui.separator();
        ui.strong(format!("Step {}", selected + 1));
        step_editor(ui, step, selected, &mut sent);
        objective_editor(ui, &mut step.objective, selected, &level.id, text);
        let (words, colour) = match met_now {
            Some(true) => ("met now: Next would open", egui::Color32::LIGHT_GREEN),
            _ => ("not met now", egui::Color32::YELLOW),
        };
        ui.colored_label(colour, words).on_hover_text(
            "Judged on what is on screen now, against the scene when the step was chosen — as \
             the level will judge it. Set the scene up as the student should, and see it turn.",
        );
    }
    ui.separator();
    save_and_share(ui, draft, text, &mut sent);
    sent
}

/// The level's own words and scene: title, id, concept, data set, what the scene holds and
/// which panel sections it shows.
fn level_words(ui: &mut egui::Ui, level: &mut voxcast_core::level::Level) {
    egui::Grid::new("editor level").num_columns(2).show(ui, |ui| {
        ui.label("Title");
        ui.text_edit_singleline(&mut level.title);
        ui.end_row();
        ui.label("Id").on_hover_text(
            "A short name, unique among the levels: the students' progress and answers are \
             kept under it (letters a-z, digits, - and _)",
        );
        ui.text_edit_singleline(&mut level.id);
        ui.end_row();
        ui.label("Concept");
        ui.add(egui::TextEdit::multiline(&mut level.concept).desired_rows(2));
        ui.end_row();
        ui.label("Data set");
        ui.label(&level.scene.volume)
            .on_hover_text("The data set on screen when the level was made (Add this view as a step keeps each step's own)");
        ui.end_row();
    });
    ui.horizontal_wrapped(|ui| {
        ui.checkbox(&mut level.scene.preview, "preview on")
            .on_hover_text("Whether the level starts with the live preview drawn");
        ui.checkbox(&mut level.scene.light, "light marker")
            .on_hover_text("Whether the light's sphere stands in the scene");
    });
    panel_sections(ui, &mut level.scene.panel);
}

/// The steps, one line each (a click chooses one), and what can be done to the chosen one.
fn step_list(
    ui: &mut egui::Ui,
    level: &voxcast_core::level::Level,
    selected: usize,
    sent: &mut Vec<EditorCommand>,
) {
    ui.strong(format!("Steps ({})", level.steps.len()));
    for (k, step) in level.steps.iter().enumerate() {
        ui.horizontal(|ui| {
            let first_line: String = step.text.chars().take(46).collect();
            let label = format!("{}. {first_line}", k + 1);
            if ui.selectable_label(k == selected, label).clicked() {
                sent.push(EditorCommand::Select(k));
            }
        });
    }
    ui.horizontal_wrapped(|ui| {
        if super::target(ui.button("Add this view as a step"), "add step")
            .on_hover_text(
                "A step after the chosen one that opens on the scene as it is now: data set, \
                 settings, transfer function, both cameras and the selected ray",
            )
            .clicked()
        {
            sent.push(EditorCommand::AddStep);
        }
        let n = level.steps.len();
        let buttons = [
            (
                "Up",
                "Move the chosen step up",
                selected > 0,
                EditorCommand::Move(selected, -1),
            ),
            (
                "Down",
                "Move the chosen step down",
                selected + 1 < n,
                EditorCommand::Move(selected, 1),
            ),
            (
                "Delete",
                "Delete the chosen step",
                n > 1,
                EditorCommand::Delete(selected),
            ),
        ];
        for (label, tip, enabled, command) in buttons {
            if ui
                .add_enabled(enabled, egui::Button::new(label))
                .on_hover_text(tip)
                .clicked()
            {
                sent.push(command);
            }
        }
        if super::target(ui.button("Play"), "play draft")
            .on_hover_text("Play the level from the chosen step, as a student would")
            .clicked()
        {
            sent.push(EditorCommand::Play(selected));
        }
    });
}

/// The chosen step's text, the view it opens on and the control it frames.
fn step_editor(
    ui: &mut egui::Ui,
    step: &mut voxcast_core::level::Step,
    selected: usize,
    sent: &mut Vec<EditorCommand>,
) {
    ui.add(
        egui::TextEdit::multiline(&mut step.text)
            .desired_rows(3)
            .desired_width(f32::INFINITY)
            .hint_text("What the student reads: what to do and what they will see"),
    );
    ui.horizontal_wrapped(|ui| {
        match &step.scene {
            Some(s) => ui.label(format!(
                "Opens on its own view ({})",
                s.volume.as_deref().unwrap_or("the data set on screen")
            )),
            None => ui.label("Opens on the scene as the step before left it"),
        };
        if ui
            .button("Retake the view")
            .on_hover_text("The step opens on the scene as it is now")
            .clicked()
        {
            sent.push(EditorCommand::Retake(selected));
        }
        if step.scene.is_some()
            && ui
                .button("No view of its own")
                .on_hover_text("The step opens on whatever the step before left")
                .clicked()
        {
            step.scene = None;
        }
    });
    control_choice(ui, &mut step.control);
}

/// The file to save to with Save, the page a link opens with Copy link, the link made and the
/// editor's last message.
fn save_and_share(
    ui: &mut egui::Ui,
    draft: &mut Draft,
    text: &mut EditorText,
    sent: &mut Vec<EditorCommand>,
) {
    ui.horizontal_wrapped(|ui| {
        ui.label("File");
        ui.text_edit_singleline(&mut draft.file);
        if super::target(ui.button("Save"), "save level")
            .on_hover_text(
                "Check the level as `voxcast levels check` does and write it (a download on the \
                 page); it joins the levels list",
            )
            .clicked()
        {
            sent.push(EditorCommand::Save);
        }
    });
    ui.horizontal_wrapped(|ui| {
        #[cfg(not(target_arch = "wasm32"))]
        {
            ui.label("Page")
                .on_hover_text("The address where the class opens Voxcast's page");
            ui.text_edit_singleline(&mut text.page);
        }
        if super::target(ui.button("Copy link"), "copy link")
            .on_hover_text(
                "The level, compressed, in the page's address after #level=: whoever opens the \
                 link plays it, and nothing needs hosting",
            )
            .clicked()
        {
            sent.push(EditorCommand::CopyLink(text.page.clone()));
        }
    });
    if let Some(link) = draft.link.clone() {
        let mut shown = link;
        ui.add(egui::TextEdit::singleline(&mut shown).desired_width(f32::INFINITY))
            .on_hover_text("Select it all and copy it where no clipboard is reached");
    }
    if let Some(m) = &draft.message {
        ui.colored_label(egui::Color32::LIGHT_BLUE, m);
    }
}

/// Which sections of the settings panel the level shows.
fn panel_sections(ui: &mut egui::Ui, panel: &mut Option<Vec<Section>>) {
    const ALL: [Section; 9] = [
        Section::Dataset,
        Section::RayCasting,
        Section::SpeedAccuracy,
        Section::ShadingAndLight,
        Section::TransferFunction,
        Section::VirtualCamera,
        Section::Preview,
        Section::LookingInside,
        Section::RayData,
    ];
    ui.collapsing("Panel sections the level shows", |ui| {
        let mut all = panel.is_none();
        if ui.checkbox(&mut all, "all of them").changed() {
            *panel = (!all).then(|| vec![Section::RayCasting]);
        }
        if let Some(shown) = panel.as_mut() {
            ui.horizontal_wrapped(|ui| {
                for s in ALL {
                    let mut on = shown.contains(&s);
                    if ui.checkbox(&mut on, super::title(s)).changed() {
                        if on {
                            shown.push(s);
                        } else {
                            shown.retain(|x| *x != s);
                        }
                    }
                }
            });
        }
    });
}

/// The control the step frames in yellow.
fn control_choice(ui: &mut egui::Ui, control: &mut Option<Control>) {
    let name =
        |c: Option<Control>| c.map_or("none".to_string(), super::levels_window::control_name);
    egui::ComboBox::from_label("framed control")
        .selected_text(name(*control))
        .width(260.0)
        .show_ui(ui, |ui| {
            ui.selectable_value(control, None, "none");
            for c in Control::ALL {
                ui.selectable_value(control, Some(c), name(Some(c)));
            }
        });
}

/// The step's objective: its kind chosen from the list (with the docs' example values), its
/// fields typed as JSON and read as they are typed.
fn objective_editor(
    ui: &mut egui::Ui,
    objective: &mut Objective,
    step: usize,
    id: &str,
    text: &mut EditorText,
) {
    let key = Some((step, id.to_string()));
    if text.for_step != key {
        text.for_step = key;
        text.objective = serde_json::to_string(objective).unwrap_or_default();
        text.error = None;
    }
    let mut chosen = None;
    egui::ComboBox::from_label("objective")
        .selected_text(objective.kind())
        .width(260.0)
        .show_ui(ui, |ui| {
            for example in Objective::examples() {
                let kind = example.kind();
                if ui
                    .selectable_label(kind == objective.kind(), &kind)
                    .clicked()
                {
                    chosen = Some(example);
                }
            }
        })
        .response
        .on_hover_text("What opens Next: docs/levels.md says what each kind checks");
    if let Some(example) = chosen {
        *objective = example;
        text.objective = serde_json::to_string(objective).unwrap_or_default();
        text.error = None;
    }
    let edit = ui.add(
        egui::TextEdit::multiline(&mut text.objective)
            .code_editor()
            .desired_rows(2)
            .desired_width(f32::INFINITY),
    );
    if edit.changed() {
        match serde_json::from_str::<Objective>(&text.objective) {
            Ok(o) => {
                *objective = o;
                text.error = None;
            }
            Err(e) => text.error = Some(e.to_string()),
        }
    }
    if let Some(e) = &text.error {
        ui.colored_label(
            egui::Color32::LIGHT_RED,
            format!("not an objective yet: {e}"),
        );
    }
}
