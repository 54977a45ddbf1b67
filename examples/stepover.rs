//! A stepover between two strike-slip strands in map view (plane strain, quasi-dynamic;
//! docs/fault-networks.md): two parallel strands with SEAS BP1's friction, loaded by creep
//! beyond their far ends, over many earthquake cycles, with the catalogue of which strand
//! each event ruptured. The program lives in [`rsf_programs::stepover`] (its flags there and
//! in `--help`).
//!
//! ```sh
//! cargo run --release --example stepover -- --gap-km 1 --overlap-km 2 --out out/stepover
//! cargo run --release --example stepover -- --gap-km 4 --dx 50 --end-years 1500 --out out/stepover_4km
//! ```

fn main() -> std::process::ExitCode {
    rsf_programs::stepover::main()
}
