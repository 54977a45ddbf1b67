//! Adaptive cross approximation of one admissible block from its entries (docs/math.md
//! §13.3): ACA+ (pivots from a reference row and a reference column, both kept as
//! residuals; Bebendorf & Grzhibovskis 2006) on every pair of components separately, each
//! stopped by the newest cross and by a seeded random sample of the residual's entries.
//!
//! With `c` interleaved components (unknown `i` is component `i mod c` of its point) a
//! block splits into `c²` component blocks (rows of component `a`, columns of component
//! `b`) that may be independent low-rank matrices, some of them zero; a pivot search in
//! one row and one column sees only the components of that row and column, so each
//! component pair gets its own search. The sample check catches what the reference row
//! and column miss inside one component pair.

use crate::error::Error;
use crate::lowrank::{max_useful_rank, LowRank};
use crate::rng::SplitMix64;

/// Tolerances and seed of the compression of one block.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AcaParams {
    /// Relative Frobenius accuracy of the block (split evenly over the component pairs).
    pub eps: f64,
    /// Number of interleaved components `c ≥ 1`.
    pub components: usize,
    /// Seed of the block's random choices (reference columns, residual samples).
    pub seed: u64,
}

/// The crosses of one component block `ms × ns`: `U` (`ms × k`) and `V` (`ns × k`),
/// column-major.
struct Crosses {
    u: Vec<f64>,
    v: Vec<f64>,
    rank: usize,
}

/// Compresses the `m × n` block whose entries `entry(i, j)` returns (block-local indices;
/// row `i` is component `row_comp[i]`, column `j` component `col_comp[j]`, both `<
/// params.components`) by ACA+ on each component pair. `None` if the total rank reaches
/// the point where the block is cheaper stored dense. Evaluates `O(k (m + n))` entries
/// per component pair (the crosses, the reference rows and columns, `m_a + n_b` samples).
pub(crate) fn compress_block(
    m: usize,
    n: usize,
    row_comp: &[usize],
    col_comp: &[usize],
    entry: &mut dyn FnMut(usize, usize) -> Result<f64, Error>,
    params: AcaParams,
) -> Result<Option<LowRank>, Error> {
    let c = params.components.max(1);
    let kmax = max_useful_rank(m, n);
    let rows: Vec<Vec<usize>> = (0..c)
        .map(|a| (0..m).filter(|&i| row_comp[i] == a).collect())
        .collect();
    let cols: Vec<Vec<usize>> = (0..c)
        .map(|b| (0..n).filter(|&j| col_comp[j] == b).collect())
        .collect();
    // Samples of every component block first: their mean square estimates each block's
    // norm, and the sum the whole block's, to which every stopping test is relative.
    let mut samples: Vec<Samples> = Vec::with_capacity(c * c);
    for (a, ra) in rows.iter().enumerate() {
        for (b, cb) in cols.iter().enumerate() {
            let mut rng = SplitMix64::new(pair_seed(params.seed, a, b));
            let mut local = |r: usize, s: usize| entry(ra[r], cb[s]);
            samples.push(Samples::draw(ra.len(), cb.len(), &mut rng, &mut local)?);
        }
    }
    let block_norm2: f64 = samples.iter().map(|s| s.norm2_estimate()).sum();
    let pair_eps = params.eps / c as f64;
    let mut found: Vec<(usize, usize, Crosses)> = Vec::new();
    let mut total_rank = 0;
    for (a, ra) in rows.iter().enumerate() {
        for (b, cb) in cols.iter().enumerate() {
            if ra.is_empty() || cb.is_empty() {
                continue;
            }
            let mut rng = SplitMix64::new(pair_seed(params.seed, a, b) ^ 0x5851_F42D_4C95_7F2D);
            let mut local = |r: usize, s: usize| entry(ra[r], cb[s]);
            let budget = kmax.saturating_sub(total_rank);
            let sample = &mut samples[a * c + b];
            let Some(x) = aca_plus(
                ra.len(),
                cb.len(),
                &mut local,
                sample,
                pair_eps,
                block_norm2,
                budget,
                &mut rng,
            )?
            else {
                return Ok(None);
            };
            total_rank += x.rank;
            found.push((a, b, x));
        }
    }
    // Embed the component blocks' crosses in the block (zeros in the other components).
    let mut u = vec![0.0; m * total_rank];
    let mut v = vec![0.0; n * total_rank];
    let mut l0 = 0;
    for (a, b, x) in &found {
        let (ra, cb) = (&rows[*a], &cols[*b]);
        for l in 0..x.rank {
            let (ul, vl) = (&mut u[(l0 + l) * m..], &mut v[(l0 + l) * n..]);
            for (r, &i) in ra.iter().enumerate() {
                ul[i] = x.u[l * ra.len() + r];
            }
            for (s, &j) in cb.iter().enumerate() {
                vl[j] = x.v[l * cb.len() + s];
            }
        }
        l0 += x.rank;
    }
    Ok(Some(LowRank {
        u,
        v,
        rank: total_rank,
    }))
}

