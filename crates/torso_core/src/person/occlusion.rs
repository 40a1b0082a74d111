//! The depth of a torso joint the camera does not see.
//!
//! In profile views the body hides its far shoulder or hip: the depth camera sees the near joint
//! of a pair, and the keypoint of the far one lands on the near side of the torso, so its depth
//! is the near side's. Each track learns its shoulder and hip widths in frontal and dorsal
//! views, where both joints are in view, and moves a far joint whose pair measures too short
//! back along its camera ray to that width. (A joint whose depth came off something else
//! altogether is dropped before this, [`crate::stray`].)

use super::Person;
use crate::coco::{Joints, N_JOINTS, TORSO, TORSO_PAIRS};
use crate::vec3::{add, distance, dot, finite, midpoint, norm, sub};
use crate::AZIMUTH;

/// `|cos|` between the torso normal and the direction to the camera above which both joints of a
/// pair are in view, so that their distance teaches the pair's width (about 37 degrees off
/// frontal or dorsal).
pub const FRONTAL_COSINE: f64 = 0.8;

/// Widths (m) a pair's distance must lie in to be learned: adult shoulders are about 0.35 m
/// apart at the keypoints, hips 0.25 m.
pub const PLAUSIBLE_WIDTH: (f64, f64) = (0.15, 0.7);

/// Shoulder and hip widths as fractions of the torso's length (shoulders' midpoint to hips'),
/// for a track that has not yet seen a frontal view to learn its own: the median keypoint
/// proportions of frontal views on the scenes benchmark's development split (adult
/// anthropometry gives about 0.7 and 0.5 for the joint centres).
const WIDTH_PER_TORSO_LENGTH: [f64; 2] = [0.68, 0.44];

/// Weight of a new frontal frame in the learned widths (an exponential mean over about ten
/// frames).
const WIDTH_RATE: f64 = 0.1;

impl Person {
    /// In a profile view the far shoulder (or hip) is hidden behind the body: the detector still
    /// places it in the image, but the depth read there is the near side's, so the pair comes
    /// out too short and the azimuth lags the turn. The 2D position is right and only the depth
    /// is wrong, so the far joint is moved back along its camera ray to where the pair has the
    /// width learned in frontal views (before any, the torso's length times
    /// [`WIDTH_PER_TORSO_LENGTH`]). The far joint is the one on the side turned away from the
    /// camera by the last pose.
    pub(super) fn complete_occluded(
        &mut self,
        joints: &mut Joints,
        camera: [f64; 3],
    ) -> [bool; N_JOINTS] {
        let mut completed = [false; N_JOINTS];
        let Some(last) = self.last_pose else {
            return completed;
        };
        let (sin, cos) = last[AZIMUTH].sin_cos();
        let left = [-sin, cos, 0.0];
        let to_camera = sub(camera, [last[0], last[1], last[2]]);
        let facing = [cos, sin, 0.0];
        let frontal = dot(facing, to_camera).abs() / norm(to_camera) > FRONTAL_COSINE;
        let torso = TORSO.map(|i| joints[i]);
        let length = torso
            .iter()
            .all(finite)
            .then(|| distance(midpoint(torso[0], torso[1]), midpoint(torso[2], torso[3])));
        for (((l, r), width), per_length) in TORSO_PAIRS
            .iter()
            .zip(self.widths.iter_mut())
            .zip(WIDTH_PER_TORSO_LENGTH)
        {
            if !(finite(&joints[*l]) && finite(&joints[*r])) {
                continue;
            }
            let measured = distance(joints[*l], joints[*r]);
            if frontal && (PLAUSIBLE_WIDTH.0..=PLAUSIBLE_WIDTH.1).contains(&measured) {
                *width = Some(width.map_or(measured, |w| w + WIDTH_RATE * (measured - w)));
            } else if let Some(w) = width.or(length.map(|l| per_length * l)) {
                if measured < self.config.occlusion_ratio * w {
                    let (near, far) = if dot(left, to_camera) > 0.0 {
                        (*l, *r)
                    } else {
                        (*r, *l)
                    };
                    joints[far] = behind_on_ray(camera, joints[far], joints[near], w);
                    completed[far] = true;
                }
            }
        }
        completed
    }
}

/// The point on the camera ray through `seen` that lies `width` from `anchor`, behind `seen`
/// (the larger root of `|c + s r - anchor| = width`); `seen` itself when the ray never comes
/// that close.
pub(super) fn behind_on_ray(
    camera: [f64; 3],
    seen: [f64; 3],
    anchor: [f64; 3],
    width: f64,
) -> [f64; 3] {
    let ray = sub(seen, camera);
    let length = norm(ray);
    if !(length > 0.0) {
        return seen;
    }
    let r = ray.map(|v| v / length);
    let a = sub(anchor, camera);
    let along = dot(r, a);
    let discriminant = along * along - dot(a, a) + width * width;
    if !(discriminant >= 0.0) {
        return seen;
    }
    let s = (along + discriminant.sqrt()).max(length);
    add(camera, r.map(|v| v * s))
}
