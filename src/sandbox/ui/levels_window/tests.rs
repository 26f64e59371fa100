//! Tests of levels_window.rs.

use super::*;
use crate::sandbox::levels::ProgressStore;
use crate::sandbox::ui::fonts::has_glyph;
use egui::FontFamily::{Monospace, Proportional};
use egui::{Pos2, Rect, vec2};

/// Drives the window's contents with the pointer events a player's clicks make.
struct Harness {
    ctx: egui::Context,
}

impl Harness {
    fn new() -> Self {
        let ctx = crate::sandbox::ui::fonts::context();
        // Debug builds then record each widget's label, to find buttons by their text.
        ctx.all_styles_mut(|s| s.debug.show_interactive_widgets = true);
        Self { ctx }
    }

    fn frame(
        &self,
        lessons: &mut Lessons,
        mode: Mode,
        events: Vec<egui::Event>,
    ) -> Option<LevelCommand> {
        let input = egui::RawInput {
            events,
            screen_rect: Some(Rect::from_min_size(Pos2::ZERO, vec2(600.0, 900.0))),
            ..Default::default()
        };
        let mut command = None;
        self.ctx
            .run_ui(input, |ui| {
                command = levels_ui(ui, lessons, mode, &mut false, &mut None)
            })
            .drop_without_applying_deltas();
        command
    }

    /// The rectangle and enabled state of the widget labelled `label` in the last frame.
    fn find(&self, label: &str) -> Option<(Rect, bool)> {
        self.ctx.viewport(|v| {
            let widgets = &v.prev_pass.widgets;
            widgets.layers().find_map(|(_, rects)| {
                rects.iter().find_map(|r| {
                    let info = widgets.info(r.id)?;
                    (info.label.as_deref() == Some(label)).then_some((r.rect, r.enabled))
                })
            })
        })
    }

    /// Clicks the widget labelled `label` (press and release over two frames).
    fn click(&self, lessons: &mut Lessons, mode: Mode, label: &str) -> Option<LevelCommand> {
        self.frame(lessons, mode, vec![]);
        let (rect, _) = self.find(label).unwrap_or_else(|| panic!("no “{label}”"));
        let at = rect.center();
        let button = |pressed| egui::Event::PointerButton {
            pos: at,
            button: egui::PointerButton::Primary,
            pressed,
            modifiers: Default::default(),
        };
        let pressed = self.frame(
            lessons,
            mode,
            vec![egui::Event::PointerMoved(at), button(true)],
        );
        pressed.or(self.frame(lessons, mode, vec![button(false)]))
    }
}

/// The start screen lists every level with its progress; a click starts one; Next is
/// greyed out and does nothing until the objective is met, then moves on; Free play leaves.
#[test]
fn clicks_on_the_window_send_the_levels_commands() {
    let h = Harness::new();
    let mut lessons = Lessons::new(ProgressStore::Nowhere);
    lessons.progress.record("sampling", 2);
    let title = format!("  2. {}", lessons.levels[1].title);
    h.frame(&mut lessons, Mode::FreePlay, vec![]);
    for (i, level) in lessons.levels.iter().enumerate() {
        // None done: no ● before the number.
        assert!(
            h.find(&format!("  {}. {}", i + 1, level.title)).is_some(),
            "{} listed",
            level.id
        );
    }
    assert_eq!(
        h.click(&mut lessons, Mode::FreePlay, &title),
        Some(LevelCommand::Start(1))
    );
    // In the level, at a step with an objective not yet met.
    let mode = Mode::Level(1);
    lessons.step = 1;
    lessons.met = false;
    h.frame(&mut lessons, mode, vec![]);
    assert_eq!(h.find("Next").map(|f| f.1), Some(false), "greyed out");
    assert_eq!(h.click(&mut lessons, mode, "Next"), None);
    lessons.met = true;
    assert_eq!(
        h.click(&mut lessons, mode, "Next"),
        Some(LevelCommand::Next)
    );
    assert_eq!(
        h.click(&mut lessons, mode, "Free play"),
        Some(LevelCommand::FreePlay)
    );
}

