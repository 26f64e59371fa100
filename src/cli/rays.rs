//! `voxcast rays`: ray data sets as RayVis views them — what a set holds (`info`), its
//! density over a grid of cells, written as NRRD volumes (`density`), drawn over the scene
//! (`render`, in `rays_render.rs`), and the set as a `.rayvis` file (`export`).

use super::CliError;
use super::progress::Progress;
use clap::{Args, Subcommand};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use voxcast_core::numbers::sig;
use voxcast_core::rays::density::{DensityParams, MAX_BYTES, compute, estimate_within};
use voxcast_core::rays::grid::DenseDensity;
use voxcast_core::rays::set::{Filter, RaySet};
use voxcast_core::rays::source::{RayData, effect_of, load};

#[derive(Args, Debug)]
pub struct RaysArgs {
    #[command(subcommand)]
    pub command: RaysCommand,
}

#[derive(Subcommand, Debug)]
pub enum RaysCommand {
    /// Per trace its id and its rays, hits and misses; the scene's meshes and triangles.
    Info(InfoArgs),
    /// The number of rays through each cell of a grid, and their mean direction, as NRRD
    /// volumes (Slicer, ParaView and Voxcast open them).
    Density(DensityArgs),
    /// Write the ray data as a .rayvis file (an RDF container RayVis reads).
    Export(ExportArgs),
    /// RayVis's study questions about each trace (where its camera stood, where its hitting
    /// rays start, where a density is particularly high or low), answered from the trace.
    Study(super::rays_study::StudyArgs),
    /// The density over the scene as a PNG, as the sandbox shows it: each pixel's ray sums the
    /// rays per cell it passes (Sum), stopped where it meets the scene, coloured by inferno
    /// and laid over the scene.
    Render(RenderArgs),
}

#[derive(Args, Debug)]
pub struct ExportArgs {
    #[command(flatten)]
    pub source: SourceArg,
    /// The .rayvis file to write.
    #[arg(long, value_name = "FILE.rayvis")]
    pub out: PathBuf,
}

/// The ray data (`builtin:cornell`).
#[derive(Args, Debug)]
pub struct SourceArg {
    /// The ray data: a .rayvis file, or builtin:cornell (the Cornell box with rays Voxcast
    /// traces through it).
    #[arg(value_name = "FILE|builtin:NAME")]
    pub source: String,
    #[arg(long, value_name = "T", default_value_t = 0.0, value_parser = non_negative,
          help = voxcast_core::tunables::MISS_TOLERANCE.doc)]
    pub miss_tolerance: f32,
}

#[derive(Args, Debug)]
pub struct InfoArgs {
    #[command(flatten)]
    pub source: SourceArg,
}

/// Which rays are counted, and the grid of cells they are counted in.
#[derive(Args, Debug)]
pub struct GridArgs {
    /// Count only this trace (see `voxcast rays info`); every trace when left out.
    #[arg(long, value_name = "ID")]
    pub trace: Option<u32>,
    /// Which rays are counted: all, the hits (their segment ends at the hit) or the misses.
    #[arg(long, default_value = "all", value_parser = ["all", "hit", "miss"])]
    pub filter: String,
    /// Cell edge S in world units: cell (i, j, k) spans [iS, (i+1)S) on each axis.
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub cell: f32,
    #[arg(long, value_name = "N", default_value_t = voxcast_core::tunables::RAY_CHUNK.default as u32,
          help = voxcast_core::tunables::RAY_CHUNK.doc)]
    pub chunk: u32,
}

