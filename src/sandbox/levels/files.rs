//! Files handed to the levels as bytes — on the page, which cannot read paths: level files and
//! the data sets and transfer functions they name (Open…, a drop, `?levels=URL`), a level in a
//! link (`#level=…`), and a class's answer files, which become one report (a download). The
//! data sets are held so a level's scene loads them from memory when it opens.

use super::*;
use crate::sandbox::shared::files::{FilesChosen, Purpose};
use voxcast_core::level::check::{self, Files};
use voxcast_core::level::{Origin, report};
use voxcast_core::volume::Volume;

/// The files handed with levels (data sets, transfer functions), by name: a level's data set
/// is loaded from here when its scene opens.
#[derive(Resource, Default)]
pub struct LevelFiles {
    pub files: Vec<(String, Vec<u8>)>,
}

impl LevelFiles {
    /// The held files as a reader finds them: by their last name (a URL's or a folder's path
    /// cut off), so a header finds its data file beside it.
    pub fn in_memory(&self) -> voxcast_core::io::InMemory {
        voxcast_core::io::InMemory::new(
            self.files
                .iter()
                .map(|(n, b)| (last_name(n).to_string(), b.clone()))
                .collect(),
        )
    }

    /// Holds `bytes` as the file `name` (in place of one held under that name).
    pub fn hold(&mut self, name: &str, bytes: Vec<u8>) {
        self.files.retain(|(n, _)| n != name);
        self.files.push((name.to_string(), bytes));
    }

    /// Whether a file named `name` is held.
    pub fn holds(&self, name: &str) -> bool {
        self.files.iter().any(|(n, _)| n == name)
    }
}

fn last_name(name: &str) -> &str {
    name.rsplit(['/', '\\']).next().unwrap_or(name)
}

/// The check's view of held files: data sets and texts by name; builtins as everywhere.
struct Held<'a>(&'a LevelFiles);

impl Files for Held<'_> {
    fn volume(&self, source: &str) -> Result<Volume, String> {
        if self.0.holds(source) {
            return voxcast_core::io::load_from(
                &self.0.in_memory(),
                std::path::Path::new(last_name(source)),
            )
            .map(|l| l.volume)
            .map_err(|e| e.to_string());
        }
        // A builtin, or (on the desktop) a file on disk.
        check::OnDisk.volume(source).map_err(|e| {
            if cfg!(target_arch = "wasm32") {
                "it was not among the files opened with the level (open them together)".into()
            } else {
                e
            }
        })
    }

    fn text(&self, name: &str) -> Result<String, String> {
        match self.0.files.iter().find(|(n, _)| n == name) {
            Some((_, b)) => Ok(String::from_utf8_lossy(b).into_owned()),
            None => check::OnDisk.text(name),
        }
    }
}

/// Where a handed level came from: a URL the page fetched, else a file's name (a folder's
/// files keep their path inside it).
fn origin_of(name: &str) -> Origin {
    if name.contains("://") {
        Origin::Url(name.into())
    } else {
        Origin::File(name.into())
    }
}

/// Whether `bytes` read as a level file (a JSON object with steps) rather than another JSON.
fn is_level(name: &str, bytes: &[u8]) -> bool {
    name.to_ascii_lowercase().ends_with(".json")
        && serde_json::from_slice::<serde_json::Value>(bytes)
            .is_ok_and(|v| v.get("steps").is_some())
}

/// A level's link to play once the window runs (`--link`): the page's address with its
/// `#level=…`.
#[derive(Resource, Default)]
pub struct OpenLink(pub Option<String>);

/// Hands `--link`'s level over as the page hands its own address's (`level-link`): the page
/// without the fragment as the name, the fragment as the bytes.
pub(super) fn open_link(mut link: ResMut<OpenLink>, mut chosen: MessageWriter<FilesChosen>) {
    if let Some(url) = link.0.take() {
        let (page, fragment) = url.split_once('#').unwrap_or((&url, ""));
        chosen.write(FilesChosen {
            purpose: Purpose::LevelLink,
            files: vec![(page.to_string(), fragment.as_bytes().to_vec())],
        });
    }
}

/// On the desktop: level files and answer files dropped on the window, read and handed to
/// [`receive_files`] as the page hands them (a volume dropped is the loader's).
pub(super) fn take_dropped(
    mut drops: MessageReader<bevy::window::FileDragAndDrop>,
    mut chosen: MessageWriter<FilesChosen>,
) {
    let mut levels = Vec::new();
    let mut answers = Vec::new();
    for drop in drops.read() {
        let bevy::window::FileDragAndDrop::DroppedFile { path_buf, .. } = drop else {
            continue;
        };
        let name = path_buf.display().to_string();
        let lower = name.to_ascii_lowercase();
        let wanted = if lower.ends_with(".json") {
            &mut levels
        } else if lower.ends_with(".csv") {
            &mut answers
        } else {
            continue;
        };
        if let Ok(bytes) = std::fs::read(path_buf) {
            wanted.push((name, bytes));
        }
    }
    for (purpose, files) in [(Purpose::Levels, levels), (Purpose::Answers, answers)] {
        if !files.is_empty() {
            chosen.write(FilesChosen { purpose, files });
        }
    }
}

