//! The public shape of the library, read from the source (issue 34): `rsf`'s root
//! re-exports at most 40 names (the rest lives in its modules and prelude). (The number of
//! parameters is clippy's `too_many_arguments`, threshold in `clippy.toml`: docs/design.md.)

use std::path::{Path, PathBuf};

fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
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
