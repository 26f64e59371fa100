//! The player's saved progress: steps completed per level, and the answers given (with their
//! time and study run), read and written as JSON and exported as CSV for a teacher.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The answers' CSV header: what the levels panel's Export and `voxcast answers` write.
pub const CSV_HEADER: &str =
    "level,step,question,answer,expected,correct,time (UTC),run,try,seconds";

/// Steps completed per level id, and the answers given, for the player and their teacher.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Progress {
    pub completed: BTreeMap<String, usize>,
    /// Every answer given, oldest first (kept from the first version that records them; older
    /// progress has none).
    #[serde(default)]
    pub answers: Vec<Answer>,
}

/// Where the player's progress is kept on a desktop: `$VOXCAST_CONFIG_DIR/progress.json`,
/// else `$XDG_CONFIG_HOME/voxcast/progress.json`, else `~/.config/voxcast/progress.json`;
/// `None` where none of these is set.
pub fn players_progress_path() -> Option<std::path::PathBuf> {
    use std::path::PathBuf;
    std::env::var_os("VOXCAST_CONFIG_DIR")
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("XDG_CONFIG_HOME").map(|d| PathBuf::from(d).join("voxcast")))
        .or_else(|| std::env::var_os("HOME").map(|h| PathBuf::from(h).join(".config/voxcast")))
        .map(|dir| dir.join("progress.json"))
}

/// One answer to a level's question: a prediction when the step was done, or an effect named.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Answer {
    /// The level's id and the step, from 1.
    pub level: String,
    pub step: usize,
    /// What was asked, in words ("value at (0.5, 0.5, 0.5)", "which effect").
    pub question: String,
    /// What the player gave, and what the code computes.
    pub answer: String,
    pub expected: String,
    pub correct: bool,
    /// When, in seconds since 1970-01-01 UTC.
    pub at: u64,
    /// In a study, which run ([`StudyRun::words`]); `None` outside one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<String>,
    /// Which try at this step it was, from 1 (`None` in progress kept before tries were
    /// counted).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attempt: Option<u32>,
    /// Seconds from the step's opening to this answer (`None` in older progress).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub seconds: Option<f64>,
}

/// The runs of a study: a level played twice, first with the preview off, then with it on,
/// as the educational ray caster's user study compared them (Virtual Ray Tracer's thesis).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudyRun {
    PreviewOff,
    PreviewOn,
}

impl StudyRun {
    /// The run's words, as the answers keep them.
    pub fn words(self) -> &'static str {
        match self {
            StudyRun::PreviewOff => "preview off",
            StudyRun::PreviewOn => "preview on",
        }
    }

    /// Whether the preview is drawn in this run.
    pub fn preview(self) -> bool {
        self == StudyRun::PreviewOn
    }

    /// The run after this one, if any.
    pub fn next(self) -> Option<Self> {
        match self {
            StudyRun::PreviewOff => Some(StudyRun::PreviewOn),
            StudyRun::PreviewOn => None,
        }
    }

    /// Which of the two it is, from 1.
    pub fn number(self) -> usize {
        match self {
            StudyRun::PreviewOff => 1,
            StudyRun::PreviewOn => 2,
        }
    }
}

impl Answer {
    /// The answer given now.
    pub fn now(
        level: &str,
        step: usize,
        question: String,
        (answer, expected, correct): (String, String, bool),
    ) -> Self {
        let at = web_time::SystemTime::now()
            .duration_since(web_time::UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        Self {
            level: level.to_string(),
            step,
            question,
            answer,
            expected,
            correct,
            at,
            run: None,
            attempt: None,
            seconds: None,
        }
    }
}

/// Now, in seconds since 1970-01-01 UTC with fractions (the browser's clock on the page).
pub fn now_seconds() -> f64 {
    web_time::SystemTime::now()
        .duration_since(web_time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// `seconds` since 1970-01-01 as an ISO 8601 UTC time, `2026-12-04T09:53:47Z`.
pub fn utc_time(seconds: u64) -> String {
    let (days, rest) = ((seconds / 86_400) as i64, seconds % 86_400);
    // Howard Hinnant's days-to-civil.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1_460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02}T{:02}:{:02}:{:02}Z",
        rest / 3_600,
        rest / 60 % 60,
        rest % 60
    )
}

impl Progress {
    /// Reads progress from `path`. A missing file is a fresh start; a corrupt one too, with a
    /// message saying so (the file is left for the player to inspect, until the next save).
    pub fn load(path: &Path) -> (Self, Option<String>) {
        match std::fs::read_to_string(path) {
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => (Self::default(), None),
            Err(e) => (
                Self::default(),
                Some(format!(
                    "cannot read {}: {e}; starting afresh",
                    path.display()
                )),
            ),
            Ok(text) => Self::from_text(&text, &path.display().to_string()),
        }
    }

    /// Reads progress from the text kept in `place` (a file, the browser's storage): a damaged
    /// text is a fresh start, with a message that names `place`.
    pub fn from_text(text: &str, place: &str) -> (Self, Option<String>) {
        match Self::parse(text) {
            Ok(p) => (p, None),
            Err(e) => (
                Self::default(),
                Some(format!("{place} is damaged ({e}); starting afresh")),
            ),
        }
    }

    /// The progress in `text`, or what is wrong with it.
    pub fn parse(text: &str) -> Result<Self, String> {
        serde_json::from_str(text).map_err(|e| e.to_string())
    }

    /// The progress as the text [`Progress::from_text`] reads.
    pub fn to_text(&self) -> String {
        serde_json::to_string_pretty(self).expect("progress is plain data")
    }

    /// Writes progress atomically: to a temporary file beside it, then renamed over it.
    pub fn save(&self, path: &Path) -> std::io::Result<()> {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let tmp = path.with_extension("json.tmp");
        std::fs::write(&tmp, self.to_text())?;
        std::fs::rename(&tmp, path)
    }

    /// Records that `steps` steps of level `id` are done (never lowers it).
    pub fn record(&mut self, id: &str, steps: usize) {
        let done = self.completed.entry(id.to_string()).or_default();
        *done = (*done).max(steps);
    }

    /// The answers as CSV, one row an answer in the order given, for a teacher's spreadsheet:
    /// [`CSV_HEADER`]'s columns (files from before `try` and `seconds` were kept end at `run`).
    pub fn answers_csv(&self) -> String {
        let field = |s: &str| {
            if s.contains([',', '"', '\n']) {
                format!("\"{}\"", s.replace('"', "\"\""))
            } else {
                s.to_string()
            }
        };
        let mut out = String::from(CSV_HEADER);
        out.push('\n');
        for a in &self.answers {
            out += &[
                field(&a.level),
                a.step.to_string(),
                field(&a.question),
                field(&a.answer),
                field(&a.expected),
                if a.correct { "yes" } else { "no" }.to_string(),
                utc_time(a.at),
                a.run.as_deref().map(field).unwrap_or_default(),
                a.attempt.map(|n| n.to_string()).unwrap_or_default(),
                a.seconds.map(|s| s.to_string()).unwrap_or_default(),
            ]
            .join(",");
            out.push('\n');
        }
        out
    }
}