/// Takes level files, links and answer files handed over.
pub(super) fn receive_files(
    mut chosen: MessageReader<FilesChosen>,
    mut lessons: ResMut<Lessons>,
    mut held: ResMut<LevelFiles>,
    mut start: MessageWriter<LevelCommand>,
) {
    for FilesChosen { purpose, files } in chosen.read() {
        match purpose {
            Purpose::Levels => {
                lessons.message = Some(add_levels(&mut lessons, &mut held, files));
            }
            Purpose::LevelLink => {
                // The page, then the fragment; after them the files the level names, which the
                // page fetched from its site (a link carries none of them).
                let fragment = files
                    .first()
                    .map(|(_, b)| String::from_utf8_lossy(b).into_owned())
                    .unwrap_or_default();
                let page = files.first().map(|(n, _)| n.clone()).unwrap_or_default();
                for (name, bytes) in files.iter().skip(1) {
                    held.hold(name, bytes.clone());
                }
                match level_from_link(&fragment, &page, &held) {
                    Ok(level) => {
                        let i = lessons.keep_level(level);
                        start.write(LevelCommand::Start(i));
                    }
                    Err(e) => lessons.message = Some(e),
                }
            }
            Purpose::Answers => lessons.message = Some(class_report(files, &lessons.levels)),
            Purpose::Volume | Purpose::Transfer | Purpose::Rays => {}
        }
    }
}

/// The level a link's fragment holds, read as `voxcast levels check` reads a file.
pub fn level_from_link(fragment: &str, page: &str, held: &LevelFiles) -> Result<Level, String> {
    let text = voxcast_core::level::link::from_fragment(fragment)?;
    let checked = check::read(&text, Origin::Url(page.into()), &Held(held));
    checked.level.ok_or_else(|| {
        let first = checked
            .problems
            .first()
            .map(|p| p.to_string())
            .unwrap_or_default();
        format!("The link's level cannot be played: {first}")
    })
}

/// Adds the level files among `files` (the rest held as their data sets); says what was added
/// and what was left out.
fn add_levels(lessons: &mut Lessons, held: &mut LevelFiles, files: &[(String, Vec<u8>)]) -> String {
    let (levels, data): (Vec<_>, Vec<_>) = files.iter().partition(|(n, b)| is_level(n, b));
    for (name, bytes) in data {
        held.hold(name, bytes.clone());
    }
    if levels.is_empty() {
        return "No level among the files opened: a level is a .json file with steps \
                (docs/levels.md)."
            .into();
    }
    let texts: Vec<(Origin, String)> = levels
        .iter()
        .map(|(n, b)| (origin_of(n), String::from_utf8_lossy(b).into_owned()))
        .collect();
    let mut added = Vec::new();
    let mut left_out = Vec::new();
    for (origin, checked) in check::read_all(&texts, &Held(held)) {
        match checked.level {
            Some(level) => {
                added.push(level.title.clone());
                lessons.keep_level(level);
            }
            None => left_out.push(format!(
                "{}: {}",
                origin.words(),
                checked
                    .problems
                    .first()
                    .map(|p| p.to_string())
                    .unwrap_or_default()
            )),
        }
    }
    let mut said = match added.len() {
        0 => "No level added".to_string(),
        1 => format!("Added “{}” to the levels list", added[0]),
        n => format!("Added {n} levels to the levels list"),
    };
    if !left_out.is_empty() {
        said += &format!(
            "; left out for errors: {} (voxcast levels check prints them all)",
            left_out.join("; ")
        );
    }
    said
}

/// A class's answer files as one report: written as `class_report.html` (a download on the
/// page); says how many files were read.
fn class_report(files: &[(String, Vec<u8>)], levels: &[Level]) -> String {
    let handed: Vec<report::Handed> = files
        .iter()
        .map(|(name, bytes)| report::Handed {
            name: name.clone(),
            text: String::from_utf8_lossy(bytes).into_owned(),
        })
        .collect();
    let class = report::class_report(&handed);
    let titles: Vec<(String, String)> = levels
        .iter()
        .map(|l| (l.id.clone(), l.title.clone()))
        .collect();
    let html = report::class_html(&class, &titles);
    let path = std::path::Path::new(REPORT_FILE);
    match crate::sandbox::shared::files::save(path, html.as_bytes(), "text/html") {
        Ok(done) => format!(
            "Class report: {} answer file{} read, {} left out: {done}",
            class.read.len(),
            if class.read.len() == 1 { "" } else { "s" },
            class.left_out.len()
        ),
        Err(e) => format!("The class report was not saved: {e}"),
    }
}

/// The class report's file: in the folder the sandbox started from, or a download.
const REPORT_FILE: &str = "class_report.html";
