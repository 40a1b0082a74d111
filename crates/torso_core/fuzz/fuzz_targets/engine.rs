//! Coverage-guided fuzzing of the engine's entry points (nightly):
//!
//! ```text
//! cd crates/torso_core && cargo +nightly fuzz run engine -- -max_total_time=300
//! ```
//!
//! The calls and their checks are `tests/fuzz_driver`, which `cargo test --test fuzz` also runs
//! on seeded inputs; a crash found here goes there as a regression.
#![no_main]

use libfuzzer_sys::fuzz_target;

#[path = "../../tests/fuzz_driver/mod.rs"]
mod fuzz_driver;

fuzz_target!(|data: &[u8]| fuzz_driver::run(data));
