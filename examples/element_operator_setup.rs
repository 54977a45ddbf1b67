//! Set-up, memory and product cost of the boundary-element operator of an element set
//! (`rsf::halfspace::ElementSet` behind `rsf::halfspace_operator::ElementOperator`; issue
//! 83 item 3, issue 85 item 2) at SEAS BP8's size: the square fault `x = 0` of side
//! `cells × 10 m` (BP8: 80 cells) in the whole space (or buried in a half-space), as
//! `cells²` squares (rectangle elements, Okada's full-space term) or `2 cells²` triangles
//! (Nikkhoo & Walter), each split along a diagonal. The operator is a fault alone
//! (`fault_alone_model`) with `ElementOptions::default()`: dense up to 4 096 unknowns, an
//! ℋ-matrix beyond (BP8's 12 800 or 25 600 unknowns: dense would be 1.3 or 5.2 GB). It
//! prints the set-up's wall and CPU time, what was stored, the sampled
//! `‖K − K_H‖_F/‖K‖_F` and the median time of one product; run it under
//! `/usr/bin/time -v` for the peak memory (docs/halfspace.md §10).
//!
//! ```sh
//! cargo run --release --example element_operator_setup -- --elements rectangles
//! cargo run --release --example element_operator_setup -- --elements triangles
//! ```

use std::process::ExitCode;
use std::time::Instant;

use clap::{Parser, ValueEnum};
use rsf::fault_operator::FaultOperator;
use rsf::halfspace::{Element, ElementSet, Medium, RectangleElement, Space, Triangle};
use rsf::halfspace_operator::{fault_alone_model, ElementOperator, ElementOptions};
use rsf_programs::estimates::operator_bytes;
use rsf_programs::guard::{in_range, AnyError, Limits, Plan, Prepared, Program};
use rsf_programs::{cpu_seconds, machine};

#[path = "common/operator_timing.rs"]
mod operator_timing;
use operator_timing::{block_columns, check_epsilon_and_products, median_product_seconds};

/// BP8's cell size (m); the operator's cost does not depend on it (the kernels are
/// scale-free), the number of cells does.
const DX: f64 = 10.0;

/// The elements the fault is cut into.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Elements {
    /// Squares (rectangle elements).
    Rectangles,
    /// Each square split along a diagonal.
    Triangles,
}

/// The medium around the fault.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
enum Around {
    /// The whole space (BP7, BP8).
    Whole,
    /// A half-space, the fault's centre `--depth` below the surface.
    Half,
}

/// Set-up and product cost of an element set's operator at BP8's size.
#[derive(Parser)]
#[command(version)]
struct Cli {
    /// Elements.
    #[arg(long, value_enum, default_value_t = Elements::Rectangles)]
    elements: Elements,
    /// Cells along each side of the square fault.
    #[arg(long, default_value_t = 80)]
    cells: usize,
    /// Whole space or half-space.
    #[arg(long, value_enum, default_value_t = Around::Whole)]
    space: Around,
    /// Depth of the fault's centre in a half-space (m).
    #[arg(long, default_value_t = 2000.0)]
    depth: f64,
    /// Accuracy ε of the ℋ-matrix.
    #[arg(long, default_value_t = 1e-6)]
    epsilon: f64,
    /// Products timed (the median is printed).
    #[arg(long, default_value_t = 11)]
    products: usize,
    #[command(flatten)]
    limits: Limits,
}

impl Cli {
    fn unknowns(&self) -> f64 {
        let n = (self.cells as f64).powi(2);
        match self.elements {
            Elements::Rectangles => 2.0 * n,
            Elements::Triangles => 4.0 * n,
        }
    }
}

impl Program for Cli {
    rsf_programs::name_and_limits!("element_operator_setup");

    fn plan(&self) -> Result<Plan, AnyError> {
        in_range(
            "--cells",
            self.cells as f64,
            (1.0, 2048.0),
            "cells per side",
        )?;
        in_range("--depth", self.depth, (0.0, 1e8), "a depth (m)")?;
        check_epsilon_and_products(self.epsilon, self.products)?;
        if self.space == Around::Half && self.depth < 0.5 * self.cells as f64 * DX {
            return Err(
                "--depth: the fault's top must be below the surface (depth ≥ cells · 10 m / 2)"
                    .into(),
            );
        }
        let m = self.unknowns();
        let dense = m <= ElementOptions::default().dense_max as f64;
        Ok(Plan::new().memory(
            operator_bytes(m, !dense),
            "--cells",
            format!("an element operator of {m} unknowns"),
        ))
    }
}

fn main() -> ExitCode {
    rsf_programs::guard::main(run)
}

/// Builds the fault alone of `elements` and its operator; prints one row.
fn measure<E: Element>(cli: &Cli, elements: Vec<E>, space: Space) -> Result<(), AnyError> {
    // BP8's medium: μ = 32.04 GPa, ν = 0.25.
    let medium = Medium::from_shear_poisson(32.04e9, 0.25)?;
    let (wall, cpu) = (Instant::now(), cpu_seconds());
    let set = ElementSet::new(medium, space, elements)?;
    let model = fault_alone_model(&set)?;
    let options = ElementOptions {
        epsilon: cli.epsilon,
        ..ElementOptions::default()
    };
    let mut op = ElementOperator::fault_alone(&model, &set, &options)?;
    let (setup_wall, setup_cpu) = (wall.elapsed().as_secs_f64(), cpu_seconds() - cpu);
    let m = op.dim();
    let product = median_product_seconds(&mut op, cli.products)?;
    let report = op.report();
    println!("on {}", machine());
    println!(
        "| elements | space | m | set-up wall (s) | set-up CPU (s) | stored f64 | MB | dense MB | dense blocks | low-rank blocks | max rank | ‖K − K_H‖_F/‖K‖_F (sampled) | product (ms, median, 1 thread) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    println!(
        "| {} {:?} | {} | {m} | {setup_wall:.2} | {setup_cpu:.2} | {} | {:.1} | {:.1} | {} | {:.2} |",
        set.n_elements(),
        cli.elements,
        space.name(),
        report.stored_entries,
        report.bytes() as f64 / 1e6,
        8.0 * (m * m) as f64 / 1e6,
        block_columns(report),
        product * 1e3
    );
    Ok(())
}

fn run(cli: Cli, _: Prepared) -> Result<(), AnyError> {
    let (space, z0) = match cli.space {
        Around::Whole => (Space::WholeSpace, 0.0),
        Around::Half => (Space::HalfSpace, -cli.depth),
    };
    let (n, dx) = (cli.cells, DX);
    let side = n as f64 * dx;
    // The fault x = 0: strike along +y (φ = 90°), vertical; x₂ = y, x₃ = −z.
    match cli.elements {
        Elements::Rectangles => {
            let elements =
                RectangleElement::grid([0.0, 0.0, z0], 90.0, 90.0, [side, side], [n, n])?;
            measure(&cli, elements, space)
        }
        Elements::Triangles => {
            let corner = |i: usize, j: usize| {
                [
                    0.0,
                    -0.5 * side + i as f64 * dx,
                    z0 + 0.5 * side - j as f64 * dx,
                ]
            };
            let mut elements = Vec::with_capacity(2 * n * n);
            for j in 0..n {
                for i in 0..n {
                    let (a, b, c, d) = (
                        corner(i, j + 1),
                        corner(i + 1, j + 1),
                        corner(i + 1, j),
                        corner(i, j),
                    );
                    elements.push(Triangle::new([a, b, c])?);
                    elements.push(Triangle::new([a, c, d])?);
                }
            }
            measure(&cli, elements, space)
        }
    }
}
