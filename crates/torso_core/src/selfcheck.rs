//! A track's forecast, checked against the track's own recent past.
//!
//! Whether a trend is worth continuing, and for how long, depends on the person and on the
//! detector: a walker's centre moves steadily and a turning person's heading keeps turning,
//! while a detector's azimuth noise on a person standing still makes any fitted trend a guess.
//! Each time the forecaster takes a sample, four predictions for each of [`HORIZONS`] are kept:
//! holding still, the forecaster's damped trend, the same fit continued without damping, and
//! constant velocity (the least-squares line through the history, a walk bent along a steady
//! turn: [`crate::trend`]). When their time comes, each is scored against the sample then
//! taken. Per pose component and horizon (the checked one nearest to the one asked for), the
//! forecast given out is the mix of them that would have erred least on the recent scores (the
//! minimum-variance convex weights of correlated predictors, from forgetting sums of their
//! products of errors).
//!
//! Each component has a prior candidate, the one it forecasts with before any check: holding still,
//! unless the track's history shows the component moving steadily: then constant velocity (a walk,
//! a steady turn), for the azimuth only for horizons no longer than the history it was seen over,
//! or where continuing the turn has already come true at every shorter checked horizon (a walk
//! mostly goes on; a turn is continued further ahead than it has been seen to last only once the
//! track's own forecasts have shown it going on), and a turn only while it is still coming true
//! (continuing it has missed by less than holding still in at least half of the recent scores at
//! the shortest horizon: a turn that has stopped stays in the history's line for as long as the
//! history holds it); the centre's height never counts as moving steadily ([`crate::trend`]), and
//! the elevation always holds still. A component's mix takes another candidate
//! than its prior only when that one's gain over the prior (the difference of their squared errors)
//! is significant: its mean [`SIGNIFICANCE`] standard errors above zero, counting the scores of one
//! horizon's span as one (overlapping forecasts err together). A detector's noise makes most fitted
//! trends of an angle, or of a person who stays in place, a guess, and a guess that wins a few
//! recent scores by chance would otherwise be continued. The centre of a steady walk is the
//! exception: it mixes its trends freely, one mix for both its coordinates over the ground. A
//! walk that has ended ([`Trend::walk_ended`]) is held still over the ground, whatever its
//! scores: they are of the walk.
//!
//! A gap that restarts the forecaster's history (a person hidden, a camera that stalled) drops
//! the predictions pending on the old history, not the scores: a track found again after a gap
//! forecasts from a short history, and its record of which candidates came true, and of how far
//! its forecasts missed, is still the same person's and detector's (forgotten with time as
//! ever). Forgetting them there left a person turning on the spot held still for seconds after a
//! stall (docs/benchmark_log.md, "a track's record kept across a gap").

use crate::error::{check_positive, Error, Result};
use crate::quantile::RecentQuantile;
use crate::trend::Trend;
use crate::{Pose, AZIMUTH, ELEVATION};
use std::f64::consts::PI;

/// Time constant (s) with which old scores are forgotten.
const MEMORY: f64 = 2.0;
/// Predictions scored before the mix is trusted.
const MIN_SCORED: f64 = 3.0;
/// Scores' worth [`INTERVAL_80`] counts for among a track's own errors in its interval's
/// multiple. A track keeps only a few seconds' scores (a few to a few dozen at a camera's frame
/// rate), and a prior counted as three of them was the 80 % point itself for most tracks,
/// whatever their own errors said (docs/benchmark_log.md, "the prior's weight in a track's
/// multiple"); as one, the track's own errors decide once it has a few.
pub const PRIOR_SCORES: f64 = 1.0;
/// Standard errors by which a candidate's mean gain over the prior must exceed zero to enter
/// the mix. Chosen on the scenes benchmark's development split (docs/benchmark_log.md).
pub const SIGNIFICANCE: f64 = 2.0;
const HOLD: usize = 0;
const VELOCITY: usize = 3;
/// Share of the truth a forecast interval is to cover.
pub const COVERAGE: f64 = 0.8;
/// Half-width of a central 80 % interval in units of [`SelfCheck::spread`], per pose component,
/// before the track's own errors say otherwise: the prior of [`SelfCheck::half_width`], counted
/// as one score's worth.
/// A normal error would need 1.28; forecast errors against the truth have heavier tails and
/// include what the track cannot see in its own errors (the estimate's offset from the true
/// pose), by different amounts for the centre and the angles, so each multiplier was set on the
/// scenes benchmark's development split to bring its component's intervals to 80 % over all
/// motions and horizons (docs/benchmark.md gives the coverage per motion). The centre's was set
/// again once the centre was placed behind the body's surface
/// ([`PersonConfig::surface_depth`](crate::PersonConfig::surface_depth)): the offset it had
/// made up for is gone. Once the track's own errors have taken over, [`TRUTH_MARGIN`] says how
/// far the truth lies beyond them.
pub const INTERVAL_80: [f64; 5] = [2.0, 2.0, 2.0, 1.9, 1.6];
/// Per pose component, the half-width that covers 80 % of the truth over the one that covers
/// 80 % of the track's own errors (its forecasts against its later estimates): how much
/// further, or nearer, the truth lies than what the track can see of it. Further for the
/// ground position and the angles, by the estimate's offset from the true pose (which is in
/// every error against the truth and in none of the track's own) and by motions that change in
/// ways the recent past did not show; nearer for the height (its own errors are larger than its
/// errors against the truth). One value for both ground coordinates (a world frame's axes are any
/// two directions). Set on the scenes benchmark's development draws to bring each component's
/// intervals to 80 % over all motions and horizons, with the prior's weight at
/// [`PRIOR_SCORES`] (docs/benchmark.md gives the coverage per motion); the intervals given
/// before a track has checked a forecast are [`INTERVAL_80`]'s.
pub const TRUTH_MARGIN: [f64; 5] = [1.67, 1.67, 0.94, 1.2, 1.19];
/// An angle's half-width taken at most half a turn: a wider interval holds every direction
/// too, and half a turn says so in a number a robot can read (an interval of several turns
/// reads as a broken one). Coverage does not change: an angle's error is at most half a turn.
fn within_half_turn(half_width: [f64; 5]) -> [f64; 5] {
    std::array::from_fn(|c| {
        if c >= AZIMUTH && half_width[c] > PI {
            PI
        } else {
            half_width[c]
        }
    })
}

