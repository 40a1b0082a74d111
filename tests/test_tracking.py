"""Per-person chain (swap correction, gating, plane or shoulders, forecaster grid) and the
multi-person tracker, on synthetic people whose poses are known exactly."""

from typing import Any

import numpy as np
import pytest

import torsocast as tc
from conftest import pose_of
from torsocast.keypoints import coco
from torsocast.tracker import PersonConfig, Tracker, TrackerConfig

CAMERA = np.zeros(3)  # camera at the world origin, people in front of it along +x
# The joints built here are joint centres, not a depth camera's surface points.
CENTRES = PersonConfig(surface_depth=(0.0, 0.0))


def person(centre, yaw, hips=True) -> tuple[np.ndarray, np.ndarray]:
    """17 world joints and scores of an upright person at ``centre`` facing azimuth ``yaw``, with
    a visible face when it faces the camera at the origin."""
    forward = np.array([np.cos(yaw), np.sin(yaw), 0.0])
    left = np.array([-np.sin(yaw), np.cos(yaw), 0.0])
    up = np.array([0.0, 0.0, 1.0])
    c = np.asarray(centre, dtype=float)
    joints = np.full((17, 3), np.nan)
    joints[coco.LEFT_SHOULDER] = c + 0.2 * left + 0.25 * up
    joints[coco.RIGHT_SHOULDER] = c - 0.2 * left + 0.25 * up
    joints[coco.LEFT_HIP] = c + 0.12 * left - 0.25 * up
    joints[coco.RIGHT_HIP] = c - 0.12 * left - 0.25 * up
    joints[coco.NOSE] = c + 0.55 * up + 0.1 * forward
    scores = np.zeros(17)
    scores[list(coco.TORSO)] = 0.9
    if not hips:
        joints[[coco.LEFT_HIP, coco.RIGHT_HIP]] = np.nan
        scores[[coco.LEFT_HIP, coco.RIGHT_HIP]] = 0.0
    faces_camera = forward @ (CAMERA - c) > 0
    scores[coco.NOSE] = 0.9 if faces_camera else 0.05
    return joints, scores


def swap_sides(values):
    """The rows of ``values`` with every left/right pair exchanged, as a detector seeing a back
    labels them."""
    out = values.copy()
    for left, right in coco.LEFT_RIGHT_PAIRS:
        out[[left, right]] = values[[right, left]]
    return out


def test_a_turning_person_keeps_the_detectors_labels_and_a_short_swap_is_undone():
    # YOLO-pose and MoveNet label the sides right in back views too (every frame of the real
    # turntable sequence, with three models), so the labels decide; a detector's swap of a few
    # frames is exchanged back.
    track = tc.Person(CENTRES)
    yaws = np.pi + np.radians(np.arange(0, 360, 4))  # facing the camera, then turning round
    errors, swaps = [], 0
    for k, yaw in enumerate(yaws):
        joints, scores = person([2.0, 0.0, 1.0], yaw)
        swap = 40 <= k < 44  # 0.16 s of exchanged labels, in the back view
        if swap:
            joints, scores = swap_sides(joints), swap_sides(scores[:, None])[:, 0]
        obs = track.update(k / 25, joints, scores, CAMERA)
        assert obs.estimate == "plane"
        swaps += obs.swapped
        assert obs.swapped == swap and not obs.reoriented
        errors.append(np.angle(np.exp(1j * (pose_of(obs)[3] - yaw))))
    assert np.abs(errors).max() < 1e-9 and swaps == 4
    assert pose_of(obs)[4] == pytest.approx(np.pi / 2)


def test_a_track_born_facing_away_takes_the_labels_and_turns_round_on_steady_evidence():
    joints, scores = person([2.0, 0.5, 1.0], 0.2)  # back to the camera, no face in sight
    obs = tc.Person().update(0.0, joints, scores, CAMERA)
    assert not obs.swapped and pose_of(obs)[3] == pytest.approx(0.2)
    # Born with the sides exchanged (facing the camera, its face not found), then labelled
    # right with the nose in front: the track turns round once and stays.
    track = tc.Person()
    flips = []
    for k in range(30):
        j, s = person([2.0, 0.5, 1.0], np.pi + 0.005 * k)
        if k == 0:
            j, s = swap_sides(j), swap_sides(s[:, None])[:, 0]
            s[coco.NOSE] = 0.0
        obs = track.update(k / 25, j, s, CAMERA)
        flips.append(obs.reoriented)
    assert flips.index(True) == 1 and sum(flips) == 1
    assert pose_of(obs)[3] == pytest.approx(tc.wrap_angle(np.pi + 0.005 * 29))


