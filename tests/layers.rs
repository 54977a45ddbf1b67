//! The workspace's layering, read from the source: no import circles between the files of a
//! crate, and crates depend on each other only downwards (docs/design.md, "Layers"); and,
//! read from the manifests too, every crate of the workspace in the test profile's list of
//! crates built at opt-level 1 (docs/performance.md, "What a newcomer waits for").
//!
//! A file `a` imports file `b` when `a` names a path `crate::…`, `super::…` or `self::…`
//! that resolves to a module defined in `b` (the longest module prefix of the path that is a
//! file; a name re-exported by `lib.rs` resolves to `lib.rs`). Comments and strings are
//! skipped. `mod x;` declarations are not imports.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The crates from the bottom up: a crate may depend only on crates before it.
const LAYERS: &[&[&str]] = &[
    &["rsf-numeric", "rsf-linalg", "rsf-metis"],
    // Processes that share work (rsf-ranks: the transport and the distributed linear
    // algebra over rsf-linalg's matrices) sit beside the finite elements and the solvers'
    // interface, below TNNMG and rsf (docs/design.md, "Layers").
    &[
        "rsf-ranks",
        "rsf-fem",
        "rsf-friction",
        "rsf-state",
        "rsf-nonsmooth",
        "rsf-hmatrix",
        "rsf-time",
    ],
    // The two solvers of the velocity problem are siblings: each depends on its interface
    // (rsf-nonsmooth), neither on the other (docs/design.md, "Layers").
    &["rsf-tnnmg", "rsf-direct"],
    // The half-space solution compresses its operator with rsf-hmatrix; rsf uses it behind
    // its feature `halfspace` (docs/design.md).
    &["rsf-halfspace"],
    &["rsf"],
    // The SEAS output files: observers of rsf, set up by the scenes (docs/design.md).
    &["rsf-seas"],
    &["rsf-scenes"],
    // The programs (flags, run folders, the guard, figures), over the scenes.
    &["rsf-programs"],
    // Outside the default build (HDF5, MPI); they run the programs of rsf-programs, the
    // MPI programs with rsf-hdf5's writers behind their feature `hdf5`.
    &["rsf-hdf5"],
    &["rsf-mpi"],
    // Outside the default build: the Python package, over the crates above (rsf-hdf5 behind
    // its feature `hdf5`).
    &["rsf-python"],
];

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let p = entry.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

/// The module path of a source file relative to `src/` (`lib.rs` → [], `a/mod.rs` → [a],
/// `a/b.rs` → [a, b]).
fn module_of(src: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(src).unwrap();
    let mut parts: Vec<String> = rel
        .iter()
        .map(|c| c.to_string_lossy().into_owned())
        .collect();
    let last = parts.pop().unwrap();
    match last.as_str() {
        "lib.rs" | "mod.rs" => {}
        name => parts.push(name.trim_end_matches(".rs").to_owned()),
    }
    parts
}

/// The code of a file without comments, string and char literals.
fn code_only(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if b[i] == b'/' && b.get(i + 1) == Some(&b'*') {
            i += 2;
            while i + 1 < b.len() && !(b[i] == b'*' && b[i + 1] == b'/') {
                i += 1;
            }
            i += 2;
        } else if b[i] == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            i += 1;
            out.push_str("\"\"");
        } else if b[i] == b'r' && b.get(i + 1) == Some(&b'#') {
            // raw strings r#"…"#
            let mut j = i + 1;
            let mut hashes = 0;
            while b.get(j) == Some(&b'#') {
                hashes += 1;
                j += 1;
            }
            if b.get(j) == Some(&b'"') {
                let close: Vec<u8> = std::iter::once(b'"')
                    .chain(std::iter::repeat_n(b'#', hashes))
                    .collect();
                j += 1;
                while j < b.len() && !b[j..].starts_with(&close) {
                    j += 1;
                }
                i = j + close.len();
                out.push_str("\"\"");
            } else {
                out.push(b[i] as char);
                i += 1;
            }
        } else {
            let ch = text[i..].chars().next().unwrap();
            out.push(ch);
            i += ch.len_utf8();
        }
    }
    out
}

