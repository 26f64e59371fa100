//! The settings panel (egui). Every control's tooltip is its tunable's one documentation
//! (`voxcast_core::tunables`). Controls edit [`RenderState`]; loading edits [`VolumeState`].

mod breakdown_panel;
mod classify;
pub(crate) mod compare;
mod cost_view;
mod cut;
mod layout;
mod levels_window;
mod light;
#[cfg(target_arch = "wasm32")]
mod page;
mod ray_data;
mod ray_overlay;
mod rays_panel;
mod trade;
mod transfer;
mod value_gradient;

use super::compare::Comparison;
use super::levels;
use super::loading::Loading;
use super::preview::PreviewSettings;
use super::state::{MainCamera, RenderState, View, VolumeState};
use super::virtual_camera::VirtualCamera;
use bevy::diagnostic::{DiagnosticsStore, FrameTimeDiagnosticsPlugin};
use bevy::prelude::*;
use bevy_egui::{EguiContexts, EguiPrimaryContextPass, egui};
use voxcast_core::builtin::DATASETS;
use voxcast_core::composite::{Method, Order};
use voxcast_core::level::{Control, Section};
use voxcast_core::preset;
use voxcast_core::sample::Interpolation;
use voxcast_core::settings::RenderSettings;
use voxcast_core::step::Length;
use voxcast_core::tunables::{self as t, Tunable};
use voxcast_core::worked::LECTURE_VOXEL;

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
    app.init_resource::<PanelState>()
        .init_resource::<Dock>()
        .init_resource::<layout::Layout>()
        .init_resource::<compare::CompareWindow>()
        .init_resource::<breakdown_panel::ExportState>()
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
                    record_viewport,
                )
                    .chain()
                    .in_set(super::Paint::Panels),
                ray_overlay::ray_overlay.in_set(super::Paint::Over),
            ),
        )
        .add_message::<super::files::FilesChosen>()
        .add_systems(Update, take_chosen_transfer.in_set(super::Frame::Rules));
    #[cfg(target_arch = "wasm32")]
    app.add_systems(
        EguiPrimaryContextPass,
        page::publish_status.in_set(super::Paint::Over),
    );
}

/// A transfer function the browser handed over (Open… in the editor).
fn take_chosen_transfer(
    mut chosen: MessageReader<super::files::FilesChosen>,
    mut panel: ResMut<PanelState>,
    mut render: ResMut<super::state::RenderState>,
) {
    for c in chosen.read() {
        if c.purpose != super::files::Purpose::Transfer {
            continue;
        }
        if let Some((name, bytes)) = c.files.first() {
            let mut tf = render.transfer.clone();
            if panel.editor.receive(name, bytes, &mut tf) {
                render.transfer = tf;
            }
        }
    }
}

/// Records the rectangle the panels left free for the scene, after they are laid out.
fn record_viewport(
    mut contexts: EguiContexts,
    dock: Res<Dock>,
    viewport: Option<ResMut<super::preview::Viewport>>,
    mut commands: Commands,
) -> Result {
    let ctx = contexts.ctx_mut()?;
    let v = super::preview::Viewport {
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

/// Display colour of linear-as-stored values (the core's values are display values).
pub(super) fn color32(c: [f32; 3]) -> egui::Color32 {
    let [r, g, b] = voxcast_core::image_out::to_u8(Vec3::from_array(c));
    egui::Color32::from_rgb(r, g, b)
}

/// The section's title in the panel.
fn title(s: Section) -> &'static str {
    match s {
        Section::Dataset => "Dataset",
        Section::RayCasting => "Ray casting",
        Section::SpeedAccuracy => "Speed against accuracy",
        Section::ShadingAndLight => "Shading and light",
        Section::TransferFunction => "Transfer function",
        Section::VirtualCamera => "Virtual camera",
        Section::Preview => "Preview (slow hardware)",
        Section::LookingInside => "Looking inside (crop and clip)",
        Section::RayData => "Ray data (RayVis)",
    }
}

/// What the current level asks of the panel: the control its step is about and the sections
/// it shows (`None`: all).
#[derive(Clone, Copy)]
struct Guide<'a> {
    spot: Spot,
    panel: Option<&'a [Section]>,
}

