//! Torso pose forecasting (thesis section 3.3, Algorithm 1) and the thesis' baselines.
//!
//! Every method reduces the history to a polynomial about the last sample, one per pose
//! component: `p_c(τ) = Σ_k d_ck τ^k / k!` with `τ` in seconds, and evaluates it at the requested
//! horizons. For filter + spline, `d_ck` are the derivatives of the last spline piece; for the
//! baselines, the last value and a mean velocity.
//!
//! With uniform weights over a full history, filter + fit + derivatives is a fixed linear map of
//! the history (the filter is linear from a steady-state start or an odd extension, the spline
//! is linear in the data), so the forecaster precomputes that `(N + 1) × T` matrix per component
//! kind and forecasts with a few hundred multiply-adds.

mod batch;
mod config;
mod spline_engine;

pub use batch::forecast_batch;
pub use config::{
    option_named, Extrapolation, FilterMode, FilterSplineConfig, ForecasterConfig, LambdaUnit,
    Method,
};

use crate::bspline::{self, MAX_DEGREE};
use crate::error::{check_len, check_positive, Error, Result};
use crate::history::{History, UpdateReport};
use crate::{Pose, AZIMUTH, ELEVATION};
use config::damped_time;
use spline_engine::SplineEngine;

/// Floor of the relative sample weights in the spline fit (see `SplineEngine::derivatives`).
pub const MIN_RELATIVE_WEIGHT: f64 = 1e-9;

/// Derivatives `d_ck` per component, in seconds.
type Derivatives = [[f64; MAX_DEGREE + 1]; 5];

/// Longest horizon (s) a forecast takes: an hour. Far longer ones would carry a fitted polynomial
/// to infinity.
pub const MAX_HORIZON: f64 = 3600.0;

/// Refuses a horizon that is not a number of seconds from 0 to [`MAX_HORIZON`]: the rule of
/// every forecast.
pub fn check_horizons(horizons: &[f64]) -> Result<()> {
    match horizons
        .iter()
        .find(|h| !(**h >= 0.0 && **h <= MAX_HORIZON))
    {
        Some(&value) => Err(Error::InvalidArgument {
            name: "horizons",
            expected: "horizons from 0 to MAX_HORIZON (3600) seconds",
            value,
        }),
        None => Ok(()),
    }
}

/// One tracked person's forecaster. Every buffer is sized in [`Forecaster::new`]; `update` and
/// `forecast` never touch the heap.
///
/// ```
/// use torso_core::{Forecaster, ForecasterConfig};
/// let mut f = Forecaster::new(ForecasterConfig::constant()).unwrap();
/// f.update([1.0, 2.0, 1.0, 0.5, 1.5], 0.0, 1.0).unwrap();
/// let mut out = [[0.0; 5]];
/// f.forecast(&[1.0], &mut out).unwrap();
/// assert_eq!(out[0], [1.0, 2.0, 1.0, 0.5, 1.5]); // Const holds the last pose
/// ```
#[derive(Clone, Debug)]
pub struct Forecaster {
    config: ForecasterConfig,
    step: f64,
    history: History,
    engine: Engine,
    /// The fit of the history as it is now (end derivatives and their order), once computed:
    /// a track's self-check and its forecast ask for the same fit in one frame.
    fit: Option<(Derivatives, usize)>,
}

#[derive(Clone, Debug)]
enum Engine {
    Const,
    Velocity { window_steps: Option<usize> },
    Spline(Box<SplineEngine>),
}

impl Forecaster {
    pub fn new(config: ForecasterConfig) -> Result<Self> {
        check_positive(
            "rate_hz",
            config.rate_hz,
            "a positive, finite grid rate in Hz",
        )?;
        check_positive(
            "history",
            config.history,
            "a positive, finite history length in seconds",
        )?;
        let capacity = config.capacity();
        if !(2..=100_000).contains(&capacity) {
            return Err(Error::InvalidArgument {
                name: "history",
                expected: "a history of 2 to 100000 samples at rate_hz",
                value: config.history,
            });
        }
        if !(config.max_gap.is_finite() && config.max_gap >= 0.0) {
            return Err(Error::InvalidArgument {
                name: "max_gap",
                expected: "a finite, non-negative gap length in seconds",
                value: config.max_gap,
            });
        }
        let step = 1.0 / config.rate_hz;
        let max_gap_steps = (config.max_gap * config.rate_hz + 1e-9).floor() as usize;
        let engine = match config.method {
            Method::Const => Engine::Const,
            Method::ConstantVelocity { window: None } => Engine::Velocity { window_steps: None },
            Method::ConstantVelocity { window: Some(w) } => {
                check_positive(
                    "window",
                    w,
                    "a positive velocity window in seconds, or None",
                )?;
                Engine::Velocity {
                    window_steps: Some(((w * config.rate_hz).round() as usize).max(1)),
                }
            }
            Method::FilterSpline(cfg) => Engine::Spline(Box::new(SplineEngine::new(
                cfg,
                capacity,
                step,
                config.fast_path,
            )?)),
        };
        Ok(Self {
            config,
            step,
            history: History::new(capacity, config.rate_hz, max_gap_steps),
            fit: None,
            engine,
        })
    }

    pub fn config(&self) -> &ForecasterConfig {
        &self.config
    }

    /// Samples currently held.
    pub fn len(&self) -> usize {
        self.history.len()
    }

    pub fn is_empty(&self) -> bool {
        self.history.is_empty()
    }

