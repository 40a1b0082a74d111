//! The COCO-17 keypoint layout that every supported 2D detector (YOLO-pose, MoveNet) outputs, as
//! far as the per-person chain needs it: the torso joints with their sides, the face, and the
//! left/right pairs a detector exchanges when it sees a back.

use crate::history::MAX_POSE_VALUE;
use crate::plane::Side;

/// Keypoints per person.
pub const N_JOINTS: usize = 17;

/// One person's keypoints as 3D points (m), NaN where missing.
pub type Joints = [[f64; 3]; N_JOINTS];

pub const NOSE: usize = 0;
pub const LEFT_EYE: usize = 1;
pub const RIGHT_EYE: usize = 2;
pub const LEFT_SHOULDER: usize = 5;
pub const RIGHT_SHOULDER: usize = 6;
pub const LEFT_HIP: usize = 11;
pub const RIGHT_HIP: usize = 12;
pub const LEFT_KNEE: usize = 13;
pub const RIGHT_KNEE: usize = 14;
pub const LEFT_ANKLE: usize = 15;
pub const RIGHT_ANKLE: usize = 16;

/// The joints the torso plane is fitted through, shoulders first.
pub const TORSO: [usize; 4] = [LEFT_SHOULDER, RIGHT_SHOULDER, LEFT_HIP, RIGHT_HIP];
/// Their sides of the body, for [`crate::fit_torso_plane`].
pub const TORSO_SIDES: [Side; 4] = [Side::Left, Side::Right, Side::Left, Side::Right];
/// The torso's `(left, right)` pairs, shoulders first, then hips.
pub const TORSO_PAIRS: [(usize, usize); 2] =
    [(LEFT_SHOULDER, RIGHT_SHOULDER), (LEFT_HIP, RIGHT_HIP)];

/// `(left, right)` index pairs: eyes, ears, shoulders, elbows, wrists, hips, knees, ankles.
pub const LEFT_RIGHT_PAIRS: [(usize, usize); 8] = [
    (1, 2),
    (3, 4),
    (5, 6),
    (7, 8),
    (9, 10),
    (11, 12),
    (13, 14),
    (15, 16),
];

/// Whether a joint can be used: finite and within ±[`MAX_POSE_VALUE`] m of the origin (larger
/// coordinates are no body a camera sees, and overflow the plane fit and the forecaster).
/// The one rule for every stage that reads joints; a joint that fails it is missing.
pub fn usable(joint: &[f64; 3]) -> bool {
    joint.iter().all(|v| v.abs() <= MAX_POSE_VALUE)
}

/// Checks where the camera is: finite and within ±[`MAX_POSE_VALUE`] m, as every call that takes
/// it does before changing anything.
pub fn check_camera_position(position: [f64; 3]) -> crate::error::Result<()> {
    match position.iter().position(|v| !(v.abs() <= MAX_POSE_VALUE)) {
        None => Ok(()),
        Some(index) if !position[index].is_finite() => Err(crate::error::Error::NonFinite {
            name: "camera_position",
            index,
        }),
        Some(index) => Err(crate::error::Error::InvalidArgument {
            name: "camera_position",
            expected: "coordinates within ±MAX_POSE_VALUE (1e6) m",
            value: position[index],
        }),
    }
}

/// `values` with every left/right pair exchanged.
pub fn swap_sides<T: Copy>(values: &mut [T; N_JOINTS]) {
    for (left, right) in LEFT_RIGHT_PAIRS {
        values.swap(left, right);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_cover_every_joint_but_the_nose_once() {
        let mut seen = [0; N_JOINTS];
        for (l, r) in LEFT_RIGHT_PAIRS {
            seen[l] += 1;
            seen[r] += 1;
        }
        assert_eq!(seen[NOSE], 0);
        assert!(seen[1..].iter().all(|&n| n == 1));
        let mut idx: [usize; N_JOINTS] = std::array::from_fn(|i| i);
        swap_sides(&mut idx);
        assert_eq!(
            (idx[LEFT_HIP], idx[RIGHT_HIP], idx[NOSE]),
            (RIGHT_HIP, LEFT_HIP, NOSE)
        );
    }
}
