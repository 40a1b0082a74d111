//! What a track is configured with.

use crate::coco::{Joints, N_JOINTS};
use crate::error::{Error, Result};
use crate::forecaster::ForecasterConfig;
use crate::gating::{GateConfig, JointGate};
use crate::sides::FacingConfig;

/// Per-person parameters.
///
/// ```
/// use torso_core::PersonConfig;
/// let config = PersonConfig { min_score: 0.5, ..PersonConfig::default() };
/// assert!(config.sees(0.6) && !config.sees(0.4) && !config.sees(f64::NAN));
/// assert!(PersonConfig { min_score: 2.0, ..config }.validate().is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PersonConfig {
    pub forecaster: ForecasterConfig,
    /// The gate's threshold applies to a joint's motion relative to the body's (see
    /// [`Person::update`](super::Person::update)). Thesis: 0.10 m at about 25 frames per second.
    /// A track holds a replaced joint over for at most `max_replacements` frames and at most as
    /// long as those last at that rate ([`GATE_RATE_HZ`](super::GATE_RATE_HZ); 0.4 s by default).
    pub gate: GateConfig,
    /// Keypoints scored below this are missing.
    pub min_score: f64,
    /// How the track decides which way the chest faces ([`crate::sides`]).
    pub facing: FacingConfig,
    /// The track checks its forecasts against its own later samples and mixes holding still,
    /// the damped trend and the plain trend by how well each came true ([`crate::selfcheck`]);
    /// `false` gives the forecaster's output as it is.
    pub self_check: bool,
    /// A shoulder or hip pair measured shorter than this fraction of its learned width has the
    /// depth of its far joint corrected (see [`Person::update`](super::Person::update)); 0 turns the correction off.
    pub occlusion_ratio: f64,
    /// How far (m) the torso's centre lies behind the body's surface along the camera's ray.
    /// Joints lifted from a depth image lie on the surface the camera sees, in front of the
    /// joint centres a torso pose is defined by, so the centre is moved back this far
    /// ([`behind_surface`](Self::behind_surface)); 0 for joints that are joint centres already
    /// (mocap, a skeleton tracker's). The default is the median of that offset on the scenes
    /// benchmark's development split (docs/benchmark.md), about half an adult torso's depth.
    pub surface_depth: f64,
}

/// [`PersonConfig::surface_depth`]'s default (m).
const SURFACE_DEPTH: f64 = 0.09;

/// Largest [`PersonConfig::surface_depth`] accepted (m): more than any torso's half depth.
const MAX_SURFACE_DEPTH: f64 = 0.3;

impl Default for PersonConfig {
    fn default() -> Self {
        Self {
            forecaster: ForecasterConfig::live(),
            gate: GateConfig::default(),
            min_score: 0.3,
            facing: FacingConfig::default(),
            self_check: true,
            occlusion_ratio: 0.8,
            surface_depth: SURFACE_DEPTH,
        }
    }
}

impl PersonConfig {
    /// Whether a keypoint scored `score` counts as seen: the one rule for every stage that
    /// masks keypoints (NaN, "not scored", is not seen).
    pub fn sees(&self, score: f64) -> bool {
        score >= self.min_score
    }

    /// Whether a lifted joint scored `score` counts: seen ([`sees`](Self::sees)) and within
    /// the range a pose may take ([`coco::usable`](crate::coco::usable); NaN is not).
    pub fn uses(&self, joint: &[f64; 3], score: f64) -> bool {
        self.sees(score) && crate::coco::usable(joint)
    }

