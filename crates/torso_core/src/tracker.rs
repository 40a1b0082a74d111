//! Every person in a stream: detections to tracks by their 3D torso centres, track birth,
//! confirmation and drop, and one [`Person`] chain per track; with
//! [`Tracker::step`], the depth lookup and deprojection of the 2D keypoints too, so that one call
//! per frame takes a detector's output and a depth image to poses.
//!
//! Each frame, the joints a detection shows on someone nearer the camera are dropped first
//! ([`crate::stray::drop_read_off_nearer`]). The cost of giving detection `j` to track `i` is
//! the distance between where track `i`'s person is expected (the last torso centre, moved on
//! at the track's walking velocity for the time unseen where its history is a steady walk) and
//! the detection's torso centre; the optimal assignment ([`Assignment`]) is taken, and pairs
//! further apart than `gate` are refused, or than [`GATE_SPREADS`] times the track's recent
//! association distance where that is wider (a measured centre that scatters; at most
//! [`MAX_SPREAD_GATE`] times `gate`), the gate widened at [`BLIND_PACE`] for the time the
//! camera sent no frame since the track was last matched. An unmatched detection opens a
//! tentative track, which is confirmed (and given the next id) after `min_hits` matched frames,
//! unless it lies within [`MIN_SEPARATION`] of a detection a track took: the same body seen
//! twice. A confirmed track unmatched for `max_missing` seconds is dropped, a tentative one at
//! its first miss, and any track unmatched in a frame where its person is expected within
//! [`MIN_SEPARATION`] of a track's matched in it: the same body tracked twice (the two would
//! take its detection in turns, and its reported id change every frame).
//!
//! At most `capacity` tracks live at once and a frame holds at most `max_detections`
//! detections; every buffer grows to those bounds at most, and a dropped track's [`Person`] is
//! reset and reused, so a stream allocates nothing once it has seen its busiest frame.
//!
//! ```
//! use torso_core::tracker::{Tracker, TrackerConfig};
//! use torso_core::coco::{Joints, N_JOINTS};
//! let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
//! // One person 2 m ahead, facing the camera at the origin, walking along y.
//! let body = |t: f64| -> Joints {
//!     let mut j = [[f64::NAN; 3]; N_JOINTS];
//!     let y = 0.5 * t;
//!     j[5] = [2.0, y - 0.2, 1.4]; // left shoulder (on the camera's right: facing it)
//!     j[6] = [2.0, y + 0.2, 1.4];
//!     j[11] = [2.0, y - 0.12, 0.9];
//!     j[12] = [2.0, y + 0.12, 0.9];
//!     j
//! };
//! let scores = [0.9; N_JOINTS];
//! for k in 0..10 {
//!     let t = k as f64 / 25.0;
//!     let outcomes = tracker.update(t, &[body(t)], &[scores], [0.0, 0.0, 1.0]).unwrap();
//!     let track = outcomes[0].track.unwrap();
//!     // Confirmed (with id 1) from its third frame.
//!     assert_eq!(track.id, (k >= 2).then_some(1));
//! }
//! ```

use crate::assignment::Assignment;
use crate::camera::Camera;
use crate::coco::{Joints, N_JOINTS, TORSO};
use crate::depth::{DepthImage, DepthLookup};
use crate::error::{Error, Result};
use crate::person::{Observation, Person, PersonConfig};
use crate::selfcheck::HORIZONS;
use crate::stray::drop_read_off_nearer;
use crate::vec3::{distance, finite};
use crate::{Pose, MAX_FRAME_STEP};

/// One detection's 2D keypoints: `(u, v, score)` per COCO-17 joint, pixels of the image the
/// depth is registered to.
pub type Keypoints = [[f64; 3]; N_JOINTS];

/// Largest `capacity` and `max_detections` a tracker accepts.
pub const MAX_CAPACITY: usize = 4096;

/// Two people's torso centres never lie closer than this (m): a torso is about as deep, front to
/// back, and two bodies do not overlap. A detection this close to one that a track took is the
/// same body seen twice (a keypoint model's non-maximum suppression, on boxes, leaves two
/// detections of one person; the keypoints of a person behind another can all read the front
/// one's depth and lift onto it), and opens no track of its own; a track left unmatched whose
/// person is expected this close to one matched in the same frame is the same body tracked
/// twice, and is dropped.
pub const MIN_SEPARATION: f64 = 0.25;

/// How fast (m/s) a track's association gate widens for the time the camera sent no frame
/// since the track was last matched (of each step between frames, the part beyond
/// [`MAX_FRAME_STEP`]): a stalled sensor or dropped frames, when everyone may have moved with
/// nothing to show it. A slow walk: people stand, turn and walk off at up to walking pace, and a
/// wider gate lets a track take someone else's detection. Time a person goes unseen in frames
/// that do come (hidden, out of the detector's sight) does not widen it: there a widened gate
/// took ids from others and found few people again (docs/benchmark_log.md). Chosen on the scenes
/// benchmark's development draws replayed with a sensor stall (`--stall`) among 0.75, 1, 1.5 and
/// 2 m/s, where the two slowest lost about as few people and passed fewest ids on.
pub const BLIND_PACE: f64 = 1.0;

/// A track's gate reaches this many times its recent association distance (root mean square,
/// from one frame to the next, between where its person was expected and the detection it
/// took) where that is wider than `gate`: a person whose measured centre scatters from frame to
/// frame (told the camera's pose with a heading that wavers, which moves everyone by their
/// distance times the error) is looked for within three of the track's own recent distances,
/// and a still, well-measured one within `gate`. Three spreads hold nearly every step of a normal scatter. Dev (a wavering
/// heading, `eval scenes --pose-noise 2`): two left most of the identity switches the scatter
/// made, four passed more ids on to someone else (docs/benchmark_log.md).
pub const GATE_SPREADS: f64 = 3.0;

/// The most, in multiples of `gate`, that a track's association distances widen its gate
/// ([`GATE_SPREADS`]). The distances a gate lets in make the spread that sets it, so a track
/// that takes someone else's detection now and then (two people in a line of sight, their
/// joints lifted onto each other) would otherwise widen its gate with each one, and take more.
/// A heading that wavers by two degrees scatters a person 8 m away about as far. Dev: within a
/// few identity switches of no bound.
pub const MAX_SPREAD_GATE: f64 = 2.0;

/// Time constant (s) over which a track forgets its association distances ([`GATE_SPREADS`]):
/// a second, as a heading's recent evidence is forgotten (`FacingConfig::memory`), so that the
/// gate follows a scatter that comes and goes.
const GATE_MEMORY: f64 = 1.0;

/// The cost of a pair beyond its gate: more than any set of allowed pairs costs, whose
/// distances within a depth camera's range are metres.
const REFUSED: f64 = 1e6;