def with_bent_knees(joints, scores, yaw, bend=0.08):
    """``joints`` with legs under the hips whose knees stand ``bend`` m forwards of them."""
    forward = np.array([np.cos(yaw), np.sin(yaw), 0.0])
    joints, scores = joints.copy(), scores.copy()
    for hip, knee, ankle in ((11, 13, 15), (12, 14, 16)):
        joints[knee] = joints[hip] + [0.0, 0.0, -0.4] + bend * forward
        joints[ankle] = joints[hip] + [0.0, 0.0, -0.8]
        scores[[knee, ankle]] = 0.9
    return joints, scores


def test_bent_knees_keep_the_heading_where_the_detector_mostly_exchanges_the_labels():
    # Back to the camera (no face seen), labels exchanged in two frames of three for two
    # seconds: the knees, which do not depend on the labels, keep the true heading; without
    # them (knee_weight=0) the exchanged labels win and the track faces the camera.
    yaw = 0.3
    for knee_weight, want in ((PersonConfig().knee_weight, yaw), (0.0, yaw + np.pi)):
        track = tc.Person(PersonConfig(knee_weight=knee_weight))
        for k in range(50):
            joints, scores = with_bent_knees(*person([2.0, 0.5, 1.0], yaw), yaw)
            if k % 3:
                joints, scores = swap_sides(joints), swap_sides(scores[:, None])[:, 0]
            obs = track.update(k / 25, joints, scores, CAMERA)
        assert tc.wrap_angle(pose_of(obs)[3] - want) == pytest.approx(0.0, abs=1e-9), knee_weight
    with pytest.raises(tc.InvalidArgumentError, match="knee_weight"):
        PersonConfig(knee_weight=-1.0)


def test_a_heading_is_confident_only_where_a_cue_beside_the_labels_agrees():
    # Back to the camera with straight legs: the labels alone, for four seconds, never make the
    # heading confident, and its evidence approaches the facing memory's worth (1 s). The
    # same person with bent knees is confident within half a second and stays so.
    yaw, memory = 0.3, PersonConfig().facing_memory
    for bent in (False, True):
        track = tc.Person()
        confident = []
        for k in range(100):
            joints, scores = person([2.0, 0.5, 1.0], yaw)
            if bent:
                joints, scores = with_bent_knees(joints, scores, yaw)
            obs = track.update(k / 25, joints, scores, CAMERA)
            confident.append(obs.heading_confident)
        if bent:
            assert confident.index(True) <= 12 and all(confident[12:])
            assert obs.facing_evidence > 2 * memory
        else:
            assert not any(confident)
            # The labels build step / (1 - exp(-step / memory)) at most: memory + step / 2 or so.
            assert 0.95 * memory < obs.facing_evidence < memory + 0.5 / 25
    # A frame without a heading has no evidence.
    nothing = tc.Person().update(0.0, np.full((17, 3), np.nan), np.zeros(17), CAMERA)
    assert nothing.facing_evidence == 0.0 and not nothing.heading_confident


def test_without_hips_the_azimuth_comes_from_the_shoulders():
    track = tc.Person(CENTRES)
    joints, scores = person([2.0, 0.0, 1.0], 2.5)
    track.update(0.0, joints, scores, CAMERA)  # plane: learns where the centre sits
    joints, scores = person([2.02, 0.0, 1.0], 2.6, hips=False)
    obs = track.update(0.04, joints, scores, CAMERA)
    assert obs.estimate == "shoulders"
    assert pose_of(obs)[3] == pytest.approx(2.6)
    assert pose_of(obs)[:3] == pytest.approx([2.02, 0.0, 1.0])


