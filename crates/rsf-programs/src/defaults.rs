//! Every program's defaults fit this project's reference machine (2 cores, 24 GB; issue 86,
//! "Defaults that run"): each program's flags as `--help` gives them — and the one-flag
//! choices a user makes first (the variant, the kernel, the source) — planned and checked
//! against the program's own default bounds (`--max-memory-gb 16`, `--max-output-gb 10`),
//! so that the defaults are not refused by their own guard. The plan builds nothing
//! (`Program::plan`); the runs themselves are in the benchmarks' tables (docs/).

#[cfg(test)]
mod tests {
    use crate::guard::{parse_from, Program};

    /// `P` with `flags` after its name: planned, and the plan within the defaults' bounds.
    fn fits<P: Program>(flags: &[&str]) {
        let args = std::iter::once(P::NAME).chain(flags.iter().copied());
        let (program, _) =
            parse_from::<P, _, _>(args).unwrap_or_else(|e| panic!("{} {flags:?}: {e}", P::NAME));
        let plan = program
            .plan()
            .unwrap_or_else(|e| panic!("{} {flags:?}: the plan is refused: {e}", P::NAME));
        eprintln!(
            "{} {flags:?}: estimated {:.2} GB",
            P::NAME,
            plan.memory_bytes() / 1e9
        );
        let limits = program.limits();
        assert_eq!(limits.max_memory_gb, 16.0, "the default bound changed");
        if let Err(e) = plan.check(limits) {
            panic!(
                "{} {flags:?}: estimated {:.1} GB, refused: {e}",
                P::NAME,
                plan.memory_bytes() / 1e9
            );
        }
    }

    #[test]
    fn the_sliders_defaults_fit() {
        fits::<crate::pipping_slider::Cli>(&[]);
        fits::<crate::slider_3d::Cli>(&[]);
        fits::<crate::distributed_sweep::Args>(&[]);
    }

    #[cfg(feature = "seas")]
    #[test]
    fn the_seas_programs_defaults_fit() {
        fits::<crate::seas_bp1::Args>(&["--out", "out/seas_bp1"]);
        fits::<crate::seas_bp3::Args>(&[]);
        fits::<crate::seas_bp5::Args>(&[]);
        fits::<crate::seas_bp5::Args>(&["--kernel", "fe"]);
        for variant in ["a", "s", "c"] {
            fits::<crate::seas_bp6::Args>(&["--variant", variant]);
        }
        fits::<crate::seas_bp7::Args>(&[]);
        fits::<crate::seas_bp7::Args>(&["--law", "slip"]);
        fits::<crate::seas_bp8::Args>(&[]);
        fits::<crate::seas_bp8::Args>(&["--source", "pw"]);
    }

    #[cfg(feature = "seas")]
    #[test]
    fn the_network_programs_defaults_fit() {
        fits::<crate::stepover::Args>(&[]);
        fits::<crate::bp5_pair::Args>(&[]);
        fits::<crate::bp5_pair::Args>(&["--kernel", "fe"]);
    }
}