/// The module paths named by `use` trees and inline paths of `code`, in module `here`.
fn named_paths(
    code: &str,
    here: &[String],
    modules: &BTreeMap<Vec<String>, String>,
) -> Vec<Vec<String>> {
    // Expand `use a::{b, c::{d, e}}` into flat paths; inline paths are taken as they are.
    let mut paths = Vec::new();
    for (p, inline) in expand_use_trees(code) {
        // Inside inline modules the paths are relative to them; they resolve to this file
        // as long as they stay inside it.
        let scoped: Vec<String> = here.iter().cloned().chain(inline.iter().cloned()).collect();
        let here = &scoped[..];
        let segs: Vec<&str> = p.split("::").map(str::trim).collect();
        let (base, rest): (Vec<String>, &[&str]) = match segs.first().copied() {
            Some("crate") => (Vec::new(), &segs[1..]),
            Some("self") => (here.to_vec(), &segs[1..]),
            Some("super") => {
                // `here` is the file's module (for `a/mod.rs` and `a/b.rs` alike); each
                // `super` goes one up.
                let mut base = here.to_vec();
                let mut k = 0;
                while segs.get(k) == Some(&"super") {
                    base.pop();
                    k += 1;
                }
                (base, &segs[k..])
            }
            // A path relative to this module through one of its child modules (`use
            // a::b;` in the parent of `a`).
            Some(first) if modules.contains_key(&[here, &[first.to_owned()]].concat()) => {
                (here.to_vec(), &segs[..])
            }
            _ => continue,
        };
        let mut full = base;
        full.extend(
            rest.iter()
                .take_while(|s| !s.is_empty() && *s != &"*" && *s != &"self")
                .map(|s| s.to_string()),
        );
        paths.push(full);
    }
    paths
}

/// Flattens `use` trees and collects inline `crate::`/`super::`/`self::` paths, each with
/// the inline modules (`mod x { … }`) it sits in. Test modules (`#[cfg(test)] mod x { … }`)
/// are skipped: they are no part of the library's structure.
fn expand_use_trees(code: &str) -> Vec<(String, Vec<String>)> {
    let mut out = Vec::new();
    let bytes = code.as_bytes();
    let is_ident = |c: u8| c.is_ascii_alphanumeric() || c == b'_';
    let mut inline: Vec<(String, usize)> = Vec::new();
    let mut depth = 0usize;
    // Depth of the test module being skipped, if any.
    let mut in_test: Option<usize> = None;
    let mut i = 0;
    while i < bytes.len() {
        // Inside a multi-byte character (e.g. `…` in a string): not the start of a word.
        if !code.is_char_boundary(i) {
            i += 1;
            continue;
        }
        let rest = &code[i..];
        let word_start = i == 0 || !is_ident(bytes[i - 1]);
        let scope = || inline.iter().map(|(n, _)| n.clone()).collect::<Vec<_>>();
        if word_start && rest.starts_with("mod ") {
            let after = rest[4..].trim_start();
            let name: String = after
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect();
            if after[name.len()..].trim_start().starts_with('{') {
                let test = code[..i].trim_end().ends_with("#[cfg(test)]");
                if test && in_test.is_none() {
                    in_test = Some(depth + 1);
                }
                inline.push((name, depth + 1));
            }
            i += 4;
            continue;
        }
        // A test module's paths are passed over; only its braces count.
        let read_paths = word_start && in_test.is_none();
        if read_paths && rest.starts_with("use ") {
            let end = rest.find(';').unwrap_or(rest.len());
            let mut flat = Vec::new();
            flatten("", &rest[4..end], &mut flat);
            out.extend(flat.into_iter().map(|p| (p, scope())));
            i += end + 1;
            continue;
        }
        if read_paths
            && (rest.starts_with("crate::")
                || rest.starts_with("super::")
                || rest.starts_with("self::"))
        {
            let end = rest
                .find(|c: char| !(c.is_alphanumeric() || c == '_' || c == ':'))
                .unwrap_or(rest.len());
            out.push((rest[..end].trim_end_matches(':').to_owned(), scope()));
            i += end;
            continue;
        }
        match bytes[i] {
            b'{' => depth += 1,
            b'}' => {
                depth = depth.saturating_sub(1);
                while inline.last().is_some_and(|(_, d)| *d > depth) {
                    inline.pop();
                }
                if in_test.is_some_and(|d| d > depth) {
                    in_test = None;
                }
            }
            _ => {}
        }
        i += 1;
    }
    out
}

