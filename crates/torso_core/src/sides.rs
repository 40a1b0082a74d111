//! Which way a person faces: the sign of the torso normal, kept per track from several cues.
//!
//! The torso plane gives the normal's line well; which of its two directions is the chest comes
//! from the detector's left/right labels, and those are wrong in a share of frames (small or far
//! people, profile views), often for many frames in a row. So a track keeps its heading
//! continuous (each frame takes the side of the torso line nearer the heading of the last fifth
//! of a second, not of the last frame alone, so that one frame whose plane is badly off cannot
//! carry the heading a quarter turn round and the next onto the back; and a frame whose knees
//! point away from its heading moves that recent heading less, none at a right angle, so that a
//! stretch of planes drifting off cannot either) and weighs four cues to whether that heading or
//! its opposite is the chest's:
//!
//! - the labels: the labelled plane's normal on the heading's side or the opposite one (in a
//!   frame where the track moved a far torso joint back to its depth from the last pose, only a
//!   pair measured as read: the moved pair's normal points where the last pose did);
//! - the face: the nose, seen in front and profile views, stands in front of the shoulders;
//! - the knees: a knee bends forwards only, so a standing leg's bent knee stands in front of the
//!   line from its hip to its ankle; this reads where the keypoints are, not how they are
//!   labelled, so it holds where the detector has the sides exchanged;
//! - the motion: people mostly face where they walk, when they walk fast enough to tell.
//!
//! The evidence is weighed twice. The side is decided on evidence forgotten as the recent
//! heading moves, whichever way (the path it sweeps, `SIDE_TURN`), and only slowly with time
//! (`SIDE_MEMORY`): which side is the chest does not change while the person does not turn, and
//! a detector's labels can stay exchanged for longer than a second while a person stands still,
//! where evidence forgotten with time alone would let them turn the track round onto its back;
//! but a heading that turns, or wavers with poor torso planes, may have lost the side the
//! evidence was for. When that evidence turns against the heading, the track turns round: the
//! heading and everything the track remembers of the body's sides are reversed. Whether the
//! heading is confident is judged on the recent evidence, forgotten over
//! [`FacingConfig::memory`] (a second). While the torso goes unseen (no torso line, so no
//! decision: hidden, out of view or not detected), nothing says whether the person turned
//! round, and the side's evidence is forgotten as fast as the recent evidence: after a second
//! or two unseen, the next frames' cues decide the side nearly as they would a new track's.
//! The labels alone, however long they agree, build about a
//! memory's worth of it; a heading with more than that has been confirmed recently by another
//! cue, and is reported confident unless the frame's torso line lies far across the recent
//! heading (a bad plane); the track also calls no heading confident whose torso leans far from
//! upright ([`crate::person::MIN_CONFIDENT_UPRIGHTNESS`]). The decision owns the side of the
//! pose the track reports ([`Facing::opposes`]), the plane fitted after the gate only its line;
//! and where that line lies far across the recent heading, the pose reports the recent heading
//! ([`Facing::across_recent`]).

use crate::coco::{self, Joints, N_JOINTS};
use crate::history::unwrap_near;
use crate::plane::shoulder_heading;
use crate::vec3::{distance, dot, finite, sub};
use crate::MAX_FRAME_STEP;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// A nose less than this (m) in front of the shoulders' midpoint, horizontally, says nothing.
const MIN_NOSE_OFFSET: f64 = 0.03;
/// A nose more than this (m) from the shoulders' midpoint, horizontally, says nothing: a head
/// reaches no further in front of the shoulders, even bowed, and a nose that far had its depth
/// read off another surface (the background past the face's edge, someone else).
const MAX_NOSE_OFFSET: f64 = 0.5;
/// Knees less than this (m) in front of their hip-to-ankle lines, horizontally, say nothing.
const MIN_KNEE_OFFSET: f64 = 0.03;
/// A leg whose lifted thigh and shin differ in length by more than this factor says nothing: a
/// thigh and a shin are about as long as each other, and one of them twice the other means a
/// joint's depth was read off another surface (a knee hidden behind the body, seen from the
/// back, takes the depth of the person's own back, nearer the camera).
const MAX_LEG_PROPORTION: f64 = 2.0;
/// Largest angle (rad) between a frame's heading and the recent heading for the frame to be
/// confident: beyond it the frame's torso line lies nearer across the recent heading than along
/// it, far more often a bad plane than a turn that fast. Chosen on the scenes benchmark's
/// development split against a stricter bar (docs/benchmark_log.md).
const MAX_CONFIDENT_TURN: f64 = FRAC_PI_4;
/// Time constant (s) of the recent heading whose side of the torso line a frame takes, for a
/// frame whose knees agree with its heading (or show no direction); longer as they point away.
const REFERENCE_TIME: f64 = 0.2;
/// The path (rad) the recent heading sweeps, turning or wavering, over which the evidence that
/// decides the side is forgotten (to 1/e): a quarter turn takes a front view to a profile,
/// where the cues read otherwise. Dev: an eighth or a half turn flipped more, and so did the
/// net turn alone, without the wavering (docs/benchmark_log.md).
const SIDE_TURN: f64 = FRAC_PI_2;
/// Time constant (s) over which the evidence that decides the side is forgotten while the
/// recent heading holds still, so that evidence built wrong does not hold a still person's
/// heading for ever. Dev: 2 s and none flipped about as often.
const SIDE_MEMORY: f64 = 3.0;
/// Walking slower than this (m/s) says nothing of the heading; the motion cue reaches its full
/// weight `FULL_SPEED_SPAN` faster.
const MIN_SPEED: f64 = 0.5;
const FULL_SPEED_SPAN: f64 = 0.5;
/// Time constant (s) of the smoothed velocity the motion cue reads.
const VELOCITY_TIME: f64 = 0.5;
/// Evidence is counted per this much time (s), so that a camera's frame rate does not change
/// how fast it builds; a longer step than [`MAX_FRAME_STEP`] counts as that, the rest of it as
/// time unseen.
const UNIT_STEP: f64 = 0.04;

