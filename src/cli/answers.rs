//! `voxcast answers`: the answers kept with the levels' progress, as CSV for a teacher (the
//! same file as the levels list's "Export answers (CSV)").

use super::CliError;
use clap::Args;
use std::path::PathBuf;
use voxcast_core::level::{Progress, players_progress_path};

#[derive(Args, Debug)]
pub struct AnswersArgs {
    /// The progress file to read (default: the player's own, as the sandbox keeps it).
    #[arg(long)]
    pub progress: Option<PathBuf>,
    /// Write the CSV here instead of to standard output.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

pub fn run(a: &AnswersArgs) -> Result<(), CliError> {
    let path = a
        .progress
        .clone()
        .or_else(players_progress_path)
        .ok_or_else(|| {
            CliError::usage("no progress file: give --progress FILE (HOME is not set)".to_string())
        })?;
    let text = std::fs::read_to_string(&path).map_err(|e| {
        CliError::usage(format!(
            "{}: {} (the levels keep a progress file once a step is done)",
            path.display(),
            voxcast_core::error::io_words(&e)
        ))
    })?;
    let progress = Progress::parse(&text)
        .map_err(|e| CliError::failed(format!("{} is damaged: {e}", path.display())))?;
    let csv = progress.answers_csv();
    match &a.out {
        Some(out) => {
            super::rays_input::check_folders([out])?;
            std::fs::write(out, &csv)
                .map_err(|e| CliError::failed(format!("cannot write {}: {e}", out.display())))?;
            eprintln!(
                "{} answers from {} → {}",
                progress.answers.len(),
                path.display(),
                out.display()
            );
        }
        None => print!("{csv}"),
    }
    Ok(())
}
