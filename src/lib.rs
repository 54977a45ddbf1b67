//! Shared helpers for the examples and benches of the rsf workspace (not a library for users).
