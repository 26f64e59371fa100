//! The levels' tests: every embedded level reads and names real things, objectives, progress.

use super::*;
use crate::composite::Method;

/// Answers round-trip through the progress text; progress written before answers were
/// kept reads with none; the CSV quotes what needs quoting and dates in UTC.
#[test]
fn answers_are_kept_and_exported() {
    let (old, message) = Progress::from_text(r#"{"completed": {"rays": 2}}"#, "old");
    assert_eq!(message, None);
    assert_eq!(old.completed["rays"], 2);
    assert!(old.answers.is_empty());
    let mut p = old;
    p.answers.push(Answer {
        level: "trilinear".into(),
        step: 2,
        question: "value at (0.5, 0.5, 0.5)".into(),
        answer: "4.99".into(),
        expected: "4.9875".into(),
        correct: true,
        at: 1_796_464_427,
        run: None,
        attempt: Some(1),
        seconds: Some(12.5),
    });
    p.answers.push(Answer {
        question: "which effect: \"trace 4\"".into(),
        answer: "reflection rays".into(),
        expected: "shadow rays".into(),
        correct: false,
        run: Some(StudyRun::PreviewOn.words().into()),
        attempt: None,
        seconds: None,
        ..p.answers[0].clone()
    });
    let (back, _) = Progress::from_text(&p.to_text(), "here");
    assert_eq!(back, p);
    let csv = p.answers_csv();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines,
        [
            "level,step,question,answer,expected,correct,time (UTC),run,try,seconds",
            "trilinear,2,\"value at (0.5, 0.5, 0.5)\",4.99,4.9875,yes,2026-12-05T09:53:47Z,,1,12.5",
            "trilinear,2,\"which effect: \"\"trace 4\"\"\",reflection rays,shadow rays,no,\
             2026-12-05T09:53:47Z,preview on,,",
        ]
    );
    for (seconds, iso) in [
        (0, "1970-01-01T00:00:00Z"),
        (951_782_400, "2000-02-29T00:00:00Z"),
        (4_107_542_399, "2100-02-28T23:59:59Z"),
    ] {
        assert_eq!(utc_time(seconds), iso);
    }
    let now = Answer::now("x", 1, "q".into(), ("a".into(), "b".into(), true));
    assert!(now.at > 1_700_000_000, "{}", now.at);
}

#[test]
fn every_embedded_level_reads_and_quotes_only_real_tunables() {
    let levels = Level::all();
    assert_eq!(levels.len(), EMBEDDED.len());
    let mut ids = std::collections::HashSet::new();
    for l in &levels {
        assert!(ids.insert(l.id.clone()), "duplicate level id {}", l.id);
        for s in &l.steps {
            assert!(!s.text.contains("{tunable:"), "{}: {}", l.id, s.text);
        }
        assert!(
            crate::builtin::load_source(&l.scene.volume).is_ok(),
            "{}: volume {}",
            l.id,
            l.scene.volume
        );
    }
}

/// The first-hit level quotes the head phantom's levels, and its isovalue objective lies
/// between the scalp's and the bone's (where the skull appears; tested in closed_forms).
#[test]
fn the_skull_level_matches_the_phantom() {
    use crate::builtin::{HEAD_BONE, HEAD_BRAIN, HEAD_SKIN};
    let level = Level::all()
        .into_iter()
        .find(|l| l.id == "first-hit")
        .unwrap();
    assert_eq!(level.scene.volume, "builtin:head");
    let text: String = level.steps.iter().map(|s| s.text.as_str()).collect();
    for v in [HEAD_SKIN, HEAD_BRAIN, HEAD_BONE] {
        assert!(text.contains(&format!("{v}")), "the text quotes {v}");
    }
    let (lo, hi) = level
        .steps
        .iter()
        .flat_map(|s| s.objective.parts())
        .find_map(|o| match *o {
            Objective::TargetBetween { lo, hi } => Some((lo, hi)),
            _ => None,
        })
        .unwrap();
    assert!(HEAD_SKIN < lo && hi < HEAD_BONE);
    // The preset starts below the scalp: the skin shows until the player acts.
    let p = crate::preset::for_volume("head").unwrap();
    let s = p
        .settings_over(&crate::settings::RenderSettings::default())
        .unwrap();
    assert!(s.target.unwrap() < HEAD_SKIN);
}