#[derive(Args, Debug)]
pub struct DensityArgs {
    #[command(flatten)]
    pub source: SourceArg,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Where to write the counts (a float NRRD volume over the stored chunks' box).
    #[arg(long, value_name = "COUNTS.nrrd")]
    pub out: PathBuf,
    /// Where to write the mean unit direction per cell (a 3-vector NRRD; zero where no ray
    /// passed).
    #[arg(long, value_name = "DIRS.nrrd")]
    pub directions: Option<PathBuf>,
}

#[derive(Args, Debug)]
pub struct RenderArgs {
    #[command(flatten)]
    pub source: SourceArg,
    #[command(flatten)]
    pub grid: GridArgs,
    /// Image size in pixels.
    #[arg(long, value_name = "WxH", default_value = "512x512", value_parser = super::args::parse_size)]
    pub size: (u32, u32),
    /// eye=X,Y,Z,target=X,Y,Z,up=X,Y,Z,fov=DEG[,ortho=HEIGHT] in world units. Default: the
    /// Cornell box's own camera for builtin:cornell, else the scene seen from the front.
    #[arg(long, value_name = "SPEC")]
    pub camera: Option<String>,
    /// Samples per cell along each ray (RayVis's "step size as fractions of the cell size"):
    /// the step is 1/K of a cell.
    #[arg(long, value_name = "K", default_value_t = 2.0)]
    pub samples_per_cell: f32,
    /// The Sum range (rays per cell times cells along a pixel's ray) spread over inferno.
    /// Default: fitted to the view, 0 to the sum that 95 % of a 32 × 32 grid of the view's
    /// rays (those that gather any) stay below.
    #[arg(long, value_name = "LOW,HIGH", value_parser = super::args::parse_range, allow_negative_numbers = true)]
    pub sum_range: Option<(f32, f32)>,
    /// How the scene is drawn under the density: grey (RayVis's default), colour (each mesh's
    /// own), instance (a colour per mesh instance), normals, barycentrics, or hidden (the
    /// density alone; meshes do not stop the rays).
    #[arg(long, default_value = "grey", value_parser = ["grey", "colour", "color", "instance", "normals", "barycentrics", "hidden"])]
    pub scene: String,
    /// The PNG to write.
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
}

fn non_negative(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("'{s}' is not a number ≥ 0")),
    }
}

pub fn run(a: &RaysArgs) -> Result<(), CliError> {
    match &a.command {
        RaysCommand::Info(i) => info(i),
        RaysCommand::Density(d) => density(d),
        RaysCommand::Export(e) => export(e),
        RaysCommand::Render(r) => super::rays_render::render(r),
        RaysCommand::Study(s) => super::rays_study::study(s),
    }
}

fn export(a: &ExportArgs) -> Result<(), CliError> {
    let data = source(&a.source)?;
    let bytes = voxcast_core::rays::rayvis::write(&data);
    write(&a.out, &bytes)?;
    let rays: usize = data.traces.iter().map(|t| t.rays.len()).sum();
    println!(
        "{} traces, {} rays, {} triangles → {} ({} MiB)",
        data.traces.len(),
        rays,
        data.scene.triangle_count(),
        a.out.display(),
        sig(bytes.len() as f32 / 1_048_576.0)
    );
    Ok(())
}

pub(super) fn source(s: &SourceArg) -> Result<RayData, CliError> {
    load(&s.source).map_err(|e| CliError::usage(e.to_string()))
}

/// A trace's name in words, with its effect for the sets Voxcast traces itself.
pub(super) fn trace_words(source: &str, id: u32) -> String {
    match effect_of(id).filter(|_| source.starts_with("builtin:cornell")) {
        Some(e) => format!("trace {id} ({})", e.words()),
        None => format!("trace {id}"),
    }
}

fn info(a: &InfoArgs) -> Result<(), CliError> {
    let data = source(&a.source)?;
    println!("{}: {}", a.source.source, data.description);
    println!(
        "scene: {} meshes, {} triangles",
        data.scene.meshes.len(),
        data.scene.triangle_count()
    );
    for m in &data.scene.meshes {
        println!("  {:<12} {} triangles", m.name, m.triangles.len());
    }
    for t in &data.traces {
        let (hits, misses) = t.hits_and_misses(a.source.miss_tolerance);
        println!(
            "{}: {} rays, {} hits, {} misses",
            trace_words(&a.source.source, t.trace_id),
            t.rays.len(),
            hits,
            misses
        );
    }
    Ok(())
}

/// A folder that is not there fails now, not after the computation.
pub(super) fn check_folders<'p>(
    paths: impl IntoIterator<Item = &'p PathBuf>,
) -> Result<(), CliError> {
    for path in paths {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty())
            && !dir.is_dir()
        {
            return Err(CliError::usage(format!(
                "{}: the folder {} does not exist",
                path.display(),
                dir.display()
            )));
        }
    }
    Ok(())
}

/// Trace `id` of `data` (read from `name`), or a usage error that lists the traces there are.
pub(super) fn trace_named<'d>(
    data: &'d RayData,
    name: &str,
    id: u32,
) -> Result<&'d RaySet, CliError> {
    data.trace(id).ok_or_else(|| {
        let ids: Vec<String> = data.traces.iter().map(|t| t.trace_id.to_string()).collect();
        CliError::usage(format!(
            "--trace {id}: {name} has traces {}",
            ids.join(", ")
        ))
    })
}

