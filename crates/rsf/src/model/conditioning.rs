//! Whether an assembled scene can be computed in double precision: a cheap (`O(nnz)`)
//! estimate from the diagonals of `K` and `M`, the load, `u₀` and the loading
//! (docs/reliability.md, "Conditioning").
//!
//! The material values themselves cannot make the time-step matrix `A = c_M M + c_K K`
//! ill-conditioned: for `c_M, c_K ≥ 0` its condition number is at most
//! `max(cond M, cond K)` (`λ_max(A) ≤ c_M λ_max(M) + c_K λ_max(K)`, `λ_min(A) ≥ c_M λ_min(M)
//! + c_K λ_min(K)`, and `(a + b)/(c + d) ≤ max(a/c, b/d)`), and those depend on the mesh,
//! not on E or ρ. What fails for a Young's modulus of 1e-300 Pa or a gravity of 1e200 m/s²
//! is **magnitude** (displacements of 1e290 m, entries whose squares in the energy norm and
//! the error estimate overflow) and **resolution** (a slip of `L` added to a displacement
//! `10¹⁸ L` is lost in round-off). Those are what [`ProblemScales::check`] tests.

use rsf_fem::SparseMatrix;

use crate::error::{Error, Result};

/// The range of magnitudes every scale of a problem must lie in:
/// `[√f64::MIN_POSITIVE, √f64::MAX] ≈ [1.5e-154, 1.3e154]`. The energy norm
/// `√(vᵀ(K + M)v)` and the root mean squares of the error estimate square them; outside,
/// the squares underflow or overflow.
pub fn representable_range() -> (f64, f64) {
    (f64::MIN_POSITIVE.sqrt(), f64::MAX.sqrt())
}

/// The smallest admissible ratio `L / D` of the characteristic slip distance `L` to the
/// displacement scale `D` (the largest of `|u₀|∞`, `|F|∞ / min K_ii` and the loading
/// displacement `|v_load| T`): `1e-12`, so that a slip of `L` added to a displacement of `D`
/// keeps about 12 of its 53 bits (`L ≥ 4500 ulp(D)`).
pub const SLIP_RESOLUTION: f64 = 1e-12;

/// Scales of an assembled problem, from its free dofs (`O(nnz)`): what
/// [`check`](Self::check) compares with the double range and with each other.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProblemScales {
    /// Smallest and largest diagonal entry of `K` over the free dofs (N/m per unit
    /// thickness in 2D).
    pub stiffness: (f64, f64),
    /// Smallest and largest diagonal entry of `M` over the free dofs (kg), if any.
    pub mass: Option<(f64, f64)>,
    /// `|F|∞` over the free dofs (N).
    pub load: f64,
    /// `|u₀|∞` (m), the initial equilibrium.
    pub displacement: f64,
    /// `|F|∞ / min K_ii` (m): the displacement the largest load gives at the softest dof
    /// alone, an estimate of the static displacement that needs no solve.
    pub displacement_estimate: f64,
}

/// One failed comparison: the quantity, its value, and the fields that set it.
struct Finding {
    what: String,
    fields: Vec<&'static str>,
}

impl ProblemScales {
    /// The scales of the problem with stiffness `K`, mass `M`, load `F`, initial
    /// displacement `u₀` and constrained dofs `fixed` (all of one length `n`).
    pub fn new(
        stiffness: &SparseMatrix,
        mass: Option<&SparseMatrix>,
        load: &[f64],
        initial_displacement: &[f64],
        fixed: &[bool],
    ) -> Self {
        Self::on_columns(stiffness, mass, load, initial_displacement, fixed, None)
    }

