//! The settings panel's sections: dataset, ray casting, shading, presets, the virtual camera
//! and the preview.

use super::*;

/// The volume's name and description, the embedded list and the path field; returns the
/// source to load, if one was chosen.
pub(super) fn dataset_section(
    ui: &mut egui::Ui,
    panel: &mut PanelState,
    volume: &VolumeState,
    loading: &mut Loading,
) -> Option<String> {
    ui.label(dataset_words(volume.volume.name(), &volume.source))
        .on_hover_text(format!(
            "The volume {} from {}",
            volume.volume.name(),
            volume.source
        ));
    if let Some(p) = &volume.preset {
        ui.label(egui::RichText::new(&p.description).small());
    }
    let embedded = embedded_menu(ui);
    let typed = if crate::sandbox::shared::files::PICKS_FILES {
        // A page reads no paths: the browser's picker (or a file dropped on the page).
        if ui
            .button("Open a volume file…")
            .on_hover_text(
                "A .nrrd, .nii, .nii.gz or .raw file from this computer (or drop one on the \
                 page); a detached .nhdr or a .hdr with its data file: choose both together",
            )
            .clicked()
        {
            crate::sandbox::shared::files::pick(crate::sandbox::shared::files::Purpose::Volume);
        }
        None
    } else {
        path_row(ui, &mut panel.path)
    };
    loading_state(ui, loading);
    embedded.or(typed)
}

