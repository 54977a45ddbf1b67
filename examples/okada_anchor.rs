//! The 3-D finite-element model against Okada's half-space (issue 55, docs/three-d.md
//! "Against Okada's half-space (issue 55)"): uniform slip on a vertical rectangle — buried
//! strike slip, surface-breaking strike slip, buried dip slip — prescribed at every split
//! pair of an internal fault (`ModelBuilder::internal_slip_at`), the static problem solved once (the direct
//! solver on the finest mesh, or TNNMG's multigrid on a refinement hierarchy: `--method`),
//! and the surface displacement and the on-fault traction compared with Okada
//! (1992) as `rsf-halfspace` evaluates it (docs/halfspace.md). The same comparison as
//! `tests/okada_anchor.rs` (the frame, the signs, the rim grown by h/2 and the traction
//! from the nodal forces: the library's `rsf::okada_comparison`), here over finer
//! cells and several domain sizes, with the far faces held at Okada's displacement or at
//! rest. The mesh: spacing `h = h0 / 2^k` along the fault and one cell beyond its rim,
//! then the coarsest mesh's cells graded from `h0` by `--ratio` per cell to the far faces
//! (`--far` from the fault's centre line, in units of the fault's width W = 1), each split
//! into `2^k`: every cell shrinks with `h`.
//!
//! Prints a markdown table: per case, far-face condition, domain and `h`, the vertices,
//! the wall time, the largest surface-displacement error (within |x|, |y| ≤ L = 2 W, at
//! least L/4 from the ends of a surface trace) relative to the largest surface
//! displacement there, the largest traction error at the fault nodes at least W/4 from
//! the rim and the surface relative to the largest traction there, and the orders
//! between successive `h`. No output files.
//!
//! ```sh
//! cargo run --release --example okada_anchor -- --levels 0,1,2,3 --far 3
//! cargo run --release --example okada_anchor -- --levels 1,2 --far 3,6,12 --held zero
//! cargo run --release --example okada_anchor -- --method multigrid --levels 2,3,4 --far 2
//! ```
//!
//! With `--method multigrid` the coarsest mesh (spacing `h0` along the fault, whose
//! rectangle lies on its lines) is refined `level` times and the reference is Okada's
//! rectangle with the model's moment, shrunk by `h/2` on the inner edges
//! (`rsf::okada_comparison::compare_refined`); memory grows like the vertices.
//! `--slip smooth` compares one smooth slip's fields with its boundary-element
//! discretisation; `--slip modes --modes k` compares the finite-element and boundary-element
//! fault operators in the operator norm on the span of the first `k × k` sine modes of the
//! rectangle (`compare_modes`, docs/three-d.md "The operator norm on resolved slips"):
//!
//! ```sh
//! cargo run --release --example okada_anchor -- --method multigrid --slip modes --cases buried --levels 1,2,3 --far 2 --modes 1
//! ```

use std::time::Instant;

use clap::{Parser, ValueEnum};
use rsf::okada_comparison::{
    compare_held, compare_modes, compare_refined, compare_smooth, hierarchy_vertices, Errors,
    Fault, ModeComparison, Solver, SLIP,
};
use rsf_programs::guard::{in_range, number, refuse, AnyError, Limits, Plan, Prepared, Program};

/// The rectangles compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Case {
    /// Strike slip on `|x| ≤ 1`, depth 0.5 to 1.5.
    Buried,
    /// Strike slip on `|x| ≤ 1`, from the surface to depth 1.
    Surface,
    /// Dip slip (hanging wall y < 0 up) on the buried rectangle.
    Dip,
}

impl Case {
    fn fault(self) -> Fault {
        match self {
            Case::Buried => Fault {
                half_length: 1.0,
                top: 0.5,
                bottom: 1.5,
                slip: [SLIP, 0.0, 0.0],
            },
            Case::Surface => Fault {
                half_length: 1.0,
                top: 0.0,
                bottom: 1.0,
                slip: [SLIP, 0.0, 0.0],
            },
            Case::Dip => Fault {
                half_length: 1.0,
                top: 0.5,
                bottom: 1.5,
                slip: [0.0, 0.0, SLIP],
            },
        }
    }
}

/// What the far faces are held at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Held {
    /// Okada's displacement (the truncation of the half-space is not in the error).
    Okada,
    /// Zero (the error of the truncated domain is).
    Zero,
}