/// How much each cue counts, and for how long.
///
/// ```
/// use torso_core::sides::FacingConfig;
/// // Ignore the nose (a detector that finds faces on the backs of heads).
/// let config = FacingConfig { face_weight: 0.0, ..FacingConfig::default() };
/// assert_eq!(config.motion_weight, FacingConfig::default().motion_weight);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FacingConfig {
    /// Time constant (s) over which the recent evidence is forgotten: what says whether the
    /// heading is confident ([`Decision::confident`]). The side itself is decided on evidence
    /// kept longer, forgotten as the heading moves (module docs), and over this time constant
    /// while the torso goes unseen.
    pub memory: f64,
    /// Weight of the nose cue, relative to the labels' (1 per 0.04 s of agreement).
    pub face_weight: f64,
    /// Weight of the bent-knees cue, relative to the labels'. The knees are right in about as
    /// many of their votes as the labels, and a knee bent forwards is read where it stands,
    /// whatever the detector calls it, so a frame's knees outvote labels it has exchanged. Set
    /// on three draws of the scenes benchmark's development split (docs/benchmark_log.md, "the
    /// knees' weight, on a third draw").
    pub knee_weight: f64,
    /// Weight of the walking-direction cue, relative to the labels'.
    pub motion_weight: f64,
}

impl Default for FacingConfig {
    fn default() -> Self {
        Self {
            memory: 1.0,
            face_weight: 2.0,
            knee_weight: 2.0,
            motion_weight: 1.0,
        }
    }
}

/// What one frame's joints say of the heading; see [`Cues::of`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cues {
    /// Azimuth of the torso plane's normal (or the shoulder line's) as the detector labelled it:
    /// the frame's torso line, and the side the labels put the chest on.
    pub labelled: f64,
    /// The azimuth the labels vote for ([`label_vote`]): `labelled`, or where the track moved a
    /// far torso joint back to its depth, the normal of a pair measured as read; `None`, no vote.
    pub label_vote: Option<f64>,
    /// The torso's centre (m).
    pub centre: [f64; 3],
    /// Horizontal direction from the shoulders to the nose, where it stands out ([`nose_direction`]).
    pub nose: Option<f64>,
    /// Horizontal direction in which the knees stand out of their legs ([`knee_direction`]).
    pub knees: Option<f64>,
}

impl Cues {
    /// The cues of a frame's `joints` (NaN where not seen), given the azimuth and centre of
    /// their labelled torso plane and which joints' depths the track `completed` (moved back
    /// from the near side of the body, [`crate::person`]).
    pub fn of(
        joints: &Joints,
        labelled: f64,
        centre: [f64; 3],
        completed: &[bool; N_JOINTS],
    ) -> Self {
        Self {
            labelled,
            label_vote: label_vote(joints, labelled, completed),
            centre,
            nose: nose_direction(joints),
            knees: knee_direction(joints),
        }
    }
}

/// What one frame's cues decided.
///
/// ```
/// use torso_core::sides::{Cues, Facing, FacingConfig};
/// let mut facing = Facing::default();
/// let cues = Cues { labelled: 0.3, label_vote: Some(0.3), centre: [2.0, 0.0, 1.0], nose: None, knees: None };
/// let first = facing.decide(0.0, &cues, &FacingConfig::default());
/// // A new track takes the labels as they are.
/// assert!(!first.exchange && !first.turned && (first.heading - 0.3).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Decision {
    /// The chest faces the opposite way from the labelled plane's normal this frame: the
    /// labels are to be exchanged.
    pub exchange: bool,
    /// The track turned round: its heading before this frame was the back's, not the chest's.
    pub turned: bool,
    /// The heading (the chest's azimuth, unwrapped near the previous one).
    pub heading: f64,
    /// The recent weighed evidence for the heading after this frame, in seconds of the labels'
    /// agreement, forgotten over [`FacingConfig::memory`]; 0 where the recent evidence is
    /// against the heading and the longer evidence that decides the side still holds it.
    pub evidence: f64,
    /// The evidence is more than the labels alone can build at this frame rate (about
    /// [`FacingConfig::memory`] seconds' worth, approached and never passed): a cue other
    /// than the labels (the face, the knees, the walking direction) has agreed recently; and
    /// the heading lies within 45 degrees (`MAX_CONFIDENT_TURN`) of the recent heading.
    pub confident: bool,
}

