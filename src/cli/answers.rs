//! `voxcast answers`: the answers kept with the levels' progress, as CSV for a teacher (the
//! same file as the levels list's "Export answers (CSV)"); and with `--class`, a class's
//! answer files read together into one HTML report (`voxcast_core::level::report`).

use super::CliError;
use clap::Args;
use std::path::PathBuf;
use voxcast_core::level::report::{Handed, class_html, class_report};
use voxcast_core::level::{Progress, players_progress_path};

#[derive(Args, Debug)]
pub struct AnswersArgs {
    /// The progress file to read (default: the player's own, as the sandbox keeps it).
    #[arg(long, conflicts_with = "class")]
    pub progress: Option<PathBuf>,
    /// Write the CSV here instead of to standard output.
    #[arg(long, conflicts_with = "class")]
    pub out: Option<PathBuf>,
    /// A class's answer files (CSV, one a student, as the sandbox exports them), or folders
    /// of them: read together into one report (--report). A damaged or foreign file is named
    /// in the report and left out.
    #[arg(long, num_args = 1.., value_name = "FILE.csv", requires = "report")]
    pub class: Vec<PathBuf>,
    /// With --class: write the report here, one HTML file with a chart per level.
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<PathBuf>,
    /// With --class: level files (a file or a folder) whose titles the report uses for
    /// levels that are not built in.
    #[arg(long, value_name = "PATH", requires = "class")]
    pub levels: Option<PathBuf>,
}

pub fn run(a: &AnswersArgs) -> Result<(), CliError> {
    if !a.class.is_empty() {
        return report(a);
    }
    if a.report.is_some() {
        return Err(CliError::usage(
            "--report writes a class's report: give the answer files with --class",
        ));
    }
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

/// `--class … --report FILE.html`: every file read (a folder's .csv files by name), one
/// report written; files that cannot be read are named in it.
fn report(a: &AnswersArgs) -> Result<(), CliError> {
    let out = a
        .report
        .as_ref()
        .expect("clap requires --report with --class");
    let mut handed = Vec::new();
    let mut unreadable = Vec::new();
    for path in &a.class {
        let files = if path.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(path)
                .map_err(|e| {
                    CliError::usage(format!(
                        "{}: {}",
                        path.display(),
                        voxcast_core::error::io_words(&e)
                    ))
                })?
                .filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x.eq_ignore_ascii_case("csv")))
                .collect();
            found.sort();
            found
        } else {
            vec![path.clone()]
        };
        for file in files {
            let name = file.display().to_string();
            match std::fs::read(&file) {
                Ok(bytes) => handed.push(Handed {
                    name,
                    text: String::from_utf8_lossy(&bytes).into_owned(),
                }),
                Err(e) => unreadable.push((name, voxcast_core::error::io_words(&e))),
            }
        }
    }
    let mut class = class_report(&handed);
    class.left_out.extend(unreadable);
    let mut titles: Vec<(String, String)> = voxcast_core::level::Level::all()
        .into_iter()
        .map(|l| (l.id, l.title))
        .collect();
    if let Some(path) = &a.levels {
        let added = crate::sandbox::levels::added_from_path(path);
        titles.extend(added.levels.into_iter().map(|l| (l.id, l.title)));
    }
    super::rays_input::check_folders([out])?;
    std::fs::write(out, class_html(&class, &titles))
        .map_err(|e| CliError::failed(format!("cannot write {}: {e}", out.display())))?;
    eprintln!(
        "{} answer files read, {} left out → {} ({} questions)",
        class.read.len(),
        class.left_out.len(),
        out.display(),
        class.steps.len()
    );
    for (name, why) in &class.left_out {
        eprintln!("left out: {name}: {why}");
    }
    Ok(())
}
