//! The Green's functions of a model's faults ([`rsf::greens::GreensFunctions`]) and the
//! dense operator `S` in one HDF5 file, and read back (docs/fault-networks.md, "Green's
//! functions").

use std::path::Path;

use hdf5::types::VarLenUnicode;
use hdf5::{File, Location};
use rsf::fault_operator::{FaultKernel, OperatorOrigin};
use rsf::greens::{GreensAccuracy, GreensFunctions};

use crate::attributes::text;
use crate::error::{h5_at, show_path, Error, Result};
use crate::frames::view;
use crate::series::replace_atomically;

/// The file's `format` attribute: the layout this module writes and reads.
pub const GREENS_FORMAT: &str = "rsf-greens-1";

/// Writes `greens` and its dense operator `s` (row-major `m × m`, N/m in 3-D, N/m² in
/// 2-D: [`GreensFunctions::dense`]) into the HDF5 file `path`, replacing it atomically
/// (written beside it, then renamed). Datasets (`m` unknowns, `n` faults):
///
/// - `S` `(m, m)`: `S_ij`, the force on unknown `i` from unit slip on unknown `j`
///   (attribute `unit`); the traction change is `−S_ij / weights_i` (Pa);
/// - `positions` `(m, 3)` (m), `directions` `(m, 3)` (unit slip vectors, Cartesian),
///   `weights` `(m)` (m² in 3-D, m in 2-D), `fault` `(m)` (an index into `fault_names`),
///   `node` `(m)` (the frictional node's fault index), `component` `(m)`;
/// - `fault_names` `(n)` (text).
///
/// Attributes of the file: `format` ([`GREENS_FORMAT`]), `rsf_version`, `dimension`,
/// `origin` ([`OperatorOrigin::code`]), `kernel` (`dense` or `hierarchical`), `epsilon`
/// and `leaf_size` (0 for dense), `relative_error` (`‖S − S_H‖_F/‖S‖_F` measured at
/// set-up), `error_samples`, `stored_entries`, `dense_blocks`, `low_rank_blocks`,
/// `max_rank`, `unit_S`, `unit_traction` (`Pa`), `description`.
///
/// # Errors
/// [`Error::InvalidParameter`] named `s` for another length than `m²` or a non-finite
/// entry, named `greens` for an invalid description ([`GreensFunctions::validate`]);
/// [`Error::Hdf5`] naming the file. The file at `path` is unchanged on error.
pub fn write_greens(path: &Path, greens: &GreensFunctions, s: &[f64]) -> Result<()> {
    greens.validate()?;
    let m = greens.dim();
    if s.len() != m * m {
        return Err(invalid("s", format!("{} entries for m = {m}", s.len())));
    }
    if let Some(i) = s.iter().position(|v| !v.is_finite()) {
        return Err(invalid("s", format!("entry {i} is {}", s[i])));
    }
    let err = h5_at("write the Green's functions into", path);
    replace_atomically(path, |partial| write_file(partial, greens, s).map_err(&err))
}

fn invalid(name: &str, reason: String) -> Error {
    Error::InvalidParameter {
        name: name.into(),
        reason,
    }
}

fn write_file(path: &Path, g: &GreensFunctions, s: &[f64]) -> hdf5::Result<()> {
    let file = File::create(path)?;
    let m = g.dim();
    let rows = |v: &[[f64; 3]]| v.iter().flatten().copied().collect::<Vec<f64>>();
    let indices = |v: &[usize]| v.iter().map(|&i| i as u64).collect::<Vec<u64>>();
    let d = file
        .new_dataset_builder()
        .with_data(view(s, &[m, m]))
        .create("S")?;
    text(&d, "unit", g.units_s())?;
    let d = file
        .new_dataset_builder()
        .with_data(view(&rows(&g.positions), &[m, 3]))
        .create("positions")?;
    text(&d, "unit", "m")?;
    let d = file
        .new_dataset_builder()
        .with_data(view(&rows(&g.directions), &[m, 3]))
        .create("directions")?;
    text(&d, "unit", "1")?;
    let d = file
        .new_dataset_builder()
        .with_data(view(&g.weights, &[m]))
        .create("weights")?;
    text(&d, "unit", g.units_weights())?;
    for (name, v) in [
        ("fault", &g.fault),
        ("node", &g.node),
        ("component", &g.component),
    ] {
        file.new_dataset_builder()
            .with_data(view(&indices(v), &[m]))
            .create(name)?;
    }
    let names = g
        .fault_names
        .iter()
        .map(|n| n.parse::<VarLenUnicode>())
        .collect::<std::result::Result<Vec<_>, _>>()
        .map_err(|e| hdf5::Error::from(format!("fault_names: {e}")))?;
    file.new_dataset_builder()
        .with_data(view(&names, &[names.len()]))
        .create("fault_names")?;
    write_attributes(&file, g)?;
    file.close()
}

