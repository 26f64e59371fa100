//! Voxcast: a sandbox for learning, teaching and checking volume ray casting.
//!
//! Without a subcommand this opens the sandbox (`sandbox`: Bevy, the live GPU preview, the
//! settings panel). The subcommands are the command line over the pure core
//! (`crates/voxcast_core`): render an image, trace one ray step by step, describe a volume,
//! measure speed against accuracy. In a browser (wasm32) there is no command line: the page
//! opens the sandbox with the options its address gives (`sandbox::page`).

mod cli;
mod sandbox;

#[cfg(not(target_arch = "wasm32"))]
use clap::{Parser, Subcommand};
#[cfg(not(target_arch = "wasm32"))]
use cli::{answers, bench, info, levels, rays, render, trace};

#[cfg(not(target_arch = "wasm32"))]
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

#[cfg(not(target_arch = "wasm32"))]
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
    /// Level files a teacher writes: check them, or print their JSON Schema.
    Levels(levels::LevelsArgs),
    /// Write the answers kept with the levels' progress as CSV, for a teacher.
    Answers(answers::AnswersArgs),
    /// List the embedded datasets and presets.
    List,
}

#[cfg(target_arch = "wasm32")]
fn main() {
    sandbox::page::run();
}

#[cfg(not(target_arch = "wasm32"))]
fn main() {
    restore_sigpipe();
    sandbox::shared::platform::ensure_runtime_dir();
    let cli = Cli::parse();
    let result = match &cli.command {
        None => sandbox::run(&cli.sandbox),
        Some(Command::Render(a)) => render::run(a),
        Some(Command::Trace(a)) => trace::run(a),
        Some(Command::Info(a)) => info::run(a),
        Some(Command::Bench(a)) => bench::run(a),
        Some(Command::Rays(a)) => rays::run(a),
        Some(Command::Levels(a)) => levels::run(a),
        Some(Command::Answers(a)) => answers::run(a),
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
#[cfg(not(target_arch = "wasm32"))]
fn restore_sigpipe() {
    #[cfg(unix)]
    // SAFETY: called first in `main`, before any thread starts; SIG_DFL is always valid.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
}

#[cfg(not(target_arch = "wasm32"))]
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
