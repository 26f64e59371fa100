//! `voxcast render`: the exact CPU image of a volume, with its time and sample rate.

use super::CliError;
use super::args::{CameraArgs, SettingsArgs, VolumeArgs, parse_size};
use super::progress::Progress;
use clap::Args;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use voxcast_core::cost::{CostMap, CostView, render_with_cost_in};
use voxcast_core::image_out::LinearImage;
use voxcast_core::render::{Cancelled, Job, RenderStats, TileSlices, render};
use voxcast_core::slices::{Deadline, Step};
use voxcast_core::trace::Scene;

#[derive(Args, Debug)]
pub struct RenderArgs {
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
    /// Output PNG.
    #[arg(long, default_value = "render.png")]
    pub out: PathBuf,
    /// Render this many times and report the median time.
    #[arg(long, default_value_t = 1)]
    pub repeat: u32,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Also write what each pixel's rays cost as a heat map, beside the image (`_cost` added
    /// to its name): samples (interpolated), skipped (positions passed without interpolating)
    /// or stops (how the rays stopped).
    #[arg(long, value_parser = ["samples", "skipped", "stops"])]
    pub cost: Option<String>,
    /// With the method First, also write its depth image: each pixel's distance from the eye
    /// to where First found the target (white nearest, dark grey farthest, misses in the
    /// background), and the raw distances beside it as a 2-D NRRD of floats (`.nrrd`).
    #[arg(long, value_name = "FILE.png")]
    pub depth: Option<PathBuf>,
    /// The depth image's scale: the volume's box (white where it comes nearest the eye, dark
    /// grey at its farthest corner; images of one view compare by shade) or the hits' own
    /// range (white the nearest hit, dark grey the farthest; a surface in a slice of the box
    /// shows its shape).
    #[arg(long, value_parser = ["box", "hits"], default_value = "box")]
    pub depth_scale: String,
}

/// One timed render's outcome.
pub struct Timed {
    pub image: LinearImage,
    pub stats: RenderStats,
    /// Seconds per render, one entry per repetition.
    pub seconds: Vec<f64>,
}

impl Timed {
    pub fn median(&self) -> f64 {
        median(&self.seconds)
    }

    /// Sample positions per second (skipped empty space included; see [`RenderStats`]).
    pub fn samples_per_second(&self) -> f64 {
        self.stats.positions as f64 / self.median()
    }
}

/// The median of `v` (NaN for none: a rate divided by it reads as no figure).
pub fn median(v: &[f64]) -> f64 {
    voxcast_core::numbers::median(v).unwrap_or(f64::NAN)
}

/// `repeat` renders of `camera`'s view of `scene`, each timed, on `threads` threads (the
/// current pool when `None`); the last one's image.
pub fn timed_render(
    scene: &Scene<'_>,
    camera: &voxcast_core::camera::Camera,
    (w, h): (u32, u32),
    repeat: u32,
    threads: Option<usize>,
    label: &str,
) -> Result<Timed, CliError> {
    let cancel = AtomicBool::new(false);
    let work =
        |progress: &(dyn Fn(usize, usize) + Sync)| render(scene, camera, w, h, progress, &cancel);
    let ((image, stats), seconds) = timed_runs(repeat, threads, label, work)?;
    Ok(Timed {
        image,
        stats,
        seconds,
    })
}

/// [`timed_render`] of the picture and its cost map from one march
/// (`render_with_cost_in`): the time is both's.
fn timed_render_with_cost(
    scene: &Scene<'_>,
    camera: &voxcast_core::camera::Camera,
    size: (u32, u32),
    repeat: u32,
    threads: Option<usize>,
    label: &str,
) -> Result<(Timed, CostMap), CliError> {
    let cancel = AtomicBool::new(false);
    let work = |progress: &(dyn Fn(usize, usize) + Sync)| {
        let job = Job::plain(scene, camera, size, progress, &cancel);
        render_with_cost_in(&job, &mut TileSlices::default(), Deadline::NONE).map(Step::whole)
    };
    let ((image, stats, cost), seconds) = timed_runs(repeat, threads, label, work)?;
    let timed = Timed {
        image,
        stats,
        seconds,
    };
    Ok((timed, cost))
}

/// `repeat` runs of `work` (given its progress callback), each timed, on `threads` threads
/// (the current pool when `None`): the last one's result and every run's seconds.
fn timed_runs<T: Send>(
    repeat: u32,
    threads: Option<usize>,
    label: &str,
    work: impl Fn(&(dyn Fn(usize, usize) + Sync)) -> Result<T, Cancelled> + Sync,
) -> Result<(T, Vec<f64>), CliError> {
    let pool = match threads {
        Some(n) => Some(
            rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| CliError::failed(format!("cannot start {n} threads: {e}")))?,
        ),
        None => None,
    };
    let mut seconds = Vec::new();
    let mut last = None;
    for i in 0..repeat.max(1) {
        let progress = Progress::new(format!("{label} {}/{}", i + 1, repeat.max(1)));
        let run = || work(&|d, t| progress.update(d, t));
        let start = Instant::now();
        let result = match &pool {
            Some(p) => p.install(run),
            None => run(),
        };
        seconds.push(start.elapsed().as_secs_f64());
        progress.finish();
        last = Some(result.map_err(|e| CliError::failed(e.to_string()))?);
    }
    Ok((last.expect("at least one run"), seconds))
}

