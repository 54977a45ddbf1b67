//! `--config`: a file's keys over the defaults, the flags over the file's keys, the
//! refusals named as written.

use rsf_scenes::{Bp7Law, SeasBp7Run};

use crate::guard::{parse_from, Program};
use crate::seas_bp7::Args;

/// `seas_bp7 --config CONFIG` and the flags `more` after it, parsed: the program's
/// arguments, or the parser's error as its message.
fn bp7_with_config(config: &std::path::Path, more: &[&str]) -> Result<Args, String> {
    let mut args = vec!["seas_bp7", "--config", config.to_str().unwrap()];
    args.extend(more);
    parse_from::<Args, _, _>(args)
        .map(|(args, _)| args)
        .map_err(|e| e.to_string())
}

/// `--config`: the file's keys over the defaults, a flag given over the file's key; an
/// unknown key, a mistyped value and a refused value named as written.
#[test]
fn a_config_file_sets_what_no_flag_gives() {
    let dir = std::env::temp_dir().join(format!("rsf-config-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The file `name` of the folder, holding `text`.
    let file = |name: &str, text: &str| {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    };
    let path = file("bp7.toml", "law = \"slip\"\ndx = 20\nend_years = 2.5\n");
    let args = bp7_with_config(&path, &["--dx", "40"]).unwrap();
    let run = args.settings;
    assert_eq!(run.law, Bp7Law::Slip);
    assert_eq!(run.dx, 40.0, "the flag wins");
    assert_eq!(run.end_years, 2.5, "the file's key");
    assert_eq!(run.d_rs, SeasBp7Run::default().d_rs, "the default");
    args.plan().unwrap();

    let unknown = file("unknown.toml", "dx = 20\nd_c = 1\n");
    let e = bp7_with_config(&unknown, &[]).err().unwrap();
    assert!(e.contains("d_c") && e.contains("--config"), "{e}");

    let typed = file("typed.toml", "dx = \"ten\"\n");
    let e = bp7_with_config(&typed, &[]).err().unwrap();
    assert!(e.contains("dx") && e.contains("typed.toml"), "{e}");

    let refused = file("refused.toml", "dx = 30\n");
    let args = bp7_with_config(&refused, &[]).unwrap();
    let e = args.plan().err().unwrap().to_string();
    assert!(
        e.contains("refused.toml: key `dx` = 30: must divide"),
        "{e}"
    );
    let args = bp7_with_config(&refused, &["--dx", "3"]).unwrap();
    let e = args.plan().err().unwrap().to_string();
    assert!(e.starts_with("--dx 3: must be in [5, 400]"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}
