//! The least-squares line through a forecaster's history: the constant-velocity candidate of the
//! self-check, and the test of a steady motion.
//!
//! A person turning on the spot turns the azimuth at a nearly constant rate for seconds, and a
//! walker moves the centre steadily; a detector's noise on anyone else wanders about a level.
//! How far a component's fitted rate stands from zero, in standard errors of the fit, tells the
//! two apart from the history alone, before the self-check has had time to score a single
//! forecast (a young track is the common case: a person turning round in front of the robot).
//!
//! A walk continued along the line goes straight on; people walk in curves, and they face where
//! they walk, so a torso turning steadily while its path bends the same way bends the line's
//! continuation with it ([`Trend::walk_turn`]), and a line through the centre that runs across
//! the torso is no walk ([`MAX_WALK_ACROSS`]). People also stop, and a walk that has ended stays
//! in the history's line for as long as the history holds it; the line through the history's
//! last moments tells ([`Trend::walk_ended`]).

use crate::forecaster::Forecaster;
use crate::{Pose, AZIMUTH, HEIGHT};
use std::f64::consts::{FRAC_PI_2, FRAC_PI_3};

/// How many ordinary standard errors the azimuth's fitted rate must stand from zero for its
/// history to count as a steady turn (the residuals of a history are correlated, so the ordinary
/// standard error is small and the bar is high). Chosen on the scenes benchmark's development
/// split (docs/benchmark_log.md gives the effect of the rule).
pub const STEADY: f64 = 10.0;

/// How many standard errors, allowing for the residuals' correlation, the centre's fitted
/// velocity over the ground must stand from zero for the history to count as a steady walk:
/// the root sum of squares of the two coordinates' rates, each in its own standard errors, so
/// that a walk is told the same whichever way it runs against the world's axes (a walk along a
/// diagonal splits its rate between them). Chosen on the scenes benchmark's development split
/// (both draws; docs/benchmark_log.md).
pub const STEADY_CENTRE: f64 = 5.0;

/// Slowest horizontal speed (m/s) of a steady walk. A slower line through the centre's history,
/// however significant, is more often the estimate drifting (a person turning on the spot,
/// seen from another side, or shuffling) than a walk, and continued it lost to holding still
/// on the scenes benchmark's development split (both draws; docs/benchmark_log.md); people walk at
/// well over half a metre a second.
pub const MIN_WALK_SPEED: f64 = 0.2;

/// Largest angle (rad) between a steady line through the centre's history and the torso's
/// normal line, either way, for the line to count as a walk. People walk facing where they go,
/// or backing away, and a sidestep does not last; a line across the torso is more often the
/// estimate drifting while a person stands (turning, bending, shifting their weight), and
/// continued it lost to holding still. A third of a turn leaves room for a young track's poor
/// torso planes: chosen on the scenes benchmark's development split, where an eighth of a turn
/// refused young runners' walks and five twelfths kept more of the drifts (docs/benchmark_log.md).
pub const MAX_WALK_ACROSS: f64 = FRAC_PI_3;

/// Shortest history (s) over which a steady turn of the torso bends a walk's continuation. A
/// walker's torso twists to and fro with every stride (a stride takes about a second), and a line
/// through less of the heading than that can take the twist for a turn (measured on the scenes
/// benchmark's development split: docs/benchmark_log.md).
pub const MIN_WALK_TURN_SEEN: f64 = 1.0;

/// Seconds at the end of the history whose line tells whether a walk goes on
/// ([`WALK_GOES_ON`]): at least four frames of the slowest camera rate the scenes benchmark has
/// (10 frames per second), less than a walker's step.
pub const RECENT_WALK_S: f64 = 0.4;

