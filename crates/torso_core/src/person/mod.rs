//! One tracked person: the thesis' per-person chain (section 3.2) on the 17 COCO keypoints of a
//! 2D detector, lifted to 3D in the world frame.
//!
//! Each frame: move a far shoulder or hip that the body hides back to its depth, decide which
//! way the chest faces from the labels, the nose and the walking direction ([`crate::sides`]),
//! gate every joint against its previous position relative to the body's motion, fit the torso
//! plane (or, without enough torso joints, take the azimuth from the shoulders; either way on
//! the side the decision chose), and feed the pose to the person's forecaster on its
//! fixed-rate grid. Everything is on the stack or sized at construction.

mod config;
mod observation;
mod occlusion;

pub use config::PersonConfig;
pub use observation::{Estimate, GridReport, Observation};
pub use occlusion::{FRONTAL_COSINE, PLAUSIBLE_WIDTH};

/// How far below the shoulders' midpoint the torso centre sits before the track has measured it
/// (half the shoulder-to-hip distance of an adult), in metres.
pub const SHOULDER_TO_CENTRE: f64 = 0.25;

/// The frame rate (Hz) the thesis' joint gate was set for: a track holds a replaced joint over
/// for at most `GateConfig::max_replacements` frames and at most as long as those frames last
/// at this rate (a joint held ten frames at 10 frames per second would stand still for a whole
/// second while the body moves on).
pub const GATE_RATE_HZ: f64 = 25.0;

/// Most horizons one [`Person::forecast`] call takes.
pub const MAX_HORIZONS: usize = 32;

/// Least length of the horizontal part of the reported torso plane's unit normal for its
/// heading to be confident: the plane leaning at most 60 degrees from upright. A torso bent
/// further (forward, back, lying) has a normal that stands nearly upright, and a small error of
/// the plane turns its azimuth by that error over the horizontal part's length: here more than
/// twice as far. Chosen on the scenes benchmark's development draws among 75, 60 and 45 degrees
/// (docs/benchmark_log.md, "people bent far from upright").
pub const MIN_CONFIDENT_UPRIGHTNESS: f64 = 0.5;

use crate::coco::{self, Joints, N_JOINTS, TORSO, TORSO_SIDES};
use crate::error::{Error, Result};
use crate::forecaster::Forecaster;
use crate::gating::{JointGate, JointStatus};
use crate::plane::{fit_torso_plane, shoulder_heading};
use crate::selfcheck::{SelfCheck, HORIZONS as CHECK_HORIZONS};
use crate::sides::{Cues, Facing};
use crate::trend::Trend;
use crate::vec3::{add, finite, midpoint, sub};
use crate::{Pose, AZIMUTH, ELEVATION};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Refuses horizons that [`Person::forecast`] and [`Person::intervals`] would: more than
/// [`MAX_HORIZONS`], or one that is not a finite, non-negative number of seconds.
pub fn check_horizons(horizons: &[f64]) -> Result<()> {
    if horizons.len() > MAX_HORIZONS {
        return Err(Error::InvalidArgument {
            name: "horizons",
            expected: "at most MAX_HORIZONS (32) horizons per call",
            value: horizons.len() as f64,
        });
    }
    crate::forecaster::check_horizons(horizons)
}

/// One person's state across frames.
///
/// ```
/// use torso_core::coco::{self, N_JOINTS};
/// use torso_core::{Estimate, Person, PersonConfig};
/// let mut person = Person::new(PersonConfig::default()).unwrap();
/// let mut joints = [[f64::NAN; 3]; N_JOINTS];
/// joints[coco::LEFT_SHOULDER] = [2.0, -0.18, 1.4]; // facing the camera at the origin
/// joints[coco::RIGHT_SHOULDER] = [2.0, 0.18, 1.4];
/// joints[coco::LEFT_HIP] = [2.0, -0.12, 0.9];
/// joints[coco::RIGHT_HIP] = [2.0, 0.12, 0.9];
/// let scores = [0.9; N_JOINTS];
/// let seen = person.update(0.0, &joints, &scores, [0.0, 0.0, 1.2]).unwrap();
/// assert_eq!(seen.estimate, Estimate::Plane);
/// assert!(person.update(0.0, &joints, &scores, [0.0, 0.0, 1.2]).is_err()); // same time: refused
/// ```
#[derive(Clone, Debug)]
pub struct Person {
    config: PersonConfig,
    gate: JointGate,
    forecaster: Forecaster,
    last_t: Option<f64>,
    previous: Option<Joints>,
    /// Summed median displacement of the body since the track began: the gate works relative to it.
    body_motion: [f64; 3],
    /// Plane centre minus shoulder midpoint, learned while both are seen.
    centre_offset: Option<[f64; 3]>,
    /// Last pose, for the elevation that a shoulders-only frame holds.
    last_pose: Option<Pose>,
    /// Last pose reported, from which forecasts start: `last_pose`, or its heading held at the
    /// recent heading ([`Observation::heading_held`]).
    reported: Option<Pose>,
    /// Shoulder and hip widths learned in frontal and dorsal views ([`coco::TORSO_PAIRS`]).
    widths: [Option<f64>; 2],
    facing: Facing,
    check: Option<SelfCheck>,
    /// The line through the forecaster's history, while the history is as it was fitted to.
    trend: Option<Trend>,
    /// Room for the plain continuation of [`Person::forecast`]'s horizons.
    scratch: [Pose; MAX_HORIZONS],
}

impl Person {
    pub fn new(config: PersonConfig) -> Result<Self> {
        config.validate()?;
        Ok(Self {
            config,
            gate: JointGate::new(N_JOINTS, config.gate)?,
            forecaster: Forecaster::new(config.forecaster)?,
            last_t: None,
            previous: None,
            body_motion: [0.0; 3],
            centre_offset: None,
            last_pose: None,
            reported: None,
            widths: [None; 2],
            facing: Facing::default(),
            check: if config.self_check {
                Some(SelfCheck::new(config.forecaster.rate_hz)?)
            } else {
                None
            },
            trend: None,
            scratch: [[0.0; 5]; MAX_HORIZONS],
        })
    }

    pub fn config(&self) -> &PersonConfig {
        &self.config
    }

    /// Forgets everything, as a new person of the same configuration would, in place: a
    /// tracker reuses a dropped track's person for the next track without allocating.
    pub fn reset(&mut self) {
        self.gate.reset();
        self.forecaster.reset();
        self.last_t = None;
        self.previous = None;
        self.body_motion = [0.0; 3];
        self.centre_offset = None;
        self.last_pose = None;
        self.reported = None;
        self.widths = [None; 2];
        self.facing = Facing::default();
        self.trend = None;
        if let Some(check) = self.check.as_mut() {
            check.reset();
        }
    }

    /// The person's forecaster (its history, grid time and sample count).
    pub fn forecaster(&self) -> &Forecaster {
        &self.forecaster
    }

