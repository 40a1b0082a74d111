//! The torso plane (thesis eqs. 3.1 to 3.4): the least-squares plane through the valid torso
//! joints, its centre, its normal oriented out of the chest, and the normal's azimuth and
//! elevation in the gravity-aligned world frame (REP-103: x forward, y left, z up).
//!
//! The plane minimising the (weighted) sum of squared distances passes through the weighted
//! mean `c` (eq. 3.2) and its normal is the eigenvector of the smallest eigenvalue of the 3×3
//! scatter matrix `S = Σ w (x - c)(x - c)ᵀ`. All of it lives on the stack.

use crate::error::{check_len, check_weights, Error, Result};
use nalgebra::{Matrix3, Vector3};

/// Which side of the body a torso joint is on; the sign of the normal comes from it.
///
/// ```
/// use torso_core::Side;
/// assert_eq!(Side::from_code('L').unwrap(), Side::Left);
/// assert!(Side::from_code('X').is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Side {
    Left,
    Right,
    Centre,
}

impl Side {
    /// Parses `L`, `R` or `C` (any case), the one-letter codes the Python API uses.
    pub fn from_code(code: char) -> Result<Self> {
        match code.to_ascii_uppercase() {
            'L' => Ok(Side::Left),
            'R' => Ok(Side::Right),
            'C' => Ok(Side::Centre),
            other => Err(Error::InvalidArgument {
                name: "sides",
                expected: "one letter per joint: L (left), R (right) or C (centre)",
                value: other as u32 as f64,
            }),
        }
    }
}

/// Ratio `λ_mid / λ_max` of the scatter eigenvalues under which the joints count as collinear.
/// A torso is about 0.35 m wide and 0.5 m tall (ratio near 0.5); 1e-4 means the spread across
/// the line is under 1 % of the spread along it, where the normal is noise.
pub const MIN_PLANARITY: f64 = 1e-4;

/// `|n · f̂|` under which the normal counts as perpendicular to the body's forward reference
/// `f = (left - right) × up`, so its sign cannot be chosen (about 3 degrees from ambiguity). The
/// default of [`fit_torso_plane`]; [`fit_torso_plane_with`] takes another.
pub const MIN_ORIENTATION_COSINE: f64 = 0.05;

/// The outcome of one frame's plane fit as a code, for batch results.
///
/// ```
/// use torso_core::fit_torso_plane;
/// use torso_core::plane::PlaneStatus;
/// use torso_core::Side;
/// let two = [[2.0, 0.2, 1.4], [2.0, -0.2, 1.4]];
/// let result = fit_torso_plane(&two, &[Side::Left, Side::Right], None);
/// assert_eq!(PlaneStatus::of(&result), PlaneStatus::TooFewJoints);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum PlaneStatus {
    Ok = 0,
    TooFewJoints = 1,
    Collinear = 2,
    /// The normal's sign cannot be chosen (or any other refusal of the frame).
    AmbiguousOrientation = 3,
}

impl PlaneStatus {
    /// Every status with its name, for bindings.
    pub const NAMES: [(&'static str, PlaneStatus); 4] = [
        ("OK", PlaneStatus::Ok),
        ("TOO_FEW_JOINTS", PlaneStatus::TooFewJoints),
        ("COLLINEAR", PlaneStatus::Collinear),
        ("AMBIGUOUS_ORIENTATION", PlaneStatus::AmbiguousOrientation),
    ];

    /// The status of a fit's result.
    pub fn of(result: &Result<TorsoPlane>) -> Self {
        match result {
            Ok(_) => PlaneStatus::Ok,
            Err(Error::TooFewJoints { .. }) => PlaneStatus::TooFewJoints,
            Err(Error::CollinearJoints { .. }) => PlaneStatus::Collinear,
            Err(_) => PlaneStatus::AmbiguousOrientation,
        }
    }
}

/// A fitted torso plane.
///
/// ```
/// use torso_core::{fit_torso_plane, Side};
/// // Facing +x, upright: azimuth 0, elevation π/2 (the normal is horizontal).
/// let joints = [[2.0, 0.18, 1.4], [2.0, -0.18, 1.4], [2.0, 0.12, 0.9], [2.0, -0.12, 0.9]];
/// let sides = [Side::Left, Side::Right, Side::Left, Side::Right];
/// let plane = fit_torso_plane(&joints, &sides, None).unwrap();
/// assert!(plane.azimuth.abs() < 1e-9);
/// assert!((plane.elevation - std::f64::consts::FRAC_PI_2).abs() < 1e-9);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TorsoPlane {
    /// Weighted mean of the valid joints (m).
    pub centre: [f64; 3],
    /// Unit normal, pointing out of the chest.
    pub normal: [f64; 3],
    /// `atan2(n_y, n_x)` in (-π, π] (rad).
    pub azimuth: f64,
    /// `acos(n_z)` in [0, π] (rad); π/2 is an upright torso.
    pub elevation: f64,
    /// Weighted RMS distance of the joints from the plane (m).
    pub rms_residual: f64,
    /// Joints that entered the fit.
    pub joints_used: usize,
}

