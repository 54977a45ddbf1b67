//! Runs the stability cases of `crates/rsf/tests/suite/stability.rs` (issue 6) and prints the
//! markdown table of `docs/stability.md`.
//!
//! `cargo run --release --example stability_table [-- NAME-SUBSTRING...]`

#[path = "../crates/rsf/tests/suite/stability.rs"]
mod stability;

use stability::Expect;

fn outcome(o: &stability::Outcome) -> String {
    match &o.error {
        None if o.finite => "Ok".into(),
        None => "**non-finite**".into(),
        Some(rsf::Error::FixedPointNotConverged {
            step,
            iterations,
            history,
            ..
        }) => format!(
            "FixedPointNotConverged (step {step}, {iterations} it., last correction {:.1e})",
            history.last().copied().unwrap_or(f64::NAN)
        ),
        Some(rsf::Error::Friction(e)) => format!("Friction: {e}"),
        Some(e) => e.to_string().chars().take(80).collect(),
    }
}

/// The stability cases of `crates/rsf/tests/suite/stability.rs` as the markdown table of
/// docs/stability.md.
#[derive(clap::Parser)]
#[command(version)]
struct Cli {
    /// Run only the cases whose name contains one of these.
    filter: Vec<String>,
    #[command(flatten)]
    limits: rsf_programs::guard::Limits,
}

impl rsf_programs::guard::Program for Cli {
    rsf_programs::name_and_limits!("stability_table");

    fn plan(&self) -> Result<rsf_programs::guard::Plan, rsf_programs::guard::AnyError> {
        // Fixed cases of the paper's slider at levels ≤ 3; the table goes to the terminal.
        Ok(rsf_programs::guard::Plan::new().memory(
            1e9,
            "(none)",
            "the stability cases (levels ≤ 3)",
        ))
    }
}

fn main() -> std::process::ExitCode {
    rsf_programs::guard::main(|cli: Cli, _| {
        table(&cli.filter);
        Ok(())
    })
}

/// Runs the cases whose name contains one of `filter` (all if empty) and prints the table.
fn table(filter: &[String]) {
    println!(
        "| case | what | steps | outcome | as expected | FPI mean / max | solver it. per solve (max per step) | steps with ω = 0.5 | max V (m/s) | time (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for c in stability::cases() {
        if !filter.is_empty() && !filter.iter().any(|f| c.name.contains(f.as_str())) {
            continue;
        }
        let o = stability::run_case(&c);
        let expected = match c.expect {
            Expect::Ok => "Ok",
            Expect::FixedPointNotConverged => "FixedPointNotConverged",
            Expect::InvalidParameter => "InvalidParameter",
        };
        let in_peak =
            c.expect != Expect::Ok || (o.max_slip_rate >= c.peak.0 && o.max_slip_rate <= c.peak.1);
        let ok = if o.as_expected(c.expect) && in_peak {
            format!("yes ({expected})")
        } else {
            format!("**NO** (expected {expected})")
        };
        let relaxed = match c.paper_relaxation {
            Some(w) if w >= 1.0 => format!("— (ω ≡ 1; rule fired in {})", o.relaxed_steps),
            _ => o.relaxed_steps.to_string(),
        };
        println!(
            "| {} | {} | {}/{} | {} | {} | {:.2} / {} | {:.1} ({}) | {} | {:.2e} | {:.2} |",
            c.name,
            c.what,
            o.steps_done,
            c.steps,
            outcome(&o),
            ok,
            o.fpi_mean,
            o.fpi_max,
            o.solver_per_solve,
            o.solver_max,
            relaxed,
            o.max_slip_rate,
            o.seconds
        );
    }
}
