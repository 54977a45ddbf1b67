//! The SCEC SEAS benchmark BP1-QD (Erickson et al. 2020; docs/seas-bp1.md): a vertical
//! strike-slip fault in an antiplane half-space, regularised rate-and-state friction with
//! the aging law, radiation damping, 3000 years of earthquake cycles. The program lives in
//! [`rsf_programs::seas_bp1`] (its flags there and in `--help`), so that the `rsf-mpi`
//! crate runs the same program on MPI ranks.
//!
//! ```text
//! cargo run --release --example seas_bp1 -- --out out/seas_bp1
//! cargo run --release --example seas_bp1 -- --out out/bp1_coarse --dz 200 --end-years 600
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::seas_bp1::main()
}