#[test]
fn light_objectives_count_lights_colours_and_the_opened_sample() {
    let white = [1.0, 1.0, 1.0];
    assert_eq!(distinct_colours(&[white, white]), 1);
    assert_eq!(
        distinct_colours(&[white, [0.95, 1.0, 0.92]]),
        1,
        "too close to tell"
    );
    assert_eq!(
        distinct_colours(&[white, [1.0, 0.4, 0.3], [0.3, 0.5, 1.0]]),
        3
    );
    let mut s = Situation {
        light_kinds: vec!["headlight", "directional"],
        light_colors: vec![white, white],
        ..Situation::default()
    };
    assert!(Objective::LightsAtLeast { count: 2 }.met(&s));
    assert!(!Objective::LightsAtLeast { count: 3 }.met(&s));
    assert!(
        Objective::LightKind {
            light: "directional".into()
        }
        .met(&s)
    );
    assert!(!Objective::DistinctLightColours { count: 2 }.met(&s));
    s.light_colors[1] = [0.3, 0.5, 1.0];
    assert!(Objective::DistinctLightColours { count: 2 }.met(&s));
    assert!(!Objective::OpenLitSample { lights: 2 }.met(&s));
    s.opened_sample_lights = Some(1);
    assert!(!Objective::OpenLitSample { lights: 2 }.met(&s));
    s.opened_sample_lights = Some(2);
    assert!(Objective::OpenLitSample { lights: 2 }.met(&s));
    assert!(!Objective::LevoyHighlight { on: true }.met(&s));
    s.levoy_highlight = true;
    assert!(Objective::LevoyHighlight { on: true }.met(&s));
    // The full model asks for both emission and a spot with its own ambient.
    s.emission = 0.1;
    assert!(!Objective::FullModel.met(&s));
    s.spot_ambient = true;
    assert!(
        !Objective::FullModel.met(&s),
        "ka = 0: no ambient term shows"
    );
    s.ka = 0.2;
    assert!(Objective::FullModel.met(&s));
    s.emission = 0.0;
    assert!(!Objective::FullModel.met(&s));
    assert!(Objective::DepthCue { on: false }.met(&s));
    s.depth_cue = true;
    assert!(Objective::DepthCue { on: true }.met(&s));
    let around = Objective::RegionAround {
        value: 110.0,
        max_gradient: 40.0,
    };
    let r = crate::classify::Region {
        value: [100.0, 120.0],
        gradient: [0.0, 30.0],
        opacity: 0.8,
    };
    assert!(!around.met(&s));
    s.regions = vec![r];
    assert!(around.met(&s));
    for off in [
        crate::classify::Region {
            gradient: [0.0, 60.0],
            ..r
        },
        crate::classify::Region {
            gradient: [5.0, 30.0],
            ..r
        },
        crate::classify::Region {
            value: [111.0, 130.0],
            ..r
        },
        crate::classify::Region { opacity: 0.0, ..r },
    ] {
        s.regions = vec![off];
        assert!(!around.met(&s), "{off:?}");
    }
}

#[test]
fn cost_objectives_read_the_preview_and_the_blocks() {
    let mut s = Situation::default();
    let samples = Objective::PreviewCostView {
        view: "samples".into(),
    };
    assert!(!samples.met(&s));
    s.preview_cost_view = Some("stops");
    assert!(!samples.met(&s));
    s.preview_cost_view = Some("samples");
    assert!(samples.met(&s));
    assert!(!Objective::SkipBlocks { on: true }.met(&s));
    s.skip_blocks_shown = true;
    assert!(Objective::SkipBlocks { on: true }.met(&s));
}

