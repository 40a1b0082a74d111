//! # torso_core
//!
//! The per-frame mathematics of torsocast, after "Human Torso Pose Forecasting for the Real
//! World" (thesis chapter 3): the least-squares torso plane, per-joint temporal gating, the
//! Butterworth low-pass and the penalised B-spline fit that forecasts each pose component.
//!
//! Conventions: SI units (metres, seconds, radians); world frame as REP-103 (x forward, y left,
//! z up); a missing joint is NaN; azimuth is unwrapped inside the forecaster.
//!
//! No I/O and no Python: other Rust robot code can depend on this crate directly. [`Tracker`]
//! takes a frame's 2D keypoints and registered depth image to every person's pose and forecast
//! in one call ([`camera`], [`depth`], [`assignment`], [`person`], [`forecaster`]). Objects that
//! run per frame ([`Tracker`], [`Person`], [`Forecaster`], [`JointGate`], [`SmoothingSpline`],
//! [`LowPass`], [`ZeroPhase`]) size every buffer at construction (a tracker: up to its busiest
//! frame) and never allocate afterwards.
//!
//! ```
//! use torso_core::{Forecaster, ForecasterConfig};
//! let mut f = Forecaster::new(ForecasterConfig::default()).unwrap();
//! for k in 0..50 {
//!     let t = k as f64 / 25.0;
//!     // Walking forward along x at 1 m/s while turning left at 0.5 rad/s.
//!     f.update([t, 0.0, 1.0, 0.5 * t, 1.5], t, 1.0).unwrap();
//! }
//! let mut out = [[0.0; 5]; 2];
//! f.forecast(&[0.4, 1.0], &mut out).unwrap();
//! // The default continues the fit as a damped trend: 1 m/s decaying with 1.5 s carries
//! // 1.5 (1 - e^(-1/1.5)) m in one second; the turn decays with 0.5 s.
//! assert!((out[1][0] - (1.96 + 1.5 * (1.0 - (-1.0f64 / 1.5).exp()))).abs() < 1e-6);
//! // The zero-phase filter's end transient costs about 3e-4 rad of azimuth here.
//! assert!((out[1][3] - (0.98 + 0.25 * (1.0 - (-2.0f64).exp()))).abs() < 1e-3);
//! ```

// `!(x > y)` is how this crate rejects NaN along with out-of-range values: keep it.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Index loops mirror the subscripts of the equations they implement.
#![allow(clippy::needless_range_loop)]

pub mod assignment;
pub mod banded;
pub mod body_frame;
pub mod bspline;
pub mod butterworth;
pub mod camera;
pub mod coco;
pub mod depth;
pub mod error;
pub mod forecaster;
pub mod gating;
pub mod history;
pub mod person;
pub mod plane;
pub mod quantile;
pub mod selfcheck;
pub mod sides;
pub mod smoothing;
pub mod stray;
pub mod tracker;
pub mod trend;
mod vec3;

pub use assignment::{linear_assignment, Assignment};
pub use body_frame::BodyFrame;
pub use butterworth::{design_lowpass, LowPass, SosFilter, ZeroPhase};
pub use error::{Error, Result};
pub use forecaster::{
    forecast_batch, Extrapolation, FilterMode, FilterSplineConfig, Forecaster, ForecasterConfig,
    LambdaUnit, Method,
};
pub use gating::{GateConfig, JointGate, JointStatus};
pub use history::UpdateReport;
pub use person::{Estimate, GridReport, Observation, Person, PersonConfig};
pub use plane::{
    fit_torso_plane, fit_torso_plane_with, fit_torso_planes, shoulder_heading, ShoulderHeading,
    Side, TorsoPlane, MIN_ORIENTATION_COSINE, MIN_PLANARITY,
};
pub use smoothing::{fit_smoothing_spline, SmoothingSpline};
pub use tracker::{Outcome, TrackRef, Tracker, TrackerConfig};

/// The README's Rust example, compiled and run as a doctest.
#[doc = include_str!("../../../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The crate README's example, compiled and run as a doctest.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct CrateReadmeDoctests;

/// A torso pose as the forecaster sees it: `[x, y, z, azimuth, elevation]` (m, m, m, rad, rad).
pub type Pose = [f64; 5];

/// Index of the centre's height (the gravity-aligned frame's z, up) in a [`Pose`].
pub const HEIGHT: usize = 2;
/// Index of the azimuth in a [`Pose`].
pub const AZIMUTH: usize = 3;
/// Index of the elevation in a [`Pose`].
pub const ELEVATION: usize = 4;

/// The longest step (s) between two frames of a camera that is watching: five frames a second,
/// half the slowest rate of the scenes benchmark. Of a longer step, the rest is time the camera
/// did not see (a stalled sensor, dropped frames): the side of a torso unseen so long is
/// forgotten ([`sides`]), and a person unseen so long is looked for further away ([`tracker`]).
pub const MAX_FRAME_STEP: f64 = 0.2;

/// Helpers shared by the unit tests.
#[cfg(test)]
pub(crate) mod testing {
    /// A reproducible stream of uniform numbers in [0, 1) (a 64-bit linear congruential
    /// generator), so that tests need no random-number crate.
    pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
        let mut state = seed;
        move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }
}