    /// As [`new`](Self::new) for matrices of only the columns of the nodes with
    /// `columns[node]` (`None`: whole matrices; `C = n / columns.len()` dofs per node):
    /// the diagonal ranges of `K` and `M` are over the kept nodes' free dofs only — the
    /// whole model's are the smallest and largest of the processes' (a reduction the caller
    /// does), and so is `|F|∞ / min K_ii` (then `|F|∞` over the smallest `min K_ii`);
    /// `(0, 0)` if no free dof is kept. `|F|∞` and `|u₀|∞` are of the whole vectors.
    pub fn on_columns(
        stiffness: &SparseMatrix,
        mass: Option<&SparseMatrix>,
        load: &[f64],
        initial_displacement: &[f64],
        fixed: &[bool],
        columns: Option<&[bool]>,
    ) -> Self {
        let free = |i: &usize| !fixed.get(*i).copied().unwrap_or(false);
        let per_node = columns.map_or(1, |k| (stiffness.ncols() / k.len().max(1)).max(1));
        let kept =
            |i: &usize| columns.is_none_or(|k| k.get(*i / per_node).copied().unwrap_or(false));
        let range = |m: &SparseMatrix| {
            let d = diagonal(m);
            let r = d
                .iter()
                .enumerate()
                .filter(|(i, _)| free(i) && kept(i))
                .fold((f64::INFINITY, 0.0_f64), |(lo, hi), (_, &x)| {
                    (nan_min(lo, x.abs()), nan_max(hi, x.abs()))
                });
            if columns.is_some() && r == (f64::INFINITY, 0.0) {
                (0.0, 0.0)
            } else {
                r
            }
        };
        let stiffness = range(stiffness);
        let load = (0..load.len())
            .filter(free)
            .fold(0.0_f64, |m, i| nan_max(m, load[i].abs()));
        Self {
            stiffness,
            mass: mass.map(range),
            load,
            displacement: initial_displacement
                .iter()
                .fold(0.0_f64, |m, x| nan_max(m, x.abs())),
            // No stiffness at all (a fault alone, Model::fault_only): no estimate.
            displacement_estimate: if load == 0.0 || stiffness.1 == 0.0 {
                0.0
            } else {
                load / stiffness.0
            },
        }
    }

    /// The whole model's scales from those of the processes' column models
    /// ([`on_columns`](Self::on_columns), one per process, in any order): the smallest and
    /// largest diagonal entries over the processes that keep a free dof (a part without
    /// one, `(0, 0)`, is left out), `|F|∞ / min K_ii` with the smallest `min K_ii`; `|F|∞`
    /// and `|u₀|∞` are every process's (the largest is taken). `NaN` anywhere stays `NaN`.
    /// Exact (minima and maxima), so every process that combines the same parts gets the
    /// same bits.
    ///
    /// # Panics
    /// If `parts` is empty.
    pub fn combined(parts: &[ProblemScales]) -> Self {
        assert!(!parts.is_empty(), "the scales of at least one process");
        let range = |ranges: &mut dyn Iterator<Item = (f64, f64)>| {
            ranges
                .filter(|&r| r != (0.0, 0.0))
                .fold(None, |acc: Option<(f64, f64)>, (lo, hi)| {
                    Some(acc.map_or((lo, hi), |(a, b)| (nan_min(a, lo), nan_max(b, hi))))
                })
                .unwrap_or((0.0, 0.0))
        };
        let stiffness = range(&mut parts.iter().map(|p| p.stiffness));
        let mass = parts[0]
            .mass
            .map(|_| range(&mut parts.iter().filter_map(|p| p.mass)));
        let load = parts.iter().fold(0.0_f64, |m, p| nan_max(m, p.load));
        Self {
            stiffness,
            mass,
            load,
            displacement: parts
                .iter()
                .fold(0.0_f64, |m, p| nan_max(m, p.displacement)),
            displacement_estimate: if load == 0.0 || stiffness.1 == 0.0 {
                0.0
            } else {
                load / stiffness.0
            },
        }
    }

