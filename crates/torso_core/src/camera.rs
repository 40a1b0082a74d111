//! The depth camera's geometry: pinhole intrinsics with Brown-Conrady distortion, deprojection
//! into the camera's optical frame (z forward, x right, y down), and the rigid transform from
//! there into the gravity-aligned world frame (REP-103: x forward, y left, z up).
//!
//! ```
//! use torso_core::camera::{Camera, Intrinsics};
//! let intrinsics = Intrinsics::new(600.0, 600.0, 320.0, 240.0, [0.0; 5]).unwrap();
//! // A level camera 1 m up: the optical axis along world +x.
//! let camera = Camera::new(intrinsics, Camera::level(1.0, 0.0));
//! let p = camera.deproject_to_world([320.0, 240.0], 2.0);
//! assert!((p[0] - 2.0).abs() < 1e-12 && p[1].abs() < 1e-12 && (p[2] - 1.0).abs() < 1e-12);
//! ```

use crate::error::{Error, Result};

/// Fixed-point iterations that invert the distortion (as OpenCV's `undistortPoints`): the mild
/// distortion of depth cameras converges in a few.
pub const UNDISTORT_ITERATIONS: usize = 20;

/// Pinhole intrinsics of the image that the keypoints and the registered depth live in.
///
/// ```
/// use torso_core::camera::Intrinsics;
/// // A Kinect v2-like depth camera with radial distortion.
/// let k = Intrinsics::new(365.0, 365.0, 256.0, 212.0, [0.09, -0.27, 0.0, 0.0, 0.09]).unwrap();
/// let point = k.deproject([300.0, 150.0], 2.0);
/// let back = k.project(point);
/// assert!((back[0] - 300.0).abs() < 1e-6 && (back[1] - 150.0).abs() < 1e-6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Intrinsics {
    pub fx: f64,
    pub fy: f64,
    pub cx: f64,
    pub cy: f64,
    /// Brown-Conrady `(k1, k2, p1, p2, k3)` in OpenCV's and RealSense's order; zeros for an
    /// undistorted image.
    pub distortion: [f64; 5],
}

impl Intrinsics {
    /// Checked intrinsics: finite values and positive focal lengths.
    pub fn new(fx: f64, fy: f64, cx: f64, cy: f64, distortion: [f64; 5]) -> Result<Self> {
        let values = [fx, fy, cx, cy];
        if let Some(index) = values
            .iter()
            .chain(&distortion)
            .position(|v| !v.is_finite())
        {
            return Err(Error::NonFinite {
                name: "intrinsics",
                index,
            });
        }
        for (name, value) in [("fx", fx), ("fy", fy)] {
            if !(value > 0.0) {
                return Err(Error::InvalidArgument {
                    name,
                    expected: "a positive focal length in pixels",
                    value,
                });
            }
        }
        Ok(Self {
            fx,
            fy,
            cx,
            cy,
            distortion,
        })
    }

    /// Normalised undistorted to normalised distorted image coordinates.
    pub fn distort(&self, [x, y]: [f64; 2]) -> [f64; 2] {
        let [k1, k2, p1, p2, k3] = self.distortion;
        let r2 = x * x + y * y;
        let radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
        [
            x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
            y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y,
        ]
    }

    /// Inverse of [`distort`](Self::distort) by fixed-point iteration.
    pub fn undistort(&self, xy: [f64; 2]) -> [f64; 2] {
        if self.distortion.iter().all(|&k| k == 0.0) {
            return xy;
        }
        let mut guess = xy;
        for _ in 0..UNDISTORT_ITERATIONS {
            let d = self.distort(guess);
            guess = [guess[0] + (xy[0] - d[0]), guess[1] + (xy[1] - d[1])];
        }
        guess
    }

    /// A pixel `(u, v)` with its depth along the optical axis (m) to an optical-frame point;
    /// NaN depth gives a NaN point.
    pub fn deproject(&self, [u, v]: [f64; 2], depth: f64) -> [f64; 3] {
        let [x, y] = self.undistort([(u - self.cx) / self.fx, (v - self.cy) / self.fy]);
        [x * depth, y * depth, depth]
    }