/// One track's heading and the evidence for it.
///
/// ```
/// use torso_core::sides::{Cues, Facing, FacingConfig};
/// let (mut facing, config) = (Facing::default(), FacingConfig::default());
/// let cues = Cues { labelled: 0.0, label_vote: Some(0.0), centre: [2.0, 0.0, 1.0], nose: None, knees: None };
/// for k in 0..25 {
///     facing.decide(k as f64 * 0.04, &cues, &config);
/// }
/// // After a second of labels facing +x, one frame that says the opposite has its labels
/// // exchanged back; the track does not turn round.
/// let pi = std::f64::consts::PI;
/// let opposite = Cues { labelled: pi, label_vote: Some(pi), ..cues };
/// let once = facing.decide(1.0, &opposite, &config);
/// assert!(once.exchange && !once.turned && once.heading == 0.0);
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Facing {
    heading: Option<f64>,
    /// The evidence that decides the side, forgotten as the recent heading moves.
    side_evidence: f64,
    /// The recent evidence, forgotten over [`FacingConfig::memory`] (may be negative).
    evidence: f64,
    last: Option<(f64, [f64; 2])>,
    velocity: [f64; 2],
    /// The recent heading as a smoothed unit vector (zero before the first frame).
    reference: [f64; 2],
}

impl Facing {
    /// Whether a torso plane with normal azimuth `azimuth` has the chest on the other side of
    /// the track's heading (its last decision's): the plane's line lies within 45 degrees
    /// (`MAX_CONFIDENT_TURN`) of the heading's (the same line, not one across it) and its
    /// normal points away from the heading. The plane a track reports is fitted after the gate,
    /// and the gate's replaced joints (earlier positions) can put its sides the other way
    /// round, in a frame the track decided on as in one whose joints allowed no decision; the
    /// side is the decision's, which weighed every cue. `false` before any decision.
    ///
    /// ```
    /// use torso_core::sides::{Cues, Facing, FacingConfig};
    /// let mut facing = Facing::default();
    /// assert!(!facing.opposes(3.0));
    /// let cues = Cues { labelled: 0.0, label_vote: Some(0.0), centre: [2.0, 0.0, 1.0], nose: None, knees: None };
    /// facing.decide(0.0, &cues, &FacingConfig::default());
    /// assert!(facing.opposes(3.0) && !facing.opposes(0.3));
    /// // A line across the heading says nothing of the side.
    /// assert!(!facing.opposes(2.0));
    /// ```
    pub fn opposes(&self, azimuth: f64) -> bool {
        self.heading
            .is_some_and(|h| (azimuth - h).cos() < -MAX_CONFIDENT_TURN.cos())
    }

    /// The track's recent heading (its decisions over the last fifth of a second), unwrapped
    /// near `azimuth`, where a torso plane with normal azimuth `azimuth` lies more than 45
    /// degrees (`MAX_CONFIDENT_TURN`) across it: far more often a bad plane than a turn that
    /// fast (the confidence rule's reason), and the recent heading says better where the chest
    /// faces. `None` where the plane lies nearer, for an azimuth that is not a number, and
    /// before any decision.
    ///
    /// ```
    /// use torso_core::sides::{Cues, Facing, FacingConfig};
    /// let mut facing = Facing::default();
    /// assert_eq!(facing.across_recent(2.0), None);
    /// let cues = Cues { labelled: 0.0, label_vote: Some(0.0), centre: [2.0, 0.0, 1.0], nose: None, knees: None };
    /// facing.decide(0.0, &cues, &FacingConfig::default());
    /// assert_eq!(facing.across_recent(0.5), None);
    /// assert_eq!(facing.across_recent(2.0), Some(0.0));
    /// // Unwrapped near the plane's azimuth.
    /// assert_eq!(facing.across_recent(2.0 + 4.0 * std::f64::consts::PI), Some(4.0 * std::f64::consts::PI));
    /// assert_eq!(facing.across_recent(f64::NAN), None);
    /// ```
    pub fn across_recent(&self, azimuth: f64) -> Option<f64> {
        let [c, s] = self.reference;
        if !azimuth.is_finite() || c.hypot(s) == 0.0 || near(azimuth, self.reference) {
            return None;
        }
        Some(unwrap_near(s.atan2(c), azimuth))
    }