/// How the model is meshed and solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Method {
    /// The finest mesh built directly (the polygon grown by h/2 to Okada's rectangle),
    /// the direct solver: memory grows like the direct factor.
    Direct,
    /// The coarsest mesh refined `level` times (the polygon on the coarsest lines, Okada's
    /// rectangle shrunk by h/2), TNNMG's multigrid: memory linear in the vertices.
    Multigrid,
}

/// The slip imposed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Slip {
    /// Uniform on the rectangle, against Okada's closed form.
    Uniform,
    /// `cos(π x / 2a) cos(π (z − z_c) / W)` times the case's direction (buried cases
    /// only), against its boundary-element discretisation (cells of side h on the nodes),
    /// the far faces held at that field; with `--method multigrid`.
    Smooth,
    /// The first `--modes` × `--modes` sine modes of the rectangle in both directions (the
    /// case's direction is not used: `--cases buried`), the two operators' Galerkin
    /// matrices compared in the operator norm on their span; with `--method multigrid`.
    Modes,
}

/// The finite-element model of uniform slip on a rectangle against Okada's half-space.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// Cases, comma separated.
    #[arg(long, value_delimiter = ',', default_value = "buried,surface,dip")]
    cases: Vec<Case>,
    /// The coarsest cell size on the fault (units of its width W = 1).
    #[arg(long, default_value_t = 0.5)]
    h0: f64,
    /// Refinement levels, comma separated: level k has h = h0 / 2^k on the fault and every
    /// graded interval of the coarsest mesh split into 2^k.
    #[arg(long, value_delimiter = ',', default_value = "0,1,2")]
    levels: Vec<u32>,
    /// Distances of the far faces from the fault's centre line (units of W), comma
    /// separated.
    #[arg(long, value_delimiter = ',', default_value = "3")]
    far: Vec<f64>,
    /// What the far faces are held at.
    #[arg(long, value_enum, default_value = "okada")]
    held: Held,
    /// How the model is meshed and solved.
    #[arg(long, value_enum, default_value = "direct")]
    method: Method,
    /// The slip imposed.
    #[arg(long, value_enum, default_value = "uniform")]
    slip: Slip,
    /// Sine modes per direction along strike and dip with `--slip modes` (1 to 8)
    /// [default: 2].
    #[arg(long)]
    modes: Option<u32>,
    /// Growth of the cells per cell away from the fault, on the coarsest mesh.
    #[arg(long, default_value_t = 1.3)]
    ratio: f64,
    #[command(flatten)]
    limits: Limits,
}

impl Program for Cli {
    rsf_programs::name_and_limits!("okada_anchor");

    fn plan(&self) -> Result<Plan, AnyError> {
        rsf_programs::guard::distinct("--levels", &self.levels)?;
        rsf_programs::guard::distinct("--far", &self.far)?;
        if !(self.h0 > 0.0 && self.h0 <= 0.5) {
            return Err(refuse(
                "--h0",
                number(self.h0),
                "must be in (0, 0.5] (units of the fault's width)",
            ));
        }
        if let Some(k) = self.levels.iter().find(|&&k| k > 6) {
            return Err(refuse("--levels", k, "at most 6"));
        }
        for &f in &self.far {
            in_range(
                "--far",
                f,
                (2.0, 1e3),
                "the fault and its surrounding cells inside",
            )?;
        }
        in_range("--ratio", self.ratio, (1.0, 2.0), "the growth of the cells")?;
        let slip = format!("{:?}", self.slip).to_lowercase();
        if self.slip != Slip::Uniform && self.method != Method::Multigrid {
            return Err(refuse("--slip", slip, "needs --method multigrid"));
        }
        if self.slip != Slip::Uniform && self.cases.contains(&Case::Surface) {
            return Err(refuse(
                "--slip",
                slip,
                "is for the buried cases (--cases buried,dip)",
            ));
        }
        if let Some(m) = self.modes {
            if self.slip != Slip::Modes {
                return Err(refuse(
                    "--modes",
                    m,
                    "a setting of --slip modes: without it, it would be ignored",
                ));
            }
            if !(1..=8).contains(&m) {
                return Err(refuse("--modes", m, "must be in 1..=8"));
            }
        }
        // The coarsest mesh graded from h0 to the far faces (about 2 W of uniform cells
        // around the fault), every interval split into 2^k: per half-axis
        // 2^k · geometric_grading_len(h0, 1.5, ratio, far) intervals, 4 n³ vertices;
        // 35 kB per vertex as the 3-D slider's direct solver; 12 kB with multigrid
        // (measured: docs/three-d.md).
        let k = self.levels.iter().copied().max().unwrap_or(0);
        let far = self.far.iter().copied().fold(2.0, f64::max);
        let (vertices, per_vertex) = match self.method {
            Method::Direct => {
                let n = 2f64.powi(k as i32)
                    * rsf::fem::geometric_grading_len(self.h0, 1.5, self.ratio, far);
                (4.0 * n * n * n, rsf_scenes::Slider3dScene::BYTES_PER_NODE)
            }
            // The hierarchy's vertices exactly (its coarsest mesh's lines).
            Method::Multigrid => {
                let mut most = 0.0f64;
                for case in &self.cases {
                    let mesh = (self.h0, k, self.ratio);
                    most = most.max(hierarchy_vertices(case.fault(), mesh, far)?);
                }
                (most, MULTIGRID_BYTES_PER_VERTEX)
            }
        };
        Ok(Plan::new().memory(
            vertices * per_vertex,
            "--levels, --far, --h0",
            format!("level {k}, far {far}: about {vertices:.3e} vertices"),
        ))
    }
}

