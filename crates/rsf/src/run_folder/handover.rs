//! `--resume CHECKPOINT --overwrite` into the folder of another run: the folder is given to
//! the checkpoint's run **whole** — every file of the folder's run removed, the files of the
//! checkpoint's run copied from the checkpoint's own folder — or the resume is refused,
//! naming why; never a mix of two runs (issue 87: B's rows up to the checkpoint's step
//! followed by A's).

use std::path::{Path, PathBuf};

use crate::checkpoint::Checkpoint;
use crate::error::{io_at, show_path, Error, Result};
use crate::run_manifest::{short_id, Manifest, MANIFEST};

use super::RunFolder;

/// Files of a run that the run writes anew and that are never copied: its checkpoint (the
/// one resumed from is read where it is) and its summary (written at the run's end).
const NOT_COPIED: [&str; 2] = ["checkpoint.bin", "summary.json"];

impl RunFolder {
    /// Gives this folder, whose run is `folder` (another run than the checkpoint `c`'s),
    /// to the run of `c`, read from `checkpoint`: that run's own folder — the checkpoint's
    /// folder, whose manifest must name `c`'s run and this program — is copied here. The
    /// outputs of this folder's run (its manifest's and this run's) are removed first,
    /// then every output the checkpoint's run lists is copied (a file inside a folder,
    /// e.g. `frames/frames.pvd`, copies that folder whole), each file written to
    /// `NAME.tmp` and renamed; the checkpoint and the summary are not copied. The copied
    /// files are then continued from the checkpoint's step by each writer's own check, as
    /// in the checkpoint's own folder.
    ///
    /// # Errors
    /// [`Error::Resume`] naming this folder when the checkpoint's folder is not that run's
    /// (no manifest, another run, another program) — nothing changed then; [`Error::File`]
    /// naming a file that could not be removed or copied.
    pub(super) fn take_over(
        &self,
        checkpoint: &Path,
        c: &Checkpoint,
        folder: &Manifest,
    ) -> Result<()> {
        let source = checkpoint
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."));
        let refuse = |why: String| Error::Resume {
            path: show_path(&self.dir),
            reason: format!(
                "--overwrite gives this folder to the checkpoint's run (run {}, at step {}) \
                 only whole, its files up to that step rewritten from that run's own folder, \
                 never continued from this folder's run ({}); but {why}: resume into the \
                 checkpoint's own folder, or start this folder anew without --resume",
                short_id(&c.run_id),
                c.state.step,
                folder.describe()
            ),
        };
        let theirs = match Manifest::read(source)? {
            Some(m) if m.run_id == c.run_id && m.program == self.program => m,
            Some(m) => {
                return Err(refuse(format!(
                    "the folder of the checkpoint `{}` holds another run ({}, of `{}`)",
                    show_path(source),
                    m.describe(),
                    rsf_numeric::excerpt(&m.program)
                )))
            }
            None => {
                return Err(refuse(format!(
                    "the folder of the checkpoint `{}` has no run manifest ({MANIFEST}) naming \
                     its run",
                    show_path(source)
                )))
            }
        };
        let copied: Vec<String> = tops(&theirs.outputs)
            .into_iter()
            .filter(|o| !NOT_COPIED.contains(&o.as_str()) && source.join(o).exists())
            .collect();
        let ours: Vec<&String> = folder.outputs.iter().chain(&self.outputs).collect();
        for name in tops(ours) {
            remove(&self.path(&name))?;
        }
        for name in &copied {
            copy_tree(&source.join(name), &self.path(name))?;
        }
        Ok(())
    }
}

/// The first component of each output path (`frames/frames.pvd` → `frames`), once each.
fn tops<'a>(outputs: impl IntoIterator<Item = &'a String>) -> Vec<String> {
    let mut tops: Vec<String> = outputs
        .into_iter()
        .filter_map(|o| {
            Path::new(o)
                .components()
                .next()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
        })
        .filter(|o| o != MANIFEST && o != "." && o != "..")
        .collect();
    tops.sort_unstable();
    tops.dedup();
    tops
}

/// Removes the file or folder `path` if it exists.
fn remove(path: &Path) -> Result<()> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => std::fs::remove_dir_all(path).map_err(io_at("remove", path)),
        Ok(_) => std::fs::remove_file(path).map_err(io_at("remove", path)),
        Err(_) => Ok(()),
    }
}

/// Copies the file `from` to `to` (through `to.tmp`, renamed), or the folder `from` with
/// everything in it.
fn copy_tree(from: &Path, to: &Path) -> Result<()> {
    let meta = std::fs::metadata(from).map_err(io_at("read", from))?;
    if meta.is_dir() {
        std::fs::create_dir_all(to).map_err(io_at("create", to))?;
        let entries = std::fs::read_dir(from).map_err(io_at("read", from))?;
        for entry in entries {
            let entry = entry.map_err(io_at("read", from))?;
            copy_tree(&entry.path(), &to.join(entry.file_name()))?;
        }
        return Ok(());
    }
    if !meta.is_file() {
        return Err(Error::Resume {
            path: show_path(from),
            reason: "it is not a regular file: a run's output cannot be copied from it".into(),
        });
    }
    let mut tmp = PathBuf::from(to);
    tmp.as_mut_os_string().push(".tmp");
    std::fs::copy(from, &tmp).map_err(io_at("copy into", &tmp))?;
    std::fs::rename(&tmp, to).map_err(io_at("rename into place", to))
}
