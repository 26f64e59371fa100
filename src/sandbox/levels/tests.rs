//! The levels' logic tested in a windowless app: commands, progress, studies, objectives.

use super::*;
use crate::sandbox::inspect::rays::{Inspection, SampleSphere};
use crate::sandbox::scene::light::LightMarker;
use bevy::tasks::{AsyncComputeTaskPool, TaskPool};
use bevy::window::FileDragAndDrop;
use voxcast_core::composite::Method;

/// The sandbox's level logic and spawners without a window or a GPU.
fn app(progress: PathBuf) -> App {
    AsyncComputeTaskPool::get_or_init(TaskPool::new);
    let (volume, render) = crate::sandbox::inspect::rays::tests::scene("bucky");
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, bevy::state::app::StatesPlugin))
        .insert_resource(volume)
        .insert_resource(render)
        .init_resource::<Assets<Mesh>>()
        .init_resource::<Assets<StandardMaterial>>()
        .add_message::<FileDragAndDrop>()
        .init_resource::<PreviewSettings>()
        .init_resource::<BreakdownState>()
        .init_resource::<Comparison>()
        .insert_resource(Lessons::new(ProgressStore::File(progress)))
        .add_plugins((
            crate::sandbox::shared::mode::plugin,
            crate::sandbox::shared::render_change::plugin,
            crate::sandbox::data::loading::plugin,
            crate::sandbox::inspect::rays::plugin,
            crate::sandbox::scene::light::marker_plugin,
            crate::sandbox::checks::trade::plugin,
            plugin,
        ))
        .add_systems(
            Update,
            crate::sandbox::inspect::virtual_camera::stage_camera,
        );
    crate::sandbox::shared::schedule::configure(&mut app);
    app
}

