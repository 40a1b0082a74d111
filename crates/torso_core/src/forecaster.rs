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

use crate::bspline::{self, MAX_DEGREE};
use crate::butterworth::{design_lowpass, SosFilter, ZeroPhase};
use crate::error::{check_len, check_positive, Error, Result};
use crate::history::{History, UpdateReport};
use crate::smoothing::SmoothingSpline;
use crate::{Pose, AZIMUTH, ELEVATION};

/// How the history is low-pass filtered before the spline fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterMode {
    /// No filter (the thesis' "no filter" ablation).
    Off,
    /// Causal filtering of the history window, started in steady state at its first sample.
    /// Lags the signal by the filter's group delay, as a filter running on a robot would.
    Causal,
    /// Forward-backward (`sosfiltfilt`) filtering of the history window: no lag, but the last
    /// samples depend on the odd extension at the window's end.
    ZeroPhase,
}

/// The time unit of the spline abscissae, which sets what `lam` means: the penalty
/// `λ ∫ f''(t)² dt` scales with the unit cubed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LambdaUnit {
    /// Knots at 0, 1, 2, ... (sample index).
    Samples,
    /// Knots at the sample times in seconds.
    Seconds,
}

/// How the fitted spline is continued past the last sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Extrapolation {
    /// Continue the last polynomial piece (what `scipy.interpolate.BSpline` does).
    Polynomial,
    /// Continue the tangent at the last sample (value and slope of the last piece).
    Linear,
    /// A damped trend (not in the thesis): the value and slope at the last sample, the slope
    /// decaying with a time constant `T_c` (seconds) per component, so that
    /// `f_c(τ) = d_c0 + d_c1 · T_c (1 - e^{-τ/T_c})`. `T_c = 0` holds the last value (Const),
    /// `T_c = ∞` is [`Extrapolation::Linear`]. People rarely keep turning or leaning at the
    /// same rate for two seconds; the slope is evidence about the next few hundred ms only.
    Damped { time_constants: [f64; 5] },
}

impl Extrapolation {
    /// Time constants selected on Human3.6M S1 (the training subject; see docs/reproduction.md)
    /// for x, y, z, azimuth and elevation: position keeps its velocity longest, elevation
    /// (leaning) reverts fastest.
    pub const DAMPED_H36M_S1: Extrapolation = Extrapolation::Damped {
        time_constants: [1.5, 1.5, 1.5, 0.5, 0.1],
    };
}

/// `T (1 - e^{-τ/T})`: how far a unit slope decaying with time constant `T` carries in `τ`.
fn damped_time(time_constant: f64, tau: f64) -> f64 {
    if time_constant == 0.0 {
        0.0
    } else if time_constant.is_infinite() {
        tau
    } else {
        -time_constant * (-tau / time_constant).exp_m1()
    }
}

/// The thesis' filter + spline forecaster.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterSplineConfig {
    pub filter: FilterMode,
    /// Butterworth order. Thesis: 2.
    pub filter_order: usize,
    /// Butterworth cut-off (Hz). Thesis: 5 Hz.
    pub cutoff_hz: f64,
    /// Which of `[x, y, z, azimuth, elevation]` are filtered. Thesis: the two angles.
    pub filter_components: [bool; 5],
    /// Spline degree `N` (0 to 4). Thesis: 1.
    pub degree: usize,
    /// Roughness weight λ. Thesis: 1.
    pub lam: f64,
    pub lambda_unit: LambdaUnit,
    pub extrapolation: Extrapolation,
}

impl Default for FilterSplineConfig {
    fn default() -> Self {
        Self {
            filter: FilterMode::ZeroPhase,
            filter_order: 2,
            cutoff_hz: 5.0,
            filter_components: [false, false, false, true, true],
            degree: 1,
            lam: 1.0,
            lambda_unit: LambdaUnit::Samples,
            // Not the thesis' rule (it continues the last polynomial piece): on Human3.6M the
            // damped trend beats Const and both constant-velocity baselines at 0.4, 1 and 2 s,
            // and the thesis' rule does not (docs/reproduction.md).
            extrapolation: Extrapolation::DAMPED_H36M_S1,
        }
    }
}

/// The forecasting method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Method {
    /// Zero velocity: the last pose, held ("Const" in the thesis).
    Const,
    /// The mean velocity over the last `window` seconds (`None`: the whole history), integrated.
    ConstantVelocity { window: Option<f64> },
    /// Low-pass filter, penalised spline fit, extrapolation.
    FilterSpline(FilterSplineConfig),
}

