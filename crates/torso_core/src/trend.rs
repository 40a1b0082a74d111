//! The least-squares line through a forecaster's history: the constant-velocity candidate of the
//! self-check, and the test of a steady motion.
//!
//! A person turning on the spot turns the azimuth at a nearly constant rate for seconds, and a
//! walker moves the centre steadily; a detector's noise on anyone else wanders about a level.
//! How far a component's fitted rate stands from zero, in standard errors of the fit, tells the
//! two apart from the history alone, before the self-check has had time to score a single
//! forecast (a young track is the common case: a person turning round in front of the robot).

use crate::forecaster::Forecaster;
use crate::{Pose, AZIMUTH};
use std::f64::consts::FRAC_PI_2;

/// How many ordinary standard errors the azimuth's fitted rate must stand from zero for its
/// history to count as a steady turn (the residuals of a history are correlated, so the ordinary
/// standard error is small and the bar is high). Chosen on the scenes benchmark's development
/// split (docs/benchmark.md gives the effect of the rule).
pub const STEADY: f64 = 10.0;

/// How many standard errors, allowing for the residuals' correlation, a centre coordinate's
/// fitted rate must stand from zero for the history to count as a steady walk. Chosen on the
/// scenes benchmark's development split (both draws; docs/benchmark.md).
pub const STEADY_CENTRE: f64 = 5.0;

/// Slowest horizontal speed (m/s) of a steady walk. A slower line through the centre's history,
/// however significant, is more often the estimate drifting (a person turning on the spot,
/// seen from another side, or shuffling) than a walk, and continued it lost to holding still
/// on the scenes benchmark's development split (both draws; docs/benchmark.md); people walk at
/// well over half a metre a second.
pub const MIN_WALK_SPEED: f64 = 0.2;

/// The residuals' lag-one autocorrelation is taken at most this: near one, the variance factor
/// `(1 + ρ) / (1 - ρ)` of a mean of correlated residuals grows without bound.
const MAX_CORRELATION: f64 = 0.99;

/// Samples a history needs before its line is fitted (two give a line with no residual).
const MIN_SAMPLES: usize = 4;

/// The fitted line of every pose component.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Trend {
    /// Rate of change per second.
    pub rate: Pose,
    /// The rate in standard errors of the fit: infinite for a perfect line that moves, zero for
    /// one that does not (within rounding), and zero for a history too short to fit. For the
    /// centre the standard error allows for the residuals' lag-one autocorrelation ρ (times
    /// `√((1 + ρ) / (1 - ρ))`, ρ taken from 0): a walker's sway or a stop in the history leaves
    /// residuals that run in one direction for a while, which count as fewer independent ones.
    /// The angles' is the ordinary one: a turning person's rate changes smoothly, and so
    /// corrected the steady turns were missed (docs/benchmark.md).
    pub significance: Pose,
    /// Seconds of history the azimuth's line was fitted to (samples over the grid rate): the
    /// whole history, or the part since its last front/back flip.
    pub seen: f64,
    /// The azimuth stepped by more than a quarter turn between two samples (a front/back flip
    /// of the estimate: no one turns that fast in a grid step) too recently for a line through
    /// the samples since: no steady turn. Before the flip the line is not fitted; the step
    /// would be taken for a turn.
    pub flipped: bool,
}

/// The least-squares line of one component against the sample index over `from..to`.
#[derive(Clone, Copy, Debug)]
struct Line {
    from: usize,
    samples: usize,
    /// Change per sample.
    slope: f64,
    mean: f64,
    /// Σ dt² about the span's centre.
    stt: f64,
    /// Residual sum of squares.
    residual: f64,
}

impl Line {
    /// One pass, on the sample index centred at zero (so that Σ dt = 0): the slope is
    /// Σ dt·y / Σ dt², the residual sum of squares Σ (y - ȳ)² - slope² Σ dt².
    fn through(y: impl Fn(usize) -> f64, from: usize, to: usize) -> Self {
        let m = to - from;
        let centre = (from + to - 1) as f64 / 2.0;
        let stt = m as f64 * ((m * m) as f64 - 1.0) / 12.0;
        let (mut sum, mut sty, mut syy) = (0.0, 0.0, 0.0);
        for i in from..to {
            let v = y(i);
            sum += v;
            sty += (i as f64 - centre) * v;
            syy += v * v;
        }
        // Too few samples for a line (the azimuth's, just after a flip): no rate.
        let slope = if m >= MIN_SAMPLES { sty / stt } else { 0.0 };
        Self {
            from,
            samples: m,
            slope,
            mean: sum / m as f64,
            stt,
            residual: (syy - sum * sum / m as f64 - slope * slope * stt).max(0.0),
        }
    }

