//! Reading a level file a teacher wrote, and every problem in it: `voxcast levels check`, the
//! sandbox's `--levels` and the page's Open… all read files this way. The file is read part by
//! part (each field of the scene, each step), so one mistake does not hide the next; each
//! problem says where (the step and field), what is wrong and what would be right. Then what
//! only the code can tell: names that name nothing (a preset, a knob, a cost view), settings
//! the renderer refuses, a data set that cannot be read, a prediction whose answer cannot be
//! computed, an objective already met when its step opens, a number the objective checks that
//! the text never tells the student.

use super::{Level, LevelScene, Objective, Origin, Situation, Step, StepScene, TransferChoice};
use crate::settings::RenderSettings;
use crate::transfer::TransferFunction;
use crate::volume::Volume;

/// How much a problem matters: an error keeps the level out of the list; a warning is for the
/// teacher to weigh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    Error,
    Warning,
}

/// One problem of a level file.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    pub severity: Severity,
    /// Where: `step 3 › objective › kind`, `scene › volume`, `line 4, column 9`.
    pub place: String,
    /// What is wrong.
    pub what: String,
    /// What would be right, where the code knows.
    pub right: Option<String>,
}

impl std::fmt::Display for Problem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kind = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        write!(f, "{kind}: {}: {}", self.place, self.what)?;
        if let Some(right) = &self.right {
            write!(f, " — {right}")?;
        }
        Ok(())
    }
}

/// What a check needs from outside: the data sets and files a level names.
pub trait Files {
    /// The volume at `source` (`builtin:NAME`, `density:…`, a path or URL).
    fn volume(&self, source: &str) -> Result<Volume, String>;
    /// The text of the file at `name` (a transfer function).
    fn text(&self, name: &str) -> Result<String, String>;
}

/// The desktop's files: read from disk, builtins from the binary.
pub struct OnDisk;

impl Files for OnDisk {
    fn volume(&self, source: &str) -> Result<Volume, String> {
        crate::builtin::load_source(source)
            .map(|l| l.volume)
            .map_err(|e| e.to_string())
    }

    fn text(&self, name: &str) -> Result<String, String> {
        std::fs::read_to_string(name).map_err(|e| crate::error::io_words(&e))
    }
}

/// A level file read: the level (none where its structure is wrong) and every problem found.
#[derive(Debug)]
pub struct Checked {
    pub level: Option<Level>,
    pub problems: Vec<Problem>,
}

impl Checked {
    /// Whether any problem is an error.
    pub fn has_errors(&self) -> bool {
        self.problems.iter().any(|p| p.severity == Severity::Error)
    }
}

/// The fields a level file may have at its top.
const TOP_FIELDS: [&str; 6] = ["$schema", "id", "title", "concept", "scene", "steps"];

/// Reads a level file's `text` (found at `origin`), checking everything `files` can reach.
pub fn read(text: &str, origin: Origin, files: &dyn Files) -> Checked {
    let mut out = Out::default();
    let level = read_structure(text, &mut out).map(|mut level| {
        level.origin = origin;
        check_level(&level, files, &mut out);
        level
    });
    let level = level
        .filter(|_| !out.has_errors())
        .map(|level| with_files_read(level, files));
    out.problems.sort_by_key(|p| p.severity);
    Checked {
        level,
        problems: out.problems,
    }
}

/// `level` with each transfer-function file it names read into it (checked to read), so that
/// playing it reads no file and a link can carry it whole.
fn with_files_read(mut level: Level, files: &dyn Files) -> Level {
    let origin = level.origin.clone();
    let read = |choice: &mut Option<TransferChoice>| {
        let Some(file) = choice.as_ref().and_then(TransferChoice::file) else {
            return;
        };
        let text = files.text(&origin.resolve(file));
        if let Some(t) = text
            .ok()
            .and_then(|text| serde_json::from_str::<TransferFunction>(&text).ok())
        {
            *choice = Some(TransferChoice::Inline(t));
        }
    };
    read(&mut level.scene.transfer);
    for step in &mut level.steps {
        if let Some(scene) = step.scene.as_mut() {
            read(&mut scene.transfer);
        }
    }
    level
}

