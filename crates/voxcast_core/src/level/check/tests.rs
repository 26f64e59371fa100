//! The check of level files: the built-in levels pass it without a word, a broken file gets
//! each of its problems named where it is, and no text makes it panic.

use super::*;
use proptest::prelude::*;

/// The built-in levels' files with their names.
fn builtin_files() -> Vec<(String, String)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/levels");
    let mut files: Vec<(String, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| {
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    files.sort();
    files
}

/// Files the tests name, held in memory; volumes from the binary.
struct Here(Vec<(&'static str, String)>);

impl Files for Here {
    fn volume(&self, source: &str) -> Result<Volume, String> {
        OnDisk.volume(source)
    }

    fn text(&self, name: &str) -> Result<String, String> {
        self.0
            .iter()
            .find(|(n, _)| name.ends_with(n))
            .map(|(_, t)| t.clone())
            .ok_or_else(|| "no such file".into())
    }
}

fn check(text: &str) -> Checked {
    read(
        text,
        Origin::File("/course/level.json".into()),
        &Here(Vec::new()),
    )
}

/// Every built-in level is a file of the format: it reads, checks without a single problem,
/// is the level the binary holds, and its file is written as the editor writes it.
#[test]
fn the_built_in_levels_are_files_of_the_format() {
    let files = builtin_files();
    let embedded = Level::all();
    assert_eq!(files.len(), embedded.len(), "a level file not compiled in");
    for ((name, text), level) in files.iter().zip(&embedded) {
        let checked = read(text, Origin::Embedded, &OnDisk);
        assert_eq!(checked.problems, [], "{name}");
        assert_eq!(
            checked.level.as_ref(),
            Some(level),
            "{name}: in teaching order"
        );
        let raw: Level = serde_json::from_str(text).unwrap();
        assert_eq!(
            &super::super::to_text(&raw),
            text,
            "{name} is not as the editor writes it"
        );
    }
    let mut ids: Vec<&str> = embedded.iter().map(|l| l.id.as_str()).collect();
    ids.sort_unstable();
    ids.dedup();
    assert_eq!(ids.len(), embedded.len(), "an id twice");
}

/// A file with a mistake in every part: each is named with its place and what would be right,
/// and the level is refused.
#[test]
fn every_problem_is_named_where_it_is() {
    let text = r#"{
      "id": "ct lesson",
      "titel": "Typo",
      "concept": "",
      "scene": {"volume": "builtin:head", "rays": 4},
      "steps": [
        {"text": "Set the step.", "objective": {"kind": "step-at-mots", "voxels": 0.25}},
        {"text": "Measure.", "objective": {"kind": "knob-measured", "knob": "stepp"}},
        {"text": "Hi", "objective": {"kind": "read"}, "scene": {"transfer": "bunnny"}},
        {"text": "Far.", "objective": {"kind": "step-at-least", "voxels": 1e39},
         "scene": {"ray": [1, "2"]}}
      ]
    }"#;
    let checked = check(text);
    assert!(checked.level.is_none());
    let lines: Vec<String> = checked.problems.iter().map(|p| p.to_string()).collect();
    let has = |needle: &str| {
        assert!(
            lines.iter().any(|l| l.contains(needle)),
            "no problem says {needle:?}: {lines:#?}"
        )
    };
    has("error: titel: no such field — did you mean \"title\"?");
    has("error: title: missing");
    has("error: concept: empty");
    has("error: step 4 › scene › ray[1]: invalid type: string \"2\", expected u32");
    has("error: step 4 › objective › voxels: 1e+39 is too large");
    has("error: step 3 › scene › transfer: no preset \"bunnny\" — did you mean \"bunny\"?");
    has(
        "error: step 1 › objective › kind: no such name \"step-at-mots\" — did you mean \"step-at-most\"?",
    );
    // What only the code can tell is checked on the steps that read.
    has("error: step 2 › objective › knob: \"stepp\" names nothing here — did you mean \"step\"?");
    has("warning: id: \"ct lesson\" has characters other than a-z");
}

/// What only the code can tell, once the file reads: names that name nothing, settings the
/// renderer refuses, a ray off the image, a prediction off the lattice, an objective met as
/// its step opens, a number the text never gives, a control hidden by the panel, a file that
/// cannot be read — each an error or a warning, with the right names.
#[test]
fn what_only_the_code_can_tell() {
    let text = r#"{
      "id": "ct-lesson",
      "title": "Mistakes",
      "concept": "Every kind of mistake.",
      "scene": {"volume": "builtin:voxel", "rays": 4, "panel": ["ray-casting"],
                "settings": {"method": "frist"}},
      "steps": [
        {"text": "Early termination.", "control": "early-termination",
         "objective": {"kind": "early-termination", "on": true}},
        {"text": "Measure it.", "objective": {"kind": "knob-measured", "knob": "stepp"}},
        {"text": "Go to 0.25.", "objective": {"kind": "step-at-most", "voxels": 0.3}},
        {"text": "Predict (2, 0, 0) within 0.1.",
         "objective": {"kind": "predict-value", "point": [2, 0, 0], "tolerance": 0.1}},
        {"text": "Light.", "control": "light", "objective": {"kind": "shading", "on": false}},
        {"text": "Click.", "objective": {"kind": "select-ray"},
         "scene": {"ray": [4, 0], "transfer": "tf.json", "volume": "missing.nrrd"}}
      ]
    }"#;
    let checked = check(text);
    assert!(checked.level.is_none(), "errors keep it out");
    let lines: Vec<String> = checked.problems.iter().map(|p| p.to_string()).collect();
    let has = |needle: &str| {
        assert!(
            lines.iter().any(|l| l.contains(needle)),
            "no problem says {needle:?}: {lines:#?}"
        )
    };
    has("error: scene › settings: unknown variant `frist`");
    has("error: step 6 › scene › transfer: cannot read");
    has("error: step 2 › objective › knob: \"stepp\" names nothing here — did you mean \"step\"?");
    has("warning: step 1 › objective: already met when the step opens");
    has("warning: step 3 › text: does not give 0.3, which the objective checks");
    has("warning: step 4 › objective: its answer cannot be computed: (2, 0, 0) lies off the");
    has("voxel coordinates from (0, 0, 0) to (1, 1, 1)");
    has("warning: step 5 › control: its section (ShadingAndLight) is not in the level's panel");
    has("error: step 6 › scene › ray: pixel (4, 0) is outside the image — x from 0 to 3");
    has("error: step 6 › scene › transfer: cannot read \"/course/tf.json\": no such file");
    has("warning: step 6 › scene › volume: cannot read \"/course/missing.nrrd\"");
    // Errors first, then warnings.
    let first_warning = checked
        .problems
        .iter()
        .position(|p| p.severity == Severity::Warning)
        .unwrap();
    assert!(
        checked.problems[first_warning..]
            .iter()
            .all(|p| p.severity == Severity::Warning)
    );
}

/// A level with only warnings still plays; a transfer function beside it is read from there.
#[test]
fn a_level_with_warnings_plays_and_reads_its_files() {
    let text = r#"{
      "id": "mine", "title": "Mine", "concept": "A level of my own.",
      "scene": {"volume": "builtin:head", "transfer": "skin.json", "rays": 2},
      "steps": [{"text": "Choose First.", "objective": {"kind": "method", "method": "first"},
                 "scene": {"settings": {"method": "first"}}}]
    }"#;
    let tf = r#"{"name": "skin", "points": [{"value": 0, "color": [1, 0.8, 0.7], "alpha": 0},
                {"value": 90, "color": [1, 0.8, 0.7], "alpha": 0.9}]}"#;
    let files = Here(vec![("skin.json", tf.into())]);
    let checked = read(text, Origin::File("/course/mine.json".into()), &files);
    let level = checked.level.expect("warnings only");
    assert_eq!(level.origin, Origin::File("/course/mine.json".into()));
    assert_eq!(level.resolve("skin.json"), "/course/skin.json");
    assert!(
        matches!(&level.scene.transfer, Some(TransferChoice::Inline(t)) if t.name == "skin"),
        "the file is read into the level"
    );
    let [p] = &checked.problems[..] else {
        panic!("{:#?}", checked.problems)
    };
    assert_eq!(p.severity, Severity::Warning);
    assert!(p.what.starts_with("already met"), "{p}");
}

