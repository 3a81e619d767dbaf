//! The structure docs/ARCHITECTURE.md promises: no cycle between the modules of either crate (read
//! from the `crate::` and `super::` paths of every source file, comments and test modules left
//! out), and no source file over 700 lines.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Every `.rs` file below `dir`.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The module path of a file of a crate whose root is `src/lib.rs`.
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap().with_extension("");
    let mut parts: Vec<String> = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
    if parts.last().is_some_and(|p| p == "mod" || p == "lib") {
        parts.pop();
    }
    parts
}

/// The code of a file without comments and without its test module (which comes last).
fn code(text: &str) -> String {
    let end = text.find("#[cfg(test)]\nmod ").unwrap_or(text.len());
    text[..end].lines().map(|l| l.find("//").map_or(l, |i| &l[..i])).collect::<Vec<_>>().join("\n")
}

/// The paths a `crate::` or `super::` prefix leads to at `rest`: `a::b::C`, or a group `{a::B, c}`.
fn paths(rest: &str) -> Vec<Vec<String>> {
    let ident = |s: &str| s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').count();
    let mut out = Vec::new();
    let mut at = 0;
    let mut prefix = Vec::new();
    loop {
        let s = &rest[at..];
        if let Some(group) = s.strip_prefix('{') {
            // Split the group at its top-level commas.
            let (mut depth, mut start) = (0, 0);
            for (i, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        out.extend(paths(group[start..i].trim()).into_iter().map(|p| [prefix.clone(), p].concat()));
                        return out;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        out.extend(paths(group[start..i].trim()).into_iter().map(|p| [prefix.clone(), p].concat()));
                        start = i + 1;
                    }
                    _ => {}
                }
            }
            return out;
        }
        let n = ident(s);
        if n == 0 {
            break;
        }
        prefix.push(s[..n].to_string());
        at += n;
        if !rest[at..].starts_with("::") {
            break;
        }
        at += 2;
    }
    if !prefix.is_empty() {
        out.push(prefix);
    }
    out
}

/// Per module of the crate rooted at `src`, the modules it uses.
fn use_graph(src: &Path) -> BTreeMap<Vec<String>, BTreeSet<Vec<String>>> {
    let files = rust_files(src);
    let modules: BTreeSet<Vec<String>> = files.iter().map(|f| module_of(src, f)).collect();
    let resolve = |path: Vec<String>| -> Vec<String> {
        (0..=path.len()).rev().map(|n| path[..n].to_vec()).find(|p| modules.contains(p)).unwrap_or_default()
    };
    let mut graph = BTreeMap::new();
    for file in &files {
        if file.file_name().is_some_and(|n| n == "main.rs") {
            continue;
        }
        let here = module_of(src, file);
        let is_dir_module = file.file_name().is_some_and(|n| n == "mod.rs" || n == "lib.rs");
        let text = code(&std::fs::read_to_string(file).unwrap());
        let mut uses = BTreeSet::new();
        for (i, _) in text.match_indices("crate::") {
            if text[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_') {
                continue;
            }
            for p in paths(&text[i + 7..]) {
                uses.insert(resolve(p));
            }
        }
        for (i, _) in text.match_indices("super::") {
            if text[..i].ends_with(|c: char| c.is_alphanumeric() || c == '_' || c == ':') {
                continue;
            }
            // `super` of a file module is its parent; of a folder's mod.rs, the folder's parent.
            let mut base = here.clone();
            base.pop();
            let _ = is_dir_module;
            for p in paths(&text[i + 7..]) {
                let mut p = p;
                let mut base = base.clone();
                while p.first().is_some_and(|s| s == "super") {
                    p.remove(0);
                    base.pop();
                }
                uses.insert(resolve([base, p].concat()));
            }
        }
        uses.remove(&here);
        graph.insert(here, uses);
    }
    graph
}