    /// Checks that every scale is representable ([`representable_range`]) and that a slip
    /// of `slip_distance` is resolvable against the displacements ([`SLIP_RESOLUTION`]).
    ///
    /// - `coefficients`: the integrator's `(c_M, c_K)` at the smallest and the largest time
    ///   step of the run, with the fields that set those steps; the diagonal of `A = c_M M
    ///   + c_K K` is checked at each;
    /// - `loading_displacement`: `|v_load| · T` (m), with its fields;
    /// - `fields`: the scene fields behind `K` (`stiffness`), `M` (`mass`), `F` (`load`)
    ///   and `u₀` (`displacement`), and `L` (`slip`).
    ///
    /// # Errors
    /// [`Error::IllConditioned`] naming the first failed quantity and the fields to change.
    pub fn check(
        &self,
        coefficients: &[((f64, f64), &[&'static str])],
        loading_displacement: (f64, &[&'static str]),
        slip_distance: f64,
        fields: &ScaleFields,
    ) -> Result<()> {
        let (lo, hi) = representable_range();
        let mut findings = Vec::new();
        let mut scale = |what: &str, x: f64, fields: &[&'static str]| {
            // Zero is exact (no load, no gravity); everything else within the range.
            if x != 0.0 && !(x >= lo && x <= hi) {
                findings.push(Finding {
                    what: format!(
                        "{what} = {x:e} is outside the representable range [{lo:.1e}, {hi:.1e}] \
                         (its square must be a normal double)"
                    ),
                    fields: fields.to_vec(),
                });
            }
        };
        scale("min K_ii", self.stiffness.0, fields.stiffness);
        scale("max K_ii", self.stiffness.1, fields.stiffness);
        if let Some((m_lo, m_hi)) = self.mass {
            scale("min M_ii", m_lo, fields.mass);
            scale("max M_ii", m_hi, fields.mass);
        }
        scale("|F|∞", self.load, fields.load);
        scale("|u₀|∞", self.displacement, fields.displacement);
        scale(
            "|F|∞ / min K_ii",
            self.displacement_estimate,
            fields.displacement,
        );
        scale("|v_load| T", loading_displacement.0, loading_displacement.1);
        for &((c_m, c_k), time_fields) in coefficients {
            let mut fs = time_fields.to_vec();
            fs.extend_from_slice(fields.stiffness);
            let (m_lo, m_hi) = self.mass.unwrap_or((0.0, 0.0));
            let a_hi = c_m * m_hi + c_k * self.stiffness.1;
            let a_lo = c_m * m_lo + c_k * self.stiffness.0;
            if self.mass.is_some() && c_m != 0.0 {
                fs.extend_from_slice(fields.mass);
            }
            scale(
                &format!("max A_ii (c_M = {c_m:e}, c_K = {c_k:e})"),
                a_hi,
                &fs,
            );
            scale(
                &format!("min A_ii (c_M = {c_m:e}, c_K = {c_k:e})"),
                a_lo,
                &fs,
            );
        }
        if let Some(f) = findings.into_iter().next() {
            return Err(ill(f));
        }
        // Resolution: a slip of L against the largest displacement.
        let candidates = [
            (self.displacement, "|u₀|∞", fields.displacement),
            (
                self.displacement_estimate,
                "|F|∞ / min K_ii",
                fields.displacement,
            ),
            (loading_displacement.0, "|v_load| T", loading_displacement.1),
        ];
        let (d, name, d_fields) =
            candidates.into_iter().fold(
                (0.0, "", &[][..]),
                |best, c| if c.0 > best.0 { c } else { best },
            );
        if d > 0.0 && !(slip_distance >= SLIP_RESOLUTION * d) {
            let mut fs = fields.slip.to_vec();
            fs.extend_from_slice(d_fields);
            return Err(ill(Finding {
                what: format!(
                    "the slip distance L = {slip_distance:e} m is below {SLIP_RESOLUTION:e} × \
                     the displacement scale {name} = {d:e} m: slips of L would be lost in the \
                     round-off of the displacements"
                ),
                fields: fs,
            }));
        }
        Ok(())
    }
}

/// The scene fields behind each scale, for the errors of [`ProblemScales::check`].
#[derive(Debug, Clone, Copy)]
pub struct ScaleFields {
    /// Behind `K`.
    pub stiffness: &'static [&'static str],
    /// Behind `M`.
    pub mass: &'static [&'static str],
    /// Behind `F`.
    pub load: &'static [&'static str],
    /// Behind `u₀` (and `|F|∞ / min K_ii`).
    pub displacement: &'static [&'static str],
    /// Behind `L`.
    pub slip: &'static [&'static str],
}

fn ill(f: Finding) -> Error {
    let mut fields = f.fields;
    let mut seen = std::collections::HashSet::new();
    fields.retain(|x| seen.insert(*x));
    Error::IllConditioned {
        fields: fields.into_iter().map(str::to_owned).collect(),
        reason: f.what,
    }
}

/// `max(a, b)`, NaN if either is NaN (`f64::max` drops a NaN: a NaN entry would pass).
fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// `min(a, b)`, NaN if either is NaN.
fn nan_min(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.min(b)
    }
}

/// The diagonal of a square CSC matrix (0 where it has no entry).
pub(crate) fn diagonal(m: &SparseMatrix) -> Vec<f64> {
    let (cp, ri, val) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
    (0..m.ncols().min(m.nrows()))
        .map(|j| {
            let range = cp[j]..cp[j + 1];
            ri[range.clone()]
                .iter()
                .position(|&i| i == j)
                .map_or(0.0, |k| val[range.start + k])
        })
        .collect()
}
