//! What the MPI tests share.

use std::process::Command;

/// `mpirun -n ranks` with the flags every launch here needs: more ranks than cores
/// (`--oversubscribe`), and as root (containers, CI) where Open MPI asks for consent.
pub fn mpirun(ranks: usize) -> Command {
    let mut c = Command::new("mpirun");
    c.args(["-n", &ranks.to_string(), "--oversubscribe"])
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    c
}
