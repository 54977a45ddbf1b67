//! The call into METIS's C library (the workspace's only `unsafe` code).
#![allow(unsafe_code)]

use std::sync::Mutex;

use metis_sys::{
    idx_t, moptions_et_METIS_OPTION_NUMBERING, moptions_et_METIS_OPTION_SEED, rstatus_et_METIS_OK,
    METIS_NodeND, METIS_NodeNDP, METIS_PartGraphKway, METIS_SetDefaultOptions, METIS_NOPTIONS,
};

use crate::{Error, Result, SEED};

/// One METIS call at a time: its random number generator (GKlib's) is a global C array,
/// and a seed set by one call must not be advanced by another's.
static METIS: Mutex<()> = Mutex::new(());

/// METIS_NodeND of a checked graph (`xadj`, `adjncy` valid, symmetric, no self-loops,
/// `n = xadj.len() − 1 ≥ 2`), with the default options, 0-based numbering and seed
/// [`SEED`]: its `perm` (`perm[k]` = the vertex eliminated `k`-th). With `halves`,
/// METIS_NodeNDP for two processors instead (the same nested dissection, which also
/// reports the top level): `perm` and the sizes of the first half, the second half and
/// the top separator, in the order's sequence; else the sizes are zero.
pub(crate) fn node_nd(
    xadj: &mut [idx_t],
    adjncy: &mut [idx_t],
    halves: bool,
) -> Result<(Vec<idx_t>, [idx_t; 3])> {
    let n = xadj.len() - 1;
    let mut nvtxs = idx_t::try_from(n).map_err(|_| Error::TooLarge {
        vertices: n,
        entries: adjncy.len(),
    })?;
    let mut perm: Vec<idx_t> = vec![0; n];
    let mut iperm: Vec<idx_t> = vec![0; n];
    let _one_at_a_time = METIS.lock().unwrap_or_else(|e| e.into_inner());
    let mut options = default_options()?;
    // SAFETY: `nvtxs` = n vertices; `xadj` has n + 1 entries rising from 0 to
    // `adjncy.len()` and every entry of `adjncy` is in 0..n (checked by the caller, as is
    // the symmetry METIS assumes); no vertex weights (null); `options` has
    // METIS_NOPTIONS entries; `perm` and `iperm` have n entries each. METIS reads its
    // inputs and writes n entries of each output, nothing else.
    // METIS_NodeNDP: the same, `npes` = 2 and `sizes` of 2 · 2 − 1 = 3 entries.
    let mut sizes: [idx_t; 3] = [0; 3];
    let status = unsafe {
        if halves {
            METIS_NodeNDP(
                nvtxs,
                xadj.as_mut_ptr(),
                adjncy.as_mut_ptr(),
                std::ptr::null_mut(),
                2,
                options.as_mut_ptr(),
                perm.as_mut_ptr(),
                iperm.as_mut_ptr(),
                sizes.as_mut_ptr(),
            )
        } else {
            METIS_NodeND(
                &mut nvtxs,
                xadj.as_mut_ptr(),
                adjncy.as_mut_ptr(),
                std::ptr::null_mut(),
                options.as_mut_ptr(),
                perm.as_mut_ptr(),
                iperm.as_mut_ptr(),
            )
        }
    };
    if status != rstatus_et_METIS_OK {
        return Err(Error::Metis(status));
    }
    Ok((perm, sizes))
}

/// METIS's default options with 0-based numbering and the seed [`SEED`] (called with the
/// lock held: the options are read by the next call).
fn default_options() -> Result<[idx_t; METIS_NOPTIONS as usize]> {
    let mut options: [idx_t; METIS_NOPTIONS as usize] = [0; METIS_NOPTIONS as usize];
    // SAFETY: `options` has METIS_NOPTIONS entries, as METIS_SetDefaultOptions writes.
    let status = unsafe { METIS_SetDefaultOptions(options.as_mut_ptr()) };
    if status != rstatus_et_METIS_OK {
        return Err(Error::Metis(status));
    }
    options[moptions_et_METIS_OPTION_NUMBERING as usize] = 0;
    options[moptions_et_METIS_OPTION_SEED as usize] = SEED;
    Ok(options)
}

/// METIS_PartGraphKway of a checked graph (`xadj`, `adjncy` valid, symmetric, no
/// self-loops, `n = xadj.len() − 1 ≥ 1`) into `nparts ≥ 2` parts, with the default options
/// (minimal edge cut, imbalance tolerance 1.03), 0-based numbering and seed [`SEED`],
/// without vertex or edge weights: `part[v]` is the part of vertex `v` (length n).
pub(crate) fn part_graph_kway(
    xadj: &mut [idx_t],
    adjncy: &mut [idx_t],
    nparts: idx_t,
) -> Result<Vec<idx_t>> {
    let n = xadj.len() - 1;
    let mut nvtxs = idx_t::try_from(n).map_err(|_| Error::TooLarge {
        vertices: n,
        entries: adjncy.len(),
    })?;
    let (mut ncon, mut nparts, mut edgecut) = (1, nparts, 0);
    let mut part: Vec<idx_t> = vec![0; n];
    let _one_at_a_time = METIS.lock().unwrap_or_else(|e| e.into_inner());
    let mut options = default_options()?;
    // SAFETY: `nvtxs` = n vertices and one balance constraint; `xadj` has n + 1 entries
    // rising from 0 to `adjncy.len()` and every entry of `adjncy` is in 0..n (checked by
    // the caller, as is the symmetry METIS assumes); no vertex weights, sizes or edge
    // weights, no target part weights and the default imbalance (null pointers); `options`
    // has METIS_NOPTIONS entries; `edgecut` is one value and `part` has n entries. METIS
    // reads its inputs and writes `edgecut` and n entries of `part`, nothing else.
    let status = unsafe {
        METIS_PartGraphKway(
            &mut nvtxs,
            &mut ncon,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            &mut nparts,
            std::ptr::null_mut(),
            std::ptr::null_mut(),
            options.as_mut_ptr(),
            &mut edgecut,
            part.as_mut_ptr(),
        )
    };
    if status != rstatus_et_METIS_OK {
        return Err(Error::Metis(status));
    }
    Ok(part)
}