    /// The velocity over the ground (m/s, world x and y) of the walk the track's history holds
    /// ([`Trend::steady`]): where to look for a walker after frames unseen. `None` while the
    /// history is no steady walk, or has not been fitted (with `self_check` off it never is).
    pub fn walking_velocity(&self) -> Option<[f64; 2]> {
        let trend = self.trend.as_ref()?;
        trend.steady()[0].then_some([trend.rate[0], trend.rate[1]])
    }

    /// One frame at time `t` (s): `joints` in the world frame (NaN where missing), their detector
    /// `scores`, and where the camera is (for a new track's front/back decision). A time stamp
    /// that does not increase, or a non-finite camera position, is refused before any state
    /// changes.
    pub fn update(
        &mut self,
        t: f64,
        joints: &Joints,
        scores: &[f64; N_JOINTS],
        camera_position: [f64; 3],
    ) -> Result<Observation> {
        if !t.is_finite() {
            return Err(Error::NonFinite {
                name: "t",
                index: 0,
            });
        }
        coco::check_camera_position(camera_position)?;
        if let Some(previous) = self.last_t.filter(|&p| !(t > p)) {
            return Err(Error::TimeNotIncreasing { previous, got: t });
        }
        // A score is a probability; NaN means "not scored" and makes the keypoint missing below.
        if let Some(index) = scores
            .iter()
            .position(|s| !s.is_nan() && !(0.0..=1.0).contains(s))
        {
            return Err(Error::InvalidArgument {
                name: "scores",
                expected: "keypoint scores from 0 to 1 (NaN for a keypoint not scored)",
                value: scores[index],
            });
        }
        let step = self.last_t.map(|last| t - last);
        self.last_t = Some(t);

        // A NaN score makes its keypoint missing and weighs nothing, so that no later step (the
        // forecaster's weight) can fail after the track's state has changed.
        let mut joints = self.config.used_joints(joints, scores, camera_position);
        let mut scores = scores.map(|s| if s.is_finite() { s } else { 0.0 });
        let mut completed = self.complete_occluded(&mut joints, camera_position);
        let decision = labelled_heading(&joints)
            .map(|(labelled, centre)| {
                let cues = Cues::of(&joints, labelled, centre, &completed);
                self.facing.decide(t, &cues, &self.config.facing)
            })
            .unwrap_or_default();
        if decision.turned {
            self.turn_round();
        }
        let swapped = decision.exchange;
        if swapped {
            coco::swap_sides(&mut joints);
            coco::swap_sides(&mut scores);
            coco::swap_sides(&mut completed);
        }
        let status = self.gate(&mut joints, step);
        self.previous = Some(joints);

        // The plane through the joint centres, not the surface the depth camera saw; the cues
        // above compare joints as read, and the gate holds them so.
        let mut centres = joints;
        self.config.behind_surface(&mut centres, camera_position);
        let (mut pose, estimate, weight) = self.torso_pose(&centres, &status, &scores);
        if let Some(p) = pose.as_mut().filter(|p| self.facing.opposes(p[AZIMUTH])) {
            turn_pose_round(p);
        }
        // A plane far across the recent heading is reported (and forecast from) at the recent
        // heading; the track keeps it as fitted. Fed back (the last pose decides which joint's
        // depth the next frames complete), a held heading changed later frames' joints, and the
        // flips went one way on one development draw and the other way on the next.
        let held = pose.and_then(|p| self.facing.across_recent(p[AZIMUTH]));
        let reported = pose.map(|mut p| {
            if let Some(recent) = held {
                p[AZIMUTH] = recent;
            }
            p
        });
        let mut grid = GridReport::default();
        if let (Some(pose), Some(reported)) = (pose, reported) {
            // The forecaster's own slot rule decides, so that its update cannot refuse the
            // time stamp after this frame has changed the track.
            if self.forecaster.takes_time(t) {
                let report = self.forecaster.update(reported, t, weight)?;
                grid.filled = report.filled;
                grid.restarted = report.restarted;
                self.check_forecast(report.restarted);
            } else {
                grid.skipped = true;
            }
            self.last_pose = Some(pose);
            self.reported = Some(reported);
        }
        Ok(Observation {
            pose: reported.map(|mut p| {
                p[AZIMUTH] = wrap_angle(p[AZIMUTH]);
                p
            }),
            estimate,
            swapped,
            reoriented: decision.turned,
            facing_evidence: decision.evidence,
            heading_confident: decision.confident
                && reported.is_none_or(|p| p[ELEVATION].sin() >= MIN_CONFIDENT_UPRIGHTNESS),
            heading_held: held.is_some(),
            joints,
            completed,
            status,
            weight,
            grid,
        })
    }

    /// Forecasts `horizons[h]` seconds after the forecaster's last grid sample into `out[h]`,
    /// moved with the latest estimate (a frame between two grid slots is not taken, and holding
    /// still holds the latest estimate), azimuth wrapped to (-π, π]. `Ok(false)` (and `out`
    /// untouched) until the history holds enough samples.
    pub fn forecast(&mut self, horizons: &[f64], out: &mut [Pose]) -> Result<bool> {
        if self.forecaster.len() < self.forecaster.min_samples() {
            return Ok(false);
        }
        let (hold, _) = self
            .forecaster
            .sample(self.forecaster.len() - 1)
            .expect("not empty");
        match &mut self.check {
            None => self.forecaster.forecast(horizons, out)?,
            Some(check) => {
                check_horizons(horizons)?;
                for &h in horizons {
                    check.prepare(h);
                }
                let plain = &mut self.scratch[..horizons.len()];
                self.forecaster.forecast_both(horizons, out, plain)?;
                let trend = self.trend.unwrap_or_else(|| Trend::of(&self.forecaster));
                for ((pose, plain), h) in out.iter_mut().zip(plain.iter()).zip(horizons) {
                    let w = check.weights(*h);
                    let velocity = trend.continued(&hold, *h);
                    for c in 0..5 {
                        pose[c] = w[c][0] * hold[c]
                            + w[c][1] * pose[c]
                            + w[c][2] * plain[c]
                            + w[c][3] * velocity[c];
                    }
                }
            }
        }
        // The forecaster's last sample may be older than the latest estimate (a frame between
        // two grid slots is not taken): every candidate moves with it, so that holding still
        // holds the latest estimate.
        let latest = self.reported.unwrap_or(hold);
        let mut offset: Pose = std::array::from_fn(|c| latest[c] - hold[c]);
        offset[AZIMUTH] = wrap_angle(offset[AZIMUTH]);
        for pose in out.iter_mut() {
            for (value, shift) in pose.iter_mut().zip(offset) {
                *value += shift;
            }
            pose[AZIMUTH] = wrap_angle(pose[AZIMUTH]);
        }
        Ok(true)
    }

