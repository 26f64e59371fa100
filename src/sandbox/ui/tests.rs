//! The panel's tests: its words, its glyphs and its widgets' behaviour.

use super::*;

/// The settings panel's sections for one method, with what they edit: the panel as the
/// tests below read it.
struct Panel {
    volume: VolumeState,
    edited: RenderState,
    s: RenderSettings,
    preview: PreviewSettings,
    state: PanelState,
    loading: Loading,
    depth: bool,
    live: crate::sandbox::preview::live::LiveView,
    step_trade: crate::sandbox::checks::trade::StepTrade,
    /// Every classification, each drawn with its controls.
    classifications: Vec<voxcast_core::classify::Classification>,
}

impl Panel {
    fn new(method: Method) -> Self {
        use voxcast_core::classify::{Classification, Region};
        let (volume, edited) = crate::sandbox::inspect::rays::tests::scene("head");
        let mut s = edited.settings.clone();
        s.method = method;
        s.clip.plane = Some(voxcast_core::clip::ClipPlane {
            normal: Vec3::X,
            position: 0.2,
        });
        let (lo, hi) = volume.volume.value_range();
        let classifications = vec![
            Classification::default(),
            Classification::IsoContours {
                isovalues: vec![40.0, 140.0],
                thickness_voxels: 1.0,
            },
            Classification::Boundaries {
                full_gradient: Some(10.0),
            },
            Classification::ValueGradient {
                regions: vec![Region {
                    value: [lo, hi],
                    gradient: [0.0, 1.0],
                    opacity: 0.5,
                }],
            },
        ];
        Self {
            volume,
            edited,
            s,
            preview: PreviewSettings {
                backend: crate::sandbox::shared::quality::Backend::Cpu,
                ..Default::default()
            },
            state: PanelState::default(),
            loading: Loading::default(),
            depth: true,
            live: Default::default(),
            step_trade: Default::default(),
            classifications,
        }
    }

    /// Every section this fixture has the state for, one below the other.
    fn draw(&mut self, ui: &mut egui::Ui) {
        for section in SECTIONS {
            self.draw_section(ui, section);
        }
    }

    /// One section's body.
    fn draw_section(&mut self, ui: &mut egui::Ui, section: Section) {
        let volume = &self.volume;
        match section {
            Section::Dataset => {
                dataset_section(ui, &mut self.state, volume, &mut self.loading);
            }
            Section::RayCasting => ray_section(ui, &mut self.s, volume, None),
            Section::ShadingAndLight => shading_section(ui, &mut self.s, volume, None),
            Section::TransferFunction => {
                preset_menu(ui, &mut self.edited, &volume.volume);
                self.state.editor.show(
                    ui,
                    &mut self.edited.transfer,
                    &volume.volume,
                    &volume.source,
                );
                for (i, c) in self.classifications.iter_mut().enumerate() {
                    ui.push_id(i, |ui| {
                        classify::classification_controls(
                            ui,
                            c,
                            &mut self.state.classify,
                            &volume.volume,
                            &volume.source,
                        )
                    });
                }
            }
            Section::SpeedAccuracy => {
                trade::trade_section(ui, &mut self.step_trade, false, 0.5, None);
            }
            Section::Preview => {
                first_preview_section(ui, &mut self.preview, &self.live, &mut self.depth);
            }
            Section::LookingInside => {
                let mut handles = crate::sandbox::scene::cut::CutHandles { crop: true };
                cut::cut_section(ui, &mut self.s.clip, &mut handles, Some(Vec3::Z), None);
            }
            Section::VirtualCamera | Section::RayData => {
                unreachable!("{section:?}: not among SECTIONS")
            }
        }
    }
}

/// The sections [`Panel`] draws (the virtual camera's and the ray data's need the scene).
const SECTIONS: [Section; 7] = [
    Section::Dataset,
    Section::RayCasting,
    Section::ShadingAndLight,
    Section::TransferFunction,
    Section::SpeedAccuracy,
    Section::Preview,
    Section::LookingInside,
];

/// Every string the settings panel's sections draw (for every method: the greyed-out
/// reasons change with it; every classification) has a glyph in the window's font.
#[test]
fn every_panel_string_can_be_drawn() {
    for method in Method::ALL {
        let mut panel = Panel::new(method);
        let missing = missing_glyphs(|ui| panel.draw(ui));
        assert!(missing.is_empty(), "{method:?}: no glyph for {missing:?}");
    }
}