/// Smallest share of a walk's speed over the history that the line through its last
/// [`RECENT_WALK_S`] must keep for the walk to count as going on. A walker's pace varies within
/// a stride and along a bend by far less; one that has stopped, or is stopping, keeps next to
/// none. Chosen on the scenes benchmark's development split, where 0.7 held a few more stops
/// but cost Human3.6M's pedestrians, who walk in loops, on one draw of three
/// (docs/benchmark_log.md, "walkers who stop").
pub const WALK_GOES_ON: f64 = 0.5;

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
    /// corrected the steady turns were missed (docs/benchmark_log.md). The samples counted are the
    /// forecaster's grid samples, the slots filled between two frames included: a camera slower
    /// than the grid gives fewer independent samples than are counted, and a history of two or
    /// three frames at 10 or 15 frames per second, filled along straight lines, has no residual
    /// and an infinite significance (the walks it starts are mostly real: docs/benchmark_log.md).
    pub significance: Pose,
    /// Root-mean-square scatter of each component's history about its line.
    pub scatter: Pose,
    /// Seconds of history the line was fitted to (samples over the grid rate).
    pub seen: f64,
    /// The azimuth steps by more than a quarter turn between two samples somewhere in the
    /// history: a front/back flip of the estimate (no one turns that fast in a grid step), whose
    /// step a line would take for a turn.
    pub flipped: bool,
    /// Rate (rad/s, counter-clockwise over the ground) at which [`continued`](Self::continued)
    /// turns the centre's path: the azimuth's fitted rate where the azimuth turns steadily
    /// ([`steady`](Self::steady)) over at least [`MIN_WALK_TURN_SEEN`] of history and the path's
    /// own bend over the ground (a quadratic through the centre's history) turns the same way;
    /// zero otherwise. The path's bend alone is too noisy a turn rate to continue (a quadratic's
    /// velocity at the end of a short history); the torso's turn is steadier, but a person can
    /// turn without walking round, which the path's bend rules out.
    pub walk_turn: f64,
    /// The torso's normal over the history: the azimuth's mean (rad), its line's value at the
    /// middle of the history, where the centre's fitted velocity is the path's. `None` for a
    /// history too short to fit or holding a front/back flip ([`flipped`](Self::flipped)), whose
    /// mean lies between the two sides.
    pub torso_line: Option<f64>,
    /// Speed over the ground (m/s) of the line through the history's last [`RECENT_WALK_S`]
    /// (all of it where shorter).
    pub recent_speed: f64,
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
        // One pass, on the sample index centred at zero (so that Σ dt = 0): the line's slope is
        // Σ dt·y / Σ dt², its residual sum of squares Σ (y - ȳ)² - slope² Σ dt².
        let centre = (n - 1) as f64 / 2.0;
        let stt = n as f64 * ((n * n) as f64 - 1.0) / 12.0;
        let (mut sum, mut sty, mut syy) = ([0.0; 5], [0.0; 5], [0.0; 5]);
        // The quadratic term over the ground, on u = dt² less its mean (orthogonal to 1 and dt):
        // Σ u·y per coordinate, and Σ u² in closed form as Σ dt² is.
        let mean_tt = stt / n as f64;
        let suu = stt * ((n * n) as f64 - 4.0) / 15.0;
        let mut suy = [0.0; 2];
        // The line through the last samples over the ground, on their own centred index.
        let rate_hz = f.config().rate_hz;
        let m = ((RECENT_WALK_S * rate_hz).round() as usize).clamp(2, n);
        let (recent_centre, recent_stt) = (
            (m - 1) as f64 / 2.0,
            m as f64 * ((m * m) as f64 - 1.0) / 12.0,
        );
        let mut recent = [0.0; 2];
        let mut flipped = false;
        let mut previous = sample(0)[AZIMUTH];
        for i in 0..n {
            let (dt, p) = (i as f64 - centre, sample(i));
            for c in 0..5 {
                sum[c] += p[c];
                sty[c] += dt * p[c];
                syy[c] += p[c] * p[c];
            }
            let u = dt * dt - mean_tt;
            suy[0] += u * p[0];
            suy[1] += u * p[1];
            flipped |= (p[AZIMUTH] - previous).abs() > FRAC_PI_2;
            previous = p[AZIMUTH];
            if i + m >= n {
                let dt = (i + m - n) as f64 - recent_centre;
                recent[0] += dt * p[0];
                recent[1] += dt * p[1];
            }
        }
        let slope: Pose = std::array::from_fn(|c| sty[c] / stt);
        let residual: Pose = std::array::from_fn(|c| {
            (syy[c] - sum[c] * sum[c] / n as f64 - slope[c] * slope[c] * stt).max(0.0)
        });
        // Second pass: the lag-one products of the residuals about the line.
        let mean: Pose = std::array::from_fn(|c| sum[c] / n as f64);
        let (mut lagged, mut previous_residual) = ([0.0; 5], [0.0; 5]);
        for i in 0..n {
            let (dt, p) = (i as f64 - centre, sample(i));
            for c in 0..3 {
                let r = p[c] - mean[c] - slope[c] * dt;
                if i > 0 {
                    lagged[c] += r * previous_residual[c];
                }
                previous_residual[c] = r;
            }
        }
        let inflation: Pose = std::array::from_fn(|c| {
            if c >= 3 || !(residual[c] > 0.0) {
                return 1.0;
            }
            let rho = (lagged[c] / residual[c]).clamp(0.0, MAX_CORRELATION);
            ((1.0 + rho) / (1.0 - rho)).sqrt()
        });
        let mut trend = Self {
            scatter: residual.map(|r| (r / (n - 2) as f64).sqrt()),
            seen: n as f64 / rate_hz,
            flipped,
            rate: slope.map(|s| s * rate_hz),
            significance: std::array::from_fn(|c| {
                let error = inflation[c] * (residual[c] / (n - 2) as f64 / stt).sqrt();
                // A change over the history within rounding of the values is no motion.
                if slope[c].abs() * n as f64 <= 1e-12 * (1.0 + mean[c].abs()) {
                    0.0
                } else {
                    slope[c].abs() / error
                }
            }),
            walk_turn: 0.0,
            torso_line: (!flipped).then_some(mean[AZIMUTH]),
            recent_speed: 0.0,
        };
        trend.recent_speed = recent[0].hypot(recent[1]) / recent_stt * rate_hz;
        // The path's turn rate: velocity x acceleration over speed squared, the acceleration
        // twice the quadratic term (per sample², hence rate² per s²).
        let [vx, vy] = [trend.rate[0], trend.rate[1]];
        let [ax, ay] = suy.map(|q| 2.0 * q / suu * rate_hz * rate_hz);
        let path_turn = vx * ay - vy * ax;
        let turn = trend.rate[AZIMUTH];
        if trend.steady()[AZIMUTH] && trend.seen >= MIN_WALK_TURN_SEEN && path_turn * turn > 0.0 {
            trend.walk_turn = turn;
        }
        trend
    }

    /// The constant-velocity prediction `horizon` seconds after `sample`: every component's
    /// rate continued; where the walk turns ([`walk_turn`](Self::walk_turn)), the centre's
    /// path over the ground at the same speed along an arc at that rate, for as long as the turn
    /// has been seen and straight on after (as a steady turn of the azimuth itself is continued).
    pub fn continued(&self, sample: &Pose, horizon: f64) -> Pose {
        let mut ahead: Pose = std::array::from_fn(|c| sample[c] + self.rate[c] * horizon);
        if self.walk_turn != 0.0 {
            let w = self.walk_turn;
            // The fitted rate is the path's mean velocity: its direction half a history ago.
            let now = rotated([self.rate[0], self.rate[1]], w * self.seen / 2.0);
            let turning = horizon.min(self.seen);
            // Along the arc: the chord, at half the arc's turn; then straight on.
            let half = w * turning / 2.0;
            let chord = if half == 0.0 {
                turning
            } else {
                turning * half.sin() / half
            };
            let arc = rotated(now, half).map(|v| v * chord);
            let on = rotated(now, 2.0 * half).map(|v| v * (horizon - turning));
            ahead[0] = sample[0] + arc[0] + on[0];
            ahead[1] = sample[1] + arc[1] + on[1];
        }
        ahead
    }

    /// Per component, how far a forecast `horizon` seconds ahead may err by what this history
    /// alone says (before any forecast of the track has been checked): the scatter about the
    /// line (the estimates' noise) with, for a component whose forecast continues the line
    /// (`continued`), its rate's standard error over the horizon, and for one held still the
    /// fitted motion over the horizon (what holding misses if the motion goes on). For an angle
    /// held still the rate is taken as the root of its square less its variance (the squared
    /// rate's unbiased estimate: a rate within a standard error of zero counts as none): a
    /// torso's sway and bob over a short history fit a rate mostly of noise, and an angle goes
    /// only as far as the body turns or leans. The centre's drift is taken whole: a person
    /// drifting too slowly to count as a walk keeps drifting (the young tracks' centre intervals
    /// are too narrow already, docs/benchmark_log.md). `None` for a history too short to fit.
    pub fn spread(&self, horizon: f64, continued: [bool; 5]) -> Option<Pose> {
        if self.seen == 0.0 {
            return None;
        }
        Some(std::array::from_fn(|c| {
            let s = self.significance[c];
            let error = if s.is_finite() {
                self.rate[c].abs() / s
            } else {
                0.0
            };
            let rate = if continued[c] {
                error
            } else if c < AZIMUTH {
                self.rate[c].abs()
            } else {
                // The fitted rate's square overstates the true rate's by the fit's variance.
                (self.rate[c].powi(2) - error.powi(2)).max(0.0).sqrt()
            };
            self.scatter[c].hypot(rate * horizon)
        }))
    }

    /// Per component, whether it moves steadily. The centre over the ground, both coordinates
    /// together: its velocity [`STEADY_CENTRE`] standard errors from zero, at a walk's pace
    /// ([`MIN_WALK_SPEED`]), along the torso's normal line within [`MAX_WALK_ACROSS`] either
    /// way (where the history has one), and not ended ([`walk_ended`](Self::walk_ended)); a
    /// walk is continued whole or not at all. The angles:
    /// their rate [`STEADY`] standard errors from zero, and for the azimuth, with no flip in the
    /// history.
    /// The centre's height never does: a torso rises or sinks only as far as the body lets it
    /// (a jump, sitting down, standing up), so a line through its recent heights is not one to
    /// continue for seconds (held still instead, no motion's forecasts on the scenes
    /// benchmark's development split got worse; docs/benchmark_log.md).
    pub fn steady(&self) -> [bool; 5] {
        let walking = self.walk_seen() && !self.walk_slowed();
        std::array::from_fn(|c| match c {
            HEIGHT => false,
            0 | 1 => walking,
            _ => self.significance[c] >= STEADY && !(c == AZIMUTH && self.flipped),
        })
    }

    /// Whether the history's line over the ground is a walk (see [`steady`](Self::steady)),
    /// going on or not.
    fn walk_seen(&self) -> bool {
        let [vx, vy] = [self.rate[0], self.rate[1]];
        let along_torso = self
            .torso_line
            .is_none_or(|line| (vy.atan2(vx) - line).cos().abs() >= MAX_WALK_ACROSS.cos());
        vx.hypot(vy) >= MIN_WALK_SPEED
            && self.significance[0].hypot(self.significance[1]) >= STEADY_CENTRE
            && along_torso
    }

    /// Whether the history holds a walk that has ended: its line over the ground a walk, the
    /// line through its last [`RECENT_WALK_S`] slower than [`WALK_GOES_ON`] of it. The walk is
    /// then neither steady nor continued ([`crate::selfcheck`] holds the centre still over the
    /// ground): people stop where they were going, and a walk continued past its stop errs by
    /// its speed times the horizon, where holding errs by the few steps of the stop.
    pub fn walk_ended(&self) -> bool {
        self.walk_seen() && self.walk_slowed()
    }

    /// Whether the line through the history's last [`RECENT_WALK_S`] is slower than
    /// [`WALK_GOES_ON`] of the history's line over the ground.
    fn walk_slowed(&self) -> bool {
        self.recent_speed < WALK_GOES_ON * self.rate[0].hypot(self.rate[1])
    }
}