/// Everything a forecaster needs to know; every choice the thesis leaves open is a field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForecasterConfig {
    /// Rate of the fixed time grid (Hz). Thesis: 25 Hz.
    pub rate_hz: f64,
    /// History length (s). Thesis: 2 s, i.e. 50 samples at 25 Hz.
    pub history: f64,
    /// Longest gap (s) that is bridged by interpolated, zero-weight samples; a longer one
    /// restarts the history.
    pub max_gap: f64,
    pub method: Method,
    /// Use the precomputed linear map when the weights are uniform and the history full.
    pub fast_path: bool,
}

impl Default for ForecasterConfig {
    fn default() -> Self {
        Self {
            rate_hz: 25.0,
            history: 2.0,
            max_gap: 0.4,
            method: Method::FilterSpline(FilterSplineConfig::default()),
            fast_path: true,
        }
    }
}

impl ForecasterConfig {
    /// The zero-velocity baseline on the default grid.
    pub fn constant() -> Self {
        Self {
            method: Method::Const,
            ..Self::default()
        }
    }

    /// The thesis' forecaster with its Butterworth low-pass on all five pose components at 1 Hz,
    /// for poses from a keypoint detector. The thesis filters only the angles (its mocap
    /// positions are clean) at 5 Hz; a detector's centres jitter by centimetres, and with N = 1
    /// the spline interpolates, so the forecast continues the last noisy step. On the bundled CMU
    /// training walks seen through the demo's camera and MoveNet, the median centre error 1 s
    /// ahead drops from 79 to 42 cm (holding still: 100 cm); 0.7 to 2 Hz were tried
    /// (docs/demo.md).
    pub fn live() -> Self {
        Self {
            method: Method::FilterSpline(FilterSplineConfig {
                cutoff_hz: 1.0,
                filter_components: [true; 5],
                ..FilterSplineConfig::default()
            }),
            ..Self::default()
        }
    }

    /// A constant-velocity baseline on the default grid.
    pub fn constant_velocity(window: Option<f64>) -> Self {
        Self {
            method: Method::ConstantVelocity { window },
            ..Self::default()
        }
    }

    /// Samples in a full history.
    pub fn capacity(&self) -> usize {
        (self.history * self.rate_hz).round() as usize
    }

    /// Checks every field, as [`Forecaster::new`] would, without precomputing the fast path.
    pub fn validate(&self) -> Result<()> {
        Forecaster::new(Self {
            fast_path: false,
            ..*self
        })
        .map(|_| ())
    }
}

/// Floor of the relative sample weights in the spline fit (see `SplineEngine::derivatives`).
pub const MIN_RELATIVE_WEIGHT: f64 = 1e-9;

/// Derivatives `d_ck` per component, in seconds.
type Derivatives = [[f64; MAX_DEGREE + 1]; 5];

/// Refuses a horizon that is not a finite, non-negative number of seconds: the rule of every
/// forecast.
pub fn check_horizons(horizons: &[f64]) -> Result<()> {
    match horizons.iter().find(|h| !(h.is_finite() && **h >= 0.0)) {
        Some(&value) => Err(Error::InvalidArgument {
            name: "horizons",
            expected: "finite, non-negative horizons in seconds",
            value,
        }),
        None => Ok(()),
    }
}

/// One tracked person's forecaster. Every buffer is sized in [`Forecaster::new`]; `update` and
/// `forecast` never touch the heap.
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