/// Fits the torso plane. `points[i]` is joint `i` in the world frame (NaN when missing), `sides[i]`
/// its side of the body and `weights[i]` its confidence (`None` for uniform; zero excludes it).
pub fn fit_torso_plane(
    points: &[[f64; 3]],
    sides: &[Side],
    weights: Option<&[f64]>,
) -> Result<TorsoPlane> {
    fit_torso_plane_with(points, sides, weights, MIN_ORIENTATION_COSINE)
}

/// [`fit_torso_plane`] with the orientation threshold given. Bent far forward, a torso's normal
/// is nearly vertical and nearly perpendicular to the forward reference; a detector's noise then
/// decides the sign, hence the default refusal. Mocap ground truth has no such noise: 0 orients
/// every frame by the sign of `n · f`, the mocap frames bent far forward included, which the
/// default refuses.
pub fn fit_torso_plane_with(
    points: &[[f64; 3]],
    sides: &[Side],
    weights: Option<&[f64]>,
    min_orientation_cosine: f64,
) -> Result<TorsoPlane> {
    check_orientation_cosine(min_orientation_cosine)?;
    check_len("sides", sides.len(), points.len())?;
    if let Some(w) = weights {
        check_len("weights", w.len(), points.len())?;
        check_weights("weights", w)?;
    }
    let weight = |i: usize| weights.map_or(1.0, |w| w[i]);
    let valid = |i: usize| weight(i) > 0.0 && points[i].iter().all(|v| v.is_finite());

    let mut sum_w = 0.0;
    let mut centre = Vector3::zeros();
    let mut used = 0;
    for i in (0..points.len()).filter(|&i| valid(i)) {
        let w = weight(i);
        centre += w * Vector3::from(points[i]);
        sum_w += w;
        used += 1;
    }
    if used < 3 {
        return Err(Error::TooFewJoints {
            valid: used,
            needed: 3,
        });
    }
    centre /= sum_w;

    // Two passes (mean, then scatter) keep the scatter accurate far from the origin.
    let mut scatter = Matrix3::zeros();
    for i in (0..points.len()).filter(|&i| valid(i)) {
        let d = Vector3::from(points[i]) - centre;
        scatter += weight(i) * d * d.transpose();
    }
    let eigen = smallest_eigenpair(&scatter);
    let planarity = if eigen.largest > 0.0 {
        eigen.middle / eigen.largest
    } else {
        0.0
    };
    if !(planarity >= MIN_PLANARITY) {
        return Err(Error::CollinearJoints {
            planarity,
            minimum: MIN_PLANARITY,
        });
    }
    let mut normal = eigen.vector;

    // Sign: out of the chest, i.e. along the forward reference (left - right) × up.
    let (mut left, mut right) = ((Vector3::zeros(), 0.0), (Vector3::zeros(), 0.0));
    for i in (0..points.len()).filter(|&i| valid(i)) {
        let acc = match sides[i] {
            Side::Left => &mut left,
            Side::Right => &mut right,
            Side::Centre => continue,
        };
        acc.0 += weight(i) * Vector3::from(points[i]);
        acc.1 += weight(i);
    }
    if left.1 == 0.0 || right.1 == 0.0 {
        return Err(Error::AmbiguousOrientation);
    }
    let forward = forward_reference(left.0 / left.1 - right.0 / right.1)?;
    let cosine = normal.dot(&forward);
    if cosine.abs() < min_orientation_cosine || cosine == 0.0 {
        return Err(Error::AmbiguousOrientation);
    }
    if cosine < 0.0 {
        normal = -normal;
    }
    // The residual is summed from the distances themselves: the closed-form eigenvalue carries an
    // absolute error of about ε·λ_max, which for a flat torso would swamp the true residual.
    let mut residual = 0.0;
    for i in (0..points.len()).filter(|&i| valid(i)) {
        residual += weight(i) * normal.dot(&(Vector3::from(points[i]) - centre)).powi(2);
    }
    let (azimuth, elevation) = angles(&normal);
    Ok(TorsoPlane {
        centre: centre.into(),
        normal: normal.into(),
        azimuth,
        elevation,
        rms_residual: (residual / sum_w).sqrt(),
        joints_used: used,
    })
}

