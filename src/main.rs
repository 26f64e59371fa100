//! Voxcast: a sandbox for learning, teaching and checking volume ray casting.
//!
//! Without a subcommand this opens the sandbox (`sandbox`: Bevy, the live GPU preview, the
//! settings panel). The subcommands are the command line over the pure core
//! (`crates/voxcast_core`): render an image, trace one ray step by step, describe a volume,
//! measure speed against accuracy.

mod cli;
mod sandbox;

use clap::{Parser, Subcommand};
use cli::{bench, info, rays, render, trace};

#[derive(Parser, Debug)]
#[command(
    name = "voxcast",
    version,
    about = "Volume ray casting you can follow step by step",
    args_conflicts_with_subcommands = true
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Without a subcommand: the sandbox's options.
    #[command(flatten)]
    sandbox: sandbox::SandboxArgs,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a volume with the exact CPU ray caster and write a PNG.
    Render(render::RenderArgs),
    /// Trace one ray and print every sample's calculation.
    Trace(trace::TraceArgs),
    /// Describe a volume file: dimensions, type, spacing, value range, histogram.
    Info(info::InfoArgs),
    /// Measure time and error against the step size (and against VTK with --peer).
    Bench(bench::BenchArgs),
    /// Ray data sets as RayVis views them: what a set holds, its density over a grid.
    Rays(rays::RaysArgs),
    /// List the embedded datasets and presets.
    List,
}

fn main() {
    restore_sigpipe();
    sandbox::platform::ensure_runtime_dir();
    let cli = Cli::parse();
    let result = match &cli.command {
        None => sandbox::run(&cli.sandbox),
        Some(Command::Render(a)) => render::run(a),
        Some(Command::Trace(a)) => trace::run(a),
        Some(Command::Info(a)) => info::run(a),
        Some(Command::Bench(a)) => bench::run(a),
        Some(Command::Rays(a)) => rays::run(a),
        Some(Command::List) => {
            list();
            Ok(())
        }
    };
    if let Err(e) = result {
        eprintln!("error: {e}");
        std::process::exit(e.exit_code());
    }
}

/// Lets a closed pipe end the program quietly, as it ends `cat` (`voxcast trace … | head`):
/// Rust ignores SIGPIPE, which turns every later `println!` into a panic.
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first in `main`, before any thread starts; SIG_DFL is always valid.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

fn list() {
    println!("embedded datasets (--volume builtin:NAME):");
    for (name, what) in voxcast_core::builtin::DATASETS {
        println!("  {name:<16} {what}");
    }
    println!("presets (--tf NAME):");
    for p in voxcast_core::preset::all() {
        println!("  {:<16} {}", p.name, p.description);
    }
    println!("ray data (voxcast rays … builtin:NAME):");
    for (name, what) in voxcast_core::rays::source::BUILTIN {
        println!("  {name:<16} {what}");
    }
}