#[derive(Clone, Debug)]
struct SplineEngine {
    cfg: FilterSplineConfig,
    causal: Option<SosFilter>,
    zero_phase: Option<ZeroPhase>,
    spline: SmoothingSpline,
    /// Abscissa units per second (1/step for samples, 1 for seconds).
    units_per_second: f64,
    abscissa_step: f64,
    values: Vec<f64>,
    smoothed: Vec<f64>,
    weights: Vec<f64>,
    abscissae: Vec<f64>,
    /// `(N + 1) × n` map from the (filtered) window to the end derivatives, for these weights.
    end_map: Vec<f64>,
    /// `(N + 1) × T` maps from a full, uniformly weighted history to the derivatives; index 0 for
    /// unfiltered components, 1 for filtered ones.
    fast: Option<[Vec<f64>; 2]>,
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

impl SplineEngine {
    fn new(cfg: FilterSplineConfig, capacity: usize, step: f64, fast_path: bool) -> Result<Self> {
        let spline = SmoothingSpline::new(cfg.degree, capacity)?;
        if !(cfg.lam.is_finite() && cfg.lam >= 0.0) || (cfg.degree >= 2 && cfg.lam == 0.0) {
            return Err(Error::InvalidArgument {
                name: "lam",
                expected: "a finite smoothing weight, > 0 for degree >= 2",
                value: cfg.lam,
            });
        }
        if let Extrapolation::Damped { time_constants } = cfg.extrapolation {
            if let Some(&value) = time_constants.iter().find(|t| !(**t >= 0.0)) {
                return Err(Error::InvalidArgument {
                    name: "time_constants",
                    expected:
                        "damping time constants >= 0 s (0 holds the value, inf keeps the slope)",
                    value,
                });
            }
        }
        let rate = 1.0 / step;
        let (causal, zero_phase) = match cfg.filter {
            FilterMode::Off => (None, None),
            FilterMode::Causal => (
                Some(design_lowpass(cfg.filter_order, cfg.cutoff_hz, rate)?),
                None,
            ),
            FilterMode::ZeroPhase => (
                None,
                Some(ZeroPhase::new(
                    design_lowpass(cfg.filter_order, cfg.cutoff_hz, rate)?,
                    capacity,
                )),
            ),
        };
        let (units_per_second, abscissa_step) = match cfg.lambda_unit {
            LambdaUnit::Samples => (rate, 1.0),
            LambdaUnit::Seconds => (1.0, step),
        };
        let mut engine = Self {
            cfg,
            causal,
            zero_phase,
            spline,
            units_per_second,
            abscissa_step,
            values: vec![0.0; 5 * capacity],
            smoothed: vec![0.0; 5 * capacity],
            weights: vec![0.0; capacity],
            abscissae: vec![0.0; capacity],
            end_map: vec![0.0; (cfg.degree + 1) * capacity],
            fast: None,
        };
        if fast_path {
            engine.fast = Some(engine.precompute_maps(capacity)?);
        }
        Ok(engine)
    }

    /// Runs the general path on each unit vector `e_j` of a full, uniformly weighted history:
    /// column `j` of the linear map, once unfiltered and once filtered. The weights are the same
    /// for every `e_j`, so the end-derivative map is built once.
    fn precompute_maps(&mut self, capacity: usize) -> Result<[Vec<f64>; 2]> {
        let order = self.cfg.degree;
        let mut maps = [
            vec![0.0; (order + 1) * capacity],
            vec![0.0; (order + 1) * capacity],
        ];
        let mut d: Derivatives = [[0.0; MAX_DEGREE + 1]; 5];
        self.weights[..capacity].fill(1.0);
        self.build_end_map(capacity)?;
        for j in 0..capacity {
            self.values[..2 * capacity].fill(0.0);
            self.values[j] = 1.0;
            self.values[capacity + j] = 1.0;
            self.filter_window(capacity, &[false, true])?;
            self.apply_end_map(capacity, 2, &mut d);
            for (kind, map) in maps.iter_mut().enumerate() {
                for k in 0..=order {
                    map[k * capacity + j] = d[kind][k];
                }
            }
        }
        Ok(maps)
    }

    /// Fills `d` for the held history; returns the polynomial order used.
    fn derivatives(&mut self, history: &History, d: &mut Derivatives) -> Result<usize> {
        let n = history.len();
        history.copy_component_major(&mut self.values[..5 * n], &mut self.weights[..n]);
        let weights = &mut self.weights[..n];
        let uniform = weights[0] > 0.0 && weights.iter().all(|&w| w == weights[0]);
        match &self.fast {
            Some(maps) if uniform && n == history.capacity() => {
                for c in 0..5 {
                    let map = &maps[self.cfg.filter_components[c] as usize];
                    let x = &self.values[c * n..(c + 1) * n];
                    for k in 0..=self.cfg.degree {
                        d[c][k] = dot(&map[k * n..(k + 1) * n], x);
                    }
                }
            }
            _ => {
                // Relative weights: λ keeps its meaning whatever the detector's score scale. The
                // floor keeps zero-weight (gap-filled) samples from leaving an interpolating fit
                // (N <= 1, where the penalty vanishes) under-determined; for N >= 2 it is noise.
                let mean = weights.iter().sum::<f64>() / n as f64;
                let scale = if mean > 0.0 { 1.0 / mean } else { 1.0 };
                weights
                    .iter_mut()
                    .for_each(|w| *w = (*w * scale).max(MIN_RELATIVE_WEIGHT));
                let mask = self.cfg.filter_components;
                self.solve_window(n, &mask, d)?;
            }
        }
        Ok(self.extrapolation_order())
    }

    fn extrapolation_order(&self) -> usize {
        match self.cfg.extrapolation {
            Extrapolation::Polynomial => self.cfg.degree,
            Extrapolation::Linear | Extrapolation::Damped { .. } => self.cfg.degree.min(1),
        }
    }

