//! What the `voxcast rays` subcommands read alike: the ray data source and its trace, the grid
//! of cells and its density, and the output folders checked before long work.

use super::CliError;
use super::progress::Progress;
use clap::Args;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;
use voxcast_core::numbers::sig;
use voxcast_core::rays::data::RayData;
use voxcast_core::rays::density::{DensityParams, MAX_BYTES, compute, estimate_within};
use voxcast_core::rays::grid::DenseDensity;
use voxcast_core::rays::set::{Filter, RaySet};
use voxcast_core::rays::source::{effect_of, load};

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

pub fn non_negative(s: &str) -> Result<f32, String> {
    match s.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("'{s}' is not a number ≥ 0")),
    }
}

pub fn source(s: &SourceArg) -> Result<RayData, CliError> {
    load(&s.source).map_err(|e| CliError::usage(e.to_string()))
}

/// A trace's name in words, with its effect for the sets Voxcast traces itself.
pub fn trace_words(source: &str, id: u32) -> String {
    match effect_of(id).filter(|_| source.starts_with("builtin:cornell")) {
        Some(e) => format!("trace {id} ({})", e.words()),
        None => format!("trace {id}"),
    }
}

/// A folder that is not there fails now, not after the computation.
pub fn check_folders<'p>(paths: impl IntoIterator<Item = &'p PathBuf>) -> Result<(), CliError> {
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
pub fn trace_named<'d>(data: &'d RayData, name: &str, id: u32) -> Result<&'d RaySet, CliError> {
    data.trace(id).ok_or_else(|| {
        let ids: Vec<String> = data.traces.iter().map(|t| t.trace_id.to_string()).collect();
        CliError::usage(format!(
            "--trace {id}: {name} has traces {}",
            ids.join(", ")
        ))
    })
}

/// The density of the chosen rays, laid out densely, with progress and a report on stdout.
pub fn dense_density(
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

pub fn grid_params(g: &GridArgs, tolerance: f32) -> Result<DensityParams, CliError> {
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
