//! The sandbox's layers, drawn from its own paths: every path a file of `src/sandbox` writes to
//! another (`crate::sandbox::…`, `super::…`) must lead to its own folder or a folder below it
//! (the order `src/sandbox/mod.rs` gives), and no files may import each other in a circle.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The sandbox's folders, bottom to top, as `src/sandbox/mod.rs` lists them.
const LAYERS: [&str; 10] = [
    "shared", "gpu", "scene", "inspect", "data", "preview", "checks", "levels", "drivers", "ui",
];

fn sandbox_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src/sandbox")
}

/// Every `.rs` file below `dir`, as its module path below the sandbox (`["preview", "live"]`).
fn modules(dir: &Path, prefix: &[String], out: &mut BTreeMap<Vec<String>, PathBuf>) {
    let mut entries: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for path in entries {
        let name = path.file_stem().unwrap().to_string_lossy().into_owned();
        if path.is_dir() {
            let mut p = prefix.to_vec();
            p.push(name);
            modules(&path, &p, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            let mut p = prefix.to_vec();
            if name != "mod" {
                p.push(name);
            }
            out.insert(p, path);
        }
    }
}

/// The sandbox-relative paths a file's code names (comments left out): each resolved against
/// the file's module, `super` by `super`, and cut at the longest prefix that is a file.
fn targets(
    source: &str,
    module: &[String],
    files: &BTreeMap<Vec<String>, PathBuf>,
) -> BTreeSet<Vec<String>> {
    let mut found = BTreeSet::new();
    let mut inline = 0usize;
    for line in source.lines() {
        let code = line.trim_start();
        if code.starts_with("//") {
            continue;
        }
        let opens_inline = {
            let words: Vec<&str> = code.split_whitespace().collect();
            let at = words.iter().position(|w| *w == "mod");
            at.is_some_and(|i| words.get(i + 2) == Some(&"{"))
        };
        if opens_inline {
            inline += 1;
            continue;
        }
        let mut scope: Vec<String> = module.to_vec();
        scope.extend(std::iter::repeat_n("<inline>".to_string(), inline));
        for (start, _) in line
            .match_indices("crate::sandbox")
            .chain(line.match_indices("super::"))
        {
            // Only where a path starts (not the `super::` inside `super::super::`).
            let before = line[..start].chars().last();
            if before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            let path: String = line[start..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':' || *c == '{')
                .collect();
            let mut segs: Vec<&str> = path.split("::").collect();
            let mut base: Vec<String> = if segs[0] == "crate" {
                segs.drain(..2);
                Vec::new()
            } else {
                let ups = segs.iter().take_while(|s| **s == "super").count();
                segs.drain(..ups);
                if ups > scope.len() {
                    continue;
                }
                scope[..scope.len() - ups].to_vec()
            };
            // A group (`{a, b::c}`): its first member is enough to find the file it lies in
            // when the group sits below a file; at a folder, each member is read.
            let mut members = vec![Vec::new()];
            for s in segs {
                if let Some(rest) = s.strip_prefix('{') {
                    let group = &line[line.find(&path).unwrap() + path.len() - rest.len() - 1..];
                    let group = group[1..group.find('}').unwrap_or(group.len())].to_string();
                    members = group
                        .split(',')
                        .map(|m| {
                            m.trim()
                                .split("::")
                                .map(|x| x.split_whitespace().next().unwrap_or("").to_string())
                                .collect()
                        })
                        .collect();
                    break;
                }
                base.push(s.to_string());
            }
            for member in members {
                let mut full = base.clone();
                full.extend(member);
                while !full.is_empty() && !files.contains_key(&full) {
                    full.pop();
                }
                if !full.iter().any(|s| s == "<inline>") {
                    found.insert(full);
                }
            }
        }
    }
    found
}

fn layer_of(module: &[String]) -> Option<usize> {
    let top = module.first()?;
    LAYERS.iter().position(|l| l == top)
}

/// Tarjan's strongly connected components: the circles among the files.
fn circles(graph: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>) -> Vec<Vec<Vec<String>>> {
    struct State<'a> {
        graph: &'a BTreeMap<Vec<String>, BTreeSet<Vec<String>>>,
        index: BTreeMap<&'a Vec<String>, usize>,
        low: BTreeMap<&'a Vec<String>, usize>,
        stack: Vec<&'a Vec<String>>,
        on: BTreeSet<&'a Vec<String>>,
        out: Vec<Vec<Vec<String>>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a Vec<String>) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on.insert(v);
        for w in s.graph.get(v).into_iter().flatten() {
            let Some((w, _)) = s.graph.get_key_value(w) else {
                continue;
            };
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.on.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = s.stack.pop().unwrap();
                s.on.remove(w);
                comp.push(w.clone());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                s.out.push(comp);
            }
        }
    }
    let mut s = State {
        graph,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in graph.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out
}

