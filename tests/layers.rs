//! The sandbox's layers, drawn from its own paths: every path a file of `src/sandbox` writes to
//! another (`crate::sandbox::…`, `super::…`) must lead to its own folder or a folder below it
//! (the order `src/sandbox/mod.rs` gives), and no files may import each other in a circle.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The sandbox's folders, bottom to top, as `src/sandbox/mod.rs` lists them.
const LAYERS: [&str; 11] = [
    "shared", "gpu", "scene", "inspect", "data", "preview", "checks", "levels", "drivers", "ui",
    "app",
];

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

/// How a tree of files is read: the path its files write to one another from the crate's root
/// (`crate::sandbox`, `crate`), and whether test code counts.
struct Tree {
    prefix: &'static str,
    with_tests: bool,
}

/// The paths a file's code names to other files of its tree (comments left out): each resolved
/// against the file's module, `super` by `super` (or a child's name), and cut at the longest
/// prefix that is a file.
fn targets(
    tree: &Tree,
    source: &str,
    module: &[String],
    files: &BTreeMap<Vec<String>, PathBuf>,
) -> BTreeSet<Vec<String>> {
    let mut found = BTreeSet::new();
    let mut inline = 0usize;
    let mut last_code = "";
    let prefix_segs = tree.prefix.split("::").count();
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
            if !tree.with_tests && last_code == "#[cfg(test)]" {
                break;
            }
            inline += 1;
            continue;
        }
        if !code.is_empty() {
            last_code = code.trim_end();
        }
        let mut scope: Vec<String> = module.to_vec();
        scope.extend(std::iter::repeat_n("<inline>".to_string(), inline));
        for (start, _) in line.match_indices("::") {
            // Where a path starts: the run of names and `::` this `::` belongs to.
            let begin = line[..start]
                .rfind(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .map_or(0, |i| i + 1);
            if line[begin..start].contains("::") {
                continue; // not the path's first `::`
            }
            let path: String = line[begin..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':' || *c == '{')
                .collect();
            let mut segs: Vec<&str> = path.split("::").collect();
            let head = segs[0];
            let mut base: Vec<String> = if path.starts_with(&format!("{}::", tree.prefix)) {
                segs.drain(..prefix_segs);
                Vec::new()
            } else if head == "super" {
                let ups = segs.iter().take_while(|s| **s == "super").count();
                segs.drain(..ups);
                if ups > scope.len() {
                    continue;
                }
                scope[..scope.len() - ups].to_vec()
            } else if inline == 0 && files.contains_key(&[module, &[head.to_string()]].concat()) {
                module.to_vec() // a child of this file's module, by its name
            } else {
                continue;
            };
            // A group (`{a, b::c}`): each member is read.
            let mut members = vec![Vec::new()];
            for s in segs {
                if let Some(rest) = s.strip_prefix('{') {
                    let group = &line[begin + path.len() - rest.len() - 1..];
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

/// The sandbox, test code included.
const SANDBOX: (&str, Tree) = (
    "src/sandbox",
    Tree {
        prefix: "crate::sandbox",
        with_tests: true,
    },
);

/// The import graph of the files below `dir`: each file's paths to other files, less those to
/// its own ancestors (a child module sees its parent: `use super::*` in a test). Without test
/// code, a module named `tests` is left out too.
fn graph((dir, tree): &(&str, Tree)) -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
    let mut files = BTreeMap::new();
    modules(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join(dir),
        &[],
        &mut files,
    );
    files
        .iter()
        .filter(|(module, _)| tree.with_tests || !module.iter().any(|m| m == "tests"))
        .map(|(module, path)| {
            let source = std::fs::read_to_string(path).unwrap();
            let edges = targets(tree, &source, module, &files)
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
    let graph = graph(&SANDBOX);
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

/// The circles among a tree's files, in words (none: empty).
fn circles_in(tree: &(&str, Tree)) -> Vec<String> {
    circles(&graph(tree))
        .iter()
        .map(|c| c.iter().map(|m| name(m)).collect::<Vec<_>>().join(", "))
        .collect()
}

#[test]
fn no_files_of_the_sandbox_import_each_other_in_a_circle() {
    let found = circles_in(&SANDBOX);
    assert!(found.is_empty(), "circles:\n{}", found.join("\n"));
}

/// The core and the command line: no circle among their files' own code (a test may use what
/// lies above the code it tests).
#[test]
fn no_files_of_the_core_or_the_command_line_import_each_other_in_a_circle() {
    let core = (
        "crates/voxcast_core/src",
        Tree {
            prefix: "crate",
            with_tests: false,
        },
    );
    let cli = (
        "src/cli",
        Tree {
            prefix: "crate::cli",
            with_tests: false,
        },
    );
    for tree in [core, cli] {
        assert!(graph(&tree).len() > 10, "{}: no files found", tree.0);
        let found = circles_in(&tree);
        assert!(
            found.is_empty(),
            "{}: circles:\n{}",
            tree.0,
            found.join("\n")
        );
    }
}

/// The checks can fail: a path upward and a circle are found in a made-up pair of files, a
/// child named by its name, and test code only where it counts.
#[test]
fn the_checks_see_an_upward_path_and_a_circle() {
    let mut files = BTreeMap::new();
    for m in [
        vec!["shared", "state"],
        vec!["ui", "panel"],
        vec!["ui", "panel", "parts"],
    ] {
        files.insert(m.iter().map(|s| s.to_string()).collect(), PathBuf::new());
    }
    let module = |m: &[&str]| -> Vec<String> { m.iter().map(|s| s.to_string()).collect() };
    let (state, panel, parts) = (
        module(&["shared", "state"]),
        module(&["ui", "panel"]),
        module(&["ui", "panel", "parts"]),
    );
    let sandbox = &SANDBOX.1;
    let up = targets(
        sandbox,
        "use crate::sandbox::ui::panel::{Panel, draw};\n",
        &state,
        &files,
    );
    assert_eq!(up, BTreeSet::from([panel.clone()]));
    assert!(layer_of(&panel) > layer_of(&state));
    let back = targets(
        sandbox,
        "    let x = super::super::shared::state::VolumeState;\n",
        &panel,
        &files,
    );
    assert_eq!(back, BTreeSet::from([state.clone()]));
    let graph = BTreeMap::from([(state.clone(), up), (panel.clone(), back)]);
    assert_eq!(circles(&graph).len(), 1);
    // Comments are not imports; a child is found by its name.
    let none = targets(
        sandbox,
        "//! see [`crate::sandbox::ui::panel`]\n",
        &state,
        &files,
    );
    assert!(none.is_empty());
    let child = targets(sandbox, "    parts::draw(ui);\n", &panel, &files);
    assert_eq!(child, BTreeSet::from([parts]));
    // Test code counts only where the tree says so.
    let test = "#[cfg(test)]\nmod tests {\n    use crate::sandbox::ui::panel::Panel;\n}\n";
    assert_eq!(targets(sandbox, test, &state, &files).len(), 1);
    let without = Tree {
        prefix: "crate::sandbox",
        with_tests: false,
    };
    assert!(targets(&without, test, &state, &files).is_empty());
}