/// Fits one plane per frame: `points` holds consecutive frames of `sides.len()` joints, and
/// `weights` (if any) one weight per point. Each frame succeeds or fails on its own.
pub fn fit_torso_planes<'a>(
    points: &'a [[f64; 3]],
    sides: &'a [Side],
    weights: Option<&'a [f64]>,
    min_orientation_cosine: f64,
) -> Result<impl Iterator<Item = Result<TorsoPlane>> + 'a> {
    let joints = sides.len();
    if joints == 0 || points.len() % joints != 0 {
        return Err(Error::LengthMismatch {
            name: "joints",
            expected: joints * (points.len() / joints.max(1)),
            got: points.len(),
        });
    }
    if let Some(w) = weights {
        check_len("weights", w.len(), points.len())?;
    }
    // Checked once here, or every frame would fail on its own with the same error.
    check_orientation_cosine(min_orientation_cosine)?;
    Ok(points
        .chunks_exact(joints)
        .enumerate()
        .map(move |(i, frame)| {
            let w = weights.map(|w| &w[i * joints..(i + 1) * joints]);
            fit_torso_plane_with(frame, sides, w, min_orientation_cosine)
        }))
}

/// The eigenvalues of a symmetric positive semi-definite 3×3 matrix and the unit eigenvector of
/// the smallest.
struct SmallestEigenpair {
    middle: f64,
    largest: f64,
    vector: Vector3<f64>,
}

/// Closed-form eigen-decomposition of a 3×3 scatter matrix: the eigenvalues from the
/// trigonometric solution of the characteristic cubic (Smith 1961), the eigenvector of the
/// smallest as the longest cross product of two rows of `S - λI`, whose rows span the space
/// orthogonal to it. No iteration, so its cost is fixed.
fn smallest_eigenpair(s: &Matrix3<f64>) -> SmallestEigenpair {
    // Scaling by the largest entry keeps the cubic's coefficients near one for any units.
    let scale = s.amax();
    if !(scale > 0.0) {
        return SmallestEigenpair {
            middle: 0.0,
            largest: 0.0,
            vector: Vector3::z(),
        };
    }
    let a = s / scale;
    let q = a.trace() / 3.0;
    let off = a[(0, 1)].powi(2) + a[(0, 2)].powi(2) + a[(1, 2)].powi(2);
    let p2 =
        (a[(0, 0)] - q).powi(2) + (a[(1, 1)] - q).powi(2) + (a[(2, 2)] - q).powi(2) + 2.0 * off;
    let p = (p2 / 6.0).sqrt();
    if p == 0.0 {
        // A multiple of the identity: every direction is an eigenvector.
        return SmallestEigenpair {
            middle: scale * q,
            largest: scale * q,
            vector: Vector3::z(),
        };
    }
    let b = (a - Matrix3::identity() * q) / p;
    let phi = (0.5 * b.determinant()).clamp(-1.0, 1.0).acos() / 3.0;
    let largest = q + 2.0 * p * phi.cos();
    let smallest = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    let middle = 3.0 * q - largest - smallest;

    let m = a - Matrix3::identity() * smallest;
    let (r0, r1, r2) = (
        m.row(0).transpose(),
        m.row(1).transpose(),
        m.row(2).transpose(),
    );
    let mut vector = r0.cross(&r1);
    for candidate in [r0.cross(&r2), r1.cross(&r2)] {
        if candidate.norm_squared() > vector.norm_squared() {
            vector = candidate;
        }
    }
    let norm = vector.norm();
    let vector = if norm > 0.0 {
        vector / norm
    } else {
        // A double smallest eigenvalue leaves `S - λI` of rank one: any vector orthogonal to
        // its non-zero row is an eigenvector.
        let row = [r0, r1, r2]
            .into_iter()
            .max_by(|x, y| x.norm_squared().total_cmp(&y.norm_squared()))
            .unwrap_or(r0);
        let helper = if row.x.abs() < 0.9 * row.norm() {
            Vector3::x()
        } else {
            Vector3::y()
        };
        row.cross(&helper).normalize()
    };
    SmallestEigenpair {
        middle: scale * middle,
        largest: scale * largest,
        vector,
    }
}

