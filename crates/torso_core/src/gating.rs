//! Per-joint temporal gating (thesis section 3.2): a joint that moves more than a threshold
//! between consecutive frames, or is missing, is replaced by its previous value; after too many
//! consecutive replacements it is reported lost rather than frozen forever, and the next finite
//! measurement is accepted afresh.

use crate::error::{check_len, check_positive, Error, Result};

/// Gating parameters.
///
/// ```
/// use torso_core::GateConfig;
/// let thesis = GateConfig::default();
/// assert_eq!((thesis.threshold, thesis.max_replacements), (0.1, 10));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GateConfig {
    /// Largest accepted frame-to-frame displacement (m). Thesis: 0.10 m.
    pub threshold: f64,
    /// Consecutive replacements after which the joint is reported lost. The thesis leaves this
    /// open; 10 frames is 0.4 s at 25 Hz, about as long as a torso joint can be held still before
    /// a walking person has moved away from it.
    pub max_replacements: u32,
}

impl Default for GateConfig {
    fn default() -> Self {
        Self {
            threshold: 0.10,
            max_replacements: 10,
        }
    }
}

/// What the gate did with one joint in one frame.
///
/// ```
/// use torso_core::JointStatus;
/// assert_eq!(JointStatus::Replaced as u8, 1);
/// assert_eq!(JointStatus::NAMES[2], ("LOST", JointStatus::Lost));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
#[repr(u8)]
pub enum JointStatus {
    /// The measurement was accepted.
    Measured = 0,
    /// Missing or jumping: the previous accepted position was used.
    Replaced = 1,
    /// No usable position: never seen yet, or replaced too many times in a row. Output is NaN.
    #[default]
    Lost = 2,
}

impl JointStatus {
    /// Every status with its name and code, for bindings.
    pub const NAMES: [(&'static str, JointStatus); 3] = [
        ("MEASURED", JointStatus::Measured),
        ("REPLACED", JointStatus::Replaced),
        ("LOST", JointStatus::Lost),
    ];
}

/// Most joints a gate takes (skeletons have tens): a size from a caller is bounded before it is
/// allocated.
pub const MAX_JOINTS: usize = 1024;

/// Gating state for one person's joints; all buffers are sized at construction.
///
/// ```
/// use torso_core::{GateConfig, JointGate, JointStatus};
/// let mut gate = JointGate::new(1, GateConfig::default()).unwrap();
/// let mut status = [JointStatus::Lost];
/// let mut joint = [[1.0, 0.0, 1.0]];
/// gate.update(&mut joint, &mut status).unwrap();
/// let mut jumped = [[1.5, 0.0, 1.0]]; // 0.5 m in one frame: a wrong depth reading
/// gate.update(&mut jumped, &mut status).unwrap();
/// assert_eq!((jumped[0], status[0]), ([1.0, 0.0, 1.0], JointStatus::Replaced));
/// ```
#[derive(Clone, Debug)]
pub struct JointGate {
    config: GateConfig,
    previous: Vec<Option<[f64; 3]>>,
    replaced_run: Vec<u32>,
}

impl JointGate {
    pub fn new(n_joints: usize, config: GateConfig) -> Result<Self> {
        check_positive(
            "threshold",
            config.threshold,
            "a positive, finite distance in metres",
        )?;
        if !(1..=MAX_JOINTS).contains(&n_joints) {
            return Err(Error::InvalidArgument {
                name: "n_joints",
                expected: "from 1 to MAX_JOINTS (1024) joints",
                value: n_joints as f64,
            });
        }
        Ok(Self {
            config,
            previous: vec![None; n_joints],
            replaced_run: vec![0; n_joints],
        })
    }

    pub fn n_joints(&self) -> usize {
        self.previous.len()
    }

    pub fn config(&self) -> GateConfig {
        self.config
    }

    /// Forgets every joint (a new track).
    pub fn reset(&mut self) {
        self.previous.fill(None);
        self.replaced_run.fill(0);
    }

    /// Exchanges what the gate remembers of joints `a` and `b` (a track that relabels the
    /// body's left and right sides). Out-of-range indices are refused before anything changes.
    pub fn swap(&mut self, a: usize, b: usize) -> Result<()> {
        for (name, i) in [("a", a), ("b", b)] {
            if i >= self.n_joints() {
                return Err(Error::InvalidArgument {
                    name,
                    expected: "a joint index below the gate's joint count",
                    value: i as f64,
                });
            }
        }
        self.previous.swap(a, b);
        self.replaced_run.swap(a, b);
        Ok(())
    }

    /// Gates one frame in place: `joints` (NaN = missing) become the gated positions and
    /// `status` says what happened to each. Lengths are checked before any state changes.
    pub fn update(&mut self, joints: &mut [[f64; 3]], status: &mut [JointStatus]) -> Result<()> {
        self.update_holding(joints, status, self.config.max_replacements)
    }