/// A collapsible section of the panel, drawn when the level shows it and opened when it holds
/// the control the step is about (`Control::section`).
fn section(
    ui: &mut egui::Ui,
    s: Section,
    open: bool,
    guide: Guide,
    body: impl FnOnce(&mut egui::Ui),
) {
    if guide.panel.is_some_and(|p| !p.contains(&s)) {
        return;
    }
    let mut header = egui::CollapsingHeader::new(title(s)).default_open(open);
    if guide.spot.and_then(Control::section) == Some(s) {
        header = header.open(Some(true));
    }
    header.show(ui, body);
}

/// The control the current level step is about, if any.
type Spot = Option<Control>;

/// Draws `add` and, when it is the control `spot` names, a frame around it.
fn marked<R>(ui: &mut egui::Ui, spot: Spot, c: Control, add: impl FnOnce(&mut egui::Ui) -> R) -> R {
    let r = ui.scope(add);
    if spot == Some(c) {
        ui.painter().rect_stroke(
            r.response.rect.expand(2.0),
            3.0,
            egui::Stroke::new(2.0, egui::Color32::YELLOW),
            egui::StrokeKind::Outside,
        );
    }
    r.inner
}

/// The volume's name and description, the embedded list and the path field; returns the
/// source to load, if one was chosen.
fn dataset_section(
    ui: &mut egui::Ui,
    panel: &mut PanelState,
    volume: &VolumeState,
    loading: &mut Loading,
) -> Option<String> {
    let mut load = None;
    ui.label(format!("{} ({})", volume.volume.name(), volume.source));
    if let Some(p) = &volume.preset {
        ui.label(egui::RichText::new(&p.description).small());
    }
    egui::ComboBox::from_label("Embedded")
        .selected_text("choose…")
        .show_ui(ui, |ui| {
            for (name, what) in DATASETS {
                if ui
                    .selectable_label(false, *name)
                    .on_hover_text(*what)
                    .clicked()
                {
                    load = Some(format!("builtin:{name}"));
                }
            }
            ui.separator();
            ui.label(egui::RichText::new("Ray densities of the Cornell box").small());
            let traces = std::iter::once((None, "every ray".to_string())).chain(
                voxcast_core::rays::effects::Effect::ALL
                    .iter()
                    .map(|e| (Some(e.id()), e.words().to_string())),
            );
            for (id, words) in traces {
                let tip = "How many of the box's rays pass through each cell of a 128-cell grid \
                           (RayVis's ray-density volume), shown with Sum and inferno";
                if ui
                    .selectable_label(false, &words)
                    .on_hover_text(tip)
                    .clicked()
                {
                    load = Some(match id {
                        Some(id) => format!("density:builtin:cornell@trace={id}"),
                        None => "density:builtin:cornell".into(),
                    });
                }
            }
        });
    if crate::sandbox::files::PICKS_FILES {
        // A page reads no paths: the browser's picker (or a file dropped on the page).
        if ui
            .button("Open a volume file…")
            .on_hover_text(
                "A .nrrd, .nii, .nii.gz or .raw file from this computer (or drop one on the \
                 page); a detached .nhdr or a .hdr with its data file: choose both together",
            )
            .clicked()
        {
            crate::sandbox::files::pick(crate::sandbox::files::Purpose::Volume);
        }
    } else {
        ui.horizontal(|ui| {
            ui.text_edit_singleline(&mut panel.path).on_hover_text(
                "A .nrrd, .nhdr, .nii, .nii.gz, .hdr or .raw file (or drop one on the window); \
                 or a ray density: density:FILE.rayvis or density:builtin:cornell, optionally \
                 followed by @cell=S,trace=ID,filter=all|hit|miss,chunk=N,tolerance=T",
            );
            if ui.button("Load").clicked() {
                load = Some(panel.path.clone());
            }
        });
    }
    if let Some((what, seconds)) = loading.under_way() {
        let mut cancel = false;
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(format!("loading {what} … {seconds:.1} s"));
            cancel = ui.button("Cancel").clicked();
        });
        if cancel {
            loading.cancel();
        }
    }
    if let Some(e) = &loading.error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
    if let Some(note) = &loading.note {
        ui.label(egui::RichText::new(note).small());
    }
    load
}