/// Runs frames until `done` holds (a level's volume loads on the task pool).
fn until(app: &mut App, done: impl Fn(&mut App) -> bool) {
    for _ in 0..500 {
        app.update();
        if done(app) {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    panic!("not reached");
}

fn entities<C: Component>(app: &mut App) -> Vec<Entity> {
    let mut q = app.world_mut().query_filtered::<Entity, With<C>>();
    q.iter(app.world()).collect()
}

fn mode(app: &App) -> Mode {
    *app.world().resource::<State<Mode>>().get()
}

fn level(app: &App, id: &str) -> usize {
    let lessons = app.world().resource::<Lessons>();
    lessons.levels.iter().position(|l| l.id == id).unwrap()
}

fn send(app: &mut App, c: LevelCommand) {
    app.world_mut().write_message(c);
    app.update();
    app.update();
}

/// A prediction done and an effect named are kept as answers, with what the code
/// computes, saved with the progress and exported as CSV.
#[test]
fn answers_are_kept_with_the_progress() {
    let dir = std::env::temp_dir().join(format!("voxcast-answers-{}", std::process::id()));
    let path = dir.join("progress.json");
    let mut app = app(path.clone());
    let trilinear = level(&app, "trilinear");
    send(&mut app, LevelCommand::Start(trilinear));
    // The step is met (read) once its scene is on screen, which the check sees after the
    // volume's frame: Next before that is refused, as the window's button would be.
    until(&mut app, |a| {
        a.world().resource::<VolumeState>().source == "builtin:voxel"
            && a.world().resource::<Lessons>().met
    });
    send(&mut app, LevelCommand::Next); // step 1 is read
    until(&mut app, |a| {
        a.world().resource::<Lessons>().detail.is_some()
    });
    // Typed, not judged; a wrong try is kept and does not meet the step; the right one does.
    app.world_mut().resource_mut::<Lessons>().prediction = "4,99".into();
    app.update();
    assert!(
        !app.world().resource::<Lessons>().met,
        "typed is not submitted"
    );
    app.world_mut().resource_mut::<Lessons>().prediction = "5.2".into();
    assert_eq!(
        app.world_mut()
            .resource_mut::<Lessons>()
            .submit_prediction(trilinear),
        Some(false)
    );
    app.update();
    assert!(!app.world().resource::<Lessons>().met, "a wrong try");
    app.world_mut().resource_mut::<Lessons>().prediction = "4,99".into();
    app.world_mut()
        .resource_mut::<Lessons>()
        .submit_prediction(trilinear);
    until(&mut app, |a| a.world().resource::<Lessons>().met);
    send(&mut app, LevelCommand::Next);
    let lessons = app.world().resource::<Lessons>();
    let [wrong, right] = &lessons.progress.answers[..] else {
        panic!("{:?}", lessons.progress.answers)
    };
    assert_eq!((right.level.as_str(), right.step), ("trilinear", 2));
    assert_eq!(right.question, "the value at (0.5, 0.5, 0.5)");
    assert_eq!(
        (
            right.answer.as_str(),
            right.expected.as_str(),
            right.correct
        ),
        ("4,99", "4.988", true)
    );
    assert_eq!((wrong.answer.as_str(), wrong.correct), ("5.2", false));
    assert_eq!((wrong.attempt, right.attempt), (Some(1), Some(2)));
    // Naming an effect: a wrong choice and the right one, both kept.
    let mut lessons = app.world_mut().resource_mut::<Lessons>();
    lessons.name_effect(trilinear, 2, 1);
    lessons.name_effect(trilinear, 1, 1);
    let kept = &lessons.progress.answers;
    assert_eq!(kept.len(), 4);
    assert!(!kept[2].correct && kept[3].correct);
    assert_eq!(kept[2].answer, "reflection rays");
    assert_eq!(kept[2].expected, "primary rays");
    let (saved, _) = Progress::load(&path);
    assert_eq!(&saved.answers, kept);
    let csv = saved.answers_csv();
    assert_eq!(csv.lines().count(), 5, "{csv}");
    let first = csv.lines().nth(2).unwrap();
    let quoted = "trilinear,2,\"the value at (0.5, 0.5, 0.5)\",\"4,99\",4.988,yes,";
    assert!(first.starts_with(quoted), "{csv}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A study plays the level twice: the preview held off in the first run (whatever the
/// player turns on), on in the second, from the first step again; each answer is kept
/// with its run's name; after the second run, free play. `--study` names a level by id or
/// number.
#[test]
fn a_study_plays_the_level_with_the_preview_off_then_on() {
    use voxcast_core::classify::{Classification, Region};
    let dir = std::env::temp_dir().join(format!("voxcast-study-{}", std::process::id()));
    let mut app = app(dir.join("progress.json"));
    let l = level(&app, "value-gradient");
    let all = Level::all();
    assert_eq!(level_named(&all, "value-gradient"), Ok(l));
    assert_eq!(level_named(&all, &(l + 1).to_string()), Ok(l));
    assert!(
        level_named(&all, "nope")
            .unwrap_err()
            .contains("value-gradient")
    );
    send(&mut app, LevelCommand::Study(l));
    until(&mut app, |a| {
        a.world().resource::<VolumeState>().source == "builtin:head"
    });
    let preview = |app: &App| app.world().resource::<PreviewSettings>().enabled;
    let play_through = |app: &mut App| {
        send(app, LevelCommand::Next); // read
        app.world_mut()
            .resource_mut::<RenderState>()
            .settings
            .classification = Classification::ValueGradient { regions: vec![] };
        until(app, |a| a.world().resource::<Lessons>().met);
        send(app, LevelCommand::Next);
        app.world_mut()
            .resource_mut::<RenderState>()
            .settings
            .classification = Classification::ValueGradient {
            regions: vec![Region {
                value: [100.0, 120.0],
                gradient: [0.0, 30.0],
                opacity: 0.6,
            }],
        };
        until(app, |a| a.world().resource::<Lessons>().met);
        app.world_mut()
            .resource_mut::<Lessons>()
            .name_effect(l, 1, 1);
        send(app, LevelCommand::Next);
    };
    assert!(!preview(&app));
    app.world_mut().resource_mut::<PreviewSettings>().enabled = true;
    app.update();
    assert!(!preview(&app), "held off in the first run");
    play_through(&mut app);
    let lessons = app.world().resource::<Lessons>();
    assert_eq!(lessons.study, Some(StudyRun::PreviewOn));
    assert_eq!((mode(&app), lessons.step), (Mode::Level(l), 0));
    assert!(lessons.message.as_deref().unwrap().contains("run 2 of 2"));
    assert!(preview(&app), "on in the second");
    play_through(&mut app);
    let lessons = app.world().resource::<Lessons>();
    assert_eq!(mode(&app), Mode::FreePlay);
    assert_eq!(lessons.study, None);
    assert!(lessons.message.as_deref().unwrap().contains("both runs"));
    let runs: Vec<Option<&str>> = lessons
        .progress
        .answers
        .iter()
        .map(|a| a.run.as_deref())
        .collect();
    assert_eq!(runs, [Some("preview off"), Some("preview on")]);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A study question answered wrong, then right: both kept, and only the right one meets
/// the step.
#[test]
fn study_answers_are_kept_and_only_the_right_one_counts() {
    let mut lessons = Lessons::new(ProgressStore::Nowhere);
    let l = lessons
        .levels
        .iter()
        .position(|l| l.id == "which-effect")
        .unwrap();
    let camera = voxcast_core::rays::study::CameraPlace::FrontHigher.words();
    lessons.answer_study(l, (1, "camera"), "inside the box", camera);
    assert_eq!(lessons.studied, None);
    lessons.answer_study(l, (1, "camera"), camera, camera);
    assert_eq!(lessons.studied, Some((1, "camera".to_string())));
    let kept: Vec<(bool, &str)> = lessons
        .progress
        .answers
        .iter()
        .map(|a| (a.correct, a.question.as_str()))
        .collect();
    let q = "where was the camera of trace 1";
    assert_eq!(kept, [(false, q), (true, q)]);
    let objective = Objective::StudyQuestion {
        trace: 1,
        question: "camera".into(),
    };
    let sit = Situation {
        studied: lessons.studied.clone(),
        ..Situation::default()
    };
    assert!(objective.met(&sit));
}

/// What the breakdown hides through the sampling level: nothing in free play; the cells'
/// number from the first step until the step that asks for it is done (it does not change with
/// the settings, so an earlier step would give it away); the sample count, formula and export
/// only while the count is asked.
#[test]
fn the_sampling_level_hides_each_count_until_it_is_answered() {
    let mut lessons = Lessons::new(ProgressStore::Nowhere);
    let l = lessons
        .levels
        .iter()
        .position(|l| l.id == "sampling")
        .unwrap();
    let asks = |lessons: &Lessons, f: fn(&Objective) -> bool| {
        lessons.levels[l]
            .steps
            .iter()
            .position(|s| s.objective.parts().into_iter().any(f))
            .unwrap()
    };
    let samples = asks(&lessons, |o| matches!(o, Objective::PredictSamples));
    let cells = asks(&lessons, |o| matches!(o, Objective::PredictCells));
    assert!(samples < cells);
    assert_eq!(lessons.hidden(Mode::FreePlay), None);
    let at = |lessons: &mut Lessons, step: usize, met: bool| {
        (lessons.step, lessons.met) = (step, met);
        lessons.hidden(Mode::Level(l)).unwrap_or_default()
    };
    let first = at(&mut lessons, 0, false);
    assert!(first.cells && !first.samples && !first.hides_working());
    let counting = at(&mut lessons, samples, false);
    assert!(counting.cells && counting.samples && counting.hides_working());
    let counted = at(&mut lessons, samples, true);
    assert!(counted.cells && !counted.samples && !counted.hides_working());
    assert!(at(&mut lessons, cells, false).cells);
    assert_eq!(at(&mut lessons, cells, true), Hidden::default());
    assert_eq!(at(&mut lessons, cells + 1, false), Hidden::default());
}

/// Levels are states: starting one spawns only what its scene holds, and what free play
/// spawned (virtual camera, body, sample spheres, light marker) leaves; Next is refused
/// until the objective is met by the state a control edits; the last Next records the
/// progress on disk and returns to free play, which spawns its own scene again.
#[test]
fn a_level_spawns_its_scene_and_everything_leaves_with_it() {
    let dir = std::env::temp_dir().join(format!("voxcast-levels-{}", std::process::id()));
    let path = dir.join("progress.json");
    let mut app = app(path.clone());
    until(&mut app, |a| !entities::<SampleSphere>(a).is_empty());
    assert_eq!(mode(&app), Mode::FreePlay);
    let free: Vec<Entity> = [
        entities::<VirtualCamera>(&mut app),
        entities::<LightMarker>(&mut app),
        entities::<SampleSphere>(&mut app),
    ]
    .concat();
    assert_eq!(entities::<VirtualCamera>(&mut app).len(), 1);
    assert_eq!(
        entities::<LightMarker>(&mut app).len(),
        voxcast_core::shade::MAX_LIGHTS
    );

    // The trilinear level: the 2³ voxel, one ray, no preview, no light marker.
    let trilinear = level(&app, "trilinear");
    send(&mut app, LevelCommand::Start(trilinear));
    until(&mut app, |a| {
        a.world().resource::<VolumeState>().source == "builtin:voxel"
            && a.world().resource::<Lessons>().scene_ready()
            && !entities::<SampleSphere>(a).is_empty()
    });
    assert_eq!(mode(&app), Mode::Level(trilinear));
    for e in &free {
        assert!(
            app.world().get_entity(*e).is_err(),
            "{e} left with free play"
        );
    }
    let vcs = entities::<VirtualCamera>(&mut app);
    assert_eq!(vcs.len(), 1);
    let vc = *app.world().get::<VirtualCamera>(vcs[0]).unwrap();
    assert_eq!((vc.width, vc.height), (1, 1));
    // It shoots the lecture's ray under the level's settings: one sample on each of P3,
    // P2 and P1 and, composited back to front under the level's own ramp (the lecture gives
    // no transfer function), the colour (0.540, 0.397, 0.375) and opacity 0.813.
    assert_eq!(vc.view, voxcast_core::worked::lecture_ray());
    let mut render = app.world().resource::<RenderState>().clone();
    render.settings.order = voxcast_core::composite::Order::BackToFront;
    let volume = app.world().resource::<VolumeState>().volume.clone();
    let ray = vc.view.ray(0.5, 0.5, 1, 1);
    let scene =
        voxcast_core::trace::Scene::new(&volume, &render.transfer, &render.settings, ray.dir)
            .unwrap();
    let traced = voxcast_core::trace::trace_ray(&scene, &ray, [0, 0]);
    // Back to front visits them from the far end: P1, P2, P3.
    let at: Vec<Vec3> = traced
        .samples
        .iter()
        .map(|s| Vec3::from(s.p_voxel))
        .collect();
    let lecture = voxcast_core::worked::LECTURE_POINTS.map(Vec3::from_array);
    assert_eq!(at.len(), 3, "{at:?}");
    assert!(at.iter().zip(lecture).all(|(a, p)| a.distance(p) < 1e-5));
    let got = [
        traced.color[0],
        traced.color[1],
        traced.color[2],
        traced.opacity,
    ];
    for (g, quoted) in got.iter().zip([0.540, 0.397, 0.375, 0.813]) {
        assert!((g - quoted).abs() < 2e-3, "{got:?}");
    }
    assert!(entities::<LightMarker>(&mut app).is_empty());
    assert!(!app.world().resource::<PreviewSettings>().enabled);
    assert_eq!(app.world().resource::<Inspection>().size, UVec2::ONE);
    // Its panel: only the sections it names.
    let lessons = app.world().resource::<Lessons>();
    assert_eq!(
        lessons.panel_in(mode(&app)),
        Some(&[voxcast_core::level::Section::RayCasting][..])
    );

    // The methods level: no virtual camera at all, so nothing is inspected.
    let methods = level(&app, "methods");
    send(&mut app, LevelCommand::Start(methods));
    until(&mut app, |a| {
        a.world().resource::<VolumeState>().source == "builtin:brainsmall"
    });
    app.update();
    assert!(entities::<VirtualCamera>(&mut app).is_empty());
    assert!(entities::<SampleSphere>(&mut app).is_empty());
    // Its own preset, over the volume's defaults: every method it teaches shows.
    assert_eq!(
        app.world().resource::<RenderState>().transfer.name,
        "brainsmall-projections"
    );
    assert_eq!(app.world().resource::<Inspection>().size, UVec2::ZERO);
    assert!(app.world().resource::<PreviewSettings>().enabled);
    // Its steps: Next is refused until the method is chosen, as the panel's menu does.
    let steps = app.world().resource::<Lessons>().levels[methods]
        .steps
        .clone();
    let mut last = Method::Accumulate;
    for (k, step) in steps.iter().enumerate() {
        let method = match step.objective {
            Objective::Read => {
                send(&mut app, LevelCommand::Next);
                assert_eq!(app.world().resource::<Lessons>().step, k + 1, "read on");
                continue;
            }
            Objective::Method { method } => method,
            _ => panic!("the methods level asks for methods"),
        };
        last = method;
        assert!(
            !app.world().resource::<Lessons>().met,
            "step {k} met at once"
        );
        send(&mut app, LevelCommand::Next);
        assert_eq!(app.world().resource::<Lessons>().step, k, "Next refused");
        app.world_mut()
            .resource_mut::<RenderState>()
            .settings
            .method = method;
        app.update();
        assert!(app.world().resource::<Lessons>().met);
        send(&mut app, LevelCommand::Next);
    }
    // Done: back in free play, with its scene, and the progress saved.
    assert_eq!(mode(&app), Mode::FreePlay);
    assert_eq!(app.world().resource::<RenderState>().settings.method, last);
    until(&mut app, |a| !entities::<SampleSphere>(a).is_empty());
    assert_eq!(entities::<VirtualCamera>(&mut app).len(), 1);
    assert_eq!(
        entities::<LightMarker>(&mut app).len(),
        voxcast_core::shade::MAX_LIGHTS
    );
    assert_eq!(
        app.world().resource::<Lessons>().panel_in(mode(&app)),
        None,
        "free play shows all"
    );
    let saved = Progress::load(&path).0;
    assert_eq!(saved.completed["methods"], steps.len());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// "At least 8 pixels across" reads the image's width: 12×4 meets it, 4×12 does not; once
/// met, the step stays met.
#[test]
fn pixels_across_is_the_image_width() {
    let dir = std::env::temp_dir().join(format!("voxcast-across-{}", std::process::id()));
    let mut app = app(dir.join("progress.json"));
    app.update();
    let rays = level(&app, "rays");
    send(&mut app, LevelCommand::Start(rays));
    let k = app.world().resource::<Lessons>().levels[rays]
        .steps
        .iter()
        .position(|s| matches!(s.objective, Objective::VirtualPixelsAtLeast { pixels: 8 }))
        .expect("the rays level asks for 8 pixels across");
    app.world_mut().resource_mut::<Lessons>().step = k;
    until(&mut app, |a| !entities::<VirtualCamera>(a).is_empty());
    // 4×12 is not 8 across; 12×4 is; shrinking it again does not take the step back.
    for ((w, h), met) in [((4, 12), false), ((12, 4), true), ((4, 4), true)] {
        let vc = entities::<VirtualCamera>(&mut app)[0];
        let mut cam = app.world_mut().get_mut::<VirtualCamera>(vc).unwrap();
        (cam.width, cam.height) = (w, h);
        app.update();
        assert_eq!(app.world().resource::<Lessons>().met, met, "{w}×{h}");
    }
    assert!(!dir.exists(), "nothing saved before a step is done");
}

/// A step about the step's trade picks the step knob, whatever was picked before.
#[test]
fn a_step_trade_step_measures_the_step() {
    let dir = std::env::temp_dir().join(format!("voxcast-knob-{}", std::process::id()));
    let mut app = app(dir.join("progress.json"));
    app.update();
    app.world_mut().resource_mut::<StepTrade>().knob = voxcast_core::knob::Knob::Cutoff;
    let sampling = level(&app, "sampling");
    send(&mut app, LevelCommand::Start(sampling));
    let k = app.world().resource::<Lessons>().levels[sampling]
        .steps
        .iter()
        .position(|s| s.objective == Objective::TradeMeasured)
        .expect("the sampling level measures the step's trade");
    app.world_mut().resource_mut::<Lessons>().step = k;
    app.update();
    assert_eq!(
        app.world().resource::<StepTrade>().knob,
        voxcast_core::knob::Knob::Step
    );
}

/// Entering a level resets the settings to its volume's defaults, so a choice made in free
/// play does not meet its objectives before the player acts.
#[test]
fn a_level_starts_from_its_volumes_defaults() {
    let dir = std::env::temp_dir().join(format!("voxcast-reset-{}", std::process::id()));
    let mut app = app(dir.join("progress.json"));
    app.update();
    app.world_mut()
        .resource_mut::<RenderState>()
        .settings
        .method = Method::Maximum;
    // The rays level shows the volume already loaded: reset once its scene opens, a frame
    // after the mode changed (when the virtual camera stands).
    let rays = level(&app, "rays");
    assert_eq!(
        app.world().resource::<Lessons>().levels[rays].scene.volume,
        "builtin:bucky"
    );
    send(&mut app, LevelCommand::Start(rays));
    until(&mut app, |a| a.world().resource::<Lessons>().scene_ready());
    let s = &app.world().resource::<RenderState>().settings;
    assert_eq!(s.method, Method::Accumulate);
    // Another volume: its load brings its defaults.
    app.world_mut()
        .resource_mut::<RenderState>()
        .settings
        .method = Method::Maximum;
    let sampling = level(&app, "sampling");
    send(&mut app, LevelCommand::Start(sampling));
    until(&mut app, |a| {
        a.world().resource::<VolumeState>().source == "builtin:blobs"
            && a.world().resource::<Lessons>().scene_ready()
    });
    let s = &app.world().resource::<RenderState>().settings;
    assert_eq!(s.method, Method::Accumulate);
    assert!(!dir.exists(), "nothing saved before a step is done");
}

/// A step that asks for a click is met by a click made while it is open, not by a ray
/// selected before; a step that asks for the step slider to be moved compares with the step
/// it opened with, taken once the level's volume has loaded.
#[test]
fn a_change_is_asked_of_the_open_step() {
    let dir = std::env::temp_dir().join(format!("voxcast-change-{}", std::process::id()));
    let mut app = app(dir.join("progress.json"));
    app.update();
    let rays = level(&app, "rays");
    send(&mut app, LevelCommand::Start(rays));
    until(&mut app, |a| !entities::<VirtualCamera>(a).is_empty());
    let k = app.world().resource::<Lessons>().levels[rays]
        .steps
        .iter()
        .position(|s| s.objective == Objective::SelectRay)
        .expect("the rays level asks for a click");
    app.world_mut().resource_mut::<Lessons>().step = k;
    // The step's baseline is taken once its scene is on screen (the level's volume loads in
    // the background): a click before that would be part of it; and a pixel is clicked once
    // the camera's image is there.
    until(&mut app, |a| {
        let at_open = &a.world().resource::<Lessons>().at_open;
        let opened = at_open.as_ref().is_some_and(|((_, step), _)| *step == k);
        opened && a.world().resource::<Inspection>().size != UVec2::ZERO
    });
    app.world_mut().resource_mut::<RaySelection>().selected = Some(UVec2::new(1, 1));
    app.update();
    assert!(
        !app.world().resource::<Lessons>().met,
        "selected, not clicked"
    );
    app.world_mut()
        .resource_mut::<RaySelection>()
        .click(UVec2::new(2, 1));
    app.update();
    assert!(app.world().resource::<Lessons>().met, "clicked");

    let opacity = level(&app, "opacity");
    send(&mut app, LevelCommand::Start(opacity));
    // The step is met (read) once its scene is on screen, which the check sees after the
    // volume's frame: Next before that is refused, as the window's button would be.
    until(&mut app, |a| {
        a.world().resource::<VolumeState>().source == "builtin:brainsmall"
            && a.world().resource::<Lessons>().met
    });
    send(&mut app, LevelCommand::Next); // read
    assert_eq!(app.world().resource::<Lessons>().step, 1);
    fn settings(app: &mut App) -> &mut voxcast_core::settings::RenderSettings {
        &mut app
            .world_mut()
            .resource_mut::<RenderState>()
            .into_inner()
            .settings
    }
    settings(&mut app).opacity_correction = false;
    app.update();
    assert!(!app.world().resource::<Lessons>().met, "the step not moved");
    let opened = app
        .world()
        .resource::<Lessons>()
        .opened()
        .unwrap()
        .step_voxels;
    settings(&mut app).step = voxcast_core::step::Length::Voxels(opened * 3.0);
    app.update();
    assert!(app.world().resource::<Lessons>().met, "moved");
}

/// A level written by the editor: made from the view on screen, a step added as a snapshot of
/// a changed view with an objective that view does not meet, saved, read back as `--levels`
/// reads it (no problem), and played to its end — the step opening on its own view.
#[test]
fn a_level_written_in_the_editor_is_saved_read_and_played() {
    use editor::{Draft, EditorCommand};
    let dir = std::env::temp_dir().join(format!("voxcast-editor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut app = app(dir.join("progress.json"));
    until(&mut app, |a| !entities::<VirtualCamera>(a).is_empty());
    let edit = |app: &mut App, c: EditorCommand| {
        app.world_mut().write_message(c);
        app.update();
    };
    edit(&mut app, EditorCommand::NewFromView);
    let render = app.world().resource::<RenderState>().clone();
    {
        let draft = app.world().resource::<Draft>();
        let level = draft.level.as_ref().expect("a draft");
        assert_eq!(level.scene.volume, "builtin:bucky");
        // The data set's preset's transfer function, by its name.
        let preset = voxcast_core::preset::by_name(&render.transfer.name).unwrap();
        assert_eq!(preset.transfer, render.transfer);
        assert_eq!(
            level.scene.transfer,
            Some(voxcast_core::level::TransferChoice::Named(preset.name))
        );
        assert!(level.scene.virtual_camera.is_some() && level.scene.camera.is_none());
        assert_eq!(level.steps.len(), 1);
    }
    // The second step's view: Average; it asks for Maximum.
    app.world_mut()
        .resource_mut::<RenderState>()
        .settings
        .method = Method::Average;
    edit(&mut app, EditorCommand::AddStep);
    {
        let mut draft = app.world_mut().resource_mut::<Draft>();
        let level = draft.level.as_mut().unwrap();
        level.id = "my-bucky".into();
        level.steps[1].text = "Switch the method to Maximum.".into();
        level.steps[1].objective = Objective::Method {
            method: Method::Maximum,
        };
        draft.file = dir.join("my-bucky").display().to_string();
        assert_eq!(draft.step, 1);
        // Judged live on what is on screen: Average, not yet Maximum.
        let now = app.world().resource::<Lessons>().now.clone();
        assert_eq!(app.world().resource::<Draft>().met_now(&now), Some(false));
    }
    edit(&mut app, EditorCommand::Save);
    let path = dir.join("my-bucky.json");
    let text = std::fs::read_to_string(&path).expect("saved");
    // The file the play-through plays in the real window (tests/levels.rs) is this one; run
    // with VOXCAST_UPDATE_FIXTURES=1 to write it again after a change to the editor.
    let fixture =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/edited_level.json");
    if std::env::var_os("VOXCAST_UPDATE_FIXTURES").is_some() {
        std::fs::write(&fixture, &text).unwrap();
    }
    assert_eq!(
        std::fs::read_to_string(&fixture).unwrap(),
        text,
        "the editor no longer writes tests/data/edited_level.json"
    );
    let checked = voxcast_core::level::check::read(
        &text,
        voxcast_core::level::Origin::File(path.clone()),
        &voxcast_core::level::check::OnDisk,
    );
    assert_eq!(checked.problems, [], "{text}");
    let read = checked.level.unwrap();
    let drafted = app.world().resource::<Draft>().level.clone().unwrap();
    assert_eq!(read, drafted, "the file is the draft");
    let l = level(&app, "my-bucky");
    assert_eq!(app.world().resource::<Lessons>().levels[l], read);
    // Played from its start, as a student plays it.
    app.world_mut()
        .resource_mut::<RenderState>()
        .settings
        .method = Method::Minimum;
    edit(&mut app, EditorCommand::Play(0));
    until(&mut app, |a| {
        mode(a) == Mode::Level(l) && a.world().resource::<Lessons>().scene_ready()
    });
    send(&mut app, LevelCommand::Next); // read
    until(&mut app, |a| a.world().resource::<Lessons>().scene_ready());
    app.update();
    assert_eq!(
        app.world().resource::<RenderState>().settings.method,
        Method::Average,
        "the step opens on its own view"
    );
    assert!(!app.world().resource::<Lessons>().met);
    app.world_mut()
        .resource_mut::<RenderState>()
        .settings
        .method = Method::Maximum;
    until(&mut app, |a| a.world().resource::<Lessons>().met);
    send(&mut app, LevelCommand::Next);
    assert_eq!(mode(&app), Mode::FreePlay);
    assert_eq!(
        app.world().resource::<Lessons>().progress.completed["my-bucky"],
        2
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A level in a link (`--link`, or the page's own `#level=…`) is read as a file is read and
/// played at once; a damaged link says so and changes nothing. Level files and answer files
/// dropped on the window join the list and become a report.
#[test]
fn a_link_plays_its_level_and_dropped_files_are_read() {
    let dir = std::env::temp_dir().join(format!("voxcast-link-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut app = app(dir.join("progress.json"));
    app.update();
    let mut level = Level::all().into_iter().find(|l| l.id == "rays").unwrap();
    level.id = "shared-rays".into();
    level.title = "Rays, shared".into();
    let url = voxcast_core::level::link::link(&level, "http://127.0.0.1:8000/").unwrap();
    app.world_mut().resource_mut::<files::OpenLink>().0 = Some(url.clone());
    until(
        &mut app,
        |a| matches!(mode(a), Mode::Level(i) if a.world().resource::<Lessons>().levels[i].id == "shared-rays"),
    );
    let damaged = format!("{}x", &url[..url.len() - 20]);
    app.world_mut().resource_mut::<files::OpenLink>().0 = Some(damaged);
    app.update();
    app.update();
    let said = app
        .world()
        .resource::<Lessons>()
        .message
        .clone()
        .unwrap_or_default();
    assert!(said.contains("damaged"), "{said}");
    // On the page a link comes with the files its level names, which the page fetched from
    // its site: they are held, and the level's data set loads from them.
    use crate::sandbox::shared::files::{FilesChosen, Purpose};
    let tiny = b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 2 2 2\nencoding: raw\n\n\
                 \x00\x10\x20\x30\x40\x50\x60\x70";
    let mut on_file = level.clone();
    on_file.id = "linked-file".into();
    on_file.scene.volume = "http://127.0.0.1:8000/course/tiny.nrrd".into();
    let url = voxcast_core::level::link::link(&on_file, "http://127.0.0.1:8000/").unwrap();
    let (page, fragment) = url.split_once('#').unwrap();
    app.world_mut().write_message(FilesChosen {
        purpose: Purpose::LevelLink,
        files: vec![
            (page.to_string(), fragment.as_bytes().to_vec()),
            (on_file.scene.volume.clone(), tiny.to_vec()),
        ],
    });
    until(&mut app, |a| {
        a.world().resource::<VolumeState>().source == on_file.scene.volume
            && a.world().resource::<VolumeState>().volume.dims() == UVec3::splat(2)
    });
    // Dropped: a level file and an answers file.
    let mut other = level.clone();
    other.id = "dropped".into();
    let level_file = dir.join("dropped.json");
    std::fs::write(&level_file, voxcast_core::level::to_text(&other)).unwrap();
    let csv = dir.join("answers.csv");
    std::fs::write(&csv, Progress::default().answers_csv()).unwrap();
    for path in [level_file, csv] {
        app.world_mut().write_message(FileDragAndDrop::DroppedFile {
            window: Entity::PLACEHOLDER,
            path_buf: path,
        });
    }
    let cwd = std::env::current_dir().unwrap();
    app.update();
    app.update();
    let lessons = app.world().resource::<Lessons>();
    assert!(
        lessons.levels.iter().any(|l| l.id == "dropped"),
        "{:?}",
        lessons.message
    );
    assert!(
        lessons
            .message
            .as_deref()
            .unwrap_or_default()
            .starts_with("Class report: 0 answer files read, 1 left out"),
        "{:?}",
        lessons.message
    );
    let report = cwd.join("class_report.html");
    assert!(
        std::fs::read_to_string(&report)
            .unwrap()
            .contains("it holds no answers")
    );
    std::fs::remove_file(report).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
}