/// Every character of every level's text, every tooltip and the texts the panels build
/// has a glyph in the window's font (a missing one shows as a box, as ′, ᵢ, ∇ and → did).
#[test]
fn every_levels_text_can_be_drawn() {
    let h = Harness::new();
    let mut lessons = Lessons::new(ProgressStore::Nowhere);
    h.frame(&mut lessons, Mode::FreePlay, vec![]);
    let mut missing = Vec::new();
    for level in &lessons.levels {
        let texts = [&level.title, &level.concept]
            .into_iter()
            .chain(level.steps.iter().map(|s| &s.text));
        for text in texts {
            for c in text.chars() {
                if !has_glyph(&Proportional, c) {
                    missing.push((level.id.clone(), c));
                }
            }
        }
    }
    // The tooltips quote the tunables' documentation.
    for t in voxcast_core::tunables::ALL {
        for c in t.label.chars().chain(t.doc.chars()) {
            if !has_glyph(&Proportional, c) {
                missing.push((t.key.to_string(), c));
            }
        }
    }
    // Texts the panels build: formulas and stop reasons of the breakdown (every method,
    // both orders), why a control is greyed out, a prediction's hint.
    let mut built: Vec<String> = Vec::new();
    let volume =
        voxcast_core::Prepared::from(voxcast_core::builtin::load_builtin("voxel").unwrap().volume);
    let tf = voxcast_core::transfer::TransferFunction::ramp(0.0, 10.0, 0.5).unwrap();
    for method in voxcast_core::composite::Method::ALL {
        for order in [
            voxcast_core::composite::Order::FrontToBack,
            voxcast_core::composite::Order::BackToFront,
        ] {
            let settings = voxcast_core::settings::RenderSettings {
                method,
                order,
                target: Some(4.0),
                ..Default::default()
            };
            let ray = voxcast_core::ray::Ray::new(Vec3::new(-2.0, 0.4, 0.6), Vec3::X).unwrap();
            let scene = voxcast_core::trace::Scene::new(&volume, &tf, &settings, ray.dir).unwrap();
            let t = voxcast_core::trace::trace_ray(&scene, &ray, [0, 0]);
            built.push(voxcast_core::explain::formula(&t, None));
            built.push(t.stop.words().into());
            for why in [
                method.uses_opacity(),
                method.uses_target(),
                method.uses_shading(),
            ] {
                built.extend(why.err().map(String::from));
            }
        }
    }
    let d = voxcast_core::sample::detail_at(
        &volume,
        Vec3::splat(0.5),
        voxcast_core::sample::Interpolation::Trilinear,
    );
    built.extend(prediction_hint(99.0, &d));
    let rows = voxcast_core::worked::back_to_front(&volume, &tf, &[[0.2, 0.3, 0.8]]);
    built.extend(composite_hint(0.9, &rows));
    // The questions about the selected ray: the hints and the workings shown once answered.
    let ray = voxcast_core::ray::Ray::new(Vec3::new(-2.0, 0.43, 0.61), Vec3::new(1.0, 0.2, 0.1));
    let ray = ray.unwrap();
    let scene =
        voxcast_core::trace::Scene::new(&volume, &tf, &Default::default(), ray.dir).unwrap();
    let t = voxcast_core::trace::trace_ray(&scene, &ray, [0, 0]);
    for asked in [
        Objective::PredictSamples,
        Objective::PredictCells,
        Objective::PredictFixedCountStep {
            steps: 16,
            tolerance: 0.01,
        },
    ] {
        built.push(ray_hint(3.0, 4.0, &asked));
        let answer = voxcast_core::level::ray_answer(&asked, &t, &volume).unwrap();
        built.push(answer.working);
    }
    // (The breakdown shows its formulas in the monospace font.)
    let mut lacking = std::collections::BTreeSet::new();
    for text in &built {
        for c in text.chars().filter(|c| *c != '\n') {
            if !has_glyph(&Proportional, c) || !has_glyph(&Monospace, c) {
                lacking.insert(c);
            }
        }
    }
    assert!(lacking.is_empty(), "no glyph for {lacking:?}");
    missing.dedup();
    assert!(missing.is_empty(), "no glyph for {missing:?}");
}

/// The composite step: a wrong try is too high or too low with the points' values; the right
/// one (within the step's tolerance) meets the objective.
#[test]
fn a_wrong_composite_gets_a_hint_and_the_right_one_passes() {
    let v = voxcast_core::builtin::worked_voxel();
    let level = voxcast_core::level::Level::all()
        .into_iter()
        .find(|l| l.id == "trilinear")
        .unwrap();
    let preset = voxcast_core::preset::for_volume("voxel").unwrap();
    let Objective::PredictComposite { points, tolerance } = level
        .steps
        .iter()
        .map(|s| s.objective.clone())
        .find(|o| matches!(o, Objective::PredictComposite { .. }))
        .unwrap()
    else {
        unreachable!()
    };
    let rows = voxcast_core::worked::back_to_front(&v, &preset.transfer, &points);
    assert_eq!(rows.len(), 3);
    let red = rows[2].after[0];
    assert!(red > 0.0 && red < 1.0, "{red}");
    let high = composite_hint(red + 0.5, &rows).unwrap();
    assert!(high.contains("too high") && high.contains("P3 ="), "{high}");
    let low = composite_hint(red - 0.5, &rows).unwrap();
    assert!(low.contains("too low"), "{low}");
    let objective = Objective::PredictComposite { points, tolerance };
    let mut sit = voxcast_core::level::Situation {
        prediction: Some((red + 0.5 * tolerance, red)),
        ..Default::default()
    };
    assert!(objective.met(&sit));
    sit.prediction = Some((red + 2.0 * tolerance, red));
    assert!(!objective.met(&sit));
}