/// Method, step, interpolation, opacity correction, termination, jitter and the target.
fn ray_section(ui: &mut egui::Ui, s: &mut RenderSettings, volume: &VolumeState, spot: Spot) {
    marked(ui, spot, Control::Method, |ui| {
        egui::ComboBox::from_label("Method")
            .selected_text(s.method.name())
            .show_ui(ui, |ui| {
                for m in Method::ALL {
                    ui.selectable_value(&mut s.method, m, m.name())
                        .on_hover_text(m.doc());
                }
            })
    });
    let voxel = volume.volume.spacing().min_element();
    let mut step = s.step.voxels(voxel);
    if marked(ui, spot, Control::Step, |ui| {
        slider(ui, &mut step, &t::STEP, 0.05..=4.0, true)
    }) {
        s.step = Length::Voxels(step);
    }
    if let Some(warning) = s.cap_warning(&volume.volume) {
        ui.colored_label(egui::Color32::YELLOW, warning);
    }
    let mut trilinear = s.interpolation == Interpolation::Trilinear;
    if marked(ui, spot, Control::Interpolation, |ui| {
        ui.checkbox(&mut trilinear, "Trilinear interpolation")
            .on_hover_text(
                "Blend the 8 surrounding lattice points (off: the nearest point's value)",
            )
            .changed()
    }) {
        s.interpolation = if trilinear {
            Interpolation::Trilinear
        } else {
            Interpolation::Nearest
        };
    }
    // Controls that do not apply to the method are greyed out, their tooltip saying why.
    let opacity = s.method.uses_opacity();
    applies(ui, opacity, |ui| {
        marked(ui, spot, Control::OpacityCorrection, |ui| {
            checkbox(ui, &mut s.opacity_correction, &t::OPACITY_CORRECTION)
        });
        let mut reference = s.reference_step.voxels(voxel);
        if slider(ui, &mut reference, &t::REFERENCE_STEP, 0.05..=4.0, true) {
            s.reference_step = Length::Voxels(reference);
        }
        marked(ui, spot, Control::EarlyTermination, |ui| {
            checkbox(ui, &mut s.early_termination, &t::EARLY_TERMINATION)
        });
        marked(ui, spot, Control::Order, |ui| {
            egui::ComboBox::from_label("Order")
                .selected_text(s.order.name())
                .show_ui(ui, |ui| {
                    for o in [Order::FrontToBack, Order::BackToFront] {
                        ui.selectable_value(&mut s.order, o, o.name())
                            .on_hover_text(o.doc());
                    }
                })
        });
    });
    let cutoff_applies = opacity.and(if !s.early_termination {
        Err("Early ray termination is off: no ray stops at the cutoff")
    } else if s.order == Order::BackToFront {
        Err("Back to front visits every sample: early termination needs front to back")
    } else {
        Ok(())
    });
    applies(ui, cutoff_applies, |ui| {
        slider(ui, &mut s.cutoff, &t::CUTOFF, 0.0..=1.0, false);
    });
    marked(ui, spot, Control::Skipping, |ui| {
        checkbox(ui, &mut s.skipping, &t::SKIPPING)
    });
    marked(ui, spot, Control::Jitter, |ui| {
        checkbox(ui, &mut s.jitter, &t::JITTER)
    });
    marked(ui, spot, Control::Supersampling, |ui| {
        // Whole rays: an integer slider (1 to 4: 16 rays a pixel is already 16 times the work).
        ui.add(egui::Slider::new(&mut s.supersampling, 1..=4).text(t::SUPERSAMPLING.label))
            .on_hover_text(t::SUPERSAMPLING.doc)
    });
    let (lo, hi) = volume.volume.value_range();
    let mut target = s.target.unwrap_or(0.5 * (lo + hi));
    applies(ui, s.method.uses_target(), |ui| {
        if marked(ui, spot, Control::Target, |ui| {
            slider(ui, &mut target, &t::TARGET, lo..=hi, false)
        }) {
            s.target = Some(target);
        }
    });
    applies(ui, s.method.uses_sum_range(), |ui| {
        marked(ui, spot, Control::SumRange, |ui| {
            sum_range(ui, &mut s.sum_range, &volume.volume)
        });
    });
}