    /// An optical-frame point to its pixel.
    pub fn project(&self, [x, y, z]: [f64; 3]) -> [f64; 2] {
        let [u, v] = self.distort([x / z, y / z]);
        [u * self.fx + self.cx, v * self.fy + self.cy]
    }
}

/// A rigid transform: `world = rotation · point + translation`.
///
/// ```
/// use torso_core::camera::Rigid;
/// // 1.2 m up, the optical axis (z) along world x: optical x is world -y, optical y world -z.
/// let to_world = Rigid::from_rows([
///     [0.0, 0.0, 1.0, 0.0],
///     [-1.0, 0.0, 0.0, 0.0],
///     [0.0, -1.0, 0.0, 1.2],
/// ])
/// .unwrap();
/// assert_eq!(to_world.apply([0.0, 0.0, 2.0]), [2.0, 0.0, 1.2]);
/// assert!(Rigid::from_rows([[2.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0]]).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rigid {
    pub rotation: [[f64; 3]; 3],
    pub translation: [f64; 3],
}

impl Rigid {
    /// From the top three rows of a 4x4 homogeneous matrix, checked to be finite with a proper
    /// rotation block.
    pub fn from_rows(rows: [[f64; 4]; 3]) -> Result<Self> {
        if let Some(index) = rows.iter().flatten().position(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                name: "camera_to_world",
                index,
            });
        }
        let rotation = rows.map(|r| [r[0], r[1], r[2]]);
        let translation = rows.map(|r| r[3]);
        let mut worst = 0.0f64;
        for i in 0..3 {
            for j in 0..3 {
                let dot: f64 = (0..3).map(|k| rotation[i][k] * rotation[j][k]).sum();
                worst = worst.max((dot - if i == j { 1.0 } else { 0.0 }).abs());
            }
        }
        let [a, b, c] = rotation;
        let det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]);
        if !(worst <= 1e-6) || !(det > 0.0) {
            return Err(Error::InvalidArgument {
                name: "camera_to_world",
                expected: "a rotation (orthonormal, determinant +1) in its 3x3 block",
                value: det,
            });
        }
        Ok(Self {
            rotation,
            translation,
        })
    }

    pub fn apply(&self, p: [f64; 3]) -> [f64; 3] {
        let r = &self.rotation;
        std::array::from_fn(|i| {
            r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2] + self.translation[i]
        })
    }
}

/// Intrinsics and where the camera is in the world.
///
/// ```
/// use torso_core::camera::{Camera, Intrinsics};
/// let camera = Camera::new(
///     Intrinsics::new(525.0, 525.0, 319.5, 239.5, [0.0; 5]).unwrap(),
///     Camera::level(1.0, 0.0),
/// );
/// assert_eq!(camera.position(), [0.0, 0.0, 1.0]);
/// let p = camera.deproject_to_world([319.5, 239.5], 3.0); // the image centre, 3 m away
/// assert!((p[0] - 3.0).abs() < 1e-12 && (p[2] - 1.0).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub intrinsics: Intrinsics,
    pub to_world: Rigid,
}

impl Camera {
    pub fn new(intrinsics: Intrinsics, to_world: Rigid) -> Self {
        Self {
            intrinsics,
            to_world,
        }
    }

    /// The optical frame of a camera `height` m above the world origin, looking along world +x,
    /// tilted down by `pitch` rad.
    pub fn level(height: f64, pitch: f64) -> Rigid {
        let (s, c) = pitch.sin_cos();
        // Optical (z forward, x right, y down) to world (x forward, y left, z up), then the tilt
        // about world y.
        let optical = [[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]];
        let tilt = [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]];
        let rotation = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..3).map(|k| tilt[i][k] * optical[k][j]).sum())
        });
        Rigid {
            rotation,
            translation: [0.0, 0.0, height],
        }
    }

    /// Where the camera is in the world.
    pub fn position(&self) -> [f64; 3] {
        self.to_world.translation
    }

    /// A pixel with its depth along the optical axis to a world point (NaN for NaN depth).
    pub fn deproject_to_world(&self, uv: [f64; 2], depth: f64) -> [f64; 3] {
        self.to_world.apply(self.intrinsics.deproject(uv, depth))
    }
}
