//! Where the levels' progress is kept: a file in the config directory (written atomically), a
//! browser's local storage, or nowhere (tests); a damaged store starts afresh with a message.

use super::*;

/// Where the levels' progress is kept.
#[derive(Clone, Debug, PartialEq)]
pub enum ProgressStore {
    /// Not kept (tests).
    #[cfg_attr(target_arch = "wasm32", allow(dead_code))]
    Nowhere,
    /// A JSON file, written atomically (the desktop).
    File(PathBuf),
    /// The browser's local storage of the page's origin, under this key.
    #[cfg(target_arch = "wasm32")]
    Browser(&'static str),
}

impl ProgressStore {
    /// The player's own: `$XDG_CONFIG_HOME/voxcast/progress.json` (else `~/.config/…`;
    /// `VOXCAST_CONFIG_DIR` overrides the folder), or in a browser its local storage.
    pub fn players() -> Self {
        #[cfg(target_arch = "wasm32")]
        return Self::Browser("voxcast-progress");
        #[cfg(not(target_arch = "wasm32"))]
        voxcast_core::level::players_progress_path().map_or(Self::Nowhere, Self::File)
    }

    /// The progress kept here: a fresh start where there is none, and with a message where
    /// what is kept is damaged or cannot be read.
    pub fn load(&self) -> (Progress, Option<String>) {
        match self {
            Self::Nowhere => (Progress::default(), None),
            Self::File(path) => Progress::load(path),
            #[cfg(target_arch = "wasm32")]
            Self::Browser(key) => match crate::sandbox::shared::web::stored(key) {
                None => (Progress::default(), None),
                Some(text) => Progress::from_text(
                    &text,
                    &format!("The progress kept in this browser (\"{key}\")"),
                ),
            },
        }
    }

    /// Keeps `progress` here.
    pub fn save(&self, progress: &Progress) -> Result<(), String> {
        match self {
            Self::Nowhere => Ok(()),
            Self::File(path) => progress.save(path).map_err(|e| e.to_string()),
            #[cfg(target_arch = "wasm32")]
            Self::Browser(key) => crate::sandbox::shared::web::store(key, &progress.to_text()),
        }
    }
}
