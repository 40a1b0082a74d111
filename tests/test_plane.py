"""Torso plane against an SVD of the centred joints (NumPy), and the angle formulas of eq. 3.3/3.4."""

import numpy as np
import pytest

import torsocast as tc

SIDES = "LRLRC"  # left/right shoulder, left/right hip, thorax


def torso(yaw, pitch, offset, rng, noise=0.005):
    local = np.array([[0, 0.18, 0.5], [0, -0.18, 0.5], [0, 0.12, 0], [0, -0.12, 0], [0.02, 0, 0.45]])
    cp, sp, cy, sy = np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    pitch_m = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    yaw_m = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return local @ pitch_m.T @ yaw_m.T + offset + noise * rng.normal(size=(5, 3))


def svd_plane(points, weights):
    """Weighted least-squares plane by SVD, oriented by (left - right) x up: the reference."""
    w = weights / weights.sum()
    centre = w @ points
    _, _, vt = np.linalg.svd(np.sqrt(w)[:, None] * (points - centre))
    normal = vt[-1]
    lr = points[[0, 2]].mean(0) - points[[1, 3]].mean(0)
    if normal @ np.cross(lr, [0, 0, 1]) < 0:
        normal = -normal
    return centre, normal, np.arctan2(normal[1], normal[0]), np.arccos(normal[2])


def test_plane_equals_weighted_svd(rng):
    for _ in range(200):
        pts = torso(rng.uniform(-np.pi, np.pi), rng.uniform(-0.6, 0.6), rng.uniform(-4, 4, 3), rng)
        w = rng.uniform(0.1, 1.0, 5)
        plane = tc.fit_plane(pts, SIDES, w)
        centre, normal, az, el = svd_plane(pts, w)
        np.testing.assert_allclose(plane.centre, centre, atol=1e-12)
        np.testing.assert_allclose(plane.normal, normal, atol=1e-9)
        assert plane.azimuth == pytest.approx(az, abs=1e-9)
        assert plane.elevation == pytest.approx(el, abs=1e-9)
        assert plane.joints_used == 5


def test_batch_equals_single_frames_and_reports_bad_frames(rng):
    frames = np.stack([torso(y, 0.1, [1, 2, 1], rng) for y in np.linspace(-3, 3, 12)])
    frames[3, :3] = np.nan  # only two joints left
    frames[5] = [[0, 0, 0], [0, 1, 0], [0, 2, 0], [0, 3, 0], [0, 4, 0]]  # collinear
    out = tc.fit_planes(frames.astype(np.float32), SIDES)
    assert list(out["status"][[3, 5]]) == [tc.PlaneStatus.TOO_FEW_JOINTS, tc.PlaneStatus.COLLINEAR]
    assert np.isnan(out["azimuth"][[3, 5]]).all()
    for i in set(range(12)) - {3, 5}:
        single = tc.fit_plane(frames[i].astype(np.float32), SIDES)
        assert out["status"][i] == tc.PlaneStatus.OK
        assert out["azimuth"][i] == single.azimuth
        np.testing.assert_array_equal(out["normal"][i], single.normal)


def test_shoulder_heading_is_the_shoulder_line_rotated_about_gravity():
    centre, az = tc.shoulder_heading([1.0, 1.2, 1.4], [1.3, 0.9, 1.45])
    # (left - right) x z = (ly, -lx, 0) with left - right = (-0.3, 0.3, -0.05)
    assert az == pytest.approx(np.arctan2(0.3, 0.3))
    np.testing.assert_allclose(centre, [1.15, 1.05, 1.425])