    /// The decision for a frame at `t` with these cues.
    pub fn decide(&mut self, t: f64, cues: &Cues, config: &FacingConfig) -> Decision {
        let Cues {
            labelled,
            label_vote,
            centre,
            nose,
            knees,
        } = *cues;
        let first = self.heading.is_none();
        let recent = self.reference; // before this frame moves it
        let reference = recent[1].atan2(recent[0]);
        let elapsed = self.last.map_or(0.0, |(last_t, _)| (t - last_t).max(0.0));
        let (dt, candidate) = match (self.heading, self.last) {
            (Some(h), Some(_)) => {
                let side = if (labelled - reference).cos() >= 0.0 {
                    labelled
                } else {
                    labelled + PI
                };
                let near = unwrap_near(side, h);
                (elapsed.min(MAX_FRAME_STEP), near)
            }
            _ => (UNIT_STEP, labelled),
        };
        if let Some((last_t, last_centre)) = self.last {
            let step = t - last_t;
            if step > 0.0 {
                let gain = 1.0 - (-step / VELOCITY_TIME).exp();
                for k in 0..2 {
                    let v = (centre[k] - last_centre[k]) / step;
                    self.velocity[k] += gain * (v - self.velocity[k]);
                }
            }
        }
        self.last = Some((t, [centre[0], centre[1]]));
        let unit = dt / UNIT_STEP;
        let agrees = |direction: f64| (direction - candidate).cos().signum();
        let mut vote = label_vote.map_or(0.0, agrees);
        if let Some(n) = nose {
            vote += config.face_weight * agrees(n);
        }
        if let Some(k) = knees {
            vote += config.knee_weight * agrees(k);
        }
        let speed = self.velocity[0].hypot(self.velocity[1]);
        if speed > MIN_SPEED {
            let strength = ((speed - MIN_SPEED) / FULL_SPEED_SPAN).min(1.0);
            vote +=
                config.motion_weight * strength * agrees(self.velocity[1].atan2(self.velocity[0]));
        }
        // A step longer than `MAX_FRAME_STEP` counts as that, and the rest of it the torso went
        // unseen (no decision): a person may turn round unseen, so both kinds of evidence are
        // forgotten over that time as fast as the recent evidence is.
        let unseen = (elapsed - dt).max(0.0);
        let keep = (-(dt + unseen) / config.memory).exp();
        self.evidence = self.evidence * keep + unit * vote;
        // The share `g` of the way to the candidate the recent heading moves this frame by time
        // alone, and the angle that takes it through, either way: the side's evidence is
        // forgotten over that path even where the knees hold the recent heading back (below).
        let (g, sweep) = if first {
            (1.0, 0.0)
        } else {
            let g = 1.0 - (-dt / REFERENCE_TIME).exp();
            (g, g * (candidate - reference).cos().acos())
        };
        let forget = dt / SIDE_MEMORY + unseen / config.memory + sweep / SIDE_TURN;
        self.side_evidence = self.side_evidence * (-forget).exp() + unit * vote;
        let mut heading = candidate;
        let mut turned = false;
        if self.side_evidence < 0.0 {
            heading += PI;
            self.side_evidence = -self.side_evidence;
            self.evidence = -self.evidence;
            turned = self.heading.is_some();
        }
        self.heading = Some(heading);
        if turned {
            self.reference = self.reference.map(|v| -v);
        }
        // A frame moves the recent heading only as far as the knees agree with its heading: a
        // torso line drifting off over a stretch of poor planes would drag the recent heading
        // round until the frames took the other side of their lines, and the knees' direction,
        // read from where the knees stand, does not drift with the torso plane.
        let g = match knees {
            Some(k) if !first => g * (heading - k).cos().max(0.0),
            _ => g,
        };
        self.reference[0] += g * (heading.cos() - self.reference[0]);
        self.reference[1] += g * (heading.sin() - self.reference[1]);
        let exchange = (heading - labelled).cos() < 0.0;
        // The labels alone, agreeing frame after frame at this step, build `unit / (1 - keep)`.
        let labels_alone = if keep < 1.0 {
            unit / (1.0 - keep)
        } else {
            f64::INFINITY
        };
        Decision {
            exchange,
            turned,
            heading,
            evidence: self.evidence.max(0.0) * UNIT_STEP,
            confident: self.evidence > labels_alone && (first || near(heading, recent)),
        }
    }
}

/// Whether `heading` lies within [`MAX_CONFIDENT_TURN`] of the direction of the recent-heading
/// vector `recent`.
fn near(heading: f64, recent: [f64; 2]) -> bool {
    let along = heading.cos() * recent[0] + heading.sin() * recent[1];
    along >= MAX_CONFIDENT_TURN.cos() * recent[0].hypot(recent[1])
}

/// The azimuth the detector's labels vote for: the labelled plane's normal `labelled`, unless
/// the track moved a far torso joint back along its camera ray (`completed`). It moves the joint
/// on the side the last pose turned away from the camera, and a pair so completed has its normal
/// where the last pose had it, whatever the labels say: its vote would be the track agreeing
/// with itself (in profile views, frame after frame, holding a wrong heading as firmly as a
/// right one). There the shoulders, else the hips, measured as read and both seen vote with
/// their own normal; without such a pair the labels do not vote.
pub fn label_vote(joints: &Joints, labelled: f64, completed: &[bool; N_JOINTS]) -> Option<f64> {
    if !coco::TORSO.iter().any(|&i| completed[i]) {
        return Some(labelled);
    }
    coco::TORSO_PAIRS
        .into_iter()
        .filter(|&(l, r)| !completed[l] && !completed[r])
        // A pair's normal is the shoulder line's, whichever pair it is.
        .find_map(|(l, r)| shoulder_heading(joints[l], joints[r]).ok())
        .map(|pair| pair.azimuth)
}

/// Horizontal direction (azimuth) from the shoulders' midpoint to the nose, where the nose and
/// both shoulders are seen (finite) and the nose stands out at least `MIN_NOSE_OFFSET` and at
/// most `MAX_NOSE_OFFSET`.
pub fn nose_direction(joints: &Joints) -> Option<f64> {
    let [n, l, r] = [coco::NOSE, coco::LEFT_SHOULDER, coco::RIGHT_SHOULDER];
    if ![n, l, r].iter().all(|&i| finite(&joints[i])) {
        return None;
    }
    let offset = [0, 1].map(|k| joints[n][k] - 0.5 * (joints[l][k] + joints[r][k]));
    direction(offset, MIN_NOSE_OFFSET).filter(|_| offset[0].hypot(offset[1]) <= MAX_NOSE_OFFSET)
}