    /// `√((1 + ρ) / (1 - ρ))`, ρ the residuals' lag-one autocorrelation (from 0 up to
    /// [`MAX_CORRELATION`]): the standard error's factor for correlated residuals.
    fn correlation_factor(&self, y: impl Fn(usize) -> f64) -> f64 {
        if !(self.residual > 0.0) {
            return 1.0;
        }
        let centre = (2 * self.from + self.samples - 1) as f64 / 2.0;
        let residual = |i: usize| y(i) - self.mean - self.slope * (i as f64 - centre);
        let lagged: f64 = (self.from + 1..self.from + self.samples)
            .map(|i| residual(i) * residual(i - 1))
            .sum();
        let rho = (lagged / self.residual).clamp(0.0, MAX_CORRELATION);
        ((1.0 + rho) / (1.0 - rho)).sqrt()
    }

    /// The slope in standard errors (times `inflation`); zero where the span changes within
    /// rounding of its values (no motion).
    fn significance(&self, inflation: f64) -> f64 {
        if self.slope.abs() * self.samples as f64 <= 1e-12 * (1.0 + self.mean.abs()) {
            return 0.0;
        }
        let error = inflation * (self.residual / (self.samples - 2) as f64 / self.stt).sqrt();
        self.slope.abs() / error
    }
}

impl Trend {
    /// The least-squares line through the samples of `f`'s history against time.
    ///
    /// ```
    /// use torso_core::trend::Trend;
    /// use torso_core::{Forecaster, ForecasterConfig, AZIMUTH};
    /// let mut f = Forecaster::new(ForecasterConfig::default()).unwrap();
    /// for k in 0..20 {
    ///     let t = k as f64 / 25.0;
    ///     f.update([1.0, 0.0, 1.0, 0.5 * t, 1.5], t, 1.0).unwrap(); // turning at 0.5 rad/s
    /// }
    /// let trend = Trend::of(&f);
    /// assert!((trend.rate[3] - 0.5).abs() < 1e-9);
    /// assert!(trend.steady()[AZIMUTH] && !trend.steady()[0] && trend.rate[0] == 0.0);
    /// ```
    pub fn of(f: &Forecaster) -> Self {
        let n = f.len();
        if n < MIN_SAMPLES {
            return Self::default();
        }
        let sample = |i: usize| f.sample(i).expect("within the history").0;
        // The azimuth's line starts after the history's last flip: the step would be taken for
        // a turn, and what came before it was often a run of bad planes.
        let mut since_flip = 0;
        for i in 1..n {
            if (sample(i)[AZIMUTH] - sample(i - 1)[AZIMUTH]).abs() > FRAC_PI_2 {
                since_flip = i;
            }
        }
        let flipped = n - since_flip < MIN_SAMPLES;
        let lines: [Line; 5] = std::array::from_fn(|c| {
            let from = if c == AZIMUTH { since_flip } else { 0 };
            Line::through(|i| sample(i)[c], from, n)
        });
        let rate_hz = f.config().rate_hz;
        Self {
            seen: lines[AZIMUTH].samples as f64 / rate_hz,
            flipped,
            rate: lines.map(|l| l.slope * rate_hz),
            significance: std::array::from_fn(|c| {
                let line = &lines[c];
                if line.samples < MIN_SAMPLES {
                    return 0.0;
                }
                // The centre's residuals are correlated: fewer independent ones.
                let inflation = if c < 3 {
                    line.correlation_factor(|i| sample(i)[c])
                } else {
                    1.0
                };
                line.significance(inflation)
            }),
        }
    }