/// [`TrackerConfig::max_missing`]'s default (s): the longest horizon a track's forecasts are
/// checked at ([`HORIZONS`]). A person hidden for a while (behind someone passing, or out of
/// the detector's sight) is looked for where their track expects them for as long as its
/// forecasts say where that is. Against a second, fewer identity switches and lost tracks on the
/// scenes benchmark's development draws, ids passed on to someone else as rarely, the forecasts
/// and headings level (docs/benchmark_log.md, "a track kept as long as it forecasts").
pub const MAX_MISSING: f64 = HORIZONS[HORIZONS.len() - 1];

/// Association, birth and drop rules, and what each track and the depth lookup use.
///
/// ```
/// use torso_core::{Tracker, TrackerConfig};
/// // Confirm on the first frame, drop after half a second, at most eight people.
/// let config = TrackerConfig { min_hits: 1, max_missing: 0.5, capacity: 8, ..TrackerConfig::default() };
/// let tracker = Tracker::new(config).unwrap();
/// assert_eq!(tracker.config().capacity, 8);
/// assert!(Tracker::new(TrackerConfig { gate: -1.0, ..config }).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackerConfig {
    /// Largest distance (m) between where a track's person is expected and the torso centre of
    /// the detection it takes: a walking person covers 0.6 m in 0.4 s (and a steady walk is
    /// followed on while its walker is unseen). A track whose recent association distances
    /// scatter wider looks [`GATE_SPREADS`] of them far instead (up to [`MAX_SPREAD_GATE`] times
    /// this), and every track's gate is widened at [`BLIND_PACE`] for the time the camera sent
    /// no frame since it was last matched.
    pub gate: f64,
    /// Matched frames before a track is confirmed and given an id.
    pub min_hits: u32,
    /// Seconds without a match after which a confirmed track is dropped ([`MAX_MISSING`] by
    /// default).
    pub max_missing: f64,
    /// Most tracks alive at once; a detection that would open one more gets no track.
    pub capacity: usize,
    /// Most detections in one frame; a frame with more is refused.
    pub max_detections: usize,
    pub person: PersonConfig,
    pub depth: DepthLookup,
}

impl Default for TrackerConfig {
    fn default() -> Self {
        Self {
            gate: 0.6,
            min_hits: 3,
            max_missing: MAX_MISSING,
            capacity: 64,
            max_detections: 256,
            person: PersonConfig::default(),
            depth: DepthLookup::default(),
        }
    }
}

impl TrackerConfig {
    /// Checks every field, as [`Tracker::new`] does.
    pub fn validate(&self) -> Result<()> {
        if !(self.gate > 0.0 && self.gate.is_finite()) {
            return Err(Error::InvalidArgument {
                name: "gate",
                expected: "a positive, finite distance in metres",
                value: self.gate,
            });
        }
        if self.min_hits < 1 {
            return Err(Error::InvalidArgument {
                name: "min_hits",
                expected: "at least 1 matched frame",
                value: f64::from(self.min_hits),
            });
        }
        if !(self.max_missing >= 0.0 && self.max_missing.is_finite()) {
            return Err(Error::InvalidArgument {
                name: "max_missing",
                expected: "a finite, non-negative time in seconds",
                value: self.max_missing,
            });
        }
        for (name, value) in [
            ("capacity", self.capacity),
            ("max_detections", self.max_detections),
        ] {
            if !(1..=MAX_CAPACITY).contains(&value) {
                return Err(Error::InvalidArgument {
                    name,
                    expected: "from 1 to MAX_CAPACITY (4096)",
                    value: value as f64,
                });
            }
        }
        self.person.validate()?;
        self.depth.validate()
    }
}

/// The track a detection was given.
///
/// ```
/// use torso_core::coco::N_JOINTS;
/// use torso_core::{Tracker, TrackerConfig};
/// let mut tracker = Tracker::new(TrackerConfig { min_hits: 1, ..TrackerConfig::default() }).unwrap();
/// let joints = [[[2.0, 0.0, 1.0]; N_JOINTS]];
/// let track = tracker.update(0.0, &joints, &[[0.9; N_JOINTS]], [0.0; 3]).unwrap()[0].track.unwrap();
/// assert_eq!((track.id, track.serial), (Some(1), 1));
/// assert!(tracker.person(track.slot).is_some());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TrackRef {
    /// Where the track lives in the tracker, for [`Tracker::forecast`] and
    /// [`Tracker::person`]; valid until the next frame.
    pub slot: usize,
    /// Unique per track over the tracker's life, tentative tracks included.
    pub serial: u64,
    /// The confirmed track's id (1, 2, ... in order of confirmation); `None` while tentative.
    pub id: Option<u64>,
}

/// One detection's outcome in a frame.
///
/// ```
/// use torso_core::coco::N_JOINTS;
/// use torso_core::{Tracker, TrackerConfig};
/// let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
/// let unseen = [[[f64::NAN; 3]; N_JOINTS]]; // a detection with no depth anywhere
/// let outcome = tracker.update(0.0, &unseen, &[[0.9; N_JOINTS]], [0.0; 3]).unwrap()[0];
/// assert_eq!((outcome.detection, outcome.track, outcome.observation), (0, None, None));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Index of the detection in the frame.
    pub detection: usize,
    /// `None` for a detection with no seen joint in 3D, or when `capacity` tracks are alive.
    pub track: Option<TrackRef>,
    pub observation: Option<Observation>,
}

#[derive(Clone, Debug)]
struct Slot {
    person: Person,
    centre: [f64; 3],
    hits: u32,
    last_seen: f64,
    /// Seconds the camera sent no frame since the track was last matched ([`BLIND_PACE`]).
    blind: f64,
    /// Mean square (m^2) of the track's recent association distances ([`GATE_SPREADS`]),
    /// weighed by `spread_weight`: the two are forgotten alike, so that their ratio is the mean
    /// of what the track has seen however young it is.
    spread: f64,
    spread_weight: f64,
    id: Option<u64>,
    serial: u64,
}

impl Slot {
    /// The track's association gate (m) for the configured `gate`: [`GATE_SPREADS`] of its
    /// recent association distances (root mean square) where that is wider, up to
    /// [`MAX_SPREAD_GATE`] times `gate`; widened at [`BLIND_PACE`] for the time the camera sent
    /// no frame since the track was last matched.
    fn gate(&self, gate: f64) -> f64 {
        let spread = if self.spread_weight > 0.0 {
            (self.spread / self.spread_weight).sqrt()
        } else {
            0.0
        };
        gate.max((GATE_SPREADS * spread).min(MAX_SPREAD_GATE * gate)) + BLIND_PACE * self.blind
    }