/// The candidates: hold still, damped trend, plain trend, constant velocity over the history.
pub const CANDIDATES: usize = 4;
/// The horizons (s) checked: the thesis' 0.4, 1 and 2 s.
pub const HORIZONS: [f64; 3] = [0.4, 1.0, 2.0];
const H: usize = HORIZONS.len();
/// Most predictions a track's self-check keeps over its longest horizon: the bound a
/// forecaster's history has on its samples.
pub const MAX_PREDICTIONS: usize = 100_000;

#[derive(Clone, Copy, Debug, Default)]
struct Prediction {
    poses: [[Pose; CANDIDATES]; H],
    /// Per checked horizon: the forecast the mix gave, and its spread (NaN before any check).
    mixed: [Pose; H],
    spread: [Pose; H],
}

/// When a prediction of the ring was made, and per checked horizon whether it waits to be
/// scored: kept apart from the predictions, so that the search for the ones due, every frame,
/// reads a few cache lines and not the whole ring.
#[derive(Clone, Copy, Debug, Default)]
struct Due {
    made: f64,
    pending: [bool; H],
}

/// The predictions awaiting their time and the scores so far; sized at construction.
///
/// ```
/// use torso_core::selfcheck::{SelfCheck, HORIZONS};
/// let mut check = SelfCheck::new(25.0).unwrap();
/// // A walk at 1 m/s along x whose plain trend comes true: after a while, the x forecast is it.
/// for k in 0..100 {
///     let t = k as f64 / 25.0;
///     let plain = HORIZONS.map(|h| [t + h, 0.0, 1.0, 0.0, 1.5]);
///     let held = HORIZONS.map(|_| [t, 0.0, 1.0, 0.0, 1.5]);
///     check.record(t, [t, 0.0, 1.0, 0.0, 1.5], &held, &plain, &held);
/// }
/// assert!((check.weights(1.0)[0][2] - 1.0).abs() < 1e-9);
/// ```
#[derive(Clone, Debug)]
pub struct SelfCheck {
    half_step: f64,
    ring: Vec<Prediction>,
    due: Vec<Due>,
    next: usize,
    /// Per checked horizon, per component: forgetting sums of the products of the candidates'
    /// errors, and of the products of their squares (for the spread of one's gain over another).
    sums: [[[[f64; CANDIDATES]; CANDIDATES]; 5]; H],
    squares: [[[[f64; CANDIDATES]; CANDIDATES]; 5]; H],
    scored: [f64; H],
    /// Per checked horizon: the forgetting count of the scores at which continuing the
    /// azimuth's line missed by less than holding it still.
    turn_wins: [f64; H],
    last_scored: [Option<f64>; H],
    /// Per checked horizon and component, the recent errors of the forecasts given, in units
    /// of the spread given with them.
    tails: [[RecentQuantile; 5]; H],
    /// Per checked horizon and component, the minimum-variance weights of `sums` where
    /// `fresh` says they are up to date ([`prepare`](SelfCheck::prepare)): a track's forecast
    /// and its intervals in one frame share them.
    mix: [[[f64; CANDIDATES]; 5]; H],
    fresh: [bool; H],
    /// Per component, whether the track's history moves steadily ([`crate::trend`]), and the
    /// seconds of history it was seen over.
    steady: [bool; 5],
    seen: f64,
    /// Whether the track's history holds a walk that has ended ([`Trend::walk_ended`]).
    walk_ended: bool,
}

impl SelfCheck {
    /// Checks on a grid of `rate_hz` (room for one prediction per slot of the longest horizon);
    /// refuses the rates [`slots`](Self::slots) refuses.
    pub fn new(rate_hz: f64) -> Result<Self> {
        let slots = Self::slots(rate_hz)?;
        Ok(Self {
            half_step: 0.5 / rate_hz,
            ring: vec![Prediction::default(); slots],
            due: vec![Due::default(); slots],
            next: 0,
            sums: [[[[0.0; CANDIDATES]; CANDIDATES]; 5]; H],
            squares: [[[[0.0; CANDIDATES]; CANDIDATES]; 5]; H],
            scored: [0.0; H],
            turn_wins: [0.0; H],
            last_scored: [None; H],
            tails: [[RecentQuantile::default(); 5]; H],
            mix: [HOLD_ALL; H],
            fresh: [false; H],
            steady: [false; 5],
            seen: 0.0,
            walk_ended: false,
        })
    }

    /// The predictions a check on a grid of `rate_hz` keeps; an error for a rate that is not
    /// positive and finite, or so fast that the longest horizon would take more than
    /// [`MAX_PREDICTIONS`] of them (each track keeps its own: a rate a forecaster takes with a
    /// short history must not make every track allocate without bound).
    ///
    /// ```
    /// use torso_core::selfcheck::{SelfCheck, MAX_PREDICTIONS};
    /// assert_eq!(SelfCheck::slots(25.0).unwrap(), 52); // 2 s at 25 Hz, and two spare
    /// assert!(SelfCheck::slots(MAX_PREDICTIONS as f64).is_err());
    /// assert!(SelfCheck::slots(f64::INFINITY).is_err() && SelfCheck::slots(0.0).is_err());
    /// ```
    pub fn slots(rate_hz: f64) -> Result<usize> {
        check_positive("rate_hz", rate_hz, "a positive, finite grid rate in Hz")?;
        let longest = (HORIZONS[H - 1] * rate_hz).ceil();
        if longest > MAX_PREDICTIONS as f64 {
            return Err(Error::InvalidArgument {
                name: "rate_hz",
                expected: "a grid rate at which a track's self-check keeps at most 100000 predictions over its longest horizon (2 s): up to 50000 Hz",
                value: rate_hz,
            });
        }
        Ok(longest as usize + 2)
    }