/// Reads many files at once: each as [`read`] does, then ids that two files share (or that a
/// built-in level has) are errors.
pub fn read_all(texts: &[(Origin, String)], files: &dyn Files) -> Vec<(Origin, Checked)> {
    let builtin: Vec<String> = Level::all().into_iter().map(|l| l.id).collect();
    let mut seen: Vec<(String, String)> = Vec::new();
    let mut out: Vec<(Origin, Checked)> = Vec::new();
    for (origin, text) in texts {
        let mut checked = read(text, origin.clone(), files);
        if let Some(id) = checked.level.as_ref().map(|l| l.id.clone()) {
            let clash = if builtin.contains(&id) {
                Some("a built-in level's".to_string())
            } else {
                seen.iter()
                    .find(|(other, _)| *other == id)
                    .map(|(_, file)| format!("{file}'s"))
            };
            if let Some(whose) = clash {
                checked.problems.insert(
                    0,
                    Problem {
                        severity: Severity::Error,
                        place: "id".into(),
                        what: format!("\"{id}\" is {whose} id too"),
                        right: Some(
                            "give each level an id of its own: the students' progress and \
                             answers are kept under it"
                                .into(),
                        ),
                    },
                );
                checked.level = None;
            } else {
                seen.push((id, origin.words()));
            }
        }
        out.push((origin.clone(), checked));
    }
    out
}

#[derive(Default)]
struct Out {
    problems: Vec<Problem>,
}

impl Out {
    fn error(&mut self, place: impl Into<String>, what: impl Into<String>, right: Option<String>) {
        self.push(Severity::Error, place.into(), what.into(), right);
    }

    fn warn(&mut self, place: impl Into<String>, what: impl Into<String>, right: Option<String>) {
        self.push(Severity::Warning, place.into(), what.into(), right);
    }

    fn push(&mut self, severity: Severity, place: String, what: String, right: Option<String>) {
        self.problems.push(Problem {
            severity,
            place,
            what,
            right,
        });
    }

    fn has_errors(&self) -> bool {
        self.problems.iter().any(|p| p.severity == Severity::Error)
    }
}

/// The file's structure, part by part, each wrong part said in `out`: the level as far as it
/// reads (a step that does not read stands in as one only read), for the checks that follow;
/// `None` where not even its scene reads.
fn read_structure(text: &str, out: &mut Out) -> Option<Level> {
    let value: serde_json::Value = match serde_json::from_str(text) {
        Ok(v) => v,
        Err(e) => {
            out.error(
                format!("line {}, column {}", e.line(), e.column()),
                format!("not JSON: {e}"),
                Some("a level file is one JSON object (docs/levels.md shows one)".into()),
            );
            return None;
        }
    };
    let Some(top) = value.as_object() else {
        out.error(
            "the file",
            "a level is a JSON object, this is not",
            Some("{\"id\": …, \"title\": …, \"concept\": …, \"scene\": …, \"steps\": […]}".into()),
        );
        return None;
    };
    too_large(&value, "", out);
    for key in top.keys().filter(|k| !TOP_FIELDS.contains(&k.as_str())) {
        out.error(key.clone(), "no such field", Some(one_of(key, &TOP_FIELDS)));
    }
    for field in ["id", "title", "concept"] {
        match top.get(field) {
            None => out.error(field, "missing", Some(format!("give the level's {field}"))),
            Some(serde_json::Value::String(s)) if s.trim().is_empty() => {
                out.error(field, "empty", Some(format!("give the level's {field}")))
            }
            Some(serde_json::Value::String(_)) => {}
            Some(other) => out.error(
                field,
                format!("{} where text was expected", kind_of(other)),
                Some("a string in quotes".into()),
            ),
        }
    }
    let scene = match top.get("scene") {
        None => {
            out.error(
                "scene",
                "missing",
                Some("give at least {\"volume\": \"builtin:head\"}".into()),
            );
            None
        }
        Some(scene) => part::<LevelScene>(scene, "scene", out),
    };
    // Each step read on its own; one that does not read stands in as a step only read, so
    // the others are still checked under their own numbers.
    let steps: Vec<Step> = match top.get("steps") {
        None => {
            out.error(
                "steps",
                "missing",
                Some("a list of steps, at least one".into()),
            );
            Vec::new()
        }
        Some(serde_json::Value::Array(steps)) if steps.is_empty() => {
            out.error(
                "steps",
                "no steps",
                Some("a level needs at least one step".into()),
            );
            Vec::new()
        }
        Some(serde_json::Value::Array(steps)) => steps
            .iter()
            .enumerate()
            .map(|(k, step)| {
                part::<Step>(step, &format!("step {}", k + 1), out).unwrap_or(Step {
                    text: "(does not read)".into(),
                    control: None,
                    objective: Objective::Read,
                    scene: None,
                })
            })
            .collect(),
        Some(other) => {
            out.error(
                "steps",
                format!("{} where a list was expected", kind_of(other)),
                Some("[{\"text\": …, \"objective\": {\"kind\": \"read\"}}, …]".into()),
            );
            Vec::new()
        }
    };
    let text_of = |field: &str| top.get(field).and_then(|v| v.as_str()).unwrap_or_default();
    let mut level = Level {
        schema: None,
        id: text_of("id").to_string(),
        title: text_of("title").to_string(),
        concept: text_of("concept").to_string(),
        scene: scene?,
        steps,
        origin: Origin::Embedded,
    };
    for (k, step) in level.steps.iter_mut().enumerate() {
        match super::fill_in(&step.text) {
            Ok(text) => step.text = text,
            Err(e) => out.error(
                format!("step {} › text", k + 1),
                e.to_string(),
                Some(one_of(
                    "",
                    &crate::tunables::ALL
                        .iter()
                        .map(|t| t.key)
                        .collect::<Vec<_>>(),
                )),
            ),
        }
    }
    Some(level)
}