/// The shading weights show two decimals at every value, their ends included (egui's own
/// choice follows the pointer's resolution at the slider's place: it showed 0.000 at an end
/// beside 0.70 between), and the opacity cutoff three (its thousandths bound a pixel's error).
#[test]
fn sliders_show_the_decimals_their_values_mean() {
    let (volume, render) = crate::sandbox::inspect::rays::tests::scene("head");
    let mut s = render.settings.clone();
    let p = &mut s.phong;
    (p.ke, p.global_ambient, p.ka, p.kd, p.ks) = (0.0, 1.0, 0.0, 0.7, 0.3);
    s.cutoff = 0.99;
    let text = drawn_text(|ui| {
        ray_section(ui, &mut s, &volume, None);
        shading_section(ui, &mut s, &volume, None);
    });
    let numbers: Vec<&str> = text.lines().filter(|l| l.parse::<f32>().is_ok()).collect();
    for shown in ["0.00", "1.00", "0.70", "0.30", "0.990"] {
        assert!(numbers.contains(&shown), "{shown} not among {numbers:?}");
    }
    for wrong in ["0.000", "1.000", "0.700"] {
        assert!(!numbers.contains(&wrong), "{wrong} among {numbers:?}");
    }
}

/// A logarithmic slider shows four significant digits, as the breakdown prints numbers: a
/// point light's attenuation at 0 and at a small value, the step at half a voxel.
#[test]
fn logarithmic_sliders_show_significant_digits() {
    let (volume, render) = crate::sandbox::inspect::rays::tests::scene("head");
    let mut s = render.settings.clone();
    s.step = Length::Voxels(0.5);
    let light = &mut s.phong.lights[0];
    light.light = voxcast_core::shade::Light::Point(Vec3::splat(100.0));
    (light.kl, light.kq) = (0.0, 0.000_123_4);
    let text = drawn_text(|ui| {
        ray_section(ui, &mut s, &volume, None);
        shading_section(ui, &mut s, &volume, None);
    });
    let lines: Vec<&str> = text.lines().collect();
    for shown in ["0.5", "0", "1.234e-4"] {
        assert!(lines.contains(&shown), "{shown} not among {lines:?}");
    }
    assert!(
        !lines.iter().any(|l| l.starts_with("0.0000")),
        "six decimals among {lines:?}"
    );
}