def test_the_plane_goes_through_the_joint_centres_behind_the_surface():
    # The default takes joints for a depth camera's surface points: the shoulders and the hips
    # move back by their depths, along the ray to the torso, before the plane is fitted.
    joints, scores = person([3.0, 1.0, 1.0], np.pi)
    obs = tc.Person().update(0.0, joints, scores, CAMERA)
    torso = joints[list(coco.TORSO)]
    ray = torso.mean(axis=0) - CAMERA
    depths = np.repeat(PersonConfig().surface_depth, 2)[:, None]
    moved = torso + depths * ray / np.linalg.norm(ray)
    plane = tc.fit_planes(moved[None], coco.TORSO_SIDES)
    assert pose_of(obs)[:3] == pytest.approx(plane["centre"][0], abs=1e-9)
    assert pose_of(obs)[3:] == pytest.approx([plane["azimuth"][0], plane["elevation"][0]], abs=1e-9)
    # Facing the camera, the hips moved back further than the shoulders lean the chest down.
    assert pose_of(obs)[4] > np.pi / 2 + 1e-3


def test_frames_faster_than_the_grid_are_skipped_and_gaps_are_filled():
    track = tc.Person()
    grid = []
    for t in [0.0, 1 / 30, 2 / 30, 3 / 30, 4 / 30, 0.28]:
        joints, scores = person([2.0, 0.0, 1.0], 3.0)
        grid.append(track.update(t, joints, scores, CAMERA).grid)
    # 30 fps onto 25 Hz slots 0, 1, 2, 3, 3 (skipped), then slot 7 after three empty slots.
    assert [g["skipped"] for g in grid] == [False, False, False, False, True, False]
    assert grid[-1]["filled"] == 3 and not grid[-1]["restarted"]
    assert len(track) == 8


def test_gate_replaces_a_jumping_joint():
    track = tc.Person()
    joints, scores = person([2.0, 0.0, 1.0], np.pi)
    track.update(0.0, joints, scores, CAMERA)
    joints[coco.LEFT_HIP] += [0.5, 0.0, 0.0]  # a depth reading from the wall
    obs = track.update(0.04, joints, scores, CAMERA)
    assert obs.joint_status[coco.LEFT_HIP] == tc.JointStatus.REPLACED
    assert pose_of(obs)[3] == pytest.approx(np.pi)


def walkers(t):
    """Two people walking towards each other 1.2 m apart in y, and a third who appears at 0.4 s."""
    a = person([1.0 + 1.0 * t, 0.6, 1.0], 0.0)
    b = person([4.0 - 1.0 * t, -0.6, 1.0], np.pi)
    c = person([3.0, 2.0, 1.0], np.pi)
    people = [a, b] + ([c] if t >= 0.4 else [])
    return np.array([p[0] for p in people]), np.array([p[1] for p in people])


def test_tracker_keeps_ids_through_a_crossing_and_a_missed_frame():
    tracker = Tracker(TrackerConfig(min_hits=3, max_missing=0.5, person=CENTRES))
    ids_a, ids_b, ids_c = set(), set(), set()
    for k in range(75):
        t = k / 25
        joints, scores = walkers(t)
        if k == 30:
            joints, scores = joints[[1, 2]], scores[[1, 2]]  # person a is not detected
        results = tracker.update(t, joints, scores, CAMERA)
        found = {r.detection: r.track_id for r in results}
        if k == 30:
            ids_b.add(found[0])
            continue
        ids_a.add(found[0])
        ids_b.add(found[1])
        if t >= 0.4:
            ids_c.add(found[2])
    # Confirmed after 3 frames: None before, then one stable id each.
    assert ids_a == {None, 1} and ids_b == {None, 2} and ids_c == {None, 3}
    assert [t.id for t in tracker.tracks] == [1, 2, 3]
    forecast = tracker.forecast(1, [0.4])
    assert forecast is not None
    # x ahead of a, who walks at 1 m/s: the damped trend carries 1.5 (1 - e^(-0.4/1.5)) m in
    # 0.4 s; the 1 Hz zero-phase filter's end effect on the ramp costs a few centimetres more.
    carried = 1.5 * (1 - np.exp(-0.4 / 1.5))
    assert forecast[0, 0] == pytest.approx(1.0 + 74 / 25 + carried, abs=0.08)