/// Sum's range: two ends, each on a logarithmic slider up to four times the default top (the
/// most a ray along the longest side can gather); the low end stays below the high end.
fn sum_range(
    ui: &mut egui::Ui,
    range: &mut Option<(f32, f32)>,
    volume: &voxcast_core::Volume,
) -> egui::Response {
    let default = voxcast_core::scene::default_sum_range(volume);
    let (mut a, mut b) = range.unwrap_or(default);
    let top = 4.0 * default.1.max(b);
    let tiny = top * 1e-6;
    ui.vertical(|ui| {
        ui.label(t::SUM_RANGE.label).on_hover_text(t::SUM_RANGE.doc);
        let high = ui
            .add(
                egui::Slider::new(&mut b, tiny..=top)
                    .logarithmic(true)
                    .custom_formatter(|v, _| voxcast_core::numbers::sig(v as f32))
                    .text("high end"),
            )
            .on_hover_text(t::SUM_RANGE.doc);
        let (floor, log) = (0.0f32.min(a), a >= 0.0);
        let low = ui
            .add(
                egui::Slider::new(&mut a, floor..=b - tiny)
                    .logarithmic(log)
                    .custom_formatter(|v, _| voxcast_core::numbers::sig(v as f32))
                    .text("low end"),
            )
            .on_hover_text(t::SUM_RANGE.doc);
        if high.changed() || low.changed() {
            a = a.min(b - tiny);
            *range = Some((a, b));
        }
        high | low
    })
    .inner
}

/// Draws `add` enabled when `why_not` is `Ok`, else greyed out with the reason as tooltip.
fn applies(ui: &mut egui::Ui, why_not: Result<(), &'static str>, add: impl FnOnce(&mut egui::Ui)) {
    let response = ui.add_enabled_ui(why_not.is_ok(), add).response;
    if let Err(why) = why_not {
        response.on_disabled_hover_text(why);
    }
}

/// Phong's coefficients and the light.
fn shading_section(ui: &mut egui::Ui, s: &mut RenderSettings, volume: &VolumeState, spot: Spot) {
    let shades = s.method.uses_shading();
    applies(ui, shades, |ui| {
        marked(ui, spot, Control::Shading, |ui| {
            checkbox(ui, &mut s.shading, &t::SHADING)
        });
    });
    let p = &mut s.phong;
    slider(ui, &mut p.ke, &t::EMISSION, 0.0..=1.0, false);
    slider(
        ui,
        &mut p.global_ambient,
        &t::GLOBAL_AMBIENT,
        0.0..=1.0,
        false,
    );
    slider(ui, &mut p.ka, &t::AMBIENT, 0.0..=1.0, false);
    slider(ui, &mut p.kd, &t::DIFFUSE, 0.0..=1.0, false);
    slider(ui, &mut p.ks, &t::SPECULAR, 0.0..=1.0, false);
    slider(ui, &mut p.shininess, &t::SHININESS, 1.0..=256.0, true);
    checkbox(ui, &mut p.two_sided, &t::TWO_SIDED);
    let (lo, hi) = volume.volume.bounds();
    marked(ui, spot, Control::Light, |ui| {
        light::light_controls(ui, p, lo, hi)
    });
}

/// The presets: each sets the transfer function and the settings it was made for; inferno is
/// spread over the loaded volume's values.
fn preset_menu(ui: &mut egui::Ui, edited: &mut RenderState, volume: &voxcast_core::Volume) {
    use voxcast_core::colormap::{INFERNO_DOC, INFERNO_PRESET, inferno_transfer};
    egui::ComboBox::from_label("Preset")
        .selected_text(edited.transfer.name.clone())
        .show_ui(ui, |ui| {
            if ui
                .selectable_label(false, INFERNO_PRESET)
                .on_hover_text(INFERNO_DOC)
                .clicked()
            {
                let (lo, hi) = volume.value_range();
                edited.transfer = inferno_transfer(lo, hi);
            }
            for pr in preset::all() {
                if ui
                    .selectable_label(false, &pr.name)
                    .on_hover_text(&pr.description)
                    .clicked()
                {
                    if let Ok(settings) = pr.settings_over(&edited.settings) {
                        edited.settings = settings;
                    }
                    edited.transfer = pr.transfer.clone();
                }
            }
        });
}

