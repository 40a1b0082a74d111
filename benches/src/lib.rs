//! Benchmarks live in benches/core.rs.
