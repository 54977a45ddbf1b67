//! Coincident nodes of a Gmsh file: two nodes at one place (within a tolerance relative to
//! the smallest cell edge) make a crack the user did not declare — the mesh falls apart
//! along it. They are refused naming both node tags, or merged when asked
//! ([`GmshOptions::merge_coincident`](super::GmshOptions)).

use std::collections::HashMap;

use super::lexer::error;
use crate::Result;

/// Relative tolerance: nodes closer than this times the smallest cell edge coincide.
pub(super) const RELATIVE_TOLERANCE: f64 = 1e-6;

/// For every vertex (in `tags` order, coordinates `vertices`, cells `connectivity` with
/// stride `D + 1`), the vertex it coincides with and is merged into (the one of the
/// smallest node tag; itself if none).
///
/// # Errors
/// [`Error::Gmsh`](crate::Error::Gmsh) in section `Nodes` naming the first two coincident
/// node tags, their place and distance, unless `merge`.
pub(super) fn representatives<const D: usize>(
    tags: &[u64],
    vertices: &[[f64; D]],
    connectivity: &[usize],
    merge: bool,
) -> Result<Vec<usize>> {
    let dist = |a: usize, b: usize| {
        (0..D)
            .map(|r| (vertices[a][r] - vertices[b][r]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let mut h_min = f64::INFINITY;
    for cell in connectivity.chunks_exact(D + 1) {
        for (i, &a) in cell.iter().enumerate() {
            for &b in &cell[i + 1..] {
                h_min = h_min.min(dist(a, b));
            }
        }
    }
    let tol = RELATIVE_TOLERANCE * h_min;
    let mut rep: Vec<usize> = (0..vertices.len()).collect();
    if !(tol > 0.0 && tol.is_finite()) {
        return Ok(rep);
    }
    // A hash grid of spacing `tol`: coincident vertices are in neighbouring cells.
    let key = |v: &[f64; D]| {
        let mut k = [0i64; 3];
        for r in 0..D {
            k[r] = (v[r] / tol).floor() as i64;
        }
        k
    };
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
    for (i, v) in vertices.iter().enumerate() {
        let k = key(v);
        let mut found = None;
        for offset in 0..3usize.pow(D as u32) {
            let mut n = k;
            let mut o = offset;
            for slot in n.iter_mut().take(D) {
                *slot += (o % 3) as i64 - 1;
                o /= 3;
            }
            if let Some(j) = grid
                .get(&n)
                .and_then(|js| js.iter().copied().find(|&j| dist(i, j) <= tol))
            {
                found = Some(j);
                break;
            }
        }
        match found {
            Some(j) if !merge => {
                return Err(error(
                    None,
                    "Nodes",
                    format!(
                        "nodes {} and {} coincide at {:?} (distance {:e} m, within {:e} of the \
                         smallest cell edge {:e} m): a crack nobody declared — remove the \
                         duplicate, declare a fault inside the body, or merge them \
                         (GmshOptions::merge_coincident)",
                        tags[j],
                        tags[i],
                        vertices[j],
                        dist(i, j),
                        RELATIVE_TOLERANCE,
                        h_min
                    ),
                ))
            }
            Some(j) => rep[i] = rep[j],
            None => grid.entry(k).or_default().push(i),
        }
    }
    Ok(rep)
}