def test_tracker_drops_tracks_and_refuses_far_matches():
    tracker = Tracker(TrackerConfig(min_hits=1, max_missing=0.2, gate=0.5))
    joints, scores = walkers(0.0)
    tracker.update(0.0, joints[:1], scores[:1], CAMERA)
    far = joints[:1] + [1.0, 0.0, 0.0]  # 1 m away in one frame: a different person
    results = tracker.update(0.04, far, scores[:1], CAMERA)
    assert results[0].track_id == 2
    tracker.update(0.5, np.zeros((0, 17, 3)), np.zeros((0, 17)), CAMERA)
    assert tracker.tracks == []


def test_a_frame_that_goes_back_in_time_is_refused_and_changes_nothing():
    tracker = Tracker(TrackerConfig(min_hits=1))
    joints, scores = walkers(0.0)
    tracker.update(0.0, joints, scores, CAMERA)
    tracker.update(0.04, joints, scores, CAMERA)
    before = [(t.id, t.samples, t.last_time) for t in tracker.tracks]
    for t in (0.04, 0.02):
        with pytest.raises(tc.TimeNotIncreasingError, match="not after"):
            tracker.update(t, joints + 5.0, scores, CAMERA)
    assert [(t.id, t.samples, t.last_time) for t in tracker.tracks] == before


def test_detection_centres_prefer_the_torso_and_ignore_empty_detections():
    # Association goes by the mean of the seen torso joints, else of every seen joint; a
    # detection with nothing seen in 3D gets no track.
    tracker = Tracker(TrackerConfig(min_hits=1, gate=0.05))
    joints, scores = walkers(0.4)
    joints[1, list(coco.TORSO)] = np.nan  # only the nose of person b is seen
    scores[2] = 0.0  # nothing of person c is believed
    first = tracker.update(0.0, joints, scores, CAMERA)
    assert [r.track_id for r in first] == [1, 2, None] and first[2].observation is None
    # Moved so that only centres taken this way stay within the 5 cm gate.
    joints[0] += [0.03, 0.0, 0.0]
    joints[1, coco.NOSE] += [0.03, 0.0, 0.0]
    again = tracker.update(0.04, joints, scores, CAMERA)
    assert [r.track_id for r in again] == [1, 2, None]


def test_the_core_person_refuses_bad_shapes_and_values_without_changing_state():
    p = tc.Person()
    joints, scores = person([2.0, 0.0, 1.0], 3.0)
    p.update(0.0, joints, scores, CAMERA)
    with pytest.raises(tc.ShapeError, match="joints"):
        p.update(0.04, joints[:16], scores, CAMERA)
    with pytest.raises(tc.ShapeError, match="scores"):
        p.update(0.04, joints, scores[:16], CAMERA)
    with pytest.raises(tc.NonFiniteError, match="camera_position"):
        p.update(0.04, joints, scores, [np.nan, 0.0, 0.0])
    with pytest.raises(tc.InvalidArgumentError, match="facing_memory"):
        PersonConfig(facing_memory=0.0)
    with pytest.raises(tc.InvalidArgumentError, match="min_score"):
        PersonConfig(min_score=2.0)  # a score is a probability: 2 was accepted
    assert len(p) == 1 and p.last_time == 0.0
    obs = p.update(0.04, joints.astype(np.float32), scores.tolist(), (0, 0, 0))  # any array-like
    assert obs.estimate == "plane" and obs.grid == {"filled": 0, "restarted": False, "skipped": False}
    assert obs.joints.shape == (17, 3) and np.isnan(obs.joints[13]).all()  # a knee: never seen
    assert "plane" in repr(obs)
    assert p.config.forecaster == tc.ForecasterConfig.live()


