//! `voxcast bench`: the speed/accuracy trade of the step size, measured, and the same scene through
//! the VTK peer in the same run.
//!
//! For each step (in voxels) and with opacity correction on and off, the scene is rendered
//! `--repeat` times (median time) and compared with a render at the reference step (1/16 voxel by
//! default) made with the same correction setting: RMSE and largest channel error, in 8-bit units
//! of the full range. With `--peer DIR` (`../shared/tools/peer`), VTK's CPU ray caster
//! (vtkFixedPointVolumeRayCastMapper) renders the same volume, transfer function, camera, size and
//! sample distance with the same number of threads, and the ratio of median times is reported.

use super::CliError;
use super::args::{CameraArgs, SettingsArgs, VolumeArgs, parse_size};
use super::plot::{Series, log_log};
use super::render::{Timed, median, timed_render};
use clap::Args;
use std::path::{Path, PathBuf};
use std::process::Command;
use voxcast_core::error::io_words;
use voxcast_core::glam::Vec3;
use voxcast_core::image_out::{LinearImage, save_rgb8_atomic};
use voxcast_core::step::Length;
use voxcast_core::trace::{Scene, Vectors};

#[derive(Args, Debug)]
pub struct BenchArgs {
    #[command(flatten)]
    pub volume: VolumeArgs,
    #[command(flatten)]
    pub settings: SettingsArgs,
    #[command(flatten)]
    pub camera: CameraArgs,
    #[command(flatten)]
    pub cpu: super::args::CpuArgs,
    /// Image size in pixels.
    #[arg(long, default_value = "512x512", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Steps to measure, in voxels.
    #[arg(long, default_value = "4,2,1,0.5,0.25,0.125", value_delimiter = ',')]
    pub steps: Vec<f32>,
    /// The reference step (voxels) errors are measured against.
    #[arg(long = "reference", default_value_t = 0.0625)]
    pub reference: f32,
    /// Renders per step; the median time is reported.
    #[arg(long, default_value_t = 3)]
    pub repeat: u32,
    /// Worker threads for Voxcast and VTK (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// The peer harness folder (../shared/tools/peer): also render with VTK and report the ratio.
    #[arg(long)]
    pub peer: Option<PathBuf>,
    /// Python with VTK (default: PEER/venv/bin/python).
    #[arg(long)]
    pub peer_python: Option<PathBuf>,
    /// The peer's transfer-function JSON (default: PEER/tf/<preset>.json).
    #[arg(long)]
    pub peer_tf: Option<PathBuf>,
    /// Instead: write the transfer function the peer is given for this scene (`--peer-tf`, else
    /// the peer's own file for the preset, else this run's in the peer's format) to this file —
    /// for a run of the peer on another machine (benches/gpu.sh).
    #[arg(long, value_name = "FILE", requires = "peer")]
    pub write_peer_tf: Option<PathBuf>,
    /// The step (voxels) at which Voxcast and VTK are compared.
    #[arg(long, default_value_t = 0.5)]
    pub peer_step: f32,
    /// Timed VTK frames per round (median reported).
    #[arg(long, default_value_t = 5)]
    pub peer_frames: u32,
    /// Rounds of VTK then Voxcast, alternating, so both see the same machine (timings on a
    /// shared machine drift); the ratio is of the medians over rounds.
    #[arg(long, default_value_t = 3)]
    pub peer_rounds: u32,
    /// Write the markdown report here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// With --report: replace only the block between `<!-- bench:NAME -->` and
    /// `<!-- /bench:NAME -->` in that file (appended if absent), keeping the rest.
    #[arg(long, value_name = "NAME", requires = "report")]
    pub section: Option<String>,
    /// Write the RMSE-vs-time plot (PNG) here.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Keep the images (Voxcast at each step, the references, VTK's) in this folder.
    #[arg(long)]
    pub images: Option<PathBuf>,
    /// Instead: measure every knob's trade (step, interpolation, cutoff, jitter,
    /// supersampling, preview resolution and step multiplier) against its exact setting, and
    /// print (or with --report, write) a markdown table per knob.
    #[arg(long)]
    pub knobs: bool,
}

/// One measured row.
struct Row {
    correction: bool,
    step: f32,
    timed: Timed,
    rmse: f64,
    max_err: f32,
}

/// What the peer measured.
struct PeerResult {
    /// Per round: VTK's median seconds per frame, then Voxcast's median for the same scene.
    rounds: Vec<(f64, f64)>,
    first_s: f64,
    threads: String,
    vtk_image: Option<LinearImage>,
    our_image: LinearImage,
}

