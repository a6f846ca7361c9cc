//! The documented architecture is the real one:
//!
//! - the crate dependency table of `docs/ARCHITECTURE.md` lists exactly the workspace
//!   dependencies that `cargo metadata` reports (normal dependencies between workspace
//!   members; dev-dependencies are left out);
//! - inside every crate of `crates/`, the top-level modules import each other one way
//!   (no cycle), so that a reader can follow a crate from the top down.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `crate → its workspace dependencies`, from `cargo metadata`.
fn metadata_graph() -> BTreeMap<String, BTreeSet<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .args(["metadata", "--no-deps", "--format-version", "1", "--offline"])
        .current_dir(workspace_root())
        .output()
        .expect("cargo metadata runs");
    assert!(output.status.success(), "cargo metadata: {}", String::from_utf8_lossy(&output.stderr));
    let metadata: serde_json::Value = serde_json::from_slice(&output.stdout).expect("cargo metadata prints JSON");
    let packages = metadata["packages"].as_array().expect("packages");
    let names: BTreeSet<String> = packages.iter().map(|p| p["name"].as_str().unwrap().to_owned()).collect();
    packages
        .iter()
        .map(|package| {
            let dependencies = package["dependencies"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|d| d["kind"].is_null())
                .map(|d| d["name"].as_str().unwrap().to_owned())
                .filter(|name| names.contains(name))
                .collect();
            (package["name"].as_str().unwrap().to_owned(), dependencies)
        })
        .collect()
}

/// The table between `<!-- dependencies: begin -->` and `<!-- dependencies: end -->`:
/// lines `crate → dep, dep` (`—` for none).
fn documented_graph(text: &str) -> BTreeMap<String, BTreeSet<String>> {
    let begin = text.find("<!-- dependencies: begin -->").expect("ARCHITECTURE.md marks its dependency table");
    let end = text.find("<!-- dependencies: end -->").expect("ARCHITECTURE.md ends its dependency table");
    text[begin..end]
        .lines()
        .filter_map(|line| line.split_once('→'))
        .map(|(name, deps)| {
            let deps = deps.split(',').map(str::trim).filter(|d| !d.is_empty() && *d != "—").map(str::to_owned);
            (name.trim().to_owned(), deps.collect())
        })
        .collect()
}

fn format_graph(graph: &BTreeMap<String, BTreeSet<String>>) -> String {
    let width = graph.keys().map(String::len).max().unwrap_or(0);
    let mut out = String::new();
    for (name, deps) in graph {
        let list: Vec<&str> = deps.iter().map(String::as_str).collect();
        let deps = if list.is_empty() { "—".to_owned() } else { list.join(", ") };
        out.push_str(&format!("{name:width$} → {deps}\n"));
    }
    out
}

#[test]
fn architecture_lists_the_real_crate_dependencies() {
    let path = workspace_root().join("docs/ARCHITECTURE.md");
    let text = std::fs::read_to_string(&path).expect("docs/ARCHITECTURE.md");
    let documented = documented_graph(&text);
    let real = metadata_graph();
    assert!(real.len() >= 20, "cargo metadata lists {} packages", real.len());
    assert_eq!(
        documented,
        real,
        "docs/ARCHITECTURE.md's dependency table differs from cargo metadata; the real one is:\n{}",
        format_graph(&real)
    );
}

/// `source` without comments (`//` to the end of the line, `/* */`) and without what
/// follows the first `#[cfg(test)]` (the crate's convention: test modules come last).
fn code_of(source: &str) -> String {
    let source = source.find("#[cfg(test)]").map_or(source, |i| &source[..i]);
    let mut out = String::with_capacity(source.len());
    let mut rest = source;
    loop {
        let line = rest.find("//");
        let block = rest.find("/*");
        match (line, block) {
            (None, None) => {
                out.push_str(rest);
                return out;
            }
            (Some(l), b) if b.is_none_or(|b| l < b) => {
                out.push_str(&rest[..l]);
                rest = rest[l..].find('\n').map_or("", |e| &rest[l + e..]);
            }
            (_, Some(b)) => {
                out.push_str(&rest[..b]);
                rest = rest[b + 2..].find("*/").map_or("", |e| &rest[b + 2 + e + 2..]);
            }
            _ => unreachable!("one of the two was found"),
        }
    }
}

/// The first identifiers after `crate::` in `code`, through `crate::{a, b::c}` groups too.
fn crate_paths(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let ident = |s: &str| s.chars().take_while(|c| c.is_alphanumeric() || *c == '_').collect::<String>();
    for (i, _) in code.match_indices("crate::") {
        let after = &code[i + "crate::".len()..];
        if let Some(group) = after.strip_prefix('{') {
            // The top-level items of the group: split at depth-0 commas.
            let mut depth = 0;
            let mut start = 0;
            for (j, c) in group.char_indices() {
                match c {
                    '{' => depth += 1,
                    '}' if depth == 0 => {
                        out.insert(ident(group[start..j].trim()));
                        break;
                    }
                    '}' => depth -= 1,
                    ',' if depth == 0 => {
                        out.insert(ident(group[start..j].trim()));
                        start = j + 1;
                    }
                    _ => {}
                }
            }
        } else {
            out.insert(ident(after));
        }
    }
    out.remove("");
    out
}