/// Whether `s`'s body is drawn under `guide` (closed by default).
fn drawn(s: Section, guide: Guide) -> bool {
    let ctx = crate::sandbox::ui::fonts::context();
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

/// The settings panel's sections fit it at its narrowest: a long label is shortened, not
/// left to widen the panel past the window (which cut every row at the right); and no row
/// takes all the height it is given.
#[test]
fn the_sections_fit_the_narrowest_settings_panel() {
    let (volume, render) = crate::sandbox::inspect::rays::tests::scene("head");
    let mut s = render.settings.clone();
    let mut edited = render.clone();
    let mut panel = PanelState::default();
    let mut loading = Loading::default();
    let room = narrowest_section_room();
    let width = |name: &str, add: &mut dyn FnMut(&mut egui::Ui)| {
        let size = size_in(room, add);
        assert!(
            size.x <= room + 0.5,
            "{name}: {} points wide in {room}",
            size.x
        );
        assert!(size.y < COLUMN / 2.0, "{name}: {} points high", size.y);
    };
    width("dataset", &mut |ui| {
        dataset_section(ui, &mut panel, &volume, &mut loading);
    });
    width("ray casting", &mut |ui| {
        ray_section(ui, &mut s, &volume, None)
    });
    width("shading", &mut |ui| {
        shading_section(ui, &mut s, &volume, None)
    });
    width("transfer", &mut |ui| {
        preset_menu(ui, &mut edited, &volume.volume);
        panel
            .editor
            .show(ui, &mut edited.transfer, &volume.volume, &volume.source);
    });
    let mut handles = crate::sandbox::scene::cut::CutHandles { crop: true };
    s.clip.plane = Some(voxcast_core::clip::ClipPlane {
        normal: Vec3::new(1.0, 1.0, 0.0).normalize(),
        position: 0.2,
    });
    width("looking inside", &mut |ui| {
        cut::cut_section(ui, &mut s.clip, &mut handles, Some(Vec3::Z), None)
    });
    let mut preview = PreviewSettings::default();
    let live = crate::sandbox::preview::live::LiveView::default();
    let mut depth = true;
    width("preview", &mut |ui| {
        first_preview_section(ui, &mut preview, &live, &mut depth)
    });
}

/// The preview section as it reads with First chosen (its depth option shown).
fn first_preview_section(
    ui: &mut egui::Ui,
    preview: &mut PreviewSettings,
    live: &crate::sandbox::preview::live::LiveView,
    depth: &mut bool,
) {
    preview_section(ui, preview, Some(live), depth, Method::First, None);
}

/// Drawing a slider leaves its value as it is, whatever decimals it shows: a preview scale of
/// 0.125 (Measure's cheapest moving frame, set while it times it) and a crop side dragged in
/// the scene to 0.3333 stay exactly that (egui's `fixed_decimals` rounded them to 0.12 and
/// 0.33 at the first frame, and Measure stopped: "the preview changed while it was timed").
#[test]
fn drawing_a_slider_leaves_its_value() {
    let (mut scale, mut side) = (0.125f32, 1.0f32 / 3.0);
    let mut changed = false;
    let text = drawn_text(|ui| {
        changed |= slider(ui, &mut scale, &t::PREVIEW_SCALE, 0.05..=1.0, false);
        changed |= ui
            .add(shown_with(
                egui::Slider::new(&mut side, 0.0..=1.0),
                FINE_DECIMALS,
            ))
            .changed();
    });
    assert_eq!((scale, side, changed), (0.125, 1.0 / 3.0, false));
    assert!(text.lines().any(|l| l == "0.33"), "{text}");
}

/// Every panel control a level points at ("Look at: Settings › Ray casting › …") is drawn in
/// the panel by the very name the level gives it, so a student can find it by reading. (The
/// rest are named by what they are: "the lights", "the editor", "the views".)
#[test]
fn the_levels_name_each_control_as_the_panel_shows_it() {
    for c in [
        Control::Method,
        Control::Step,
        Control::OpacityCorrection,
        Control::EarlyTermination,
        Control::Target,
        Control::SumRange,
        Control::Order,
        Control::Jitter,
        Control::Interpolation,
        Control::Supersampling,
        Control::Skipping,
        Control::Shading,
        Control::CropBox,
        Control::ClipPlane,
        Control::PreviewScale,
        Control::PreviewOn,
        Control::PreviewView,
        Control::Classification,
        Control::StepTrade,
    ] {
        let section = c.section().expect("a control of the panel");
        // Every method: some controls are greyed out, but drawn, under others.
        let mut text = String::new();
        for method in Method::ALL {
            let mut panel = Panel::new(method);
            text.push_str(&drawn_text(|ui| panel.draw_section(ui, section)));
        }
        let name = super::levels_window::control_name(c);
        let label = name.rsplit(" › ").next().unwrap_or(&name);
        assert!(
            text.lines().any(|l| l == label || l == format!("{label}:")),
            "{c:?}: the level says {name:?}, its section shows no {label:?}"
        );
    }
}

/// The virtual camera's section: its field of view in tenths of a degree (egui's own choice
/// showed 61.54°), and the pixel sliders a level names as "pixels across and down".
#[test]
fn the_virtual_camera_shows_its_angle_in_tenths() {
    let (volume, render) = crate::sandbox::inspect::rays::tests::scene("head");
    let mut vc = VirtualCamera::framing(&volume, None).expect("a camera framing the head");
    let v = vc.view;
    vc.view = voxcast_core::camera::Camera::new(
        v.eye,
        v.target,
        v.up,
        voxcast_core::camera::Projection::Perspective {
            fov_y_deg: 61.538_46,
        },
    )
    .unwrap();
    let mut world = World::new();
    let id = world.spawn(vc).id();
    let mut settings = render.settings.clone();
    let text = drawn_text(|ui| {
        let mut camera = world.get_mut::<VirtualCamera>(id).unwrap();
        virtual_camera_section(ui, &mut camera, &mut settings, None, &volume, None);
    });
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines.contains(&"61.5"), "no 61.5 among {lines:?}");
    assert!(!lines.contains(&"61.54"), "61.54 among {lines:?}");
    let name = super::levels_window::control_name(Control::VirtualPixels);
    for part in ["pixels across", "pixels down"] {
        assert!(lines.contains(&part), "no {part:?} among {lines:?}");
    }
    assert!(
        name.ends_with("› pixels across and down"),
        "the level says {name:?}"
    );
    let after = world.get::<VirtualCamera>(id).unwrap();
    assert_eq!(
        crate::sandbox::inspect::virtual_camera::fov(&after.view),
        Some(61.538_46),
        "drawing leaves the angle"
    );
}