impl PeerResult {
    fn vtk_median(&self) -> f64 {
        median(&self.rounds.iter().map(|r| r.0).collect::<Vec<_>>())
    }
    fn our_median(&self) -> f64 {
        median(&self.rounds.iter().map(|r| r.1).collect::<Vec<_>>())
    }
}

pub fn run(a: &BenchArgs) -> Result<(), CliError> {
    a.cpu.apply();
    if a.steps.is_empty()
        || a.steps
            .iter()
            .chain([&a.reference])
            .any(|s| !(s.is_finite() && *s > 0.0))
    {
        return Err(CliError::usage(
            "--steps and --reference must be positive numbers",
        ));
    }
    let loaded = a.volume.load()?;
    let resolved = a.settings.resolve(&loaded)?;
    for note in &resolved.notes {
        eprintln!("note: {note}");
    }
    let camera = a.camera.camera(&loaded, resolved.preset.as_ref())?;
    let voxel = loaded.volume.spacing().min_element();
    if let (Some(file), Some(dir)) = (&a.write_peer_tf, &a.peer) {
        let text = peer_transfer(a, dir, &resolved, voxel).map_err(CliError::failed)?;
        return std::fs::write(file, text)
            .map_err(|e| CliError::failed(format!("{}: {}", file.display(), io_words(&e))));
    }
    if a.knobs {
        return knobs_report(a, &loaded, &resolved, &camera);
    }
    let threads = a
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    if let Some(dir) = &a.images {
        std::fs::create_dir_all(dir)
            .map_err(|e| CliError::failed(format!("{}: {}", dir.display(), io_words(&e))))?;
    }

    let mut rows = Vec::new();
    for correction in [true, false] {
        let mut s = resolved.settings.clone();
        s.opacity_correction = correction;
        s.step = Length::Voxels(a.reference);
        let scene = Scene::new(&loaded.volume, &resolved.transfer, &s, camera.forward())?;
        let label = format!("reference 1/{:.0} voxel", 1.0 / a.reference);
        let reference = timed_render(&scene, &camera, a.size, 1, Some(threads), &label)?;
        save_image(
            a,
            &format!("reference_{}.png", tag(correction)),
            &reference.image,
        )?;
        for &step in &a.steps {
            s.step = Length::Voxels(step);
            let scene = Scene::new(&loaded.volume, &resolved.transfer, &s, camera.forward())?;
            let timed = timed_render(
                &scene,
                &camera,
                a.size,
                a.repeat,
                Some(threads),
                &format!("step {step}"),
            )?;
            let diff = timed.image.diff(&reference.image).expect("same size");
            save_image(
                a,
                &format!("step_{step}_{}.png", tag(correction)),
                &timed.image,
            )?;
            eprintln!(
                "correction {:3}, step {step:>6}: {:.3} s, {:>11} samples ({} interpolated), RMSE {:.3}/255",
                tag(correction),
                timed.median(),
                timed.stats.positions,
                timed.stats.samples,
                diff.rmse * 255.0
            );
            rows.push(Row {
                correction,
                step,
                rmse: diff.rmse,
                max_err: diff.max_abs,
                timed,
            });
        }
    }

    let peer = a
        .peer
        .as_ref()
        .map(|dir| compare_with_peer(a, dir, &loaded.volume, &resolved, &camera, voxel, threads));
    let report = report(
        a,
        &loaded.volume,
        &resolved,
        &rows,
        peer.as_ref(),
        threads,
        voxel,
    );
    println!("{report}");
    if let Some(path) = &a.report {
        write_report(path, a.section.as_deref(), &report)?;
    }
    if let Some(path) = &a.plot {
        let series: Vec<Series> = [(true, [31, 119, 180]), (false, [230, 120, 20])]
            .into_iter()
            .map(|(correction, color)| Series {
                name: format!("correction {}", tag(correction)),
                color,
                points: rows
                    .iter()
                    .filter(|r| r.correction == correction)
                    .map(|r| (r.timed.median(), r.rmse * 255.0, format!("{}", r.step)))
                    .collect(),
            })
            .collect();
        let title = format!(
            "{} - RMSE VS TIME, LABELS: STEP IN VOXELS",
            loaded.volume.name()
        );
        let img = log_log(&series, &title, "TIME PER FRAME (S)", "RMSE (/255)");
        save_rgb8_atomic(&img, path)
            .map_err(|e| CliError::failed(format!("{}: {e}", path.display())))?;
    }
    Ok(())
}

