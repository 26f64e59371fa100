//! `voxcast levels`: level files a teacher writes — `check` reads each file (or each `.json`
//! in a folder) as the sandbox's `--levels` would and prints every problem, where it is, what
//! is wrong and what would be right; `schema` prints the format's JSON Schema (the one
//! `docs/levels.schema.json` holds) for an editor that checks a file as it is typed.

use super::CliError;
use clap::{Args, Subcommand};
use std::io::Write;
use std::path::PathBuf;
use voxcast_core::level::check::{self, OnDisk, Severity};

#[derive(Args, Debug)]
pub struct LevelsArgs {
    #[command(subcommand)]
    pub command: LevelsCommand,
}

#[derive(Subcommand, Debug)]
pub enum LevelsCommand {
    /// Check level files (a file, or the .json files of a folder): every error and warning,
    /// with the step and field; the exit code is 1 if any file has an error.
    Check {
        /// Level files or folders of them.
        #[arg(required = true)]
        paths: Vec<PathBuf>,
    },
    /// Print the levels' JSON Schema (docs/levels.schema.json is this).
    Schema {
        /// Write it to this file instead of standard output.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

pub fn run(a: &LevelsArgs) -> Result<(), CliError> {
    match &a.command {
        LevelsCommand::Check { paths } => check_paths(paths),
        LevelsCommand::Schema { out } => {
            let text = voxcast_core::level::schema_text();
            match out {
                Some(path) => std::fs::write(path, text).map_err(|e| {
                    CliError::failed(format!(
                        "cannot write {}: {}",
                        path.display(),
                        voxcast_core::error::io_words(&e)
                    ))
                }),
                None => {
                    print!("{text}");
                    Ok(())
                }
            }
        }
    }
}

/// Checks every file under `paths` and prints the report; an error in any file fails.
fn check_paths(paths: &[PathBuf]) -> Result<(), CliError> {
    let mut texts = Vec::new();
    let mut unreadable = Vec::new();
    for path in paths {
        match voxcast_core::level::files_at(path) {
            Err(e) => unreadable.push(e),
            Ok(files) => {
                for (origin, text) in files {
                    match text {
                        Ok(text) => texts.push((origin, text)),
                        Err(e) => unreadable.push(format!("{}: {e}", origin.words())),
                    }
                }
            }
        }
    }
    let checked = check::read_all(&texts, &OnDisk);
    let mut out = std::io::stdout().lock();
    let mut report = String::new();
    for e in &unreadable {
        report.push_str(&format!("{e}\n  error: cannot be read\n"));
    }
    let (mut errors, mut warnings, mut fine) = (unreadable.len(), 0, 0);
    for (origin, c) in &checked {
        let title = c
            .level
            .as_ref()
            .map(|l| format!(" — “{}” ({} steps)", l.title, l.steps.len()))
            .unwrap_or_default();
        report.push_str(&format!("{}{title}\n", origin.words()));
        if c.problems.is_empty() {
            report.push_str("  fine\n");
            fine += 1;
        }
        for p in &c.problems {
            report.push_str(&format!("  {p}\n"));
        }
        errors += usize::from(c.has_errors());
        warnings += c
            .problems
            .iter()
            .filter(|p| p.severity == Severity::Warning)
            .count();
    }
    let files = checked.len() + unreadable.len();
    report.push_str(&format!(
        "{files} file{}: {fine} without a problem, {errors} with errors (left out of the levels list), \
         {warnings} warning{}\n",
        if files == 1 { "" } else { "s" },
        if warnings == 1 { "" } else { "s" },
    ));
    // A closed pipe ends the program quietly (SIGPIPE); any other write error is reported.
    out.write_all(report.as_bytes())
        .map_err(|e| CliError::failed(format!("cannot write the report: {e}")))?;
    if errors > 0 {
        return Err(CliError::failed(format!(
            "{errors} of {files} level files have errors"
        )));
    }
    Ok(())
}