/// The embedded datasets and the Cornell box's ray densities, in one menu: the source chosen.
fn embedded_menu(ui: &mut egui::Ui) -> Option<String> {
    let mut load = None;
    combo(ui, "Embedded", "choose…", |ui| {
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
    load
}

/// The desktop's path field and Load (or Enter): the path typed, once it is asked for.
fn path_row(ui: &mut egui::Ui, path: &mut String) -> Option<String> {
    // Nothing to load until a path is typed (an empty one read as ": unknown file format").
    let typed = path_to_load(path).is_some();
    let (field, clicked) = field_row(ui, path, |ui| {
        ui.add_enabled(typed, egui::Button::new("Load"))
            .on_disabled_hover_text("Type a file's path in the field first")
            .clicked()
    });
    // Enter in the field loads it too, as a student who typed a path expects.
    let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
    field.on_hover_text(
        "A .nrrd, .nhdr, .nii, .nii.gz, .hdr or .raw file (or drop one on the window); \
         or a ray density: density:FILE.rayvis or density:builtin:cornell, optionally \
         followed by @cell=S,trace=ID,filter=all|hit|miss,chunk=N,tolerance=T",
    );
    (clicked || entered).then(|| path_to_load(path)).flatten()
}

/// A load under way (its share, its time, Cancel), the last load's error, and its note.
fn loading_state(ui: &mut egui::Ui, loading: &mut Loading) {
    if let Some((what, seconds)) = loading.under_way() {
        let mut cancel = false;
        ui.horizontal(|ui| {
            ui.spinner();
            let share = loading.fraction().map_or(String::new(), |f| {
                format!("{}, ", voxcast_core::numbers::percent(f))
            });
            // Cancel and the figures before the name: a long name pushes what follows it off
            // the panel.
            cancel = super::target(ui.button("Cancel"), "Cancel loading").clicked();
            ui.label(format!("{share}{seconds:.1} s: loading {what}"));
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
}

/// Method, step, interpolation, opacity correction, termination, jitter and the target.
pub(super) fn ray_section(
    ui: &mut egui::Ui,
    s: &mut RenderSettings,
    volume: &VolumeState,
    spot: Spot,
) {
    marked(ui, spot, Control::Method, |ui| {
        combo(ui, "Method", s.method.title(), |ui| {
            for m in Method::ALL {
                ui.selectable_value(&mut s.method, m, m.title())
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
    compositing_controls(ui, s, voxel, spot);
    marked(ui, spot, Control::Skipping, |ui| {
        checkbox(ui, &mut s.skipping, &t::SKIPPING)
    });
    marked(ui, spot, Control::Jitter, |ui| {
        checkbox(ui, &mut s.jitter, &t::JITTER)
    });
    marked(ui, spot, Control::Supersampling, |ui| {
        // Whole rays: an integer slider (1 to 4: 16 rays a pixel is already 16 times the work).
        tunable_slider(
            ui,
            egui::Slider::new(&mut s.supersampling, 1..=4),
            &t::SUPERSAMPLING,
        )
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

/// What applies to methods that use opacity (greyed out for the others, their tooltip saying
/// why): opacity correction and its reference step, early termination, the order, and the
/// cutoff (which also needs early termination, front to back).
fn compositing_controls(ui: &mut egui::Ui, s: &mut RenderSettings, voxel: f32, spot: Spot) {
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
            combo(ui, "Order", s.order.name(), |ui| {
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
        // Thousandths: 1 − cutoff bounds each pixel's error, and 0.999 is a setting to try.
        let cutoff = shown_with(egui::Slider::new(&mut s.cutoff, 0.0..=1.0), 3);
        tunable_slider(ui, cutoff, &t::CUTOFF);
    });
}

/// Sum's range: two ends, each on a logarithmic slider up to four times the default top (the
/// most a ray along the longest side can gather); the low end stays below the high end.
pub(super) fn sum_range(
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
        // Low end above high end, as a range reads; the low end's slider stops below the
        // high end as it stood, and the clamp below keeps it there if the high end moves.
        let (floor, log) = (0.0f32.min(a), a >= 0.0);
        let low = labelled(
            ui,
            significant(egui::Slider::new(&mut a, floor..=b - tiny).logarithmic(log)),
            "low end",
        )
        .on_hover_text(t::SUM_RANGE.doc);
        let high = labelled(
            ui,
            significant(egui::Slider::new(&mut b, tiny..=top).logarithmic(true)),
            "high end",
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

/// Phong's coefficients and the light.
pub(super) fn shading_section(
    ui: &mut egui::Ui,
    s: &mut RenderSettings,
    volume: &VolumeState,
    spot: Spot,
) {
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
pub(super) fn preset_menu(
    ui: &mut egui::Ui,
    edited: &mut RenderState,
    volume: &voxcast_core::Volume,
) {
    use voxcast_core::colormap::{INFERNO_DOC, INFERNO_PRESET, inferno_transfer};
    combo(ui, "Preset", edited.transfer.name.clone(), |ui| {
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
pub(super) fn virtual_camera_section(
    ui: &mut egui::Ui,
    vc: &mut Mut<VirtualCamera>,
    settings: &mut RenderSettings,
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
            labelled(
                ui,
                egui::Slider::new(value, range.clone()),
                format!("pixels {axis}"),
            )
            .on_hover_text(t::VIRTUAL_RESOLUTION.doc);
        }
    });
    if let Some(mut fov) = crate::sandbox::inspect::virtual_camera::fov(&edited.view) {
        let changed = labelled(
            ui,
            // Tenths of a degree: a student drags it; hundredths said nothing more.
            shown_with(egui::Slider::new(&mut fov, 5.0..=120.0), 1),
            "field of view (°)",
        )
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
pub(super) fn preview_section(
    ui: &mut egui::Ui,
    preview: &mut PreviewSettings,
    live: Option<&crate::sandbox::preview::live::LiveView>,
    depth: &mut bool,
    method: Method,
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
            (crate::sandbox::shared::quality::Backend::Gpu, "GPU"),
            (crate::sandbox::shared::quality::Backend::Cpu, "CPU"),
        ] {
            ui.selectable_value(&mut q.backend, backend, name)
                .on_hover_text(t::PREVIEW_BACKEND.doc);
        }
    });
    marked(ui, spot, Control::PreviewView, |ui| {
        cost_view::choice(ui, &cost_view::PREVIEW, &mut q.cost_view, method)
    });
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
    let gpu = q.backend == crate::sandbox::shared::quality::Backend::Gpu;
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
    let tip = if crate::sandbox::shared::quality::GPU_READS_DEPTH {
        "Depth-prepass termination: preview rays end where an opaque mesh stands inside the volume"
    } else {
        "Preview rays end where an opaque mesh stands inside the volume: in the CPU live view and \
         Render image. In this browser (WebGL2) the GPU preview cannot read the depth prepass: \
         its rays pass through the meshes, drawn over it (WebGPU can)"
    };
    ui.checkbox(depth, "Stop rays at scene geometry")
        .on_hover_text(tip);
}

/// What the path field asks to load: the path without the spaces a paste leaves around it, or
/// nothing while it is blank.
fn path_to_load(field: &str) -> Option<String> {
    let path = field.trim();
    (!path.is_empty()).then(|| path.to_string())
}

/// The loaded dataset in words: an embedded one by its description (`bunny_sdf
/// (builtin:bunny)` read as code), a ray density of embedded rays by their name in the ray
/// data's list (and its trace), anything else by its name and where it came from.
fn dataset_words(name: &str, source: &str) -> String {
    use crate::sandbox::data::source::SourceKind;
    use voxcast_core::numbers::capitalised;
    if let Some(Ok(spec)) = voxcast_core::rays::as_volume::parse(source) {
        let rays = SourceKind::ALL
            .into_iter()
            .find(|k| k.builtin() == Some(spec.source.as_str()));
        return match (rays, spec.trace) {
            (Some(k), Some(trace)) => format!("Ray density of the {}, trace {trace}", k.words()),
            (Some(k), None) => format!("Ray density of the {}", k.words()),
            (None, _) => capitalised(name),
        };
    }
    source
        .strip_prefix("builtin:")
        .and_then(|b| DATASETS.iter().find(|(n, _)| *n == b))
        .map(|(_, what)| capitalised(what))
        .unwrap_or_else(|| format!("{name} ({source})"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_blank_path_loads_nothing_and_a_pasted_one_loses_its_spaces() {
        assert_eq!(path_to_load(""), None);
        assert_eq!(path_to_load("  \t\n"), None);
        assert_eq!(
            path_to_load(" /data/ct.nrrd\n").as_deref(),
            Some("/data/ct.nrrd")
        );
    }

    #[test]
    fn an_embedded_dataset_is_named_in_words() {
        assert_eq!(
            dataset_words("bunny_sdf", "builtin:bunny"),
            "Stanford bunny as a smooth density, surface at 128 (128×126×101, uint8)"
        );
        assert_eq!(
            dataset_words("shells", "builtin:shells"),
            "Concentric spherical shells (64³, uint8)"
        );
        assert_eq!(
            dataset_words(
                "ray density of builtin:cornell (trace 2)",
                "density:builtin:cornell@trace=2"
            ),
            "Ray density of the Cornell box (embedded), trace 2"
        );
        // The million-ray box by its own words (a text replace once read "Cornell box-1m").
        assert_eq!(
            dataset_words(
                "ray density of builtin:cornell-1m",
                "density:builtin:cornell-1m"
            ),
            "Ray density of the Cornell box, a million rays"
        );
        assert_eq!(
            dataset_words("ray density of r.rayvis", "density:r.rayvis"),
            "Ray density of r.rayvis"
        );
        // A file or an unknown name keeps the name and where it came from.
        assert_eq!(dataset_words("ct", "/data/ct.nrrd"), "ct (/data/ct.nrrd)");
        assert_eq!(dataset_words("x", "builtin:nope"), "x (builtin:nope)");
        for (name, _) in DATASETS {
            let words = dataset_words("v", &format!("builtin:{name}"));
            assert!(words.starts_with(|c: char| c.is_uppercase()), "{words}");
        }
    }
}
