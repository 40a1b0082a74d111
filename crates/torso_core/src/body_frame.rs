//! A torso pose as a body frame: where a consumer that speaks ROS conventions hangs a person in
//! its transform tree (REP-155's `body_<id>`, under the world frame the pose is in).
//!
//! The frame's x axis points out of the chest (the torso plane's normal, the pose's azimuth and
//! elevation) and its z axis towards the head; y is the body's left (REP-103's right-handed x
//! forward, y left, z up, as a person standing upright and facing the world's x has the world's
//! own axes). A pose has five components and a frame six: the roll about the chest's normal is
//! the one the pose does not carry. The frame takes the spine in the vertical plane through the
//! normal (z is the world's up less its part along the normal, the torso plane's steepest
//! direction), as it is for a person standing, bending forwards or leaning back; a person lying
//! on one side, spine level, gets the frame of one standing with that heading, for the pose
//! cannot tell the two apart. So the frame is the world's, turned by the azimuth about the
//! world's z and then by the lean from upright about its own y: leaning forwards (an elevation
//! over a right angle) pitches the chest down.
//!
//! REP-155 puts the origin at the hips' midpoint; a pose's centre is the torso's (the middle of
//! the shoulders and hips, behind the body's surface), which is where the origin is here.

use crate::error::{Error, Result};
use crate::{Pose, AZIMUTH, ELEVATION};
use nalgebra::UnitQuaternion;
use std::f64::consts::{FRAC_PI_2, PI};

/// A person's body frame in the world frame of the pose it came from.
///
/// ```
/// use std::f64::consts::{FRAC_1_SQRT_2 as H, FRAC_PI_2};
/// use torso_core::BodyFrame;
/// // Upright, facing the world's y: a quarter turn about z.
/// let frame = BodyFrame::of(&[1.0, 2.0, 1.1, FRAC_PI_2, FRAC_PI_2]).unwrap();
/// assert_eq!(frame.translation, [1.0, 2.0, 1.1]);
/// assert!(frame.rotation.iter().zip([0.0, 0.0, H, H]).all(|(a, b)| (a - b).abs() < 1e-12));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyFrame {
    /// The frame's origin (m): the pose's centre.
    pub translation: [f64; 3],
    /// The frame's orientation as a unit quaternion `[x, y, z, w]` (the order of ROS's
    /// `geometry_msgs/Quaternion`), `w` never negative.
    pub rotation: [f64; 4],
}