def test_the_body_frame_of_a_fitted_torso_is_the_bodys_own_frame(rng):
    # A torso turned by a yaw and leant forward or back by a pitch: its own frame (x out of the
    # chest, y to its left, z up the spine) is SciPy's intrinsic z-then-y rotation, which the
    # plane's azimuth and elevation, put back together as a REP-155 body frame, must give.
    from scipy.spatial.transform import Rotation

    for _ in range(200):
        yaw, pitch = rng.uniform(-np.pi, np.pi), rng.uniform(-1.2, 1.2)
        offset = rng.uniform(-4, 4, 3)
        plane = tc.fit_plane(torso(yaw, pitch, offset, rng, noise=0)[:4], "LRLR")
        pose = [*plane.centre, plane.azimuth, plane.elevation]
        translation, rotation = tc.body_frame(pose)
        truth = Rotation.from_euler("ZY", [yaw, pitch])
        assert (Rotation.from_quat(rotation).inv() * truth).magnitude() < 1e-9
        np.testing.assert_allclose(translation, plane.centre)
        assert rotation[3] >= 0 and np.linalg.norm(rotation) == pytest.approx(1.0)
    with pytest.raises(tc.InvalidArgumentError, match="elevation"):
        tc.body_frame([0.0, 0.0, 1.0, 0.0, -0.2])
    with pytest.raises(tc.NonFiniteError, match="pose"):
        tc.body_frame([0.0, 0.0, np.inf, 0.0, 1.5])
    with pytest.raises(tc.ShapeError, match="pose"):
        tc.body_frame([0.0, 0.0, 1.0, 0.0])


def test_plane_errors_are_typed(rng):
    pts = torso(0.0, 0.0, [0, 0, 1], rng, noise=0)
    with pytest.raises(tc.TooFewJointsError, match="joints"):
        tc.fit_plane(pts[:2], "LR")
    with pytest.raises(tc.AmbiguousOrientationError):
        tc.fit_plane(pts, "CCCCC")
    with pytest.raises(tc.InvalidArgumentError, match="sides"):
        tc.fit_plane(pts, "LRLRX")
    with pytest.raises(tc.ShapeError, match="sides"):
        tc.fit_plane(pts, "LRLR")
    with pytest.raises(tc.ShapeError, match="joints"):
        tc.fit_plane(pts[:, :2], "LRLRC")
    with pytest.raises(tc.InvalidArgumentError, match="weights"):
        tc.fit_plane(pts, SIDES, [1, 1, -1, 1, 1])
    with pytest.raises(tc.TooFewJointsError):
        tc.shoulder_heading([np.nan, 0, 0], [0, 0, 0])
    assert issubclass(tc.TooFewJointsError, ValueError)


def test_min_orientation_cosine_zero_orients_a_torso_bent_double():
    # Shoulders 0.5 m from the hips along a direction 1 degree from straight down-forward.
    lean = np.radians(89.0)
    axis = np.array([np.sin(lean), 0.0, np.cos(lean)])
    joints = np.array([[0.0, 0.18, 0.0], [0.0, -0.18, 0.0], [0.0, 0.12, 0.0], [0.0, -0.12, 0.0]])
    joints[:2] += 0.5 * axis
    frames = joints[None] + np.array([0.0, 0.0, 1.0])
    assert tc.fit_planes(frames, "LRLR")["status"][0] == tc.PlaneStatus.AMBIGUOUS_ORIENTATION
    out = tc.fit_planes(frames, "LRLR", min_orientation_cosine=0.0)
    # Independent reference: SVD normal, signed along (left - right) x up.
    centred = frames[0] - frames[0].mean(axis=0)
    normal = np.linalg.svd(centred)[2][2]
    forward = np.cross(frames[0, 0] + frames[0, 2] - frames[0, 1] - frames[0, 3], [0.0, 0.0, 1.0])
    normal *= np.sign(normal @ forward)
    assert out["status"][0] == tc.PlaneStatus.OK
    assert np.allclose(out["normal"][0], normal, atol=1e-12)
    with pytest.raises(tc.InvalidArgumentError, match="min_orientation_cosine"):
        tc.fit_planes(frames, "LRLR", min_orientation_cosine=1.5)


def test_the_status_enums_are_the_cores_codes():
    from torsocast import _core

    assert {s.name: s.value for s in tc.PlaneStatus} == _core.PLANE_STATUS
    assert {s.name: s.value for s in tc.JointStatus} == _core.JOINT_STATUS