/// The virtual camera: shown or not, its resolution and field of view, and where it stands.
fn virtual_camera_section(
    ui: &mut egui::Ui,
    (vc, settings): (&mut Mut<VirtualCamera>, &mut RenderSettings),
    main: Option<voxcast_core::camera::Camera>,
    volume: &VolumeState,
    spot: Spot,
) {
    let mut edited = **vc;
    ui.checkbox(&mut edited.shown, "Show the virtual camera")
        .on_hover_text("Its body, frustum and pixel grid in the scene");
    let range = t::VIRTUAL_RESOLUTION.min as u32..=t::VIRTUAL_RESOLUTION.max as u32;
    marked(ui, spot, Control::VirtualPixels, |ui| {
        for (value, axis) in [(&mut edited.width, "across"), (&mut edited.height, "down")] {
            ui.add(egui::Slider::new(value, range.clone()).text(format!("pixels {axis}")))
                .on_hover_text(t::VIRTUAL_RESOLUTION.doc);
        }
    });
    if let Some(mut fov) = super::virtual_camera::fov(&edited.view) {
        let changed = ui
            .add(egui::Slider::new(&mut fov, 5.0..=120.0).text("field of view (°)"))
            .on_hover_text("The virtual camera's vertical opening angle")
            .changed();
        if changed
            && let Ok(v) = voxcast_core::camera::Camera::new(
                edited.view.eye,
                edited.view.target,
                edited.view.up,
                voxcast_core::camera::Projection::Perspective { fov_y_deg: fov },
            )
        {
            edited.view = v;
        }
    }
    ui.horizontal(|ui| {
        if let Some(view) = main
            && ui
                .button("Place at the main camera")
                .on_hover_text("Move the virtual camera to where you are looking from")
                .clicked()
        {
            edited.view = view;
        }
        if ui
            .button("Reset")
            .on_hover_text("Frame the volume from the default side")
            .clicked()
            && let Some(framed) = VirtualCamera::framing(volume, main.as_ref())
        {
            edited.view = framed.view;
        }
    });
    // On the lecture's voxel: its worked ray, to click and follow in the breakdown.
    if volume.source == LECTURE_VOXEL
        && ui
            .button("The lecture's ray")
            .on_hover_text(
                "One pixel whose ray runs from P3 towards P1, the far end, with one sample on \
                 each of P3, P2 and P1 (no opacity correction, no shading): click its pixel to \
                 see the lecture's numbers",
            )
            .clicked()
    {
        edited.view = voxcast_core::worked::lecture_ray();
        (edited.width, edited.height) = (1, 1);
        *settings = voxcast_core::worked::lecture_ray_settings(settings);
    }
    if edited != **vc {
        **vc = edited;
    }
}

/// The preview's quality controls and depth termination.
fn preview_section(
    ui: &mut egui::Ui,
    preview: &mut PreviewSettings,
    live: Option<&super::live::LiveView>,
    (depth, method): (&mut bool, Method),
    spot: Spot,
) {
    let mut q = preview.clone();
    marked(ui, spot, Control::PreviewOn, |ui| {
        ui.checkbox(&mut q.enabled, "Show the preview")
            .on_hover_text("Turn the live preview off (Render image still works)")
    });
    ui.horizontal(|ui| {
        ui.label(t::PREVIEW_BACKEND.label)
            .on_hover_text(t::PREVIEW_BACKEND.doc);
        for (backend, name) in [
            (super::live::Backend::Gpu, "GPU"),
            (super::live::Backend::Cpu, "CPU"),
        ] {
            ui.selectable_value(&mut q.backend, backend, name)
                .on_hover_text(t::PREVIEW_BACKEND.doc);
        }
    });
    cost_view::choice(ui, &cost_view::PREVIEW, &mut q.cost_view, method);
    if let Some(view) = q.cost_view {
        let words = live
            .and_then(|l| l.shown.as_ref())
            .filter(|f| f.key.cost_view == Some(view))
            .and_then(|f| f.legend.as_deref());
        cost_view::legend(ui, view, words);
    }
    if let (true, Some(live)) = (q.cpu_live(), live) {
        ui.label(format!("Live view: {}", live.status()));
    }
    marked(ui, spot, Control::PreviewScale, |ui| {
        slider(ui, &mut q.scale, &t::PREVIEW_SCALE, 0.05..=1.0, false)
    });
    let gpu = q.backend == super::live::Backend::Gpu;
    let why = "The CPU live view always uses the settings' own step: it refines to the exact \
               render";
    ui.add_enabled_ui(gpu, |ui| {
        slider(
            ui,
            &mut q.step_multiplier,
            &t::PREVIEW_STEP_MULTIPLIER,
            1.0..=16.0,
            true,
        );
    })
    .response
    .on_disabled_hover_text(why);
    checkbox(ui, &mut q.adaptive, &t::ADAPTIVE_QUALITY);
    ui.add_enabled_ui(gpu, |ui| {
        slider(ui, &mut q.moving_scale, &t::MOVING_SCALE, 0.05..=1.0, false);
        slider(
            ui,
            &mut q.moving_step_multiplier,
            &t::MOVING_STEP_MULTIPLIER,
            1.0..=16.0,
            true,
        );
    })
    .response
    .on_disabled_hover_text(
        "The CPU live view sizes its frames while moving from its measured speed",
    );
    if q != *preview {
        *preview = q;
    }
    let tip = if super::preview::GPU_READS_DEPTH {
        "Depth-prepass termination: preview rays end where an opaque mesh stands inside the volume"
    } else {
        "Preview rays end where an opaque mesh stands inside the volume: in the CPU live view and \
         Render image. In this browser (WebGL2) the GPU preview cannot read the depth prepass: \
         its rays pass through the meshes, drawn over it (WebGPU can)"
    };
    ui.checkbox(depth, "Stop rays at scene geometry")
        .on_hover_text(tip);
}

