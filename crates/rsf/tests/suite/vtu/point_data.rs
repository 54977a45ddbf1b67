//! A VTU piece's point data as numbers: a module of `vtu` in `rsf`'s suite, and of
//! `crates/rsf-hdf5/tests/common`, which includes this file by `#[path]`.

/// The point data `name` of a frame's `piece`, flattened (a vector per vertex: its
/// components one after the other).
///
/// # Panics
/// The piece has no such point data, or not as numbers.
pub fn point_data(piece: &vtkio::model::UnstructuredGridPiece, name: &str) -> Vec<f64> {
    let attr = piece
        .data
        .point
        .iter()
        .find(|a| a.name() == name)
        .unwrap_or_else(|| panic!("no point data `{name}`"));
    let vtkio::model::Attribute::DataArray(array) = attr else {
        panic!("`{name}` is not a data array")
    };
    array
        .data
        .clone()
        .cast_into::<f64>()
        .expect("numeric point data")
}