/// The sampling level quotes the steps and the reference the trade measures.
#[test]
fn the_sampling_level_quotes_the_trades_steps() {
    let level = Level::all()
        .into_iter()
        .find(|l| l.id == "sampling")
        .unwrap();
    let step = level
        .steps
        .iter()
        .find(|s| s.objective == Objective::TradeMeasured)
        .unwrap();
    for v in crate::trade::STEPS {
        assert!(step.text.contains(&format!("{v}")), "{v}");
    }
    assert_eq!(crate::trade::REFERENCE, 1.0 / 16.0);
    assert!(step.text.contains("1/16 voxel"));
    // The grid it names is the one it loads.
    let v = crate::builtin::load_source(&level.scene.volume)
        .unwrap()
        .volume;
    let d = v.dims();
    assert!(
        level.steps[0]
            .text
            .contains(&format!("{}×{}×{}", d.x, d.y, d.z))
    );
}

#[test]
fn quoted_tunables_are_filled_in_and_unknown_ones_refused() {
    let t = fill_in("the step is {tunable:step} voxel").unwrap();
    assert_eq!(t, format!("the step is {} voxel", tunables::STEP.default));
    assert!(fill_in("{tunable:nonsense}").is_err());
    assert!(fill_in("{tunable:step").is_err());
}

#[test]
fn objectives_check_the_situation() {
    let mut s = Situation {
        step_voxels: 0.5,
        virtual_pixels_across: 4,
        ray_values: vec![1.0, 7.0, 3.0],
        ..Default::default()
    };
    assert!(Objective::Read.met(&s));
    assert!(!Objective::SelectRay.met(&s));
    assert!(!Objective::StepAtMost { voxels: 0.25 }.met(&s));
    s.step_voxels = 0.2500001;
    assert!(Objective::StepAtMost { voxels: 0.25 }.met(&s));
    assert!(!Objective::StepAtLeast { voxels: 2.0 }.met(&s));
    s.step_voxels = 1.9999;
    assert!(
        Objective::StepAtLeast { voxels: 2.0 }.met(&s),
        "a slider's rounding"
    );
    assert!(!Objective::Jitter { on: true }.met(&s));
    s.jitter = true;
    assert!(Objective::Jitter { on: true }.met(&s));
    assert!(Objective::Interpolation { trilinear: false }.met(&s));
    s.trilinear = true;
    assert!(!Objective::Interpolation { trilinear: false }.met(&s));
    assert!(!Objective::SupersamplingAtLeast { rays: 2 }.met(&s));
    s.supersampling = 3;
    assert!(Objective::SupersamplingAtLeast { rays: 2 }.met(&s));
    let between = Objective::ClipPositionBetween { lo: -0.6, hi: -0.2 };
    assert!(Objective::ClipPlane { on: false }.met(&s));
    assert!(!between.met(&s), "no plane: no position");
    s.clip.plane = Some(crate::clip::ClipPlane {
        normal: glam::Vec3::X,
        position: -0.4,
    });
    assert!(Objective::ClipPlane { on: true }.met(&s) && between.met(&s));
    s.clip.plane.as_mut().unwrap().position = 0.0;
    assert!(!between.met(&s));
    let crop = Objective::CropAtMost { fraction: 0.5 };
    assert!(!crop.met(&s));
    s.clip.crop_lo.z = 0.3;
    s.clip.crop_hi.z = 0.8;
    assert!(crop.met(&s));
    s.ray_selected = true;
    assert!(!Objective::SelectCutRay.met(&s));
    s.ray_cut = true;
    assert!(
        !Objective::SelectCutRay.met(&s),
        "no step open: no click in it"
    );
    s.at_open = Some(Box::new(s.clone()));
    assert!(
        !Objective::SelectCutRay.met(&s),
        "selected before the step opened"
    );
    s.ray_clicks += 1;
    assert!(Objective::SelectCutRay.met(&s), "clicked while it is open");
    s.at_open = None;
    assert!(Objective::Skipping { on: false }.met(&s));
    let stops = Objective::CostViewed {
        view: "stops".into(),
    };
    assert!(!stops.met(&s));
    s.cost_view = Some("samples");
    assert!(!stops.met(&s));
    s.cost_view = Some("stops");
    assert!(stops.met(&s));
    s.preview_scale = 0.50000006;
    assert!(Objective::PreviewScaleAtMost { scale: 0.5 }.met(&s));
    assert!(!Objective::PreviewScaleAtLeast { scale: 1.0 }.met(&s));
    assert!(Objective::Preview { on: false }.met(&s));
    let measured = Objective::KnobMeasured {
        knob: "preview-scale".into(),
    };
    assert!(!measured.met(&s));
    s.measured_knob = Some("preview-scale");
    assert!(measured.met(&s));
    assert!(!Objective::VirtualPixelsAtLeast { pixels: 8 }.met(&s));
    assert!(
        !Objective::Method {
            method: Method::Maximum
        }
        .met(&s)
    );
    s.method = Some(Method::Maximum);
    assert!(
        Objective::Method {
            method: Method::Maximum
        }
        .met(&s)
    );
    s.opened_sample = Some(2);
    assert!(!Objective::OpenHighestSample.met(&s));
    s.opened_sample = Some(1);
    assert!(Objective::OpenHighestSample.met(&s));
    assert!(Objective::EarlyTermination { on: false }.met(&s));
    assert!(!Objective::Shading { on: true }.met(&s));
    s.target = Some(128.0);
    assert!(
        Objective::TargetBetween {
            lo: 120.0,
            hi: 136.0
        }
        .met(&s)
    );
    assert!(!Objective::TargetBetween { lo: 0.0, hi: 100.0 }.met(&s));
    s.classification = "boundaries";
    assert!(
        Objective::Classification {
            mode: "boundaries".into()
        }
        .met(&s)
    );
}