    /// The forecaster took `sample` at grid time `t` and predicts `damped[k]`, `plain[k]` and
    /// `velocity[k]` for `t + HORIZONS[k]`: the predictions aimed at `t` are scored against
    /// `sample`, and these kept.
    pub fn record(
        &mut self,
        t: f64,
        sample: Pose,
        damped: &[Pose; H],
        plain: &[Pose; H],
        velocity: &[Pose; H],
    ) {
        // The forecast this track gives now, with its spread, as its latest call to
        // `forecast` prepared it. A horizon whose mix no forecast has solved since the last
        // score is not solved again here: its prediction adds nothing to the intervals' errors.
        let poses: [[Pose; CANDIDATES]; H] =
            std::array::from_fn(|k| [sample, damped[k], plain[k], velocity[k]]);
        let (mut mixed, mut spread) = ([[f64::NAN; 5]; H], [[f64::NAN; 5]; H]);
        for (k, h) in HORIZONS.into_iter().enumerate() {
            if let Some(j) = self.checked(h).filter(|&j| self.fresh[j]) {
                let w = self.weights(h);
                mixed[k] = std::array::from_fn(|c| {
                    (0..CANDIDATES).map(|a| w[c][a] * poses[k][a][c]).sum()
                });
                spread[k] = self.spread_of(h, j, &w);
            }
        }
        for (p, due) in self.ring.iter().zip(self.due.iter_mut()) {
            for k in 0..H {
                if !(due.pending[k] && due.made + HORIZONS[k] <= t + self.half_step) {
                    continue;
                }
                due.pending[k] = false;
                // A longer horizon's prior reads this one's scores (`turn_shown`).
                self.fresh[k..].fill(false);
                let decay =
                    self.last_scored[k].map_or(1.0, |last| (-(t - last).max(0.0) / MEMORY).exp());
                self.last_scored[k] = Some(t);
                self.scored[k] = self.scored[k] * decay + 1.0;
                for c in 0..5 {
                    let given = p.spread[k][c];
                    let z = (given > 0.0).then(|| (sample[c] - p.mixed[k][c]).abs() / given);
                    self.tails[k][c].add(z, decay);
                    let e = p.poses[k].map(|pose| sample[c] - pose[c]);
                    if c == AZIMUTH {
                        let won = e[VELOCITY].abs() < e[HOLD].abs();
                        self.turn_wins[k] = self.turn_wins[k] * decay + f64::from(u8::from(won));
                    }
                    let (sums, squares) = (&mut self.sums[k][c], &mut self.squares[k][c]);
                    for a in 0..CANDIDATES {
                        for b in 0..CANDIDATES {
                            sums[a][b] = sums[a][b] * decay + e[a] * e[b];
                            squares[a][b] = squares[a][b] * decay + (e[a] * e[b]).powi(2);
                        }
                    }
                }
            }
        }
        self.ring[self.next] = Prediction {
            poses,
            mixed,
            spread,
        };
        self.due[self.next] = Due {
            made: t,
            pending: [true; H],
        };
        self.next = (self.next + 1) % self.ring.len();
    }

    /// Per component, the weights of hold, damped trend, plain trend and constant velocity
    /// (non-negative, summing to one) for a forecast `horizon` seconds ahead: those of the
    /// checked horizon nearest to it (on a log scale), once it has been scored a few times.
    /// Before that, the centre takes a shorter horizon's and the angles their prior, and before
    /// any check every component its prior.
    pub fn weights(&self, horizon: f64) -> [[f64; CANDIDATES]; 5] {
        let mut w = self.mixed_weights(horizon);
        if self.walk_ended {
            w[0] = HOLD_ONLY;
            w[1] = HOLD_ONLY;
        }
        w
    }

    /// [`weights`](Self::weights) before a walk that has ended is held.
    fn mixed_weights(&self, horizon: f64) -> [[f64; CANDIDATES]; 5] {
        let nearest = self.nearest(horizon);
        match self.checked(horizon) {
            Some(k) if k == nearest => self.mix(k),
            // Not yet checked this far: a walk mostly goes on, so the centre's shorter check
            // serves; an angle's evidence at a shorter horizon says little of a longer one.
            Some(k) => {
                let mix = self.mix(k);
                let prior = self.unchecked(nearest);
                std::array::from_fn(|c| if c < 3 { mix[c] } else { prior[c] })
            }
            None => self.unchecked(nearest),
        }
    }

    /// Every component's prior for checked horizon `k`, as weights.
    fn unchecked(&self, k: usize) -> [[f64; CANDIDATES]; 5] {
        std::array::from_fn(|c| {
            let mut w = [0.0; CANDIDATES];
            w[self.prior(c, k)] = 1.0;
            w
        })
    }

    /// Component `c`'s prior candidate for checked horizon `k` (see the module's description):
    /// a walk mostly goes on, a turn is continued further ahead than it has been seen only once
    /// the track's forecasts have shown it going on.
    fn prior(&self, c: usize, k: usize) -> usize {
        let steady = match c {
            0..=2 => self.steady[c],
            AZIMUTH => {
                self.steady[c]
                    && (self.seen >= HORIZONS[k] - 1e-9 || self.turn_shown(k))
                    && self.turn_goes_on()
            }
            _ => false,
        };
        if steady {
            VELOCITY
        } else {
            HOLD
        }
    }

    /// Whether the turn is still coming true: continuing the azimuth's line has missed by less
    /// than holding still in at least half of the recent scores at the shortest horizon (yes
    /// before a few scores). A line through a turn that has stopped still passes the
    /// steadiness test for as long as the turn stays in the history; the shortest horizon's
    /// scores are the first to show it stopped. Counting wins, not summing squares: one bad
    /// plane's estimate would outweigh a second of a turn coming true.
    fn turn_goes_on(&self) -> bool {
        self.scored[0] < MIN_SCORED || self.turn_came_true(0)
    }

    /// Whether the track's own forecasts have shown its turn going on at every checked horizon
    /// shorter than `k` (at least one): continuing the azimuth's line missed by less than
    /// holding still in at least half of the recent scores at each. Wins, as in
    /// [`turn_goes_on`](Self::turn_goes_on): the mean gain in squares, against its spread, hardly
    /// ever showed a turn, bad planes and all, going on.
    fn turn_shown(&self, k: usize) -> bool {
        k > 0 && (0..k).all(|j| self.turn_came_true(j))
    }

    /// Whether continuing the azimuth's line has missed by less than holding still in at least
    /// half of the recent scores at checked horizon `k`, scored a few times.
    fn turn_came_true(&self, k: usize) -> bool {
        self.scored[k] >= MIN_SCORED && self.turn_wins[k] >= 0.5 * self.scored[k]
    }

    /// Tells the check what the line through the track's history shows: which components
    /// move steadily, how many seconds of history it holds and whether a walk in it has ended
    /// ([`Trend::steady`], [`Trend::seen`], [`Trend::walk_ended`]).
    pub fn set_trend(&mut self, trend: &Trend) {
        self.set_steady(trend.steady(), trend.seen);
        self.walk_ended = trend.walk_ended();
    }

    /// Tells the check which components of the track's history move steadily
    /// ([`crate::trend`]) and how many seconds of history it holds: a steady component takes a
    /// trend as its prior (a steady turn only for horizons up to that long, unless its forecasts
    /// have shown it going on), the others holding still. No walk in it has ended
    /// ([`set_trend`](Self::set_trend) says so where one has): what an earlier call was told
    /// of the history does not outlast a new one.
    pub fn set_steady(&mut self, steady: [bool; 5], seen: f64) {
        self.walk_ended = false;
        if steady != self.steady || seen != self.seen {
            self.steady = steady;
            self.seen = seen;
            self.fresh = [false; H];
        }
    }