    /// Half-widths of the central 80 % intervals around [`forecast`](Self::forecast)'s poses at
    /// `horizons`, per component, into `out`: the spread of the track's own recent forecast
    /// errors, times the multiple of it that covered 80 % of them, times how much further the
    /// truth lies than the track's own estimates
    /// ([`SelfCheck::half_width`](crate::selfcheck::SelfCheck::half_width)); before the track
    /// has checked a forecast, what the line through its history says a forecast may err
    /// ([`SelfCheck::unchecked_half_width`]); an angle's at most half a turn. `Ok(false)` (and
    /// `out` untouched) while the history is too short for a line, or without the self-check.
    pub fn intervals(&self, horizons: &[f64], out: &mut [Pose]) -> Result<bool> {
        if out.len() != horizons.len() {
            return Err(Error::LengthMismatch {
                name: "out",
                expected: horizons.len(),
                got: out.len(),
            });
        }
        check_horizons(horizons)?;
        let Some(check) = &self.check else {
            return Ok(false);
        };
        if horizons.iter().all(|&h| check.has_spread(h)) {
            for (h, o) in horizons.iter().zip(out.iter_mut()) {
                *o = check.half_width(*h).expect("has_spread said so");
            }
            return Ok(true);
        }
        // Nothing checked yet: what the line through the history says, where it says something
        // finite (absurd coordinates can overflow it); every horizon's before any is written, so
        // that a refusal leaves `out` untouched.
        let trend = self.trend.unwrap_or_else(|| Trend::of(&self.forecaster));
        let mut widths = [[0.0; 5]; MAX_HORIZONS];
        for (&h, w) in horizons.iter().zip(widths.iter_mut()) {
            match check.unchecked_half_width(&trend, h) {
                Some(width) if width.iter().all(|v| v.is_finite()) => *w = width,
                _ => return Ok(false),
            }
        }
        out.copy_from_slice(&widths[..horizons.len()]);
        Ok(true)
    }

    /// Scores the track's earlier forecasts against the sample just taken and records the next
    /// one ([`crate::selfcheck`]).
    fn check_forecast(&mut self, restarted: bool) {
        let Some(check) = self.check.as_mut() else {
            return;
        };
        // The history a gap restarted is gone, and so are the predictions made from it; the
        // scores stay, forgotten with time as ever: they are of the same person and detector.
        if restarted {
            check.drop_pending();
        }
        let n = self.forecaster.len();
        let (Some(t), Some((sample, _))) =
            (self.forecaster.last_time(), self.forecaster.sample(n - 1))
        else {
            return;
        };
        let trend = Trend::of(&self.forecaster);
        self.trend = Some(trend);
        let (mut damped, mut plain) = ([[0.0; 5]; 3], [[0.0; 5]; 3]);
        // Too short a history (or any refusal) leaves nothing to record this time.
        if self
            .forecaster
            .forecast_both(&CHECK_HORIZONS, &mut damped, &mut plain)
            .is_ok()
        {
            let velocity = CHECK_HORIZONS.map(|h| trend.continued(&sample, h));
            // Recorded with the mix the track's last forecast gave, then told what moves now.
            check.record(t, sample, &damped, &plain, &velocity);
            check.set_trend(&trend);
        }
    }

    /// The track had been facing the wrong way: what it remembers of the body's sides is turned
    /// round (the last joints, the gate's memory, the last pose and the forecaster's history),
    /// so that the new heading continues from it.
    fn turn_round(&mut self) {
        if let Some(previous) = self.previous.as_mut() {
            coco::swap_sides(previous);
        }
        for (l, r) in coco::LEFT_RIGHT_PAIRS {
            self.gate.swap(l, r).expect("COCO pairs are gate indices");
        }
        for pose in [&mut self.last_pose, &mut self.reported]
            .into_iter()
            .flatten()
        {
            turn_pose_round(pose);
        }
        self.forecaster.flip();
        self.trend = None;
        if let Some(check) = self.check.as_mut() {
            check.drop_pending();
        }
    }
    /// The gate applied to the joints' motion relative to the body's: at 1.3 m/s and 30 frames
    /// per second every joint of a walker moves 4 cm a frame, and an absolute gate holds a
    /// rejected joint still while the body walks away from it until it is lost. The body's
    /// motion is the median displacement of the joints seen in this frame and the last, robust
    /// to the one joint that jumps and unaffected by which joints happen to be seen. At a low
    /// frame rate a joint is held over for fewer frames ([`GATE_RATE_HZ`]; `frame_step`, seconds
    /// since the last frame, is `None` on a track's first).
    fn gate(&mut self, joints: &mut Joints, frame_step: Option<f64>) -> [JointStatus; N_JOINTS] {
        if let Some(step) = self.previous.as_ref().and_then(|p| median_step(joints, p)) {
            for k in 0..3 {
                self.body_motion[k] += step[k];
            }
        }
        for x in joints.iter_mut() {
            *x = sub(*x, self.body_motion);
        }
        let mut status = [JointStatus::Lost; N_JOINTS];
        let frames = self.config.gate.max_replacements;
        let held = frame_step.map_or(frames, |dt| {
            ((f64::from(frames) / GATE_RATE_HZ / dt).round().max(1.0) as u32).min(frames)
        });
        self.gate
            .update_holding(joints, &mut status, held)
            .expect("the gate was built for N_JOINTS joints");
        for x in joints.iter_mut() {
            *x = add(*x, self.body_motion);
        }
        status
    }

    /// The plane where three torso joints are usable, else the shoulder heading.
    fn torso_pose(
        &mut self,
        joints: &Joints,
        status: &[JointStatus; N_JOINTS],
        scores: &[f64; N_JOINTS],
    ) -> (Option<Pose>, Estimate, f64) {
        let points = TORSO.map(|i| joints[i]);
        // Replaced joints are last frame's positions: they count, at half weight.
        let weights = TORSO.map(|i| {
            let w = if status[i] == JointStatus::Measured {
                scores[i]
            } else {
                0.5 * scores[i]
            };
            if finite(&joints[i]) && w.is_finite() {
                w.max(0.0)
            } else {
                0.0
            }
        });
        let [left, right] = [points[0], points[1]];
        let shoulders_seen = finite(&left) && finite(&right);
        if let Ok(plane) = fit_torso_plane(&points, &TORSO_SIDES, Some(&weights)) {
            if shoulders_seen && finite(&points[2]) && finite(&points[3]) {
                self.centre_offset = Some(sub(plane.centre, midpoint(left, right)));
            }
            let used = weights.iter().filter(|&&w| w > 0.0);
            let mean = used.clone().sum::<f64>() / used.count() as f64;
            let [x, y, z] = plane.centre;
            return (
                Some([x, y, z, plane.azimuth, plane.elevation]),
                Estimate::Plane,
                mean,
            );
        }
        if !shoulders_seen {
            return (None, Estimate::None, 0.0);
        }
        let Ok(heading) = shoulder_heading(left, right) else {
            return (None, Estimate::None, 0.0);
        };
        let offset = self
            .centre_offset
            .unwrap_or([0.0, 0.0, -SHOULDER_TO_CENTRE]);
        let elevation = self.last_pose.map_or(FRAC_PI_2, |p| p[ELEVATION]);
        let [x, y, z] = add(heading.centre, offset);
        (
            Some([x, y, z, heading.azimuth, elevation]),
            Estimate::Shoulders,
            0.5 * (weights[0] + weights[1]),
        )
    }
}