impl BodyFrame {
    /// The body frame of `pose` (`[x, y, z, azimuth, elevation]`). Refused: a component that is
    /// not finite, an elevation outside 0 to π (a normal's angle from the world's up).
    pub fn of(pose: &Pose) -> Result<Self> {
        if let Some(index) = pose.iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                name: "pose",
                index,
            });
        }
        let elevation = pose[ELEVATION];
        if !(0.0..=PI).contains(&elevation) {
            return Err(Error::InvalidArgument {
                name: "elevation",
                expected: "an angle from 0 to π (rad) from the world's up",
                value: elevation,
            });
        }
        // Yaw about the world's z, then pitch about the body's y: nalgebra's roll, pitch, yaw.
        let q = UnitQuaternion::from_euler_angles(0.0, elevation - FRAC_PI_2, pose[AZIMUTH]);
        let sign = if q.w < 0.0 { -1.0 } else { 1.0 };
        Ok(Self {
            translation: [pose[0], pose[1], pose[2]],
            rotation: [q.i, q.j, q.k, q.w].map(|v| sign * v),
        })
    }

    /// The frame's x (out of the chest), y (the body's left) and z (towards the head) axes in
    /// the world frame.
    pub fn axes(&self) -> [[f64; 3]; 3] {
        let [x, y, z, w] = self.rotation;
        let q = UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(w, x, y, z));
        let m = q.to_rotation_matrix();
        std::array::from_fn(|c| [m[(0, c)], m[(1, c)], m[(2, c)]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::uniform;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        a.iter().zip(b).all(|(p, q)| (p - q).abs() < 1e-12)
    }

    #[test]
    fn the_x_axis_is_the_poses_normal_and_z_the_torso_planes_steepest_direction() {
        let mut next = uniform(7);
        for _ in 0..200 {
            let (az, el) = (4.0 * PI * next() - 2.0 * PI, PI * next());
            let frame = BodyFrame::of(&[next(), next(), next(), az, el]).unwrap();
            let [x, y, z] = frame.axes();
            // The normal from its azimuth and its angle from the world's up.
            let normal = [el.sin() * az.cos(), el.sin() * az.sin(), el.cos()];
            assert!(close(x, normal), "x {x:?} normal {normal:?}");
            // The world's up less its part along the normal, normalised (sin el > 0).
            let up = [
                -el.cos() * normal[0],
                -el.cos() * normal[1],
                1.0 - el.cos() * normal[2],
            ];
            let length = up.iter().map(|v| v * v).sum::<f64>().sqrt();
            if length > 1e-6 {
                assert!(close(z, up.map(|v| v / length)), "z {z:?} up {up:?}");
            }
            // Right-handed: y = z × x, level (the spine in the vertical plane through the normal).
            let cross = [
                z[1] * x[2] - z[2] * x[1],
                z[2] * x[0] - z[0] * x[2],
                z[0] * x[1] - z[1] * x[0],
            ];
            assert!(close(y, cross) && y[2].abs() < 1e-12);
            let norm = frame.rotation.iter().map(|v| v * v).sum::<f64>();
            assert!((norm - 1.0).abs() < 1e-12 && frame.rotation[3] >= 0.0);
        }
    }

    #[test]
    fn an_upright_person_facing_the_worlds_x_has_the_worlds_axes_and_leaning_forward_pitches_down()
    {
        let upright = BodyFrame::of(&[0.5, -1.0, 1.2, 0.0, FRAC_PI_2]).unwrap();
        assert!(upright
            .rotation
            .iter()
            .zip([0.0, 0.0, 0.0, 1.0])
            .all(|(a, b)| (a - b).abs() < 1e-12));
        assert_eq!(upright.translation, [0.5, -1.0, 1.2]);
        // Bent 30 degrees forward, facing x: the chest points down, the head forward.
        let bent = BodyFrame::of(&[0.0, 0.0, 1.0, 0.0, FRAC_PI_2 + PI / 6.0]).unwrap();
        let [x, _, z] = bent.axes();
        assert!(x[2] < 0.0 && z[0] > 0.0 && (z[0] - 0.5).abs() < 1e-12);
        // Lying on the back, head towards -x: the chest up, facing +x's azimuth.
        let lying = BodyFrame::of(&[0.0, 0.0, 0.3, 0.0, 0.0]).unwrap();
        let [x, _, z] = lying.axes();
        assert!(close(x, [0.0, 0.0, 1.0]) && close(z, [-1.0, 0.0, 0.0]));
    }

    #[test]
    fn a_pose_that_is_not_a_number_or_an_elevation_past_the_vertical_is_refused() {
        let nan = BodyFrame::of(&[0.0, f64::NAN, 1.0, 0.0, 1.5]);
        assert_eq!(
            nan,
            Err(Error::NonFinite {
                name: "pose",
                index: 1
            })
        );
        for el in [-0.1, PI + 0.1] {
            assert!(matches!(
                BodyFrame::of(&[0.0, 0.0, 1.0, 0.0, el]),
                Err(Error::InvalidArgument {
                    name: "elevation",
                    ..
                })
            ));
        }
        // An unwrapped azimuth is the same frame as its wrapped one.
        let a = BodyFrame::of(&[0.0, 0.0, 1.0, 0.4 + 4.0 * PI, 1.2]).unwrap();
        let b = BodyFrame::of(&[0.0, 0.0, 1.0, 0.4, 1.2]).unwrap();
        assert!(a
            .rotation
            .iter()
            .zip(b.rotation)
            .all(|(p, q)| (p - q).abs() < 1e-12));
    }
}