fn flatten(prefix: &str, tree: &str, out: &mut Vec<String>) {
    let tree = tree.trim();
    if let Some(open) = tree.find('{') {
        let head = tree[..open].trim().trim_end_matches("::");
        let inner = &tree[open + 1..tree.rfind('}').unwrap()];
        let prefix = join(prefix, head);
        let mut depth = 0;
        let mut start = 0;
        for (k, c) in inner.char_indices() {
            match c {
                '{' => depth += 1,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    flatten(&prefix, &inner[start..k], out);
                    start = k + 1;
                }
                _ => {}
            }
        }
        flatten(&prefix, &inner[start..], out);
    } else if !tree.is_empty() {
        let path = tree.split(" as ").next().unwrap().trim();
        out.push(join(prefix, path));
    }
}

fn join(a: &str, b: &str) -> String {
    match (a.is_empty(), b.is_empty()) {
        (true, _) => b.to_owned(),
        (_, true) => a.to_owned(),
        _ => format!("{a}::{b}"),
    }
}

/// The file-level import graph of one crate: file → files it imports. A module's `pub use`
/// lines (the facade of `lib.rs`, and of a `mod.rs` that re-exports its children's items
/// under the module's public path) are no imports: a re-export is a name, not a use of the
/// item's code. A name taken through a facade counts as taken from the module that defines
/// it (followed through chains of re-exports).
fn import_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let modules: BTreeMap<Vec<String>, String> = files
        .iter()
        .map(|f| {
            (
                module_of(src, f),
                f.strip_prefix(src).unwrap().display().to_string(),
            )
        })
        .collect();
    // Every file's re-exports: the public path of a name → the path of the item.
    let mut facade: BTreeMap<Vec<String>, Vec<String>> = BTreeMap::new();
    let mut code_of = BTreeMap::new();
    for f in &files {
        let here = module_of(src, f);
        let code = code_only(&std::fs::read_to_string(f).unwrap());
        let (reexports, rest): (Vec<&str>, Vec<&str>) = code
            .split_inclusive(';')
            .partition(|stmt| without_attributes(stmt).starts_with("pub use "));
        let reexports: String = reexports
            .iter()
            .map(|s| without_attributes(s).trim_start_matches("pub "))
            .collect();
        for item in named_paths(&reexports, &here, &modules) {
            if let Some(name) = item.last() {
                let key: Vec<String> = here.iter().chain([name]).cloned().collect();
                if key != item {
                    facade.insert(key, item);
                }
            }
        }
        code_of.insert(here, rest.concat());
    }
    let mut graph = BTreeMap::new();
    for f in &files {
        let here = module_of(src, f);
        let name = modules[&here].clone();
        let code = &code_of[&here];
        let mut targets = BTreeSet::new();
        for mut path in named_paths(code, &here, &modules) {
            // Through the facades to the defining module (a chain is at most a few long).
            for _ in 0..8 {
                let Some(k) = (1..=path.len())
                    .rev()
                    .find(|&k| facade.contains_key(&path[..k]))
                else {
                    break;
                };
                path = facade[&path[..k]]
                    .iter()
                    .chain(&path[k..])
                    .cloned()
                    .collect();
            }
            // The longest prefix that is a module with a file.
            let target = (0..=path.len())
                .rev()
                .find_map(|k| modules.get(&path[..k]))
                .expect("the crate root is a module");
            // A file's own inline test module, `self`, or a child declared in it are no
            // imports of another file's items when they resolve to the file itself.
            if *target != name {
                targets.insert(target.clone());
            }
        }
        graph.insert(name, targets);
    }
    graph
}

