//! A fixed-capacity history of torso poses on a fixed-rate time grid.
//!
//! Each time stamp is mapped to its nearest grid slot (`t0 + k / rate`): jitter below half a step
//! disappears, a skipped slot is filled by linear interpolation with weight zero (the spline
//! ignores it, the filter gets a plausible value), and a gap longer than `max_gap_steps` restarts
//! the history. Azimuth is unwrapped on the way in, so the history is a continuous signal.

use crate::error::{Error, Result};
use crate::{Pose, AZIMUTH, ELEVATION};
use std::f64::consts::{PI, TAU};

/// Largest magnitude of a pose component (m or rad) a history takes: the filter and the spline's
/// normal equations square the values, so poses near `f64::MAX` turn into infinities.
pub const MAX_POSE_VALUE: f64 = 1e6;

/// What [`History::push`] did besides storing the sample.
///
/// ```
/// use torso_core::{Forecaster, ForecasterConfig};
/// let mut f = Forecaster::new(ForecasterConfig::default()).unwrap();
/// f.update([0.0; 5], 0.0, 1.0).unwrap();
/// let report = f.update([0.0; 5], 0.12, 1.0).unwrap(); // two 25 Hz slots were missed
/// assert_eq!((report.filled, report.restarted), (2, false));
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct UpdateReport {
    /// Missing grid slots filled by interpolation (weight 0) before this sample.
    pub filled: usize,
    /// The gap was too long: the history was cleared and starts again at this sample.
    pub restarted: bool,
}

/// ```
/// use torso_core::history::History;
/// let mut h = History::new(50, 25.0, 10);
/// h.push([0.0, 0.0, 0.0, 3.1, 1.5], 0.0, 1.0).unwrap();
/// h.push([0.0, 0.0, 0.0, -3.1, 1.5], 0.04, 1.0).unwrap();
/// // The azimuth is unwrapped across the branch cut: a small step, not a turn of 6.2 rad.
/// assert!((h.get(1).0[3] - (2.0 * std::f64::consts::PI - 3.1)).abs() < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct History {
    step: f64,
    max_gap_steps: usize,
    poses: Vec<Pose>,
    weights: Vec<f64>,
    /// Ring position of the oldest sample.
    head: usize,
    len: usize,
    origin: f64,
    last_slot: i64,
}

impl History {
    /// Room for `capacity` samples at `rate_hz`; gaps of up to `max_gap_steps` slots are filled.
    pub fn new(capacity: usize, rate_hz: f64, max_gap_steps: usize) -> Self {
        Self {
            step: 1.0 / rate_hz,
            max_gap_steps,
            poses: vec![[0.0; 5]; capacity],
            weights: vec![0.0; capacity],
            head: 0,
            len: 0,
            origin: 0.0,
            last_slot: 0,
        }
    }

    pub fn capacity(&self) -> usize {
        self.poses.len()
    }

    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Grid time of the newest sample.
    pub fn last_time(&self) -> Option<f64> {
        (self.len > 0).then_some(self.origin + self.last_slot as f64 * self.step)
    }

    /// The `i`-th sample, oldest first: pose (azimuth unwrapped) and weight.
    pub fn get(&self, i: usize) -> (Pose, f64) {
        let k = (self.head + i) % self.capacity();
        (self.poses[k], self.weights[k])
    }

    pub fn clear(&mut self) {
        self.len = 0;
        self.head = 0;
    }

    /// Turns every sample to face the other way: the torso normal is negated, so the azimuth
    /// gains π (staying unwrapped) and the elevation becomes π minus itself.
    pub fn flip(&mut self) {
        for i in 0..self.len {
            let k = (self.head + i) % self.capacity();
            self.poses[k][AZIMUTH] += PI;
            self.poses[k][ELEVATION] = PI - self.poses[k][ELEVATION];
        }
    }

    /// Whether a sample at `t` would land on a later grid slot than the newest one (always, for
    /// an empty history): the one rule [`push`](Self::push) applies to time stamps.
    pub fn takes_time(&self, t: f64) -> bool {
        self.last_time().is_none() || self.slot_of(t) > self.last_slot as f64
    }

    fn slot_of(&self, t: f64) -> f64 {
        ((t - self.origin) / self.step).round()
    }

