//! A coarse SEAS BP3-QD (a thrust or normal fault dipping under a free surface, plane
//! strain, quasi-dynamic; docs/seas-bp3.md). The program lives in
//! [`rsf_programs::seas_bp3`] (its flags there and in `--help`), so that the `rsf-mpi`
//! crate runs the same program on MPI ranks.
//!
//! ```sh
//! cargo run --release --example seas_bp3 -- --dip 60 --out out/bp3_60 --end-years 300
//! cargo run --release --example seas_bp3 -- --dip 30 --dx 250 --out out/bp3_30
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::seas_bp3::main()
}
