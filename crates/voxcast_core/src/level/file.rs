//! Level files: the text the editor saves (and the built-in levels are kept in) — JSON with
//! two-space indents, the fields in the order docs/levels.md gives them, and a list of plain
//! values on one line (`"point": [0.5, 0.5, 0.5]`) — and the files a path names, one level
//! file or a folder of them.

use super::{Level, Origin};
use std::path::{Path, PathBuf};

/// The level as its file holds it.
pub fn to_text(level: &Level) -> String {
    let pretty = serde_json::to_string_pretty(level).expect("a level is plain data");
    compact_flat_lists(&pretty) + "\n"
}

/// Writes each number of `value` that holds an `f32` (settings turned into JSON) as the
/// shortest decimal that reads back as that `f32`: `0.99`, not `0.9900000095367432`.
pub fn shortest_f32s(value: &mut serde_json::Value) {
    match value {
        serde_json::Value::Number(n) => {
            if let Some(x) = n.as_f64().filter(|_| !n.is_i64() && !n.is_u64()) {
                let f = x as f32;
                if f as f64 == x
                    && let Some(short) = f.to_string().parse::<f64>().ok()
                    && let Some(number) = serde_json::Number::from_f64(short)
                {
                    *n = number;
                }
            }
        }
        serde_json::Value::Array(items) => items.iter_mut().for_each(shortest_f32s),
        serde_json::Value::Object(map) => map.values_mut().for_each(shortest_f32s),
        _ => {}
    }
}

/// `pretty` with each list that holds no list or object written on one line.
fn compact_flat_lists(pretty: &str) -> String {
    let bytes = pretty.as_bytes();
    let mut out = String::with_capacity(pretty.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'"' {
            let end = string_end(bytes, i);
            out.push_str(&pretty[i..end]);
            i = end;
            continue;
        }
        if bytes[i] == b'['
            && let Some((end, items)) = flat_list(pretty, i)
        {
            out.push('[');
            out.push_str(&items.join(", "));
            out.push(']');
            i = end;
            continue;
        }
        let c = pretty[i..].chars().next().expect("inside the text");
        out.push(c);
        i += c.len_utf8();
    }
    out
}

/// The index just past the string that opens at `start` (a `"`).
fn string_end(bytes: &[u8], start: usize) -> usize {
    let mut i = start + 1;
    while i < bytes.len() {
        match bytes[i] {
            b'\\' => i += 2,
            b'"' => return i + 1,
            _ => i += 1,
        }
    }
    bytes.len()
}

/// For a list opening at `start` that holds only plain values: the index past its `]` and
/// its items.
fn flat_list(text: &str, start: usize) -> Option<(usize, Vec<String>)> {
    let bytes = text.as_bytes();
    let mut i = start + 1;
    let mut items = Vec::new();
    let mut item = String::new();
    while i < bytes.len() {
        match bytes[i] {
            b'[' | b'{' => return None,
            b']' => {
                let last = item.trim();
                if !last.is_empty() {
                    items.push(last.to_string());
                }
                return Some((i + 1, items));
            }
            b',' => {
                items.push(item.trim().to_string());
                item.clear();
                i += 1;
            }
            b'"' => {
                let end = string_end(bytes, i);
                item.push_str(&text[i..end]);
                i = end;
            }
            _ => {
                let c = text[i..].chars().next()?;
                item.push(c);
                i += c.len_utf8();
            }
        }
    }
    None
}

/// A level file found: where it is, and its text or why it cannot be read.
pub type Found = (Origin, Result<String, String>);

/// The level files `path` names: itself, or the `.json` files in a folder (not in its
/// subfolders), by name; each with its text, or why it cannot be read.
pub fn files_at(path: &Path) -> Result<Vec<Found>, String> {
    let words = |e: &std::io::Error| format!("{}: {}", path.display(), crate::error::io_words(e));
    let meta = std::fs::metadata(path).map_err(|e| words(&e))?;
    let paths: Vec<PathBuf> = if meta.is_dir() {
        let mut found: Vec<PathBuf> = std::fs::read_dir(path)
            .map_err(|e| words(&e))?
            .filter_map(Result::ok)
            .map(|e| e.path())
            .filter(|p| {
                p.is_file()
                    && p.extension()
                        .is_some_and(|x| x.eq_ignore_ascii_case("json"))
            })
            .collect();
        found.sort();
        if found.is_empty() {
            return Err(format!("{}: no level files (.json) in it", path.display()));
        }
        found
    } else {
        vec![path.to_path_buf()]
    };
    Ok(paths
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).map_err(|e| crate::error::io_words(&e));
            (Origin::File(p), text)
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_lists_go_on_one_line_and_strings_stay_whole() {
        let pretty = "{\n  \"a\": [\n    1.0,\n    2.5\n  ],\n  \"b\": [\n    [\n      1,\n      \
                      2\n    ]\n  ],\n  \"c\": \"[x, \\\"y\\\"]\",\n  \"d\": []\n}";
        assert_eq!(
            compact_flat_lists(pretty),
            "{\n  \"a\": [1.0, 2.5],\n  \"b\": [\n    [1, 2]\n  ],\n  \"c\": \"[x, \\\"y\\\"]\",\
             \n  \"d\": []\n}"
        );
    }

    /// Settings as JSON hold their `f32`s widened; written shortest, they read back as the
    /// same settings, and whole numbers and true `f64`s are left alone.
    #[test]
    fn settings_are_written_with_their_shortest_numbers() {
        let settings = crate::settings::RenderSettings {
            cutoff: 0.99,
            ..Default::default()
        };
        let mut value = serde_json::to_value(&settings).unwrap();
        assert_eq!(value["cutoff"], serde_json::json!(0.9900000095367432));
        shortest_f32s(&mut value);
        assert_eq!(value["cutoff"], serde_json::json!(0.99));
        assert_eq!(value["phong"]["depth_kl"], serde_json::json!(0.002));
        let back: crate::settings::RenderSettings = serde_json::from_value(value).unwrap();
        assert_eq!(back, settings);
        let mut other = serde_json::json!([3, 0.1, 1e300, -2.5]);
        shortest_f32s(&mut other);
        assert_eq!(other, serde_json::json!([3, 0.1, 1e300, -2.5]));
    }
}