/// A slider for a tunable, with its documentation as tooltip.
fn slider(
    ui: &mut egui::Ui,
    value: &mut f32,
    tunable: &Tunable,
    range: std::ops::RangeInclusive<f32>,
    log: bool,
) -> bool {
    ui.add(
        egui::Slider::new(value, range)
            .logarithmic(log)
            .text(tunable.label),
    )
    .on_hover_text(tunable.doc)
    .changed()
}

/// A grid's header row: each title in bold, then the row's end.
fn header_row(ui: &mut egui::Ui, titles: &[&str]) {
    for title in titles {
        ui.strong(*title);
    }
    ui.end_row();
}

fn checkbox(ui: &mut egui::Ui, value: &mut bool, tunable: &Tunable) -> bool {
    ui.checkbox(value, tunable.label)
        .on_hover_text(tunable.doc)
        .changed()
}

/// What the Ray data section reads and edits.
type RayParams<'w> = (
    ResMut<'w, super::raydata::RayChoices>,
    Res<'w, super::raydata::RayScene>,
    Res<'w, super::raydata::Estimator>,
    Res<'w, super::rayviews::ViewReport>,
    ResMut<'w, super::raydata::RangeFit>,
);

fn settings_panel(
    mut contexts: EguiContexts,
    (mut panel, mut dock): (ResMut<PanelState>, ResMut<Dock>),
    (volume, mut loading, lessons, mode): (
        Res<VolumeState>,
        ResMut<Loading>,
        Res<levels::Lessons>,
        Res<State<super::mode::Mode>>,
    ),
    (mut render, mut step_trade, mut cut_handles): (
        ResMut<RenderState>,
        ResMut<super::trade::StepTrade>,
        ResMut<super::cut::CutHandles>,
    ),
    (diagnostics, mut preview, live, rays): (
        Res<DiagnosticsStore>,
        ResMut<PreviewSettings>,
        Option<Res<super::live::LiveView>>,
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
    let mut edited = render.clone();
    let mut load: Option<String> = None;
    let spot: Spot = lessons.spot;
    // A level that asks which effect a trace holds names traces by number only.
    let hide_effects = match *mode.get() {
        super::mode::Mode::Level(l) => lessons.levels.get(l).is_some_and(|level| {
            level.steps.iter().any(|s| {
                matches!(
                    s.objective,
                    voxcast_core::level::Objective::NameEffect { .. }
                )
            })
        }),
        super::mode::Mode::FreePlay => false,
    };
    let guide = Guide {
        spot,
        panel: lessons.panel_in(*mode.get()),
    };
    let trade_current = step_trade
        .current(main_views.single().ok(), &render, &volume)
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
                ui.horizontal(|ui| {
                    ui.label(format!(
                        "frame time: {}",
                        fps.map_or("…".into(), |ms| format!("{ms:.1} ms"))
                    ));
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
    if edited != *render && edited.settings.validate().is_ok() {
        *render = edited;
    }
    if let Some(source) = load {
        loading.start_keeping_choices(source);
    }
    Ok(())
}

/// Every text `add` draws, and the characters among them that the window's font has no glyph
/// for (they would show as boxes). An ID clash between two widgets shows up here too: egui
/// paints its warning with a '🔥' the font lacks.
#[cfg(test)]
pub(super) fn missing_glyphs(add: impl FnMut(&mut egui::Ui)) -> std::collections::BTreeSet<char> {
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
    let ctx = egui::Context::default();
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
    assert!(all.len() > 100, "little text drawn: {all}");
    let font = egui::FontId::proportional(14.0);
    all.chars()
        .filter(|c| !c.is_whitespace())
        .filter(|&c| !ctx.fonts_mut(|f| f.has_glyph(&font, c)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every string the settings panel's sections draw (for every method: the greyed-out
    /// reasons change with it; every classification) has a glyph in the window's font.
    #[test]
    fn every_panel_string_can_be_drawn() {
        let (volume, render) = crate::sandbox::inspect::tests::scene("head");
        for method in Method::ALL {
            let mut s = render.settings.clone();
            s.method = method;
            let mut preview = PreviewSettings {
                backend: crate::sandbox::live::Backend::Cpu,
                ..Default::default()
            };
            let mut panel = PanelState::default();
            let mut loading = Loading::default();
            let mut edited = render.clone();
            let mut depth = true;
            let live = crate::sandbox::live::LiveView::default();
            let mut step_trade = crate::sandbox::trade::StepTrade::default();
            let (lo, hi) = volume.volume.value_range();
            let mut classifications = [
                voxcast_core::classify::Classification::default(),
                voxcast_core::classify::Classification::IsoContours {
                    isovalues: vec![40.0, 140.0],
                    thickness_voxels: 1.0,
                },
                voxcast_core::classify::Classification::Boundaries {
                    full_gradient: Some(10.0),
                },
                voxcast_core::classify::Classification::ValueGradient {
                    regions: vec![voxcast_core::classify::Region {
                        value: [lo, hi],
                        gradient: [0.0, 1.0],
                        opacity: 0.5,
                    }],
                },
            ];
            let missing = missing_glyphs(|ui| {
                dataset_section(ui, &mut panel, &volume, &mut loading);
                ray_section(ui, &mut s, &volume, None);
                shading_section(ui, &mut s, &volume, None);
                preset_menu(ui, &mut edited, &volume.volume);
                panel
                    .editor
                    .show(ui, &mut edited.transfer, &volume.volume, &volume.source);
                for (i, c) in classifications.iter_mut().enumerate() {
                    ui.push_id(i, |ui| {
                        classify::classification_controls(
                            ui,
                            c,
                            &mut panel.classify,
                            &volume.volume,
                            &volume.source,
                        )
                    });
                }
                trade::trade_section(ui, &mut step_trade, false, 0.5, None);
                preview_section(
                    ui,
                    &mut preview,
                    Some(&live),
                    (&mut depth, Method::First),
                    None,
                );
                let mut handles = crate::sandbox::cut::CutHandles { crop: true };
                s.clip.plane = Some(voxcast_core::clip::ClipPlane {
                    normal: Vec3::X,
                    position: 0.2,
                });
                cut::cut_section(ui, &mut s.clip, &mut handles, Some(Vec3::Z), None);
            });
            assert!(missing.is_empty(), "{method:?}: no glyph for {missing:?}");
        }
    }

    /// Whether `s`'s body is drawn under `guide` (closed by default).
    fn drawn(s: Section, guide: Guide) -> bool {
        let ctx = egui::Context::default();
        let mut drawn = false;
        ctx.run_ui(egui::RawInput::default(), |ui| {
            section(ui, s, false, guide, |_| drawn = true)
        })
        .drop_without_applying_deltas();
        drawn
    }

    /// A section opens for every control it holds (the light's too), and a level's panel hides
    /// the sections it does not name.
    #[test]
    fn sections_open_for_their_controls_and_hide_outside_the_levels_panel() {
        let all = Guide {
            spot: None,
            panel: None,
        };
        assert!(!drawn(Section::ShadingAndLight, all), "closed by default");
        for (c, s) in [
            (Control::Light, Section::ShadingAndLight),
            (Control::Shading, Section::ShadingAndLight),
            (Control::StepTrade, Section::SpeedAccuracy),
            (Control::VirtualPixels, Section::VirtualCamera),
            (Control::ClipPlane, Section::LookingInside),
            (Control::CropBox, Section::LookingInside),
        ] {
            let guide = Guide {
                spot: Some(c),
                panel: None,
            };
            assert!(drawn(s, guide), "{c:?} opens {s:?}");
            let hidden = Guide {
                spot: Some(c),
                panel: Some(&[Section::RayCasting]),
            };
            assert!(!drawn(s, hidden), "{s:?} outside the level's panel");
        }
    }
}