/// `--knobs`: every knob's table, printed or written into the report's section.
fn knobs_report(
    a: &BenchArgs,
    loaded: &super::args::Opened,
    resolved: &super::args::Resolved,
    camera: &voxcast_core::camera::Camera,
) -> Result<(), CliError> {
    let view = voxcast_core::trade::View {
        volume: &loaded.volume,
        transfer: &resolved.transfer,
        camera,
        size: a.size,
    };
    let words = format!(
        "{} ({}), {}",
        loaded.volume.name(),
        resolved.settings.method.name(),
        super::knobs::camera_words(camera)
    );
    let text = super::knobs::tables(&view, &resolved.settings, &words)?;
    match &a.report {
        Some(path) => {
            print!("{text}");
            write_report(path, a.section.as_deref(), &text)
        }
        None => {
            print!("{text}");
            Ok(())
        }
    }
}

/// Writes `report` to `path`, or with `section` only into that section of it.
pub(super) fn write_report(
    path: &Path,
    section: Option<&str>,
    report: &str,
) -> Result<(), CliError> {
    let text = match section {
        None => report.to_string(),
        Some(name) => replace_section(
            &std::fs::read_to_string(path).unwrap_or_default(),
            name,
            report,
        ),
    };
    std::fs::write(path, text)
        .map_err(|e| CliError::failed(format!("{}: {}", path.display(), io_words(&e))))
}

/// `old` with the block between the `bench:NAME` markers replaced by `body` (or appended).
fn replace_section(old: &str, name: &str, body: &str) -> String {
    let (open, close) = (
        format!("<!-- bench:{name} -->"),
        format!("<!-- /bench:{name} -->"),
    );
    let block = format!("{open}\n{}\n{close}", body.trim_end());
    match (old.find(&open), old.find(&close)) {
        (Some(a), Some(b)) if b > a => format!("{}{block}{}", &old[..a], &old[b + close.len()..]),
        _ => format!(
            "{}{}{block}\n",
            old,
            if old.is_empty() || old.ends_with('\n') {
                ""
            } else {
                "\n"
            }
        ),
    }
}

fn tag(correction: bool) -> &'static str {
    if correction { "on" } else { "off" }
}

fn save_image(a: &BenchArgs, name: &str, img: &LinearImage) -> Result<(), CliError> {
    if let Some(dir) = &a.images {
        let path = dir.join(name);
        img.save_png(&path)
            .map_err(|e| CliError::failed(format!("{}: {e}", path.display())))?;
    }
    Ok(())
}

/// The transfer function the peer is given (JSON in its format): `--peer-tf`, else the peer's
/// own file for the preset where it has one, else this run's transfer function and settings
/// written in its format.
fn peer_transfer(
    a: &BenchArgs,
    dir: &Path,
    resolved: &super::args::Resolved,
    voxel: f32,
) -> Result<String, String> {
    let own = resolved
        .preset
        .as_ref()
        .map(|p| dir.join("tf").join(format!("{}.json", p.name)));
    let file = match (&a.peer_tf, own) {
        (Some(p), _) => p.clone(),
        (None, Some(p)) if p.exists() => p,
        _ => {
            return Ok(voxcast_core::peer::to_json(
                &resolved.transfer,
                &resolved.settings,
                voxel,
            ));
        }
    };
    std::fs::read_to_string(&file).map_err(|e| format!("{}: {}", file.display(), io_words(&e)))
}

