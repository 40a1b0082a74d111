//! The filter + spline method's machinery: the low-pass over the history window, the penalised
//! spline fit, the end derivatives, and the precomputed linear map of the fast path.

use super::{
    Derivatives, Extrapolation, FilterMode, FilterSplineConfig, LambdaUnit, MIN_RELATIVE_WEIGHT,
};
use crate::bspline::MAX_DEGREE;
use crate::butterworth::{check_samples, design_lowpass, ForwardBackward, SosFilter};
use crate::error::{Error, Result};
use crate::history::History;
use crate::smoothing::SmoothingSpline;

#[derive(Clone, Debug)]
pub(super) struct SplineEngine {
    pub(super) cfg: FilterSplineConfig,
    pub(super) causal: Option<SosFilter>,
    /// The components filtered side by side, one lane each.
    pub(super) zero_phase: Option<ForwardBackward<[f64; 5]>>,
    pub(super) spline: SmoothingSpline,
    /// Abscissa units per second (1/step for samples, 1 for seconds).
    pub(super) units_per_second: f64,
    pub(super) abscissa_step: f64,
    pub(super) values: Vec<f64>,
    pub(super) smoothed: Vec<f64>,
    pub(super) weights: Vec<f64>,
    pub(super) abscissae: Vec<f64>,
    /// `(N + 1) × n` map from the (filtered) window to the end derivatives, for these weights.
    pub(super) end_map: Vec<f64>,
    /// `(N + 1) × T` maps from a full, uniformly weighted history to the derivatives; index 0 for
    /// unfiltered components, 1 for filtered ones.
    pub(super) fast: Option<[Vec<f64>; 2]>,
}

impl SplineEngine {
    pub(super) fn new(
        cfg: FilterSplineConfig,
        capacity: usize,
        step: f64,
        fast_path: bool,
    ) -> Result<Self> {
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
                Some(ForwardBackward::new(
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
    pub(super) fn precompute_maps(&mut self, capacity: usize) -> Result<[Vec<f64>; 2]> {
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
    pub(super) fn derivatives(&mut self, history: &History, d: &mut Derivatives) -> Result<usize> {
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

    pub(super) fn extrapolation_order(&self) -> usize {
        match self.cfg.extrapolation {
            Extrapolation::Polynomial => self.cfg.degree,
            Extrapolation::Linear | Extrapolation::Damped { .. } => self.cfg.degree.min(1),
        }
    }

    /// Filter (where `filtered[c]`), fit and differentiate the first `filtered.len()` components
    /// of `self.values` (`n` samples each) with `self.weights`.
    pub(super) fn solve_window(
        &mut self,
        n: usize,
        filtered: &[bool],
        d: &mut Derivatives,
    ) -> Result<()> {
        self.filter_window(n, filtered)?;
        self.build_end_map(n)?;
        self.apply_end_map(n, filtered.len(), d);
        Ok(())
    }

    /// `self.smoothed` from `self.values`: filtered where `filtered[c]`, copied otherwise.
    pub(super) fn filter_window(&mut self, n: usize, filtered: &[bool]) -> Result<()> {
        let k = filtered.len();
        let (values, smoothed) = (&self.values[..k * n], &mut self.smoothed[..k * n]);
        smoothed.copy_from_slice(values);
        if let Some(sos) = &self.causal {
            for (y, _) in smoothed
                .chunks_exact_mut(n)
                .zip(filtered)
                .filter(|(_, &on)| on)
            {
                sos.filter_from_steady_state(y);
            }
        }
        if let Some(zp) = &mut self.zero_phase {
            zp.check_len(n)?;
            for (x, _) in values.chunks_exact(n).zip(filtered).filter(|(_, &on)| on) {
                check_samples("x", x)?;
            }
            // Every component in its own lane: the filtered ones are copied out.
            let lanes = zp.filter(n, |i| {
                std::array::from_fn(|c| if c < k { values[c * n + i] } else { 0.0 })
            });
            for (c, y) in smoothed.chunks_exact_mut(n).enumerate() {
                if filtered[c] {
                    y.iter_mut().zip(lanes).for_each(|(y, lane)| *y = lane[c]);
                }
            }
        }
        Ok(())
    }

    /// `self.end_map` for `n` samples weighted by `self.weights`.
    pub(super) fn build_end_map(&mut self, n: usize) -> Result<()> {
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
    pub(super) fn apply_end_map(&self, n: usize, k: usize, d: &mut Derivatives) {
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