    /// Where the track's person is expected at `t`: the last centre, moved on at its walk's
    /// velocity over the time unseen where its history is a steady walk
    /// ([`Person::walking_velocity`]). A walker hidden for a few frames walks on out of a gate
    /// around where they were last seen; a person who stands, or whose history is too short to
    /// tell, is looked for where they were.
    fn expected_centre(&self, t: f64) -> [f64; 3] {
        let [x, y, z] = self.centre;
        match self.person.walking_velocity() {
            Some([vx, vy]) => {
                let dt = t - self.last_seen;
                [x + vx * dt, y + vy * dt, z]
            }
            None => self.centre,
        }
    }
}

/// Tracks of every person in a stream. See the [module documentation](self).
///
/// ```
/// use torso_core::coco::N_JOINTS;
/// use torso_core::{Tracker, TrackerConfig};
/// let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
/// tracker.update(1.0, &[], &[], [0.0; 3]).unwrap();
/// assert!(tracker.check_time(0.5).is_err()); // earlier than the last frame
/// let no_people: [[[f64; 3]; N_JOINTS]; 0] = [];
/// assert!(tracker.update(2.0, &no_people, &[], [0.0; 3]).unwrap().is_empty());
/// ```
#[derive(Clone, Debug)]
pub struct Tracker {
    config: TrackerConfig,
    /// Every track's storage; `active` lists the live ones in order of birth, `free` the rest.
    slots: Vec<Slot>,
    active: Vec<usize>,
    free: Vec<usize>,
    next_id: u64,
    next_serial: u64,
    last_t: Option<f64>,
    // Per-frame working memory, sized by the bounds above.
    /// The frame's joints as given or lifted; `joints`, those the tracks take (some dropped).
    lifted: Vec<Joints>,
    joints: Vec<Joints>,
    scores: Vec<[f64; N_JOINTS]>,
    centres: Vec<[f64; 3]>,
    /// Detections nearest the camera first.
    order: Vec<usize>,
    placeable: Vec<usize>,
    cost: Vec<f64>,
    matched: Vec<Option<usize>>,
    solver: Assignment,
    outcomes: Vec<Outcome>,
}

impl Tracker {
    pub fn new(config: TrackerConfig) -> Result<Self> {
        config.validate()?;
        let (c, d) = (config.capacity, config.max_detections);
        Ok(Self {
            config,
            slots: Vec::with_capacity(c),
            active: Vec::with_capacity(c),
            free: Vec::with_capacity(c),
            next_id: 1,
            next_serial: 1,
            last_t: None,
            lifted: Vec::with_capacity(d),
            joints: Vec::with_capacity(d),
            scores: Vec::with_capacity(d),
            centres: Vec::with_capacity(d),
            order: Vec::with_capacity(d),
            placeable: Vec::with_capacity(d),
            cost: Vec::with_capacity(c * d),
            matched: Vec::with_capacity(d),
            solver: Assignment::with_capacity(c, d),
            outcomes: Vec::with_capacity(d),
        })
    }

    pub fn config(&self) -> &TrackerConfig {
        &self.config
    }

    /// Drops every track and forgets the last frame's time, as for a new stream; ids and keys
    /// go on counting, so that no id is given twice. A stream whose clock jumped (a recording
    /// replayed from its start, one frame stamped far ahead) starts again from here.
    pub fn restart(&mut self) {
        for &i in &self.active {
            self.slots[i].person.reset();
            self.free.push(i);
        }
        self.active.clear();
        self.last_t = None;
    }

    /// Live tracks, tentative ones included.
    pub fn live(&self) -> usize {
        self.active.len()
    }

    /// Time of the last accepted frame.
    pub fn last_time(&self) -> Option<f64> {
        self.last_t
    }

    /// One frame of 3D joints in the world frame: `joints[d]` and `scores[d]` for detection `d`
    /// (NaN joints are missing; NaN scores mean "not scored"). Every argument is checked
    /// before anything changes: a refused frame leaves the tracker as it was.
    pub fn update(
        &mut self,
        t: f64,
        joints: &[Joints],
        scores: &[[f64; N_JOINTS]],
        camera_position: [f64; 3],
    ) -> Result<&[Outcome]> {
        if scores.len() != joints.len() {
            return Err(Error::LengthMismatch {
                name: "scores",
                expected: joints.len(),
                got: scores.len(),
            });
        }
        self.check(t, scores.iter().copied(), camera_position)?;
        self.lifted.clear();
        self.lifted.extend_from_slice(joints);
        self.scores.clear();
        self.scores.extend_from_slice(scores);
        self.track(t, camera_position)
    }

    /// One frame of 2D `keypoints` `(u, v, score)` with the depth image registered to them:
    /// each seen keypoint's depth is looked up ([`DepthLookup`]) and deprojected into the world
    /// through `camera`, then the frame is tracked as in [`update`](Self::update).
    /// [`joints`](Self::joints) gives the lifted joints afterwards.
    pub fn step(
        &mut self,
        t: f64,
        keypoints: &[Keypoints],
        depth: &DepthImage<'_>,
        camera: &Camera,
    ) -> Result<&[Outcome]> {
        let position = camera.position();
        self.check(t, keypoints.iter().map(|k| k.map(|p| p[2])), position)?;
        self.lifted.clear();
        self.scores.clear();
        let (lookup, person_config) = (&self.config.depth, &self.config.person);
        let mut ahead = keypoints
            .iter()
            .flatten()
            .filter(|p| person_config.sees(p[2]))
            .map(|p| [p[0], p[1]]);
        lookup.prefetch(depth, ahead.by_ref().take(crate::depth::LOOKAHEAD));
        for person in keypoints {
            let scores = person.map(|p| p[2]);
            let joints = std::array::from_fn(|j| {
                let [u, v, score] = person[j];
                if person_config.sees(score) {
                    lookup.prefetch(depth, ahead.next().into_iter());
                    let z = lookup.depth_at(depth, [u, v]);
                    camera.deproject_to_world([u, v], z)
                } else {
                    [f64::NAN; 3]
                }
            });
            self.lifted.push(joints);
            self.scores.push(scores);
        }
        self.track(t, position)
    }

    /// The joints of the last frame as the tracks took them: those given to
    /// [`update`](Self::update) or lifted by [`step`](Self::step) (unseen ones NaN), less any
    /// the tracker dropped as read off someone nearer the camera.
    pub fn joints(&self) -> &[Joints] {
        &self.joints
    }

    /// The joints of the last frame as given to [`update`](Self::update) or lifted by
    /// [`step`](Self::step), before the tracker dropped any: [`update`](Self::update) with them
    /// tracks the frame again as it was tracked (a recording of a stream replays it so; the
    /// joints as the tracks took them would be judged a second time).
    pub fn lifted(&self) -> &[Joints] {
        &self.lifted
    }

