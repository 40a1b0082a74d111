//! A fuzz harness on stable Rust: byte strings drive a sequence of calls on the public entry
//! points (a tracker fed 3D joints or keypoints and a depth image, a forecaster, a streaming
//! filter, the plane fit, the assignment solver), with NaN, infinities, huge and tiny values,
//! odd sizes and out-of-order time stamps. Every call must return (never panic), a refused call
//! must leave its object as it was, and an accepted one must give finite numbers.
//!
//! `cargo test --test fuzz` runs a fixed set of seeded byte strings (what CI runs); with
//! `TORSO_FUZZ_CASES=N` it runs N more, drawn from the clock. The seed of a byte string that
//! ever fails goes into `REGRESSIONS` below, so that it is run for good.

mod fuzz_driver;

use fuzz_driver::run;

/// Seeds whose byte strings once failed, with what they found.
const REGRESSIONS: &[u64] = &[
    // A refused tracker frame that had changed the tracker (a joint at 1e308 m made a pose the
    // forecaster refused after the track had taken the frame); a filter window of 1e308 samples
    // taken and filtered to infinity.
    1796151871291658040,
    // A forecast at a horizon of about 1e308 s: NaN from the plain trend's infinity times a
    // zero weight.
    1796151892679108150,
];

/// Byte strings from a seed (a 64-bit linear congruential generator).
fn bytes(seed: u64, len: usize) -> Vec<u8> {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    (0..len)
        .map(|_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 56) as u8
        })
        .collect()
}

#[test]
fn every_call_returns_and_a_refused_one_changes_nothing() {
    for &seed in REGRESSIONS {
        run(&bytes(seed, 4096));
    }
    for seed in 0..300 {
        run(&bytes(seed, 4096));
    }
    let extra: u64 = std::env::var("TORSO_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    let start = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    for k in 0..extra {
        let seed = start.wrapping_add(k);
        let data = bytes(seed, 4096);
        let outcome = std::panic::catch_unwind(|| run(&data));
        assert!(
            outcome.is_ok(),
            "seed {seed} failed: add bytes({seed}, 4096) to REGRESSIONS"
        );
    }
}