/// A seed per block and component pair.
fn pair_seed(seed: u64, a: usize, b: usize) -> u64 {
    let mut r = SplitMix64::new(seed ^ ((a as u64) << 32 | b as u64));
    r.next_u64()
}

/// Seeded random positions of a component block, with the residual there.
struct Samples {
    /// `(row, column, residual entry)`.
    at: Vec<(usize, usize, f64)>,
    /// `ms ns / samples` (1 when every entry is sampled).
    scale: f64,
}

impl Samples {
    /// `min(ms ns, ms + ns)` positions: every entry when there are no more, otherwise
    /// uniform with replacement.
    fn draw(
        ms: usize,
        ns: usize,
        rng: &mut SplitMix64,
        entry: &mut dyn FnMut(usize, usize) -> Result<f64, Error>,
    ) -> Result<Self, Error> {
        let total = ms * ns;
        let count = total.min(ms + ns);
        let mut at = Vec::with_capacity(count);
        if count == total {
            for s in 0..ns {
                for r in 0..ms {
                    at.push((r, s, entry(r, s)?));
                }
            }
        } else {
            for _ in 0..count {
                let k = rng.below(total as u64) as usize;
                let (r, s) = (k % ms, k / ms);
                at.push((r, s, entry(r, s)?));
            }
        }
        let scale = if count == 0 {
            0.0
        } else {
            total as f64 / count as f64
        };
        Ok(Self { at, scale })
    }

    /// `(ms ns / samples) Σ residual²`: unbiased estimate of the residual's `‖·‖_F²`.
    fn norm2_estimate(&self) -> f64 {
        self.scale * self.at.iter().map(|&(_, _, x)| x * x).sum::<f64>()
    }

    /// Subtracts the cross `u vᵀ` from the sampled residual.
    fn subtract(&mut self, u: &[f64], v: &[f64]) {
        for (r, s, x) in &mut self.at {
            *x -= u[*r] * v[*s];
        }
    }

