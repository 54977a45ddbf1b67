//! The direct solver of the velocity problem: exact condensation onto the nonsmooth blocks
//! (docs/math.md §8) and the dense nonsmooth Newton iteration on them.

use std::time::Instant;

use faer::sparse::SparseColMatRef;
use rsf_linalg::{Csc, Parallelism};
use rsf_nonsmooth::{
    check_inputs, BlockNonlinearity, BlockedMatrix, NonsmoothSolver, SolveReport, StepSolver,
    Stopping,
};

use crate::condensation::Condensation;
use crate::error::{Error, Result};
use crate::fault_newton::DenseFault;
use crate::harmonic::harmonic_energy;
use crate::options::DirectOptions;
use crate::partial_cholesky::PartialCholesky;
use rsf_nonsmooth::ProblemError;

/// Block `k` of the node-major vector `v`.
#[inline]
fn load<const D: usize>(v: &[f64], k: usize) -> [f64; D] {
    let mut out = [0.0; D];
    out.copy_from_slice(&v[D * k..D * k + D]);
    out
}

/// What the condensation computed for one set of nonsmooth blocks.
struct Condensed<const D: usize> {
    cond: Condensation<D>,
    fault: DenseFault<D>,
}

/// Direct solver by exact condensation onto the nonsmooth blocks (docs/math.md §8), for
/// single solves ([`NonsmoothSolver`]) and, above all, for the fixed point iterations of a
/// time step ([`StepSolver`]).
///
/// Set-up (once per matrix and set of blocks): the free dofs are split into the interior
/// `R` and the free components `F` of the nonsmooth blocks; faer factorises `A` on them
/// with `R` first (AMD order) and `F` last, which gives the dense Schur complement
/// `S = A_FF − A_FR A_RR⁻¹ A_RF` as the last diagonal block. With an energy-norm matrix `E`
/// the set-up also forms `N = Zᵀ E Z` for the discrete harmonic extension
/// `Z = [−A_RR⁻¹ A_RF; I]` (one multi-right-hand-side sweep), so that the norm of a change of
/// the fault unknowns is exactly the energy norm of the change of the full solution.
///
/// Per time step: one forward sweep gives the condensed right-hand side, every solve works
/// on the `|F|` unknowns only (nonlinear Gauss–Seidel + truncated Newton with dense
/// Cholesky on the soft blocks + line search, see [`DirectOptions::soft_ratio`]), and
/// one backward sweep recovers the interior. No refactorisation while `A` stays.
///
/// Threads ([`with_parallelism`](Self::with_parallelism), default
/// [`Parallelism::default`]): the two halves of the interior in every sweep and the
/// columns of the harmonic extension from [`INTERIOR_PARALLEL_MIN`](crate::INTERIOR_PARALLEL_MIN) interior unknowns on,
/// and the dense Newton factorisations from [`DENSE_PARALLEL_MIN`](crate::DENSE_PARALLEL_MIN) unknowns on. The
/// results do not depend on them.
pub struct DirectSolver<const D: usize> {
    a: Csc,
    fixed: Vec<bool>,
    energy: Option<Csc>,
    opts: DirectOptions,
    par: Parallelism,
    cache: Option<Condensed<D>>,
    in_step: bool,
    /// Scratch of [`StepSolver::current_iterate`] (allocated on its first use).
    peek: Vec<f64>,
}

impl<const D: usize> DirectSolver<D> {
    /// Set-up for the matrix `a` (`n × n`, symmetric, both triangles stored, positive
    /// definite on the free dofs) and fixed dofs `fixed` (length `n`); the condensation is
    /// computed on the first solve for the nonlinearity's active blocks.
    ///
    /// # Errors
    /// Invalid shapes or pattern, `n` not a multiple of `D`, invalid options.
    pub fn new(
        a: SparseColMatRef<'_, usize, f64>,
        fixed: &[bool],
        opts: DirectOptions,
    ) -> Result<Self> {
        opts.stopping.validate()?;
        if !(opts.soft_ratio > 0.0) {
            return Err(ProblemError::InvalidOption("soft_ratio must be positive".into()).into());
        }
        let BlockedMatrix { a, fixed } = BlockedMatrix::<D>::new(Csc::from_faer(a)?, fixed)?;
        Ok(Self {
            a,
            fixed,
            energy: None,
            opts,
            par: Parallelism::default(),
            cache: None,
            in_step: false,
            peek: Vec::new(),
        })
    }

