//! A track's forecast, checked against the track's own recent past.
//!
//! Whether a trend is worth continuing depends on the person and on the detector: a walker's
//! centre moves steadily, while a detector's azimuth noise on a person standing still makes
//! any fitted trend a guess. Each time the forecaster takes a sample, it also says where the
//! person will be `horizon` seconds later; when that time comes, the prediction is scored
//! against the sample then taken, beside "the pose stays as it was". Per pose component, the
//! forecast given out is the mix of the two that would have erred least on the recent scores
//! (the optimal weight of two correlated predictors, from forgetting sums of their squared
//! and joint errors), so a trend the track's own data do not support is shrunk towards
//! holding still, and a reliable one is kept.

use crate::Pose;

/// Time constant (s) with which old scores are forgotten.
const MEMORY: f64 = 2.0;
/// Predictions scored before the mix is trusted; until then the forecast holds still (a trend
/// the track has not yet seen come true is not given out).
const MIN_SCORED: f64 = 3.0;

#[derive(Clone, Copy, Debug, Default)]
struct Prediction {
    aim: f64,
    hold: Pose,
    trend: Pose,
    pending: bool,
}

/// The predictions awaiting their time and the scores so far; sized at construction.
#[derive(Clone, Debug)]
pub struct SelfCheck {
    horizon: f64,
    half_step: f64,
    ring: Vec<Prediction>,
    next: usize,
    /// Per component: forgetting sums of e_hold², e_trend², e_hold·e_trend.
    sums: [[f64; 3]; 5],
    scored: f64,
    last_scored: Option<f64>,
}

impl SelfCheck {
    /// Checks at `horizon` seconds on a grid of `rate_hz` (room for one prediction per slot).
    pub fn new(horizon: f64, rate_hz: f64) -> Self {
        let slots = (horizon * rate_hz).ceil() as usize + 2;
        Self {
            horizon,
            half_step: 0.5 / rate_hz,
            ring: vec![Prediction::default(); slots],
            next: 0,
            sums: [[0.0; 3]; 5],
            scored: 0.0,
            last_scored: None,
        }
    }

    pub fn horizon(&self) -> f64 {
        self.horizon
    }

    /// The forecaster took `sample` at grid time `t`, and forecasts `trend` for `t + horizon`:
    /// the predictions aimed at `t` are scored against `sample`, and this one is kept.
    pub fn record(&mut self, t: f64, sample: Pose, trend: Pose) {
        for p in self
            .ring
            .iter_mut()
            .filter(|p| p.pending && p.aim <= t + self.half_step)
        {
            p.pending = false;
            let decay = self
                .last_scored
                .map_or(1.0, |last| (-(t - last).max(0.0) / MEMORY).exp());
            self.last_scored = Some(t);
            self.scored = self.scored * decay + 1.0;
            for c in 0..5 {
                let (eh, et) = (sample[c] - p.hold[c], sample[c] - p.trend[c]);
                let s = &mut self.sums[c];
                s[0] = s[0] * decay + eh * eh;
                s[1] = s[1] * decay + et * et;
                s[2] = s[2] * decay + eh * et;
            }
        }
        self.ring[self.next] = Prediction {
            aim: t + self.horizon,
            hold: sample,
            trend,
            pending: true,
        };
        self.next = (self.next + 1) % self.ring.len();
    }

    /// Per component, the weight of the trend in the mix (0: hold still, 1: the forecaster's).
    pub fn trend_weights(&self) -> [f64; 5] {
        if self.scored < MIN_SCORED {
            return [0.0; 5];
        }
        self.sums.map(|[hh, tt, ht]| {
            let spread = hh + tt - 2.0 * ht; // the summed squared difference of the two
            if spread > 0.0 {
                ((hh - ht) / spread).clamp(0.0, 1.0)
            } else {
                0.5
            }
        })
    }

    /// Forgets the pending predictions (the history they were made from changed), not the
    /// scores.
    pub fn drop_pending(&mut self) {
        for p in self.ring.iter_mut() {
            p.pending = false;
        }
    }

    /// Forgets everything (a restarted history).
    pub fn reset(&mut self) {
        self.drop_pending();
        self.sums = [[0.0; 3]; 5];
        self.scored = 0.0;
        self.last_scored = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_trend_that_comes_true_is_kept_and_one_that_does_not_is_dropped() {
        // Component 0 moves at 1 m/s and the trend says so; component 3 stands still and the
        // trend says it moves at 1 rad/s. Hold is wrong for 0, right for 3.
        let mut check = SelfCheck::new(0.4, 25.0);
        assert_eq!(check.trend_weights(), [0.0; 5]);
        for k in 0..100 {
            let t = k as f64 / 25.0;
            let sample = [t, 0.0, 1.0, 0.3, 1.5];
            let trend = [t + 0.4, 0.0, 1.0, 0.3 + 0.4, 1.5];
            check.record(t, sample, trend);
        }
        let w = check.trend_weights();
        assert!((w[0] - 1.0).abs() < 1e-12 && w[3].abs() < 1e-12);
        assert_eq!(w[1], 0.5); // both exact: no evidence either way
    }

    #[test]
    fn two_equally_noisy_independent_predictions_are_mixed_half_and_half() {
        // The truth is 0; hold and trend err by independent ±1 patterns of equal power.
        let mut check = SelfCheck::new(0.04, 25.0);
        for k in 0..400 {
            let t = k as f64 / 25.0;
            let eh = if k % 2 == 0 { 1.0 } else { -1.0 };
            let et = if k % 4 < 2 { 1.0 } else { -1.0 };
            check.record(t, [0.0; 5], [-et; 5]);
            // The prediction stored now is scored at the next sample; make its hold err by eh.
            let last = (check.next + check.ring.len() - 1) % check.ring.len();
            check.ring[last].hold = [-eh; 5];
        }
        let w = check.trend_weights();
        assert!((w[0] - 0.5).abs() < 0.05, "{w:?}");
    }
}