/// `v` turned counter-clockwise by `angle` (rad).
fn rotated(v: [f64; 2], angle: f64) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    [c * v[0] - s * v[1], s * v[0] + c * v[1]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ForecasterConfig;
    use std::f64::consts::PI;

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
    fn before_any_check_the_spread_is_the_scatter_with_the_rate_s_error_or_the_motion() {
        // The centre's x stays about a level (no walk: the whole fitted motion counts); the
        // azimuth turns steadily (only its rate's standard error counts); the same noise on both.
        let noise = |k: usize| 0.01 * [1.0, -1.0, 0.5, -0.3, 0.8][k % 5];
        let (xs, azimuths): (Vec<f64>, Vec<f64>) = (0..50)
            .map(|k| (1.0 + noise(k), 0.02 * k as f64 + noise(k)))
            .unzip();
        let trend = Trend::of(&history(
            xs.iter()
                .zip(&azimuths)
                .map(|(&x, &a)| [x, 0.0, 1.0, a, 1.5]),
        ));
        assert!(!trend.steady()[0] && trend.steady()[AZIMUTH]);
        let sxx: f64 = 50.0 * (50.0 * 50.0 - 1.0) / 12.0;
        let h = 2.0;
        let spread = trend.spread(h, trend.steady()).unwrap();
        let (b, t, _) = by_hand(&xs);
        let scatter = (b / t).abs() * sxx.sqrt();
        assert!((spread[0] - scatter.hypot(25.0 * b.abs() * h)).abs() < 1e-12);
        let (b, t, _) = by_hand(&azimuths);
        let scatter = (b / t).abs() * sxx.sqrt();
        assert!((spread[AZIMUTH] - scatter.hypot(25.0 * (b / t).abs() * h)).abs() < 1e-12);
        // Held still instead of continued, the forecast misses the fitted turn, its rate less
        // its standard error in squares (an angle's).
        let held = trend.spread(h, [false; 5]).unwrap();
        let rate = (b * b - (b / t).powi(2)).sqrt();
        assert!((held[AZIMUTH] - scatter.hypot(25.0 * rate * h)).abs() < 1e-12);
        // A rate within a standard error of zero counts as none.
        let slow = Trend {
            rate: [0.0, 0.0, 0.0, 0.1, 0.0],
            significance: [0.0, 0.0, 0.0, 0.8, 0.0],
            scatter: [0.01; 5],
            seen: 1.0,
            ..Trend::default()
        };
        assert_eq!(slow.spread(h, [false; 5]).unwrap()[AZIMUTH], 0.01);
        // A history too short for a line says nothing.
        assert_eq!(
            Trend::of(&history((0..3).map(|_| [0.0; 5]))).spread(h, [true; 5]),
            None
        );
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
        let ahead = trend.continued(&[1.0, 2.0, 3.0, 0.5, 1.5], 2.0);
        assert_eq!(ahead, [1.0, 2.0, 3.0, 0.5 + 2.0 * trend.rate[3], 1.5]);
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
        assert!(trend.steady()[0]);
        // The same line (1 m/s) at a tenth of the pace: as significant, but no walk.
        let drift = Trend::of(&history(
            walk.iter().map(|&x| [0.1 * x, 0.0, 1.0, 0.0, 1.5]),
        ));
        assert!(drift.significance[0] > STEADY_CENTRE && !drift.steady()[0]);
        // Sinking as steadily while walking: the walk is steady, the height is not.
        let sitting = Trend::of(&history(
            walk.iter().map(|&x| [x, 0.0, 1.0 - 0.5 * x, 0.0, 1.5]),
        ));
        assert!(sitting.significance[HEIGHT] > STEADY_CENTRE);
        assert_eq!(sitting.steady()[..3], [true, true, false]);
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
    fn a_walk_is_told_by_its_velocity_over_the_ground_whichever_way_it_runs() {
        // Half a second of a walk at 1 m/s, swaying across the path and jittering along it, along
        // the x axis and along the diagonal: the same walk, so the same answer, for both
        // coordinates at once.
        let walk = |heading: f64| {
            let (s, c) = heading.sin_cos();
            history((0..12).map(move |k| {
                let along = 0.04 * k as f64 + 0.08 * [1.0, -1.0, 0.5, 0.0][k % 4];
                let across = 0.14 * [0.0, 1.0, 0.0, -1.0][k % 4];
                [
                    c * along - s * across,
                    s * along + c * across,
                    1.0,
                    0.0,
                    1.5,
                ]
            }))
        };
        let (straight, diagonal) = (
            Trend::of(&walk(0.0)),
            Trend::of(&walk(std::f64::consts::FRAC_PI_4)),
        );
        let ground = |t: &Trend| t.significance[0].hypot(t.significance[1]);
        assert!(straight.significance[0] >= STEADY_CENTRE);
        // On the diagonal neither coordinate alone stands the bar; the velocity does.
        assert!(diagonal.significance[..2]
            .iter()
            .all(|&z| z < STEADY_CENTRE));
        assert!(ground(&diagonal) >= STEADY_CENTRE);
        assert!((ground(&diagonal) / ground(&straight) - 1.0).abs() < 0.25);
        for trend in [straight, diagonal] {
            assert_eq!(trend.steady()[..3], [true, true, false], "{trend:?}");
        }
        // The same sway about a level: no walk in either coordinate.
        let still = Trend::of(&history((0..12).map(|k| {
            let s = 0.08 * [1.0, -1.0, 0.5, 0.0][k % 4];
            [s, 0.14 * [0.0, 1.0, 0.0, -1.0][k % 4], 1.0, 0.0, 1.5]
        })));
        assert_eq!(still.steady()[..2], [false, false]);
    }

    #[test]
    fn a_line_across_the_torso_is_no_walk() {
        // Half a second at 1 m/s along x, the torso's normal at `facing` (and, with `flip`, a
        // front/back flip of the estimate at the fourth sample).
        let line = |facing: f64, flip: bool| {
            Trend::of(&history((0..12).map(move |k| {
                let turned = if flip && k >= 4 { PI } else { 0.0 };
                [0.04 * k as f64, 0.0, 1.0, facing + turned, 1.5]
            })))
        };
        // Facing the way it goes, or backing away, within a third of a turn: a walk.
        for facing in [
            0.0,
            PI,
            0.9 * FRAC_PI_3,
            -0.9 * FRAC_PI_3,
            PI + 0.9 * FRAC_PI_3,
        ] {
            assert_eq!(line(facing, false).steady()[..2], [true, true], "{facing}");
        }
        // Across the torso: the same line through the centre is no walk.
        for facing in [FRAC_PI_2, -FRAC_PI_2, 1.1 * FRAC_PI_3, PI - 1.1 * FRAC_PI_3] {
            let trend = line(facing, false);
            assert!(trend.significance[0] > STEADY_CENTRE, "{trend:?}");
            assert_eq!(trend.steady()[..2], [false, false], "{facing}");
        }
        // A history holding a flip has no torso line to judge the walk by.
        let flipped = line(FRAC_PI_2, true);
        assert!(flipped.flipped && flipped.torso_line.is_none());
        assert_eq!(flipped.steady()[..2], [true, true]);
    }

    #[test]
    fn a_walk_that_has_stopped_is_no_longer_steady() {
        // 1.5 s of a walk at 1 m/s along x, then `still` samples standing where it stopped (the
        // speed falling over 0.2 s), with a few millimetres of jitter; the torso faces the way.
        let walk = |still: usize| {
            let mut x = 0.0;
            history((0..38 + still).map(move |k| {
                let speed = (1.0 - (k as f64 - 37.0).max(0.0) / 5.0).max(0.0);
                x += speed / 25.0;
                let jitter = 0.003 * [1.0, -1.0, 0.5, 0.0][k % 4];
                [x + jitter, jitter, 1.0, 0.0, 1.5]
            }))
        };
        let going = Trend::of(&walk(0));
        assert!(going.steady()[0] && !going.walk_ended(), "{going:?}");
        assert!((going.recent_speed - 1.0).abs() < 0.05);
        // Half a second after the stop the history's line still says a walk (it holds a
        // second and a half of it), its last 0.4 s do not: the walk has ended, and is held.
        let stopped = Trend::of(&walk(12));
        assert!(stopped.rate[0] > 0.5 && stopped.significance[0] > STEADY_CENTRE);
        assert!(stopped.walk_ended() && stopped.steady()[..2] == [false, false]);
        // A walk round a bend keeps its pace, whichever way its last moments run.
        let (bend, _) = circle(50, 1.0);
        let trend = Trend::of(&bend);
        assert!(!trend.walk_ended() && trend.steady()[0]);
        // Standing still throughout is no walk, ended or going on.
        let standing = Trend::of(&history((0..50).map(|k| {
            let jitter = 0.003 * [1.0, -1.0, 0.5, 0.0][k % 4];
            [jitter, jitter, 1.0, 0.0, 1.5]
        })));
        assert!(!standing.walk_ended() && !standing.steady()[0]);
    }

    /// `n` samples at 25 Hz of a walk at 1 m/s round a circle of radius 2 m, counter-clockwise,
    /// the chest facing along the path (or `facing_turn` times as fast, -1: the other way).
    fn circle(n: usize, facing_turn: f64) -> (Forecaster, impl Fn(f64) -> [f64; 2]) {
        let (radius, w) = (2.0, 0.5);
        let at = move |t: f64| [radius * (w * t).cos(), radius * (w * t).sin()];
        let f = history((0..n).map(|k| {
            let t = k as f64 / 25.0;
            let [x, y] = at(t);
            [x, y, 1.0, facing_turn * w * t + FRAC_PI_2, 1.5]
        }));
        (f, at)
    }

    #[test]
    fn a_walk_whose_torso_turns_with_its_path_is_continued_round_the_bend() {
        let (f, at) = circle(50, 1.0);
        let trend = Trend::of(&f);
        assert!((trend.walk_turn - 0.5).abs() < 1e-9);
        let last = f.sample(49).unwrap().0;
        let t = 49.0 / 25.0;
        for h in [0.4, 1.0, 2.0] {
            let [x, y] = at(t + h);
            let miss = |p: Pose| (p[0] - x).hypot(p[1] - y);
            let bent = miss(trend.continued(&last, h));
            let straight = miss(std::array::from_fn(|c| last[c] + trend.rate[c] * h));
            // The line's mean velocity is a little slower than the walk round the circle (its
            // chord): a few centimetres 2 s ahead, where the straight line misses by a metre.
            assert!(
                bent < 0.04 * h && straight > 0.3 * h,
                "{h}: {bent} {straight}"
            );
        }
        // Past the history it was seen over, the turn stops: straight on from there.
        let (f, _) = circle(30, 1.0);
        let trend = Trend::of(&f);
        let last = f.sample(29).unwrap().0;
        let ahead = [0.8, 1.0, 1.3, 1.6, 2.0].map(|h| trend.continued(&last, h));
        let heading = |p: Pose, q: Pose| (q[1] - p[1]).atan2(q[0] - p[0]);
        assert!((heading(ahead[2], ahead[3]) - heading(ahead[3], ahead[4])).abs() < 1e-9);
        assert!(heading(ahead[1], ahead[2]) - heading(ahead[0], ahead[1]) > 0.05);
    }

    #[test]
    fn a_turn_seen_briefly_or_against_the_path_bends_nothing() {
        // Under a second of history: a stride's twist could be the turn.
        let (f, _) = circle(20, 1.0);
        let trend = Trend::of(&f);
        assert!(trend.steady()[AZIMUTH] && trend.walk_turn == 0.0);
        // The torso turning one way while the path bends the other.
        let (f, _) = circle(50, -1.0);
        let trend = Trend::of(&f);
        assert!(trend.steady()[AZIMUTH] && trend.walk_turn == 0.0);
        let last = f.sample(49).unwrap().0;
        let line: Pose = std::array::from_fn(|c| last[c] + trend.rate[c] * 2.0);
        assert_eq!(trend.continued(&last, 2.0), line);
        // Turning on the spot: no path to bend.
        let spot = history((0..50).map(|k| [1.0, 0.0, 1.0, 0.02 * k as f64, 1.5]));
        assert_eq!(Trend::of(&spot).walk_turn, 0.0);
    }

    #[test]
    fn noise_about_a_level_is_no_steady_turn_and_a_short_history_no_line() {
        let wander = history((0..50).map(|k| [0.0, 0.0, 0.0, 0.2 * (k as f64 * 0.7).sin(), 1.5]));
        assert_eq!(Trend::of(&wander).steady(), [false; 5]);
        // A flip of the estimate halfway: a steep, significant line, but no turn.
        let flip = history((0..50).map(|k| [0.0, 0.0, 0.0, if k < 25 { 0.0 } else { 3.1 }, 1.5]));
        let trend = Trend::of(&flip);
        assert!(trend.significance[AZIMUTH] > STEADY && trend.flipped && !trend.steady()[AZIMUTH]);
        let short = history((0..3).map(|k| [0.0, 0.0, 0.0, k as f64, 1.5]));
        assert_eq!(Trend::of(&short), Trend::default());
    }
}