    /// [`update`](Self::update), holding a joint over for at most `max_replacements` frames in
    /// a row instead of the configured count: a caller whose frame rate varies holds a joint
    /// for a time rather than a number of frames.
    pub fn update_holding(
        &mut self,
        joints: &mut [[f64; 3]],
        status: &mut [JointStatus],
        max_replacements: u32,
    ) -> Result<()> {
        check_len("joints", joints.len(), self.n_joints())?;
        check_len("status", status.len(), self.n_joints())?;
        let limit = self.config.threshold * self.config.threshold;
        for ((x, st), (prev, run)) in joints
            .iter_mut()
            .zip(status.iter_mut())
            .zip(self.previous.iter_mut().zip(self.replaced_run.iter_mut()))
        {
            let finite = x.iter().all(|v| v.is_finite());
            *st = match *prev {
                Some(p) if finite && squared_distance(x, &p) <= limit => JointStatus::Measured,
                Some(_) if *run < max_replacements => JointStatus::Replaced,
                Some(_) => JointStatus::Lost,
                None if finite => JointStatus::Measured,
                None => JointStatus::Lost,
            };
            match *st {
                JointStatus::Measured => {
                    *prev = Some(*x);
                    *run = 0;
                }
                JointStatus::Replaced => {
                    *x = prev.expect("replaced joints have a previous value");
                    *run += 1;
                }
                JointStatus::Lost => {
                    *x = [f64::NAN; 3];
                    *prev = None;
                    *run = 0;
                }
            }
        }
        Ok(())
    }
}

fn squared_distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]) * (a[k] - b[k])).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use JointStatus::*;

    #[test]
    fn a_joint_is_held_over_as_many_frames_as_the_caller_says() {
        let mut gate = JointGate::new(1, GateConfig::default()).unwrap();
        let mut status = [Lost];
        gate.update(&mut [[0.0, 0.0, 1.0]], &mut status).unwrap();
        let mut seen = Vec::new();
        for _ in 0..5 {
            gate.update_holding(&mut [[f64::NAN; 3]], &mut status, 3)
                .unwrap();
            seen.push(status[0]);
        }
        assert_eq!(seen, [Replaced, Replaced, Replaced, Lost, Lost]);
    }

    #[test]
    fn swapping_exchanges_two_joints_memories_and_refuses_indices_out_of_range() {
        let mut gate = JointGate::new(2, GateConfig::default()).unwrap();
        let mut joints = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0]];
        let mut status = [Lost; 2];
        gate.update(&mut joints, &mut status).unwrap();
        let before = format!("{gate:?}");
        assert!(gate.swap(0, 2).is_err() && gate.swap(5, 1).is_err());
        assert_eq!(format!("{gate:?}"), before);
        gate.swap(0, 1).unwrap();
        // The joints in their exchanged places are where the gate now expects them.
        let mut swapped = [[1.0, 0.0, 1.0], [0.0, 0.0, 1.0]];
        gate.update(&mut swapped, &mut status).unwrap();
        assert_eq!(status, [Measured, Measured]);
    }

    #[test]
    fn jumps_and_gaps_are_replaced_then_lost_then_reacquired() {
        let mut gate = JointGate::new(
            1,
            GateConfig {
                threshold: 0.1,
                max_replacements: 2,
            },
        )
        .unwrap();
        let mut st = [Lost];
        let mut run = |x: [f64; 3]| {
            let mut j = [x];
            gate.update(&mut j, &mut st).unwrap();
            (j[0], st[0])
        };
        assert_eq!(run([0.0, 0.0, 1.0]), ([0.0, 0.0, 1.0], Measured));
        assert_eq!(run([0.05, 0.0, 1.0]), ([0.05, 0.0, 1.0], Measured));
        assert_eq!(run([0.5, 0.0, 1.0]), ([0.05, 0.0, 1.0], Replaced));
        assert_eq!(run([f64::NAN; 3]), ([0.05, 0.0, 1.0], Replaced));
        let (x, s) = run([0.6, 0.0, 1.0]);
        assert!(x[0].is_nan() && s == Lost);
        assert_eq!(run([0.6, 0.0, 1.0]), ([0.6, 0.0, 1.0], Measured));
    }

    #[test]
    fn threshold_is_inclusive_and_checked_against_the_last_accepted_value() {
        let mut gate = JointGate::new(2, GateConfig::default()).unwrap();
        let mut st = [Lost; 2];
        let mut j = [[0.0, 0.0, 0.0], [f64::NAN; 3]];
        gate.update(&mut j, &mut st).unwrap();
        assert_eq!(st, [Measured, Lost]);
        let mut j = [[0.0, 0.0, 0.1], [1.0, 1.0, 1.0]];
        gate.update(&mut j, &mut st).unwrap();
        assert_eq!(st, [Measured, Measured]);
    }

    #[test]
    fn bad_calls_leave_the_state_alone() {
        assert!(JointGate::new(
            3,
            GateConfig {
                threshold: -1.0,
                max_replacements: 1
            }
        )
        .is_err());
        assert!(JointGate::new(0, GateConfig::default()).is_err());
        let mut gate = JointGate::new(2, GateConfig::default()).unwrap();
        let mut j = [[0.0; 3]];
        assert!(matches!(
            gate.update(&mut j, &mut [Lost; 2]),
            Err(Error::LengthMismatch { name: "joints", .. })
        ));
        let mut pair = [[0.0; 3], [1.0; 3]];
        assert!(matches!(
            gate.update_holding(&mut pair, &mut [Lost; 3], 4),
            Err(Error::LengthMismatch { name: "status", .. })
        ));
        let mut j = [[0.0; 3], [1.0; 3]];
        let mut st = [Lost; 2];
        gate.update(&mut j, &mut st).unwrap();
        assert_eq!(st, [Measured, Measured]);
    }
}