    /// The joints a track works from, and the association places a detection by: those not
    /// counted ([`uses`](Self::uses)) missing (NaN), then the torso joints whose depth came off
    /// something else dropped ([`crate::stray`], seen from `camera`).
    ///
    /// ```
    /// use torso_core::coco::{N_JOINTS, LEFT_SHOULDER, RIGHT_SHOULDER, LEFT_HIP, RIGHT_HIP, NOSE};
    /// use torso_core::PersonConfig;
    /// let mut joints = [[f64::NAN; 3]; N_JOINTS];
    /// joints[NOSE] = [4.0, 0.0, 1.7];
    /// joints[LEFT_SHOULDER] = [1.0, -0.2, 1.4]; // the depth of someone 3 m nearer
    /// joints[RIGHT_SHOULDER] = [1.0, 0.2, 1.4];
    /// joints[LEFT_HIP] = [4.0, -0.12, 0.9];
    /// joints[RIGHT_HIP] = [4.0, 0.12, 0.9];
    /// let mut scores = [0.9; N_JOINTS];
    /// scores[NOSE] = 0.1; // below `min_score`
    /// let used = PersonConfig::default().used_joints(&joints, &scores, [0.0, 0.0, 1.0]);
    /// assert!(used[NOSE][0].is_nan() && used[LEFT_SHOULDER][0].is_nan());
    /// assert_eq!(used[LEFT_HIP], joints[LEFT_HIP]);
    /// ```
    pub fn used_joints(
        &self,
        joints: &Joints,
        scores: &[f64; N_JOINTS],
        camera: [f64; 3],
    ) -> Joints {
        let mut used = *joints;
        for (x, &s) in used.iter_mut().zip(scores) {
            if !self.uses(x, s) {
                *x = [f64::NAN; 3];
            }
        }
        crate::stray::drop_stray(&mut used, camera);
        used
    }

    /// `point`, seen on the body's surface from `camera`, moved [`surface_depth`](Self::surface_depth)
    /// further along the camera's ray: where the joint centres lie.
    ///
    /// ```
    /// use torso_core::PersonConfig;
    /// let config = PersonConfig { surface_depth: 0.1, ..PersonConfig::default() };
    /// let centre = config.behind_surface([3.0, 4.0, 1.0], [0.0, 0.0, 1.0]);
    /// assert!((centre[0] - 3.06).abs() < 1e-12 && (centre[1] - 4.08).abs() < 1e-12);
    /// ```
    pub fn behind_surface(&self, point: [f64; 3], camera: [f64; 3]) -> [f64; 3] {
        let ray = crate::vec3::sub(point, camera);
        let range = crate::vec3::norm(ray);
        if !(range > 0.0) {
            return point;
        }
        let scale = self.surface_depth / range;
        std::array::from_fn(|k| point[k] + scale * ray[k])
    }

    /// Checks every field, as [`Person::new`](super::Person::new) does.
    pub fn validate(&self) -> Result<()> {
        self.forecaster.validate()?;
        JointGate::new(N_JOINTS, self.gate)?;
        if !(0.0..=1.0).contains(&self.min_score) {
            return Err(Error::InvalidArgument {
                name: "min_score",
                expected: "a keypoint score from 0 to 1",
                value: self.min_score,
            });
        }
        let f = &self.facing;
        for (name, value, expected) in [
            (
                "facing_memory",
                f.memory,
                "a positive, finite time in seconds",
            ),
            (
                "face_weight",
                f.face_weight,
                "a finite, non-negative weight",
            ),
            (
                "knee_weight",
                f.knee_weight,
                "a finite, non-negative weight",
            ),
            (
                "motion_weight",
                f.motion_weight,
                "a finite, non-negative weight",
            ),
        ] {
            let ok = value.is_finite() && value >= 0.0 && (name != "facing_memory" || value > 0.0);
            if !ok {
                return Err(Error::InvalidArgument {
                    name,
                    expected,
                    value,
                });
            }
        }
        if !(0.0..1.0).contains(&self.occlusion_ratio) {
            return Err(Error::InvalidArgument {
                name: "occlusion_ratio",
                expected: "a fraction in [0, 1): 0 turns the correction off",
                value: self.occlusion_ratio,
            });
        }
        if !(0.0..=MAX_SURFACE_DEPTH).contains(&self.surface_depth) {
            return Err(Error::InvalidArgument {
                name: "surface_depth",
                expected: "a depth in metres from 0 to 0.3",
                value: self.surface_depth,
            });
        }
        Ok(())
    }
}