/// Every number beyond what a level's numbers (32-bit) can hold, said where it is: it would
/// read as infinite.
fn too_large(value: &serde_json::Value, place: &str, out: &mut Out) {
    let inner = |key: &str| {
        if place.is_empty() {
            key.to_string()
        } else {
            format!("{place} › {key}")
        }
    };
    match value {
        serde_json::Value::Number(n)
            if n.as_f64().is_some_and(|x| x.abs() > f64::from(f32::MAX)) =>
        {
            out.error(
                place,
                format!("{n} is too large"),
                Some(format!("a number of at most {:e} either way", f32::MAX)),
            )
        }
        serde_json::Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                // Steps are counted from 1, as the sandbox shows them; other lists as serde
                // says (`ray[1]`).
                let at = if place == "steps" {
                    format!("step {}", i + 1)
                } else {
                    format!("{place}[{i}]")
                };
                too_large(item, &at, out);
            }
        }
        serde_json::Value::Object(fields) => {
            for (k, v) in fields {
                too_large(v, &inner(k), out);
            }
        }
        _ => {}
    }
}

/// Reads `value` as a `T`, saying where (under `place`) and what failed.
fn part<T: serde::de::DeserializeOwned>(
    value: &serde_json::Value,
    place: &str,
    out: &mut Out,
) -> Option<T> {
    let e = match serde_path_to_error::deserialize::<_, T>(value) {
        Ok(t) => return Some(t),
        Err(e) => e,
    };
    let path = e.path().to_string();
    let place = if path == "." || path.is_empty() {
        place.to_string()
    } else {
        format!("{place} › {}", path.replace('.', " › "))
    };
    let message = e.inner().to_string();
    match unknown_name(&message) {
        Some((what, right)) => out.error(place, what, Some(right)),
        None => out.error(place, message, None),
    }
    None
}

/// For serde's "unknown variant `x`, expected one of `a`, `b`" (or field): what was given,
/// and the nearest name — or all of them where none is near.
fn unknown_name(message: &str) -> Option<(String, String)> {
    let quoted: Vec<&str> = message.split('`').skip(1).step_by(2).collect();
    let (&given, expected) = quoted.split_first()?;
    if !message.starts_with("unknown") || expected.is_empty() {
        return None;
    }
    let what = if message.starts_with("unknown field") {
        format!("no such field \"{given}\"")
    } else {
        format!("no such name \"{given}\"")
    };
    Some((what, one_of(given, expected)))
}