    /// The solver with the parallelism `par` (see the type's documentation); a set-up
    /// already done keeps its results, later work uses `par`.
    pub fn with_parallelism(mut self, par: Parallelism) -> Self {
        self.par = par;
        if let Some(c) = &mut self.cache {
            c.cond.factor.set_parallelism(par);
            c.fault.set_parallelism(par);
        }
        self
    }

    /// The parallelism of the solver (of its set-up, sweeps and dense factorisations).
    pub fn parallelism(&self) -> Parallelism {
        debug_assert!(self.cache.as_ref().is_none_or(|c| {
            c.cond.parallelism() == self.par && c.fault.parallelism() == self.par
        }));
        self.par
    }

    /// Measures changes in the energy norm `‖x‖² = xᵀEx` (`E`: `n × n`, symmetric positive
    /// semidefinite; the paper's `K + M`) instead of the norm of `A`.
    ///
    /// # Errors
    /// [`ProblemError::DimensionMismatch`] if `E` is not `n × n`; non-finite entries.
    pub fn with_energy_norm(mut self, e: SparseColMatRef<'_, usize, f64>) -> Result<Self> {
        let e = Csc::from_faer(e)?;
        if e.nrows != self.a.nrows || e.ncols != self.a.ncols {
            return Err(ProblemError::DimensionMismatch {
                what: "energy-norm matrix",
                expected: self.a.nrows,
                got: e.nrows,
            }
            .into());
        }
        self.energy = Some(e);
        self.cache = None;
        Ok(self)
    }

    /// The solver for another matrix `a` with the same pattern, fixed dofs, energy norm and
    /// options (e.g. `c_M M + c_K K` at another time step): the condensation for the same
    /// blocks reuses this one's ordering and symbolic factorisation, so only the numeric
    /// factorisation, the Schur complement and the harmonic extension are computed again.
    /// A matrix with another pattern is set up from scratch.
    ///
    /// # Errors
    /// As [`new`](Self::new) and [`prepare`](Self::prepare).
    pub fn for_matrix(&self, a: SparseColMatRef<'_, usize, f64>) -> Result<Self> {
        let BlockedMatrix { a, fixed } = BlockedMatrix::<D>::new(Csc::from_faer(a)?, &self.fixed)?;
        let mut solver = Self {
            a,
            fixed,
            energy: self.energy.clone(),
            opts: self.opts.clone(),
            par: self.par,
            cache: None,
            in_step: false,
            peek: Vec::new(),
        };
        if let Some(c) = &self.cache {
            solver.cache = Some(solver.condense(c.cond.blocks(), Some(&c.cond.factor))?);
        }
        Ok(solver)
    }

    /// Computes the condensation for the given blocks now (it is otherwise done on the
    /// first solve).
    ///
    /// # Errors
    /// Blocks out of range or not increasing; `A` not positive definite on the free dofs.
    pub fn prepare(&mut self, blocks: &[usize]) -> Result<()> {
        if self
            .cache
            .as_ref()
            .is_none_or(|c| c.cond.blocks() != blocks)
        {
            self.cache = Some(self.condense(blocks, None)?);
        }
        Ok(())
    }

    /// Entries of the sparse factor (0 before the set-up).
    pub fn factor_nnz(&self) -> usize {
        self.cache.as_ref().map_or(0, |c| c.cond.factor_nnz())
    }

    /// Number of condensed unknowns `|F|` (0 before the set-up).
    pub fn condensed_dim(&self) -> usize {
        self.cache.as_ref().map_or(0, |c| c.fault.num_free())
    }