/// Azimuth and centre of the torso plane through the seen torso joints as labelled, or of the
/// shoulder line where fewer than three are seen; `None` where neither can be had.
fn labelled_heading(joints: &Joints) -> Option<(f64, [f64; 3])> {
    let torso = TORSO.map(|i| joints[i]);
    if let Ok(plane) = fit_torso_plane(&torso, &TORSO_SIDES, None) {
        return Some((plane.azimuth, plane.centre));
    }
    let [left, right] = [torso[0], torso[1]];
    shoulder_heading(left, right)
        .ok()
        .map(|h| (h.azimuth, h.centre))
}

/// The same torso plane with its normal the other way: the chest where the back was.
fn turn_pose_round(pose: &mut Pose) {
    pose[AZIMUTH] += PI;
    pose[ELEVATION] = PI - pose[ELEVATION];
}

/// Per-axis median displacement of the joints seen in both frames; `None` when there is none.
fn median_step(current: &Joints, previous: &Joints) -> Option<[f64; 3]> {
    let mut steps = [[0.0; N_JOINTS]; 3];
    let mut n = 0;
    for (x, p) in current.iter().zip(previous) {
        if finite(x) && finite(p) {
            for k in 0..3 {
                steps[k][n] = x[k] - p[k];
            }
            n += 1;
        }
    }
    (n > 0).then(|| steps.map(|mut axis| median(&mut axis[..n])))
}

