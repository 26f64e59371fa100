//! The settings panel: its sections in order, each drawn from the state it edits.

use super::*;
use crate::sandbox::checks::trade::StepTrade;
use crate::sandbox::data::choices::{RayChoices, ViewReport};
use crate::sandbox::data::estimate::{Estimator, RangeFit};
use crate::sandbox::data::source::RayScene;
use crate::sandbox::preview::live::LiveView;
use crate::sandbox::scene::cut::CutHandles;
use crate::sandbox::shared::mode::Mode;
use crate::sandbox::shared::pacing::{Pacing, REST_WAIT, WORK_WAIT};
use bevy::ecs::system::SystemParam;

/// The panel's top row: the frame time, and Render image.
#[derive(SystemParam)]
pub(super) struct TopRow<'w> {
    diagnostics: Res<'w, DiagnosticsStore>,
    pacing: Option<Res<'w, Pacing>>,
    window: ResMut<'w, compare::CompareWindow>,
    comparison: ResMut<'w, Comparison>,
}

/// What the sections change: the render's and the preview's settings (asked for through
/// their owner), and the controls' state that is not a setting.
#[derive(SystemParam)]
pub(super) struct Controls<'w, 's> {
    render: RenderChanges<'w>,
    preview: PreviewChanges<'w>,
    panel: ResMut<'w, PanelState>,
    loading: ResMut<'w, Loading>,
    step_trade: ResMut<'w, StepTrade>,
    cut_handles: ResMut<'w, CutHandles>,
    virtual_cameras: Query<'w, 's, &'static mut VirtualCamera>,
}

/// What the sections show: the volume, the main camera's view and the preview's live view.
#[derive(SystemParam)]
pub(super) struct Shown<'w, 's> {
    volume: Res<'w, VolumeState>,
    main_views: Query<'w, 's, &'static View, With<MainCamera>>,
    live: Option<Res<'w, LiveView>>,
}

/// What the Ray data section reads and edits.
#[derive(SystemParam)]
pub(super) struct RayParams<'w> {
    choices: ResMut<'w, RayChoices>,
    scene: Res<'w, RayScene>,
    estimator: Res<'w, Estimator>,
    report: Res<'w, ViewReport>,
    range_fit: ResMut<'w, RangeFit>,
}

/// The settings as this frame's controls leave them, and a volume asked for: sent once the
/// panel is drawn.
struct Draft {
    render: RenderState,
    preview: PreviewSettings,
    load: Option<String>,
}

pub(super) fn settings_panel(
    mut contexts: EguiContexts,
    mut place: Docked,
    mut top: TopRow,
    mut controls: Controls,
    shown: Shown,
    mut rays: RayParams,
) -> Result {
    let ctx = contexts.ctx_mut()?.clone();
    if !place.layout.settings {
        return Ok(());
    }
    let mode = *place.mode.get();
    let guide = Guide {
        spot: place.lessons.spot,
        panel: place.lessons.panel_in(mode),
    };
    let hide_effects = asks_for_effects(&place.lessons, mode);
    let mut draft = Draft {
        render: controls.render.now.clone(),
        preview: controls.preview.now.as_deref().cloned().unwrap_or_default(),
        load: None,
    };
    let shares = place.layout.shares;
    place.dock.show(&ctx, "settings", |dock_ui| {
        egui::Panel::left("settings")
            .resizable(true)
            .default_size(shares.side_width(layout::Side::Settings))
            .max_size(shares.side_max(layout::Side::Settings))
            .min_size(layout::SIDE_MIN)
            .show(dock_ui, |ui| {
                // The frame time and Render image stay at the top; the sections scroll.
                top_row(ui, &mut top, guide.spot);
                ui.separator();
                egui::ScrollArea::vertical()
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        image_sections(ui, guide, &mut draft, &mut controls, &shown);
                        camera_and_data_sections(
                            ui,
                            guide,
                            &mut draft,
                            &mut controls,
                            &shown,
                            &mut rays,
                            hide_effects,
                        );
                    });
            });
    });
    controls.render.edited(Author::Panel, draft.render);
    controls.preview.edited(Author::Panel, draft.preview);
    if let Some(source) = draft.load {
        controls.loading.start_keeping_choices(source);
    }
    Ok(())
}