fn check_orientation_cosine(value: f64) -> Result<()> {
    if (0.0..1.0).contains(&value) {
        Ok(())
    } else {
        Err(Error::InvalidArgument {
            name: "min_orientation_cosine",
            expected: "a cosine in [0, 1)",
            value,
        })
    }
}

/// Unit forward direction `(left - right) × ẑ` of a body whose left-right axis is `lr`. Refused
/// when that axis is within about 6 degrees of vertical, where the cross product is all noise.
fn forward_reference(lr: Vector3<f64>) -> Result<Vector3<f64>> {
    let forward = Vector3::new(lr.y, -lr.x, 0.0);
    let norm = forward.norm();
    if !(norm > 0.1 * lr.norm()) {
        return Err(Error::AmbiguousOrientation);
    }
    Ok(forward / norm)
}

/// Azimuth `atan2(n_y, n_x)` and elevation `acos(n_z / |n|)` of a normal (eqs. 3.3, 3.4).
fn angles(n: &Vector3<f64>) -> (f64, f64) {
    (n.y.atan2(n.x), (n.z / n.norm()).clamp(-1.0, 1.0).acos())
}

/// A heading from the shoulders alone, for frames where the hips are not seen. It has no
/// elevation: the shoulder line fixes the facing direction about gravity, nothing more.
///
/// ```
/// use torso_core::shoulder_heading;
/// // Left shoulder at +y, right at -y: the chest faces +x.
/// let heading = shoulder_heading([2.0, 0.18, 1.4], [2.0, -0.18, 1.4]).unwrap();
/// assert!(heading.azimuth.abs() < 1e-12 && heading.centre == [2.0, 0.0, 1.4]);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShoulderHeading {
    /// Midpoint of the shoulders (m), not the torso centre: it sits about 0.25 m higher.
    pub centre: [f64; 3],
    /// Azimuth of `(left - right) × up` (rad), comparable with [`TorsoPlane::azimuth`].
    pub azimuth: f64,
}

