//! The clap flags of a run folder (`--overwrite`, `--allow-change`, `--max-steps`; the
//! output bound `--max-output-gb` is every program's, `crate::guard::Limits`). The procedure itself (refusing another run's folder, checking a resume
//! before any file is cut, output bounds and step caps) is the library's:
//! [`rsf::run_folder`] (docs/reliability.md).

/// The flags of a run folder: how to treat existing files, deliberate changes on resume
/// and the step cap (for adaptive steps without `--max-steps`, the run stops at the step
/// count whose output fits in `--max-output-gb`, with a checkpoint to resume from).
#[derive(Debug, Clone, Default, clap::Args)]
pub struct FolderArgs {
    /// Replace the files of an earlier run in the output folder (without it, a folder
    /// holding another run's files is refused and left untouched).
    #[arg(long)]
    pub overwrite: bool,
    /// On `--resume`, accept a checkpoint whose fingerprint differs in these fields
    /// (comma separated, e.g. `end_time_s`): a deliberate change of the run. A field that
    /// is not in the run's fingerprint is refused, naming the fields that are.
    #[arg(long, value_delimiter = ',', value_name = "FIELD,…")]
    pub allow_change: Vec<String>,
    /// Stop the run after this many steps in total (across resumes), writing a checkpoint
    /// to continue from with a larger value; bounds the output of adaptive runs. 0
    /// computes no step.
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u64>,
}

/// The error of a resumed Schur-only set-up whose kept elimination, `path` (`setup.bin`
/// in the run folder), is of another problem than the changed flags give (`--allow-change
/// ordering|mesh|fault_zone|…`), with what to do: delete the file to rebuild the set-up
/// (issue 87: the refusal named no way out). Other errors pass unchanged.
#[cfg(feature = "seas")]
pub(crate) fn kept_setup_hint(
    e: rsf::Error,
    path: &std::path::Path,
    allow_change: &[String],
) -> Box<dyn std::error::Error> {
    match e {
        rsf::Error::Direct(rsf::direct::Error::CheckpointMismatch { .. }) => format!(
            "{e}. It is the elimination kept by the run before the change{}: delete `{}` to \
             rebuild the set-up from this run's flags (the resume eliminates again), or \
             resume without the change",
            if allow_change.is_empty() {
                String::new()
            } else {
                format!(" (--allow-change {})", allow_change.join(","))
            },
            rsf_numeric::excerpt(&path.display().to_string())
        )
        .into(),
        e => e.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::kept_setup_hint;
    use std::path::Path;

    /// A kept elimination of another problem (the ordering changed by `--allow-change`) is
    /// refused naming the file to delete; any other error passes as it was.
    #[test]
    fn a_kept_setup_of_another_problem_names_the_file_to_delete() {
        let path = Path::new("out/run/setup.bin");
        let mismatch = rsf::Error::Direct(rsf::direct::Error::CheckpointMismatch {
            path: path.display().to_string(),
            reason: "another ordering".into(),
        });
        let e = kept_setup_hint(mismatch, path, &["ordering".into()]).to_string();
        assert!(
            e.contains("delete `out/run/setup.bin`") && e.contains("--allow-change ordering"),
            "{e}"
        );
        let other = rsf::Error::InvalidParameter {
            name: "dx".into(),
            reason: "r".into(),
        };
        let shown = other.to_string();
        assert_eq!(kept_setup_hint(other, path, &[]).to_string(), shown);
    }
}