def test_configs_are_frozen_values_built_from_the_cores_defaults():
    import pickle

    config = TrackerConfig()
    assert config == TrackerConfig(person=PersonConfig(), depth=tc.DepthLookup())
    assert config.person.forecaster == tc.ForecasterConfig.live() and config.person.self_check
    changed = config.replace(gate=0.5, person=config.person.replace(face_weight=0.0))
    assert (changed.gate, changed.person.face_weight, changed.min_hits) == (0.5, 0.0, config.min_hits)
    assert changed != config and config.gate != 0.5  # replace() leaves the original alone
    methods: list[Any] = tc.ForecasterConfig.options()["method"]  # names, as the stubs' literals
    forecasters = [tc.ForecasterConfig(m) for m in methods]
    for value in (config, changed, config.person, config.depth, *forecasters):
        assert pickle.loads(pickle.dumps(value)) == value
        assert eval(repr(value), vars(tc)) == value  # the repr is the constructor call
    with pytest.raises(AttributeError):
        config.gate = 1.0  # type: ignore[misc]
    with pytest.raises(TypeError, match="unexpected keyword"):
        config.replace(gates=1.0)
    for bad in (dict(gate=0.0), dict(min_hits=0), dict(capacity=0), dict(max_detections=10**9)):
        with pytest.raises(tc.InvalidArgumentError, match=next(iter(bad))):
            TrackerConfig(**bad)
    assert tc.Person(PersonConfig(gate_max_replacements=3)).config.gate_max_replacements == 3
    for depths in ((-0.01, 0.09), (0.06, 0.5), (float("nan"), 0.09)):
        with pytest.raises(tc.InvalidArgumentError, match="surface_depth"):
            PersonConfig(surface_depth=depths)
    assert PersonConfig(surface_depth=(0.0, 0.0)).surface_depth == (0.0, 0.0)
    # A grid the forecaster takes with a short history, but at which every track's self-check
    # would keep 2e9 predictions: the process aborted on the allocation when a track opened.
    fast = tc.ForecasterConfig("constant_velocity", rate_hz=1e9, history=1e-7)
    with pytest.raises(tc.InvalidArgumentError, match="rate_hz"):
        PersonConfig(forecaster=fast)
    assert not tc.Person(PersonConfig(forecaster=fast, self_check=False)).config.self_check


def test_a_walkers_track_checks_its_forecasts_and_gives_intervals():
    # Walking along +y at 1 m/s facing +y, with a little keypoint noise: the centre trend comes
    # true, so after its checks the track continues it, with finite 80 % half-widths.
    rng = np.random.default_rng(3)
    track = tc.Person()
    assert track.intervals([0.4]) is None
    for k in range(100):
        t = k / 25
        joints, scores = person([3.0, 1.0 * t, 1.0], np.pi / 2)
        track.update(t, joints + rng.normal(0.0, 0.005, joints.shape), scores, CAMERA)
        if k == 2:
            assert track.intervals([0.4]) is None  # too short a history for a line
        if k == 5:
            early = track.intervals([0.4])  # nothing checked yet: the history's line speaks
            assert early is not None
            assert early.shape == (1, 5) and np.isfinite(early).all() and (early > 0).all()
    ahead = track.forecast([1.0])
    assert ahead is not None
    # More of the walk than the damped trend alone carries (1.5 (1 - e^(-1/1.5)) = 0.73 m).
    assert 0.75 < ahead[0, 1] - 99 / 25 < 1.1
    half = track.intervals([0.4, 1.0, 2.0])
    assert half is not None
    assert half.shape == (3, 5) and np.isfinite(half).all() and (half > 0).all()
    assert half[0, 1] < 0.3  # the walking direction's error at 0.4 s stays within decimetres
    with pytest.raises(tc.InvalidArgumentError, match="horizons"):
        track.intervals([-1.0])