/// The strongly connected components of more than one module (Tarjan).
fn cycles(graph: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>) -> Vec<Vec<String>> {
    let names: Vec<&Vec<String>> = graph.keys().collect();
    let index_of: BTreeMap<&Vec<String>, usize> = names.iter().enumerate().map(|(i, n)| (*n, i)).collect();
    let edges: Vec<Vec<usize>> =
        names.iter().map(|n| graph[*n].iter().filter_map(|m| index_of.get(m).copied()).collect()).collect();
    struct State {
        index: Vec<Option<usize>>,
        low: Vec<usize>,
        on_stack: Vec<bool>,
        stack: Vec<usize>,
        next: usize,
        found: Vec<Vec<usize>>,
    }
    fn visit(v: usize, edges: &[Vec<usize>], s: &mut State) {
        s.index[v] = Some(s.next);
        s.low[v] = s.next;
        s.next += 1;
        s.stack.push(v);
        s.on_stack[v] = true;
        for &w in &edges[v] {
            match s.index[w] {
                None => {
                    visit(w, edges, s);
                    s.low[v] = s.low[v].min(s.low[w]);
                }
                Some(i) if s.on_stack[w] => s.low[v] = s.low[v].min(i),
                _ => {}
            }
        }
        if Some(s.low[v]) == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                s.on_stack[w] = false;
                component.push(w);
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                s.found.push(component);
            }
        }
    }
    let n = names.len();
    let mut s = State {
        index: vec![None; n],
        low: vec![0; n],
        on_stack: vec![false; n],
        stack: vec![],
        next: 0,
        found: vec![],
    };
    for v in 0..n {
        if s.index[v].is_none() {
            visit(v, &edges, &mut s);
        }
    }
    let name = |i: usize| if names[i].is_empty() { "crate".to_string() } else { names[i].join("::") };
    s.found.into_iter().map(|c| c.into_iter().map(name).collect()).collect()
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

#[test]
fn no_module_cycles_in_either_crate() {
    for src in ["src", "ui/src"] {
        let graph = use_graph(&repo().join(src));
        assert!(graph.len() > 5, "{src}: only {} modules found", graph.len());
        let found = cycles(&graph);
        assert!(found.is_empty(), "{src}: modules that use each other in a cycle: {found:?}");
    }
}

#[test]
fn the_cycle_check_can_fail() {
    let graph: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = [
        (vec!["a".to_string()], BTreeSet::from([vec!["b".to_string()]])),
        (vec!["b".to_string()], BTreeSet::from([vec!["a".to_string()]])),
        (vec!["c".to_string()], BTreeSet::from([vec!["a".to_string()]])),
    ]
    .into();
    assert_eq!(cycles(&graph).len(), 1);
    assert_eq!(paths("{a::B, c::{d, e}}, x"), vec![vec!["a", "B"], vec!["c", "d"], vec!["c", "e"]]);
}

#[test]
fn no_source_file_over_700_lines() {
    for dir in ["src", "ui/src", "tests", "ui/tests"] {
        for file in rust_files(&repo().join(dir)) {
            let lines = std::fs::read_to_string(&file).unwrap().lines().count();
            assert!(lines <= 700, "{}: {lines} lines (at most 700)", file.display());
        }
    }
}

/// What each of the viewer's components uses of the others (docs/ARCHITECTURE.md: components
/// depend on the shared modules only; `app` and `window` compose them; a component's parts are
/// modules of its own, such as `viewport::motion`).
fn component_uses(graph: &BTreeMap<Vec<String>, BTreeSet<Vec<String>>>) -> Vec<(String, String)> {
    const SHARED: [&str; 7] = ["action", "scene", "settings", "shortcuts", "widgets", "jobs", "paths"];
    let viewer = |m: &Vec<String>| (m.len() >= 2 && m[0] == "viewer").then(|| m[1].clone());
    let component = |name: &str| !["app", "window"].contains(&name) && !SHARED.contains(&name);
    let mut out = Vec::new();
    for (module, uses) in graph {
        let Some(from) = viewer(module).filter(|n| component(n)) else { continue };
        for to in uses.iter().filter_map(viewer).filter(|n| component(n) && *n != from) {
            out.push((from.clone(), to));
        }
    }
    out
}

#[test]
fn viewer_components_use_only_the_shared_modules() {
    let graph = use_graph(&repo().join("ui/src"));
    let uses = component_uses(&graph);
    assert!(uses.is_empty(), "viewer components that use other components: {uses:?}");
    // The rule can fail: a component that uses another is reported.
    let mut broken = graph.clone();
    broken.entry(vec!["viewer".into(), "status".into()]).or_default().insert(vec!["viewer".into(), "viewport".into()]);
    assert_eq!(component_uses(&broken), [("status".to_string(), "viewport".to_string())]);
}
