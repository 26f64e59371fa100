//! Files the student saves and opens, the same on the desktop and in a browser: a save is a file
//! written atomically (a temporary beside it, renamed over it) on the desktop and a download in
//! a browser; files a browser hands the page (picked or dropped) arrive as a [`FilesChosen`]
//! message, their names and bytes, which each feature reads as it reads a path on the desktop.

use bevy::prelude::*;
use std::path::Path;

/// What files were chosen for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Purpose {
    /// A volume to look at (NRRD, NIfTI, raw; a detached header with its data file).
    Volume,
    /// A transfer function (JSON).
    Transfer,
    /// Level files (JSON) and the data sets and transfer functions they name.
    Levels,
    /// A class's answer files (CSV), for a report.
    Answers,
    /// A level's link: the page's address fragment (`level=…`), as text.
    LevelLink,
    /// A ray data set (a `.rayvis` file) for the Ray data section, whose density is computed.
    Rays,
}

#[cfg(any(test, target_arch = "wasm32"))]
impl Purpose {
    /// The name the page uses for it.
    pub fn name(self) -> &'static str {
        match self {
            Purpose::Volume => "volume",
            Purpose::Transfer => "transfer",
            Purpose::Levels => "levels",
            Purpose::Answers => "answers",
            Purpose::LevelLink => "level-link",
            Purpose::Rays => "rays",
        }
    }

    pub fn parse(name: &str) -> Option<Self> {
        [
            Purpose::Volume,
            Purpose::Transfer,
            Purpose::Levels,
            Purpose::Answers,
            Purpose::LevelLink,
            Purpose::Rays,
        ]
        .into_iter()
        .find(|p| p.name() == name)
    }

    /// The file types a picker offers for it.
    pub fn accept(self) -> String {
        match self {
            Purpose::Volume => {
                // A raw file's data, or a detached header's, may end in anything.
                let mut types = voxcast_core::io::VOLUME_SUFFIXES.join(",");
                types.push_str(",.img,.gz,.raw");
                types
            }
            Purpose::Transfer | Purpose::LevelLink => ".json".into(),
            // A level with the data sets it names, picked together.
            Purpose::Levels => format!(".json,{}", Purpose::Volume.accept()),
            Purpose::Answers => ".csv".into(),
            Purpose::Rays => ".rayvis".into(),
        }
    }
}

/// Files the student chose in a browser (the desktop reads paths instead).
#[derive(Message, Clone, Debug)]
pub struct FilesChosen {
    pub purpose: Purpose,
    /// Each file's name and bytes.
    pub files: Vec<(String, Vec<u8>)>,
}

/// In a browser: the files the page handed over, as this feature's messages (a purpose it
/// does not know is dropped).
#[cfg(target_arch = "wasm32")]
pub(crate) fn plugin(app: &mut App) {
    app.add_message::<FilesChosen>()
        .add_systems(PreUpdate, take_handed); // the page's files arrive in First
}

/// Takes the handed files out of their messages (this is their one reader), so a volume's
/// bytes are not copied.
#[cfg(target_arch = "wasm32")]
fn take_handed(
    mut handed: ResMut<Messages<crate::sandbox::shared::web::FilesHanded>>,
    mut chosen: MessageWriter<FilesChosen>,
) {
    for h in handed.drain() {
        if let Some(purpose) = Purpose::parse(&h.purpose) {
            chosen.write(FilesChosen {
                purpose,
                files: h.files,
            });
        }
    }
}

/// Whether opening asks the browser's picker (a page cannot read paths) rather than a path.
pub const PICKS_FILES: bool = cfg!(target_arch = "wasm32");

/// Asks the browser for files for `purpose` (nothing on the desktop, where paths are typed).
pub fn pick(purpose: Purpose) {
    #[cfg(target_arch = "wasm32")]
    crate::sandbox::shared::web::pick_files(purpose.name(), &purpose.accept());
    #[cfg(not(target_arch = "wasm32"))]
    let _ = purpose;
}

/// The file `path` names, or what to ask of a student who left the field blank.
pub fn file_name(path: &Path) -> Result<&std::ffi::OsStr, String> {
    path.file_name().ok_or_else(|| "give a file name".into())
}

