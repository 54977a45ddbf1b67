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