/// Whether the level on screen asks which effect a trace holds: then traces are named by
/// number only.
fn asks_for_effects(lessons: &levels::Lessons, mode: Mode) -> bool {
    let Mode::Level(l) = mode else {
        return false;
    };
    lessons.levels.get(l).is_some_and(|level| {
        level.steps.iter().any(|s| {
            matches!(
                s.objective,
                voxcast_core::level::Objective::NameEffect { .. }
            )
        })
    })
}

/// The median of the last `frames` of `values` (oldest first, at most 20), none before the
/// third.
fn recent_median(values: &[f64], frames: u32) -> Option<f64> {
    let n = (frames.min(20) as usize).min(values.len());
    if n < 3 {
        return None;
    }
    voxcast_core::numbers::median(&values[values.len() - n..])
}

/// The frame time (or that the window rests) and the Render image button.
fn top_row(ui: &mut egui::Ui, top: &mut TopRow, spot: Spot) {
    // The median of the frames drawn since the window last woke (up to the last 20): the
    // frame that ended a wait measures the wait, not the drawing.
    let awake = top.pacing.as_ref().map_or(u32::MAX, |p| p.awake_frames);
    let frame_time = top
        .diagnostics
        .get(&FrameTimeDiagnosticsPlugin::FRAME_TIME)
        .and_then(|d| recent_median(&d.values().copied().collect::<Vec<_>>(), awake));
    let resting = top.pacing.as_ref().is_some_and(|p| p.resting);
    let working = top.pacing.as_ref().is_some_and(|p| p.working);
    ui.horizontal(|ui| {
        if working {
            ui.label("frame time: paced for the work")
                .on_hover_text(format!(
                    "Only background work is under way (a render, a load, a measurement), so \
                     the window draws its progress every {} s and leaves the computer to the \
                     work; it draws every frame again as soon as something moves.",
                    WORK_WAIT.as_secs_f32()
                ));
        } else if resting {
            ui.label("frame time: at rest").on_hover_text(format!(
                "Nothing moves and nothing is under way, so the window draws only when \
                 something changes (and at least every {} s), leaving the computer free; the \
                 frame time shows again once something moves.",
                REST_WAIT.as_secs_f32()
            ));
        } else {
            ui.label(format!(
                "frame time: {}",
                frame_time.map_or("…".into(), |ms| format!("{ms:.1} ms"))
            ));
        }
        let clicked = marked(ui, spot, Control::RenderImage, |ui| {
            target(ui.button("Render image…"), "render image")
                .on_hover_text(
                    "Render this view exactly on the CPU and compare it with the preview",
                )
                .clicked()
        });
        if clicked {
            top.window.open = true;
            top.comparison.start();
        }
    });
}