/// Horizontal direction in which the knees stand out of the lines from their hips to their
/// ankles, where every leg whose three joints are seen and in proportion (`MAX_LEG_PROPORTION`)
/// has its knee at least `MIN_KNEE_OFFSET` out that way (a detector that pairs one leg's knee
/// with the other's ankle, or reads a knee's depth off the other leg, bends that leg backwards,
/// so one leg against the other says nothing). Which leg is labelled left does not matter, only
/// that a leg's joints are one leg's.
///
/// A knee stands out of its leg's line at right angles to it (`knee_bend`), forwards and
/// horizontally only where the leg stands: a leg whose line lies nearer the horizontal than the
/// vertical (seated on the floor, the legs out in front) bends its knee upwards, and what is
/// left horizontal is the knee fallen to one side, which says nothing of the heading.
pub fn knee_direction(joints: &Joints) -> Option<f64> {
    let legs = [
        [coco::LEFT_HIP, coco::LEFT_KNEE, coco::LEFT_ANKLE],
        [coco::RIGHT_HIP, coco::RIGHT_KNEE, coco::RIGHT_ANKLE],
    ];
    let offsets = legs.map(|[hip, knee, ankle]| {
        let seen = [hip, knee, ankle].iter().all(|&i| finite(&joints[i]));
        let (thigh, shin) = (
            distance(joints[hip], joints[knee]),
            distance(joints[knee], joints[ankle]),
        );
        (seen && thigh <= MAX_LEG_PROPORTION * shin && shin <= MAX_LEG_PROPORTION * thigh)
            .then(|| knee_bend(joints[hip], joints[knee], joints[ankle]))
            .flatten()
    });
    let sum = offsets
        .iter()
        .flatten()
        .fold([0.0; 2], |s, o| [s[0] + o[0], s[1] + o[1]]);
    let azimuth = direction(sum, MIN_KNEE_OFFSET)?;
    let (c, s) = (azimuth.cos(), azimuth.sin());
    let every_leg = offsets
        .iter()
        .flatten()
        .all(|o| o[0] * c + o[1] * s >= MIN_KNEE_OFFSET);
    every_leg.then_some(azimuth)
}

/// The horizontal part of the knee's offset from the line through its hip and ankle, taken at
/// right angles to the line; `None` where the line lies nearer the horizontal than the vertical,
/// or the hip and the ankle coincide. Taken from the line's midpoint instead, a sloping leg's
/// offset holds the knee's place along the line as well as its bend: a knee nearer its hip than
/// its ankle stands out towards the hip, backwards for a person seated with the legs out in front.
fn knee_bend(hip: [f64; 3], knee: [f64; 3], ankle: [f64; 3]) -> Option<[f64; 2]> {
    let (line, to_knee) = (sub(ankle, hip), sub(knee, hip));
    let squared = dot(line, line);
    (squared > 0.0 && line[2].abs() >= line[0].hypot(line[1])).then(|| {
        let along = dot(to_knee, line) / squared;
        [0, 1].map(|k| to_knee[k] - along * line[k])
    })
}