/// The module that defines each name `lib.rs` re-exports (`pub use module::{A, B};`).
fn root_reexports(lib: &str) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    for statement in lib.split(';') {
        let Some(at) = statement.find("pub use ") else { continue };
        let path = statement[at + "pub use ".len()..].trim();
        let Some((module, names)) = path.split_once("::") else { continue };
        let names = names.trim().trim_start_matches('{').trim_end_matches('}');
        for name in names.split(',') {
            let name = name.trim().rsplit("::").next().unwrap_or("").trim();
            if !name.is_empty() {
                out.insert(name.to_owned(), module.trim().to_owned());
            }
        }
    }
    out
}

/// Strongly connected components with more than one module (Tarjan).
fn cycles(graph: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct State<'a> {
        graph: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, usize>,
        low: BTreeMap<&'a str, usize>,
        stack: Vec<&'a str>,
        next: usize,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(s: &mut State<'a>, v: &'a str) {
        s.index.insert(v, s.next);
        s.low.insert(v, s.next);
        s.next += 1;
        s.stack.push(v);
        for w in s.graph.get(v).into_iter().flatten() {
            let w = w.as_str();
            if !s.index.contains_key(w) {
                visit(s, w);
                let low = s.low[v].min(s.low[w]);
                s.low.insert(v, low);
            } else if s.stack.contains(&w) {
                let low = s.low[v].min(s.index[w]);
                s.low.insert(v, low);
            }
        }
        if s.low[v] == s.index[v] {
            let mut component = Vec::new();
            while let Some(w) = s.stack.pop() {
                component.push(w.to_owned());
                if w == v {
                    break;
                }
            }
            if component.len() > 1 {
                s.found.push(component);
            }
        }
    }
    let mut state =
        State { graph, index: BTreeMap::new(), low: BTreeMap::new(), stack: Vec::new(), next: 0, found: Vec::new() };
    for v in graph.keys() {
        if !state.index.contains_key(v.as_str()) {
            visit(&mut state, v);
        }
    }
    state.found
}

/// `top-level module → modules it imports` of one crate's `src/`.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap_or_default();
    let reexports = root_reexports(&code_of(&lib));
    let mut files = vec![src.to_path_buf()];
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    while let Some(path) = files.pop() {
        if path.is_dir() {
            files.extend(std::fs::read_dir(&path).unwrap().map(|e| e.unwrap().path()));
            continue;
        }
        // `lib.rs` only declares and re-exports; a `tests.rs` file is a `#[cfg(test)]` module.
        if path.extension().is_none_or(|e| e != "rs")
            || path.file_name().is_some_and(|n| n == "lib.rs" || n == "tests.rs")
        {
            continue;
        }
        let relative = path.strip_prefix(src).unwrap();
        let first = relative.components().next().unwrap().as_os_str().to_string_lossy().into_owned();
        let module = first.trim_end_matches(".rs").to_owned();
        let code = code_of(&std::fs::read_to_string(&path).unwrap());
        let targets = graph.entry(module.clone()).or_default();
        for name in crate_paths(&code) {
            let target = reexports.get(&name).cloned().unwrap_or(name);
            if target != module {
                targets.insert(target);
            }
        }
    }
    let modules: BTreeSet<String> = graph.keys().cloned().collect();
    for targets in graph.values_mut() {
        targets.retain(|t| modules.contains(t));
    }
    graph
}

#[test]
fn modules_of_every_crate_import_one_way() {
    let mut checked = 0;
    let mut problems = Vec::new();
    for entry in std::fs::read_dir(workspace_root().join("crates")).unwrap().map(Result::unwrap) {
        let src = entry.path().join("src");
        if !src.join("lib.rs").exists() {
            continue;
        }
        let graph = module_graph(&src);
        checked += 1;
        for cycle in cycles(&graph) {
            problems.push(format!("{}: {}", entry.file_name().to_string_lossy(), cycle.join(" ↔ ")));
        }
    }
    assert!(checked >= 15, "checked {checked} crates");
    assert!(
        problems.is_empty(),
        "modules that import each other (split out what they share):\n{}",
        problems.join("\n")
    );
}

#[test]
fn the_module_check_finds_a_cycle() {
    let code = "use crate::b::X;\nfn f() { crate::{c::Y, d}; } // crate::e\n#[cfg(test)] use crate::f;";
    assert_eq!(crate_paths(&code_of(code)), ["b", "c", "d"].map(String::from).into());
    let mut graph = BTreeMap::new();
    graph.insert("a".to_owned(), BTreeSet::from(["b".to_owned()]));
    graph.insert("b".to_owned(), BTreeSet::from(["c".to_owned()]));
    graph.insert("c".to_owned(), BTreeSet::from(["a".to_owned()]));
    graph.insert("d".to_owned(), BTreeSet::from(["a".to_owned()]));
    let found = cycles(&graph);
    assert_eq!(found.len(), 1);
    assert_eq!(
        found[0].iter().collect::<BTreeSet<_>>(),
        ["a", "b", "c"].iter().map(|s| s.to_string()).collect::<BTreeSet<_>>().iter().collect()
    );
    assert_eq!(
        root_reexports("pub use mesh::{GrainMesh, area};\npub use error::MeshError;")
            .get("MeshError")
            .map(String::as_str),
        Some("error")
    );
}