def test_a_refused_frame_leaves_the_tracker_as_it_was():
    # The time stamp was stored before the frame was checked: a NaN stamp on the first frame
    # refused every later frame, and bad arrays used up the frame's time slot.
    tracker = Tracker()
    joints, scores = person([2.0, 0.0, 1.0], np.pi)
    good = (joints[None], scores[None], CAMERA)
    bad_frames: list[tuple[Any, ...]] = [
        (float("nan"), *good),
        (float("inf"), *good),
        (0.0, joints, scores, CAMERA),  # unbatched joints
        (0.0, joints[None], scores[None, :5], CAMERA),  # wrong-length scores
        (0.0, joints[None], scores[None], [np.nan, 0.0, 0.0]),
        (0.0, joints[None], 5.0 * scores[None], CAMERA),
    ]
    for t, j, s, camera in bad_frames:
        with pytest.raises(tc.TorsocastError):
            tracker.update(t, j, s, camera)
        assert tracker.last_time is None and len(tracker) == 0
    assert len(tracker.update(0.0, *good)) == 1
    with pytest.raises(tc.InvalidArgumentError, match="horizons"):  # checked before the frame
        tracker.update(0.04, *good, horizons=[-1.0])
    assert tracker.last_time == 0.0


def test_linear_assignment_matches_scipy(rng):
    from scipy.optimize import linear_sum_assignment

    for rows, cols in [(1, 1), (3, 5), (5, 3), (6, 6), (20, 17), (50, 50)]:
        cost = rng.uniform(0.0, 3.0, size=(rows, cols))
        cost[rng.random(cost.shape) < 0.3] = 1e6  # pairs beyond the gate, as the tracker passes them
        r, c = tc.linear_assignment(cost)
        want_r, want_c = linear_sum_assignment(cost)
        assert len(r) == len(want_r) == min(rows, cols)
        assert cost[r, c].sum() == pytest.approx(cost[want_r, want_c].sum(), rel=1e-12)
        assert (np.diff(r) > 0).all() and len(set(c.tolist())) == len(c)
    with pytest.raises(tc.NonFiniteError, match="cost"):
        tc.linear_assignment(np.array([[1.0, np.nan]]))