    /// Brings the weights that serve `horizon` up to date, so that later calls of
    /// [`weights`](Self::weights) and [`spread`](Self::spread) in the same frame read them
    /// instead of solving for them again.
    pub fn prepare(&mut self, horizon: f64) {
        if let Some(k) = self.checked(horizon) {
            if !self.fresh[k] {
                self.mix[k] = self.solve(k);
                self.fresh[k] = true;
            }
        }
    }

    fn mix(&self, k: usize) -> [[f64; CANDIDATES]; 5] {
        if self.fresh[k] {
            self.mix[k]
        } else {
            self.solve(k)
        }
    }

    fn solve(&self, k: usize) -> [[f64; CANDIDATES]; 5] {
        // Over the ground, one mix for both coordinates of a walk, from the products of the
        // error vectors (summed over x and y): a walk is one motion whichever way it runs
        // against the world's axes, and each coordinate's own scores alone are half the evidence.
        let ground: [[f64; CANDIDATES]; CANDIDATES] = std::array::from_fn(|a| {
            std::array::from_fn(|b| self.sums[k][0][a][b] + self.sums[k][1][a][b])
        });
        std::array::from_fn(|c| {
            // A walk's centre mixes its trends freely: gated, the walkers' forecasts came late.
            if c < 3 && self.steady[c] {
                let sums = if c < 2 { &ground } else { &self.sums[k][c] };
                return convex_min_variance(sums, allowed(c), HOLD);
            }
            let p = self.prior(c, k);
            let significant = (0..CANDIDATES)
                .filter(|&a| allowed(c) & (1 << a) != 0 && self.significant(k, c, a, p))
                .fold(1 << p, |set, a| set | (1 << a));
            convex_min_variance(&self.sums[k][c], significant, p)
        })
    }

    /// Whether candidate `a`'s mean gain over `p` at checked horizon `k` on component `c` is
    /// [`SIGNIFICANCE`] standard errors above zero, with one effective score per horizon's span.
    fn significant(&self, k: usize, c: usize, a: usize, p: usize) -> bool {
        let (s, q, n) = (&self.sums[k][c], &self.squares[k][c], self.scored[k]);
        let mean = (s[p][p] - s[a][a]) / n;
        let second = (q[p][p] - 2.0 * q[a][p] + q[a][a]) / n;
        let spread = (second - mean * mean).max(0.0).sqrt();
        let independent = (n * self.half_step * 2.0 / HORIZONS[k]).max(1.0);
        mean > SIGNIFICANCE * spread / independent.sqrt()
    }

    /// Per component, the root-mean-square error the mix of [`weights`](Self::weights) made on
    /// the recent scores at the checked horizon nearest to `horizon` (scaled by the square root
    /// of the horizons' ratio where a shorter check stands in for it); `None` before any check
    /// has been scored a few times. The scores are against the track's own later estimates, so
    /// the spread holds their noise as well as the forecast's.
    pub fn spread(&self, horizon: f64) -> Option<[f64; 5]> {
        let k = self.checked(horizon)?;
        Some(self.spread_of(horizon, k, &self.weights(horizon)))
    }

    /// [`spread`](Self::spread) with the weights `w` and checked horizon `k` that serve
    /// `horizon`.
    fn spread_of(&self, horizon: f64, k: usize, w: &[[f64; CANDIDATES]; 5]) -> [f64; 5] {
        let growth = if k == self.nearest(horizon) {
            1.0
        } else {
            (horizon / HORIZONS[k]).max(1.0).sqrt()
        };
        std::array::from_fn(|c| {
            growth * (quadratic(&self.sums[k][c], &w[c]).max(0.0) / self.scored[k]).sqrt()
        })
    }

    /// Per component, the half-width of an interval meant to hold the pose `horizon` seconds
    /// ahead with probability [`COVERAGE`]: the [`spread`](Self::spread) times the share
    /// [`COVERAGE`] of the track's recent errors at that horizon in units of the spread given
    /// with them, [`INTERVAL_80`] counted among them as one error's worth (so a
    /// walker's few outliers, which swell its spread, and a player whose motion keeps changing
    /// beyond what its spread foresaw, each move their own multiple), times [`TRUTH_MARGIN`].
    /// Where a shorter check stands in for `horizon`, [`INTERVAL_80`] in place of the
    /// multiple. `None` when `spread` is.
    pub fn half_width(&self, horizon: f64) -> Option<[f64; 5]> {
        let k = self.checked(horizon)?;
        let spread = self.spread_of(horizon, k, &self.weights(horizon));
        let own = k == self.nearest(horizon);
        Some(within_half_turn(std::array::from_fn(|c| {
            let multiple = if own {
                self.tails[k][c].quantile(COVERAGE, INTERVAL_80[c], PRIOR_SCORES)
            } else {
                INTERVAL_80[c]
            };
            multiple * TRUTH_MARGIN[c] * spread[c]
        })))
    }

    /// Per component, the half-width of an interval meant to hold the pose `horizon` seconds
    /// ahead before the track has checked a forecast: [`INTERVAL_80`] times what `trend`, the
    /// line through the track's history, says the forecast given then may err
    /// ([`Trend::spread`]): a component whose prior at that horizon continues the line, by the
    /// uncertainty of the line's rate; one held still (a steady turn further ahead than it has
    /// been seen, the elevation), by the fitted motion ([`Trend::spread`]). `None` for a history
    /// too short to fit.
    pub fn unchecked_half_width(&self, trend: &Trend, horizon: f64) -> Option<[f64; 5]> {
        let k = self.nearest(horizon);
        let continued = std::array::from_fn(|c| self.prior(c, k) == VELOCITY);
        let spread = trend.spread(horizon, continued)?;
        Some(within_half_turn(std::array::from_fn(|c| {
            INTERVAL_80[c] * spread[c]
        })))
    }

    /// Whether [`spread`](Self::spread) has an answer for `horizon` (without computing it).
    pub fn has_spread(&self, horizon: f64) -> bool {
        self.checked(horizon).is_some()
    }

    /// The checked horizon whose scores serve `horizon`: the nearest one once it has been
    /// scored a few times, else the longest shorter one that has; `None` before any has.
    fn checked(&self, horizon: f64) -> Option<usize> {
        (0..=self.nearest(horizon))
            .rev()
            .find(|&k| self.scored[k] >= MIN_SCORED)
    }