/// The sections that decide the image: the dataset, how rays are cast, the step's trade, the
/// cut, shading and light, and the transfer function.
fn image_sections(
    ui: &mut egui::Ui,
    guide: Guide,
    draft: &mut Draft,
    controls: &mut Controls,
    shown: &Shown,
) {
    let spot = guide.spot;
    let volume = &*shown.volume;
    let view = shown.main_views.single().ok();
    let trade_current = controls
        .step_trade
        .current(view, &controls.render.now, volume)
        .is_some();
    let voxel = volume.volume.spacing().min_element();
    let settings = &mut draft.render.settings;
    section(ui, Section::Dataset, true, guide, |ui| {
        draft.load = dataset_section(ui, &mut controls.panel, volume, &mut controls.loading);
    });
    section(ui, Section::RayCasting, true, guide, |ui| {
        ray_section(ui, settings, volume, spot)
    });
    section(ui, Section::SpeedAccuracy, false, guide, |ui| {
        let step = settings.step.voxels(voxel);
        trade::trade_section(ui, &mut controls.step_trade, trade_current, step, spot)
    });
    section(ui, Section::LookingInside, false, guide, |ui| {
        let forward = view.map(|v| v.0.forward());
        cut::cut_section(
            ui,
            &mut settings.clip,
            &mut controls.cut_handles,
            forward,
            spot,
        )
    });
    section(ui, Section::ShadingAndLight, false, guide, |ui| {
        shading_section(ui, settings, volume, spot)
    });
    section(ui, Section::TransferFunction, true, guide, |ui| {
        let render = &mut draft.render;
        preset_menu(ui, render, &volume.volume);
        let panel = &mut controls.panel;
        panel
            .editor
            .show(ui, &mut render.transfer, &volume.volume, &volume.source);
        marked(ui, spot, Control::Classification, |ui| {
            classify::classification_controls(
                ui,
                &mut render.settings.classification,
                &mut panel.classify,
                &volume.volume,
                &volume.source,
            )
        });
    });
}

/// The sections around the image: the virtual camera, the ray data and the preview.
fn camera_and_data_sections(
    ui: &mut egui::Ui,
    guide: Guide,
    draft: &mut Draft,
    controls: &mut Controls,
    shown: &Shown,
    rays: &mut RayParams,
    hide_effects: bool,
) {
    let spot = guide.spot;
    let volume = &*shown.volume;
    if let Ok(mut vc) = controls.virtual_cameras.single_mut() {
        section(ui, Section::VirtualCamera, false, guide, |ui| {
            let main = shown.main_views.single().ok().map(|v| v.0);
            let settings = &mut draft.render.settings;
            virtual_camera_section(ui, &mut vc, settings, main, volume, spot)
        });
    }
    section(ui, Section::RayData, false, guide, |ui| {
        let vc = controls.virtual_cameras.single().ok().cloned();
        let mut choices = rays.choices.clone();
        let mut back = false;
        let panel = ray_data::RayPanel {
            choices: &mut choices,
            rays: &rays.scene,
            estimator: &rays.estimator,
            report: &rays.report,
            volume,
            render: &mut draft.render,
            loading: &mut controls.loading,
            virtual_camera: vc.as_ref(),
            preview_on: &mut draft.preview.enabled,
            back: &mut back,
            fit: &mut rays.range_fit,
            hide_effects,
        };
        ray_data::ray_data_section(ui, panel, spot);
        choices.back = back;
        if choices != *rays.choices {
            *rays.choices = choices;
        }
    });
    section(ui, Section::Preview, false, guide, |ui| {
        let (live, render) = (shown.live.as_deref(), &mut draft.render);
        let method = render.settings.method;
        let depth = &mut render.depth_termination;
        preview_section(ui, &mut draft.preview, live, depth, method, spot)
    });
}

#[cfg(test)]
mod tests {
    use super::recent_median;

    #[test]
    fn the_frame_time_shown_leaves_out_the_wait_that_ended_a_rest() {
        // Resting frames a second apart, then the wake (its frame measures the wait) and three
        // frames of some 17 ms.
        let values = vec![1000.0, 1000.0, 1000.0, 1000.0, 17.0, 18.0, 16.0];
        assert_eq!(recent_median(&values, 2), None, "too few frames awake");
        let shown = recent_median(&values, 4).unwrap();
        assert!((16.0..=18.0).contains(&shown), "{shown}");
        // Long awake: the last 20 frames.
        let busy: Vec<f64> = (0..100).map(|i| if i < 80 { 50.0 } else { 20.0 }).collect();
        assert_eq!(recent_median(&busy, u32::MAX), Some(20.0));
    }
}
