//! What a track made of one frame.

use crate::coco::{Joints, N_JOINTS};
use crate::gating::JointStatus;
use crate::Pose;

/// Where a frame's pose came from.
///
/// ```
/// use torso_core::Estimate;
/// assert_eq!(Estimate::Shoulders as u8, 2);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Estimate {
    /// Nothing to estimate it from: no pose this frame.
    None = 0,
    /// The torso plane through at least three torso joints.
    Plane = 1,
    /// The shoulder line and gravity (azimuth only; the elevation is held).
    Shoulders = 2,
}

/// What the forecaster's time grid did with a frame.
///
/// ```
/// use torso_core::GridReport;
/// let report = GridReport::default();
/// assert!(!report.skipped && !report.restarted && report.filled == 0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GridReport {
    /// Slots interpolated before this sample.
    pub filled: usize,
    /// The history was cleared after a gap longer than the forecaster's `max_gap`.
    pub restarted: bool,
    /// A faster camera than the grid: the frame's slot already had a sample, so it was not added.
    pub skipped: bool,
}

/// What a person's track made of one frame.
///
/// ```
/// use torso_core::coco::N_JOINTS;
/// use torso_core::{Estimate, Person, PersonConfig};
/// let mut person = Person::new(PersonConfig::default()).unwrap();
/// let nothing = [[f64::NAN; 3]; N_JOINTS];
/// let seen = person.update(0.0, &nothing, &[0.0; N_JOINTS], [0.0; 3]).unwrap();
/// assert_eq!((seen.pose, seen.estimate), (None, Estimate::None));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Observation {
    /// `[x, y, z, azimuth, elevation]` in the world frame, azimuth wrapped to (-π, π]; `None`
    /// when there was nothing to estimate it from.
    pub pose: Option<Pose>,
    pub estimate: Estimate,
    /// The detector's left and right labels were exchanged in this frame: the track's cues say
    /// the chest faces the other way from what the labels make it.
    pub swapped: bool,
    /// The track turned round in this frame: the cues said it had been facing the wrong way,
    /// and its history was turned round with it.
    pub reoriented: bool,
    /// The track's recent weighed evidence for its heading after this frame, in seconds of the
    /// labels' agreement (0 where the frame had no heading, or where the recent evidence is
    /// against a heading the longer evidence holds; [`crate::sides::Decision`]).
    pub facing_evidence: f64,
    /// The heading's side is confirmed by a cue other than the detector's labels (more evidence
    /// than the labels alone can build) and it lies near the track's recent heading
    /// ([`crate::sides::Decision::confident`]), and the torso leans no further than 60 degrees
    /// from upright ([`super::MIN_CONFIDENT_UPRIGHTNESS`]: a bent torso's azimuth is poorly
    /// conditioned).
    pub heading_confident: bool,
    /// The frame's torso plane lay more than 45 degrees across the track's recent heading
    /// ([`crate::sides::Facing::across_recent`]): `pose` reports the recent heading instead of
    /// the plane's (its centre and elevation are the plane's), and the forecasts start from it.
    pub heading_held: bool,
    /// The joints after the swap, the depth completion and the gate (NaN where lost).
    pub joints: Joints,
    /// Joints whose measured depth was replaced by the one the learned pair width gives (a far
    /// shoulder or hip hidden by the body).
    pub completed: [bool; N_JOINTS],
    pub status: [JointStatus; N_JOINTS],
    /// Confidence weight given to the forecaster: mean score of the torso joints used, a joint
    /// held over from the previous frame at half its score.
    pub weight: f64,
    pub grid: GridReport,
}