    fn nearest(&self, horizon: f64) -> usize {
        // A checked horizon itself, as most forecasts ask, without the logarithms.
        if let Some(k) = HORIZONS.iter().position(|&h| h == horizon) {
            return k;
        }
        (0..H)
            .min_by(|&a, &b| {
                let da = (horizon.max(1e-3) / HORIZONS[a]).ln().abs();
                let db = (horizon.max(1e-3) / HORIZONS[b]).ln().abs();
                da.total_cmp(&db)
            })
            .unwrap_or(0)
    }

    /// Forgets the pending predictions (the history they were made from changed), not the
    /// scores.
    pub fn drop_pending(&mut self) {
        for due in self.due.iter_mut() {
            due.pending = [false; H];
        }
    }

    /// Forgets everything (a person's state reused for a new track).
    pub fn reset(&mut self) {
        self.drop_pending();
        self.sums = [[[[0.0; CANDIDATES]; CANDIDATES]; 5]; H];
        self.squares = [[[[0.0; CANDIDATES]; CANDIDATES]; 5]; H];
        self.scored = [0.0; H];
        self.turn_wins = [0.0; H];
        self.last_scored = [None; H];
        self.tails = [[RecentQuantile::default(); 5]; H];
        self.steady = [false; 5];
        self.seen = 0.0;
        self.walk_ended = false;
        self.mix = [HOLD_ALL; H];
        self.fresh = [false; H];
    }
}

/// One component's weights that hold it still.
const HOLD_ONLY: [f64; CANDIDATES] = [1.0, 0.0, 0.0, 0.0];
/// Every component's prior where nothing moves steadily: holding still.
const HOLD_ALL: [[f64; CANDIDATES]; 5] = [HOLD_ONLY; 5];

/// The candidates a component may mix, as a bit set: all four for the centre and the azimuth
/// (a walk, a steady turn); the elevation holds still. A torso's pitch has no trend a track
/// can continue: on the scenes benchmark's development split, with its trends allowed through
/// the significance test, no motion or view gained or lost more than a tenth of a degree.
fn allowed(component: usize) -> u32 {
    if component == ELEVATION {
        1 << HOLD
    } else {
        0b1111
    }
}

/// The weights `w ≥ 0`, `Σ w = 1` over the `allowed` candidates that minimise `wᵀ S w`: the best
/// of the equality-constrained minima over every subset whose weights come out non-negative.
/// Candidate `start` wins ties and degenerate cases.
fn convex_min_variance(
    s: &[[f64; CANDIDATES]; CANDIDATES],
    allowed: u32,
    start: usize,
) -> [f64; CANDIDATES] {
    let mut best = [0.0; CANDIDATES];
    best[start] = 1.0;
    let mut best_value = quadratic(s, &best);
    for i in (0..CANDIDATES).filter(|&i| i != start && allowed & (1 << i) != 0) {
        // A single candidate needs no solve (and may have erred not at all).
        if s[i][i] < best_value {
            best = [0.0; CANDIDATES];
            best[i] = 1.0;
            best_value = s[i][i];
        }
    }
    for subset in (1u32..(1 << CANDIDATES)).filter(|s| s & !allowed == 0) {
        if subset.count_ones() < 2 {
            continue;
        }
        let mut idx = [0usize; CANDIDATES];
        let mut n = 0;
        for i in (0..CANDIDATES).filter(|i| subset & (1 << i) != 0) {
            idx[n] = i;
            n += 1;
        }
        if let Some(w) = subset_minimum(s, &idx[..n]) {
            let value = quadratic(s, &w);
            if value < best_value - 1e-15 * best_value.abs().max(1e-300) {
                best = w;
                best_value = value;
            }
        }
    }
    best
}

/// `w = S⁻¹1 / (1ᵀS⁻¹1)` on the candidates `idx` (zero elsewhere), if it is non-negative.
fn subset_minimum(s: &[[f64; CANDIDATES]; CANDIDATES], idx: &[usize]) -> Option<[f64; CANDIDATES]> {
    let n = idx.len();
    let mut a = [[0.0; CANDIDATES + 1]; CANDIDATES];
    for (r, &i) in idx.iter().enumerate() {
        for (c, &j) in idx.iter().enumerate() {
            a[r][c] = s[i][j];
        }
        a[r][n] = 1.0;
    }
    // Gaussian elimination with partial pivoting on the n x (n + 1) system.
    for col in 0..n {
        let pivot = (col..n).max_by(|&x, &y| a[x][col].abs().total_cmp(&a[y][col].abs()))?;
        if !(a[pivot][col].abs() > 1e-12 * (1.0 + s[idx[col]][idx[col]].abs())) {
            return None;
        }
        a.swap(col, pivot);
        for r in 0..n {
            if r != col {
                let f = a[r][col] / a[col][col];
                for c in col..=n {
                    a[r][c] -= f * a[col][c];
                }
            }
        }
    }
    let mut x = [0.0; CANDIDATES];
    for r in 0..n {
        x[r] = a[r][n] / a[r][r];
    }
    let total: f64 = x[..n].iter().sum();
    if !(total.abs() > 0.0) || x[..n].iter().any(|v| !(v / total >= 0.0)) {
        return None;
    }
    let mut w = [0.0; CANDIDATES];
    for (r, &i) in idx.iter().enumerate() {
        w[i] = x[r] / total;
    }
    Some(w)
}