    /// Per component, whether it moves steadily: its rate [`STEADY_CENTRE`] (centre) or
    /// [`STEADY`] (angles) standard errors from zero; for the centre, at a walk's pace
    /// ([`MIN_WALK_SPEED`] over the ground), and for the azimuth, with no flip in the history.
    pub fn steady(&self) -> [bool; 5] {
        let walking = self.rate[0].hypot(self.rate[1]) >= MIN_WALK_SPEED;
        std::array::from_fn(|c| match c {
            0..=2 => self.significance[c] >= STEADY_CENTRE && walking,
            _ => self.significance[c] >= STEADY && !(c == AZIMUTH && self.flipped),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ForecasterConfig;

    fn history(poses: impl Iterator<Item = Pose>) -> Forecaster {
        let mut f = Forecaster::new(ForecasterConfig::default()).unwrap();
        for (k, p) in poses.enumerate() {
            f.update(p, k as f64 / 25.0, 1.0).unwrap();
        }
        f
    }

    /// Simple regression of `ys` on the sample index by the textbook formulas: the slope per
    /// sample, its ordinary t (slope over standard error), and the residuals' lag-one
    /// autocorrelation.
    fn by_hand(ys: &[f64]) -> (f64, f64, f64) {
        let n = ys.len() as f64;
        let xs: Vec<f64> = (0..ys.len()).map(|k| k as f64).collect();
        let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
        let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
        let b = xs
            .iter()
            .zip(ys)
            .map(|(x, y)| (x - mx) * (y - my))
            .sum::<f64>()
            / sxx;
        let r: Vec<f64> = xs
            .iter()
            .zip(ys)
            .map(|(x, y)| y - my - b * (x - mx))
            .collect();
        let sse: f64 = r.iter().map(|v| v * v).sum();
        let rho = r.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / sse;
        (b, b / (sse / (n - 2.0) / sxx).sqrt(), rho)
    }

    #[test]
    fn the_line_matches_the_closed_form_and_its_significance_the_ordinary_standard_error() {
        // y = 0.3 t plus +-0.01 alternating, on the azimuth.
        let ys: Vec<f64> = (0..30)
            .map(|k| 0.3 * k as f64 / 25.0 + if k % 2 == 0 { 0.01 } else { -0.01 })
            .collect();
        let trend = Trend::of(&history(ys.iter().map(|&y| [0.0, 0.0, 0.0, y, 1.5])));
        let (b, t, _) = by_hand(&ys);
        assert!((trend.rate[3] - b * 25.0).abs() < 1e-12);
        assert!((trend.significance[3] - t).abs() < 1e-9 * t);
        assert_eq!((trend.rate[0], trend.significance[0]), (0.0, 0.0));
        // A level that is not a binary fraction: no motion, whatever the rounding.
        let level = history((0..37).map(|_| [0.3, 1.1, 0.7, 2.9, 1.3]));
        assert_eq!(Trend::of(&level).significance, [0.0; 5]);
    }

    #[test]
    fn the_centres_standard_error_allows_for_correlated_residuals() {
        // Alternating noise on a walk: negative correlation counts as none, the ordinary error.
        let walk: Vec<f64> = (0..30)
            .map(|k| 0.04 * k as f64 + if k % 2 == 0 { 0.01 } else { -0.01 })
            .collect();
        let (_, t, rho) = by_hand(&walk);
        let trend = Trend::of(&history(walk.iter().map(|&x| [x, 0.0, 1.0, 0.0, 1.5])));
        assert!(rho < 0.0 && (trend.significance[0] - t).abs() < 1e-9 * t);
        assert!(trend.steady()[0]); // 1 m/s
                                    // The same line at a tenth of the pace: as significant, but no walk.
        let drift = Trend::of(&history(
            walk.iter().map(|&x| [0.1 * x, 0.0, 1.0, 0.0, 1.5]),
        ));
        assert!(drift.significance[0] > STEADY_CENTRE && !drift.steady()[0]);
        // A step: standing, then half a metre on, standing again. A line fits it with residuals
        // that run one way for a third of the history at a time: far fewer independent ones.
        let step: Vec<f64> = (0..50)
            .map(|k| (if k < 25 { 0.0 } else { 0.5 }) + if k % 2 == 0 { 0.003 } else { -0.003 })
            .collect();
        let (_, t, rho) = by_hand(&step);
        let trend = Trend::of(&history(step.iter().map(|&y| [0.0, y, 1.0, 0.0, 1.5])));
        let corrected = t / ((1.0 + rho) / (1.0 - rho)).sqrt();
        assert!(rho > 0.5 && (trend.significance[1] - corrected).abs() < 1e-9 * corrected);
        assert!(t > STEADY_CENTRE && !trend.steady()[1]);
        // The azimuth's stays the ordinary one.
        let turn = Trend::of(&history(step.iter().map(|&a| [0.0, 0.0, 1.0, a, 1.5])));
        assert!((turn.significance[AZIMUTH] - t).abs() < 1e-9 * t);
    }

    #[test]
    fn noise_about_a_level_is_no_steady_turn_and_a_short_history_no_line() {
        let wander = history((0..50).map(|k| [0.0, 0.0, 0.0, 0.2 * (k as f64 * 0.7).sin(), 1.5]));
        assert_eq!(Trend::of(&wander).steady(), [false; 5]);
        // A flip of the estimate halfway, standing still on either side: the line through the
        // whole history would be steep and significant; the one since the flip is level.
        let flip = history((0..50).map(|k| [0.0, 0.0, 0.0, if k < 25 { 0.0 } else { 3.1 }, 1.5]));
        let trend = Trend::of(&flip);
        assert!(!trend.flipped && trend.significance[AZIMUTH] == 0.0);
        assert!(trend.rate[AZIMUTH].abs() < 1e-12);
        assert!(!trend.steady()[AZIMUTH] && (trend.seen - 1.0).abs() < 1e-12);
        // A steady turn with a flip in it: the turn since the flip, over the second it lasted.
        let turn = |k: usize| 0.02 * k as f64 + if (20..30).contains(&k) { 3.1 } else { 0.0 };
        let trend = Trend::of(&history((0..50).map(|k| [0.0, 0.0, 0.0, turn(k), 1.5])));
        assert!(trend.steady()[AZIMUTH] && (trend.rate[AZIMUTH] - 0.5).abs() < 1e-9);
        assert!((trend.seen - 20.0 / 25.0).abs() < 1e-12);
        // A flip two samples ago: too few since for a line, no turn and no rate.
        let late = history((0..50).map(|k| {
            [
                0.0,
                0.0,
                0.0,
                0.02 * k as f64 + if k >= 48 { 3.1 } else { 0.0 },
                1.5,
            ]
        }));
        let trend = Trend::of(&late);
        assert!(trend.flipped && !trend.steady()[AZIMUTH] && trend.rate[AZIMUTH] == 0.0);
        let short = history((0..3).map(|k| [0.0, 0.0, 0.0, k as f64, 1.5]));
        assert_eq!(Trend::of(&short), Trend::default());
    }
}