/// Renders the same scene with VTK's fixed-point CPU ray caster and with Voxcast, alternating.
fn compare_with_peer(
    a: &BenchArgs,
    dir: &Path,
    volume: &voxcast_core::Prepared,
    resolved: &super::args::Resolved,
    camera: &voxcast_core::camera::Camera,
    voxel: f32,
    threads: usize,
) -> Result<PeerResult, String> {
    let python = a
        .peer_python
        .clone()
        .unwrap_or_else(|| dir.join("venv/bin/python"));
    let out = std::env::temp_dir().join(format!("voxcast-peer-{}", std::process::id()));
    std::fs::create_dir_all(&out).map_err(|e| e.to_string())?;
    let tf = out.join("tf.json");
    std::fs::write(&tf, peer_transfer(a, dir, resolved, voxel)?)
        .map_err(|e| format!("{}: {}", tf.display(), io_words(&e)))?;
    let camera_file = a
        .camera
        .camera
        .clone()
        .filter(|c| !c.contains('='))
        .ok_or("the peer needs --camera FILE (a peer camera JSON)")?;
    if a.volume.volume.starts_with("builtin:") {
        return Err("the peer needs --volume FILE".into());
    }
    let (png, json) = (out.join("vtk.png"), out.join("vtk.json"));
    let method = match resolved.settings.method {
        voxcast_core::composite::Method::Accumulate => "composite",
        voxcast_core::composite::Method::Maximum => "mip",
        voxcast_core::composite::Method::Minimum => "minip",
        other => return Err(format!("VTK's CPU mapper has no {} mode", other.name())),
    };
    let mut settings = resolved.settings.clone();
    settings.opacity_correction = true;
    settings.step = Length::Voxels(a.peer_step);
    let scene = Scene::new(volume, &resolved.transfer, &settings, camera.forward())
        .map_err(|e| e.to_string())?;
    let mut rounds = Vec::new();
    let mut first_s = f64::NAN;
    let mut fp_threads = String::new();
    let mut ours = None;
    for round in 0..a.peer_rounds.max(1) {
        eprintln!("round {}: the VTK peer ({threads} threads)…", round + 1);
        let status = Command::new(&python)
            .arg(dir.join("vtk_render.py"))
            .args(["--volume", &a.volume.volume])
            .arg("--tf")
            .arg(&tf)
            .args([
                "--camera",
                &camera_file,
                "--mapper",
                "fixedpoint",
                "--blend",
                method,
            ])
            .args(["--sample-distance", &format!("{}", a.peer_step * voxel)])
            .args(["--size", &a.size.0.to_string(), &a.size.1.to_string()])
            .args([
                "--frames",
                &a.peer_frames.to_string(),
                "--threads",
                &threads.to_string(),
            ])
            .arg("--out")
            .arg(&png)
            .arg("--json-out")
            .arg(&json)
            .status()
            .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
        if !status.success() {
            return Err(format!("the peer exited with {status}"));
        }
        let text = std::fs::read_to_string(&json).map_err(|e| e.to_string())?;
        let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
        let vtk_s = v["median_s"]
            .as_f64()
            .ok_or("no median_s in the peer's JSON")?;
        first_s = v["first_frame_s"].as_f64().unwrap_or(f64::NAN);
        fp_threads = v["fixedpoint_threads"].to_string();
        let timed = timed_render(
            &scene,
            camera,
            a.size,
            a.repeat,
            Some(threads),
            &format!("round {} Voxcast", round + 1),
        )
        .map_err(|e| e.to_string())?;
        eprintln!(
            "round {}: VTK {vtk_s:.3} s, Voxcast {:.3} s",
            round + 1,
            timed.median()
        );
        rounds.push((vtk_s, timed.median()));
        ours = Some(timed.image);
    }
    let vtk_image = image::open(&png)
        .ok()
        .map(|i| LinearImage::from_rgb8(&i.to_rgb8()));
    if let (Some(dir), Some(img)) = (&a.images, &vtk_image) {
        let _ = img.save_png(&dir.join("vtk.png"));
    }
    Ok(PeerResult {
        rounds,
        first_s,
        threads: fp_threads,
        vtk_image,
        our_image: ours.expect("at least one round"),
    })
}