/// The name in `names` nearest to `given`, if it is near (a typo, not another word).
fn nearest<'a>(given: &str, names: &[&'a str]) -> Option<&'a str> {
    let (best, d) = names
        .iter()
        .map(|n| (*n, distance(given, n)))
        .min_by_key(|(_, d)| *d)?;
    (d <= given.chars().count().max(3) / 3 + 1).then_some(best)
}

/// Levenshtein's edit distance.
fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let up = row[j + 1];
            row[j + 1] = (up + 1)
                .min(row[j] + 1)
                .min(diagonal + usize::from(ca != *cb));
            diagonal = up;
        }
    }
    row[b.len()]
}

/// "did you mean …?" where `given` is a typo of one of `names`; else "one of: a, b, c"
/// (a long list is left to docs/levels.md).
fn one_of(given: &str, names: &[&str]) -> String {
    match nearest(given, names) {
        Some(n) if !given.is_empty() => format!("did you mean \"{n}\"?"),
        _ if names.len() > 12 => format!(
            "one of the {} names docs/levels.md lists ({}, …)",
            names.len(),
            names[..6].join(", ")
        ),
        _ => format!("one of: {}", names.join(", ")),
    }
}

fn kind_of(v: &serde_json::Value) -> &'static str {
    match v {
        serde_json::Value::Null => "null",
        serde_json::Value::Bool(_) => "true or false",
        serde_json::Value::Number(_) => "a number",
        serde_json::Value::String(_) => "text",
        serde_json::Value::Array(_) => "a list",
        serde_json::Value::Object(_) => "an object",
    }
}

/// What a scene (the level's, then each step's) leaves on screen, as the check follows it.
struct Shown {
    volume: Option<Volume>,
    transfer: TransferFunction,
    settings: RenderSettings,
    /// The virtual camera's pixels across and down (`None`: no virtual camera).
    pixels: Option<[u32; 2]>,
}

/// What only the code can tell about a level that reads.
fn check_level(level: &Level, files: &dyn Files, out: &mut Out) {
    if !level
        .id
        .chars()
        .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-' || c == '_')
    {
        out.warn(
            "id",
            format!(
                "\"{}\" has characters other than a-z, 0-9, - and _",
                level.id
            ),
            Some("the id names the level in the answers' files and on the command line".into()),
        );
    }
    let scene = &level.scene;
    let mut shown = Shown {
        volume: None,
        transfer: TransferFunction::constant([1.0; 3], 0.5).expect("a constant is valid"),
        settings: RenderSettings::default(),
        pixels: scene.rays.map(|n| [n, n]),
    };
    if let Some(name) = &scene.preset {
        check_preset(name, "scene › preset", out);
    }
    if let Some(n) = scene.rays
        && !(1..=64).contains(&n)
    {
        out.error(
            "scene › rays",
            format!("{n} pixels"),
            Some("1 to 64".into()),
        );
    }
    if let Some(s) = scene.preview_scale {
        let t = &crate::tunables::PREVIEW_SCALE;
        if !(t.min..=t.max).contains(&s) {
            out.error(
                "scene › preview_scale",
                format!("{s}"),
                Some(format!("{} to {}", t.min, t.max)),
            );
        }
    }
    open_scene(
        level,
        &scene.snapshot(),
        true,
        &mut shown,
        files,
        "scene",
        out,
    );
    for (k, step) in level.steps.iter().enumerate() {
        let place = format!("step {}", k + 1);
        if step.text.trim().is_empty() {
            out.error(
                format!("{place} › text"),
                "empty",
                Some("say what to do".into()),
            );
        }
        if let (Some(section), Some(panel)) = (step.control.and_then(|c| c.section()), &scene.panel)
            && !panel.contains(&section)
        {
            out.warn(
                format!("{place} › control"),
                format!("its section ({section:?}) is not in the level's panel"),
                Some("add it to scene › panel, or the student cannot reach the control".into()),
            );
        }
        if let Some(s) = &step.scene {
            open_scene(
                level,
                s,
                false,
                &mut shown,
                files,
                &format!("{place} › scene"),
                out,
            );
        }
        check_objective(&step.objective, &format!("{place} › objective"), out);
        check_quoted(step, &place, out);
        check_prediction(step, &shown, &place, out);
        // Where the check knows the state the step opens in: the first step, and a step that
        // sets its own scene (as if the steps before changed nothing else).
        if k == 0 || step.scene.is_some() {
            check_met_at_open(level, step, &shown, &place, out);
        }
    }
}