/// The azimuth of a horizontal offset at least `min` long.
fn direction(offset: [f64; 2], min: f64) -> Option<f64> {
    (offset[0].hypot(offset[1]) >= min).then(|| offset[1].atan2(offset[0]))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn error(a: f64, b: f64) -> f64 {
        crate::person::wrap_angle(a - b).abs()
    }

    fn cues(labelled: f64, centre: [f64; 3], nose: Option<f64>) -> Cues {
        Cues {
            labelled,
            label_vote: Some(labelled),
            centre,
            nose,
            knees: None,
        }
    }

    #[test]
    fn a_pair_the_track_completed_casts_no_label_vote() {
        let mut joints = [[f64::NAN; 3]; N_JOINTS];
        // Shoulders facing +x; hips turned to face -45 degrees.
        joints[coco::LEFT_SHOULDER] = [2.0, 0.2, 1.4];
        joints[coco::RIGHT_SHOULDER] = [2.0, -0.2, 1.4];
        joints[coco::LEFT_HIP] = [2.1, 0.1, 0.9];
        joints[coco::RIGHT_HIP] = [1.9, -0.1, 0.9];
        let completed = |list: &[usize]| {
            let mut c = [false; N_JOINTS];
            list.iter().for_each(|&i| c[i] = true);
            c
        };
        let vote = |list: &[usize]| label_vote(&joints, 0.3, &completed(list));
        assert_eq!(vote(&[]), Some(0.3));
        assert!(error(vote(&[coco::LEFT_HIP]).unwrap(), 0.0) < 1e-12);
        assert!(error(vote(&[coco::RIGHT_SHOULDER]).unwrap(), -FRAC_PI_4) < 1e-12);
        assert_eq!(vote(&[coco::RIGHT_SHOULDER, coco::LEFT_HIP]), None);
        // A joint outside the torso moved back says nothing of the labels.
        assert_eq!(vote(&[coco::NOSE]), Some(0.3));
    }

    #[test]
    fn labels_alone_decide_and_a_short_disagreement_does_not_turn_the_track() {
        let config = FacingConfig::default();
        let mut facing = Facing::default();
        for k in 0..50 {
            let t = k as f64 / 25.0;
            // Labels exchanged in frames 20 to 24 (0.2 s): the heading holds.
            let labelled = if (20..25).contains(&k) { 0.3 + PI } else { 0.3 };
            let d = facing.decide(t, &cues(labelled, [2.0, 0.0, 1.0], None), &config);
            assert!(error(d.heading, 0.3) < 1e-12, "frame {k}");
            assert_eq!(d.exchange, (20..25).contains(&k));
            assert!(!d.turned);
        }
    }

    #[test]
    fn evidence_is_forgotten_while_the_torso_goes_unseen() {
        // Two seconds facing 0.3 by the labels and the nose, then unseen, then the labels alone
        // for the other side (the person turned round while hidden), frame after frame: the
        // longer the gap, the sooner the track turns round, and after a few seconds unseen the
        // side is the next frames' (as a new track's would be) within a few frames.
        let config = FacingConfig::default();
        let frames_to_turn = |gap: f64| {
            let mut facing = Facing::default();
            for k in 0..50 {
                let seen = cues(0.3, [2.0, 0.0, 1.0], Some(0.3));
                facing.decide(k as f64 / 25.0, &seen, &config);
            }
            let back = cues(0.3 + PI, [2.0, 0.0, 1.0], None);
            (0..250)
                .position(|k| {
                    facing
                        .decide(1.96 + gap + k as f64 / 25.0, &back, &config)
                        .turned
                })
                .expect("the labels turn the track round in the end")
        };
        let turns: Vec<usize> = [0.04, 0.5, 1.0, 3.0].map(frames_to_turn).to_vec();
        assert!(turns.windows(2).all(|w| w[1] < w[0]), "{turns:?}");
        assert!(turns[0] > 25 && turns[3] <= 2, "{turns:?}");
    }

    #[test]
    fn a_steady_cue_against_the_heading_turns_the_track_round() {
        let config = FacingConfig::default();
        let mut facing = Facing::default();
        // Born from exchanged labels (heading 0.3 + π), then a nose and labels that say 0.3.
        let first = facing.decide(0.0, &cues(0.3 + PI, [2.0, 0.0, 1.0], None), &config);
        assert!(error(first.heading, 0.3 + PI) < 1e-12);
        let mut turned_at = None;
        for k in 1..50 {
            let now = cues(0.3, [2.0, 0.0, 1.0], Some(0.4));
            let d = facing.decide(k as f64 / 25.0, &now, &config);
            if d.turned {
                turned_at = Some(k);
            }
            if turned_at.is_some() {
                assert!(error(d.heading, 0.3) < 1e-12 && !d.exchange, "frame {k}");
            }
        }
        assert_eq!(turned_at, Some(1)); // three votes against one: at once
    }

    #[test]
    fn walking_decides_where_the_labels_are_mostly_wrong() {
        // Walking along +x at 1.5 m/s, no face seen, and labels that say it faces -x in three
        // frames of five: the walking direction wins; standing still, the labels would.
        for (speed, want) in [(1.5, 0.0), (0.0, PI)] {
            let mut facing = Facing::default();
            let mut last = Decision::default();
            for k in 0..75 {
                let t = k as f64 / 25.0;
                let labelled = if k % 5 < 3 { PI } else { 0.0 };
                let config = FacingConfig::default();
                last = facing.decide(t, &cues(labelled, [speed * t, 0.0, 1.0], None), &config);
            }
            assert!(error(last.heading, want) < 1e-12, "speed {speed}");
        }
    }

    #[test]
    fn two_frames_of_a_bad_plane_do_not_carry_the_heading_onto_the_back() {
        // Facing 0 for a second, then two frames whose torso line (and labels) come out 60 and
        // 120 degrees off: continuing from the last frame alone would take 60, then 120 (the
        // back); the recent heading keeps the side of the line at -60, and then 0 again.
        let config = FacingConfig::default();
        let mut facing = Facing::default();
        let bad = [60f64.to_radians(), 120f64.to_radians()];
        for k in 0..30 {
            let labelled = if (25..27).contains(&k) {
                bad[k - 25]
            } else {
                0.0
            };
            let now = cues(labelled, [2.0, 0.0, 1.0], None);
            let d = facing.decide(k as f64 / 25.0, &now, &config);
            assert!(
                error(d.heading, 0.0) <= 60f64.to_radians() + 1e-9,
                "frame {k}"
            );
            assert!(!d.turned);
        }
    }

    #[test]
    fn a_torso_line_drifting_off_does_not_drag_the_heading_past_the_knees() {
        // Facing 0, knees pointing 0 throughout. After a second, the torso line (and the labels
        // with it) drifts 15 degrees a frame round to 180 and stays there: the same line as the
        // truth, its labels exchanged. Following every frame, the recent heading would drift
        // round with it and the frames would stay on the back for half a second before the knees
        // turned the track round; frames whose heading the knees point away from do not move it,
        // and the next frames come back to the chest's side of their lines.
        let config = FacingConfig::default();
        let mut facing = Facing::default();
        for k in 0..60 {
            let drift = (15.0 * (k as f64 - 24.0)).clamp(0.0, 180.0).to_radians();
            let now = Cues {
                knees: Some(0.0),
                ..cues(drift, [2.0, 0.0, 1.0], None)
            };
            let d = facing.decide(k as f64 / 25.0, &now, &config);
            // Past a right angle only with the first frame the knees point away from.
            assert!(
                error(d.heading, 0.0) <= 105f64.to_radians() + 1e-9,
                "frame {k}: {d:?}"
            );
            assert!(!d.turned, "frame {k}");
        }
    }

    #[test]
    fn bent_knees_overrule_exchanged_labels() {
        // Facing +x, labels exchanged in two frames of every three: with the knees seen bent
        // (in front of their legs) the track keeps +x; without them the labels win.
        for (knees, want) in [(Some(0.1), 0.0), (None, PI)] {
            let mut facing = Facing::default();
            let mut last = Decision::default();
            for k in 0..50 {
                let labelled = if k % 3 == 0 { 0.0 } else { PI };
                let frame = Cues {
                    knees,
                    ..cues(labelled, [2.0, 0.0, 1.0], None)
                };
                last = facing.decide(k as f64 / 25.0, &frame, &FacingConfig::default());
            }
            assert!(error(last.heading, want) < 1e-12, "knees {knees:?}");
        }
    }

    #[test]
    fn the_side_s_evidence_is_forgotten_as_the_person_turns_not_while_they_stand() {
        // Two seconds of labels and bent knees on 0.3, then labels exchanged with nothing else
        // seen for two and a half seconds. Standing still, the track keeps its heading (evidence
        // forgotten over a second alone would have turned it round after about one and a half);
        // turning half a turn over those seconds, the evidence goes with the turn and the labels
        // turn the track round.
        let config = FacingConfig::default();
        for rate in [0.0, PI / 2.5] {
            let mut facing = Facing::default();
            for k in 0..50 {
                let confirmed = Cues {
                    knees: Some(0.3),
                    ..cues(0.3, [2.0, 0.0, 1.0], None)
                };
                facing.decide(k as f64 / 25.0, &confirmed, &config);
            }
            let mut turned = 0;
            let mut last = Decision::default();
            for k in 1..=62 {
                let t = k as f64 / 25.0;
                let yaw = 0.3 + rate * t;
                last = facing.decide(2.0 + t, &cues(yaw + PI, [2.0, 0.0, 1.0], None), &config);
                turned += usize::from(last.turned);
                if rate == 0.0 {
                    assert!(error(last.heading, 0.3) < 1e-12, "frame {k}");
                }
            }
            if rate == 0.0 {
                // The recent evidence is against the heading by now: reported as none.
                assert_eq!((turned, last.evidence, last.confident), (0, 0.0, false));
            } else {
                assert_eq!(turned, 1);
                assert!(
                    error(last.heading, 0.3 + rate * 2.48 + PI) < 0.1,
                    "{last:?}"
                );
            }
        }
    }

    #[test]
    fn only_a_cue_beside_the_labels_makes_the_heading_confident() {
        // Ten seconds of unanimous labels at 25 and at 30 frames per second: the evidence
        // approaches the memory's worth and the heading never becomes confident.
        let config = FacingConfig::default();
        for fps in [25.0, 30.0] {
            let mut facing = Facing::default();
            let mut last = Decision::default();
            for k in 0..(10.0 * fps) as usize {
                let now = cues(0.3, [2.0, 0.0, 1.0], None);
                last = facing.decide(k as f64 / fps, &now, &config);
                assert!(!last.confident, "fps {fps} frame {k}");
            }
            assert!(
                (last.evidence - config.memory).abs() < 0.05 * config.memory,
                "{last:?}"
            );
        }
        // A nose that agrees as well: three votes a frame build 3 (1 - keep^k) / (1 - keep)
        // after k frames (keep = exp(-0.04 s / memory)), more than the labels' 1 / (1 - keep)
        // once keep^k < 2/3: from the eleventh frame (0.4 s).
        let mut facing = Facing::default();
        let mut confident_at = None;
        for k in 0..50 {
            let d = facing.decide(
                k as f64 / 25.0,
                &cues(0.3, [2.0, 0.0, 1.0], Some(0.3)),
                &config,
            );
            if d.confident && confident_at.is_none() {
                confident_at = Some(k);
            }
        }
        let k = (1.5f64.ln() / (0.04 / config.memory)).ceil() as usize;
        assert_eq!(confident_at, Some(k - 1));
        // A track that has just turned round holds only the margin it turned by.
        let mut facing = Facing::default();
        let born = facing.decide(0.0, &cues(0.3 + PI, [2.0, 0.0, 1.0], None), &config);
        let turned = facing.decide(0.04, &cues(0.3, [2.0, 0.0, 1.0], Some(0.3)), &config);
        assert!(!born.confident && turned.turned && !turned.confident);
        // Two seconds of labels and nose on 0.3, then one frame whose torso line comes out 60
        // degrees round (its nose with it): that frame is not confident, the next is again.
        let mut facing = Facing::default();
        for k in 0..50 {
            facing.decide(
                k as f64 / 25.0,
                &cues(0.3, [2.0, 0.0, 1.0], Some(0.3)),
                &config,
            );
        }
        let off = 0.3 + 60f64.to_radians();
        let bad = facing.decide(2.0, &cues(off, [2.0, 0.0, 1.0], Some(off)), &config);
        let next = facing.decide(2.04, &cues(0.3, [2.0, 0.0, 1.0], Some(0.3)), &config);
        assert!(error(bad.heading, off) < 1e-12 && !bad.confident && next.confident);
    }

    #[test]
    fn the_knee_direction_reads_places_not_labels_and_needs_a_bend() {
        // Facing +x: hips at 0.9 m, knees bent 8 cm forwards, ankles under the hips.
        let mut joints = [[f64::NAN; 3]; N_JOINTS];
        joints[coco::LEFT_HIP] = [2.0, -0.1, 0.9];
        joints[coco::RIGHT_HIP] = [2.0, 0.1, 0.9];
        joints[coco::LEFT_KNEE] = [2.08, -0.1, 0.5];
        joints[coco::RIGHT_KNEE] = [2.08, 0.1, 0.5];
        joints[coco::LEFT_ANKLE] = [2.0, -0.1, 0.1];
        joints[coco::RIGHT_ANKLE] = [2.0, 0.1, 0.1];
        assert!(error(knee_direction(&joints).unwrap(), 0.0) < 1e-12);
        // Labels exchanged (as a detector does for a back view): the same direction.
        let mut exchanged = joints;
        coco::swap_sides(&mut exchanged);
        assert!(error(knee_direction(&exchanged).unwrap(), 0.0) < 1e-12);
        // One leg bent backwards by more than the other's bend forwards (a knee read off the
        // other leg): the legs disagree, and say nothing.
        let mut disagree = joints;
        disagree[coco::RIGHT_KNEE] = [1.77, 0.1, 0.5];
        assert_eq!(knee_direction(&disagree), None);
        // Seen from behind, a sitting person's knee hidden by the body takes the depth of the
        // back: 10 cm nearer the camera (at -x) than the hip, its thigh 0.15 m against a 0.4 m
        // shin. That leg says nothing; the other, in proportion, still counts.
        let mut hidden = joints;
        hidden[coco::RIGHT_KNEE] = [1.9, 0.1, 0.8];
        assert!(error(knee_direction(&hidden).unwrap(), 0.0) < 1e-12);
        hidden[coco::LEFT_KNEE] = [1.9, -0.1, 0.8];
        assert_eq!(knee_direction(&hidden), None);
        // Seated on a chair facing +x, the thighs level and the shins down: the legs' lines
        // slope down a little steeper than 45 degrees, and the knees stand out of them forwards.
        let mut seated = joints;
        let legs = [
            (coco::LEFT_HIP, coco::LEFT_KNEE, coco::LEFT_ANKLE, -0.1),
            (coco::RIGHT_HIP, coco::RIGHT_KNEE, coco::RIGHT_ANKLE, 0.1),
        ];
        for (hip, knee, ankle, y) in legs {
            seated[hip] = [2.15, y, 0.5];
            seated[knee] = [2.45, y, 0.5];
            seated[ankle] = [2.55, y, 0.05];
        }
        assert!(error(knee_direction(&seated).unwrap(), 0.0) < 1e-12);
        // Seated on the floor, the legs out in front, the knees raised and fallen to one side:
        // the legs' lines lie nearer the horizontal, and their knees say nothing. (Measured from
        // the lines' midpoints, knees nearer the hips than the ankles stood out backwards.)
        for (hip, knee, ankle, y) in legs {
            seated[hip] = [2.0, y, 0.3];
            seated[knee] = [2.3, y + 0.1, 0.45];
            seated[ankle] = [2.75, y, 0.08];
        }
        assert_eq!(knee_direction(&seated), None);
        // One leg seen is enough; straight legs say nothing.
        joints[coco::RIGHT_ANKLE] = [f64::NAN; 3];
        assert!(error(knee_direction(&joints).unwrap(), 0.0) < 1e-12);
        joints[coco::LEFT_KNEE] = [2.01, -0.1, 0.5];
        assert_eq!(knee_direction(&joints), None);
        joints[coco::LEFT_ANKLE] = [f64::NAN; 3];
        assert_eq!(knee_direction(&joints), None);
    }

    #[test]
    fn the_nose_direction_is_horizontal_and_needs_an_offset() {
        let mut joints = [[f64::NAN; 3]; N_JOINTS];
        joints[coco::LEFT_SHOULDER] = [2.0, -0.18, 1.4];
        joints[coco::RIGHT_SHOULDER] = [2.0, 0.18, 1.4];
        joints[coco::NOSE] = [1.9, 0.0, 1.65];
        assert!(error(nose_direction(&joints).unwrap(), PI) < 1e-12);
        joints[coco::NOSE] = [1.99, 0.0, 1.65];
        assert_eq!(nose_direction(&joints), None);
        // Its depth read off the wall behind: no nose stands 2 m behind its shoulders.
        joints[coco::NOSE] = [4.0, 0.0, 1.65];
        assert_eq!(nose_direction(&joints), None);
        joints[coco::NOSE] = [f64::NAN; 3]; // not seen
        assert_eq!(nose_direction(&joints), None);
    }
}