    /// The person chain of the track in `slot` (from a [`TrackRef`] of the latest frame).
    pub fn person(&self, slot: usize) -> Option<&Person> {
        self.active
            .contains(&slot)
            .then(|| &self.slots[slot].person)
    }

    /// [`Person::forecast`] of the track in `slot`; `Ok(false)` for a slot with no live track.
    pub fn forecast(&mut self, slot: usize, horizons: &[f64], out: &mut [Pose]) -> Result<bool> {
        if !self.active.contains(&slot) {
            return Ok(false);
        }
        self.slots[slot].person.forecast(horizons, out)
    }

    /// [`Person::intervals`] of the track in `slot`; `Ok(false)` for a slot with no live track.
    pub fn intervals(&self, slot: usize, horizons: &[f64], out: &mut [Pose]) -> Result<bool> {
        match self.person(slot) {
            Some(person) => person.intervals(horizons, out),
            None => Ok(false),
        }
    }

    /// The confirmed tracks, in order of birth.
    pub fn tracks(&self) -> impl Iterator<Item = (TrackRef, &Person)> + '_ {
        self.active.iter().filter_map(|&i| {
            let s = &self.slots[i];
            s.id.map(|id| {
                let track = TrackRef {
                    slot: i,
                    serial: s.serial,
                    id: Some(id),
                };
                (track, &s.person)
            })
        })
    }

    /// Whether a frame at `t` would be taken: a finite time after the last frame's. A caller
    /// with work to do before the frame reaches the tracker (running a keypoint model) asks
    /// first.
    pub fn check_time(&self, t: f64) -> Result<()> {
        if !t.is_finite() {
            return Err(Error::NonFinite {
                name: "t",
                index: 0,
            });
        }
        match self.last_t.filter(|&p| !(t > p)) {
            Some(previous) => Err(Error::TimeNotIncreasing { previous, got: t }),
            None => Ok(()),
        }
    }

    fn check(
        &self,
        t: f64,
        mut scores: impl ExactSizeIterator<Item = [f64; N_JOINTS]>,
        camera_position: [f64; 3],
    ) -> Result<()> {
        self.check_time(t)?;
        crate::coco::check_camera_position(camera_position)?;
        if scores.len() > self.config.max_detections {
            return Err(Error::InvalidArgument {
                name: "detections",
                expected: "at most max_detections detections in one frame",
                value: scores.len() as f64,
            });
        }
        match scores.find_map(|p| {
            p.into_iter()
                .find(|s| !s.is_nan() && !(0.0..=1.0).contains(s))
        }) {
            Some(value) => Err(Error::InvalidArgument {
                name: "scores",
                expected: "keypoint scores from 0 to 1 (NaN for a keypoint not scored)",
                value,
            }),
            None => Ok(()),
        }
    }

    /// Association, birth, the per-person chain and drop, on the checked frame in `joints` and
    /// `scores`.
    fn track(&mut self, t: f64, camera_position: [f64; 3]) -> Result<&[Outcome]> {
        let blind = self
            .last_t
            .map_or(0.0, |last| (t - last - MAX_FRAME_STEP).max(0.0));
        for &i in &self.active {
            self.slots[i].blind += blind;
        }
        let previous = self.last_t.replace(t);
        self.joints.clear();
        self.joints.extend_from_slice(&self.lifted);
        self.place_detections(camera_position);
        self.drop_read_off_nearer(camera_position);
        self.placeable.clear();
        self.placeable
            .extend((0..self.centres.len()).filter(|&d| self.centres[d][0].is_finite()));
        self.associate(t)?;

        self.outcomes.clear();
        self.outcomes
            .extend((0..self.joints.len()).map(|detection| Outcome {
                detection,
                track: None,
                observation: None,
            }));
        for k in 0..self.placeable.len() {
            let d = self.placeable[k];
            let slot = match self.matched[d] {
                Some(slot) => slot,
                None if self.seen_twice(d) => continue,
                None => match self.open() {
                    Some(slot) => {
                        // A second detection of this body later in the frame opens none.
                        self.matched[d] = Some(slot);
                        slot
                    }
                    None => continue,
                },
            };
            let s = &mut self.slots[slot];
            // The scatter of a person's measured centre from one frame to the next; a track
            // found again after frames without it has the person's unseen motion in its step.
            if s.hits > 0 && Some(s.last_seen) == previous {
                let step = distance(s.expected_centre(t), self.centres[d]);
                let weight = 1.0 - (-(t - s.last_seen) / GATE_MEMORY).exp();
                s.spread += weight * (step * step - s.spread);
                s.spread_weight += weight * (1.0 - s.spread_weight);
            }
            let observation =
                s.person
                    .update(t, &self.joints[d], &self.scores[d], camera_position)?;
            s.hits += 1;
            s.last_seen = t;
            s.blind = 0.0;
            s.centre = match observation.pose {
                Some(p) => [p[0], p[1], p[2]],
                None => self.centres[d],
            };
            if s.id.is_none() && s.hits >= self.config.min_hits {
                s.id = Some(self.next_id);
                self.next_id += 1;
            }
            self.outcomes[d] = Outcome {
                detection: d,
                track: Some(TrackRef {
                    slot,
                    serial: s.serial,
                    id: s.id,
                }),
                observation: Some(observation),
            };
        }
        let max_missing = self.config.max_missing;
        let (slots, free, outcomes) = (&mut self.slots, &mut self.free, &self.outcomes);
        self.active.retain(|&i| {
            // The tracks matched in this frame are those its outcomes name; an unmatched one is
            // where association looked for it.
            let same_body = slots[i].last_seen != t && {
                let expected = slots[i].expected_centre(t);
                outcomes
                    .iter()
                    .filter_map(|o| o.track)
                    .any(|track| distance(slots[track.slot].centre, expected) < MIN_SEPARATION)
            };
            let s = &mut slots[i];
            let keep = !same_body
                && (s.last_seen == t || (s.id.is_some() && t - s.last_seen <= max_missing));
            if !keep {
                s.person.reset();
                free.push(i);
            }
            keep
        });
        Ok(&self.outcomes)
    }

    /// `centres[d]`: where detection `d` is, for association ([`detection_centre`]).
    fn place_detections(&mut self, camera: [f64; 3]) {
        let person = self.config.person;
        self.centres.clear();
        self.centres.extend(
            self.joints
                .iter()
                .zip(&self.scores)
                .map(|(j, s)| detection_centre(j, s, &person, camera)),
        );
    }

    /// Drops the joints each detection shows on someone nearer the camera
    /// ([`drop_read_off_nearer`]) and places it again without them, nearest first: a person
    /// in front is placed from their own joints before anyone behind is judged against them,
    /// so a detection lifted among the people in front takes nothing from them.
    fn drop_read_off_nearer(&mut self, camera: [f64; 3]) {
        let depth = |c: &[f64; 3]| {
            let d = distance(*c, camera);
            if d.is_finite() {
                d
            } else {
                f64::INFINITY
            }
        };
        self.order.clear();
        self.order.extend(0..self.centres.len());
        let centres = &self.centres;
        self.order.sort_unstable_by(|&a, &b| {
            depth(&centres[a])
                .total_cmp(&depth(&centres[b]))
                .then(a.cmp(&b))
        });
        let person = self.config.person;
        for k in 1..self.order.len() {
            let d = self.order[k];
            if !finite(&self.centres[d]) {
                break; // the rest have no centre either
            }
            let nearer = self.order[..k].iter().map(|&e| self.centres[e]);
            if drop_read_off_nearer(&mut self.joints[d], self.centres[d], nearer) > 0 {
                self.centres[d] =
                    detection_centre(&self.joints[d], &self.scores[d], &person, camera);
            }
        }
    }

    /// `matched[d]`: the slot of the live track that detection `d` continues, if any, in the
    /// frame at `t`.
    fn associate(&mut self, t: f64) -> Result<()> {
        self.matched.clear();
        self.matched.resize(self.joints.len(), None);
        let (rows, cols) = (self.active.len(), self.placeable.len());
        if rows == 0 || cols == 0 {
            return Ok(());
        }
        self.cost.clear();
        for &i in &self.active {
            let a = self.slots[i].expected_centre(t);
            let gate = self.slots[i].gate(self.config.gate);
            for &d in &self.placeable {
                let b = self.centres[d];
                let distance = distance(a, b);
                // Pairs beyond the gate cost more than any allowed set of pairs, and are refused
                // below if the solver still takes them.
                self.cost
                    .push(if distance <= gate { distance } else { REFUSED });
            }
        }
        for &(r, c) in self.solver.solve(&self.cost, rows, cols)? {
            if self.cost[r * cols + c] < REFUSED {
                self.matched[self.placeable[c]] = Some(self.active[r]);
            }
        }
        Ok(())
    }

    /// Whether detection `d` lies within [`MIN_SEPARATION`] of a detection a track took (or
    /// opened, earlier in this frame).
    fn seen_twice(&self, d: usize) -> bool {
        self.placeable.iter().any(|&e| {
            self.matched[e].is_some() && distance(self.centres[e], self.centres[d]) < MIN_SEPARATION
        })
    }

    /// A new tentative track's slot: a freed one, or a new one below `capacity`.
    fn open(&mut self) -> Option<usize> {
        let slot = match self.free.pop() {
            Some(slot) => slot,
            None if self.slots.len() < self.config.capacity => {
                let person = Person::new(self.config.person).expect("validated with the config");
                self.slots.push(Slot {
                    person,
                    centre: [f64::NAN; 3],
                    hits: 0,
                    last_seen: f64::NAN,
                    blind: 0.0,
                    spread: 0.0,
                    spread_weight: 0.0,
                    id: None,
                    serial: 0,
                });
                self.slots.len() - 1
            }
            None => return None,
        };
        let s = &mut self.slots[slot];
        s.hits = 0;
        s.blind = 0.0;
        s.spread = 0.0;
        s.spread_weight = 0.0;
        s.id = None;
        s.serial = self.next_serial;
        self.next_serial += 1;
        self.active.push(slot);
        Some(slot)
    }
}

