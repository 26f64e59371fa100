//! The levels' file format as a JSON Schema (draft 2020-12), generated from the Rust types
//! with schemars: the field docs become its descriptions, so an editor that reads the schema
//! (`"$schema"` in a level file) shows them and marks a wrong field as it is typed. The copy in
//! `docs/levels.schema.json` is tested to be this one; `voxcast levels schema` prints it.

use super::Level;

/// Where the schema is published beside the docs (a level file's `"$schema"`).
pub const SCHEMA_FILE: &str = "levels.schema.json";

/// The schema of a level file.
pub fn schema() -> serde_json::Value {
    let mut schema = serde_json::to_value(schemars::schema_for!(Level)).expect("a schema is JSON");
    if let Some(o) = schema.as_object_mut() {
        o.insert(
            "title".into(),
            "A Voxcast level: a data set, what the scene holds, and steps a student follows, \
             each with the objective that opens Next"
                .into(),
        );
    }
    schema
}

/// The schema as the file holds it (two-space indents, a newline at the end).
pub fn schema_text() -> String {
    serde_json::to_string_pretty(&schema()).expect("a schema is JSON") + "\n"
}