/// The import graph: each file's paths to other files, less those to its own ancestors (a
/// child module sees its parent: `use super::*` in a test).
fn graph() -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
    let mut files = BTreeMap::new();
    modules(&sandbox_dir(), &[], &mut files);
    files
        .iter()
        .map(|(module, path)| {
            let source = std::fs::read_to_string(path).unwrap();
            let edges = targets(&source, module, &files)
                .into_iter()
                .filter(|t| !module.starts_with(t))
                .collect();
            (module.clone(), edges)
        })
        .collect()
}

fn name(module: &[String]) -> String {
    if module.is_empty() {
        "mod.rs (the root)".into()
    } else {
        module.join("/")
    }
}

#[test]
fn every_folder_imports_only_its_own_and_those_below() {
    let graph = graph();
    assert!(graph.len() > 40, "the sandbox's files were not found");
    let mut upward = Vec::new();
    for (from, tos) in &graph {
        if from.is_empty() {
            continue; // the root builds the app from every layer
        }
        let Some(lf) = layer_of(from) else {
            upward.push(format!("{} lies in no layer", name(from)));
            continue;
        };
        for to in tos {
            match layer_of(to) {
                Some(lt) if lt <= lf => {}
                _ => upward.push(format!("{} imports {}", name(from), name(to))),
            }
        }
    }
    assert!(
        upward.is_empty(),
        "imports running upward:\n{}",
        upward.join("\n")
    );
}

#[test]
fn no_files_import_each_other_in_a_circle() {
    let found = circles(&graph());
    let words: Vec<String> = found
        .iter()
        .map(|c| c.iter().map(|m| name(m)).collect::<Vec<_>>().join(", "))
        .collect();
    assert!(words.is_empty(), "circles:\n{}", words.join("\n"));
}

/// The checks can fail: a path upward and a circle are found in a made-up pair of files.
#[test]
fn the_checks_see_an_upward_path_and_a_circle() {
    let mut files = BTreeMap::new();
    for m in [vec!["shared", "state"], vec!["ui", "panel"]] {
        files.insert(m.iter().map(|s| s.to_string()).collect(), PathBuf::new());
    }
    let state: Vec<String> = vec!["shared".into(), "state".into()];
    let panel: Vec<String> = vec!["ui".into(), "panel".into()];
    let up = targets(
        "use crate::sandbox::ui::panel::{Panel, draw};\n",
        &state,
        &files,
    );
    assert_eq!(up, BTreeSet::from([panel.clone()]));
    assert!(layer_of(&panel) > layer_of(&state));
    let back = targets(
        "    let x = super::super::shared::state::VolumeState;\n",
        &panel,
        &files,
    );
    assert_eq!(back, BTreeSet::from([state.clone()]));
    let graph = BTreeMap::from([(state.clone(), up), (panel.clone(), back)]);
    assert_eq!(circles(&graph).len(), 1);
    // Comments are not imports.
    let none = targets("//! see [`crate::sandbox::ui::panel`]\n", &state, &files);
    assert!(none.is_empty());
}