/// Where a detection is, for association: the mean of its seen torso joints, after those whose
/// depth came off something else ([`crate::stray`], seen from `camera`), else of every seen
/// joint, the torso's moved behind the surface as a track moves them
/// ([`PersonConfig::behind_surface`]); NaN when it has no seen joint in 3D.
pub fn detection_centre(
    joints: &Joints,
    scores: &[f64; N_JOINTS],
    config: &PersonConfig,
    camera: [f64; 3],
) -> [f64; 3] {
    let mut seen = config.used_joints(joints, scores, camera);
    // Placed as a track's centre is, from the torso's joint centres behind the surface.
    config.behind_surface(&mut seen, camera);
    let torso_seen = TORSO.iter().any(|&j| finite(&seen[j]));
    let mut total = [0.0; 3];
    let mut n = 0usize;
    for (j, x) in seen.iter().enumerate() {
        if finite(x) && (!torso_seen || TORSO.contains(&j)) {
            for (t, v) in total.iter_mut().zip(x) {
                *t += v;
            }
            n += 1;
        }
    }
    if n == 0 {
        return [f64::NAN; 3];
    }
    total.map(|v| v / n as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::Intrinsics;

    /// A person facing -x (towards a camera at the origin) at `(x, y)`.
    fn body(x: f64, y: f64) -> Joints {
        std::array::from_fn(|j| {
            let side = match j {
                0 => 0.0,
                _ if j % 2 == 1 => -0.18,
                _ => 0.18,
            };
            [x, y + side, 1.7 - 0.08 * j as f64]
        })
    }

    const SEEN: [f64; N_JOINTS] = [0.9; N_JOINTS];

    #[test]
    fn the_per_frame_types_can_move_to_and_be_shared_with_other_threads() {
        fn send_and_sync<T: Send + Sync>() {}
        send_and_sync::<Tracker>();
        send_and_sync::<Person>();
        send_and_sync::<crate::Forecaster>();
        send_and_sync::<DepthImage<'_>>();
    }

    #[test]
    fn a_restart_drops_every_track_and_keeps_counting_ids() {
        let mut tracker = Tracker::new(TrackerConfig {
            min_hits: 1,
            ..TrackerConfig::default()
        })
        .unwrap();
        let two = [body(2.0, 0.0), body(3.0, 1.0)];
        tracker.update(3600.0, &two, &[SEEN; 2], [0.0; 3]).unwrap();
        assert!(tracker.check_time(10.0).is_err());
        tracker.restart();
        assert_eq!((tracker.live(), tracker.last_time()), (0, None));
        let out = tracker.update(10.0, &two[..1], &[SEEN], [0.0; 3]).unwrap();
        assert_eq!(out[0].track.unwrap().id, Some(3));
    }

    #[test]
    fn a_reset_person_behaves_as_a_new_one() {
        let config = PersonConfig::default();
        let mut used = Person::new(config).unwrap();
        for k in 0..80 {
            let t = k as f64 / 25.0;
            used.update(t, &body(3.0 - 0.02 * k as f64, 0.1 * t), &SEEN, [0.0; 3])
                .unwrap();
        }
        used.reset();
        let mut fresh = Person::new(config).unwrap();
        let (mut a, mut b) = ([[0.0; 5]; 2], [[0.0; 5]; 2]);
        for k in 0..80 {
            let t = 10.0 + k as f64 / 30.0;
            let joints = body(2.0 + 0.03 * k as f64, -0.05 * k as f64);
            let x = used.update(t, &joints, &SEEN, [0.0; 3]).unwrap();
            let y = fresh.update(t, &joints, &SEEN, [0.0; 3]).unwrap();
            assert_eq!(format!("{x:?}"), format!("{y:?}"), "frame {k}");
            assert_eq!(
                used.forecast(&[0.4, 1.0], &mut a).unwrap(),
                fresh.forecast(&[0.4, 1.0], &mut b).unwrap()
            );
            assert_eq!(format!("{a:?}"), format!("{b:?}"));
            assert_eq!(
                used.intervals(&[0.4, 1.0], &mut a).unwrap(),
                fresh.intervals(&[0.4, 1.0], &mut b).unwrap()
            );
            assert_eq!(format!("{a:?}"), format!("{b:?}"));
        }
    }

    #[test]
    fn a_person_whose_shoulders_read_someone_nearer_keeps_their_track() {
        // Every other frame the shoulders' keypoints take the depth of a person 2.5 m nearer the
        // camera: the mean of the four torso joints would move 1.25 m, beyond the gate.
        let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
        for k in 0..10 {
            let mut joints = body(4.0, 0.0);
            if k % 2 == 1 {
                joints[crate::coco::LEFT_SHOULDER][0] -= 2.5;
                joints[crate::coco::RIGHT_SHOULDER][0] -= 2.5;
            }
            let out = tracker
                .update(k as f64 / 15.0, &[joints], &[SEEN], [0.0, 0.0, 1.0])
                .unwrap();
            assert_eq!(out[0].track.unwrap().id, (k >= 2).then_some(1), "frame {k}");
            assert_eq!(tracker.live(), 1);
            // On the surface (no depth behind it), the hips' x: the shoulders were dropped.
            let surface = PersonConfig {
                surface_depth: [0.0; 2],
                ..PersonConfig::default()
            };
            let centre = detection_centre(&joints, &SEEN, &surface, [0.0; 3]);
            assert!((centre[0] - 4.0).abs() < 1e-9, "frame {k}: {centre:?}");
        }
    }

    /// Two people about 2.9 and 3.25 m from the camera, 0.7 m apart, and a third one 4.4 m away
    /// behind them who shows a shoulder and a hip on each, all read at their depths.
    fn hidden_behind_two() -> ([Joints; 2], Joints) {
        let front = [body(2.85, -0.2), body(3.15, -0.8)];
        let mut hidden = body(4.4, -0.5);
        hidden[crate::coco::LEFT_SHOULDER] = [2.85, -0.35, 1.3];
        hidden[crate::coco::LEFT_HIP] = [2.85, -0.3, 0.8];
        hidden[crate::coco::RIGHT_SHOULDER] = [3.15, -0.65, 1.3];
        hidden[crate::coco::RIGHT_HIP] = [3.15, -0.7, 0.8];
        for i in 0..N_JOINTS {
            if !TORSO.contains(&i) {
                hidden[i] = [f64::NAN; 3];
            }
        }
        (front, hidden)
    }

    #[test]
    fn a_person_lifted_among_the_people_in_front_opens_no_track_of_their_own() {
        // Lifted, the person behind's torso centre lies between the two in front, further than
        // the gate from their own and further than MIN_SEPARATION from either front person's.
        let (front, hidden) = hidden_behind_two();
        let surface = PersonConfig {
            surface_depth: [0.0; 2],
            ..PersonConfig::default()
        };
        let lifted = detection_centre(&hidden, &SEEN, &surface, [0.0; 3]);
        for f in front {
            let own = detection_centre(&f, &SEEN, &surface, [0.0; 3]);
            assert!(distance(lifted, own) > MIN_SEPARATION, "{lifted:?} {own:?}");
        }
        let mut tracker = Tracker::new(TrackerConfig {
            min_hits: 1,
            ..TrackerConfig::default()
        })
        .unwrap();
        for k in 0..5 {
            let frame = [front[0], hidden, front[1]];
            let out = tracker
                .update(k as f64 / 15.0, &frame, &[SEEN; 3], [0.0; 3])
                .unwrap();
            // Judged before the farther front person (its lifted centre is the nearer), it keeps
            // the joints on them and is that person seen twice: two tracks, one each.
            let tracked: Vec<bool> = out.iter().map(|o| o.track.is_some()).collect();
            assert!(
                tracked[0] && tracked[1] != tracked[2],
                "frame {k}: {tracked:?}"
            );
            assert_eq!(tracker.live(), 2, "frame {k}");
            // The people in front keep every joint; the one behind, those not on the nearer.
            assert_eq!(
                format!("{:?}", tracker.joints()[0]),
                format!("{:?}", front[0])
            );
            assert_eq!(
                format!("{:?}", tracker.joints()[2]),
                format!("{:?}", front[1])
            );
            let kept = TORSO.map(|i| finite(&tracker.joints()[1][i]));
            assert_eq!(kept, [false, true, false, true], "frame {k}");
        }
    }

    #[test]
    fn a_frame_tracked_again_from_its_lifted_joints_is_tracked_as_it_was() {
        // The person behind shows joints on both people in front, and the tracks take only
        // those not on the nearer one. A recording keeps the joints as lifted: tracked again,
        // the frame's joints are judged from the same start.
        let (front, hidden) = hidden_behind_two();
        let config = TrackerConfig {
            min_hits: 1,
            ..TrackerConfig::default()
        };
        let frame = [front[0], hidden, front[1]];
        let (mut live, mut again) = (Tracker::new(config).unwrap(), Tracker::new(config).unwrap());
        for k in 0..5 {
            let t = k as f64 / 15.0;
            let out = format!(
                "{:?}",
                live.update(t, &frame, &[SEEN; 3], [0.0; 3]).unwrap()
            );
            assert_eq!(format!("{:?}", live.lifted()), format!("{frame:?}"));
            let lifted = live.lifted().to_vec();
            let replayed = again.update(t, &lifted, &[SEEN; 3], [0.0; 3]).unwrap();
            assert_eq!(format!("{replayed:?}"), out, "frame {k}");
            assert_eq!(
                format!("{:?}", again.joints()),
                format!("{:?}", live.joints())
            );
            // The tracks took fewer of the person behind's joints than were lifted.
            let kept = |joints: &Joints| TORSO.map(|i| finite(&joints[i]));
            assert_eq!(kept(&live.joints()[1]), [false, true, false, true]);
            assert_eq!(kept(&live.lifted()[1]), [true; 4]);
        }
    }

    #[test]
    fn a_body_seen_twice_keeps_one_track_and_two_people_side_by_side_keep_two() {
        let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
        // Which detections got a track (and a pose), and how many tracks live.
        let mut frame = |t: f64, bodies: &[Joints]| {
            let scores = vec![SEEN; bodies.len()];
            let out = tracker.update(t, bodies, &scores, [0.0; 3]).unwrap();
            let tracked: Vec<bool> = out
                .iter()
                .map(|o| o.track.is_some() && o.observation.is_some())
                .collect();
            (tracked, tracker.live())
        };
        // Seen twice from its first frame: one track, the first detection's.
        let twice = [body(3.0, 0.0), body(3.05, 0.0)];
        assert_eq!(frame(0.0, &twice), (vec![true, false], 1));
        // The same body again, 5 cm off, beside the one the track takes: no second track.
        let mut again = body(3.05, 0.0);
        again[0][2] += 0.1;
        assert_eq!(
            frame(0.04, &[body(3.0, 0.0), again]),
            (vec![true, false], 1)
        );
        // A second person with their torso centre 0.4 m away (shoulder to shoulder) gets one.
        let two = [body(3.0, 0.0), body(3.0, 0.4)];
        assert_eq!(frame(0.08, &two), (vec![true, true], 2));
    }

    #[test]
    fn a_walker_hidden_for_a_while_is_looked_for_further_on_and_a_standing_person_where_they_stood()
    {
        // 2 s in view at 15 frames per second, then 0.6 s hidden (the frames come, without
        // them), then seen again 0.72 m on from where the track last saw them: beyond the gate
        // (0.6 m).
        let id_after_gap = |speed: f64| {
            let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
            let at = |t: f64| body(5.0 - speed * t, 0.0);
            let mut first = None;
            for k in 0..=30 {
                let t = k as f64 / 15.0;
                let out = tracker.update(t, &[at(t)], &[SEEN], [0.0; 3]).unwrap();
                first = first.or(out[0].track.and_then(|track| track.id));
            }
            let nobody: [Joints; 0] = [];
            for k in 31..39 {
                tracker
                    .update(k as f64 / 15.0, &nobody, &[], [0.0; 3])
                    .unwrap();
            }
            let t = 2.0 + 0.6;
            let seen = body(5.0 - speed * 2.0 - 0.72, 0.0);
            let out = tracker.update(t, &[seen], &[SEEN], [0.0; 3]).unwrap();
            (first, out[0].track.unwrap())
        };
        // Walking towards the camera at 1.2 m/s (the torso faces it): the walk went on unseen,
        // and the same track takes the person again.
        let (first, track) = id_after_gap(1.2);
        assert_eq!((first, track.id), (Some(1), Some(1)));
        // Standing still, the same displacement is someone else: a new, tentative track.
        let (first, track) = id_after_gap(0.0);
        assert_eq!((first, track.id), (Some(1), None));
    }

    #[test]
    fn a_person_who_moved_while_the_camera_sent_no_frame_keeps_their_track() {
        // A person standing 4 m away, seen at 30 frames per second for a second; then they are
        // seen again `gap` s later, 0.9 m to the side: beyond the gate (0.6 m).
        let id_after = |gap: f64, frames_in_gap: bool| {
            let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
            for k in 0..=30 {
                let t = k as f64 / 30.0;
                tracker
                    .update(t, &[body(4.0, 0.0)], &[SEEN], [0.0; 3])
                    .unwrap();
            }
            let nobody: [Joints; 0] = [];
            let steps = (gap * 30.0).round() as usize;
            if frames_in_gap {
                for k in 1..steps {
                    let t = 1.0 + k as f64 / 30.0;
                    tracker.update(t, &nobody, &[], [0.0; 3]).unwrap();
                }
            }
            let t = 1.0 + steps as f64 / 30.0;
            let out = tracker
                .update(t, &[body(4.0, 0.9)], &[SEEN], [0.0; 3])
                .unwrap();
            out[0].track.unwrap().id
        };
        // The camera sent nothing for a second (a stalled sensor): the gate widens at a slow
        // walk's pace for the 0.8 s beyond a frame step, and the track takes the person again.
        assert_eq!(id_after(1.0, false), Some(1));
        // Half a second's stall widens it 0.3 m: not enough, and a new, tentative track opens.
        assert_eq!(id_after(0.5, false), None);
        // Frames that came without the person (hidden, out of the detector's sight) widen
        // nothing: the same move is someone else's.
        assert_eq!(id_after(1.0, true), None);
    }

    #[test]
    fn a_person_whose_measured_centre_scatters_is_found_within_three_of_its_own_spreads() {
        // A person standing 6 m away, seen at 30 frames per second, whose measured centre jumps
        // sideways from frame to frame (a robot's heading that wavers by a few degrees): 0.4 m
        // for a second, then 0.7 m for two and 1 m for one, beyond the gate (0.6 m) but within
        // three of the track's own recent jumps. A jump of 1.4 m is beyond twice the gate, the
        // most a scatter widens it to. Then they are measured still for three seconds, and a
        // detection 0.9 m away is someone else's again.
        let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
        let mut ids = Vec::new();
        let mut y = 0.0;
        for k in 0..120 {
            let t = k as f64 / 30.0;
            let half = [0.2, 0.35, 0.35, 0.5][k / 30];
            y = if k % 2 == 0 { half } else { -half };
            let out = tracker
                .update(t, &[body(6.0, y)], &[SEEN], [0.0; 3])
                .unwrap();
            ids.push(out[0].track.unwrap().id);
        }
        assert!(ids[2..].iter().all(|&id| id == Some(1)), "{ids:?}");
        let out = tracker
            .update(4.0, &[body(6.0, y + 1.4)], &[SEEN], [0.0; 3])
            .unwrap();
        assert_eq!(out[0].track.unwrap().id, None);
        for k in 121..210 {
            let t = k as f64 / 30.0;
            let out = tracker
                .update(t, &[body(6.0, 0.0)], &[SEEN], [0.0; 3])
                .unwrap();
            assert_eq!(out[0].track.unwrap().id, Some(1));
        }
        let out = tracker
            .update(7.0, &[body(6.0, 0.9)], &[SEEN], [0.0; 3])
            .unwrap();
        assert_eq!(out[0].track.unwrap().id, None);
    }

    #[test]
    fn a_body_tracked_twice_keeps_one_track_and_a_neighbour_unseen_for_a_frame_keeps_theirs() {
        // Two tracks 0.6 m apart; the second's detection then comes `near` m from the first
        // for two frames (both tracks matched), and in the next frame only the first is seen.
        let live_after = |near: f64| {
            let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
            let mut frame = |k: usize, bodies: &[Joints]| {
                let scores = vec![SEEN; bodies.len()];
                let t = k as f64 / 15.0;
                let out = tracker.update(t, bodies, &scores, [0.0; 3]).unwrap();
                out[0].track.unwrap().id
            };
            for k in 0..3 {
                frame(k, &[body(3.0, 0.0), body(3.0, 0.6)]);
            }
            for k in 3..5 {
                frame(k, &[body(3.0, 0.0), body(3.0, near)]);
            }
            let id = frame(5, &[body(3.0, 0.0)]);
            (id, tracker.live())
        };
        // 0.2 m apart is one body tracked twice: the track left unmatched goes at once (it
        // would take the body's detection in turns with the other).
        assert_eq!(live_after(0.2), (Some(1), 1));
        // 0.6 m apart is a neighbour unseen for a frame: their track lives on.
        assert_eq!(live_after(0.6), (Some(1), 2));
    }

    #[test]
    fn a_hidden_walker_whose_last_place_someone_else_takes_keeps_their_track() {
        // A walks towards the camera at 1.2 m/s for 2 s, is hidden for 0.6 s and comes back
        // where the walk went on; B crosses A's path, reaching where A was last seen while A
        // is hidden (15 frames per second).
        let mut tracker = Tracker::new(TrackerConfig::default()).unwrap();
        let a = |t: f64| body(5.0 - 1.2 * t, 0.0);
        let b = |t: f64| body(2.6, 0.1 + 1.2 * (t - 2.4));
        let mut ids = Vec::new();
        for k in 0..=39 {
            let t = k as f64 / 15.0;
            let bodies = if (31..39).contains(&k) {
                vec![b(t)]
            } else {
                vec![b(t), a(t)]
            };
            let scores = vec![SEEN; bodies.len()];
            let out = tracker.update(t, &bodies, &scores, [0.0; 3]).unwrap();
            ids.push(out.iter().map(|o| o.track.unwrap().id).collect::<Vec<_>>());
        }
        // A's track is not dropped as B's body tracked twice (at 2.4 s B is 0.1 m from A's
        // last centre, and A's walk has gone on 0.48 m from it): A comes back with their id.
        let (b_id, a_id) = (ids[30][0], ids[30][1]);
        assert!(a_id.is_some() && b_id.is_some() && a_id != b_id, "{ids:?}");
        assert_eq!(ids[39], vec![b_id, a_id]);
    }

    #[test]
    fn a_refused_frame_changes_nothing() {
        let mut tracker = Tracker::new(TrackerConfig {
            max_detections: 2,
            ..TrackerConfig::default()
        })
        .unwrap();
        tracker
            .update(0.0, &[body(2.0, 0.0)], &[SEEN], [0.0; 3])
            .unwrap();
        let before = format!("{tracker:?}");
        let mut bad = SEEN;
        bad[3] = 5.0;
        let three = [body(2.0, 0.0), body(3.0, 0.0), body(4.0, 0.0)];
        let one = [body(2.0, 0.0)];
        type Frame<'a> = (f64, &'a [Joints], &'a [[f64; N_JOINTS]], [f64; 3]);
        let frames: [Frame; 6] = [
            (0.0, &one, &[SEEN], [0.0; 3]),
            (f64::NAN, &one, &[SEEN], [0.0; 3]),
            (0.04, &one, &[bad], [0.0; 3]),
            (0.04, &one, &[], [0.0; 3]),
            (0.04, &one, &[SEEN], [f64::NAN; 3]),
            (0.04, &three, &[SEEN; 3], [0.0; 3]),
        ];
        for (t, joints, scores, camera) in frames {
            assert!(tracker.update(t, joints, scores, camera).is_err());
        }
        assert_eq!(format!("{tracker:?}"), before);
    }

    #[test]
    fn capacity_bounds_the_tracks_and_dropped_slots_are_reused() {
        let mut tracker = Tracker::new(TrackerConfig {
            capacity: 2,
            min_hits: 1,
            max_missing: 0.1,
            ..TrackerConfig::default()
        })
        .unwrap();
        let three = [body(2.0, 0.0), body(3.0, 1.0), body(4.0, -1.0)];
        let out = tracker.update(0.0, &three, &[SEEN; 3], [0.0; 3]).unwrap();
        let ids: Vec<Option<u64>> = out.iter().map(|o| o.track.and_then(|t| t.id)).collect();
        assert_eq!(ids, [Some(1), Some(2), None]);
        // The first two leave for longer than max_missing; the third then gets a reused slot.
        tracker.update(0.5, &[], &[], [0.0; 3]).unwrap();
        assert_eq!(tracker.tracks().count(), 0);
        let out = tracker
            .update(0.54, &three[2..], &[SEEN], [0.0; 3])
            .unwrap();
        let track = out[0].track.unwrap();
        assert_eq!((track.id, track.serial), (Some(3), 3));
        assert!(track.slot < 2);
        assert_eq!(tracker.person(track.slot).unwrap().forecaster().len(), 1);
    }

    #[test]
    fn step_lifts_keypoints_as_the_camera_and_lookup_say_and_tracks_them() {
        let (w, h) = (64usize, 48usize);
        let data = vec![2.5f32; w * h];
        let image = DepthImage::new(&data, w, h).unwrap();
        let camera = Camera::new(
            Intrinsics::new(50.0, 50.0, 32.0, 24.0, [0.1, 0.0, 0.0, 0.0, 0.0]).unwrap(),
            Camera::level(1.2, 0.0),
        );
        let keypoints: Keypoints = std::array::from_fn(|j| {
            [
                20.0 + j as f64,
                5.0 + 2.0 * j as f64,
                if j == 1 { 0.1 } else { 0.8 },
            ]
        });
        let mut a = Tracker::new(TrackerConfig::default()).unwrap();
        let from_step = a.step(0.0, &[keypoints], &image, &camera).unwrap()[0];
        let lifted = a.joints()[0];
        assert!(
            lifted[1].iter().all(|v| v.is_nan()),
            "below min_score: not lifted"
        );
        for j in (0..N_JOINTS).filter(|&j| j != 1) {
            let [u, v, _] = keypoints[j];
            let p = lifted[j];
            // Back through the camera: the same pixel, 2.5 m along the optical axis.
            let optical = [-(p[1]), -(p[2] - 1.2), p[0]];
            assert!((optical[2] - 2.5).abs() < 1e-12);
            let uv = camera.intrinsics.project(optical);
            assert!(
                (uv[0] - u).abs() < 1e-9 && (uv[1] - v).abs() < 1e-9,
                "{uv:?}"
            );
        }
        let mut b = Tracker::new(TrackerConfig::default()).unwrap();
        let scores = keypoints.map(|k| k[2]);
        let from_update = b
            .update(0.0, &[lifted], &[scores], [0.0, 0.0, 1.2])
            .unwrap();
        assert_eq!(format!("{:?}", from_update), format!("{:?}", [from_step]));
    }
}
