//! The manifest every run writes into its folder (`rsf-run.txt`: the program, the run's id,
//! its command line and outputs), read by the run folder's checks
//! ([`RunFolder`](crate::run_folder::RunFolder)) and by the checkpoints a run writes into
//! its folder ([`Checkpointer`](crate::observe::Checkpointer): the run id they carry).

use std::path::Path;

use crate::error::{io_at, Result};

/// Name of the manifest every run writes into its folder: `program=NAME`, `run=ID` (the
/// run's id: made when a run starts in the folder, kept by its resumes, carried by its
/// checkpoints, [`Checkpoint::run_id`](crate::checkpoint::Checkpoint::run_id)), `command=…` (the
/// command line that started or last resumed it, if given:
/// [`RunFolder::command`](crate::run_folder::RunFolder::command)) and one `output=FILE` line per file
/// the run writes (paths relative to the folder).
pub const MANIFEST: &str = "rsf-run.txt";

/// A manifest's content: the program, its run and outputs.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Manifest {
    pub(crate) program: String,
    /// Empty for a manifest of a version before run ids.
    pub(crate) run_id: String,
    pub(crate) command: String,
    pub(crate) outputs: Vec<String>,
}

impl Manifest {
    pub(crate) fn text(&self) -> String {
        let mut t = format!("program={}\n", self.program);
        if !self.run_id.is_empty() {
            t.push_str(&format!("run={}\n", self.run_id));
        }
        if !self.command.is_empty() {
            t.push_str(&format!("command={}\n", self.command.replace('\n', " ")));
        }
        for o in &self.outputs {
            t.push_str(&format!("output={o}\n"));
        }
        t
    }

    /// Reads the manifest of `dir` (`None` if there is none).
    pub(crate) fn read(dir: &Path) -> Result<Option<Self>> {
        let path = dir.join(MANIFEST);
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(io_at("read the run manifest", &path)(e)),
        };
        let mut m = Manifest {
            program: String::new(),
            run_id: String::new(),
            command: String::new(),
            outputs: Vec::new(),
        };
        for line in text.lines() {
            match line.split_once('=') {
                Some(("program", p)) => m.program = p.to_owned(),
                Some(("run", r)) => m.run_id = r.to_owned(),
                Some(("command", c)) => m.command = c.to_owned(),
                Some(("output", o)) => m.outputs.push(o.to_owned()),
                _ => {}
            }
        }
        if m.program.is_empty() {
            // A manifest that names no program: of an unknown run, never ours.
            m.program = "an unknown program".into();
        }
        Ok(Some(m))
    }

    /// The run as a message names it: its id and command line.
    pub(crate) fn describe(&self) -> String {
        let id = if self.run_id.is_empty() {
            "of unknown id".to_owned()
        } else {
            short_id(&self.run_id)
        };
        if self.command.is_empty() {
            format!("run {id}")
        } else {
            format!("run {id}, `{}`", rsf_numeric::excerpt(&self.command))
        }
    }
}

/// The first 12 characters of a run id (enough to tell runs apart in a message).
pub(crate) fn short_id(id: &str) -> String {
    rsf_numeric::excerpt(&id.chars().take(12).collect::<String>())
}

/// A new run id: 32 hexadecimal digits from the operating system's randomness (the keys
/// of [`std::hash::RandomState`]), the time and the process id — unique among the runs
/// of any number of machines for all practical purposes.
pub fn new_run_id() -> String {
    use std::hash::{BuildHasher, Hasher};
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    let word = || {
        let mut h = std::collections::hash_map::RandomState::new().build_hasher();
        h.write_u128(nanos);
        h.write_u32(std::process::id());
        h.finish()
    };
    format!("{:016x}{:016x}", word(), word())
}

/// The run id of the run folder `dir` (its manifest's `run=`), if it has one.
pub fn run_id(dir: &Path) -> Option<String> {
    Manifest::read(dir)
        .ok()
        .flatten()
        .map(|m| m.run_id)
        .filter(|id| !id.is_empty())
}
