//! The programs' run session: the library's [`rsf::run_folder::Session`] (the resume
//! sequence every front end shares, the Python package's too; docs/reliability.md, "One
//! guard for every program") with its settings from the programs' flags
//! ([`ResumeArgs::session_flags`]).

pub use rsf::run_folder::{Session, SessionFlags};

use crate::cli::ResumeArgs;

impl ResumeArgs {
    /// The flags of a session: `--resume FILE`, `--allow-change FIELD,…`,
    /// `--checkpoint-every N` and the step cap `--max-steps`.
    pub fn session_flags(&self) -> SessionFlags<'_> {
        self.session_flags_with_cap(self.max_steps)
    }

    /// The flags of a session with the step cap `step_cap` (a program that derives its
    /// cap from its output bound when `--max-steps` is not given).
    pub fn session_flags_with_cap(&self, step_cap: Option<u64>) -> SessionFlags<'_> {
        SessionFlags {
            resume: self.resume.as_deref(),
            allow_change: &self.allow_change,
            checkpoint_every: self.checkpoint_every,
            step_cap,
        }
    }
}
