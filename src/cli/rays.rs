//! `voxcast rays`: ray data sets as RayVis views them — what a set holds (`info`), its
//! density over a grid of cells, written as NRRD volumes (`density`), drawn over the scene
//! (`render`, in `rays_render.rs`), and the set as a `.rayvis` file (`export`). What the
//! subcommands read alike (the source, its trace, the grid) is `rays_input.rs`.

use super::CliError;
use super::rays_input::{
    GridArgs, SourceArg, check_folders, dense_density, grid_params, source, trace_words,
};
use super::rays_render::RenderArgs;
use clap::{Args, Subcommand};
use std::path::PathBuf;
use voxcast_core::numbers::sig;

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

#[derive(Args, Debug)]
pub struct InfoArgs {
    #[command(flatten)]
    pub source: SourceArg,
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