    /// The condensation onto `blocks`; with `previous`, a factor of a matrix with the same
    /// pattern for the same blocks, whose analysis is reused if the pattern matches.
    fn condense(
        &self,
        blocks: &[usize],
        previous: Option<&PartialCholesky>,
    ) -> Result<Condensed<D>> {
        let cond =
            Condensation::build(&self.a, &self.fixed, blocks, previous)?.with_parallelism(self.par);
        let (factor, order, pos) = (&cond.factor, &cond.order, &cond.pos);
        let s = factor.schur_complement();
        let norm = self.energy.as_ref().map(|e| {
            let nf = order.len() - factor.nr;
            let store_extension = self.opts.stores_extension(order.len(), nf);
            harmonic_energy(factor, e, order, pos, store_extension)
        });
        let fault = DenseFault::new(s, norm, cond.free.clone(), self.opts.soft_ratio, self.par);
        Ok(Condensed { cond, fault })
    }
}

impl<const D: usize> StepSolver<D> for DirectSolver<D> {
    type Error = Error;

    fn name(&self) -> &'static str {
        "direct"
    }

    fn dim(&self) -> usize {
        self.a.nrows
    }

    fn begin_step(&mut self, b: &[f64], v: &[f64], active: &[usize]) -> Result<()> {
        check_inputs(self.a.nrows, b, v)?;
        self.prepare(active)?;
        let cd = self.cache.as_mut().expect("prepared above");
        cd.cond.condense_in_place(b, v);
        let nr = cd.cond.factor.nr;
        cd.fault.g.copy_from_slice(&cd.cond.y[nr..]);
        for (k, &p) in cd.cond.blocks().iter().enumerate() {
            cd.fault.xb[D * k..D * k + D].copy_from_slice(&v[D * p..D * p + D]);
        }
        cd.fault.change = f64::INFINITY;
        cd.fault.residual_valid = false;
        // A step depends on nothing of earlier steps (so a run resumed from a checkpoint is
        // bit-identical): no factorisation carried over.
        cd.fault.forget_factorization();
        self.in_step = true;
        Ok(())
    }

    fn solve_step<N: BlockNonlinearity<D>>(
        &mut self,
        nl: &N,
        stopping: Stopping,
    ) -> Result<SolveReport> {
        stopping.validate()?;
        let cd = match self.cache.as_mut() {
            Some(cd) if self.in_step && cd.cond.blocks() == nl.active_blocks() => cd,
            _ => {
                return Err(ProblemError::InvalidOption(
                    "solve_step needs begin_step with the nonlinearity's active blocks".into(),
                )
                .into())
            }
        };
        cd.fault.solve(nl, stopping)
    }

    fn block(&self, k: usize) -> [f64; D] {
        let cd = self.cache.as_ref().expect("block() inside a step");
        load::<D>(&cd.fault.xb, k)
    }

    fn last_change(&self) -> f64 {
        self.cache
            .as_ref()
            .map_or(f64::INFINITY, |c| c.fault.change)
    }

    fn finish_step(&mut self, v: &mut [f64]) -> Result<()> {
        let done = self.recover(v, true);
        self.in_step = false;
        done
    }

    fn current_iterate(&mut self, v: &mut [f64]) -> Result<()> {
        self.recover(v, false)
    }
}

impl<const D: usize> DirectSolver<D> {
    /// Writes the whole current iterate into `v` (the interior by one backward sweep from
    /// the step's forward-condensed right-hand side): in place at the end of a step
    /// (`in_place`), on a copy inside it, where the right-hand side stays for the step's
    /// further solves.
    fn recover(&mut self, v: &mut [f64], in_place: bool) -> Result<()> {
        let n = self.a.nrows;
        ProblemError::check_length("iterate", n, v.len())?;
        let cd = match self.cache.as_mut() {
            Some(cd) if self.in_step => cd,
            _ => {
                return Err(ProblemError::InvalidOption(
                    "finish_step or current_iterate without begin_step".into(),
                )
                .into())
            }
        };
        let c = &mut cd.cond;
        let nr = c.factor.nr;
        let y = if in_place {
            &mut c.y
        } else {
            self.peek.clear();
            self.peek.extend_from_slice(&c.y);
            &mut self.peek
        };
        for i in 0..cd.fault.num_free() {
            y[nr + i] = cd.fault.xb[cd.fault.comp(i)];
        }
        c.factor.backward_interior(y);
        for (k, &i) in c.order.iter().enumerate() {
            v[i] = y[k];
        }
        if y.iter().any(|x| !x.is_finite()) {
            return Err(ProblemError::NonFinite("direct solution").into());
        }
        Ok(())
    }
}