/// Follows a scene as it opens (the level's with `fresh`, starting from its data set's own
/// settings; a step's over what was on screen), checking each of its parts.
fn open_scene(
    level: &Level,
    scene: &StepScene,
    fresh: bool,
    shown: &mut Shown,
    files: &dyn Files,
    place: &str,
    out: &mut Out,
) {
    if let Some(name) = &scene.volume {
        let source = level.resolve(name);
        match files.volume(&source) {
            Ok(volume) => {
                if fresh || shown.volume.is_none() {
                    let (transfer, settings) = crate::preset::defaults_for(&volume);
                    (shown.transfer, shown.settings) = (transfer, settings);
                }
                shown.volume = Some(volume);
            }
            Err(e) => {
                out.warn(
                    format!("{place} › volume"),
                    format!("cannot read \"{source}\": {e}"),
                    Some(
                        "give builtin:NAME or a volume file (NRRD, NIfTI, raw) beside the level"
                            .into(),
                    ),
                );
                shown.volume = None;
            }
        }
    }
    if fresh {
        level
            .scene
            .over_defaults(&mut shown.transfer, &mut shown.settings);
    }
    if let Some(choice) = &scene.transfer {
        let place = format!("{place} › transfer");
        match choice {
            TransferChoice::Inline(t) => shown.transfer = t.clone(),
            TransferChoice::Named(name) => match choice.file() {
                Some(file) => {
                    let path = level.resolve(file);
                    let read = files.text(&path).and_then(|text| {
                        serde_json::from_str::<TransferFunction>(&text).map_err(|e| e.to_string())
                    });
                    match read {
                        Ok(t) => shown.transfer = t,
                        Err(e) => out.error(
                            place,
                            format!("cannot read \"{path}\": {e}"),
                            Some("a transfer function saved from the editor (JSON)".into()),
                        ),
                    }
                }
                None => {
                    if let Some(p) = check_preset(name, &place, out) {
                        shown.transfer = p.transfer;
                    }
                }
            },
        }
    }
    if let Some(changes) = &scene.settings {
        match crate::preset::settings_written_over(&shown.settings, changes) {
            Ok(s) => shown.settings = s,
            Err(e) => out.error(
                format!("{place} › settings"),
                e,
                Some("the names and values a preset's settings use (docs/levels.md)".into()),
            ),
        }
    }
    for (which, camera) in [
        ("camera", scene.camera),
        ("virtual_camera", scene.virtual_camera),
    ] {
        let Some(c) = camera else { continue };
        let place = format!("{place} › {which}");
        let (eye, target) = (glam::Vec3::from(c.eye), glam::Vec3::from(c.target));
        if !eye.is_finite() || !target.is_finite() || eye.distance(target) <= 0.0 {
            out.error(
                &place,
                "the eye must stand apart from its target",
                Some("two different points, in world units".into()),
            );
        }
        if glam::Vec3::from(c.up).cross(target - eye).length_squared() <= 0.0 {
            out.error(
                &place,
                "up runs along the line of sight",
                Some("an up direction across it, such as [0, 1, 0]".into()),
            );
        }
        if let Some(fov) = c.fov_y_deg
            && !(fov > 1.0 && fov < 179.0)
        {
            out.error(
                format!("{place} › fov_y_deg"),
                format!("{fov}°"),
                Some("between 1 and 179 degrees".into()),
            );
        }
        if let Some(p) = c.pixels {
            if which == "camera" {
                out.error(
                    format!("{place} › pixels"),
                    "the main camera has the window's pixels",
                    Some("give pixels to the virtual camera".into()),
                );
            } else if p.iter().any(|n| !(1..=64).contains(n)) {
                out.error(
                    format!("{place} › pixels"),
                    format!("{} × {}", p[0], p[1]),
                    Some("1 to 64 each way".into()),
                );
            } else {
                shown.pixels = Some(p);
            }
        }
    }
    if let Some(ray) = scene.ray {
        match shown.pixels {
            None => out.error(
                format!("{place} › ray"),
                "a selected ray needs a virtual camera",
                Some("give the level's scene \"rays\"".into()),
            ),
            Some(p) if ray[0] >= p[0] || ray[1] >= p[1] => out.error(
                format!("{place} › ray"),
                format!("pixel ({}, {}) is outside the image", ray[0], ray[1]),
                Some(format!(
                    "x from 0 to {}, y from 0 to {}",
                    p[0] - 1,
                    p[1] - 1
                )),
            ),
            _ => {}
        }
    }
}

