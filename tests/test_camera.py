"""Intrinsics, distortion, depth lookup and frames, against closed forms and a real Kinect frame."""

import json

import numpy as np
import pytest
from PIL import Image

from conftest import shared_path
from torsocast.camera import Camera, DepthLookup, Intrinsics, level_camera

KINECT_V2 = (0.0956, -0.272, 9.7e-05, -0.000133, 0.0925)


def test_undistort_inverts_distort_and_deprojection_inverts_projection(rng):
    k = Intrinsics(364.7, 364.7, 255.8, 209.5, KINECT_V2)
    xy = rng.uniform(-0.65, 0.65, size=(500, 2))  # the Kinect v2 depth camera's field of view
    assert np.abs(k.undistort(k.distort(xy)) - xy).max() < 1e-9
    points = np.column_stack([xy * 3.0, np.full(500, 3.0)])
    uv = k.project(points)
    assert np.abs(k.deproject(uv, points[:, 2]) - points).max() < 1e-8


def test_deprojection_without_distortion_is_the_pinhole_closed_form():
    k = Intrinsics(525.0, 520.0, 320.0, 240.0)
    p = k.deproject(np.array([[425.0, 110.0], [320.0, 240.0]]), np.array([2.0, np.nan]))
    assert p[0] == pytest.approx([2.0 * 105 / 525, 2.0 * -130 / 520, 2.0])
    assert np.isnan(p[1]).all()
    with pytest.raises(ValueError, match="positive focal"):
        Intrinsics(0.0, 525.0, 320.0, 240.0)


def test_depth_lookup_takes_the_body_not_the_wall_and_nan_for_holes():
    depth = np.full((60, 80), 3.0, dtype=np.float32)
    depth[:, :40] = 1.2  # a body edge at column 40, wall behind
    depth[10:20, 60:70] = 0.0  # a hole
    lookup = DepthLookup(radius=3)
    uv = np.array([[40.0, 30.0], [20.0, 30.0], [65.0, 15.0], [-5.0, 3.0], [np.nan, 1.0]])
    z = lookup(depth, uv)
    assert z[:2] == pytest.approx([1.2, 1.2])  # edge keypoint: half wall, body wins
    assert np.isnan(z[2:]).all()
    assert lookup(depth, uv.reshape(1, 5, 2)).shape == (1, 5)


def test_level_camera_maps_optical_axes_to_rep103():
    t = level_camera(height=1.2)
    cam = Camera(Intrinsics(500, 500, 320, 240), t)
    # optical z (forward) -> world x, optical x (right) -> world -y, optical y (down) -> world -z
    assert cam.to_world(np.array([[0.0, 0.0, 2.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])) == pytest.approx(
        np.array([[2.0, 0.0, 1.2], [0.0, -1.0, 1.2], [0.0, 0.0, 0.2]])
    )
    down = Camera(Intrinsics(500, 500, 320, 240), level_camera(1.0, pitch=np.radians(30)))
    ahead = down.to_world(np.array([0.0, 0.0, 2.0]))
    assert ahead == pytest.approx([2 * np.cos(np.radians(30)), 0.0, 1.0 - 2 * np.sin(np.radians(30))])
    # And back: the world point 2 m ahead, on the tilted optical axis.
    assert down.to_optical(ahead) == pytest.approx([0.0, 0.0, 2.0])
    assert cam.to_optical(np.array([[2.0, 0.0, 1.2], [0.0, -1.0, 1.2]])) == pytest.approx(
        np.array([[0.0, 0.0, 2.0], [1.0, 0.0, 0.0]])
    )
    with pytest.raises(ValueError, match="rotation"):
        Camera(Intrinsics(500, 500, 320, 240), np.diag([1.0, 1.0, -1.0, 1.0]))


def test_panoptic_kinect_frame_deprojects_to_a_person_at_a_plausible_distance():
    base = shared_path("data", "rgbd", "panoptic_kinect_frame")
    sensor = json.loads((base / "kcalibration_171204_pose1.json").read_text())["sensors"][0]
    k_depth = np.array(sensor["K_depth"])
    # distCoeffs_depth holds 7 numbers; the first 5 are OpenCV's (k1, k2, p1, p2, k3).
    k = Intrinsics(
        k_depth[0, 0], k_depth[1, 1], k_depth[0, 2], k_depth[1, 2], tuple(sensor["distCoeffs_depth"][:5])
    )
    depth = np.load(base / "depth_424x512_f8.npy") / 1000.0
    v, u = np.mgrid[0 : depth.shape[0], 0 : depth.shape[1]]
    points = k.deproject(np.stack([u, v], axis=-1).astype(float), np.where(depth > 0, depth, np.nan))
    valid = depth > 0
    z = points[valid][:, 2]
    assert 0.5 < z.min() and z.max() < 8.0  # Kinect v2 reads 0.5 to 8 m along its axis
    # Corner rays leave at up to 45 degrees off the axis once undistorted (the lens' field of view).
    assert np.degrees(np.arctan(np.hypot(*points[valid][:, :2].T) / z).max()) < 50.0
    assert np.median(points[valid][:, 2]) == pytest.approx(4.3, abs=0.1)  # README: median 4308 mm
    with Image.open(base / "segmentation.png") as image:
        person = (np.asarray(image) > 0) & valid
    body = points[person]
    assert 2.3 < np.median(body[:, 2]) < 2.8  # the segmented person stands 2.5 m away
    height = np.percentile(body[:, 1], 99) - np.percentile(body[:, 1], 1)
    width = np.percentile(body[:, 0], 99) - np.percentile(body[:, 0], 1)
    assert 1.0 < height < 2.0 and 0.3 < width < 1.2  # metric, human-sized


def test_depth_lookup_matches_a_nan_aware_numpy_reference(rng):
    depth = rng.choice([0.0, 1.0, 1.05, 1.1, 2.5, 3.0], size=(40, 50)) + rng.normal(0, 0.01, (40, 50))
    depth[depth < 0.5] = 0.0
    lookup = DepthLookup(radius=2, band=0.15, min_valid=4)
    uv = rng.uniform(0, 49, size=(300, 2))
    uv[:, 1] = uv[:, 1] * 39 / 49
    got = lookup(depth.astype(np.float32), uv)
    for (u, v), z in zip(np.rint(uv).astype(int), got):
        window = depth[max(v - 2, 0) : v + 3, max(u - 2, 0) : u + 3].ravel()
        # the lookup clamps at the border (repeats edge pixels); compare only interior windows
        if window.size != 25:
            continue
        valid = window[(window >= lookup.min_depth) & (window <= lookup.max_depth)]
        if valid.size < lookup.min_valid:
            assert np.isnan(z)
            continue
        front = np.percentile(valid, 25)
        kept = valid[valid <= front + lookup.band]
        expected = np.median(kept) if kept.size >= lookup.min_valid else np.nan
        assert z == pytest.approx(expected, abs=1e-6, nan_ok=True)