impl<const D: usize> NonsmoothSolver<D> for DirectSolver<D> {
    type Error = Error;

    fn name(&self) -> &'static str {
        StepSolver::<D>::name(self)
    }

    fn dim(&self) -> usize {
        StepSolver::<D>::dim(self)
    }

    fn stopping(&self) -> Stopping {
        self.opts.stopping
    }

    fn set_stopping(&mut self, stopping: Stopping) -> Result<()> {
        stopping.validate()?;
        self.opts.stopping = stopping;
        Ok(())
    }

    fn solve<N: BlockNonlinearity<D>>(
        &mut self,
        b: &[f64],
        nl: &N,
        v: &mut [f64],
    ) -> Result<SolveReport> {
        let start = Instant::now();
        self.begin_step(b, v, nl.active_blocks())?;
        let stopping = self.opts.stopping;
        let mut report = self.solve_step(nl, stopping)?;
        self.finish_step(v)?;
        report.seconds = start.elapsed().as_secs_f64();
        Ok(report)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::partial_cholesky::tests::split_grid;
    use crate::{DENSE_PARALLEL_MIN, INTERIOR_PARALLEL_MIN};

    /// The two ways of forming `N = Zᵀ E Z` agree: the stored extension's dense product and
    /// the block-by-block forward sweeps (an identity of the factor, not the same sums).
    #[test]
    fn harmonic_energy_by_blocks_equals_the_stored_product() {
        let m = 40;
        // Interface: the first two grid rows (80 unknowns: three blocks of columns).
        let (a, interior, interface) = split_grid(m, 2);
        // E: the grid matrix with another diagonal (SPD, not A).
        let mut e = a.clone();
        for j in 0..e.ncols {
            let (start, end) = (e.col_ptr[j], e.col_ptr[j + 1]);
            for k in start..end {
                if e.row_idx[k] == j {
                    e.val[k] = 4.0 + (j % 7) as f64;
                }
            }
        }
        let (factor, order) = PartialCholesky::new(&a, &interior, &interface).unwrap();
        let mut pos = vec![usize::MAX; a.nrows];
        for (k, &i) in order.iter().enumerate() {
            pos[i] = k;
        }
        let stored = harmonic_energy(&factor, &e, &order, &pos, true);
        let blocks = harmonic_energy(&factor, &e, &order, &pos, false);
        let scale = stored.iter().fold(0.0_f64, |x, v| x.max(v.abs()));
        let diff = stored
            .iter()
            .zip(&blocks)
            .fold(0.0_f64, |x, (p, q)| x.max((p - q).abs()));
        assert!(
            scale > 1.0 && diff <= 1e-13 * scale,
            "max |ΔN| = {diff:e}, max |N| = {scale:e}"
        );
        println!("max |ΔN| = {diff:e} of max |N| = {scale:e}");
    }

    /// `φ(v) = w (√(1 + v²) − 1)`: smooth, convex, Hessian at most `w`, so every block of a
    /// grid with `w` of the order of the diagonal is soft (the whole fault in the Newton step).
    struct Soft {
        nodes: Vec<usize>,
        w: f64,
    }

    impl BlockNonlinearity<1> for Soft {
        fn active_blocks(&self) -> &[usize] {
            &self.nodes
        }
        fn value(&self, _: usize, v: &[f64; 1]) -> f64 {
            self.w * ((1.0 + v[0] * v[0]).sqrt() - 1.0)
        }
        fn minimize_block(
            &self,
            _: usize,
            a: &[[f64; 1]; 1],
            r: &[f64; 1],
            free: &[bool; 1],
            v: &mut [f64; 1],
        ) {
            if !free[0] {
                return;
            }
            // a x + φ'(x) = r, increasing in x: bisection on a bracket.
            let f = |x: f64| a[0][0] * x + self.w * x / (1.0 + x * x).sqrt() - r[0];
            let (mut lo, mut hi) = (
                -(r[0].abs() + self.w) / a[0][0],
                (r[0].abs() + self.w) / a[0][0],
            );
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid == lo || mid == hi {
                    break;
                }
                if f(mid) > 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            v[0] = 0.5 * (lo + hi);
        }
        fn linearize(&self, _: usize, v: &[f64; 1]) -> rsf_nonsmooth::Linearization<1> {
            let q = 1.0 + v[0] * v[0];
            rsf_nonsmooth::Linearization::Smooth {
                gradient: [self.w * v[0] / q.sqrt()],
                hessian: [[self.w / (q * q.sqrt())]],
            }
        }
        fn directional_derivatives(&self, _: usize, v: &[f64; 1], d: &[f64; 1]) -> (f64, f64) {
            let s = self.w * v[0] / (1.0 + v[0] * v[0]).sqrt() * d[0];
            (s, s)
        }
    }

    /// The bounds of the stopping norm (direct/norm_bounds.rs) skip most of its evaluations
    /// and change no bit: the same iterate, iterations, correction and change with and without
    /// them, for an absolute and a relative stopping test, in several solves from the last
    /// one's iterate (as a coupled time step makes them).
    #[test]
    fn norm_bounds_leave_the_bits_unchanged() {
        let m = 40;
        // 160 fault nodes (≥ NORM_BOUNDS_MIN), all soft.
        let (a, fixed, nl) = grid_with_fault(m, 18..22, 2.0);
        let n = m * m;
        let run = |bounds: bool, stopping: Stopping| {
            let opts = DirectOptions {
                stopping,
                ..DirectOptions::default()
            };
            let mut s = energy_solver(&a, &fixed, opts);
            s.prepare(&nl.nodes).unwrap();
            if !bounds {
                s.cache.as_mut().unwrap().fault.without_norm_bounds();
            }
            let mut v = vec![0.0; n];
            let mut bits = Vec::new();
            for solve in 0..4 {
                let b: Vec<f64> = (0..n)
                    .map(|i| (0.37 * i as f64 + solve as f64).sin() * 10f64.powi(solve - 1))
                    .collect();
                let report = s.solve(&b, &nl, &mut v).unwrap();
                bits.extend(v.iter().map(|x| x.to_bits()));
                bits.push(report.iterations as u64);
                bits.push(report.correction.to_bits());
                bits.push(s.last_change().to_bits());
            }
            let fault = &s.cache.as_ref().unwrap().fault;
            assert_eq!(fault.norm_bounds().is_some(), bounds);
            (bits, fault.norm_evaluations())
        };
        for stopping in [
            DirectOptions::default().stopping,
            Stopping {
                absolute: 1e-10,
                relative: 0.0,
                max_iterations: 200,
            },
        ] {
            let (with, evaluations) = run(true, stopping);
            let (without, all_evaluations) = run(false, stopping);
            assert!(with == without, "{stopping:?}");
            println!("{stopping:?}: {evaluations} of {all_evaluations} norm evaluations");
            assert!(evaluations < all_evaluations, "{stopping:?}");
        }
    }

    /// The `m × m` grid matrix, nothing fixed, and a fault of the grid rows `rows` with the
    /// smooth nonlinearity of weight `w`.
    fn grid_with_fault(
        m: usize,
        rows: std::ops::Range<usize>,
        w: f64,
    ) -> (faer::sparse::SparseColMat<usize, f64>, Vec<bool>, Soft) {
        let nodes = (rows.start * m..rows.end * m).collect();
        (
            crate::memory::tests::grid(m),
            vec![false; m * m],
            Soft { nodes, w },
        )
    }

    /// The direct solver of `a` with `opts`, its stopping norm `a`'s energy norm.
    fn energy_solver(
        a: &faer::sparse::SparseColMat<usize, f64>,
        fixed: &[bool],
        opts: DirectOptions,
    ) -> DirectSolver<1> {
        DirectSolver::<1>::new(a.as_ref(), fixed, opts)
            .unwrap()
            .with_energy_norm(a.as_ref())
            .unwrap()
    }

    /// The parallelism survives a set-up, a later change and a set-up for another matrix.
    #[test]
    fn parallelism_reaches_every_part_of_the_solver() {
        let m = 12;
        let a = crate::memory::tests::grid(m);
        let fixed = vec![false; m * m];
        let nodes: Vec<usize> = (0..m).collect();
        let three = Parallelism::rayon(3);
        let mut s = DirectSolver::<1>::new(a.as_ref(), &fixed, DirectOptions::default())
            .unwrap()
            .with_parallelism(three);
        s.prepare(&nodes).unwrap();
        let parts = |s: &DirectSolver<1>| {
            let cd = s.cache.as_ref().unwrap();
            (
                s.parallelism(),
                cd.cond.parallelism(),
                cd.fault.parallelism(),
            )
        };
        assert_eq!(parts(&s), (three, three, three));
        assert_eq!(
            parts(&s.for_matrix(a.as_ref()).unwrap()),
            (three, three, three)
        );
        let s = s.with_parallelism(Parallelism::SEQ);
        let seq = Parallelism::SEQ;
        assert_eq!(parts(&s), (seq, seq, seq));
        assert_eq!(
            DirectSolver::<1>::new(a.as_ref(), &fixed, DirectOptions::default())
                .unwrap()
                .parallelism(),
            Parallelism::default()
        );
    }

    /// A problem above every threshold (5 360 interior unknowns ≥ INTERIOR_PARALLEL_MIN,
    /// a Newton system of 1 040 ≥ DENSE_PARALLEL_MIN unknowns, the harmonic extension
    /// stored and block by block) gives the same bits with one thread, with rayon's 1, 2
    /// and 4, and in a pool of one thread.
    #[test]
    fn direct_solver_is_bit_identical_for_every_thread_count() {
        let m = 80;
        // The fault: 13 grid rows in the middle.
        let (a, fixed, nl) = grid_with_fault(m, 40..53, 1.0);
        let n = m * m;
        let b: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
        let run = |par: Parallelism, max_extension_bytes: usize| {
            let opts = DirectOptions {
                max_extension_bytes,
                ..DirectOptions::default()
            };
            let mut s = energy_solver(&a, &fixed, opts).with_parallelism(par);
            assert_eq!(s.parallelism(), par);
            let mut v = vec![0.0; n];
            let report = s.solve(&b, &nl, &mut v).unwrap();
            let cd = s.cache.as_ref().unwrap();
            assert_eq!(cd.cond.factor.interior_par(), par);
            assert!(cd.cond.factor.nr >= INTERIOR_PARALLEL_MIN);
            assert!(
                cd.fault.factored_len() >= DENSE_PARALLEL_MIN,
                "Newton system of {} unknowns",
                cd.fault.factored_len()
            );
            assert_eq!(
                s.opts.stores_extension(n, nl.nodes.len()),
                max_extension_bytes > 1
            );
            let mut bits: Vec<u64> = v.iter().map(|x| x.to_bits()).collect();
            bits.push(report.iterations as u64);
            bits
        };
        for max_extension_bytes in [DirectOptions::default().max_extension_bytes, 1] {
            let reference = run(Parallelism::SEQ, max_extension_bytes);
            for threads in [1, 2, 4] {
                let par = Parallelism::rayon(threads);
                assert!(run(par, max_extension_bytes) == reference, "{par:?}");
            }
            let one = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .unwrap();
            let pooled = one.install(|| run(Parallelism::rayon(2), max_extension_bytes));
            assert!(pooled == reference);
        }
    }
}