fn report(
    a: &BenchArgs,
    volume: &voxcast_core::Prepared,
    resolved: &super::args::Resolved,
    rows: &[Row],
    peer: Option<&Result<PeerResult, String>>,
    threads: usize,
    voxel: f32,
) -> String {
    use std::fmt::Write;
    use voxcast_core::composite::Method;
    let s = &resolved.settings;
    let mut r = String::new();
    let ghz = super::knobs::cpu_ghz();
    let scene = voxcast_core::trace::Scene::new(volume, &resolved.transfer, s, Vec3::NEG_Z);
    let path = match s.method {
        Method::Maximum | Method::Minimum => "the projections' eight-lane values and bricks' test",
        Method::Average | Method::Sum => "the projections' eight-lane values",
        Method::Accumulate | Method::First => "Accumulate's eight-lane path",
    };
    let instructions = scene.as_ref().ok().and_then(|scene| match s.method {
        Method::Accumulate | Method::First => voxcast_core::trace::lane_instructions(scene),
        _ => voxcast_core::trace::value_lane_instructions(scene),
    });
    let path = match instructions {
        Some(i) => format!("{path} ({i})"),
        None => path.to_string(),
    };
    let lanes = instructions.is_some();
    let _ = writeln!(
        r,
        "Measured on {} ({} threads{}), {path} {}. *ns* and \
         *cycles* are per interpolated sample, all of the render's time counted (threads × \
         seconds ÷ interpolated samples; cycles at the nominal clock: this machine exposes no \
         cycle counters).\n",
        super::knobs::cpu_model(),
        threads,
        ghz.map_or(String::new(), |g| format!(", {g:.2} GHz nominal")),
        match (voxcast_core::trace::vectors(), lanes) {
            (Vectors::Off, _) => {
                "turned off (`--no-lanes`: as a CPU without their vector instructions renders)"
            }
            (Vectors::Narrow, true) => {
                "on, in two halves of four (`--narrow-lanes`: as a CPU without AVX renders)"
            }
            (Vectors::Narrow, false) =>
                "turned off (`--narrow-lanes`: as a CPU without AVX renders)",
            (Vectors::Wide, true) => "on",
            (Vectors::Wide, false) => "not used",
        },
    );
    let _ = writeln!(
        r,
        "Scene: `{}` ({}×{}×{} {}), transfer function `{}`, method {}, {}×{} pixels, shading {}, \
         early termination {} (cutoff {}), {} threads, {} render(s) per step (median). Errors are \
         against step {} voxel with the same correction setting, in 8-bit units (/255).\n",
        volume.name(),
        volume.dims().x,
        volume.dims().y,
        volume.dims().z,
        volume.scalar_type().name(),
        resolved.transfer.name,
        s.method.name(),
        a.size.0,
        a.size.1,
        tag(s.shading),
        tag(s.early_termination),
        s.cutoff,
        threads,
        a.repeat,
        a.reference
    );
    let _ = writeln!(
        r,
        "| correction | step (voxels) | time (s) | samples | M samples/s | interpolated | ns | cycles | RMSE (/255) | max error (/255) |"
    );
    let _ = writeln!(
        r,
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for row in rows {
        let ns = row.timed.median() * threads as f64 * 1e9 / row.timed.stats.samples.max(1) as f64;
        let _ = writeln!(
            r,
            "| {} | {} | {:.3} | {} | {:.1} | {} | {:.0} | {} | {:.3} | {:.0} |",
            tag(row.correction),
            row.step,
            row.timed.median(),
            row.timed.stats.positions,
            row.timed.samples_per_second() / 1e6,
            row.timed.stats.samples,
            ns,
            ghz.map_or("–".into(), |g| format!("{:.0}", ns * g)),
            row.rmse * 255.0,
            row.max_err * 255.0
        );
    }
    if let Some(peer) = peer {
        match peer {
            Ok(p) => {
                let diff = p
                    .vtk_image
                    .as_ref()
                    .and_then(|img| p.our_image.diff(img))
                    .map_or("n/a".into(), |d| format!("{:.1}/255 RMSE", d.rmse * 255.0));
                let rounds: Vec<String> = p
                    .rounds
                    .iter()
                    .map(|(v, o)| format!("{v:.3}/{o:.3}"))
                    .collect();
                let _ = writeln!(
                    r,
                    "\nVTK peer (vtkFixedPointVolumeRayCastMapper, {} threads, sample distance {:.4} world units = {} voxel, \
                     opacity correction on both): {:.3} s per frame, Voxcast {:.3} s (medians over {} alternating rounds; \
                     VTK/Voxcast per round {}; VTK's first frame {:.3} s). **VTK / Voxcast = {:.2}×** (above 1: Voxcast is \
                     faster). Image difference Voxcast vs VTK: {}.",
                    p.threads,
                    a.peer_step * voxel,
                    a.peer_step,
                    p.vtk_median(),
                    p.our_median(),
                    p.rounds.len(),
                    rounds.join(", "),
                    p.first_s,
                    p.vtk_median() / p.our_median(),
                    diff
                );
            }
            Err(e) => {
                let _ = writeln!(r, "\nVTK peer: not measured ({e}).");
            }
        }
    }
    r
}

#[cfg(test)]
mod tests {
    use super::replace_section;

    #[test]
    fn sections_are_replaced_in_place_or_appended() {
        let doc = "# B\n<!-- bench:x -->\nold\n<!-- /bench:x -->\ntail\n";
        assert_eq!(
            replace_section(doc, "x", "new"),
            "# B\n<!-- bench:x -->\nnew\n<!-- /bench:x -->\ntail\n"
        );
        assert_eq!(
            replace_section("# B", "y", "t"),
            "# B\n<!-- bench:y -->\nt\n<!-- /bench:y -->\n"
        );
    }
}
