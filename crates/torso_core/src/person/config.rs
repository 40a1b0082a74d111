//! What a track is configured with.

use crate::coco::{Joints, N_JOINTS, TORSO};
use crate::error::{Error, Result};
use crate::forecaster::ForecasterConfig;
use crate::gating::{GateConfig, JointGate};
use crate::selfcheck::SelfCheck;
use crate::sides::FacingConfig;
use crate::vec3::{add, finite, norm, sub};

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
    /// How far (m) the shoulders' and the hips' joint centres lie behind the body's surface
    /// along the camera's ray. Joints lifted from a depth image lie on the surface the camera
    /// sees, in front of the joint centres a torso pose is defined by, so the plane is fitted
    /// to the torso joints moved back this far ([`behind_surface`](Self::behind_surface)); 0 for
    /// joints that are joint centres already (mocap, a skeleton tracker's). The hips lie deeper
    /// behind their surface than the shoulders, so a plane through the surface points leans its
    /// top away from the camera: each pair has its own depth.
    /// The defaults are the medians of those offsets for the measured (not completed) joints
    /// on the scenes benchmark's development split (docs/benchmark_log.md), about the body's radius
    /// at the shoulder and the hip.
    pub surface_depth: [f64; 2],
}

/// [`PersonConfig::surface_depth`]'s default (m): shoulders, hips.
const SURFACE_DEPTH: [f64; 2] = [0.06, 0.09];

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

    /// The shoulders and hips of `joints`, seen on the body's surface from `camera`, each moved
    /// its pair's [`surface_depth`](Self::surface_depth) further from the camera, along the ray
    /// to the seen torso joints' mean: where the joint centres lie. One direction for all four
    /// moves the torso back and leans it by the pairs' difference, nothing else; along their
    /// own rays, which diverge, the pairs would also spread across the view (and the azimuths
    /// came out worse on the scenes benchmark: the keypoints mark the body's outline, not the
    /// rays through its joint centres). The other joints, and missing ones, are left as they
    /// are.
    ///
    /// ```
    /// use torso_core::coco::{N_JOINTS, LEFT_SHOULDER, LEFT_HIP, NOSE};
    /// use torso_core::PersonConfig;
    /// let config = PersonConfig { surface_depth: [0.1, 0.2], ..PersonConfig::default() };
    /// let mut joints = [[f64::NAN; 3]; N_JOINTS];
    /// joints[LEFT_SHOULDER] = [3.0, 4.0, 1.0]; // 5 m from the camera, level with it
    /// joints[LEFT_HIP] = [3.0, 4.0, 1.0];
    /// joints[NOSE] = [3.0, 4.0, 1.0];
    /// config.behind_surface(&mut joints, [0.0, 0.0, 1.0]);
    /// assert!((joints[LEFT_SHOULDER][0] - 3.06).abs() < 1e-12 && (joints[LEFT_SHOULDER][1] - 4.08).abs() < 1e-12);
    /// assert!((joints[LEFT_HIP][0] - 3.12).abs() < 1e-12 && (joints[LEFT_HIP][1] - 4.16).abs() < 1e-12);
    /// assert_eq!(joints[NOSE], [3.0, 4.0, 1.0]);
    /// ```
    pub fn behind_surface(&self, joints: &mut Joints, camera: [f64; 3]) {
        let (mut sum, mut n) = ([0.0; 3], 0.0);
        for &j in TORSO.iter() {
            if finite(&joints[j]) {
                sum = add(sum, joints[j]);
                n += 1.0;
            }
        }
        let ray = sub(sum.map(|v| v / n), camera);
        let range = norm(ray);
        if !(n > 0.0 && range > 0.0 && range.is_finite()) {
            return;
        }
        let along = ray.map(|v| v / range);
        for (k, &j) in TORSO.iter().enumerate() {
            let depth = self.surface_depth[k / 2];
            joints[j] = std::array::from_fn(|i| joints[j][i] + depth * along[i]);
        }
    }

    /// Checks every field, as [`Person::new`](super::Person::new) does.
    pub fn validate(&self) -> Result<()> {
        self.forecaster.validate()?;
        if self.self_check {
            SelfCheck::slots(self.forecaster.rate_hz)?;
        }
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
        if let Some(&depth) = self
            .surface_depth
            .iter()
            .find(|d| !(0.0..=MAX_SURFACE_DEPTH).contains(*d))
        {
            return Err(Error::InvalidArgument {
                name: "surface_depth",
                expected: "depths in metres from 0 to 0.3 (shoulders, hips)",
                value: depth,
            });
        }
        Ok(())
    }
}