/// A statement without its leading attributes (`#[cfg(…)] pub use …;` → `pub use …;`).
fn without_attributes(stmt: &str) -> &str {
    let mut s = stmt.trim_start();
    while s.starts_with("#[") {
        let mut depth = 0;
        let end = s
            .char_indices()
            .find(|&(_, c)| match c {
                '[' => {
                    depth += 1;
                    false
                }
                ']' => {
                    depth -= 1;
                    depth == 0
                }
                _ => false,
            })
            .map_or(s.len(), |(k, _)| k + 1);
        s = s[end..].trim_start();
    }
    s
}

fn find_cycle(graph: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Open,
        Done,
    }
    fn visit(
        n: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        mark: &mut BTreeMap<String, Mark>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        mark.insert(n.to_owned(), Mark::Open);
        stack.push(n.to_owned());
        for m in graph.get(n).into_iter().flatten() {
            match mark.get(m).copied().unwrap_or(Mark::New) {
                Mark::Open => {
                    let i = stack.iter().position(|s| s == m).unwrap();
                    let mut cycle = stack[i..].to_vec();
                    cycle.push(m.clone());
                    return Some(cycle);
                }
                Mark::New => {
                    if let Some(c) = visit(m, graph, mark, stack) {
                        return Some(c);
                    }
                }
                Mark::Done => {}
            }
        }
        stack.pop();
        mark.insert(n.to_owned(), Mark::Done);
        None
    }
    let mut mark = BTreeMap::new();
    for n in graph.keys() {
        if mark.get(n).copied().unwrap_or(Mark::New) == Mark::New {
            if let Some(c) = visit(n, graph, &mut mark, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

fn crates() -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(workspace().join("crates"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("Cargo.toml").exists())
        .collect();
    dirs.sort();
    dirs
}

#[test]
fn no_import_circles_between_the_files_of_a_crate() {
    let mut checked = 0;
    // The libraries, the programs and the root package (its `src/` is a stub).
    for dir in crates().into_iter().chain([workspace()]) {
        let graph = import_graph(&dir.join("src"));
        checked += graph.len();
        if let Some(cycle) = find_cycle(&graph) {
            panic!("{}: import circle {}", dir.display(), cycle.join(" -> "));
        }
    }
    assert!(checked > 50, "only {checked} files found");
}

/// A temporary crate, `rsf-NAME-PID` in the temporary folder, whose `src/` holds `files`
/// (each a path below `src/` and its text); returns the crate's folder.
fn temp_crate(name: &str, files: &[(&str, &str)]) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rsf-{name}-{}", std::process::id()));
    for (path, text) in files {
        let path = dir.join("src").join(path);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(path, text).unwrap();
    }
    dir
}

/// The detector itself: a circle through a `super::` import and a name taken through the
/// root's re-export is found; the re-export itself is no import.
#[test]
fn the_circle_detector_sees_circles() {
    let dir = temp_crate(
        "layers",
        &[
            ("lib.rs", "mod a;\npub use a::b::Thing;\n"),
            ("a/mod.rs", "pub(crate) mod b;\npub(crate) mod c;\n"),
            ("a/b.rs", "use super::c::Other; pub struct Thing;\n"),
            (
                "a/c.rs",
                "// use crate::Thing;\nuse crate::{Thing};\npub struct Other;\n",
            ),
        ],
    );
    let src = dir.join("src");
    let graph = import_graph(&src);
    let cycle = find_cycle(&graph).expect("a circle");
    assert!(
        cycle.contains(&"a/b.rs".to_owned()) && cycle.contains(&"a/c.rs".to_owned()),
        "{cycle:?}"
    );
    std::fs::write(
        src.join("a/c.rs"),
        "// use crate::Thing;\npub struct Other;\n",
    )
    .unwrap();
    assert_eq!(find_cycle(&import_graph(&src)), None);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn crates_depend_only_on_lower_layers() {
    let layer_of = |name: &str| LAYERS.iter().position(|l| l.contains(&name));
    for dir in crates() {
        let manifest = std::fs::read_to_string(dir.join("Cargo.toml")).unwrap();
        let table: toml::Table = toml::from_str(&manifest).unwrap();
        let name = table["package"]["name"].as_str().unwrap().to_owned();
        let own = layer_of(&name).unwrap_or_else(|| panic!("{name} is in no layer"));
        let deps = table.get("dependencies").and_then(|d| d.as_table());
        for dep in deps.into_iter().flat_map(|d| d.keys()) {
            if let Some(l) = layer_of(dep) {
                assert!(l < own, "{name} (layer {own}) depends on {dep} (layer {l})");
            }
        }
    }
    // The rule the layers encode: a friction potential takes α as a number, so the friction
    // laws and the state laws do not know each other.
    assert_eq!(layer_of("rsf-friction"), layer_of("rsf-state"));
    // And TNNMG and the direct solver (with the condensation) do not know each other.
    assert_eq!(layer_of("rsf-tnnmg"), layer_of("rsf-direct"));
}

/// Every package of the workspace (the root package and the members `crates/*` that are not
/// excluded) is built at opt-level 1 in the test profile, and no other package is named
/// there: a crate left out would be compiled at the dependencies' opt-level 2, where rustc
/// shares no generic instance between crates (the root `Cargo.toml`'s comment).
#[test]
fn every_workspace_crate_is_in_the_test_profile() {
    let root: toml::Table =
        toml::from_str(&std::fs::read_to_string(workspace().join("Cargo.toml")).unwrap()).unwrap();
    let excluded: Vec<&str> = root["workspace"]["exclude"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e.as_str().unwrap())
        .collect();
    let mut members = BTreeSet::from([root["package"]["name"].as_str().unwrap().to_owned()]);
    for dir in crates() {
        let rel = format!("crates/{}", dir.file_name().unwrap().to_string_lossy());
        if excluded.contains(&rel.as_str()) {
            continue;
        }
        let manifest: toml::Table =
            toml::from_str(&std::fs::read_to_string(dir.join("Cargo.toml")).unwrap()).unwrap();
        members.insert(manifest["package"]["name"].as_str().unwrap().to_owned());
    }
    let packages = root["profile"]["test"]["package"].as_table().unwrap();
    let at_level_1: BTreeSet<String> = packages
        .iter()
        .filter(|(_, p)| p.get("opt-level").and_then(|l| l.as_integer()) == Some(1))
        .map(|(name, _)| name.clone())
        .collect();
    assert_eq!(
        at_level_1, members,
        "[profile.test.package] names the workspace's packages at opt-level 1"
    );
}

/// The top-level module (a file or folder of `src/`) of a file of the import graph:
/// `model/builder/mod.rs` → `model`, `ranks.rs` → `ranks`, `lib.rs` → `lib`.
fn top_module(file: &str) -> String {
    let first = file.split('/').next().unwrap_or(file);
    first.trim_end_matches(".rs").to_owned()
}

/// The import graph between the top-level modules of `src`: a module's imports of itself
/// and of the facade `lib` (the names `lib.rs` itself defines or re-exports from other
/// crates, e.g. `crate::fem`) dropped.
fn module_graph(src: &Path) -> BTreeMap<String, BTreeSet<String>> {
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (file, targets) in import_graph(src) {
        let here = top_module(&file);
        let entry = graph.entry(here.clone()).or_default();
        entry.extend(
            targets
                .iter()
                .map(|t| top_module(t))
                .filter(|t| *t != here && t != "lib"),
        );
    }
    graph
}

/// The imports of `graph` (a [`module_graph`]) that point to a higher layer of `layers`
/// (from the bottom up), as `from -> to` lines, and the modules in no layer.
fn upward_imports(graph: &BTreeMap<String, BTreeSet<String>>, layers: &[&[&str]]) -> Vec<String> {
    let layer_of = |m: &str| layers.iter().position(|l| l.contains(&m));
    let mut found = Vec::new();
    for (module, targets) in graph {
        if module == "lib" {
            continue;
        }
        let Some(own) = layer_of(module) else {
            found.push(format!("{module} is in no layer"));
            continue;
        };
        for t in targets {
            match layer_of(t) {
                Some(l) if l <= own => {}
                Some(l) => found.push(format!("{module} (layer {own}) -> {t} (layer {l})")),
                None => found.push(format!("{t} is in no layer")),
            }
        }
    }
    found
}

/// The top-level modules (files and folders of `src/`) of `rsf`, from the bottom up: a
/// module imports only modules of its own layer or below (and the module graph has no
/// circle, [`no_import_circles_between_the_folders_of_a_crate`]). docs/design.md,
/// "Modules of crates/rsf/src".
const RSF_MODULES: &[&[&str]] = &[
    // Foundations: errors, reports, states and their files, the model, the fault operator.
    &[
        "error",
        "report",
        "method_state",
        "simulation_state",
        "checkpoint",
        "run_manifest",
        "input_file",
        "fault_operator",
        "model",
    ],
    // The model's parts: the methods' choices, the friction functional, the operators of
    // a fault (condensed, whole space, half-space), the nodes' local solves, probes.
    &[
        "method",
        "friction_blocks",
        "volume_probe",
        "okada_comparison",
        "fault_kernel",
        "greens",
        "whole_space",
        "halfspace_operator",
        "node_solves",
    ],
    // Observing and running: observers and files, run control and folders, the normal
    // stress and the pore pressure (observed), the problem.
    &[
        "observe",
        "run",
        "run_folder",
        "pore_pressure",
        "normal_stress",
        "problem",
    ],
    // Processes that share a fault ODE's evaluations.
    &["ranks"],
    // The engines: a fault alone, the fault ODE, the coupled simulation, switching
    // between them, any run.
    &[
        "fault_alone",
        "fault_ode",
        "simulation",
        "switching",
        "any_run",
    ],
];

#[test]
fn no_import_circles_between_the_folders_of_a_crate() {
    let mut found = Vec::new();
    for dir in crates().into_iter().chain([workspace()]) {
        if let Some(cycle) = find_cycle(&module_graph(&dir.join("src"))) {
            found.push(format!("{}: {}", dir.display(), cycle.join(" -> ")));
        }
    }
    assert!(
        found.is_empty(),
        "import circles between modules:\n{}",
        found.join("\n")
    );
}

/// The order check itself, on a temporary crate: an import from a folder to a higher
/// layer's file is found, its removal passes, and a module no layer lists is named.
#[test]
fn the_order_check_sees_upward_imports() {
    let dir = temp_crate(
        "order",
        &[
            ("lib.rs", "mod low;\nmod high;\n"),
            ("low/mod.rs", "pub(crate) mod part;\n"),
            ("high.rs", "use crate::low::part::Thing;\npub struct Top;\n"),
            // The temporary violation: the low folder takes a name of the higher file.
            ("low/part.rs", "use crate::high::Top;\npub struct Thing;\n"),
        ],
    );
    let src = dir.join("src");
    let layers: &[&[&str]] = &[&["low"], &["high"]];
    let found = upward_imports(&module_graph(&src), layers);
    assert_eq!(found, ["low (layer 0) -> high (layer 1)"], "{found:?}");
    std::fs::write(src.join("low/part.rs"), "pub struct Thing;\n").unwrap();
    assert!(upward_imports(&module_graph(&src), layers).is_empty());
    assert_eq!(
        upward_imports(&module_graph(&src), &[&["low"]]),
        ["high is in no layer"]
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The top-level modules (files and folders of `src/`, `bin` the binaries' folder) of
/// every package but `rsf` (whose order is [`RSF_MODULES`]), from the bottom up: a module
/// imports only modules of its own layer or below. The layers are the order of the code as
/// it is (each module one layer above the highest it imports), so that an import against
/// it — the first step towards a circle — fails here, and a new module is placed by whoever
/// adds it. docs/design.md, "Layers".
const CRATE_MODULES: &[(&str, &[&[&str]])] = &[
    (
        "rsf-direct",
        &[
            &["dense", "error", "norm_bounds", "options"],
            &["fault_newton", "ordering"],
            &["partial_cholesky"],
            &["condensation", "harmonic"],
            &["functionals", "schur_entries", "schur_only", "solver"],
            &["memory"],
        ],
    ),
    ("rsf-examples", &[&["main"]]),
    (
        "rsf-fem",
        &[
            &["error", "geometry", "input_file"],
            &["constraints", "dof_transform", "element", "mesh"],
            &["assembly", "frames", "refine", "split", "structured"],
            &["hierarchy", "network", "octree", "part", "split_surface"],
            &[
                "bisection",
                "boundary",
                "elastic_box",
                "gmsh",
                "loads",
                "split_transform",
            ],
        ],
    ),
    ("rsf-friction", &[&["potentials"], &["asinh"]]),
    (
        "rsf-halfspace",
        &[
            &["dual", "error", "space"],
            &["okada", "stress"],
            &["bem", "triangle", "two_d"],
            &["elements"],
            &["element_set"],
        ],
    ),
    (
        "rsf-hdf5",
        &[
            &["attributes", "bin", "error"],
            &["frames"],
            &["fault_fields", "fields", "series"],
            &["greens", "programs"],
        ],
    ),
    (
        "rsf-hmatrix",
        &[
            &["error", "rng"],
            &["lowrank", "options", "points"],
            &["aca", "cluster", "kernels"],
            &["block"],
            &["product"],
            &["columns"],
            &["hmatrix"],
        ],
    ),
    (
        "rsf-linalg",
        &[
            &["error"],
            &["cholesky", "ops", "parallelism"],
            &["reduce", "sprs_conversion"],
            &["csc"],
        ],
    ),
    ("rsf-metis", &[&["ffi"]]),
    ("rsf-mpi", &[&["bin", "halo"], &["ranks"]]),
    (
        "rsf-nonsmooth",
        &[
            &["error", "nonlinearity", "watch"],
            &["matrix", "solver"],
            &["step"],
        ],
    ),
    (
        "rsf-numeric",
        &[&["convention", "message", "omega", "root"]],
    ),
    (
        "rsf-programs",
        &[
            &[
                "defaults",
                "flag_ranges",
                "heat_map",
                "memory",
                "panels",
                "process",
                "run",
                "run_folder",
                "seas_overview",
            ],
            &["curved", "guard"],
            &["config", "estimates", "fields"],
            &["cli"],
            &["distributed_sweep", "own_model", "seas_args", "session"],
            &[
                "network",
                "pipping_slider",
                "seas_bp1",
                "seas_bp3",
                "seas_bp5",
                "seas_bp6",
                "slider_3d",
                "square_fault",
            ],
            &["bp5_pair", "on_ranks", "seas_bp7", "seas_bp8", "stepover"],
            &["config_round_trip"],
            &["config_tests"],
        ],
    ),
    (
        "rsf-python",
        &[
            &["engine", "errors"],
            &["arrays", "convert", "counts", "fields"],
            &["dislocations", "network", "simulation"],
            &["mesh"],
            &["problem", "run_folder"],
            &["scenes"],
            &["seas_bp3", "seas_bp5", "seas_bp6", "seas_square"],
        ],
    ),
    (
        "rsf-ranks",
        &[
            &["block", "error", "transport"],
            &["bsr", "groups"],
            &["colouring", "local_rows", "processes"],
            &["halo", "linear"],
            &["gather", "node_graph", "node_plan", "reduce", "sweep"],
            &["cg", "sweep_tests"],
        ],
    ),
    (
        "rsf-scenes",
        &[
            &[
                "scene_file",
                "seas_bp1",
                "seas_bp5",
                "seas_bp6",
                "square_fault",
            ],
            &[
                "run_config",
                "seas_bp3",
                "seas_bp5_output",
                "seas_bp7",
                "seas_bp8",
                "slider",
                "square_volume",
                "stepover",
            ],
            &["incline", "output", "seas_square_run", "slider3d"],
            &[
                "bp5_pair_run",
                "curved",
                "seas_bp1_run",
                "seas_bp3_run",
                "seas_bp5_run",
                "seas_bp6_run",
                "seas_bp7_volume",
                "seas_bp8_volume",
                "stepover_run",
            ],
        ],
    ),
    (
        "rsf-seas",
        &[
            &["error", "setup"],
            &["reserve", "text"],
            &["read", "resume"],
            &["along_dip", "bp6", "strike_dip"],
        ],
    ),
    (
        "rsf-state",
        &[
            &["error"],
            &["generic", "probe"],
            &["law"],
            &["laws"],
            &["kind"],
        ],
    ),
    (
        "rsf-time",
        &[
            &["adaptive", "choice", "krylov", "load"],
            &["runge_kutta"],
            &["rosenbrock", "stabilized", "test_systems"],
            &["stepper"],
        ],
    ),
    (
        "rsf-tnnmg",
        &[
            &["chunks", "error", "line_search"],
            &["coarse", "galerkin", "norm", "problem", "smoother_order"],
            &["multigrid", "report"],
            &["gauss_seidel", "linear_correction"],
            &["tnnmg"],
            &["distributed"],
        ],
    ),
];

/// The table of the package of `dir` (its `Cargo.toml`'s name): [`RSF_MODULES`] for `rsf`,
/// else its entry of [`CRATE_MODULES`].
fn module_table(dir: &Path) -> (String, Option<&'static [&'static [&'static str]]>) {
    let manifest: toml::Table =
        toml::from_str(&std::fs::read_to_string(dir.join("Cargo.toml")).unwrap()).unwrap();
    let name = manifest["package"]["name"].as_str().unwrap().to_owned();
    let table = match name.as_str() {
        "rsf" => Some(RSF_MODULES),
        other => CRATE_MODULES
            .iter()
            .find(|(n, _)| *n == other)
            .map(|(_, layers)| *layers),
    };
    (name, table)
}

#[test]
fn every_crates_modules_import_only_their_own_layer_or_below() {
    let mut found = Vec::new();
    for dir in crates().into_iter().chain([workspace()]) {
        let (name, table) = module_table(&dir);
        let Some(layers) = table else {
            found.push(format!("{name} has no table of its modules"));
            continue;
        };
        let graph = module_graph(&dir.join("src"));
        found.extend(
            upward_imports(&graph, layers)
                .into_iter()
                .map(|line| format!("{name}: {line}")),
        );
        // A table names only modules that exist (a removed module leaves it).
        for module in layers.iter().flat_map(|l| l.iter()) {
            if !graph.contains_key(*module) {
                found.push(format!("{name}: {module} is listed but not in src/"));
            }
        }
    }
    assert!(found.is_empty(), "{}", found.join("\n"));
}