def test_the_runtime_and_a_full_run_need_no_scipy(tmp_path):
    import subprocess
    import sys

    from conftest import shared_path

    turntable = shared_path("data", "rgbd", "turntable")
    code = f"""
import importlib.abc, sys
class NoScipy(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name == "scipy" or name.startswith("scipy."):
            raise ImportError("SciPy is not installed here")
sys.meta_path.insert(0, NoScipy())
import torsocast
from torsocast.cli import main
sys.exit(main(["run", {str(turntable)!r}, "--out", {str(tmp_path / "out")!r}]))
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "100 frames" in done.stdout and (tmp_path / "out" / "frames.jsonl").is_file()


def test_trackers_stepped_in_threads_give_the_serial_results():
    # Tracker.step releases the GIL while the core works: trackers of different streams run in
    # parallel threads, and each gives exactly what it gives alone.
    from concurrent.futures import ThreadPoolExecutor

    from torsocast.camera import Intrinsics, level_camera

    k = Intrinsics(300.0, 300.0, 160.0, 120.0, (0.05, -0.01, 0.0, 0.0, 0.0))
    pose = level_camera(1.0, 0.1)

    def stream(seed):
        rng = np.random.default_rng(seed)
        depth = (2.0 + rng.random((240, 320))).astype(np.float32)
        frames = []
        for i in range(60):
            keypoints = np.zeros((3, 17, 3))
            keypoints[..., 0] = 60 + 80 * np.arange(3)[:, None] + rng.normal(0, 2, (3, 17)) + i
            keypoints[..., 1] = 40 + 9 * np.arange(17) + rng.normal(0, 2, (3, 17))
            keypoints[..., 2] = 0.9
            frames.append((i / 30, keypoints, depth))
        return frames

    def run(frames):
        tracker, out = Tracker(TrackerConfig(min_hits=1)), []
        for t, keypoints, depth in frames:
            joints, people = tracker.step(
                t, keypoints, depth, (k.fx, k.fy, k.cx, k.cy), k.coefficients, pose, [0.5]
            )
            out.append((joints, [(p.track_id, p.forecast) for p in people]))
        return out

    streams = [stream(seed) for seed in range(4)]
    serial = [run(s) for s in streams]
    with ThreadPoolExecutor(4) as pool:
        parallel = list(pool.map(run, streams))
    for a, b in zip(serial, parallel):
        for (ja, pa), (jb, pb) in zip(a, b):
            np.testing.assert_array_equal(ja, jb)
            assert [i for i, _ in pa] == [i for i, _ in pb]
            for (_, fa), (_, fb) in zip(pa, pb):
                assert (fa is None and fb is None) or np.array_equal(fa, fb)
    assert any(f is not None for _, people in serial[0] for _, f in people)


def test_a_joint_too_far_to_be_a_body_is_missing_not_a_pose_the_forecaster_refuses():
    # The fuzz harness found a joint at 1e308 m making a pose the forecaster refused after the
    # track had taken the frame: the refused frame had changed the track.
    tracker = Tracker(TrackerConfig(min_hits=1))
    joints, scores = person([2.0, 0.0, 1.0], np.pi)
    for k in range(10):
        tracker.update(k / 25, joints[None], scores[None], CAMERA)
    far = joints.copy()
    far[coco.LEFT_HIP] = [1e308, 0.0, 1.0]
    observation = tracker.update(0.4, far[None], scores[None], CAMERA)[0].observation
    assert observation is not None
    assert observation.estimate == "plane" and np.isfinite(pose_of(observation)).all()
    # The far joint was missing: the gate held its last position over instead of measuring it.
    assert observation.joint_status[coco.LEFT_HIP] == tc.JointStatus.REPLACED
    with pytest.raises(tc.InvalidArgumentError, match="camera_position"):
        tracker.update(0.44, joints[None], scores[None], [1e308, 0.0, 0.0])
    assert tracker.last_time == 0.4


def test_a_keypoint_off_the_image_is_never_lifted():
    # A keypoint model guesses joints out of view (a person cut by the image edge) with pixel
    # coordinates outside the image and sometimes a high score: the JSON output gives them as the
    # model did, and no 3D joint is made of them (the depth window is off the image).
    from torsocast.tracker import Tracker, TrackerConfig

    depth = np.full((240, 320), 2.5, dtype=np.float32)
    keypoints = np.zeros((1, 17, 3))
    keypoints[0, :, 0] = 100 + 5 * np.arange(17)
    keypoints[0, :, 1] = 40 + 9 * np.arange(17)
    keypoints[0, :, 2] = 0.9
    keypoints[0, 3] = (-40.0, 100.0, 0.95)  # left of the image
    keypoints[0, 4] = (330.0, 100.0, 0.95)  # right of it
    keypoints[0, 5] = (100.0, 250.0, 0.95)  # below it
    camera_to_world = np.eye(4)
    joints, _ = Tracker(TrackerConfig()).step(
        0.0, keypoints, depth, (300.0, 300.0, 160.0, 120.0), (0.0,) * 5, camera_to_world
    )
    lifted = np.isfinite(joints[0]).all(axis=1)
    assert not lifted[[3, 4, 5]].any() and lifted[[0, 1, 2, 6, 7]].all()


def test_the_joints_as_lifted_track_the_frame_again_as_it_was_tracked():
    # A person 4 m away whose right shoulder and hip read the depth of someone 1.2 m nearer
    # (the keypoints fall on the person in front): the tracks take that detection without them;
    # the joints as lifted keep them, and tracked again they give the same frame.
    front, front_scores = person([2.8, 0.0, 1.2], np.pi)
    behind, behind_scores = person([4.0, 0.1, 1.2], np.pi)
    for joint in (coco.RIGHT_SHOULDER, coco.RIGHT_HIP):
        behind[joint] = front[joint] + [0.0, 0.05, 0.0]
    joints, scores = np.stack([front, behind]), np.stack([front_scores, behind_scores])
    config = TrackerConfig(min_hits=1, person=CENTRES)
    live, again = Tracker(config), Tracker(config)

    def seen(outcomes):
        return [(o.track_id, o.observation.joints.tolist()) for o in outcomes]

    for k in range(5):
        t = k / 15
        out = live.update(t, joints, scores, CAMERA)
        assert out[1].observation is not None
        taken = out[1].observation.joints
        assert np.isnan(taken[[coco.RIGHT_SHOULDER, coco.RIGHT_HIP]]).all()
        np.testing.assert_array_equal(live.lifted, joints)
        replayed = again.update(t, live.lifted, scores, CAMERA)
        assert str(seen(replayed)) == str(seen(out))