#[test]
fn a_wrong_prediction_gets_a_hint() {
    let v = voxcast_core::builtin::worked_voxel();
    let d = voxcast_core::sample::detail_at(
        &v,
        Vec3::splat(0.5),
        voxcast_core::sample::Interpolation::Trilinear,
    );
    let high = prediction_hint(d.value + 10.0, &d).unwrap();
    assert!(
        high.contains("too high") && high.contains("weight"),
        "{high}"
    );
    let low = prediction_hint(d.value - 10.0, &d).unwrap();
    assert!(low.contains("too low"), "{low}");
}

/// A prediction step takes the typed value through the text field's own events, judges
/// nothing while it is typed, and submits it on Enter: a wrong try is kept and hinted at, a
/// text that is no number is refused and kept as nothing.
#[test]
fn a_prediction_is_typed_into_the_field() {
    let h = Harness::new();
    let mut lessons = Lessons::new(ProgressStore::Nowhere);
    let l = lessons
        .levels
        .iter()
        .position(|l| l.id == "trilinear")
        .unwrap();
    lessons.step = lessons.levels[l]
        .steps
        .iter()
        .position(|s| matches!(s.objective, Objective::PredictValue { .. }))
        .unwrap();
    let v = voxcast_core::builtin::worked_voxel();
    lessons.detail = Some(voxcast_core::sample::detail_at(
        &v,
        Vec3::splat(0.5),
        voxcast_core::sample::Interpolation::Trilinear,
    ));
    let mode = Mode::Level(l);
    h.frame(&mut lessons, mode, vec![]);
    let field = h.ctx.viewport(|v| {
        let w = &v.prev_pass.widgets;
        w.layers()
            .flat_map(|(_, r)| r.iter())
            .find(|r| {
                w.info(r.id)
                    .is_some_and(|i| i.typ == egui::WidgetType::TextEdit)
            })
            .map(|r| r.rect.center())
    });
    let at = field.expect("a text field");
    let button = |pressed| egui::Event::PointerButton {
        pos: at,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: Default::default(),
    };
    h.frame(
        &mut lessons,
        mode,
        vec![egui::Event::PointerMoved(at), button(true)],
    );
    h.frame(&mut lessons, mode, vec![button(false)]);
    h.frame(&mut lessons, mode, vec![egui::Event::Text("4.5".into())]);
    assert_eq!(lessons.prediction, "4.5");
    assert_eq!(
        (lessons.tried, lessons.progress.answers.len()),
        (None, 0),
        "only typed"
    );
    let enter = |pressed| egui::Event::Key {
        key: egui::Key::Enter,
        physical_key: None,
        pressed,
        repeat: false,
        modifiers: Default::default(),
    };
    h.frame(&mut lessons, mode, vec![enter(true), enter(false)]);
    h.frame(&mut lessons, mode, vec![]);
    assert_eq!(lessons.tried, Some(4.5), "submitted with Enter");
    let [a] = &lessons.progress.answers[..] else {
        panic!("{:?}", lessons.progress.answers)
    };
    assert_eq!(
        (a.answer.as_str(), a.correct, a.attempt),
        ("4.5", false, Some(1))
    );
    assert!(a.seconds.is_some());
    lessons.prediction = "four".into();
    assert_eq!(lessons.submit_prediction(l), None);
    assert!(lessons.message.as_deref().unwrap().contains("not a number"));
    assert_eq!(
        lessons.progress.answers.len(),
        1,
        "a text that is no number is no try"
    );
    lessons.prediction = "4,99".into();
    assert_eq!(lessons.submit_prediction(l), Some(true));
    let kept: Vec<(Option<u32>, bool)> = lessons
        .progress
        .answers
        .iter()
        .map(|a| (a.attempt, a.correct))
        .collect();
    assert_eq!(kept, [(Some(1), false), (Some(2), true)]);
}
