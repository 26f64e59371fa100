//! The settings panel (egui). Every control's tooltip is its tunable's one documentation
//! (`voxcast_core::tunables`). Controls ask for changes of [`RenderState`]
//! (`shared/render_change.rs`); loading edits [`VolumeState`].

mod breakdown_panel;
mod classify;
pub(crate) mod compare;
mod cost_view;
mod cut;
mod fonts;
mod layout;
mod level_editor;
mod levels_window;
mod light;
#[cfg(target_arch = "wasm32")]
mod page;
mod ray_data;
mod ray_overlay;
mod rays_panel;
mod sections;
mod settings;
mod trade;
mod transfer;
mod value_gradient;
mod widgets;

use crate::sandbox::checks::compare::Comparison;
use crate::sandbox::data::loading::Loading;
use crate::sandbox::inspect::virtual_camera::VirtualCamera;
use crate::sandbox::levels;
use crate::sandbox::shared::quality::PreviewSettings;
use crate::sandbox::shared::render_change::{Author, Change, PreviewChanges, RenderChanges};
use crate::sandbox::shared::state::{MainCamera, RenderState, View, VolumeState};
use bevy::diagnostic::{DiagnosticsStore, FrameTimeDiagnosticsPlugin};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};
use sections::*;
use settings::*;
use voxcast_core::builtin::DATASETS;
use voxcast_core::composite::{Method, Order};
use voxcast_core::level::{Control, Section};
use voxcast_core::preset;
use voxcast_core::sample::Interpolation;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::tunables::{self as t, Tunable};
use voxcast_core::worked::LECTURE_VOXEL;
use widgets::*;

/// The part of the window not yet taken by a docked panel this frame (egui lays panels out
/// inside a `Ui`; each panel system adds its panel to what the ones before it left).
#[derive(Resource, Default)]
pub(super) struct Dock(Option<egui::Rect>);

impl Dock {
    /// Adds panels (through `add`) to the part of the window still free; keeps what is left.
    pub(super) fn show(&mut self, ctx: &egui::Context, id: &str, add: impl FnOnce(&mut egui::Ui)) {
        let rect = self.0.unwrap_or(ctx.viewport_rect());
        let mut ui = egui::Ui::new(
            ctx.clone(),
            egui::Id::new(("dock", id)),
            egui::UiBuilder::new()
                .layer_id(egui::LayerId::background())
                .max_rect(rect),
        );
        add(&mut ui);
        self.0 = Some(ui.available_rect_before_wrap());
    }

    /// The part of the window the panels left for the scene.
    pub(super) fn free(&self, ctx: &egui::Context) -> egui::Rect {
        self.0.unwrap_or(ctx.viewport_rect())
    }
}

/// What a docked panel needs to be placed and guided: the part of the window left
/// ([`Dock`]), the layout's shares and which panels are shown, and the level on screen.
#[derive(bevy::ecs::system::SystemParam)]
pub(super) struct Docked<'w> {
    pub(super) dock: ResMut<'w, Dock>,
    pub(super) layout: Res<'w, layout::Layout>,
    pub(super) lessons: Res<'w, levels::Lessons>,
    pub(super) mode: Res<'w, State<crate::sandbox::shared::mode::Mode>>,
}

/// A new frame: the whole window is free again, and no control has been drawn yet.
fn begin_dock(mut dock: ResMut<Dock>, mut contexts: EguiContexts) {
    dock.0 = None;
    if let Ok(ctx) = contexts.ctx_mut() {
        ctx.data_mut(|d| d.remove_temp::<Targets>(egui::Id::new(TARGETS)));
    }
}

/// Where this frame drew the controls a script clicks by name (in egui points): what the
/// page reports to its test (`voxcast_status()`), as a screen reader would find them by name.
#[derive(Clone, Default)]
pub(super) struct Targets(pub Vec<(String, egui::Rect)>);

const TARGETS: &str = "voxcast-click-targets";

/// Notes `response`'s control under `name`; gives the response back.
pub(super) fn target(response: egui::Response, name: &str) -> egui::Response {
    response.ctx.data_mut(|d| {
        d.get_temp_mut_or_default::<Targets>(egui::Id::new(TARGETS))
            .0
            .push((name.to_owned(), response.rect))
    });
    response
}

/// The controls noted this frame.
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
pub(super) fn targets(ctx: &egui::Context) -> Targets {
    ctx.data(|d| d.get_temp::<Targets>(egui::Id::new(TARGETS)))
        .unwrap_or_default()
}

/// What the panel keeps between frames.
#[derive(Resource, Default)]
struct PanelState {
    path: String,
    editor: transfer::TransferEditor,
    classify: classify::ClassifyText,
}