    /// The position of the largest residual sample in a row not `used`, if not zero.
    fn worst(&self, used: &[bool]) -> Option<(usize, usize)> {
        let mut best: Option<(usize, usize, f64)> = None;
        for &(r, s, x) in &self.at {
            if x != 0.0 && !used[r] && best.is_none_or(|(_, _, b)| x.abs() > b) {
                best = Some((r, s, x.abs()));
            }
        }
        best.map(|(r, s, _)| (r, s))
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Index and absolute value of the largest `|x_i|` over the indices not `used` (first on
/// ties); `None` if all are used.
fn argmax_unused(x: &[f64], used: &[bool]) -> Option<(usize, f64)> {
    let mut best: Option<(usize, f64)> = None;
    for (i, (&xi, &ui)) in x.iter().zip(used).enumerate() {
        if !ui && best.is_none_or(|(_, b)| xi.abs() > b) {
            best = Some((i, xi.abs()));
        }
    }
    best
}

/// A row or a column of a block.
#[derive(Debug, Clone, Copy)]
enum Line {
    Row(usize),
    Col(usize),
}

/// The residual crosses so far, and the residual rows and columns they need.
struct Approximation {
    us: Vec<Vec<f64>>,
    vs: Vec<Vec<f64>>,
    /// `‖Σ u_l v_lᵀ‖_F²`, updated exactly.
    norm2: f64,
}

impl Approximation {
    /// Row `i` (`ns` long) or column `j` (`ms`) of the residual into `out`:
    /// `entry(i, s) − Σ_l u_l[i] v_l[s]` or `entry(r, j) − Σ_l v_l[j] u_l[r]`, the crosses
    /// subtracted in order.
    fn residual(
        &self,
        line: Line,
        entry: &mut dyn FnMut(usize, usize) -> Result<f64, Error>,
        out: &mut [f64],
    ) -> Result<(), Error> {
        let (k, coefficients, vectors) = match line {
            Line::Row(i) => (i, &self.us, &self.vs),
            Line::Col(j) => (j, &self.vs, &self.us),
        };
        for (s, o) in out.iter_mut().enumerate() {
            *o = match line {
                Line::Row(i) => entry(i, s)?,
                Line::Col(j) => entry(s, j)?,
            };
        }
        for (cl, xl) in coefficients.iter().zip(vectors) {
            let c = cl[k];
            for (o, x) in out.iter_mut().zip(xl) {
                *o -= c * x;
            }
        }
        Ok(())
    }

    /// A cross's pivot `(i, j)` from the line `from`: its residual (into `row` for a row,
    /// `col` for a column), its largest entry at an unused index of the other direction
    /// (`used`), the residual line through it into the other buffer; `None` if every index
    /// is used.
    fn pivot(
        &self,
        from: Line,
        entry: &mut dyn FnMut(usize, usize) -> Result<f64, Error>,
        (row, col): (&mut [f64], &mut [f64]),
        used: &[bool],
    ) -> Result<Option<(usize, usize)>, Error> {
        let (first, second) = match from {
            Line::Row(_) => (row, col),
            Line::Col(_) => (col, row),
        };
        self.residual(from, entry, first)?;
        let Some((k, _)) = argmax_unused(first, used) else {
            return Ok(None);
        };
        let (across, pivot) = match from {
            Line::Row(i) => (Line::Col(k), (i, k)),
            Line::Col(j) => (Line::Row(k), (k, j)),
        };
        self.residual(across, entry, second)?;
        Ok(Some(pivot))
    }

    /// Appends the cross `u vᵀ` and returns `‖u‖ ‖v‖`.
    fn push(&mut self, u: Vec<f64>, v: Vec<f64>) -> f64 {
        let (nu2, nv2) = (dot(&u, &u), dot(&v, &v));
        let cross: f64 = self
            .us
            .iter()
            .zip(&self.vs)
            .map(|(ul, vl)| dot(ul, &u) * dot(vl, &v))
            .sum();
        self.norm2 = (self.norm2 + 2.0 * cross + nu2 * nv2).max(0.0);
        self.us.push(u);
        self.vs.push(v);
        (nu2 * nv2).sqrt()
    }

    fn into_crosses(self) -> Crosses {
        let rank = self.us.len();
        Crosses {
            u: self.us.concat(),
            v: self.vs.concat(),
            rank,
        }
    }
}

/// A new reference column (random among the unused ones) and its residual; `None` if
/// every column is used.
fn new_reference(used: &[bool], rng: &mut SplitMix64) -> Option<usize> {
    let free = used.iter().filter(|&&u| !u).count();
    if free == 0 {
        return None;
    }
    let mut k = rng.below(free as u64) as usize;
    for (j, &u) in used.iter().enumerate() {
        if !u {
            if k == 0 {
                return Some(j);
            }
            k -= 1;
        }
    }
    None
}

/// ACA+ on one `ms × ns` component block, stopped when the newest cross and the sampled
/// residual are both at most `eps ‖B‖_F`, with `‖B‖_F²` the larger of `block_norm2` (the
/// whole block's sampled estimate) and the approximation's own. `None` if the rank would
/// pass `kmax`.
#[allow(clippy::too_many_arguments)]
fn aca_plus(
    ms: usize,
    ns: usize,
    entry: &mut dyn FnMut(usize, usize) -> Result<f64, Error>,
    samples: &mut Samples,
    eps: f64,
    block_norm2: f64,
    kmax: usize,
    rng: &mut SplitMix64,
) -> Result<Option<Crosses>, Error> {
    let mut x = Approximation {
        us: Vec::new(),
        vs: Vec::new(),
        norm2: 0.0,
    };
    let mut row_used = vec![false; ms];
    let mut col_used = vec![false; ns];
    // Reference column (random) and row (where the reference column is smallest).
    let mut jref = new_reference(&col_used, rng);
    let mut cref = vec![0.0; ms];
    if let Some(j) = jref {
        x.residual(Line::Col(j), entry, &mut cref)?;
    }
    let mut iref = argmin_abs(&cref);
    let mut rref = vec![0.0; ns];
    if let Some(i) = iref {
        x.residual(Line::Row(i), entry, &mut rref)?;
    }
    let mut row = vec![0.0; ns];
    let mut col = vec![0.0; ms];
    let mut forced: Option<usize> = None;
    loop {
        let tol2 = eps * eps * block_norm2.max(x.norm2);
        // The pivot: a forced row (from the sample check), else the larger of the
        // reference column's and reference row's largest residual entries.
        let by_col = iref.and_then(|_| argmax_unused(&rref, &col_used));
        let by_row = jref.and_then(|_| argmax_unused(&cref, &row_used));
        let lines = (&mut row[..], &mut col[..]);
        let cross = if let Some(i) = forced.take() {
            x.pivot(Line::Row(i), entry, lines, &col_used)?
        } else {
            let cmax = by_row.map_or(0.0, |(_, v)| v);
            let rmax = by_col.map_or(0.0, |(_, v)| v);
            if cmax == 0.0 && rmax == 0.0 {
                // The references are reproduced: the samples decide.
                let refs = (&mut jref, &mut cref[..]);
                let used = (&row_used[..], &col_used[..]);
                forced = follow(&mut x, entry, samples, tol2, refs, used, rng)?;
                if forced.is_none() {
                    break;
                }
                continue;
            }
            if rmax > cmax {
                let (j, _) = by_col.unwrap_or((0, 0.0));
                x.pivot(Line::Col(j), entry, lines, &row_used)?
            } else {
                let (i, _) = by_row.unwrap_or((0, 0.0));
                x.pivot(Line::Row(i), entry, lines, &col_used)?
            }
        };
        let Some((i, j)) = cross else {
            break;
        };
        row_used[i] = true;
        col_used[j] = true;
        let pivot = row[j];
        if pivot == 0.0 {
            // A residual row or column that vanishes (the reference saw round-off).
            continue;
        }
        if x.us.len() >= kmax {
            return Ok(None);
        }
        let u = col.clone();
        let v: Vec<f64> = row.iter().map(|r| r / pivot).collect();
        if let Some(jr) = jref {
            let b = v[jr];
            for (c, ui) in cref.iter_mut().zip(&u) {
                *c -= b * ui;
            }
        }
        if let Some(ir) = iref {
            let a = u[ir];
            for (r, vj) in rref.iter_mut().zip(&v) {
                *r -= a * vj;
            }
        }
        samples.subtract(&u, &v);
        let size = x.push(u, v);
        // Used-up references are replaced.
        if jref.is_some_and(|jr| col_used[jr]) {
            jref = new_reference(&col_used, rng);
            if let Some(jr) = jref {
                x.residual(Line::Col(jr), entry, &mut cref)?;
            }
        }
        if iref.is_some_and(|ir| row_used[ir]) {
            iref = new_reference(&row_used, rng);
            if let Some(ir) = iref {
                x.residual(Line::Row(ir), entry, &mut rref)?;
            }
        }
        let tol2 = eps * eps * block_norm2.max(x.norm2);
        if size * size <= tol2 {
            // The newest cross is small: the samples decide.
            let refs = (&mut jref, &mut cref[..]);
            let used = (&row_used[..], &col_used[..]);
            forced = follow(&mut x, entry, samples, tol2, refs, used, rng)?;
            if forced.is_none() {
                break;
            }
        }
    }
    Ok(Some(x.into_crosses()))
}

/// The sample check where the crosses would stop (`tol2`, the squared tolerance): `None`
/// if the samples' residual is at most `tol2` or every sample's row is used (ACA+ stops).
/// Else it fails at the worst sample `(r, s)` and returns its row `r`, the next pivot
/// row, after following it: the reference column (`jref`, its residual `cref`) moves to
/// `s` if unused, so that the search goes on where the samples found the residual; and
/// the samples are drawn anew (with their residual), so that the next check is made on
/// entries that guided no pivot — a sample set that chose pivots is reproduced at its
/// own positions first and would stop early. Costs `ms + ns` entries per failed check,
/// each followed by at least one cross.
#[allow(clippy::too_many_arguments)]
fn follow(
    x: &mut Approximation,
    entry: &mut dyn FnMut(usize, usize) -> Result<f64, Error>,
    samples: &mut Samples,
    tol2: f64,
    (jref, cref): (&mut Option<usize>, &mut [f64]),
    (row_used, col_used): (&[bool], &[bool]),
    rng: &mut SplitMix64,
) -> Result<Option<usize>, Error> {
    if samples.norm2_estimate() <= tol2 {
        return Ok(None);
    }
    let Some((r, s)) = samples.worst(row_used) else {
        return Ok(None);
    };
    if !col_used[s] {
        *jref = Some(s);
        x.residual(Line::Col(s), entry, cref)?;
    }
    let (ms, ns) = (cref.len(), col_used.len());
    *samples = Samples::draw(ms, ns, rng, entry)?;
    for (u, v) in x.us.iter().zip(&x.vs) {
        samples.subtract(u, v);
    }
    Ok(Some(r))
}

/// Index of the smallest `|x_i|` (first on ties); `None` for an empty slice.
fn argmin_abs(x: &[f64]) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, &xi) in x.iter().enumerate() {
        if best.is_none_or(|(_, b)| xi.abs() < b) {
            best = Some((i, xi.abs()));
        }
    }
    best.map(|(i, _)| i)
}