#[test]
fn not_json_and_not_a_level() {
    let checked = check("{\"id\": \"x\",\n \"title\": }");
    assert_eq!(checked.problems.len(), 1);
    assert!(checked.problems[0].place.starts_with("line 2, column"));
    let checked = check("[1, 2]");
    assert_eq!(
        checked.problems[0].what,
        "a level is a JSON object, this is not"
    );
    let checked = check(
        r#"{"id": "x", "title": "t", "concept": "c", "scene": {"volume": "builtin:head"}, "steps": []}"#,
    );
    assert_eq!(
        checked.problems[0].to_string(),
        "error: steps: no steps — a level needs at least one step"
    );
}

/// Two files with one id, and a file with a built-in level's id: errors, and neither is added
/// twice.
#[test]
fn ids_are_unique_across_files_and_the_built_in_levels() {
    let level = |id: &str| {
        format!(
            r#"{{"id": "{id}", "title": "T", "concept": "C", "scene": {{"volume": "builtin:head"}},
               "steps": [{{"text": "Read.", "objective": {{"kind": "read"}}}}]}}"#
        )
    };
    let texts = vec![
        (Origin::File("a.json".into()), level("mine")),
        (Origin::File("b.json".into()), level("mine")),
        (Origin::File("c.json".into()), level("rays")),
    ];
    let read = read_all(&texts, &OnDisk);
    assert!(read[0].1.level.is_some());
    for (_, checked) in &read[1..] {
        assert!(checked.level.is_none());
    }
    assert!(read[1].1.problems[0].what.contains("a.json's id too"));
    assert!(read[2].1.problems[0].what.contains("a built-in level's id"));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Whatever a file holds — a built-in level cut short, a byte changed, a value replaced —
    /// the check answers without panicking, and a level it accepts reads again from its own
    /// text.
    #[test]
    fn no_file_makes_the_check_panic(
        file in 0usize..19,
        cut in 0.0f64..1.0,
        at in 0.0f64..1.0,
        byte in any::<u8>(),
        value in prop_oneof![
            Just("null".to_string()), Just("-1e39".to_string()), Just("\"\"".to_string()),
            Just("[]".to_string()), Just("{}".to_string()), Just("1e400".to_string()),
            Just("\"builtin:nothing\"".to_string()), Just("4294967296".to_string()),
        ],
    ) {
        let files = builtin_files();
        let text = &files[file % files.len()].1;
        let bytes = text.as_bytes();
        // Cut short.
        let n = (cut * bytes.len() as f64) as usize;
        let _ = check(&String::from_utf8_lossy(&bytes[..n]));
        // One byte changed.
        let mut changed = bytes.to_vec();
        let i = ((at * bytes.len() as f64) as usize).min(bytes.len() - 1);
        changed[i] = byte;
        let _ = check(&String::from_utf8_lossy(&changed));
        // One number replaced by something else.
        let digits: Vec<usize> = text.match_indices(|c: char| c.is_ascii_digit()).map(|(i, _)| i).collect();
        if !digits.is_empty() {
            let i = digits[((at * digits.len() as f64) as usize).min(digits.len() - 1)];
            let end = text[i..].find(|c: char| !(c.is_ascii_digit() || c == '.')).map_or(text.len(), |e| i + e);
            let replaced = format!("{}{}{}", &text[..i], value, &text[end..]);
            let checked = check(&replaced);
            if let Some(level) = checked.level {
                let again = check(&super::super::to_text(&level));
                prop_assert!(again.level.is_some(), "{:?}", again.problems);
            }
        }
    }
}