#[test]
fn ray_data_objectives() {
    let mut s = Situation::default();
    let cornell = |trace| Objective::RayDensity {
        source: "builtin:cornell".into(),
        trace,
        side_at_least: 0,
    };
    let camera = Objective::RayDensity {
        source: "camera".into(),
        trace: None,
        side_at_least: 128,
    };
    assert!(!cornell(None).met(&s) && !camera.met(&s));
    s.ray_density = Some(RayDensityFacts {
        source: "builtin:cornell".into(),
        trace: Some(2),
        side: 0,
    });
    assert!(cornell(None).met(&s) && cornell(Some(2)).met(&s));
    assert!(!cornell(Some(3)).met(&s) && !camera.met(&s));
    s.ray_density = Some(RayDensityFacts {
        source: "camera".into(),
        trace: None,
        side: 64,
    });
    assert!(!camera.met(&s), "too few rays across");
    s.ray_density.as_mut().unwrap().side = 128;
    assert!(camera.met(&s));
    let field = |on| Objective::RayView {
        view: "field".into(),
        on,
    };
    assert!(!field(true).met(&s) && field(false).met(&s));
    s.ray_views = vec!["volume", "field"];
    assert!(field(true).met(&s) && !field(false).met(&s));
    assert!(!Objective::NameEffect { trace: 2 }.met(&s));
    s.named_effect = Some(3);
    assert!(!Objective::NameEffect { trace: 2 }.met(&s));
    s.named_effect = Some(2);
    assert!(Objective::NameEffect { trace: 2 }.met(&s));
    // Either primary trace is "primary rays".
    s.named_effect = Some(0);
    assert!(Objective::NameEffect { trace: 1 }.met(&s));
    assert!(!Objective::NameEffect { trace: 4 }.met(&s));
}

#[test]
fn progress_survives_a_round_trip_and_a_damaged_file_starts_afresh() {
    let dir = std::env::temp_dir().join(format!("voxcast-progress-{}", std::process::id()));
    let path = dir.join("sub/progress.json");
    let (fresh, note) = Progress::load(&path);
    assert_eq!((fresh, note), (Progress::default(), None));
    let mut p = Progress::default();
    p.record("rays", 3);
    p.record("rays", 1);
    p.save(&path).unwrap();
    assert_eq!(Progress::load(&path).0.completed["rays"], 3);
    std::fs::write(&path, "{ not json").unwrap();
    let (fresh, note) = Progress::load(&path);
    assert_eq!(fresh, Progress::default());
    assert!(note.unwrap().contains("damaged"));
    std::fs::remove_dir_all(&dir).unwrap();
}