    /// Filter (where `filtered[c]`), fit and differentiate the first `filtered.len()` components
    /// of `self.values` (`n` samples each) with `self.weights`.
    fn solve_window(&mut self, n: usize, filtered: &[bool], d: &mut Derivatives) -> Result<()> {
        self.filter_window(n, filtered)?;
        self.build_end_map(n)?;
        self.apply_end_map(n, filtered.len(), d);
        Ok(())
    }

    /// `self.smoothed` from `self.values`: filtered where `filtered[c]`, copied otherwise.
    fn filter_window(&mut self, n: usize, filtered: &[bool]) -> Result<()> {
        for (c, &on) in filtered.iter().enumerate() {
            let (x, y) = (
                &self.values[c * n..(c + 1) * n],
                &mut self.smoothed[c * n..(c + 1) * n],
            );
            match (on, &self.causal, &mut self.zero_phase) {
                (true, Some(sos), _) => {
                    y.copy_from_slice(x);
                    sos.filter_from_steady_state(y);
                }
                (true, None, Some(zp)) => zp.apply(x, y)?,
                _ => y.copy_from_slice(x),
            }
        }
        Ok(())
    }

    /// `self.end_map` for `n` samples weighted by `self.weights`.
    fn build_end_map(&mut self, n: usize) -> Result<()> {
        if self.spline.sample_count() != n {
            for (i, a) in self.abscissae[..n].iter_mut().enumerate() {
                *a = (i as f64 - (n - 1) as f64) * self.abscissa_step;
            }
            self.spline.set_abscissae(&self.abscissae[..n])?;
        }
        let map = &mut self.end_map[..(self.cfg.degree + 1) * n];
        self.spline
            .end_derivative_map(&self.weights[..n], self.cfg.lam, map)
    }

    /// Derivatives in seconds of the first `k` smoothed components through `self.end_map`.
    fn apply_end_map(&self, n: usize, k: usize, d: &mut Derivatives) {
        let map = &self.end_map[..(self.cfg.degree + 1) * n];
        for (c, y) in self.smoothed[..k * n].chunks_exact(n).enumerate() {
            // d/dt = (units per second) · d/du, once per order of differentiation.
            let mut scale = 1.0;
            for (order, h) in map.chunks_exact(n).enumerate() {
                d[c][order] = dot(h, y) * scale;
                scale *= self.units_per_second;
            }
        }
    }
}

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Forecasts many history windows in one call, for evaluations. `histories` is a flat,
/// C-ordered `(n, window_len, 5)` array of poses on the config's grid (azimuth may be wrapped: it
/// is unwrapped per window); `out` receives the flat `(n, horizons.len(), 5)` forecasts. The
/// config's `history` is replaced by the window length. One forecaster serves every window.
pub fn forecast_batch(
    config: &ForecasterConfig,
    histories: &[f64],
    window_len: usize,
    horizons: &[f64],
    out: &mut [f64],
) -> Result<()> {
    let stride = window_len * 5;
    if window_len == 0 || histories.len() % stride != 0 {
        return Err(Error::LengthMismatch {
            name: "histories",
            expected: stride.max(5) * (histories.len() / stride.max(5)).max(1),
            got: histories.len(),
        });
    }
    let count = histories.len() / stride;
    check_len("out", out.len(), count * horizons.len() * 5)?;
    check_positive(
        "rate_hz",
        config.rate_hz,
        "a positive, finite grid rate in Hz",
    )?;
    let cfg = ForecasterConfig {
        history: window_len as f64 / config.rate_hz,
        ..*config
    };
    let mut f = Forecaster::new(cfg)?;
    let mut poses = [[0.0; 5]; 16];
    for (w, window) in histories.chunks_exact(stride).enumerate() {
        f.reset();
        for (i, p) in window.chunks_exact(5).enumerate() {
            let pose = [p[0], p[1], p[2], p[3], p[4]];
            f.update(pose, i as f64 / cfg.rate_hz, 1.0)
                .map_err(|e| match e {
                    Error::NonFinite { name: "pose", .. } => Error::NonFinite {
                        name: "histories",
                        index: w,
                    },
                    other => other,
                })?;
        }
        let dest = &mut out[w * horizons.len() * 5..(w + 1) * horizons.len() * 5];
        // Horizons in chunks of 16 so the forecast buffer stays on the stack.
        for (hs, d) in horizons.chunks(16).zip(dest.chunks_mut(16 * 5)) {
            f.forecast(hs, &mut poses[..hs.len()])?;
            for (o, p) in d.chunks_exact_mut(5).zip(&poses) {
                o.copy_from_slice(p);
            }
        }
    }
    Ok(())
}

/// Names of the pose components, in order.
pub const COMPONENTS: [&str; 5] = ["x", "y", "z", "azimuth", "elevation"];

const _: () = assert!(AZIMUTH == 3 && ELEVATION == 4);
