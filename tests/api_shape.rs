//! The public shape of the library, read from the source (issue 34): `rsf`'s root
//! re-exports at most 40 names (the rest lives in its modules and prelude), and no public
//! function of any crate takes more than 5 parameters (a sixth is an options struct).

use std::path::{Path, PathBuf};

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

/// The names a `pub use` item at the top level of `lib.rs` re-exports (before the first
/// `pub mod … {` block's contents are skipped).
fn root_reexports(lib: &str) -> Vec<String> {
    let mut names = Vec::new();
    let mut depth = 0usize;
    let mut item = String::new();
    for line in lib.lines() {
        let code = line.split("//").next().unwrap_or("");
        if depth == 0 && (code.starts_with("pub use ") || !item.is_empty()) {
            item.push_str(code);
            if code.contains(';') {
                let body = item.trim_start_matches("pub use ").trim_end_matches(';');
                let inner = match (body.find('{'), body.rfind('}')) {
                    (Some(a), Some(b)) => body[a + 1..b].to_string(),
                    _ => body.rsplit("::").next().unwrap().to_string(),
                };
                for n in inner.split(',') {
                    let n = n.trim();
                    if !n.is_empty() {
                        names.push(n.rsplit(" as ").next().unwrap().to_string());
                    }
                }
                item.clear();
            }
        }
        depth += code.matches('{').count();
        depth -= code.matches('}').count().min(depth);
    }
    names
}

#[test]
fn the_root_of_rsf_reexports_at_most_40_names() {
    let lib = std::fs::read_to_string(workspace().join("crates/rsf/src/lib.rs")).unwrap();
    let names = root_reexports(&lib);
    eprintln!("{} root names: {names:?}", names.len());
    assert!(names.contains(&"Simulation".to_string()), "{names:?}");
    assert!(
        names.len() <= 40,
        "{} names at the root: {names:?}",
        names.len()
    );
}

/// Parameters of every `pub fn` (without `self`), by counting the top-level commas of its
/// parameter list.
fn public_fns(text: &str) -> Vec<(String, usize)> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("pub fn ") {
        rest = &rest[i + 7..];
        let name: String = rest
            .chars()
            .take_while(|c| c.is_alphanumeric() || *c == '_')
            .collect();
        // The parameter list: the first '(' after the name at generic depth 0.
        let (mut angle, mut open) = (0i32, None);
        for (k, c) in rest.char_indices() {
            match c {
                '<' => angle += 1,
                '>' if k > 0 && &rest[k - 1..k] != "-" => angle -= 1,
                '(' if angle == 0 => {
                    open = Some(k);
                    break;
                }
                _ => {}
            }
        }
        let Some(open) = open else { continue };
        let (mut depth, mut params, mut current) = (0i32, Vec::new(), String::new());
        for (k, c) in rest[open + 1..].char_indices() {
            let prev = rest[open + 1..][..k].chars().last();
            match c {
                '(' | '[' | '{' => depth += 1,
                '<' => depth += 1,
                '>' if prev != Some('-') && prev != Some('=') => depth -= 1,
                ')' | ']' | '}' if depth == 0 => break,
                ')' | ']' | '}' => depth -= 1,
                ',' if depth == 0 => {
                    params.push(std::mem::take(&mut current));
                    continue;
                }
                _ => {}
            }
            current.push(c);
        }
        params.push(current);
        let n = params
            .iter()
            .map(|p| p.trim())
            .filter(|p| !p.is_empty())
            .filter(|p| {
                let p = p.trim_start_matches('&').trim_start_matches("mut ").trim();
                !(p == "self" || p.starts_with("self:") || p.starts_with("'") && p.contains("self"))
            })
            .count();
        out.push((name, n));
    }
    out
}

#[test]
fn no_public_function_takes_more_than_5_parameters() {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(workspace().join("crates")).unwrap() {
        let src = entry.unwrap().path().join("src");
        if src.is_dir() {
            rust_files(&src, &mut files);
        }
    }
    assert!(files.len() > 50, "{} files", files.len());
    let mut worst = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (name, n) in public_fns(&text) {
            if n > 5 {
                worst.push(format!("{}: {name} ({n})", f.display()));
            }
        }
    }
    assert!(
        worst.is_empty(),
        "public functions with more than 5 parameters: {worst:?}"
    );
    // The counter itself counts: a function of six parameters is found.
    let six = "pub fn f<T: Into<f64>>(a: T, b: &[f64], c: impl Fn(f64) -> f64, d: (u8, u8), e: u8, g: u8) {}";
    assert_eq!(public_fns(six), vec![("f".to_string(), 6)]);
    assert_eq!(
        public_fns("pub fn m(&mut self, a: u8) {}"),
        vec![("m".to_string(), 1)]
    );
}