fn write_attributes(file: &File, g: &GreensFunctions) -> hdf5::Result<()> {
    let a = &g.accuracy;
    let (epsilon, leaf_size) = match a.kernel {
        FaultKernel::Dense => (0.0, 0),
        FaultKernel::Hierarchical { epsilon, leaf_size } => (epsilon, leaf_size),
    };
    text(file, "format", GREENS_FORMAT)?;
    text(file, "rsf_version", rsf::greens::RSF_VERSION)?;
    text(file, "origin", g.origin.code())?;
    text(file, "kernel", a.kernel.name())?;
    text(file, "unit_S", g.units_s())?;
    text(file, "unit_traction", "Pa")?;
    text(
        file,
        "description",
        "the fault operator S of an rsf model: S[i, j] is the force on slip unknown i from \
         unit slip (1 m) on unknown j; the traction change at i is -S[i, j] / weights[i] \
         (Pa); symmetric positive semi-definite (to the accuracy of an H-matrix kernel)",
    )?;
    number(file, "epsilon", epsilon)?;
    number(file, "relative_error", a.relative_error)?;
    for (name, v) in [
        ("dimension", g.dimension),
        ("leaf_size", leaf_size),
        ("error_samples", a.error_samples),
        ("stored_entries", a.stored_entries),
        ("dense_blocks", a.dense_blocks),
        ("low_rank_blocks", a.low_rank_blocks),
        ("max_rank", a.max_rank),
    ] {
        count(file, name, v)?;
    }
    Ok(())
}

fn number(at: &Location, name: &str, v: f64) -> hdf5::Result<()> {
    at.new_attr::<f64>()
        .shape(())
        .create(name)?
        .write_scalar(&v)
}

fn count(at: &Location, name: &str, v: usize) -> hdf5::Result<()> {
    at.new_attr::<u64>()
        .shape(())
        .create(name)?
        .write_scalar(&(v as u64))
}

/// The Green's functions and the dense `S` (row-major) of a file [`write_greens`] wrote.
///
/// # Errors
/// [`Error::Hdf5`] naming the file for one that cannot be read or lacks a dataset or
/// attribute; [`Error::InvalidParameter`] named `path` for another `format`, datasets of
/// inconsistent shapes, an unknown `origin` or `kernel`, or a description that does not
/// validate.
pub fn read_greens(path: &Path) -> Result<(GreensFunctions, Vec<f64>)> {
    let err = h5_at("read the Green's functions from", path);
    let file = File::open(path).map_err(&err)?;
    let bad = |reason: String| invalid("path", format!("`{}`: {reason}", show_path(path)));
    let format = read_text(&file, "format").map_err(&err)?;
    if format != GREENS_FORMAT {
        return Err(bad(format!("format `{format}`, not `{GREENS_FORMAT}`")));
    }
    let (g, s) = read_file(&file).map_err(&err)?;
    let m = g.weights.len();
    if s.len() != m * m {
        return Err(bad(format!("S of {} entries for {m} weights", s.len())));
    }
    let origin = OperatorOrigin::from_code(&read_text(&file, "origin").map_err(&err)?)?;
    let kernel = match read_text(&file, "kernel").map_err(&err)?.as_str() {
        "dense" => FaultKernel::Dense,
        "hierarchical" => FaultKernel::Hierarchical {
            epsilon: file
                .attr("epsilon")
                .map_err(&err)?
                .read_scalar()
                .map_err(&err)?,
            leaf_size: read_count(&file, "leaf_size").map_err(&err)?,
        },
        other => return Err(bad(format!("kernel `{other}`"))),
    };
    let relative_error: f64 = file
        .attr("relative_error")
        .map_err(&err)?
        .read_scalar()
        .map_err(&err)?;
    let c = |name: &str| read_count(&file, name).map_err(&err);
    let g = GreensFunctions {
        dimension: c("dimension")?,
        origin,
        accuracy: GreensAccuracy {
            kernel,
            relative_error,
            error_samples: c("error_samples")?,
            stored_entries: c("stored_entries")?,
            dense_blocks: c("dense_blocks")?,
            low_rank_blocks: c("low_rank_blocks")?,
            max_rank: c("max_rank")?,
        },
        ..g
    };
    g.validate()?;
    Ok((g, s))
}

/// The datasets of a Green's functions file (the attributes' fields left at defaults).
fn read_file(file: &File) -> hdf5::Result<(GreensFunctions, Vec<f64>)> {
    let f64s = |name: &str| file.dataset(name)?.read_raw::<f64>();
    let idx = |name: &str| -> hdf5::Result<Vec<usize>> {
        Ok(file
            .dataset(name)?
            .read_raw::<u64>()?
            .into_iter()
            .map(|i| i as usize)
            .collect())
    };
    let triples =
        |v: Vec<f64>| -> Vec<[f64; 3]> { v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect() };
    let names: Vec<VarLenUnicode> = file.dataset("fault_names")?.read_raw()?;
    let g = GreensFunctions {
        dimension: 0,
        fault_names: names.iter().map(|n| n.as_str().to_owned()).collect(),
        fault: idx("fault")?,
        node: idx("node")?,
        component: idx("component")?,
        positions: triples(f64s("positions")?),
        weights: f64s("weights")?,
        directions: triples(f64s("directions")?),
        origin: OperatorOrigin::Other,
        accuracy: GreensAccuracy {
            kernel: FaultKernel::Dense,
            relative_error: 0.0,
            error_samples: 0,
            stored_entries: 0,
            dense_blocks: 0,
            low_rank_blocks: 0,
            max_rank: 0,
        },
    };
    Ok((g, f64s("S")?))
}

fn read_text(at: &Location, name: &str) -> hdf5::Result<String> {
    let v: VarLenUnicode = at.attr(name)?.read_scalar()?;
    Ok(v.as_str().to_owned())
}

fn read_count(at: &Location, name: &str) -> hdf5::Result<usize> {
    Ok(at.attr(name)?.read_scalar::<u64>()? as usize)
}