/// Median of finite values, the mean of the middle two for an even count (as NumPy's).
fn median(values: &mut [f64]) -> f64 {
    values.sort_unstable_by(f64::total_cmp);
    let n = values.len();
    if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// An angle wrapped into (-π, π].
pub fn wrap_angle(angle: f64) -> f64 {
    let wrapped = angle - TAU * (angle / TAU).round();
    if wrapped <= -PI {
        wrapped + TAU
    } else {
        wrapped
    }
}

#[cfg(test)]
mod tests {
    use super::occlusion::behind_on_ray;
    use super::*;
    use crate::coco::{LEFT_HIP, LEFT_SHOULDER, NOSE, RIGHT_HIP, RIGHT_SHOULDER};
    use crate::sides::FacingConfig;
    use crate::stray::drop_stray;
    use crate::vec3::{distance, dot, norm};
    use crate::{ForecasterConfig, GateConfig, HEIGHT};

    const CAMERA: [f64; 3] = [0.0; 3];

    /// An upright person at `c` facing azimuth `yaw`, with a visible face when facing the camera
    /// at the origin.
    /// The joints these tests build are joint centres, not a depth camera's surface points.
    fn centres_given() -> PersonConfig {
        PersonConfig {
            surface_depth: [0.0; 2],
            ..PersonConfig::default()
        }
    }

    fn person(c: [f64; 3], yaw: f64, hips: bool) -> (Joints, [f64; N_JOINTS]) {
        let (s, co) = yaw.sin_cos();
        let at = |side: f64, up: f64, fwd: f64| {
            [
                c[0] - side * s + fwd * co,
                c[1] + side * co + fwd * s,
                c[2] + up,
            ]
        };
        let mut joints = [[f64::NAN; 3]; N_JOINTS];
        let mut scores = [0.0; N_JOINTS];
        joints[LEFT_SHOULDER] = at(0.2, 0.25, 0.0);
        joints[RIGHT_SHOULDER] = at(-0.2, 0.25, 0.0);
        joints[NOSE] = at(0.0, 0.55, 0.1);
        for i in [LEFT_SHOULDER, RIGHT_SHOULDER] {
            scores[i] = 0.9;
        }
        if hips {
            joints[LEFT_HIP] = at(0.12, -0.25, 0.0);
            joints[RIGHT_HIP] = at(-0.12, -0.25, 0.0);
            scores[LEFT_HIP] = 0.9;
            scores[RIGHT_HIP] = 0.9;
        }
        let faces_camera = co * (CAMERA[0] - c[0]) + s * (CAMERA[1] - c[1]) > 0.0;
        scores[NOSE] = if faces_camera { 0.9 } else { 0.05 };
        (joints, scores)
    }

    fn angle_error(a: f64, b: f64) -> f64 {
        wrap_angle(a - b).abs()
    }

    #[test]
    fn the_reported_plane_takes_the_side_the_track_decided() {
        // A person turning at 50 degrees per second whose torso joints jump by up to 0.4 m in
        // half the frames: the gate replaces the jumps with earlier positions, and the plane
        // through old and new joints can have its sides the other way round from the frame's
        // own (in 19 of 1500 frames here before the side became the decision's). The reported
        // azimuth never points away from the track's heading along the same torso line: the
        // heading is the frame's labelled plane's normal (after the stray joints are dropped,
        // as the track does), turned where the track exchanged the labels.
        let config = PersonConfig {
            occlusion_ratio: 0.0,
            ..centres_given()
        };
        let mut track = Person::new(config).unwrap();
        let mut seed = 7_u64;
        let mut uniform = || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut checked = 0;
        for k in 0..1500 {
            let yaw = (2.0 * k as f64).to_radians();
            let (mut joints, scores) = person([3.0, 0.5, 1.0], yaw, true);
            for &i in &TORSO {
                if uniform() < 0.5 {
                    for v in joints[i].iter_mut().take(2) {
                        *v += 0.8 * (uniform() - 0.5);
                    }
                }
            }
            let obs = track
                .update(k as f64 / 25.0, &joints, &scores, CAMERA)
                .unwrap();
            drop_stray(&mut joints, CAMERA);
            let (Some(pose), Some((labelled, _))) = (obs.pose, labelled_heading(&joints)) else {
                continue;
            };
            let heading = if obs.swapped { labelled + PI } else { labelled };
            let along = (pose[AZIMUTH] - heading).cos();
            assert!(
                along >= -std::f64::consts::FRAC_1_SQRT_2 - 1e-9,
                "frame {k}: {along}"
            );
            checked += 1;
        }
        assert!(checked > 1400);
    }

    #[test]
    fn a_torso_bent_far_from_upright_keeps_its_heading_but_not_its_confidence() {
        // Facing the camera with the face in view for a second and a half: confident. Then the
        // torso bends forward about the hips, a degree per frame, to 80 degrees and stays: the
        // heading and the evidence hold, and the heading is confident until the plane leans
        // past 60 degrees from upright.
        let mut track = Person::new(centres_given()).unwrap();
        let centre = [2.0, 0.0, 1.0];
        let hips = centre[2] - 0.25;
        for k in 0..120_u32 {
            let bend = f64::from(k.saturating_sub(40).min(80)).to_radians();
            let (mut joints, scores) = person(centre, PI, true);
            for i in [LEFT_SHOULDER, RIGHT_SHOULDER, NOSE] {
                // About the hips' line, towards the camera (the person faces -x).
                let (up, forward) = (joints[i][2] - hips, centre[0] - joints[i][0]);
                let (s, c) = bend.sin_cos();
                joints[i][2] = hips + up * c - forward * s;
                joints[i][0] = centre[0] - (up * s + forward * c);
            }
            let obs = track
                .update(k as f64 / 25.0, &joints, &scores, CAMERA)
                .unwrap();
            let pose = obs.pose.unwrap();
            // Bent past about 50 degrees, a shoulder lies further from the other torso joints
            // than the stray rule allows, and the gate holds it where it was last seen: the
            // plane turns, the side holds.
            assert!(angle_error(pose[AZIMUTH], PI) < PI / 4.0, "frame {k}");
            let leaning = (pose[ELEVATION] - FRAC_PI_2).abs();
            if k >= 30 {
                let expected = leaning < 60f64.to_radians() - 0.02;
                assert!(
                    obs.heading_confident == expected
                        || (leaning - 60f64.to_radians()).abs() < 0.02,
                    "frame {k}: leaning {} degrees, confident {}",
                    leaning.to_degrees(),
                    obs.heading_confident
                );
            }
            match k {
                60 | 85 => assert!(obs.heading_confident, "frame {k}"),
                119 => assert!(!obs.heading_confident && obs.facing_evidence > 1.0),
                _ => {}
            }
        }
    }

    #[test]
    fn a_plane_far_across_the_recent_heading_is_reported_at_the_recent_heading() {
        // Facing the camera for a second; then one frame whose torso comes out turned by 70
        // degrees (a gate wide enough to let it through, no depth completion), then facing the
        // camera again.
        let config = PersonConfig {
            occlusion_ratio: 0.0,
            gate: GateConfig {
                threshold: 1.0,
                ..GateConfig::default()
            },
            ..centres_given()
        };
        let mut track = Person::new(config).unwrap();
        let mut update = |k: usize, yaw: f64| {
            let (joints, scores) = person([3.0, 0.0, 1.0], yaw, true);
            track
                .update(k as f64 / 25.0, &joints, &scores, CAMERA)
                .unwrap()
        };
        for k in 0..25 {
            assert!(!update(k, PI).heading_held);
        }
        let bad = update(25, PI + 70f64.to_radians());
        let reported = bad.pose.unwrap()[AZIMUTH];
        assert!(bad.heading_held);
        assert!(angle_error(reported, PI) < 20f64.to_radians(), "{reported}");
        let again = update(26, PI);
        assert!(!again.heading_held);
        assert!(angle_error(again.pose.unwrap()[AZIMUTH], PI) < 1e-9);
        // A forecast holding the heading still holds the reported one.
        let (mut track, mut out) = (Person::new(config).unwrap(), [[0.0; 5]; 1]);
        for k in 0..26 {
            let yaw = if k == 25 { PI + 70f64.to_radians() } else { PI };
            let (joints, scores) = person([3.0, 0.0, 1.0], yaw, true);
            let seen = track
                .update(k as f64 / 25.0, &joints, &scores, CAMERA)
                .unwrap();
            if k == 25 {
                assert!(track.forecast(&[0.4], &mut out).unwrap());
                assert!(angle_error(out[0][AZIMUTH], seen.pose.unwrap()[AZIMUTH]) < 1e-9);
            }
        }
    }

    #[test]
    fn a_turning_person_labelled_right_keeps_the_labels_and_a_short_swap_is_undone() {
        let mut track = Person::new(centres_given()).unwrap();
        for k in 0..90 {
            let yaw = PI + (4.0 * k as f64).to_radians();
            let (mut joints, mut scores) = person([2.0, 0.0, 1.0], yaw, true);
            // The detector exchanges the sides for three frames (0.12 s) in the back view.
            let swap = (45..48).contains(&k);
            if swap {
                coco::swap_sides(&mut joints);
                coco::swap_sides(&mut scores);
            }
            let obs = track
                .update(k as f64 / 25.0, &joints, &scores, CAMERA)
                .unwrap();
            assert_eq!(obs.estimate, Estimate::Plane);
            assert_eq!(obs.swapped, swap, "frame {k}");
            assert!(!obs.reoriented);
            let pose = obs.pose.unwrap();
            assert!(angle_error(pose[AZIMUTH], yaw) < 1e-9, "frame {k}");
            assert!((pose[ELEVATION] - FRAC_PI_2).abs() < 1e-9);
            assert!(pose[AZIMUTH] > -PI && pose[AZIMUTH] <= PI);
        }
    }

    #[test]
    fn a_new_track_takes_the_labels_even_from_behind() {
        let (joints, scores) = person([2.0, 0.5, 1.0], 0.2, true); // back to the camera
        let mut track = Person::new(centres_given()).unwrap();
        let obs = track.update(0.0, &joints, &scores, CAMERA).unwrap();
        assert!(!obs.swapped && angle_error(obs.pose.unwrap()[AZIMUTH], 0.2) < 1e-9);
    }

    #[test]
    fn a_track_born_the_wrong_way_turns_round_with_its_history() {
        // Born from exchanged labels while walking towards +y and facing it; then labelled
        // right, with the nose in front: the cues turn the track round, history included.
        let mut track = Person::new(centres_given()).unwrap();
        let mut turned = 0;
        for k in 0..40 {
            let t = k as f64 / 25.0;
            let (mut joints, mut scores) = person([2.0, 0.4 * t, 1.0], FRAC_PI_2, true);
            if k < 5 {
                coco::swap_sides(&mut joints);
                coco::swap_sides(&mut scores);
                scores[NOSE] = 0.0;
            }
            let obs = track.update(t, &joints, &scores, CAMERA).unwrap();
            turned += usize::from(obs.reoriented);
            let pose = obs.pose.unwrap();
            let want = if turned > 0 { FRAC_PI_2 } else { -FRAC_PI_2 };
            assert!(angle_error(pose[AZIMUTH], want) < 1e-9, "frame {k}");
        }
        assert_eq!(turned, 1);
        let f = track.forecaster();
        for i in 0..f.len() {
            let (pose, _) = f.sample(i).unwrap();
            assert!(angle_error(pose[AZIMUTH], FRAC_PI_2) < 1e-9, "sample {i}");
            assert!((pose[ELEVATION] - FRAC_PI_2).abs() < 1e-9);
            if i > 0 {
                let (before, _) = f.sample(i - 1).unwrap();
                assert!((pose[AZIMUTH] - before[AZIMUTH]).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn a_walk_is_continued_over_the_ground_and_its_height_held() {
        // Walking to +y at 1 m/s while sinking at 0.3 m/s (sitting down in stride), seen for
        // less than the shortest checked horizon, so that nothing but the history's line says
        // what moves: one second ahead the walk goes on, the torso's height stays where it is
        // (a body sinks only so far; its own later checks may still let a trend in).
        let mut track = Person::new(centres_given()).unwrap();
        let mut last = [0.0; 5];
        for k in 0..8 {
            let t = k as f64 / 25.0;
            let (joints, scores) = person([2.0, t, 1.0 - 0.3 * t], FRAC_PI_2, true);
            let obs = track.update(t, &joints, &scores, CAMERA).unwrap();
            last = obs.pose.unwrap();
        }
        let mut ahead = [[0.0; 5]];
        assert!(track.forecast(&[1.0], &mut ahead).unwrap());
        assert!((ahead[0][1] - (last[1] + 1.0)).abs() < 1e-6);
        assert!((ahead[0][HEIGHT] - last[HEIGHT]).abs() < 1e-9);
    }

    #[test]
    fn a_track_found_again_after_a_gap_keeps_the_record_of_its_forecasts() {
        // Turning on the spot at 0.8 rad/s, seen for 3 s at 25 frames per second, unseen for
        // 0.6 s (beyond the forecaster's 0.4 s gap: its history starts again), then seen for
        // 0.6 s more, turning on from where it was last seen. A track that saw the whole turn
        // knows its forecasts of the turn came true and continues it 2 s ahead; a new track
        // that saw only the last 0.6 s has not seen its turn's forecasts come true and holds it
        // there.
        let rate = 0.8;
        let frame = |t: f64| person([2.0, 0.0, 1.0], rate * t.min(3.0).max(t - 0.6), true);
        let mut found_again = Person::new(centres_given()).unwrap();
        let mut new = Person::new(centres_given()).unwrap();
        let mut restarted = 0;
        for k in (0..=75).chain(90..=105) {
            let t = k as f64 / 25.0;
            let (joints, scores) = frame(t);
            let obs = found_again.update(t, &joints, &scores, CAMERA).unwrap();
            restarted += usize::from(obs.grid.restarted);
            if k >= 90 {
                new.update(t, &joints, &scores, CAMERA).unwrap();
            }
        }
        assert_eq!(restarted, 1);
        let now = rate * (105.0 / 25.0 - 0.6);
        let (mut kept, mut fresh) = ([[0.0; 5]], [[0.0; 5]]);
        assert!(found_again.forecast(&[2.0], &mut kept).unwrap());
        assert!(new.forecast(&[2.0], &mut fresh).unwrap());
        assert!(angle_error(kept[0][AZIMUTH], now + 2.0 * rate) < 0.1);
        assert!(angle_error(fresh[0][AZIMUTH], now) < 0.1);
    }

    #[test]
    fn without_hips_the_shoulders_give_the_azimuth_and_the_learned_centre() {
        let mut track = Person::new(PersonConfig::default()).unwrap();
        let (first, scores) = person([2.0, 0.0, 1.0], 2.5, true);
        track.update(0.0, &first, &scores, CAMERA).unwrap();
        let (second, scores) = person([2.02, 0.0, 1.0], 2.6, false);
        let obs = track.update(0.04, &second, &scores, CAMERA).unwrap();
        assert_eq!(obs.estimate, Estimate::Shoulders);
        let pose = obs.pose.unwrap();
        // The shoulders' midpoint plus where the centre sat from it in the first frame, both
        // from the joint centres behind the surface; the azimuth is their line's.
        let centres = |mut joints: Joints| {
            track.config().behind_surface(&mut joints, CAMERA);
            let shoulders = midpoint(joints[LEFT_SHOULDER], joints[RIGHT_SHOULDER]);
            let hips = midpoint(joints[LEFT_HIP], joints[RIGHT_HIP]);
            let line = sub(joints[LEFT_SHOULDER], joints[RIGHT_SHOULDER]);
            (
                shoulders,
                midpoint(shoulders, hips),
                (-line[0]).atan2(line[1]),
            )
        };
        // The second frame's joints as the track worked with them: the gate holds the first
        // frame's hips over (they weigh nothing without a score, but they are there).
        let ((shoulders, centre, _), (now, _, azimuth)) = (centres(first), centres(obs.joints));
        assert!(angle_error(pose[AZIMUTH], azimuth) < 1e-9 && angle_error(azimuth, 2.6) < 0.01);
        let want = add(now, sub(centre, shoulders));
        for (got, want) in pose[..3].iter().zip(want) {
            assert!((got - want).abs() < 1e-9);
        }
    }

    #[test]
    fn the_plane_is_fitted_through_the_joint_centres_behind_the_surface() {
        let (joints, scores) = person([3.0, 1.0, 1.0], PI, true);
        let depths = [0.06, 0.09];
        let config = PersonConfig {
            surface_depth: depths,
            ..PersonConfig::default()
        };
        let pose = Person::new(config)
            .unwrap()
            .update(0.0, &joints, &scores, CAMERA)
            .unwrap()
            .pose
            .unwrap();
        // By hand: each torso joint moved away from the camera along the ray to the four's
        // mean, the shoulders by the first depth and the hips by the second; the plane through
        // those.
        let seen = TORSO.map(|i| joints[i]);
        let mean = seen
            .iter()
            .fold([0.0; 3], |m, p| add(m, p.map(|v| v / 4.0)));
        let ray = sub(mean, CAMERA);
        let along = ray.map(|v| v / norm(ray));
        let moved: [[f64; 3]; 4] =
            std::array::from_fn(|k| add(seen[k], along.map(|v| v * depths[k / 2])));
        let plane = fit_torso_plane(&moved, &TORSO_SIDES, None).unwrap();
        for (got, want) in pose[..3].iter().zip(plane.centre) {
            assert!((got - want).abs() < 1e-9);
        }
        assert!(angle_error(pose[AZIMUTH], plane.azimuth) < 1e-9);
        assert!((pose[ELEVATION] - plane.elevation).abs() < 1e-9);
        // Facing the camera, the hips moved back further than the shoulders lean the plane's
        // top towards it: the chest's normal points down (on the surface it was level).
        assert!(plane.elevation > FRAC_PI_2 + 1e-3);
    }

    #[test]
    fn a_joint_no_longer_seen_is_held_over_no_longer_at_a_low_frame_rate() {
        // The default holds a joint over ten frames and at most 0.4 s (ten frames at 25 Hz):
        // 4 frames at 10 frames per second, 6 at 15, 10 at 25 and at 30.
        for (rate, held) in [(10.0, 4), (15.0, 6), (25.0, 10), (30.0, 10)] {
            let mut track = Person::new(centres_given()).unwrap();
            let (joints, scores) = person([3.0, 0.0, 1.0], PI, true);
            let mut statuses = Vec::new();
            for k in 0..20 {
                let mut frame = joints;
                if k >= 5 {
                    frame[LEFT_HIP] = [f64::NAN; 3];
                }
                let obs = track
                    .update(k as f64 / rate, &frame, &scores, CAMERA)
                    .unwrap();
                statuses.push(obs.status[LEFT_HIP]);
            }
            let replaced = statuses
                .iter()
                .filter(|&&s| s == JointStatus::Replaced)
                .count();
            assert_eq!(replaced, held, "{rate} Hz");
            assert_eq!(statuses[5 + held], JointStatus::Lost, "{rate} Hz");
        }
    }

    #[test]
    fn a_walker_at_30_fps_keeps_every_joint_and_a_jumping_joint_is_replaced() {
        // 1.5 m/s is 5 cm a frame: within an absolute 10 cm gate, but a joint replaced once would
        // then fall further behind every frame. Relative to the body it never does.
        let config = PersonConfig {
            gate: GateConfig {
                threshold: 0.04,
                max_replacements: 10,
            },
            ..centres_given()
        };
        let mut track = Person::new(config).unwrap();
        for k in 0..60 {
            let t = k as f64 / 30.0;
            let (mut joints, scores) = person([1.0 + 1.5 * t, 0.0, 1.0], 0.0, true);
            if k == 30 {
                joints[LEFT_HIP][0] += 0.5; // a depth reading from the wall behind
            }
            let obs = track.update(t, &joints, &scores, CAMERA).unwrap();
            let expected = if k == 30 {
                JointStatus::Replaced
            } else {
                JointStatus::Measured
            };
            assert_eq!(obs.status[LEFT_HIP], expected, "frame {k}");
            assert_eq!(obs.status[LEFT_SHOULDER], JointStatus::Measured);
            // The replaced hip moves with the body: it is last frame's hip plus the body's step.
            let want = person([1.0 + 1.5 * t, 0.0, 1.0], 0.0, true).0[LEFT_HIP];
            assert!(distance(obs.joints[LEFT_HIP], want) < 1e-9, "frame {k}");
        }
    }

    #[test]
    fn frames_faster_than_the_grid_are_skipped_and_gaps_filled() {
        let mut track = Person::new(centres_given()).unwrap();
        let (joints, scores) = person([2.0, 0.0, 1.0], 3.0, true);
        let grids: Vec<GridReport> = [0.0, 1.0 / 30.0, 2.0 / 30.0, 0.1, 4.0 / 30.0, 0.28]
            .iter()
            .map(|&t| track.update(t, &joints, &scores, CAMERA).unwrap().grid)
            .collect();
        let skipped: Vec<bool> = grids.iter().map(|g| g.skipped).collect();
        assert_eq!(skipped, [false, false, false, false, true, false]);
        assert_eq!(grids[5].filled, 3);
        assert_eq!(track.forecaster().len(), 8);
        let mut out = [[0.0; 5]; 1];
        assert!(track.forecast(&[0.4], &mut out).unwrap());
        assert!(angle_error(out[0][AZIMUTH], 3.0) < 1e-6);
    }

    #[test]
    fn every_frame_of_common_camera_rates_is_taken() {
        // Time stamps k / fps land on grid slot boundaries (0.7 s at 10 fps is 17.5 steps of
        // the 25 Hz grid) where a skip test and the grid's rounding can disagree: the frame
        // must then be skipped, not refused after the track has changed.
        let (joints, scores) = person([2.0, 0.0, 1.0], 3.0, true);
        for fps in [10.0, 15.0, 20.0, 24.0, 30.0, 50.0, 60.0] {
            let mut track = Person::new(centres_given()).unwrap();
            for k in 0..600 {
                let t = k as f64 / fps;
                track.update(t, &joints, &scores, CAMERA).unwrap();
            }
        }
    }

    #[test]
    fn bad_frames_are_refused_and_leave_the_track_alone() {
        let mut track = Person::new(centres_given()).unwrap();
        let (joints, scores) = person([2.0, 0.0, 1.0], 3.0, true);
        track.update(0.0, &joints, &scores, CAMERA).unwrap();
        let before = track.clone();
        for (t, camera) in [
            (0.0, CAMERA),
            (-1.0, CAMERA),
            (f64::NAN, CAMERA),
            (0.04, [f64::INFINITY, 0.0, 0.0]),
        ] {
            assert!(track.update(t, &joints, &scores, camera).is_err());
        }
        // Debug output compares NaN joints equal, which `==` would not.
        assert_eq!(format!("{track:?}"), format!("{before:?}"));
        assert_eq!(track.forecaster().len(), 1);
        // No torso seen yet: no pose, nothing for the forecaster, so no forecast.
        let mut fresh = Person::new(centres_given()).unwrap();
        let obs = fresh
            .update(0.0, &[[f64::NAN; 3]; N_JOINTS], &[0.9; N_JOINTS], CAMERA)
            .unwrap();
        assert_eq!((obs.pose, obs.estimate), (None, Estimate::None));
        assert!(!fresh.forecast(&[0.4], &mut [[0.0; 5]]).unwrap());
        let bad = PersonConfig {
            facing: FacingConfig {
                memory: 0.0,
                ..FacingConfig::default()
            },
            ..centres_given()
        };
        assert!(Person::new(bad).is_err());
    }

    /// The far joint of each pair seen at the depth of the near one, along its own camera ray:
    /// what a depth camera reports when the body hides the far shoulder and hip.
    fn occlude_far_side(joints: &mut Joints, yaw: f64) {
        let left_is_near = -yaw.sin() * -2.0 > 0.0; // left · (camera - centre), person at x = 2
        for (l, r) in coco::TORSO_PAIRS {
            let (near, far) = if left_is_near { (l, r) } else { (r, l) };
            let scale = joints[near][0] / joints[far][0]; // camera at the origin looking along +x
            joints[far] = joints[far].map(|v| v * scale);
        }
    }

    #[test]
    fn profile_views_get_the_far_joints_depth_back_from_the_learned_widths() {
        let run = |occlusion_ratio: f64| {
            let config = PersonConfig {
                occlusion_ratio,
                ..centres_given()
            };
            let mut track = Person::new(config).unwrap();
            let mut worst: f64 = 0.0;
            for k in 0..45 {
                // Facing the camera, then turning left through a profile view at 2 degrees a frame.
                let yaw = PI + (2.0 * k as f64).to_radians();
                let (mut joints, scores) = person([2.0, 0.0, 1.0], yaw, true);
                if yaw.cos().abs() < 0.6 {
                    occlude_far_side(&mut joints, yaw);
                }
                let obs = track
                    .update(k as f64 / 25.0, &joints, &scores, CAMERA)
                    .unwrap();
                let profile = yaw.cos().abs() < 0.6;
                assert!(occlusion_ratio == 0.0 || obs.completed.iter().any(|&c| c) == profile);
                // Without the correction the far joints are gated out, then lost: no pose at all.
                let error = obs.pose.map_or(PI, |p| angle_error(p[AZIMUTH], yaw));
                worst = worst.max(error);
            }
            worst.to_degrees()
        };
        // Without the correction the shortened pairs turn the plane by tens of degrees; with it
        // the far joints land where they are (the widths were learned exactly).
        assert!(run(0.0) > 10.0, "{}", run(0.0));
        assert!(run(0.8) < 1e-6, "{}", run(0.8));
    }

    #[test]
    fn a_profile_views_completed_pairs_do_not_confirm_the_heading() {
        // Facing the camera, then turning left into a profile view and staying there, the face
        // out of view. Each far joint, read at the near side's depth, is moved back on the side
        // the last pose turned away, so the labelled plane faces where the last pose did
        // whatever the labels say: those labels do not vote, and the evidence of the frontal
        // frames fades instead of being built up again by the track agreeing with itself (to
        // about a second's worth, what the labels alone build).
        let mut track = Person::new(centres_given()).unwrap();
        let mut last = None;
        for k in 0..100 {
            let yaw = PI + (2.0 * k.min(45) as f64).to_radians();
            let (mut joints, mut scores) = person([2.0, 0.0, 1.0], yaw, true);
            let profile = yaw.cos().abs() < 0.6;
            if profile {
                occlude_far_side(&mut joints, yaw);
                scores[NOSE] = 0.0; // no other cue
            }
            let obs = track
                .update(k as f64 / 25.0, &joints, &scores, CAMERA)
                .unwrap();
            assert_eq!(
                obs.completed.iter().filter(|&&c| c).count(),
                2 * usize::from(profile)
            );
            last = Some(obs);
        }
        let last = last.unwrap();
        assert!(last.facing_evidence < 0.25, "{}", last.facing_evidence);
        // With no vote the heading holds.
        let yaw = PI + 90f64.to_radians();
        assert!(angle_error(last.pose.unwrap()[AZIMUTH], yaw) < 1e-6);
    }

    #[test]
    fn the_far_joint_moves_back_along_its_ray_to_the_width() {
        let camera = [0.0, 0.0, 1.0];
        let near = [2.0, 0.1, 1.0];
        let seen = [2.0, -0.1, 1.0]; // as deep as the near one
        let moved = behind_on_ray(camera, seen, near, 0.35);
        assert!((distance(moved, near) - 0.35).abs() < 1e-12);
        let (ray, along) = (sub(seen, camera), sub(moved, camera));
        assert!(
            norm(along) > norm(ray)
                && (dot(ray, along) / norm(ray) / norm(along) - 1.0).abs() < 1e-12
        );
        // A ray that passes further than the width from the anchor leaves the point alone.
        assert_eq!(
            behind_on_ray(camera, [2.0, -1.0, 1.0], near, 0.35),
            [2.0, -1.0, 1.0]
        );
    }

    #[test]
    fn a_torso_joint_read_off_someone_in_front_is_dropped_and_a_broad_torso_is_not() {
        // Facing the camera 4 m away; the right shoulder's keypoint lands on a person 1.5 m
        // nearer the camera. With it the plane would turn by tens of degrees; dropped, the
        // other three give the azimuth exactly.
        let (mut joints, scores) = person([4.0, 0.0, 1.0], PI, true);
        joints[RIGHT_SHOULDER][0] -= 1.5;
        let mut probe = joints;
        assert_eq!(drop_stray(&mut probe, CAMERA), [false, true, false, false]);
        let obs = Person::new(centres_given())
            .unwrap()
            .update(0.0, &joints, &scores, CAMERA)
            .unwrap();
        assert_eq!(obs.estimate, Estimate::Plane);
        assert!(angle_error(obs.pose.unwrap()[AZIMUTH], PI) < 1e-9);
        // Shoulders 0.5 m and hips 0.35 m apart, in any view: nothing lies beyond the spread.
        for yaw in [0.0, 0.7, PI / 2.0, 2.5] {
            let (mut broad, _) = person([3.0, 1.0, 1.0], yaw, true);
            for (joint, scale) in [(LEFT_SHOULDER, 1.25), (RIGHT_SHOULDER, 1.25)]
                .into_iter()
                .chain([(LEFT_HIP, 35.0 / 24.0), (RIGHT_HIP, 35.0 / 24.0)])
            {
                for k in 0..2 {
                    let centre = [3.0, 1.0][k];
                    broad[joint][k] = centre + scale * (broad[joint][k] - centre);
                }
            }
            assert!(distance(broad[LEFT_SHOULDER], broad[RIGHT_SHOULDER]) > 0.49);
            assert_eq!(drop_stray(&mut broad, CAMERA), [false; 4], "yaw {yaw}");
        }
    }

    #[test]
    fn a_nan_score_makes_its_keypoint_missing_and_a_score_out_of_range_is_refused() {
        let mut track = Person::new(centres_given()).unwrap();
        let (joints, mut scores) = person([2.0, 0.0, 1.0], 3.0, true);
        scores[LEFT_HIP] = f64::NAN;
        let obs = track.update(0.0, &joints, &scores, CAMERA).unwrap();
        assert_eq!(obs.status[LEFT_HIP], JointStatus::Lost);
        assert!(obs.weight.is_finite() && angle_error(obs.pose.unwrap()[AZIMUTH], 3.0) < 1e-9);
        // A score of 5, 1e300 or infinity would become the forecaster's weight: refused, and the
        // track is as it was (the next frame at the same time is taken).
        let before = format!("{track:?}");
        for bad in [5.0, 1e300, f64::INFINITY, -0.1] {
            scores[LEFT_HIP] = bad;
            assert!(track.update(0.04, &joints, &scores, CAMERA).is_err());
            assert_eq!(format!("{track:?}"), before);
        }
        scores[LEFT_HIP] = 0.9;
        let obs = track.update(0.04, &joints, &scores, CAMERA).unwrap();
        assert!(obs.weight.is_finite() && obs.estimate == Estimate::Plane);
    }

    #[test]
    fn a_grid_too_fast_for_the_self_checks_predictions_is_refused_before_anything_is_allocated() {
        // A forecaster takes 10 MHz with a history short enough to fit its bound on samples; its
        // self-check would keep 20 million predictions per track (and at 1 GHz the process
        // aborted on the allocation).
        let fast = ForecasterConfig {
            rate_hz: 1e7,
            history: 1e-3,
            ..ForecasterConfig::constant_velocity(None)
        };
        assert!(fast.validate().is_ok());
        let config = PersonConfig {
            forecaster: fast,
            ..PersonConfig::default()
        };
        match Person::new(config) {
            Err(Error::InvalidArgument { name, value, .. }) => {
                assert_eq!((name, value), ("rate_hz", 1e7))
            }
            other => panic!("{other:?}"),
        }
        let unchecked = PersonConfig {
            self_check: false,
            ..config
        };
        assert!(Person::new(unchecked).is_ok());
        let fastest = PersonConfig {
            forecaster: ForecasterConfig {
                rate_hz: 50_000.0,
                history: 1.0,
                ..fast
            },
            ..config
        };
        assert!(Person::new(fastest).is_ok()); // 100000 predictions over 2 s: the bound
    }

    #[test]
    fn wrap_angle_lands_in_the_half_open_interval() {
        for (a, want) in [
            (PI, PI),
            (-PI, PI),
            (3.0 * PI, PI),
            (0.5, 0.5),
            (-7.0, -7.0 + TAU),
        ] {
            assert!((wrap_angle(a) - want).abs() < 1e-12, "{a}");
        }
    }
}