/// The embedded preset `name`, or an error saying which there are.
fn check_preset(name: &str, place: &str, out: &mut Out) -> Option<crate::preset::Preset> {
    let found = crate::preset::by_name(name);
    if found.is_none() {
        let names: Vec<String> = crate::preset::all().into_iter().map(|p| p.name).collect();
        let names: Vec<&str> = names.iter().map(String::as_str).collect();
        out.error(
            place,
            format!("no preset \"{name}\""),
            Some(format!(
                "{}; or a transfer-function file ending in .json",
                one_of(name, &names)
            )),
        );
    }
    found
}

/// Names an objective gives that must name something real.
fn check_objective(objective: &Objective, place: &str, out: &mut Out) {
    let wrong = |out: &mut Out, field: &str, given: &str, names: &[&str]| {
        if !names.contains(&given) {
            out.error(
                format!("{place} › {field}"),
                format!("\"{given}\" names nothing here"),
                Some(one_of(given, names)),
            );
        }
    };
    let views: Vec<&str> = crate::cost::CostView::ALL
        .iter()
        .map(|v| v.name())
        .collect();
    let knobs: Vec<&str> = crate::knob::Knob::ALL.iter().map(|k| k.name()).collect();
    for o in objective.parts() {
        match o {
            Objective::KnobMeasured { knob } => wrong(out, "knob", knob, &knobs),
            Objective::CostViewed { view } => wrong(out, "view", view, &views),
            Objective::PreviewCostView { view } => {
                let mut names = vec!["picture"];
                names.extend(&views);
                wrong(out, "view", view, &names)
            }
            Objective::RayView { view, .. } => {
                wrong(out, "view", view, &["volume", "mesh", "field"])
            }
            Objective::Classification { mode } => wrong(
                out,
                "mode",
                mode,
                &["table", "iso-contours", "boundaries", "value-gradient"],
            ),
            Objective::LightKind { light } => wrong(
                out,
                "light",
                light,
                &["headlight", "point", "directional", "spot"],
            ),
            Objective::Specular { model } => wrong(out, "model", model, &["phong", "blinn-phong"]),
            Objective::StudyQuestion { trace, question } => {
                let questions = ["camera", "hits", "density-high", "density-low"];
                wrong(out, "question", question, &questions);
                wrong(out, "trace", &trace.to_string(), &["0", "1", "2", "3", "4"]);
            }
            Objective::NameEffect { trace } => {
                wrong(out, "trace", &trace.to_string(), &["0", "1", "2", "3", "4"])
            }
            Objective::All { of } if of.is_empty() => out.error(
                format!("{place} › of"),
                "nothing to meet",
                Some("list the objectives to meet together".into()),
            ),
            Objective::PredictValue { tolerance, .. }
            | Objective::PredictComposite { tolerance, .. }
            | Objective::TfColorNear { tolerance, .. }
                if tolerance.is_nan() || *tolerance <= 0.0 =>
            {
                out.error(
                    format!("{place} › tolerance"),
                    format!("{tolerance}"),
                    Some("a number above 0".into()),
                )
            }
            _ => {}
        }
    }
}