/// Peak resident bytes per vertex of a [`Method::Multigrid`] row, rounded up: 11.7 kB
/// measured at 216 330 and at 815 298 vertices (docs/three-d.md; the builder's change of
/// variables is the peak).
const MULTIGRID_BYTES_PER_VERTEX: f64 = 12e3;

fn main() -> std::process::ExitCode {
    rsf_programs::guard::main(run)
}

fn run(cli: Cli, prepared: Prepared) -> Result<(), AnyError> {
    if cli.slip == Slip::Modes {
        return run_modes(cli, prepared);
    }
    let at_okada = cli.held == Held::Okada;
    println!(
        "| case | far faces | far | h | vertices | wall (s) | surface error | order | \
         traction error | order | jump error (m) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for &case in &cli.cases {
        for &far in &cli.far {
            let mut previous: Option<Errors> = None;
            for &level in &cli.levels {
                let t = Instant::now();
                let mesh = (cli.h0, level, cli.ratio);
                let e = match cli.method {
                    Method::Direct => compare_held(case.fault(), mesh, far, at_okada)?,
                    Method::Multigrid if cli.slip == Slip::Smooth => {
                        compare_smooth(case.fault(), mesh, far, Solver::Multigrid)?
                    }
                    Method::Multigrid => {
                        compare_refined(case.fault(), mesh, far, at_okada, Solver::Multigrid)?
                    }
                };
                let h = e.h;
                let wall = t.elapsed().as_secs_f64();
                let rate = |a: f64, b: f64, ha: f64| (a / b).ln() / (ha / e.h).ln();
                let (p_s, p_t) = previous
                    .as_ref()
                    .map_or((String::new(), String::new()), |p| {
                        (
                            format!("{:.2}", rate(p.surface, e.surface, p.h)),
                            format!("{:.2}", rate(p.traction, e.traction, p.h)),
                        )
                    });
                println!(
                    "| {case:?} | {:?} | {far} | {h} | {} | {wall:.1} | {:.3e} | {p_s} | {:.3e} | \
                     {p_t} | {:.1e} |",
                    cli.held, e.vertices, e.surface, e.traction, e.jump
                );
                previous = Some(e);
            }
        }
    }
    Ok(())
}

/// `--slip modes`: the two operators' relative difference in the operator norm on the
/// modes' span, per case (its rectangle), far and level, and its order in `h`.
fn run_modes(cli: Cli, _: Prepared) -> Result<(), AnyError> {
    println!(
        "| far | h | vertices | modes | wall (s) | ‖Ĝ_FE − Ĝ_BEM‖₂/‖Ĝ_BEM‖₂ | order | \
         ‖Ĝ_FE‖₂/‖Ĝ_BEM‖₂ | worst mode | FE asymmetry |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for &case in &cli.cases {
        for &far in &cli.far {
            let mut previous: Option<ModeComparison> = None;
            for &level in &cli.levels {
                let t = Instant::now();
                let mesh = (cli.h0, level, cli.ratio);
                let e = compare_modes(case.fault(), mesh, far, cli.modes.unwrap_or(2))?;
                let wall = t.elapsed().as_secs_f64();
                let order = previous.as_ref().map_or(String::new(), |p| {
                    format!("{:.2}", (p.operator / e.operator).ln() / (p.h / e.h).ln())
                });
                println!(
                    "| {far} | {} | {} | {} | {wall:.1} | {:.3e} | {order} | {:.4} | {:.3e} | \
                     {:.1e} |",
                    e.h, e.vertices, e.modes, e.operator, e.norm_ratio, e.worst_mode, e.asymmetry
                );
                previous = Some(e);
            }
        }
    }
    Ok(())
}
