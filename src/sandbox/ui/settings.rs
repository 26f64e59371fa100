//! The settings panel: its sections in order, each drawn from the state it edits.

use super::*;

/// What the Ray data section reads and edits.
pub(super) type RayParams<'w> = (
    ResMut<'w, crate::sandbox::data::choices::RayChoices>,
    Res<'w, crate::sandbox::data::source::RayScene>,
    Res<'w, crate::sandbox::data::estimate::Estimator>,
    Res<'w, crate::sandbox::data::choices::ViewReport>,
    ResMut<'w, crate::sandbox::data::estimate::RangeFit>,
);

pub(super) fn settings_panel(
    mut contexts: EguiContexts,
    (mut panel, mut dock, pacing): (
        ResMut<PanelState>,
        ResMut<Dock>,
        Option<Res<crate::sandbox::shared::pacing::Pacing>>,
    ),
    (volume, mut loading, lessons, mode): (
        Res<VolumeState>,
        ResMut<Loading>,
        Res<levels::Lessons>,
        Res<State<crate::sandbox::shared::mode::Mode>>,
    ),
    (mut render, mut step_trade, mut cut_handles): (
        RenderChanges,
        ResMut<crate::sandbox::checks::trade::StepTrade>,
        ResMut<crate::sandbox::scene::cut::CutHandles>,
    ),
    (diagnostics, mut previewing, live, rays): (
        Res<DiagnosticsStore>,
        PreviewChanges,
        Option<Res<crate::sandbox::preview::live::LiveView>>,
        RayParams,
    ),
    mut comparison: (ResMut<compare::CompareWindow>, ResMut<Comparison>),
    (mut virtual_cameras, main_views, layout): (
        Query<&mut VirtualCamera>,
        Query<&View, With<MainCamera>>,
        Res<layout::Layout>,
    ),
) -> Result {
    let (mut ray_choices, ray_scene, estimator, ray_report, mut range_fit) = rays;
    let ctx = contexts.ctx_mut()?;
    let mut edited = render.now.clone();
    let mut preview = previewing.now.as_deref().cloned().unwrap_or_default();
    let mut load: Option<String> = None;
    let spot: Spot = lessons.spot;
    // A level that asks which effect a trace holds names traces by number only.
    let hide_effects = match *mode.get() {
        crate::sandbox::shared::mode::Mode::Level(l) => {
            lessons.levels.get(l).is_some_and(|level| {
                level.steps.iter().any(|s| {
                    matches!(
                        s.objective,
                        voxcast_core::level::Objective::NameEffect { .. }
                    )
                })
            })
        }
        crate::sandbox::shared::mode::Mode::FreePlay => false,
    };
    let guide = Guide {
        spot,
        panel: lessons.panel_in(*mode.get()),
    };
    let trade_current = step_trade
        .current(main_views.single().ok(), &render.now, &volume)
        .is_some();
    let voxel = volume.volume.spacing().min_element();
    let ctx = ctx.clone();
    if !layout.settings {
        return Ok(());
    }
    dock.show(&ctx, "settings", |dock_ui| {
        egui::Panel::left("settings")
            .resizable(true)
            .default_size(layout.shares.side_width(layout::Side::Settings))
            .max_size(layout.shares.side_max(layout::Side::Settings))
            .min_size(layout::SIDE_MIN)
            .show(dock_ui, |ui| {
                // The frame time and Render image stay at the top; the sections scroll.
                let fps = diagnostics
                    .get(&FrameTimeDiagnosticsPlugin::FRAME_TIME)
                    .and_then(|d| d.smoothed());
                let resting = pacing.as_ref().is_some_and(|p| p.resting);
                ui.horizontal(|ui| {
                    if resting {
                        ui.label("frame time: at rest").on_hover_text(format!(
                            "Nothing moves and nothing is under way, so the window draws only \
                             when something changes (and at least every {} s), leaving the \
                             computer free; the frame time shows again once something moves.",
                            crate::sandbox::shared::pacing::REST_WAIT.as_secs_f32()
                        ));
                    } else {
                        ui.label(format!(
                            "frame time: {}",
                            fps.map_or("…".into(), |ms| format!("{ms:.1} ms"))
                        ));
                    }
                    let clicked = marked(ui, spot, Control::RenderImage, |ui| {
                        target(ui.button("Render image…"), "render image")
                            .on_hover_text(
                                "Render this view exactly on the CPU and compare it with \
                                     the preview",
                            )
                            .clicked()
                    });
                    if clicked {
                        comparison.0.open = true;
                        comparison.1.start();
                    }
                });
                ui.separator();
                egui::ScrollArea::vertical()
                    .auto_shrink([false, false])
                    .show(ui, |ui| {
                        section(ui, Section::Dataset, true, guide, |ui| {
                            load = dataset_section(ui, &mut panel, &volume, &mut loading);
                        });
                        section(ui, Section::RayCasting, true, guide, |ui| {
                            ray_section(ui, &mut edited.settings, &volume, spot)
                        });
                        section(ui, Section::SpeedAccuracy, false, guide, |ui| {
                            trade::trade_section(
                                ui,
                                &mut step_trade,
                                trade_current,
                                edited.settings.step.voxels(voxel),
                                spot,
                            )
                        });
                        section(ui, Section::LookingInside, false, guide, |ui| {
                            let forward = main_views.single().ok().map(|v| v.0.forward());
                            cut::cut_section(
                                ui,
                                &mut edited.settings.clip,
                                &mut cut_handles,
                                forward,
                                spot,
                            )
                        });
                        section(ui, Section::ShadingAndLight, false, guide, |ui| {
                            shading_section(ui, &mut edited.settings, &volume, spot)
                        });
                        section(ui, Section::TransferFunction, true, guide, |ui| {
                            preset_menu(ui, &mut edited, &volume.volume);
                            panel.editor.show(
                                ui,
                                &mut edited.transfer,
                                &volume.volume,
                                &volume.source,
                            );
                            marked(ui, spot, Control::Classification, |ui| {
                                classify::classification_controls(
                                    ui,
                                    &mut edited.settings.classification,
                                    &mut panel.classify,
                                    &volume.volume,
                                    &volume.source,
                                )
                            });
                        });
                        if let Ok(mut vc) = virtual_cameras.single_mut() {
                            section(ui, Section::VirtualCamera, false, guide, |ui| {
                                let main = main_views.single().ok().map(|v| v.0);
                                virtual_camera_section(
                                    ui,
                                    (&mut vc, &mut edited.settings),
                                    main,
                                    &volume,
                                    spot,
                                )
                            });
                        }
                        section(ui, Section::RayData, false, guide, |ui| {
                            let vc = virtual_cameras.single().ok().cloned();
                            let mut choices = ray_choices.clone();
                            let mut back = false;
                            ray_data::ray_data_section(
                                ui,
                                ray_data::RayPanel {
                                    choices: &mut choices,
                                    rays: &ray_scene,
                                    estimator: &estimator,
                                    report: &ray_report,
                                    volume: &volume,
                                    render: &mut edited,
                                    loading: &mut loading,
                                    virtual_camera: vc.as_ref(),
                                    preview_on: &mut preview.enabled,
                                    back: &mut back,
                                    fit: &mut range_fit,
                                    hide_effects,
                                },
                                spot,
                            );
                            choices.back = back;
                            if choices != *ray_choices {
                                *ray_choices = choices;
                            }
                        });
                        section(ui, Section::Preview, false, guide, |ui| {
                            preview_section(
                                ui,
                                &mut preview,
                                live.as_deref(),
                                (&mut edited.depth_termination, edited.settings.method),
                                spot,
                            )
                        });
                    });
            });
    });
    render.edited(Author::Panel, edited);
    previewing.edited(Author::Panel, preview);
    if let Some(source) = load {
        loading.start_keeping_choices(source);
    }
    Ok(())
}