/// Puts `text` on the clipboard: in a browser through the page; on the desktop through the
/// system's clipboard program (`wl-copy`, `xclip`, `xsel`, `pbcopy` or `clip`, whichever is
/// there). Says why not where none is.
pub fn copy_text(text: &str) -> Result<(), String> {
    #[cfg(target_arch = "wasm32")]
    return crate::sandbox::shared::web::copy_text(text);
    #[cfg(not(target_arch = "wasm32"))]
    {
        use std::io::Write;
        let programs: [(&str, &[&str]); 5] = [
            ("wl-copy", &[]),
            ("xclip", &["-selection", "clipboard"]),
            ("xsel", &["--clipboard", "--input"]),
            ("pbcopy", &[]),
            ("clip", &[]),
        ];
        for (program, args) in programs {
            let child = std::process::Command::new(program)
                .args(args)
                .stdin(std::process::Stdio::piped())
                .stdout(std::process::Stdio::null())
                .stderr(std::process::Stdio::null())
                .spawn();
            let Ok(mut child) = child else { continue };
            let written = child
                .stdin
                .take()
                .is_some_and(|mut input| input.write_all(text.as_bytes()).is_ok());
            // xclip and xsel stay to serve the selection: only a quick failure is one.
            std::thread::sleep(std::time::Duration::from_millis(50));
            let failed = matches!(child.try_wait(), Ok(Some(s)) if !s.success());
            if written && !failed {
                return Ok(());
            }
        }
        Err("No clipboard program here (wl-copy, xclip, xsel)".into())
    }
}

/// Saves `bytes` as `path` (`mime` is its type for a browser): on the desktop through a
/// temporary file and a rename, so a failed write loses nothing; in a browser as a download
/// named like the path's last part. Says what was done, or why not.
pub fn save(path: &Path, bytes: &[u8], mime: &str) -> Result<String, String> {
    let name = file_name(path)?;
    #[cfg(target_arch = "wasm32")]
    return {
        let name = name.to_string_lossy();
        crate::sandbox::shared::web::download(&name, bytes, mime)
            .map(|()| format!("downloaded {name}"))
    };
    #[cfg(not(target_arch = "wasm32"))]
    {
        let _ = (name, mime);
        let mut tmp = path.as_os_str().to_owned();
        tmp.push(".tmp");
        std::fs::write(&tmp, bytes)
            .and_then(|_| std::fs::rename(&tmp, path))
            .map_err(|e| {
                format!(
                    "cannot save {}: {}",
                    path.display(),
                    voxcast_core::error::io_words(&e)
                )
            })?;
        Ok(format!("saved {}", path.display()))
    }
}

/// The file of the files `names` a reader starts from: a header (which names its data file)
/// before anything else, then any volume file, else the first (whose format the reader then
/// names).
pub fn volume_entry<'a>(names: impl Iterator<Item = &'a str> + Clone) -> Option<&'a str> {
    let header = |n: &&str| {
        let n = n.to_ascii_lowercase();
        n.ends_with(".nhdr") || n.ends_with(".hdr")
    };
    names
        .clone()
        .find(header)
        .or_else(|| names.clone().find(|n| voxcast_core::io::is_volume_name(n)))
        .or(names.clone().next())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_header_is_read_first_whatever_the_order() {
        let f = |names: &'static [&'static str]| volume_entry(names.iter().copied());
        assert_eq!(f(&["d.raw", "h.NHDR"]), Some("h.NHDR"));
        assert_eq!(f(&["s.img", "s.hdr"]), Some("s.hdr"));
        assert_eq!(f(&["notes.txt", "a.nii.gz"]), Some("a.nii.gz"));
        assert_eq!(f(&["notes.txt"]), Some("notes.txt"));
        assert_eq!(f(&[]), None);
        assert_eq!(Purpose::parse("volume"), Some(Purpose::Volume));
        assert!(Purpose::Volume.accept().contains(".nii.gz"));
        assert_eq!(Purpose::parse("rays"), Some(Purpose::Rays));
    }

    #[test]
    fn a_save_replaces_the_file_whole_or_says_why_not() {
        let dir = std::env::temp_dir().join(format!("voxcast-save-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.json");
        assert_eq!(
            save(&path, b"{}", "application/json").unwrap(),
            format!("saved {}", path.display())
        );
        assert_eq!(std::fs::read(&path).unwrap(), b"{}");
        let nowhere = dir.join("no/such/folder/b.json");
        assert!(save(&nowhere, b"{}", "application/json").is_err());
        assert!(save(Path::new(""), b"", "").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