/// The numbers an objective checks, which its text should tell the student.
fn numbers(objective: &Objective) -> Vec<f32> {
    objective
        .parts()
        .into_iter()
        .flat_map(|o| match o {
            Objective::VirtualPixelsAtLeast { pixels } => vec![*pixels as f32],
            Objective::StepAtMost { voxels } | Objective::StepAtLeast { voxels } => vec![*voxels],
            Objective::TargetBetween { lo, hi } => vec![*lo, *hi],
            Objective::TfAlphaAtMost { value, alpha } => vec![*value, *alpha],
            Objective::TfBinary { threshold, within } => {
                vec![threshold - within, threshold + within]
            }
            Objective::TfColorNear { value, alpha, .. } => vec![*value, *alpha],
            Objective::Compared { max } => vec![*max],
            Objective::SupersamplingAtLeast { rays } => vec![*rays as f32],
            Objective::LightsAtLeast { count } | Objective::DistinctLightColours { count } => {
                vec![*count as f32]
            }
            Objective::OpenLitSample { lights } => vec![*lights as f32],
            Objective::ClipPositionBetween { lo, hi } => vec![*lo, *hi],
            Objective::CropAtMost { fraction } => vec![*fraction],
            Objective::PreviewScaleAtMost { scale } | Objective::PreviewScaleAtLeast { scale } => {
                vec![*scale]
            }
            Objective::PredictValue { point, tolerance } => {
                point.iter().copied().chain([*tolerance]).collect()
            }
            Objective::PredictComposite { points, tolerance } => points
                .iter()
                .flatten()
                .copied()
                .chain([*tolerance])
                .collect(),
            Objective::PredictFixedCountStep { steps, tolerance } => {
                vec![*steps as f32, *tolerance]
            }
            _ => vec![],
        })
        .collect()
}

/// A number the objective checks but the text never gives: the student cannot know it.
fn check_quoted(step: &Step, place: &str, out: &mut Out) {
    for v in numbers(&step.objective) {
        if !step.text.contains(&format!("{v}")) {
            out.warn(
                format!("{place} › text"),
                format!("does not give {v}, which the objective checks"),
                Some("say the number the student has to reach".into()),
            );
        }
    }
}

/// A prediction whose answer the code cannot compute: a point off the volume's lattice.
fn check_prediction(step: &Step, shown: &Shown, place: &str, out: &mut Out) {
    let points: Vec<[f32; 3]> = step
        .objective
        .parts()
        .into_iter()
        .flat_map(|o| match o {
            Objective::PredictValue { point, .. } => vec![*point],
            Objective::PredictComposite { points, .. } => points.clone(),
            _ => vec![],
        })
        .collect();
    if points.is_empty() {
        return;
    }
    let Some(volume) = &shown.volume else {
        out.warn(
            format!("{place} › objective"),
            "its answer cannot be computed: the data set cannot be read",
            None,
        );
        return;
    };
    let last = (volume.dims() - glam::UVec3::ONE).as_vec3();
    for p in points {
        let inside = (0..3).all(|a| p[a].is_finite() && p[a] >= 0.0 && p[a] <= last[a]);
        if !inside {
            out.warn(
                format!("{place} › objective"),
                format!(
                    "its answer cannot be computed: ({}, {}, {}) lies off the volume's lattice",
                    p[0], p[1], p[2]
                ),
                Some(format!(
                    "voxel coordinates from (0, 0, 0) to ({}, {}, {})",
                    last.x, last.y, last.z
                )),
            );
        }
    }
}

/// An objective met before the student does anything: Next is open at once.
fn check_met_at_open(level: &Level, step: &Step, shown: &Shown, place: &str, out: &mut Out) {
    if step.objective == Objective::Read {
        return;
    }
    let Some(volume) = &shown.volume else { return };
    let mut s = Situation::from_settings(
        &shown.settings,
        &shown.transfer,
        volume.bounds(),
        volume.spacing().min_element(),
    );
    s.preview_on = level.scene.preview;
    s.preview_scale = level.scene.preview_scale.unwrap_or(1.0);
    s.virtual_pixels_across = shown.pixels.map_or(0, |p| p[0]);
    s.ray_selected = step
        .scene
        .as_ref()
        .map_or(level.scene.ray, |s| s.ray)
        .is_some();
    s.at_open = Some(Box::new(s.clone()));
    if step.objective.met(&s) {
        out.warn(
            format!("{place} › objective"),
            "already met when the step opens: Next is open before the student does anything",
            Some("ask for a change from what the scene starts with".into()),
        );
    }
}

#[cfg(test)]
mod tests;