/// The density of the chosen rays, laid out densely, with progress and a report on stdout.
pub(super) fn dense_density(
    data: &RayData,
    name: &str,
    params: &DensityParams,
    g: &GridArgs,
) -> Result<DenseDensity, CliError> {
    let set: RaySet = match g.trace {
        Some(id) => trace_named(data, name, id)?.clone(),
        None => data.all_rays(),
    };
    let what = g
        .trace
        .map_or("every trace".to_string(), |id| trace_words(name, id));
    let Some(est) = estimate_within(&set, params, MAX_BYTES).filter(|e| e.bytes <= MAX_BYTES)
    else {
        return Err(CliError::usage(format!(
            "{what} through cells of {} would take more than the {} MiB allowed: choose larger \
             cells (--cell), smaller chunks (--chunk), one trace (--trace) or a filter (--filter)",
            sig(params.cell),
            MAX_BYTES >> 20
        )));
    };
    println!(
        "{what}: {} rays; about {} chunks of {}³ cells of {}, {} MiB",
        set.rays.len(),
        est.chunks,
        params.chunk,
        sig(params.cell),
        sig(est.bytes as f32 / 1_048_576.0)
    );
    let started = Instant::now();
    let progress = Progress::new("density");
    let d = compute(
        &set,
        params,
        &|done, total| progress.update(done, total),
        &AtomicBool::new(false),
    )
    .map_err(|_| CliError::failed("cancelled"))?;
    progress.finish();
    let seconds = started.elapsed().as_secs_f64();
    let r = &d.report;
    println!(
        "{} rays counted, {} cell visits in {:.2} s ({} M rays/s, {} M visits/s); {} chunks \
         stored, {} MiB (a dense grid: {} MiB)",
        r.rays,
        r.visits,
        seconds,
        sig((r.rays as f64 / seconds.max(1e-9) / 1e6) as f32),
        sig((r.visits as f64 / seconds.max(1e-9) / 1e6) as f32),
        d.chunks.len(),
        sig(d.memory_bytes() as f32 / 1_048_576.0),
        sig(d.dense_bytes() as f32 / 1_048_576.0)
    );
    for (n, why) in [
        (r.malformed, "skipped as malformed"),
        (r.out_of_range, "skipped for starting too far out"),
        (r.capped, "cut short at the cells-per-ray cap"),
    ] {
        if n > 0 {
            println!("{n} rays {why}");
        }
    }
    DenseDensity::new(&d)
        .map_err(CliError::failed)?
        .ok_or_else(|| {
            CliError::failed(format!(
                "no ray of {what} passed the filter '{}': nothing to show",
                g.filter
            ))
        })
}

pub(super) fn grid_params(g: &GridArgs, tolerance: f32) -> Result<DensityParams, CliError> {
    let params = DensityParams {
        cell: g.cell,
        chunk: g.chunk,
        filter: Filter::parse(&g.filter).unwrap_or_default(),
        tolerance,
        ..Default::default()
    };
    params.check().map_err(CliError::usage)?;
    Ok(params)
}

fn density(a: &DensityArgs) -> Result<(), CliError> {
    let params = grid_params(&a.grid, a.source.miss_tolerance)?;
    check_folders(std::iter::once(&a.out).chain(&a.directions))?;
    let data = source(&a.source)?;
    let dense = dense_density(&data, &a.source.source, &params, &a.grid)?;
    if dense.inexact_counts() {
        println!("note: some cells hold more than 16 777 216 rays; their float counts are rounded");
    }
    write(&a.out, &dense.counts_nrrd())?;
    let o = dense.origin();
    println!(
        "counts → {} ({} × {} × {} cells, first cell's centre at ({}, {}, {}))",
        a.out.display(),
        dense.dims.x,
        dense.dims.y,
        dense.dims.z,
        sig(o.x),
        sig(o.y),
        sig(o.z)
    );
    if let Some(path) = &a.directions {
        write(path, &dense.directions_nrrd())?;
        println!("mean directions → {}", path.display());
    }
    Ok(())
}

fn write(path: &std::path::Path, bytes: &[u8]) -> Result<(), CliError> {
    std::fs::write(path, bytes).map_err(|e| {
        CliError::failed(format!(
            "{}: {}",
            path.display(),
            voxcast_core::error::io_words(&e)
        ))
    })
}
