//! Tests of the run configurations through the programs (docs/design.md, "One run
//! configuration"): random configurations round-trip through each program's command line
//! and through TOML; every setting is in the fingerprint; a `--config` file's keys, the
//! flags over them, the defaults under both; the refusals named as written. Apart from
//! `config.rs`, which the programs import.

mod config_file;
mod fingerprints;
mod round_trips;
