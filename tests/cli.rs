//! The `voxcast` command line, run as a user runs it: outputs, formats, and errors with exit codes.

use std::path::PathBuf;
use std::process::{Command, Output};

fn voxcast(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_voxcast"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn out_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("voxcast-cli-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

#[test]
fn render_writes_a_png_and_reports_speed() {
    let png = out_dir().join("shells.png");
    let o = voxcast(&[
        "render",
        "--volume",
        "builtin:shells",
        "--size",
        "48x32",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let line = String::from_utf8_lossy(&o.stdout);
    assert!(
        line.contains("samples/s") && line.contains("48×32"),
        "{line}"
    );
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (48, 32));
    assert!(
        img.pixels().any(|p| p.0 != [0, 0, 0]),
        "something is visible"
    );
}

/// A step far too small for the sample cap still renders (exit 0), but says how many rays the
/// cap cut short; a usual step says nothing of the cap.
#[test]
fn render_warns_when_the_sample_cap_cuts_rays_short() {
    let png = out_dir().join("capped.png");
    let render = |settings: &[&str]| {
        let size = ["render", "--volume", "builtin:shells", "--size", "8x8"];
        let out = ["--out", png.to_str().unwrap()];
        voxcast(&[&size[..], settings, &out].concat())
    };
    let o = render(&["--step", "0.000001", "--max-samples", "100"]);
    assert!(o.status.success(), "{}", text(&o));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("warning:") && err.contains("of 64 rays") && err.contains("sample cap (100)"),
        "{err}"
    );
    let o = render(&[]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(!String::from_utf8_lossy(&o.stderr).contains("sample cap"));
}

/// `info` counts the voxels that hold no data (a masked volume's NaN and ±∞).
#[test]
fn info_counts_the_voxels_without_data() {
    let o = voxcast(&["info", "builtin:masked"]);
    assert!(o.status.success(), "{}", text(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let want = voxcast_core::builtin::masked().no_data_count();
    assert!(want > 0);
    assert!(out.contains(&format!("no data:    {want} voxels")), "{out}");
    let o = voxcast(&["info", "builtin:shells"]);
    assert!(!String::from_utf8_lossy(&o.stdout).contains("no data"));
}

#[test]
fn every_method_renders_every_builtin() {
    for (volume, _) in voxcast_core::builtin::DATASETS {
        for method in ["accumulate", "first", "average", "maximum", "minimum"] {
            let png = out_dir().join(format!("{volume}_{method}.png"));
            let o = voxcast(&[
                "render",
                "--volume",
                &format!("builtin:{volume}"),
                "--method",
                method,
                "--size",
                "24x24",
                "--out",
                png.to_str().unwrap(),
            ]);
            assert!(o.status.success(), "{volume} {method}: {}", text(&o));
        }
    }
}

/// `render --method first --depth FILE.png`: the depth image beside the colour one, its raw
/// distances as a NRRD the volume readers open, the scale in words; without First, or with a
/// name that is not a PNG, a usage error before any work.
#[test]
fn render_writes_firsts_depth_image() {
    let dir = out_dir();
    let (png, depth) = (dir.join("first.png"), dir.join("first_depth.png"));
    let o = voxcast(&[
        "render",
        "--volume",
        "builtin:bunny",
        "--method",
        "first",
        "--size",
        "48x40",
        "--out",
        png.to_str().unwrap(),
        "--depth",
        depth.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("Distance from the eye"), "{}", text(&o));
    let image = image::open(&depth).unwrap().to_rgb8();
    assert_eq!(image.dimensions(), (48, 40));
    let colour = image::open(&png).unwrap().to_rgb8();
    // Hits are grey, and where the colour image shows the bunny the depth image has a hit.
    let background = *colour.get_pixel(0, 0);
    let mut hits = 0;
    for (x, y, p) in colour.enumerate_pixels() {
        let d = image.get_pixel(x, y);
        if *p != background {
            assert!(
                d[0] == d[1] && d[1] == d[2] && d[0] > 30,
                "({x}, {y}): {d:?}"
            );
            hits += 1;
        }
    }
    assert!(hits > 100, "{hits} hits");
    // The raw distances open as a volume one voxel deep.
    let raw = depth.with_extension("nrrd");
    let o = voxcast(&["info", raw.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("48 × 40 × 1"), "{}", text(&o));

    let o = voxcast(&["render", "--depth", depth.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("choose the method First"), "{}", text(&o));
    let o = voxcast(&["render", "--method", "first", "--depth", "x.nrrd"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("ending in .png"), "{}", text(&o));
}

/// `--specular`: Phong's R·V draws other highlights than Blinn-Phong's N·H, which is the
/// default (bit for bit).
#[test]
fn the_specular_model_is_chosen_on_the_command_line() {
    let dir = out_dir();
    let render = |name: &str, extra: &[&str]| {
        let png = dir.join(name);
        let args = [
            &[
                "render",
                "--volume",
                "builtin:bunny",
                "--size",
                "40x32",
                "--out",
            ][..],
            &[png.to_str().unwrap()],
            extra,
        ]
        .concat();
        let o = voxcast(&args);
        assert!(o.status.success(), "{}", text(&o));
        image::open(&png).unwrap().to_rgb8()
    };
    let default = render("spec_default.png", &[]);
    let blinn = render("spec_blinn.png", &["--specular", "blinn-phong"]);
    let phong = render("spec_phong.png", &["--specular", "phong"]);
    assert!(default == blinn, "Blinn-Phong is the default");
    assert!(phong != blinn, "R·V and N·H give other highlights");
}

/// `voxcast answers`: the player's progress (here `VOXCAST_CONFIG_DIR`'s) as CSV, to standard
/// output or a file (an answer kept before tries were counted leaves `try` and `seconds` empty);
/// a missing or damaged progress file says so and exits non-zero.
#[test]
fn answers_are_exported_as_csv() {
    let dir = out_dir().join("answers");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("progress.json"),
        r#"{"completed": {"trilinear": 2}, "answers": [{"level": "trilinear", "step": 2,
            "question": "the value at (0.5, 0.5, 0.5)", "answer": "4.99", "expected": "4.988",
            "correct": true, "at": 1796464427}]}"#,
    )
    .unwrap();
    let run = |args: &[&str]| {
        Command::new(env!("CARGO_BIN_EXE_voxcast"))
            .args(args)
            .env("VOXCAST_CONFIG_DIR", &dir)
            .output()
            .unwrap()
    };
    let o = run(&["answers"]);
    assert!(o.status.success(), "{}", text(&o));
    let csv = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        csv,
        "level,step,question,answer,expected,correct,time (UTC),run,try,seconds\n\
         trilinear,2,\"the value at (0.5, 0.5, 0.5)\",4.99,4.988,yes,2026-12-05T09:53:47Z,,,\n"
    );
    let out = dir.join("answers.csv");
    let o = run(&["answers", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    assert_eq!(std::fs::read_to_string(&out).unwrap(), csv);
    let o = run(&["answers", "--progress", "/no/such/progress.json"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("/no/such/progress.json"), "{}", text(&o));
    std::fs::write(dir.join("progress.json"), "{ damaged").unwrap();
    let o = run(&["answers"]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("is damaged"), "{}", text(&o));
}

#[test]
fn trace_prints_json_csv_and_a_table() {
    let args = [
        "trace",
        "--volume",
        "builtin:bucky",
        "--origin",
        "-5,15.5,15.5",
        "--dir",
        "1,0,0",
        "--step",
        "1",
    ];
    let o = voxcast(&[&args[..], &["--json"]].concat());
    assert!(o.status.success(), "{}", text(&o));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let samples = json["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 32, "31 voxels at one voxel per step");
    assert_eq!(
        samples[0]["reconstruction"]["weights"]
            .as_array()
            .unwrap()
            .len(),
        8
    );
    assert!(json["stop"].is_string());
    let o = voxcast(&[&args[..], &["--csv"]].concat());
    let csv = String::from_utf8_lossy(&o.stdout);
    assert!(csv.starts_with(voxcast_core::breakdown::CSV_HEADER));
    assert_eq!(csv.lines().filter(|l| !l.starts_with('#')).count(), 33);
    let o = voxcast(&args);
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("enters at t = 5.0"),
        "{}",
        text(&o)
    );
    // In voxel space and through a pixel.
    let o = voxcast(&[
        "trace",
        "--volume",
        "builtin:bunny",
        "--pixel",
        "256,256",
        "--json",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = voxcast(&[
        "trace",
        "--volume",
        "builtin:bunny",
        "--origin",
        "-1,60,50",
        "--dir",
        "1,0,0",
        "--space",
        "voxel",
    ]);
    assert!(o.status.success(), "{}", text(&o));
}

#[test]
fn info_and_list_describe_what_there_is() {
    let o = voxcast(&["info", "builtin:brainsmall"]);
    let t = text(&o);
    assert!(
        o.status.success() && t.contains("128 × 128 × 84") && t.contains("uint8"),
        "{t}"
    );
    let o = voxcast(&["list"]);
    let t = text(&o);
    assert!(
        t.contains("marschner-lobb") && t.contains("ct_skin_bone"),
        "{t}"
    );
    // The help names every embedded dataset and preset.
    let help = text(&voxcast(&["render", "--help"]));
    for (name, _) in voxcast_core::builtin::DATASETS {
        assert!(help.contains(name), "--help lacks builtin {name}");
    }
    for p in voxcast_core::preset::all() {
        assert!(help.contains(&p.name), "--help lacks preset {}", p.name);
    }
}

#[test]
fn bench_writes_its_table_and_plot() {
    let dir = out_dir();
    let (report, plot) = (dir.join("bench.md"), dir.join("bench.png"));
    let o = voxcast(&[
        "bench",
        "--volume",
        "builtin:bucky",
        "--size",
        "32x32",
        "--steps",
        "2,1",
        "--repeat",
        "1",
        "--report",
        report.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let md = std::fs::read_to_string(&report).unwrap();
    assert_eq!(
        md.lines()
            .filter(|l| l.starts_with("| on") || l.starts_with("| off"))
            .count(),
        4
    );
    // The machine is named, and each row gives the cost of an interpolated sample.
    assert!(md.contains("Measured on "), "{md}");
    assert!(md.contains("| ns | cycles |"), "{md}");
    for row in md.lines().filter(|l| l.starts_with("| on")) {
        assert_eq!(row.matches('|').count(), 11, "{row}");
    }
    assert!(image::open(&plot).is_ok());
}

/// `--no-lanes` renders as a CPU without the lanes' vector units does, `--narrow-lanes` as an
/// The transfer function `bench --peer` gives VTK, written for a peer run elsewhere
/// (benches/gpu.sh): the peer's own file for a preset it has, else Voxcast's preset in the
/// peer's format, which reads back as the same table.
#[test]
fn bench_writes_the_transfer_function_it_gives_the_peer() {
    let dir = out_dir().join("peer");
    std::fs::create_dir_all(dir.join("tf")).unwrap();
    let own = "{\"color\": [[0, 1, 1, 1]], \"opacity\": [[0, 0.5]]}";
    std::fs::write(dir.join("tf/bunny.json"), own).unwrap();
    let written = dir.join("written.json");
    let peer = dir.to_str().unwrap();
    let write = |volume: &str| {
        let o = voxcast(&[
            "bench",
            "--volume",
            volume,
            "--peer",
            peer,
            "--write-peer-tf",
            written.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", text(&o));
        std::fs::read_to_string(&written).unwrap()
    };
    assert_eq!(write("builtin:bunny"), own);
    let ours = write("builtin:brainsmall");
    let table = voxcast_core::peer::from_json(&ours).expect("the peer's format");
    let preset = voxcast_core::preset::by_name("brainsmall").expect("a preset");
    assert_eq!(table.transfer.points(), preset.transfer.points());
}

/// x86-64 without AVX: `bench` says so, and the images of `bench` and `render` are the widest
/// lanes' bit for bit; the two switches together are refused.
#[test]
fn bench_without_or_with_narrow_lanes_says_so_and_draws_the_same_images() {
    let dir = out_dir();
    let run = |name: &str, extra: &[&str]| {
        let (report, images) = (dir.join(format!("{name}.md")), dir.join(name));
        let mut args = vec![
            "bench",
            "--volume",
            "builtin:bunny",
            "--size",
            "48x40",
            "--steps",
            "0.5",
            "--repeat",
            "1",
            "--report",
            report.to_str().unwrap(),
            "--images",
            images.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let o = voxcast(&args);
        assert!(o.status.success(), "{}", text(&o));
        (std::fs::read_to_string(&report).unwrap(), images)
    };
    let (with, with_images) = run("lanes_on", &[]);
    let (without, without_images) = run("lanes_off", &["--no-lanes"]);
    let (narrow, narrow_images) = run("lanes_narrow", &["--narrow-lanes"]);
    assert!(without.contains("turned off"), "{without}");
    assert!(!with.contains("turned off"), "{with}");
    assert!(narrow.contains("`--narrow-lanes`"), "{narrow}");
    let names: Vec<_> = std::fs::read_dir(&with_images)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert!(names.len() >= 3, "{names:?}");
    for name in names {
        let a = std::fs::read(with_images.join(&name)).unwrap();
        let b = std::fs::read(without_images.join(&name)).unwrap();
        let c = std::fs::read(narrow_images.join(&name)).unwrap();
        assert!(a == b, "{name:?} differs without the lanes");
        assert!(a == c, "{name:?} differs with the narrow lanes");
    }
    // `render` takes the switch too.
    let render = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let mut args = vec![
            "render",
            "--volume",
            "builtin:brainsmall",
            "--size",
            "40x32",
        ];
        args.extend_from_slice(&["--out", out.to_str().unwrap()]);
        args.extend_from_slice(extra);
        let o = voxcast(&args);
        assert!(o.status.success(), "{}", text(&o));
        std::fs::read(out).unwrap()
    };
    let on = render("lanes_on.png", &[]);
    assert!(on == render("lanes_off.png", &["--no-lanes"]));
    assert!(on == render("lanes_narrow.png", &["--narrow-lanes"]));
    // Both at once is refused, with a message.
    let o = voxcast(&["render", "--no-lanes", "--narrow-lanes"]);
    assert!(!o.status.success());
    assert!(text(&o).contains("cannot be used with"), "{}", text(&o));
}

/// `--knobs`: one table per knob, each ending with its reference, written into a section of an
/// existing report; and `render --cost` writes its heat map beside the image.
#[test]
fn knobs_and_cost_maps_are_written() {
    let dir = out_dir();
    let report = dir.join("knobs.md");
    std::fs::write(
        &report,
        "# kept\n<!-- bench:knobs -->\nold\n<!-- /bench:knobs -->\n# also kept\n",
    )
    .unwrap();
    let o = voxcast(&[
        "bench",
        "--volume",
        "builtin:bucky",
        "--size",
        "24x24",
        "--knobs",
        "--report",
        report.to_str().unwrap(),
        "--section",
        "knobs",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let md = std::fs::read_to_string(&report).unwrap();
    assert!(md.starts_with("# kept") && md.trim_end().ends_with("# also kept"));
    assert!(!md.contains("old"));
    for k in voxcast_core::knob::Knob::ALL {
        assert!(md.contains(&format!("**{}**", k.label())), "{k:?}");
    }
    assert_eq!(
        md.matches("(reference) |").count(),
        voxcast_core::knob::Knob::ALL.len()
    );
    let out = dir.join("costly.png");
    let o = voxcast(&[
        "render",
        "--volume",
        "builtin:bucky",
        "--size",
        "24x24",
        "--cost",
        "stops",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("left the volume"), "{}", text(&o));
    assert!(image::open(dir.join("costly_cost.png")).is_ok());
}

#[test]
fn bad_arguments_and_files_fail_clearly() {
    let cases: &[(&[&str], i32, &str)] = &[
        (&["render", "--size", "0x10"], 2, "1 to 16384"),
        (&["render", "--step", "-1"], 2, "step"),
        (&["render", "--step", "nan"], 2, "step"),
        (&["render", "--cutoff", "2"], 2, "cutoff"),
        (&["render", "--method", "median"], 2, "accumulate"),
        (&["render", "--camera", "eye=1,2"], 2, "eye"),
        (
            &["render", "--camera", "eye=0,0,0,target=0,0,0"],
            2,
            "same point",
        ),
        (&["render", "--tf", "no_such_preset"], 2, "no_such_preset"),
        (
            &["render", "--volume", "/no/such/file.nrrd"],
            1,
            "/no/such/file.nrrd",
        ),
        (
            &["render", "--volume", "builtin:teapot"],
            1,
            "no embedded dataset",
        ),
        (&["info", "/no/such/file.nrrd"], 1, "file not found"),
        (
            &["render", "--volume", "thing.xyz"],
            1,
            "unknown file format",
        ),
        (&["render", "--classify", "iso:"], 2, "classify"),
        (
            &["trace", "--origin", "0,0,0", "--dir", "0,0,0"],
            2,
            "non-zero",
        ),
        (&["trace", "--pixel", "600,0"], 2, "outside"),
        (&["info", "/no/such.nii"], 1, "/no/such.nii"),
        (&["--measure-knob", "speed"], 2, "preview-step-multiplier"),
        (&["--auto-orbit", "2"], 2, "--time-frames"),
        (
            &["bench", "--write-peer-tf", "/tmp/never.json"],
            2,
            "--peer",
        ),
    ];
    for (args, code, needle) in cases {
        let o = voxcast(args);
        let t = text(&o);
        assert_eq!(o.status.code(), Some(*code), "{args:?}: {t}");
        assert!(
            t.contains(needle),
            "{args:?} should mention '{needle}': {t}"
        );
        assert!(!t.contains("panicked"), "{args:?}: {t}");
        assert!(!t.contains("os error"), "{args:?} in words: {t}");
        assert!(!t.contains("bad header"), "{args:?}: {t}");
    }
}

/// Without a display the sandbox says how to work without one instead of panicking in winit.
#[test]
fn no_display_points_to_the_headless_commands() {
    let o = Command::new(env!("CARGO_BIN_EXE_voxcast"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(t.contains("--screenshot") && t.contains("xvfb-run"), "{t}");
    assert!(!t.contains("panicked"), "{t}");
    let o = Command::new(env!("CARGO_BIN_EXE_voxcast"))
        .env("DISPLAY", ":4711")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    assert!(t.contains(":4711") && !t.contains("panicked"), "{t}");
}

/// `voxcast trace … | head -1`: the reader leaves early; the writer ends quietly.
#[test]
fn a_closed_pipe_ends_quietly() {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_voxcast"))
        .args([
            "trace",
            "--volume",
            "builtin:bucky",
            "--origin",
            "-5,15.5,15.5",
        ])
        .args(["--dir", "1,0,0", "--step", "0.01"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    assert!(first.starts_with("ray from"), "{first}");
    // The pipe is closed here, with thousands of rows still to write.
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!err.contains("panicked"), "{err}");
    assert_ne!(o.status.code(), Some(101), "a panic's exit code: {err}");
}

/// RayVis's study questions answered from the traces, as the which-effect level checks them: trace 0's
/// camera level in front of the box, trace 1's higher, the shadow rays (trace 4) from many
/// points (no camera) and scarcest, of those that miss, on the back wall.
#[test]
fn rays_study_answers_the_studys_questions() {
    let o = voxcast(&["rays", "study", "builtin:cornell", "--cell", "40"]);
    let t = text(&o);
    assert!(o.status.success(), "{t}");
    let block = |id: u32| {
        let start = t
            .find(&format!("trace {id} ("))
            .unwrap_or_else(|| panic!("{t}"));
        let rest = &t[start..];
        let end = rest[1..].find("\ntrace ").map_or(rest.len(), |e| e + 1);
        rest[..end].to_string()
    };
    assert!(
        block(0).contains("Where was the camera of trace 0? in front of the open side, level"),
        "{t}"
    );
    assert!(block(1).contains("higher than the box's top"), "{t}");
    let shadow = block(4);
    assert!(
        shadow.contains("Where was the camera of trace 4? no answer in this trace"),
        "{shadow}"
    );
    assert!(
        shadow.contains("the smallest share of the rays that start there miss? the back wall"),
        "{shadow}"
    );
    let bad = voxcast(&["rays", "study", "builtin:cornell", "--trace", "9"]);
    assert_eq!(bad.status.code(), Some(2), "{}", text(&bad));
    assert!(text(&bad).contains("has traces"), "{}", text(&bad));
}

/// The help lists the methods with their descriptions; info's options all have help; the
/// percentiles are data values (the 1 % of a volume mostly empty is 0, not a bin centre).
#[test]
fn help_and_info_say_what_they_mean() {
    let help = text(&voxcast(&["render", "--help"]));
    for m in voxcast_core::composite::Method::ALL {
        assert!(
            help.contains(m.name()) && help.contains(m.doc()),
            "{m:?}: {help}"
        );
    }
    let help = text(&voxcast(&["info", "--help"]));
    for line in help.lines().filter(|l| l.trim_start().starts_with("--")) {
        let words = line.split_whitespace().count();
        assert!(words > 2, "no help for '{line}'");
    }
    let o = voxcast(&["info", "builtin:bucky"]);
    let t = text(&o);
    assert!(t.contains("percentiles: 1% 0,"), "{t}");
    for spelling in ["builtin:marschner_lobb", "builtin:marschner-lobb"] {
        let o = voxcast(&["info", spelling]);
        assert!(o.status.success(), "{spelling}: {}", text(&o));
    }
}

/// `voxcast rays`: the Cornell box's traces, and their density written as NRRD volumes that
/// `voxcast info` (and so Slicer and ParaView) opens; bad values fail before any work.
#[test]
fn rays_info_and_density_describe_and_write_the_cornell_box() {
    let o = voxcast(&["rays", "info", "builtin:cornell"]);
    assert!(o.status.success(), "{}", text(&o));
    let out = text(&o);
    for line in [
        "30 triangles",
        "trace 0 (primary rays from camera 1): 65536 rays",
        "trace 1 (primary rays from camera 2): 65536 rays",
        "trace 2 (reflection rays)",
        "trace 3 (ambient-occlusion rays)",
        "trace 4 (shadow rays)",
    ] {
        assert!(out.contains(line), "{line} in\n{out}");
    }
    let counts = out_dir().join("cornell_counts.nrrd");
    let dirs = out_dir().join("cornell_dirs.nrrd");
    let o = voxcast(&[
        "rays",
        "density",
        "builtin:cornell",
        "--trace",
        "4",
        "--filter",
        "hit",
        "--cell",
        "20",
        "--out",
        counts.to_str().unwrap(),
        "--directions",
        dirs.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let out = text(&o);
    assert!(
        out.contains("trace 4 (shadow rays)") && out.contains("cell visits"),
        "{out}"
    );
    let info = voxcast(&["info", counts.to_str().unwrap()]);
    assert!(info.status.success(), "{}", text(&info));
    assert!(
        text(&info).contains("spacing:    20 × 20 × 20"),
        "{}",
        text(&info)
    );
    let header = std::fs::read(&dirs).unwrap();
    let header = String::from_utf8_lossy(&header[..400]);
    assert!(
        header.contains("kinds: vector domain domain domain"),
        "{header}"
    );
    for (args, words) in [
        (
            vec!["--cell", "-1"],
            "cell size -1 must be a positive number",
        ),
        (vec!["--cell", "0.01"], "more than the 2048 MiB allowed"),
        (
            vec!["--cell", "20", "--trace", "9"],
            "has traces 0, 1, 2, 3, 4",
        ),
        (vec!["--cell", "20", "--chunk", "0"], "chunk size 0"),
    ] {
        let mut all = vec!["rays", "density", "builtin:cornell", "--out"];
        all.push(counts.to_str().unwrap());
        all.extend(args);
        let o = voxcast(&all);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert!(text(&o).contains(words), "{words} in {}", text(&o));
    }
    let o = voxcast(&[
        "rays",
        "density",
        "builtin:cornell",
        "--cell",
        "20",
        "--out",
        "/nonexistent/c.nrrd",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
    assert!(text(&o).contains("does not exist"), "{}", text(&o));
    let o = voxcast(&["rays", "info", "/nonexistent/scene.rayvis"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).contains("no such file"), "{}", text(&o));
    // Exported as a .rayvis file and read back: the same traces.
    let file = out_dir().join("cornell.rayvis");
    let o = voxcast(&[
        "rays",
        "export",
        "builtin:cornell",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    let o = voxcast(&["rays", "info", file.to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let out = text(&o);
    assert!(
        out.contains("30 triangles") && out.contains("trace 0: 65536 rays, 61204 hits"),
        "{out}"
    );
    // The file is named once, at the start of its line.
    let name = file.to_str().unwrap();
    assert_eq!(out.matches(name).count(), 1, "{out}");
    assert!(
        out.starts_with(&format!("{name}: a RayVis file: 5 traces")),
        "{out}"
    );
    let garbage = out_dir().join("garbage.rayvis");
    std::fs::write(&garbage, b"AMD_RDF \x03\0\0\0").unwrap();
    let o = voxcast(&["rays", "info", garbage.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).contains("the file ends inside the header"),
        "{}",
        text(&o)
    );
}

/// `voxcast rays render`: the Cornell box's shadow-ray density over the box, as a PNG whose
/// pixels show inferno where the rays are dense and the grey box elsewhere; hiding the scene
/// leaves the density alone on black; bad values fail before any work.
#[test]
fn rays_render_draws_the_density_over_the_scene() {
    let png = out_dir().join("cornell_density.png");
    let render = |extra: &[&str]| {
        let mut args = vec![
            "rays",
            "render",
            "builtin:cornell",
            "--trace",
            "1",
            "--cell",
            "20",
            "--size",
            "96x96",
            "--out",
            png.to_str().unwrap(),
        ];
        args.extend(extra);
        let o = voxcast(&args);
        assert!(o.status.success(), "{extra:?}: {}", text(&o));
        assert!(text(&o).contains("rendered 96×96"), "{}", text(&o));
        image::open(&png).unwrap().to_rgb8()
    };
    let is_grey = |p: &&image::Rgb<u8>| p[0] == p[1] && p[1] == p[2] && p[0] > 20;
    let is_warm = |p: &&image::Rgb<u8>| p[0] > 100 && p[0] as u32 > p[2] as u32 + 40;
    // The fitted range: inferno's reds and yellows over most of the picture.
    let over = render(&[]);
    let warm = over.pixels().filter(is_warm).count();
    assert!(warm > 96 * 96 / 4, "inferno shows: {warm} warm pixels");
    // A range far above every sum: the density is transparent and the grey box shows.
    let faint = render(&["--sum-range", "0,1e9"]);
    let grey = faint.pixels().filter(is_grey).count();
    assert!(grey > 96 * 96 / 2, "the grey box shows: {grey} grey pixels");
    let alone = render(&["--sum-range", "0,1e9", "--scene", "hidden"]);
    assert_eq!(alone.pixels().filter(is_grey).count(), 0, "hidden: no box");
    // A narrower range saturates more pixels to inferno's top.
    let bright = |img: &image::RgbImage| img.pixels().filter(|p| p[0] > 240 && p[1] > 240).count();
    let narrow = render(&["--sum-range", "0,10"]);
    assert!(
        bright(&narrow) > bright(&over),
        "{} vs {}",
        bright(&narrow),
        bright(&over)
    );
    for (args, words) in [
        (vec!["--samples-per-cell", "0"], "--samples-per-cell 0"),
        (vec!["--sum-range", "5,1"], "the low one first"),
        (vec!["--camera", "eye=0,0,0"], "target"),
        (vec!["--scene", "shiny"], "shiny"),
    ] {
        let mut all = vec![
            "rays",
            "render",
            "builtin:cornell",
            "--cell",
            "20",
            "--out",
            png.to_str().unwrap(),
        ];
        all.extend(args);
        let o = voxcast(&all);
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert!(text(&o).contains(words), "{words} in {}", text(&o));
    }
}

/// A ray density opens wherever a volume does: `info` describes it with its inferno preset and
/// where it sits, `render` draws it with Sum; a bad spec says why.
#[test]
fn a_ray_density_is_a_volume_source() {
    let spec = "density:builtin:cornell@trace=1,cell=40";
    let o = voxcast(&["info", spec]);
    assert!(o.status.success(), "{}", text(&o));
    let out = text(&o);
    assert!(
        out.contains("preset:     inferno") && out.contains("rays through cells of 40"),
        "{out}"
    );
    let png = out_dir().join("density_volume.png");
    let o = voxcast(&[
        "render",
        "--volume",
        spec,
        "--size",
        "64x64",
        "--out",
        png.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(text(&o).contains("(sum,"), "{}", text(&o));
    let img = image::open(&png).unwrap().to_rgb8();
    assert!(
        img.pixels().any(|p| p[0] > 150),
        "inferno's light end shows"
    );
    let o = voxcast(&["info", "density:builtin:cornell@cell=x"]);
    assert_eq!(o.status.code(), Some(1), "a load error: {}", text(&o));
    assert!(text(&o).contains("cell=x: not a number"), "{}", text(&o));
}

/// `voxcast levels check` reads a folder of level files as the sandbox's `--levels` would:
/// every problem with its file, step and field, and the exit code says whether any file has
/// an error; a file with warnings only passes. `voxcast levels schema` prints the schema the
/// docs publish.
#[test]
fn levels_check_names_every_problem() {
    let dir = out_dir().join("levels");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("a_broken.json"),
        r#"{"id": "broken", "titel": "x", "concept": "c",
            "scene": {"volume": "builtin:head"},
            "steps": [{"text": "t", "objective": {"kind": "step-at-mots", "voxels": 1}},
                      {"text": "u", "objective": {"kind": "knob-measured", "knob": "stepp"}}]}"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("b_fine.json"),
        r#"{"id": "mine", "title": "Mine", "concept": "c",
            "scene": {"volume": "builtin:head", "rays": 2},
            "steps": [{"text": "Set the step to 2 or more.",
                       "objective": {"kind": "step-at-least", "voxels": 2}}]}"#,
    )
    .unwrap();
    let o = voxcast(&["levels", "check", dir.to_str().unwrap()]);
    let t = text(&o);
    assert_eq!(o.status.code(), Some(1), "{t}");
    for needle in [
        "a_broken.json",
        "error: titel: no such field — did you mean \"title\"?",
        "error: step 1 › objective › kind: no such name \"step-at-mots\" — did you mean \"step-at-most\"?",
        "error: step 2 › objective › knob: \"stepp\" names nothing here — did you mean \"step\"?",
        "b_fine.json — “Mine” (1 steps)",
        "2 files: 1 without a problem, 1 with errors",
    ] {
        assert!(t.contains(needle), "no {needle:?} in:\n{t}");
    }
    let o = voxcast(&["levels", "check", dir.join("b_fine.json").to_str().unwrap()]);
    assert!(o.status.success(), "{}", text(&o));
    let o = voxcast(&["levels", "check", dir.join("nothing").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).contains("cannot be read"), "{}", text(&o));
    let o = voxcast(&["levels", "schema"]);
    assert!(o.status.success());
    let published = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/levels.schema.json"),
    )
    .unwrap();
    assert_eq!(String::from_utf8_lossy(&o.stdout), published);
}

/// `voxcast answers --class` reads a class's answer files (a folder or files) into one HTML
/// report; a foreign file is named in it and left out, never fatal.
#[test]
fn a_class_report_is_written_from_answer_files() {
    let dir = out_dir().join("class");
    std::fs::create_dir_all(&dir).unwrap();
    let header = "level,step,question,answer,expected,correct,time (UTC),run,try,seconds";
    for (k, first) in ["4.99", "5.1", "5.1"].iter().enumerate() {
        let mut rows = vec![header.to_string()];
        let correct = *first == "4.99";
        rows.push(format!(
            "trilinear,2,\"the value at (0.5, 0.5, 0.5)\",{first},4.988,{},2026-12-07T09:00:0{k}Z,,1,20",
            if correct { "yes" } else { "no" }
        ));
        if !correct {
            rows.push(format!(
                "trilinear,2,\"the value at (0.5, 0.5, 0.5)\",4.988,4.988,yes,2026-12-07T09:01:0{k}Z,,2,45"
            ));
        }
        std::fs::write(dir.join(format!("s{k}.csv")), rows.join("\n") + "\n").unwrap();
    }
    std::fs::write(dir.join("marks.csv"), "name,mark\nAda,9\n").unwrap();
    let html = out_dir().join("class.html");
    let o = voxcast(&[
        "answers",
        "--class",
        dir.to_str().unwrap(),
        "--report",
        html.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("3 answer files read, 1 left out"),
        "{}",
        text(&o)
    );
    let page = std::fs::read_to_string(&html).unwrap();
    for needle in [
        "Trilinear interpolation",
        "marks.csv: not a Voxcast answers file",
        "1 (33%)",
        "5.1 ×2",
        "<svg",
    ] {
        assert!(page.contains(needle), "no {needle:?} in the report");
    }
    let o = voxcast(&["answers", "--report", html.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2), "{}", text(&o));
}