/// The schema beside the docs is the one the types generate (`voxcast levels schema --out
/// docs/levels.schema.json` writes it again), and it names every objective's kind.
#[test]
fn the_published_schema_is_the_types_schema() {
    let published = include_str!("../../../../../docs/levels.schema.json");
    assert!(
        published == crate::level::schema_text(),
        "docs/levels.schema.json is out of date: run voxcast levels schema --out docs/levels.schema.json"
    );
    let schema = crate::level::schema();
    let kinds: Vec<&str> = schema["$defs"]["Objective"]["oneOf"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v["properties"]["kind"]["const"].as_str().unwrap())
        .collect();
    for kind in [
        "read",
        "all",
        "step-moved",
        "predict-value",
        "study-question",
    ] {
        assert!(kinds.contains(&kind), "{kind}: {kinds:?}");
    }
    assert_eq!(
        schema["additionalProperties"], false,
        "a misspelt field is marked"
    );
}

/// docs/levels.md says what is true of the code: its whole level checks without a problem,
/// every objective example in it reads, every kind the schema has is shown by an example, and
/// every setting name it lists is one the renderer reads.
#[test]
fn the_format_s_documentation_is_the_code_s() {
    let doc = include_str!("../../../../../docs/levels.md");
    let block = doc
        .split("```json\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .expect("a whole level in the docs");
    let checked = read(block, Origin::Embedded, &OnDisk);
    assert_eq!(checked.problems, [], "the docs' level");
    let mut shown = Vec::new();
    let blocks = doc
        .split("```json\n")
        .skip(2)
        .filter_map(|b| b.split("```").next());
    let spans = doc.split('`').skip(1).step_by(2);
    for span in spans.chain(blocks).map(str::trim) {
        if span.starts_with("{\"kind\"") {
            let o: Objective = serde_json::from_str(span).unwrap_or_else(|e| panic!("{span}: {e}"));
            let kind = |o: &Objective| {
                serde_json::to_value(o).unwrap()["kind"]
                    .as_str()
                    .unwrap()
                    .to_string()
            };
            shown.push(kind(&o));
            shown.extend(o.parts().into_iter().map(kind));
        }
    }
    let schema = crate::level::schema();
    for v in schema["$defs"]["Objective"]["oneOf"].as_array().unwrap() {
        let kind = v["properties"]["kind"]["const"].as_str().unwrap();
        assert!(
            shown.iter().any(|s| s == kind),
            "docs/levels.md shows no {kind}"
        );
    }
    let settings = doc
        .split("```text\n")
        .nth(1)
        .and_then(|rest| rest.split("```").next())
        .unwrap();
    let defaults = serde_json::to_value(RenderSettings::default()).unwrap();
    for name in settings.split('"').skip(1).step_by(2) {
        let known = defaults.get(name).is_some()
            || defaults["phong"].get(name).is_some()
            || defaults["clip"].get(name).is_some()
            || ["voxels", "mode", "normal", "position"].contains(&name)
            || name.chars().all(|c| c.is_ascii_lowercase() || c == '-');
        assert!(
            known,
            "docs/levels.md lists a setting \"{name}\" the renderer has not"
        );
    }
    for knob in crate::knob::Knob::ALL {
        assert!(
            doc.contains(&format!("`{}`", knob.name())),
            "{}",
            knob.name()
        );
    }
    for view in crate::cost::CostView::ALL {
        assert!(
            doc.contains(&format!("`{}`", view.name())),
            "{}",
            view.name()
        );
    }
}

/// The editor's lists are the format's: an example objective of every kind the schema has, in
/// its order, each read back as it is written; every control the schema names.
#[test]
fn the_editor_offers_every_kind_and_control() {
    let schema = crate::level::schema();
    let kinds: Vec<String> = schema["$defs"]["Objective"]["oneOf"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| {
            v["properties"]["kind"]["const"]
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();
    let examples: Vec<String> = Objective::examples().iter().map(Objective::kind).collect();
    assert_eq!(examples, kinds);
    // The schema lists the documented controls one by one, the rest in one enum.
    let controls: Vec<String> = schema["$defs"]["Control"]["oneOf"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|v| match v["enum"].as_array() {
            Some(names) => names.clone(),
            None => vec![v["const"].clone()],
        })
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    let all: Vec<String> = crate::level::Control::ALL
        .iter()
        .map(|c| {
            serde_json::to_value(c)
                .unwrap()
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();
    assert_eq!(all, controls);
}