pub(super) fn plugin(app: &mut App) {
    app.add_plugins(fonts::plugin)
        .init_resource::<PanelState>()
        .init_resource::<Dock>()
        .init_resource::<layout::Layout>()
        .init_resource::<compare::CompareWindow>()
        .add_message::<crate::sandbox::checks::compare::ShowRenderImage>()
        .init_resource::<breakdown_panel::ExportState>()
        .init_resource::<level_editor::EditorText>()
        .add_systems(
            EguiPrimaryContextPass,
            (
                // Docked: the level on top and the breakdown below span the window; the
                // settings and the rays take the sides; the scene gets what is left.
                (
                    begin_dock,
                    levels_window::levels_window,
                    breakdown_panel::breakdown_panel,
                    layout::layout_strip,
                    settings_panel,
                    rays_panel::rays_panel,
                    compare::compare_window,
                    level_editor::editor_window,
                    record_viewport,
                )
                    .chain()
                    .in_set(crate::sandbox::shared::schedule::Paint::Panels),
                ray_overlay::ray_overlay.in_set(crate::sandbox::shared::schedule::Paint::Over),
            ),
        )
        .add_message::<crate::sandbox::shared::files::FilesChosen>()
        .add_systems(
            Update,
            take_chosen_transfer.in_set(crate::sandbox::shared::schedule::Frame::Rules),
        );
    #[cfg(target_arch = "wasm32")]
    app.add_systems(
        EguiPrimaryContextPass,
        page::publish_status.in_set(crate::sandbox::shared::schedule::Paint::Notes),
    );
}

/// A transfer function the browser handed over (Open… in the editor).
fn take_chosen_transfer(
    mut chosen: MessageReader<crate::sandbox::shared::files::FilesChosen>,
    mut panel: ResMut<PanelState>,
    mut render: RenderChanges,
) {
    for c in chosen.read() {
        if c.purpose != crate::sandbox::shared::files::Purpose::Transfer {
            continue;
        }
        if let Some((name, bytes)) = c.files.first() {
            let mut tf = render.now.transfer.clone();
            if panel.editor.receive(name, bytes, &mut tf) {
                render.ask(Author::TransferFile, Change::Transfer(tf));
            }
        }
    }
}

/// Records the rectangle the panels left free for the scene, after they are laid out.
fn record_viewport(
    mut contexts: EguiContexts,
    dock: Res<Dock>,
    viewport: Option<ResMut<crate::sandbox::shared::viewport::Viewport>>,
    mut commands: Commands,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let v = crate::sandbox::shared::viewport::Viewport {
        rect: dock.free(ctx),
        pixels_per_point: ctx.pixels_per_point(),
    };
    match viewport {
        Some(mut old) => {
            if *old != v {
                *old = v;
            }
        }
        None => commands.insert_resource(v),
    }
    Ok(())
}

/// The characters among the texts `add` draws ([`drawn_text`]) that the window's font has no
/// glyph for (they would show as boxes). An ID clash between two widgets shows up here too:
/// egui paints its warning with a '🔥' the font lacks.
#[cfg(test)]
pub(super) fn missing_glyphs(add: impl FnMut(&mut egui::Ui)) -> std::collections::BTreeSet<char> {
    let all = drawn_text(add);
    assert!(all.len() > 100, "little text drawn: {all}");
    all.chars()
        .filter(|c| !c.is_whitespace())
        .filter(|&c| !fonts::has_glyph(&egui::FontFamily::Proportional, c))
        .collect()
}

/// Every text `add` draws in a 1200×4000-point window, one a line.
#[cfg(test)]
pub(super) fn drawn_text(add: impl FnMut(&mut egui::Ui)) -> String {
    fn texts(shape: &egui::Shape, out: &mut String) {
        match shape {
            egui::Shape::Text(t) => {
                out.push_str(t.galley.text());
                out.push('\n');
            }
            egui::Shape::Vec(v) => v.iter().for_each(|s| texts(s, out)),
            _ => {}
        }
    }
    let ctx = crate::sandbox::ui::fonts::context();
    let input = || egui::RawInput {
        screen_rect: Some(egui::Rect::from_min_size(
            egui::Pos2::ZERO,
            egui::vec2(1200.0, 4000.0),
        )),
        ..Default::default()
    };
    let mut add = add;
    // Twice: the second frame lays out what the first measured.
    ctx.run_ui(input(), &mut add).drop_without_applying_deltas();
    let mut output = ctx.run_ui(input(), &mut add);
    let shapes = std::mem::take(&mut output.shapes);
    output.drop_without_applying_deltas();
    let mut all = String::new();
    for clipped in &shapes {
        texts(&clipped.shape, &mut all);
    }
    all
}

/// The size `add` takes when given a column `room` points wide and [`COLUMN`] high: wider than
/// `room` where a row neither wraps nor shortens (a side panel then grows past its room and
/// cuts its rows), as high as the column where a row takes all the height it is given.
#[cfg(test)]
pub(super) fn size_in(room: f32, mut add: impl FnMut(&mut egui::Ui)) -> egui::Vec2 {
    let ctx = crate::sandbox::ui::fonts::context();
    let mut size = egui::Vec2::ZERO;
    // Twice: the second frame lays out what the first measured.
    for _ in 0..2 {
        ctx.run_ui(egui::RawInput::default(), |ui| {
            let column = egui::Rect::from_min_size(ui.min_rect().min, egui::vec2(room, COLUMN));
            let scope = ui.scope_builder(egui::UiBuilder::new().max_rect(column), &mut add);
            size = scope.response.rect.size();
        })
        .drop_without_applying_deltas();
    }
    size
}

/// The room a section's rows have in the settings panel at its narrowest: the panel's
/// [`layout::SIDE_MIN`] less its frame (8 points a side) and a section's indent.
#[cfg(test)]
pub(super) fn narrowest_section_room() -> f32 {
    layout::SIDE_MIN - 16.0 - egui::Spacing::default().indent
}

/// [`size_in`]'s column height, points: more than any section needs.
#[cfg(test)]
pub(super) const COLUMN: f32 = 4000.0;

#[cfg(test)]
mod tests;