fn quadratic(s: &[[f64; CANDIDATES]; CANDIDATES], w: &[f64; CANDIDATES]) -> f64 {
    (0..CANDIDATES)
        .map(|a| (0..CANDIDATES).map(|b| w[a] * s[a][b] * w[b]).sum::<f64>())
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_rate_s_limit_is_spelled_out_as_the_constants_set_it() {
        // The error text is a `&'static str` and cannot be formatted from the constants: this
        // keeps its numbers from going stale when MAX_PREDICTIONS or the horizons change.
        let longest = HORIZONS[H - 1];
        let fastest = MAX_PREDICTIONS as f64 / longest;
        let text = SelfCheck::slots(2.0 * fastest).unwrap_err().to_string();
        for number in [
            format!("at most {MAX_PREDICTIONS} predictions"),
            format!("({longest} s)"),
            format!("up to {fastest} Hz"),
        ] {
            assert!(text.contains(&number), "{number:?} not in {text:?}");
        }
        assert!(SelfCheck::slots(fastest).is_ok());
    }

    #[test]
    fn a_trend_that_comes_true_is_kept_and_one_that_does_not_is_dropped() {
        // Component 0 moves at 1 m/s: the plain trend says so, the damped one says half of it.
        // Component 3 stands still while both trends say it moves at 1 rad/s.
        let mut check = SelfCheck::new(25.0).unwrap();
        assert_eq!(check.weights(0.4), HOLD_ALL);
        for k in 0..150 {
            let t = k as f64 / 25.0;
            let sample = [t, 0.0, 1.0, 0.3, 1.5];
            let damped = HORIZONS.map(|h| [t + 0.5 * h, 0.0, 1.0, 0.3 + 0.5 * h, 1.5]);
            let plain = HORIZONS.map(|h| [t + h, 0.0, 1.0, 0.3 + h, 1.5]);
            check.record(t, sample, &damped, &damped, &plain);
        }
        for h in [0.1, 0.4, 0.8, 1.5, 3.0] {
            let w = check.weights(h);
            assert!((w[0][3] - 1.0).abs() < 1e-12, "{h}: {:?}", w[0]);
            assert!((w[3][0] - 1.0).abs() < 1e-12, "{h}: {:?}", w[3]);
            assert_eq!(w[1], HOLD_ONLY); // all exact: no evidence for a trend
        }
    }

    #[test]
    fn the_spread_is_the_mix_s_rms_error() {
        // Samples alternate between +0.1 and -0.1 every 0.04 s; both trends add 0.3. At 0.4 s
        // (10 steps, an even count) holding is exact; at 1 s (25 steps) it errs by 0.2 every time
        // and still beats the trends. 2 s has not been checked after 1.6 s: the 1 s spread
        // stands in, grown by the square root of 2.
        let mut check = SelfCheck::new(25.0).unwrap();
        assert_eq!(check.spread(0.4), None);
        for k in 0..40 {
            let t = k as f64 / 25.0;
            let sample = [if k % 2 == 0 { 0.1 } else { -0.1 }; 5];
            let trend = sample.map(|v| v + 0.3);
            check.record(t, sample, &[trend; 3], &[trend; 3], &[trend; 3]);
        }
        assert_eq!(check.weights(0.4)[0], HOLD_ONLY);
        assert_eq!(check.weights(1.0)[0], HOLD_ONLY);
        assert!(check.spread(0.4).unwrap()[0] < 1e-12);
        assert!((check.spread(1.0).unwrap()[0] - 0.2).abs() < 1e-9);
        assert!((check.spread(2.0).unwrap()[0] - 0.2 * 2f64.sqrt()).abs() < 1e-9);
    }

    #[test]
    fn a_few_errors_of_its_own_outweigh_the_prior_multiple() {
        // Ten scores, the most a track at 10 frames per second keeps in its first second: nine
        // errors of half the spread given and one of five. The 80 % point is the track's own
        // half spread; the prior, counted as three scores, would have been the answer.
        let mut tails = RecentQuantile::default();
        for z in [0.5; 9].into_iter().chain([5.0]) {
            tails.add(Some(z), 1.0);
        }
        let own = tails.quantile(COVERAGE, INTERVAL_80[AZIMUTH], PRIOR_SCORES);
        assert!((own / 0.5 - 1.0).abs() < 0.15, "{own}");
        let as_three = tails.quantile(COVERAGE, INTERVAL_80[AZIMUTH], 3.0);
        assert_eq!(as_three, INTERVAL_80[AZIMUTH]);
    }

    #[test]
    fn the_interval_s_multiple_of_the_spread_is_the_track_s_own_errors_quantile() {
        // Samples of ±0.1 in a pseudo-random order, every candidate holding still: half the
        // errors 0.4 s ahead are 0 and half ±0.2, so the spread (their root mean square) is
        // 0.2 / √2 and 80 % of the errors lie within √2 spreads, not INTERVAL_80's 2 (the
        // half-width is that multiple times the truth's margin).
        let mut check = SelfCheck::new(25.0).unwrap();
        let mut state: u32 = 12345;
        for k in 0..200 {
            let t = k as f64 / 25.0;
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let sample = [if state >> 31 == 1 { 0.1 } else { -0.1 }; 5];
            // A track's forecast in each frame brings its mix up to date.
            for h in HORIZONS {
                check.prepare(h);
            }
            if k == 15 {
                // Scored a few times, nothing of its own errors yet: the prior multiple, times
                // each component's own margin.
                let (half, spread) = (check.half_width(0.4).unwrap(), check.spread(0.4).unwrap());
                for c in 0..5 {
                    let want = INTERVAL_80[c] * TRUTH_MARGIN[c];
                    assert!((half[c] / spread[c] - want).abs() < 1e-12, "{c}");
                }
            }
            check.record(t, sample, &[sample; 3], &[sample; 3], &[sample; 3]);
        }
        let (half, spread) = (check.half_width(0.4).unwrap(), check.spread(0.4).unwrap());
        let multiple = half[0] / spread[0] / TRUTH_MARGIN[0];
        assert!((multiple / 2f64.sqrt() - 1.0).abs() < 0.13, "{multiple}");
        assert!(
            (spread[0] - 0.2 / 2f64.sqrt()).abs() < 0.03,
            "{}",
            spread[0]
        );
    }

    #[test]
    fn an_angle_trend_enters_the_mix_only_when_its_gain_is_significant() {
        // The azimuth of one track turns at 0.5 rad/s (constant velocity is exact, holding errs
        // by 0.5 h); the other's is level noise, where a velocity candidate is off by a small
        // error of either sign that, scored against the noisy samples, sometimes wins.
        let noise = |k: usize| 0.05 * ((k * 7919 % 101) as f64 / 50.0 - 1.0);
        let (mut turn, mut level) = (SelfCheck::new(25.0).unwrap(), SelfCheck::new(25.0).unwrap());
        for k in 0..150 {
            let t = k as f64 / 25.0;
            let at = |az: f64| [0.0, 0.0, 1.0, az, 1.5];
            let held = [at(0.5 * t); 3];
            let velocity = HORIZONS.map(|h| at(0.5 * (t + h)));
            turn.record(t, at(0.5 * t), &held, &held, &velocity);
            let held = [at(noise(k)); 3];
            let wrong =
                HORIZONS.map(|h| at(noise(k) + 0.02 * h * if k % 2 == 0 { 1.0 } else { -1.0 }));
            level.record(t, at(noise(k)), &held, &held, &wrong);
        }
        for h in [0.4, 1.0, 2.0] {
            assert_eq!(turn.weights(h)[AZIMUTH], [0.0, 0.0, 0.0, 1.0], "{h}");
            assert_eq!(level.weights(h)[AZIMUTH], HOLD_ONLY, "{h}");
        }
    }

    #[test]
    fn a_walk_that_has_ended_is_held_over_the_ground_whatever_its_scores() {
        // Two seconds of a walk along x whose constant velocity came true: the mix continues it.
        let mut check = SelfCheck::new(25.0).unwrap();
        check.set_steady([true, true, false, false, false], 2.0);
        for k in 0..60 {
            let t = k as f64 / 25.0;
            let sample = [t, 0.0, 1.0, 0.0, 1.5];
            let walked = HORIZONS.map(|h| [t + h, 0.0, 1.0, 0.0, 1.5]);
            let held = HORIZONS.map(|_| sample);
            check.record(t, sample, &held, &held, &walked);
        }
        assert_eq!(check.weights(1.0)[0], [0.0, 0.0, 0.0, 1.0]);
        // Its history's last moments show it has stopped: held over the ground, the height
        // and the angles left as they were.
        let stopped = {
            let mut f = crate::Forecaster::new(crate::ForecasterConfig::default()).unwrap();
            for k in 0..50 {
                let x = (k as f64).min(38.0) / 25.0;
                f.update([x, 0.0, 1.0, 0.0, 1.5], k as f64 / 25.0, 1.0)
                    .unwrap();
            }
            Trend::of(&f)
        };
        assert!(stopped.walk_ended());
        let before = check.weights(1.0);
        check.set_trend(&stopped);
        for h in HORIZONS {
            let w = check.weights(h);
            assert_eq!((w[0], w[1]), (HOLD_ONLY, HOLD_ONLY), "{h}");
            assert_eq!(w[2..], before[2..], "{h}");
        }
        // Walking on again: the scores decide once more.
        let mut going = stopped;
        going.recent_speed = going.rate[0];
        check.set_trend(&going);
        assert_eq!(check.weights(1.0)[0], [0.0, 0.0, 0.0, 1.0]);
        // Told only what moves steadily, the check keeps no ended walk from an earlier call.
        check.set_trend(&stopped);
        check.set_steady([true, true, false, false, false], 2.0);
        assert_eq!(check.weights(1.0)[0], [0.0, 0.0, 0.0, 1.0]);
    }

    #[test]
    fn a_steady_motion_makes_a_trend_the_prior() {
        let mut check = SelfCheck::new(25.0).unwrap();
        assert!(check.weights(0.4).iter().all(|w| *w == HOLD_ONLY));
        check.set_steady([true; 5], 1.0);
        let w = check.weights(0.4);
        assert_eq!(w[0], [0.0, 0.0, 0.0, 1.0]); // a walk: constant velocity
        assert_eq!(w[AZIMUTH], [0.0, 0.0, 0.0, 1.0]); // a steady turn too
        assert_eq!(w[ELEVATION], HOLD_ONLY); // a torso does not keep pitching

        // Seen for a second: the walk is continued two seconds ahead, the turn not.
        let w = check.weights(2.0);
        assert_eq!((w[0], w[AZIMUTH]), ([0.0, 0.0, 0.0, 1.0], HOLD_ONLY));
    }

    #[test]
    fn a_walk_s_two_coordinates_share_one_mix_whichever_way_it_runs() {
        // A steady walk at 1 m/s whose plain trend errs across the path and whose line errs
        // along it, run along x and along the diagonal: the same walk, so the same mix, and one
        // for both coordinates.
        let mix = |heading: f64| {
            let (s, c) = heading.sin_cos();
            let at = |along: f64, across: f64| {
                [
                    c * along - s * across,
                    s * along + c * across,
                    1.0,
                    0.0,
                    1.5,
                ]
            };
            let mut check = SelfCheck::new(25.0).unwrap();
            check.set_steady([true, true, false, false, false], 2.0);
            for k in 0..150 {
                let t = k as f64 / 25.0;
                let wobble = if k % 3 == 0 { 0.1 } else { -0.05 };
                let held = [at(t, 0.0); 3];
                let plain = HORIZONS.map(|h| at(t + h, wobble * h));
                let line = HORIZONS.map(|h| at(t + h + 0.5 * wobble * h, 0.0));
                check.record(t, at(t, 0.0), &held, &plain, &line);
            }
            let w = check.weights(1.0);
            (w[0], w[1])
        };
        let (x, y) = mix(0.0);
        assert!(
            x.iter().zip(y).all(|(a, b)| (a - b).abs() < 1e-12),
            "{x:?} {y:?}"
        );
        assert!(x[2] > 0.05 && x[3] > 0.05, "a mix of the two trends: {x:?}");
        let (dx, dy) = mix(std::f64::consts::FRAC_PI_4);
        for w in [dx, dy] {
            assert!(
                w.iter().zip(x).all(|(a, b)| (a - b).abs() < 1e-9),
                "{w:?} {x:?}"
            );
        }
    }

    #[test]
    fn a_turn_is_continued_further_than_seen_once_its_forecasts_have_come_true() {
        // Young tracks whose azimuth history is a steady turn seen for 1.2 s. One turn goes
        // on: continuing it came true 0.4 and 1 s ahead, holding erred by 0.2 and 0.5 rad. So
        // does another, but every fifth estimate is a bad plane 1 rad behind, which holding
        // misses by less: in squares holding wins or the turn's gain is lost in its spread, in
        // the count of scores the turn wins. The last stopped as each forecast was made:
        // continuing it erred, holding was right.
        let mut going = SelfCheck::new(25.0).unwrap();
        let (mut bad_planes, mut stopped) = (going.clone(), going.clone());
        for check in [&mut going, &mut bad_planes, &mut stopped] {
            check.set_steady([false, false, false, true, false], 1.2);
        }
        let at = |az: f64| [0.0, 0.0, 1.0, az, 1.5];
        for k in 0..30 {
            let t = k as f64 / 25.0;
            let held = [at(0.5 * t); 3];
            let velocity = HORIZONS.map(|h| at(0.5 * (t + h)));
            going.record(t, at(0.5 * t), &held, &held, &velocity);
            let bad = if k % 5 == 4 { 1.0 } else { 0.0 };
            bad_planes.record(t, at(0.5 * t - bad), &held, &held, &velocity);
            let held = [at(0.0); 3];
            let velocity = HORIZONS.map(|h| at(0.5 * h));
            stopped.record(t, at(0.0), &held, &held, &velocity);
        }
        assert!((0..2).all(|j| !bad_planes.significant(j, AZIMUTH, VELOCITY, HOLD)));
        // 2 s ahead (not yet checked, and longer than the turn has been seen): the turns whose
        // forecasts came true are continued, the other held.
        assert_eq!(going.weights(2.0)[AZIMUTH], [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(bad_planes.weights(2.0)[AZIMUTH], [0.0, 0.0, 0.0, 1.0]);
        assert_eq!(stopped.weights(2.0)[AZIMUTH], HOLD_ONLY);
        // Before any forecast was scored, neither had shown anything: both held.
        let mut young = SelfCheck::new(25.0).unwrap();
        young.set_steady([false, false, false, true, false], 1.2);
        assert_eq!(young.weights(2.0)[AZIMUTH], HOLD_ONLY);
    }

    #[test]
    fn a_steady_turn_stops_being_the_prior_once_holding_wins_most_of_its_recent_scores() {
        // Two tracks whose 2 s histories both pass the steadiness test for a turn. One turn
        // goes on (continuing it comes true 0.4 s ahead, holding errs by 0.2 rad) but every
        // fifth estimate is a bad plane 1 rad behind, which holding misses by less: in squares
        // holding wins, in the count of scores the turn does. The other turn has stopped.
        let (mut going, mut stopped) =
            (SelfCheck::new(25.0).unwrap(), SelfCheck::new(25.0).unwrap());
        for check in [&mut going, &mut stopped] {
            check.set_steady([false, false, false, true, false], 2.0);
        }
        let at = |az: f64| [0.0, 0.0, 1.0, az, 1.5];
        for k in 0..50 {
            let t = k as f64 / 25.0;
            let bad = if k % 5 == 4 { 1.0 } else { 0.0 };
            let held = [at(0.5 * t); 3];
            let velocity = HORIZONS.map(|h| at(0.5 * (t + h)));
            going.record(t, at(0.5 * t - bad), &held, &held, &velocity);
            let held = [at(0.0); 3];
            let velocity = HORIZONS.map(|h| at(0.5 * h));
            stopped.record(t, at(0.0), &held, &held, &velocity);
        }
        let squares = &going.sums[0][AZIMUTH];
        assert!(squares[HOLD][HOLD] < squares[VELOCITY][VELOCITY]);
        assert_eq!(going.prior(AZIMUTH, 0), VELOCITY);
        assert_eq!(stopped.prior(AZIMUTH, 0), HOLD);
        assert_eq!(stopped.weights(0.4)[AZIMUTH], HOLD_ONLY);
        // The walk's prior is not the turn's business.
        stopped.set_steady([true, false, false, true, false], 2.0);
        assert_eq!(stopped.prior(0, 0), VELOCITY);
    }

    #[test]
    fn an_unchecked_interval_is_that_of_the_forecast_the_prior_gives() {
        // A steady turn at 0.5 rad/s seen for 1.2 s, its rate 20 standard errors from zero;
        // nothing checked yet. 0.4 and 1 s ahead the turn is continued: the interval allows for
        // its rate's standard error. 2 s ahead (further than it has been seen) the heading is
        // held: the interval allows for the turn (its rate less its standard error, in squares).
        // The elevation, held at every horizon however steadily it moves, likewise.
        let trend = Trend {
            rate: [0.0, 0.0, 0.0, 0.5, 0.1],
            significance: [0.0, 0.0, 0.0, 20.0, 20.0],
            scatter: [0.01, 0.01, 0.01, 0.05, 0.02],
            seen: 1.2,
            ..Trend::default()
        };
        let mut check = SelfCheck::new(25.0).unwrap();
        check.set_steady(trend.steady(), trend.seen);
        let held = |rate: f64| (rate * rate - (rate / 20.0).powi(2)).sqrt();
        for (h, rate) in [(0.4, 0.5 / 20.0), (1.0, 0.5 / 20.0), (2.0, held(0.5))] {
            let w = check.unchecked_half_width(&trend, h).unwrap();
            let expected = INTERVAL_80[AZIMUTH] * 0.05f64.hypot(rate * h);
            assert!((w[AZIMUTH] - expected).abs() < 1e-12, "{h}: {w:?}");
            let expected = INTERVAL_80[ELEVATION] * 0.02f64.hypot(held(0.1) * h);
            assert!((w[ELEVATION] - expected).abs() < 1e-12, "{h}: {w:?}");
        }
    }

    #[test]
    fn an_angle_interval_is_at_most_half_a_turn() {
        // Estimates that swing by 3 rad (and 10 m) about the forecasts every 0.4 s: the spread
        // times the multiple is well over half a turn, and says no more than half a turn does.
        let mut check = SelfCheck::new(25.0).unwrap();
        for k in 0..60 {
            let t = k as f64 / 25.0;
            let swing = if (k / 10) % 2 == 0 { 1.0 } else { -1.0 };
            let sample = [10.0 * swing, 0.0, 1.0, 3.0 * swing, 1.5];
            let forecast = [[0.0, 0.0, 1.0, 0.0, 1.5]; 3];
            check.record(t, sample, &forecast, &forecast, &forecast);
        }
        let spread = check.spread(0.4).unwrap();
        assert!(INTERVAL_80[AZIMUTH] * spread[AZIMUTH] > PI, "{spread:?}");
        let half = check.half_width(0.4).unwrap();
        assert_eq!(half[AZIMUTH], PI);
        assert!(half[0] > 10.0); // a distance has no such bound
        let trend = Trend {
            rate: [0.0, 0.0, 0.0, 5.0, 0.0],
            significance: [0.0, 0.0, 0.0, 20.0, 0.0],
            scatter: [0.01; 5],
            seen: 1.0,
            ..Trend::default()
        };
        let unchecked = SelfCheck::new(25.0)
            .unwrap()
            .unchecked_half_width(&trend, 2.0)
            .unwrap();
        assert_eq!(unchecked[AZIMUTH], PI);
    }

    #[test]
    fn the_convex_minimum_matches_closed_forms() {
        // Two independent predictors of variances 1 and 3: weights 3/4 and 1/4.
        let s = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 3.0, 0.0, 0.0],
            [0.0, 0.0, 1e9, 0.0],
            [0.0, 0.0, 0.0, 1e9],
        ];
        let w = convex_min_variance(&s, 0b1111, HOLD);
        assert!((w[0] - 0.75).abs() < 1e-6 && (w[1] - 0.25).abs() < 1e-6 && w[2].abs() < 1e-6);
        // A predictor whose error is always larger and positively correlated gets no weight.
        let s = [
            [1.0, 1.5, 0.0, 0.0],
            [1.5, 4.0, 0.0, 0.0],
            [0.0, 0.0, 9.0, 0.0],
            [0.0, 0.0, 0.0, 9.0],
        ];
        let w = convex_min_variance(&s, 0b1111, HOLD);
        assert!(w.iter().all(|&v| v >= 0.0) && (w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert!(w[1].abs() < 1e-12, "{w:?}");
    }
}
