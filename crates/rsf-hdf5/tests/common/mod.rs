//! What the integration tests share: temporary folders, the point data of a VTU frame,
//! numbers as bits.
#![allow(dead_code)]

/// A fresh folder for `name` under the target directory's tmp.
pub fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The point data `name` of a VTU frame.
pub fn vtu_field(path: &std::path::Path, name: &str) -> Vec<f64> {
    let vtk = vtkio::Vtk::import(path).expect("valid VTK XML");
    let vtkio::model::DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
        panic!("not an unstructured grid")
    };
    let piece = pieces[0].load_piece_data(None).expect("inline piece");
    point_data::point_data(&piece, name)
}

#[path = "../../../rsf/tests/suite/vtu/point_data.rs"]
mod point_data;

/// Bits, so that NaN (off the fault) compares equal to NaN.
pub fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}