    /// Adds a sample. Everything is checked before anything changes, so a rejected sample
    /// leaves the history exactly as it was.
    pub fn push(&mut self, pose: Pose, t: f64, weight: f64) -> Result<UpdateReport> {
        if !t.is_finite() {
            return Err(Error::NonFinite {
                name: "t",
                index: 0,
            });
        }
        if let Some(index) = pose.iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                name: "pose",
                index,
            });
        }
        if let Some(index) = pose.iter().position(|v| v.abs() > MAX_POSE_VALUE) {
            return Err(Error::InvalidArgument {
                name: "pose",
                expected: "positions and angles within ±1e6 (m, rad): the filter and the fit \
                           overflow far beyond",
                value: pose[index],
            });
        }
        if !(weight.is_finite() && weight >= 0.0) {
            return Err(Error::InvalidArgument {
                name: "weight",
                expected: "a finite, non-negative confidence weight",
                value: weight,
            });
        }
        let Some(previous) = self.last_time() else {
            self.start_at(pose, t, weight);
            return Ok(UpdateReport::default());
        };
        let slot = self.slot_of(t);
        if !(slot > self.last_slot as f64) {
            return Err(Error::TimeNotIncreasing { previous, got: t });
        }
        let missing = slot - self.last_slot as f64 - 1.0;
        if missing > self.max_gap_steps as f64 {
            self.clear();
            self.start_at(pose, t, weight);
            return Ok(UpdateReport {
                filled: 0,
                restarted: true,
            });
        }
        let (last, _) = self.get(self.len - 1);
        let mut pose = pose;
        pose[AZIMUTH] = unwrap_near(pose[AZIMUTH], last[AZIMUTH]);
        let missing = missing as usize;
        for k in 1..=missing {
            let f = k as f64 / (missing + 1) as f64;
            let mut filled = [0.0; 5];
            for c in 0..5 {
                filled[c] = last[c] + f * (pose[c] - last[c]);
            }
            self.append(filled, 0.0);
        }
        self.append(pose, weight);
        self.last_slot = slot as i64;
        Ok(UpdateReport {
            filled: missing,
            restarted: false,
        })
    }

    fn start_at(&mut self, pose: Pose, t: f64, weight: f64) {
        self.origin = t;
        self.last_slot = 0;
        self.append(pose, weight);
    }

    fn append(&mut self, pose: Pose, weight: f64) {
        let cap = self.capacity();
        let k = (self.head + self.len) % cap;
        self.poses[k] = pose;
        self.weights[k] = weight;
        if self.len < cap {
            self.len += 1;
        } else {
            self.head = (self.head + 1) % cap;
        }
    }

    /// Copies the history oldest-first into component-major `values[c * n + i]` and `weights[i]`.
    pub fn copy_component_major(&self, values: &mut [f64], weights: &mut [f64]) {
        let n = self.len;
        for i in 0..n {
            let (pose, w) = self.get(i);
            for (c, v) in pose.iter().enumerate() {
                values[c * n + i] = *v;
            }
            weights[i] = w;
        }
    }
}

/// `angle + 2πk` closest to `reference`.
pub fn unwrap_near(angle: f64, reference: f64) -> f64 {
    angle + TAU * ((reference - angle) / TAU).round()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(v: f64, az: f64) -> Pose {
        [v, 0.0, 0.0, az, 1.5]
    }

    #[test]
    fn azimuth_is_unwrapped_across_the_branch_cut() {
        let mut h = History::new(4, 25.0, 2);
        h.push(pose(0.0, 3.1), 0.0, 1.0).unwrap();
        h.push(pose(0.0, -3.1), 0.04, 1.0).unwrap();
        assert!((h.get(1).0[AZIMUTH] - (TAU - 3.1)).abs() < 1e-12);
    }

    #[test]
    fn gaps_are_filled_with_zero_weight_or_restart_the_history() {
        let mut h = History::new(10, 25.0, 2);
        h.push(pose(0.0, 0.0), 1.0, 1.0).unwrap();
        // Two slots skipped, with 5 ms of jitter.
        let r = h.push(pose(3.0, 0.0), 1.125, 1.0).unwrap();
        assert_eq!(
            r,
            UpdateReport {
                filled: 2,
                restarted: false
            }
        );
        assert_eq!(h.len(), 4);
        assert_eq!(h.get(1), (pose(1.0, 0.0), 0.0));
        assert!((h.last_time().unwrap() - 1.12).abs() < 1e-12);
        let r = h.push(pose(4.0, 0.0), 1.4, 1.0).unwrap();
        assert!(r.restarted && h.len() == 1);
    }

    #[test]
    fn ring_keeps_the_newest_samples() {
        let mut h = History::new(3, 10.0, 0);
        for k in 0..5 {
            h.push(pose(k as f64, 0.0), k as f64 * 0.1, 1.0).unwrap();
        }
        assert_eq!(
            (0..3).map(|i| h.get(i).0[0]).collect::<Vec<_>>(),
            vec![2.0, 3.0, 4.0]
        );
    }

    #[test]
    fn rejected_samples_change_nothing() {
        let mut h = History::new(3, 25.0, 1);
        h.push(pose(0.0, 0.0), 0.0, 1.0).unwrap();
        assert!(matches!(
            h.push(pose(1.0, 0.0), 0.01, 1.0),
            Err(Error::TimeNotIncreasing { .. })
        ));
        assert!(matches!(
            h.push(pose(1.0, 0.0), -1.0, 1.0),
            Err(Error::TimeNotIncreasing { .. })
        ));
        assert!(matches!(
            h.push([f64::NAN; 5], 0.04, 1.0),
            Err(Error::NonFinite { name: "pose", .. })
        ));
        assert!(matches!(
            h.push(pose(1.0, 0.0), f64::NAN, 1.0),
            Err(Error::NonFinite { name: "t", .. })
        ));
        assert!(matches!(
            h.push(pose(1.0, 0.0), 0.04, -0.5),
            Err(Error::InvalidArgument { name: "weight", .. })
        ));
        assert_eq!(h.len(), 1);
    }

    #[test]
    fn a_pose_too_large_to_filter_is_refused_and_changes_nothing() {
        let mut h = History::new(10, 25.0, 10);
        h.push([0.0, 0.0, 1.0, 0.1, 1.5], 0.0, 1.0).unwrap();
        for bad in [1e7, -1e308] {
            assert!(h.push([bad, 0.0, 1.0, 0.1, 1.5], 0.04, 1.0).is_err());
            assert_eq!(h.len(), 1);
        }
        assert!(h.push([1e6, 0.0, 1.0, 0.1, 1.5], 0.04, 1.0).is_ok());
    }
}