/// Azimuth from the shoulder line and gravity.
pub fn shoulder_heading(left: [f64; 3], right: [f64; 3]) -> Result<ShoulderHeading> {
    let valid =
        left.iter().all(|v| v.is_finite()) as usize + right.iter().all(|v| v.is_finite()) as usize;
    if valid < 2 {
        return Err(Error::TooFewJoints { valid, needed: 2 });
    }
    let (l, r) = (Vector3::from(left), Vector3::from(right));
    let forward = forward_reference(l - r)?;
    Ok(ShoulderHeading {
        centre: (0.5 * (l + r)).into(),
        azimuth: forward.y.atan2(forward.x),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    /// Shoulders and hips of an upright person at `origin` facing azimuth `yaw`, leaning
    /// forward by `lean` radians.
    pub(crate) fn torso(origin: [f64; 3], yaw: f64, lean: f64) -> ([[f64; 3]; 5], [Side; 5]) {
        let local = [
            [0.0, 0.18, 0.5],  // left shoulder
            [0.0, -0.18, 0.5], // right shoulder
            [0.0, 0.12, 0.0],  // left hip
            [0.0, -0.12, 0.0], // right hip
            [0.02, 0.0, 0.45], // thorax, a little in front of the plane
        ];
        let mut out = [[0.0; 3]; 5];
        for (o, p) in out.iter_mut().zip(local) {
            // Lean about the local y axis (forward tilt), then yaw about z.
            let (x, z) = (
                p[0] * lean.cos() + p[2] * lean.sin(),
                -p[0] * lean.sin() + p[2] * lean.cos(),
            );
            let y = p[1];
            *o = [
                origin[0] + x * yaw.cos() - y * yaw.sin(),
                origin[1] + x * yaw.sin() + y * yaw.cos(),
                origin[2] + z,
            ];
        }
        (
            out,
            [
                Side::Left,
                Side::Right,
                Side::Left,
                Side::Right,
                Side::Centre,
            ],
        )
    }

    #[test]
    fn upright_torso_facing_forward() {
        let (p, s) = torso([2.0, -1.0, 0.9], 0.0, 0.0);
        let plane = fit_torso_plane(&p[..4], &s[..4], None).unwrap();
        assert!(plane.azimuth.abs() < 1e-12);
        assert!((plane.elevation - FRAC_PI_2).abs() < 1e-12);
        assert!((plane.centre[2] - 1.15).abs() < 1e-12);
        assert!(plane.rms_residual < 1e-12);
    }

    #[test]
    fn yaw_and_lean_are_recovered() {
        for &yaw in &[-3.0, -1.2, 0.4, 2.9] {
            for &lean in &[0.0, 0.3, -0.2] {
                let (p, s) = torso([0.0, 0.0, 1.0], yaw, lean);
                let plane = fit_torso_plane(&p[..4], &s[..4], None).unwrap();
                assert!(
                    (plane.azimuth - yaw).abs() < 1e-9,
                    "yaw {yaw}: {}",
                    plane.azimuth
                );
                // Leaning forward tips the chest normal down: elevation grows by the lean.
                assert!((plane.elevation - (FRAC_PI_2 + lean)).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn weights_exclude_and_missing_joints_are_skipped() {
        let (mut p, s) = torso([0.0, 0.0, 1.0], 0.5, 0.0);
        // The thorax sits off the plane; zero weight removes its pull entirely.
        let with_thorax = fit_torso_plane(&p, &s, None).unwrap();
        let without = fit_torso_plane(&p, &s, Some(&[1.0, 1.0, 1.0, 1.0, 0.0])).unwrap();
        assert!(with_thorax.rms_residual > 1e-3 && without.rms_residual < 1e-12);
        p[4] = [f64::NAN; 3];
        assert_eq!(fit_torso_plane(&p, &s, None).unwrap(), without);
    }

    #[test]
    fn degenerate_inputs_are_typed_errors() {
        let (p, s) = torso([0.0, 0.0, 1.0], 0.0, 0.0);
        assert_eq!(
            fit_torso_plane(&p[..2], &s[..2], None),
            Err(Error::TooFewJoints {
                valid: 2,
                needed: 3
            })
        );
        let line = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 2.0, 1e-9]];
        assert!(matches!(
            fit_torso_plane(&line, &[Side::Left, Side::Centre, Side::Right], None),
            Err(Error::CollinearJoints { .. })
        ));
        assert_eq!(
            fit_torso_plane(&p[..4], &[Side::Centre; 4], None),
            Err(Error::AmbiguousOrientation)
        );
        assert!(matches!(
            fit_torso_plane(&p, &s[..3], None),
            Err(Error::LengthMismatch { name: "sides", .. })
        ));
        assert!(matches!(
            fit_torso_plane(&p, &s, Some(&[1.0, 1.0, f64::NAN, 1.0, 1.0])),
            Err(Error::InvalidArgument {
                name: "weights",
                ..
            })
        ));
        // Lying flat on the back: the chest faces up, left-right axis horizontal, normal vertical.
        let flat = [
            [0.0, 0.2, 0.3],
            [0.0, -0.2, 0.3],
            [0.5, 0.2, 0.3],
            [0.5, -0.2, 0.3],
        ];
        assert_eq!(
            fit_torso_plane(
                &flat,
                &[Side::Left, Side::Right, Side::Left, Side::Right],
                None
            ),
            Err(Error::AmbiguousOrientation)
        );
    }

    #[test]
    fn closed_form_eigenpair_matches_the_iterative_solver() {
        // Scatter matrices of random point sets, from isotropic to nearly flat, at metre and
        // millimetre scales, against nalgebra's iterative symmetric eigen-decomposition.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for case in 0..500 {
            let flatness = [1.0, 0.3, 1e-2, 1e-4, 0.0][case % 5];
            let units = if case % 2 == 0 { 1.0 } else { 1e3 };
            let mut s = Matrix3::zeros();
            for _ in 0..6 {
                let d = Vector3::new(uniform(), uniform(), flatness * uniform()) * units;
                s += d * d.transpose();
            }
            let rotation =
                nalgebra::Rotation3::new(Vector3::new(uniform(), uniform(), uniform()) * 6.0);
            let s = rotation.matrix() * s * rotation.matrix().transpose();
            let reference = nalgebra::SymmetricEigen::new(s);
            let mut values = [0, 1, 2].map(|i| reference.eigenvalues[i]);
            values.sort_by(f64::total_cmp);
            let ours = smallest_eigenpair(&s);
            let tolerance = 1e-12 * values[2];
            assert!((ours.largest - values[2]).abs() < tolerance, "case {case}");
            assert!((ours.middle - values[1]).abs() < tolerance, "case {case}");
            // The eigenvector is defined up to sign; its Rayleigh quotient is the smallest value.
            assert!((ours.vector.norm() - 1.0).abs() < 1e-12);
            let rayleigh = ours.vector.dot(&(s * ours.vector));
            assert!((rayleigh - values[0]).abs() < tolerance, "case {case}");
        }
        let isotropic = smallest_eigenpair(&(Matrix3::identity() * 2.0));
        assert_eq!((isotropic.middle, isotropic.largest), (2.0, 2.0));
        assert_eq!(smallest_eigenpair(&Matrix3::zeros()).largest, 0.0);
        // A double smallest eigenvalue: any unit vector orthogonal to the largest axis will do.
        let rod = smallest_eigenpair(&Matrix3::from_diagonal(&Vector3::new(0.0, 3.0, 0.0)));
        assert!(rod.vector.y.abs() < 1e-12 && (rod.vector.norm() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_torso_bent_double_is_refused_by_default_and_oriented_on_request() {
        // Bent forward by 89 degrees: the normal is 1 degree from vertical, |n · f̂| = 0.017.
        let (p, s) = torso([0.0, 0.0, 1.0], 0.7, 1.553);
        assert_eq!(
            fit_torso_plane(&p[..4], &s[..4], None),
            Err(Error::AmbiguousOrientation)
        );
        let plane = fit_torso_plane_with(&p[..4], &s[..4], None, 0.0).unwrap();
        assert!((plane.azimuth - 0.7).abs() < 1e-9);
        assert!((plane.elevation - (FRAC_PI_2 + 1.553)).abs() < 1e-9);
        assert!(fit_torso_plane_with(&p, &s, None, 1.0).is_err());
    }

    #[test]
    fn shoulder_heading_agrees_with_the_plane_for_an_upright_torso() {
        let (p, s) = torso([1.0, 1.0, 1.0], -2.2, 0.0);
        let plane = fit_torso_plane(&p[..4], &s[..4], None).unwrap();
        let heading = shoulder_heading(p[0], p[1]).unwrap();
        assert!((heading.azimuth - plane.azimuth).abs() < 1e-12);
        assert!(shoulder_heading(p[0], [f64::NAN; 3]).is_err());
        assert_eq!(
            shoulder_heading([0.0, 0.0, 1.0], [0.0, 0.0, 1.5]),
            Err(Error::AmbiguousOrientation)
        );
    }
}