pub fn run(a: &RenderArgs) -> Result<(), CliError> {
    a.cpu.apply();
    let t_load = Instant::now();
    let loaded = a.volume.load()?;
    let load_s = t_load.elapsed().as_secs_f64();
    let resolved = a.settings.resolve(&loaded)?;
    for note in &resolved.notes {
        eprintln!("note: {note}");
    }
    let camera = a.camera.camera(&loaded, resolved.preset.as_ref())?;
    if let Some(path) = &a.depth {
        let method = resolved.settings.method;
        if method != voxcast_core::composite::Method::First {
            return Err(CliError::usage(
                voxcast_core::depth::DepthError::NotFirst(method.name()).to_string(),
            ));
        }
        if path
            .extension()
            .is_none_or(|e| !e.eq_ignore_ascii_case("png"))
        {
            return Err(CliError::usage(format!(
                "{}: give the depth image a name ending in .png (its raw distances go \
                 beside it as .nrrd)",
                path.display()
            )));
        }
        super::rays_input::check_folders([path])?;
    }
    let t_prep = Instant::now();
    let scene = Scene::new(
        &loaded.volume,
        &resolved.transfer,
        &resolved.settings,
        camera.forward(),
    )?;
    let prep_s = t_prep.elapsed().as_secs_f64();
    // The cost views and First's depth come from the render's own march, timed with it.
    let (timed, cost) = if a.cost.is_some() || a.depth.is_some() {
        let (timed, cost) =
            timed_render_with_cost(&scene, &camera, a.size, a.repeat, a.threads, "rendering")?;
        (timed, Some(cost))
    } else {
        let timed = timed_render(&scene, &camera, a.size, a.repeat, a.threads, "rendering")?;
        (timed, None)
    };
    timed
        .image
        .save_png(&a.out)
        .map_err(|e| CliError::failed(format!("cannot write {}: {e}", a.out.display())))?;
    let s = &resolved.settings;
    println!(
        "rendered {}×{} {} ({}, step {} voxel){} in {:.3} s{}: {} sample positions, {} interpolated ({}), {:.1} M samples/s → {} (loading {:.2} s and preparation {:.2} s excluded)",
        a.size.0,
        a.size.1,
        loaded.volume.name(),
        s.method.name(),
        voxcast_core::numbers::sig(s.step.voxels(loaded.volume.spacing().min_element())),
        if cost.is_some() {
            " with its cost map (one march)"
        } else {
            ""
        },
        timed.median(),
        if a.repeat > 1 {
            format!(" (median of {})", a.repeat)
        } else {
            String::new()
        },
        timed.stats.positions,
        timed.stats.samples,
        if timed.stats.samples < timed.stats.positions {
            "the rest skipped"
        } else {
            "none skipped"
        },
        timed.samples_per_second() / 1e6,
        a.out.display(),
        load_s,
        prep_s,
    );
    if let Some(warning) = timed.stats.cap_warning(s.max_samples) {
        eprintln!("warning: {warning}");
    }
    if let Some(map) = cost {
        if let Some(view) = a.cost.as_deref().and_then(CostView::parse) {
            write_cost(&map, a, view)?;
        }
        let view = if a.depth_scale == "hits" {
            CostView::DepthOfHits
        } else {
            CostView::Depth
        };
        if let (Some(path), Some(depth)) = (&a.depth, map.depth_as(view)) {
            write_depth(&depth, map.background, path)?;
        }
    }
    Ok(())
}

/// Writes First's depth image to `path` and its raw distances beside it (`.nrrd`).
fn write_depth(
    depth: &voxcast_core::depth::DepthMap,
    background: voxcast_core::glam::Vec3,
    path: &std::path::Path,
) -> Result<(), CliError> {
    let cannot = |p: &std::path::Path, e: &dyn std::fmt::Display| {
        CliError::failed(format!("cannot write {}: {e}", p.display()))
    };
    depth
        .image(background)
        .save_png(path)
        .map_err(|e| cannot(path, &e))?;
    let raw = path.with_extension("nrrd");
    std::fs::write(&raw, depth.nrrd()).map_err(|e| cannot(&raw, &e))?;
    println!(
        "depth → {} (raw distances → {}): {}.",
        path.display(),
        raw.display(),
        depth.scale_words()
    );
    Ok(())
}

/// Writes the cost heat map of the render beside its image, and says what its scale means.
fn write_cost(map: &CostMap, a: &RenderArgs, view: CostView) -> Result<(), CliError> {
    let stem = a.out.file_stem().unwrap_or_default().to_string_lossy();
    let path = a.out.with_file_name(format!("{stem}_cost.png"));
    map.image(view)
        .save_png(&path)
        .map_err(|e| CliError::failed(format!("cannot write {}: {e}", path.display())))?;
    let scale = match view {
        CostView::Stops => String::new(),
        _ => format!(
            " {}.",
            voxcast_core::cost::scale_words(map.full_scale, map.max(view))
        ),
    };
    println!(
        "cost ({}) → {}: {}{scale}",
        view.name(),
        path.display(),
        view.doc()
    );
    Ok(())
}