    /// Samples in a full history.
    pub fn capacity(&self) -> usize {
        self.history.capacity()
    }

    /// Grid time of the newest sample; horizons count from here.
    pub fn last_time(&self) -> Option<f64> {
        self.history.last_time()
    }

    /// The `i`-th held sample, oldest first (azimuth unwrapped), with its weight.
    pub fn sample(&self, i: usize) -> Option<(Pose, f64)> {
        (i < self.history.len()).then(|| self.history.get(i))
    }

    /// Turns the whole history to face the other way (see [`Person`](crate::Person): a track
    /// that had the body's sides the wrong way round).
    pub fn flip(&mut self) {
        self.fit = None;
        self.history.flip();
    }

    /// Whether [`update`](Self::update) would take a finite sample at `t`: its time stamp maps
    /// to a later slot of the fixed-rate grid than the newest sample's.
    pub fn takes_time(&self, t: f64) -> bool {
        t.is_finite() && self.history.takes_time(t)
    }

    /// Fewest samples before [`Forecaster::forecast`] answers.
    pub fn min_samples(&self) -> usize {
        match &self.engine {
            Engine::Const => 1,
            Engine::Velocity { .. } => 2,
            Engine::Spline(e) => bspline::min_samples(e.cfg.degree),
        }
    }

    /// Forgets the history (a new track).
    pub fn reset(&mut self) {
        self.fit = None;
        self.history.clear();
    }

    /// Adds a pose `[x, y, z, azimuth, elevation]` observed at time `t` (s) with confidence
    /// `weight` (relative; the spline divides by the window's mean). Baselines ignore the weight.
    pub fn update(&mut self, pose: Pose, t: f64, weight: f64) -> Result<UpdateReport> {
        let report = self.history.push(pose, t, weight)?;
        self.fit = None;
        Ok(report)
    }

    /// Forecasts the pose `horizons[h]` seconds after the last sample into `out[h]`. Azimuth
    /// comes out unwrapped (continuous with the history); wrap it only for display.
    pub fn forecast(&mut self, horizons: &[f64], out: &mut [Pose]) -> Result<()> {
        let (d, order) = self.derivatives(horizons, out.len())?;
        self.extrapolate(&d, order, horizons, out, true);
        Ok(())
    }

    /// [`forecast`](Self::forecast) into `damped`, and the same fit continued as its plain
    /// polynomial (no damping) into `plain`, from one fit. For methods without damping the
    /// two are equal.
    pub fn forecast_both(
        &mut self,
        horizons: &[f64],
        damped: &mut [Pose],
        plain: &mut [Pose],
    ) -> Result<()> {
        check_len("plain", plain.len(), horizons.len())?;
        let (d, order) = self.derivatives(horizons, damped.len())?;
        self.extrapolate(&d, order, horizons, damped, true);
        self.extrapolate(&d, order, horizons, plain, false);
        Ok(())
    }

    /// The end derivatives of every component and their highest order, after the checks every
    /// forecast makes.
    fn derivatives(&mut self, horizons: &[f64], out_len: usize) -> Result<(Derivatives, usize)> {
        check_len("out", out_len, horizons.len())?;
        check_horizons(horizons)?;
        let need = self.min_samples();
        let n = self.history.len();
        if n < need {
            return Err(Error::NotEnoughHistory { have: n, need });
        }
        if let Some(fit) = self.fit {
            return Ok(fit);
        }
        let mut d: Derivatives = [[0.0; MAX_DEGREE + 1]; 5];
        let order = match &mut self.engine {
            Engine::Const => {
                let (last, _) = self.history.get(n - 1);
                for c in 0..5 {
                    d[c][0] = last[c];
                }
                0
            }
            Engine::Velocity { window_steps } => {
                let k = window_steps.map_or(n - 1, |w| w.min(n - 1));
                let (last, _) = self.history.get(n - 1);
                let (first, _) = self.history.get(n - 1 - k);
                for c in 0..5 {
                    d[c][0] = last[c];
                    d[c][1] = (last[c] - first[c]) / (k as f64 * self.step);
                }
                1
            }
            Engine::Spline(e) => e.derivatives(&self.history, &mut d)?,
        };
        self.fit = Some((d, order));
        Ok((d, order))
    }

    fn extrapolate(
        &self,
        d: &Derivatives,
        order: usize,
        horizons: &[f64],
        out: &mut [Pose],
        damped: bool,
    ) {
        let damping = match &self.engine {
            Engine::Spline(e) if damped => match e.cfg.extrapolation {
                Extrapolation::Damped { time_constants } if order >= 1 => Some(time_constants),
                _ => None,
            },
            _ => None,
        };
        for (h, o) in horizons.iter().zip(out.iter_mut()) {
            for c in 0..5 {
                o[c] = match damping {
                    Some(t) => d[c][0] + d[c][1] * damped_time(t[c], *h),
                    None => taylor(&d[c][..=order], *h),
                };
            }
        }
    }
}

/// `Σ_k d_k τ^k / k!` by Horner's rule.
fn taylor(d: &[f64], tau: f64) -> f64 {
    let mut acc = 0.0;
    for k in (0..d.len()).rev() {
        acc = d[k] + acc * tau / (k + 1) as f64;
    }
    acc
}

/// Names of the pose components, in order.
pub const COMPONENTS: [&str; 5] = ["x", "y", "z", "azimuth", "elevation"];

const _: () = assert!(AZIMUTH == 3 && ELEVATION == 4);
