"""Property tests of the public entry points: any input gives either a typed error that leaves
the object as it was, or a finite result (hypothesis draws the inputs, including NaN, infinity,
huge and tiny values)."""

from typing import Any

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import torsocast as tc
from conftest import run_cli

#: Floats as a hostile caller sends them: NaN, infinities, huge and tiny magnitudes included.
ANY_FLOAT = st.floats(allow_nan=True, allow_infinity=True, width=64)


def any_points(least, most=None):
    """Lists of ``least`` to ``most`` (default: exactly ``least``) 3D points of any floats."""
    return st.lists(st.lists(ANY_FLOAT, min_size=3, max_size=3), min_size=least, max_size=most or least)


SETTINGS = settings(
    max_examples=150, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow]
)


def walking(forecaster, n=30):
    for k in range(n):
        forecaster.update([0.04 * k, 0.1, 1.0, 0.02 * k, 1.5], k / 25, 1.0)


@SETTINGS
@given(pose=st.lists(ANY_FLOAT, min_size=5, max_size=5), t=ANY_FLOAT, weight=ANY_FLOAT)
def test_a_forecaster_update_is_taken_whole_or_refused_whole(pose, t, weight):
    f = tc.Forecaster(tc.ForecasterConfig.live())
    walking(f)
    before = (len(f), f.last_time, f.forecast([0.4, 1.0]).tobytes())
    try:
        f.update(pose, t, weight)
    except tc.TorsocastError:
        assert (len(f), f.last_time, f.forecast([0.4, 1.0]).tobytes()) == before
        return
    if len(f) >= f.min_samples:  # a long gap restarts the history with this one sample
        assert np.isfinite(f.forecast([0.4, 1.0, 2.0])).all()


@SETTINGS
@given(horizons=st.lists(ANY_FLOAT, min_size=1, max_size=4))
def test_a_forecast_is_finite_or_a_typed_error(horizons):
    f = tc.Forecaster()
    walking(f)
    try:
        out = f.forecast(horizons)
    except tc.TorsocastError:
        return
    assert out.shape == (len(horizons), 5) and np.isfinite(out).all()


@SETTINGS
@given(
    joints=any_points(17),
    scores=st.lists(ANY_FLOAT, min_size=17, max_size=17),
    t=ANY_FLOAT,
)
def test_a_person_takes_a_frame_whole_or_refuses_it_whole(joints, scores, t):
    person = tc.Person()
    rng = np.random.default_rng(0)
    for k in range(10):
        good = np.array([[2.0, -0.18, 1.4], [2.0, 0.18, 1.4], [2.0, -0.12, 0.9], [2.0, 0.12, 0.9]])
        j = np.full((17, 3), np.nan)
        j[[5, 6, 11, 12]] = good + rng.normal(0, 0.005, good.shape)
        s = np.zeros(17)
        s[[5, 6, 11, 12]] = 0.9
        person.update(k / 25, j, s, [0.0, 0.0, 1.2])
    ahead = person.forecast([0.4])
    assert ahead is not None
    before = (len(person), person.last_time, ahead.tobytes())
    try:
        obs = person.update(t, joints, scores, [0.0, 0.0, 1.2])
    except tc.TorsocastError:
        after = person.forecast([0.4])
        assert after is not None
        assert (len(person), person.last_time, after.tobytes()) == before
        return
    assert obs.pose is None or np.isfinite(obs.pose).all()
    ahead = person.forecast([0.4, 1.0])
    assert ahead is None or np.isfinite(ahead).all()
    half = person.intervals([0.4])
    assert half is None or (np.isfinite(half).all() and (half >= 0).all())


@SETTINGS
@given(
    cost=st.integers(0, 6).flatmap(
        lambda r: st.integers(0, 6).flatmap(
            lambda c: st.lists(st.lists(ANY_FLOAT, min_size=c, max_size=c), min_size=r, max_size=r)
        )
    )
)
def test_an_assignment_is_one_to_one_and_optimal_or_a_typed_error(cost):
    cost = np.array(cost, dtype=np.float64).reshape(len(cost), -1 if cost and cost[0] else 0)
    try:
        rows, cols = tc.linear_assignment(cost)
    except tc.TorsocastError:
        assert not np.isfinite(cost).all()
        return
    assert len(rows) == min(cost.shape) and len(set(cols.tolist())) == len(cols)


@SETTINGS
@given(points=any_points(1, 6))
def test_a_plane_fit_is_finite_or_a_typed_error(points):
    sides = "LRLRCC"[: len(points)]
    try:
        plane = tc.fit_plane(np.array(points), sides=sides)
    except tc.TorsocastError:
        return
    assert np.isfinite([plane.azimuth, plane.elevation, *plane.centre, *plane.normal]).all()


@pytest.mark.parametrize("size", [0, -1, 10**12, 2**63])
def test_sizes_from_callers_are_typed_errors(size):
    with pytest.raises((tc.TorsocastError, OverflowError)):
        tc.JointGate(size)


def _tracker_state(tracker):
    """What a refused frame must not change: the time, the live tracks, each confirmed track's
    history and forecast."""
    tracks = [(s.id, s.key, s.samples, s.last_time) for s in tracker.tracks]
    ahead = [tracker.forecast(s.id, [0.4, 1.0]) for s in tracker.tracks]
    return tracker.last_time, len(tracker), tracks, [None if a is None else a.tobytes() for a in ahead]


def _walkers(tracker, frames=20):
    rng = np.random.default_rng(1)
    for k in range(frames):
        joints = np.stack([[2.0 + 0.04 * k, y, 1.0] + rng.normal(0, 0.01, (17, 3)) for y in (-1.0, 1.0)])
        joints[:, 5:7, 1] += [[0.18, -0.18]]  # shoulders apart: a torso plane to fit
        joints[:, 11:13, 1] += [[0.12, -0.12]]
        joints[:, 11:13, 2] -= 0.5
        tracker.update(k / 25, joints, np.full((2, 17), 0.9), [0.0, 0.0, 1.0])


@SETTINGS
@given(
    joints=st.lists(any_points(17), max_size=3),
    score=ANY_FLOAT,
    t=ANY_FLOAT,
    camera=st.lists(ANY_FLOAT, min_size=3, max_size=3),
)
def test_a_tracker_takes_a_frame_whole_or_refuses_it_whole(joints, score, t, camera):
    tracker = tc.Tracker(tc.TrackerConfig(min_hits=1))
    _walkers(tracker)
    before = _tracker_state(tracker)
    j = np.array(joints, dtype=float).reshape(-1, 17, 3)
    scores = np.full(j.shape[:2], score)
    try:
        out = tracker.update(t, j, scores, camera, [0.4, 1.0])
    except tc.TorsocastError:
        assert _tracker_state(tracker) == before
        return
    assert len(out) == len(j) and tracker.last_time == t
    for outcome in out:
        pose = outcome.observation.pose if outcome.observation is not None else None
        assert pose is None or np.isfinite(pose).all()
        assert outcome.forecast is None or np.isfinite(outcome.forecast).all()


@SETTINGS
@given(
    uv=st.lists(st.tuples(ANY_FLOAT, ANY_FLOAT), min_size=17, max_size=17),
    depth_value=ANY_FLOAT,
    intrinsics=st.tuples(ANY_FLOAT, ANY_FLOAT, ANY_FLOAT, ANY_FLOAT),
)
def test_a_tracker_step_lifts_any_pixels_to_finite_joints_or_refuses(uv, depth_value, intrinsics):
    tracker = tc.Tracker()
    keypoints = np.array([[u, v, 0.9] for u, v in uv])[None]
    with np.errstate(over="ignore"):  # a huge reading becomes an infinite float32 one: also hostile
        depth = np.full((48, 64), depth_value, dtype=np.float32)
    camera_to_world = np.eye(4)
    try:
        joints, out = tracker.step(0.0, keypoints, depth, intrinsics, (0.0,) * 5, camera_to_world)
    except tc.TorsocastError:
        assert tracker.last_time is None and len(tracker) == 0
        return
    # A joint is either lifted to a finite point or missing (NaN in all three coordinates).
    seen = np.isfinite(joints).all(axis=-1)
    assert (seen | np.isnan(joints).all(axis=-1)).all()
    assert len(out) == 1 and tracker.last_time == 0.0


@pytest.mark.parametrize(
    ("make", "name"),
    [
        (lambda: tc.JointGate(-1), "n_joints"),
        (lambda: tc.TrackerConfig(capacity=-3), "capacity"),
        (lambda: tc.TrackerConfig(min_hits=-1), "min_hits"),
        (lambda: tc.DepthLookup(radius=-1), "radius"),
        (lambda: tc.PersonConfig(gate_max_replacements=-1), "gate_max_replacements"),
        (lambda: tc.ForecasterConfig(degree=-1), "degree"),
        (lambda: tc.LowPass(order=-2), "order"),
        (lambda: tc.butter_lowpass(-1, 5.0, 25.0), "order"),
    ],
)
def test_a_negative_count_is_a_typed_error_naming_the_argument(make, name):
    # pyo3's own conversion raised an OverflowError that named nothing.
    with pytest.raises(tc.InvalidArgumentError, match=f"`{name}` = -"):
        make()


class _FixedModel:
    """A 'keypoint model' that returns whatever detections the test gives it."""

    family, input_size, faces_on_backs = "fixed", 0, False

    def __init__(self):
        self.next = None

    def __call__(self, image):
        return self.next


@SETTINGS
@given(
    keypoints=st.lists(
        st.lists(st.tuples(ANY_FLOAT, ANY_FLOAT, ANY_FLOAT), min_size=17, max_size=17), max_size=3
    ),
    t=ANY_FLOAT,
    depth_value=st.floats(0.0, 12.0) | ANY_FLOAT,
    colour_only=st.booleans(),
)
def test_a_pipeline_frame_is_taken_or_refused_as_a_bad_frame_with_nothing_changed(
    keypoints, t, depth_value, colour_only
):
    from torsocast.camera import Camera, Intrinsics
    from torsocast.keypoints import Detections
    from torsocast.pipeline import BadFrameError, Pipeline
    from torsocast.sources import Frame

    model = _FixedModel()
    pipeline = Pipeline(model)
    camera = Camera(Intrinsics(60.0, 60.0, 32.0, 24.0))
    colour = np.zeros((48, 64, 3), np.uint8)
    good = np.full((1, 17, 3), [30.0, 20.0, 0.9])
    model.next = Detections(good, np.zeros((1, 4)), np.ones(1))
    for k in range(5):
        pipeline(Frame(k, k / 25, colour, np.full((48, 64), 2.0, np.float32), camera))
    before = (pipeline.last_time, pipeline.frames, _tracker_state(pipeline.tracker))
    kp = np.array(keypoints, dtype=float).reshape(-1, 17, 3)
    model.next = Detections(kp, np.zeros((len(kp), 4)), np.ones(len(kp)))
    with np.errstate(over="ignore"):
        depth = None if colour_only else np.full((48, 64), depth_value, np.float32)
    frame = Frame(5, t, colour, depth, None if colour_only else camera)
    try:
        result = pipeline(frame)
    except (BadFrameError, tc.TimeNotIncreasingError):
        assert (pipeline.last_time, pipeline.frames, _tracker_state(pipeline.tracker)) == before
        return
    assert pipeline.last_time == t and len(result.detections) == len(kp)
    for ahead in result.forecasts.values():
        assert np.isfinite(ahead).all()
    if result.joints is not None:
        seen = np.isfinite(result.joints).all(axis=-1)
        assert (seen | np.isnan(result.joints).all(axis=-1)).all()


def _camera_xml(values: str) -> str:
    return (
        '<?xml version="1.0"?>\n<opencv_storage>\n<intrinsic type_id="opencv-matrix">\n'
        f"<rows>3</rows><cols>3</cols><dt>f</dt><data>{values}</data></intrinsic>\n</opencv_storage>\n"
    )


@SETTINGS
@given(
    which=st.sampled_from(["colour", "depth", "camera"]),
    content=st.one_of(
        st.binary(max_size=64),
        st.integers(0, 200).map(lambda n: ("truncate", n)),
        st.lists(ANY_FLOAT.map(repr) | st.text(max_size=4), max_size=12).map(lambda v: ("xml", " ".join(v))),
    ),
)
def test_a_folder_source_gives_each_frame_or_says_why_not(tmp_path_factory, which, content):
    # Any damage to one frame's files: that frame is a SkippedFrame with a reason, the others
    # come as they are; never an exception out of the source.
    import io

    from PIL import Image

    from torsocast.sources import Frame, SkippedFrame, open_source

    root = tmp_path_factory.mktemp("frames")
    colour, depth = io.BytesIO(), io.BytesIO()
    Image.fromarray(np.zeros((24, 32, 3), np.uint8)).save(colour, format="PNG")
    Image.fromarray(np.full((24, 32), 2000, np.uint16)).save(depth, format="PNG")
    files = {
        "colour": ("{}.png", colour.getvalue()),
        "depth": ("{}_depth.png", depth.getvalue()),
        "camera": ("{}_camera.xml", _camera_xml("50. 0. 16. 0. 50. 12. 0. 0. 1.").encode()),
    }
    for stem in ("0000", "0001"):
        for kind, (pattern, data) in files.items():
            if stem == "0001" and kind == which:
                if isinstance(content, bytes):
                    data = content
                elif content[0] == "truncate":
                    data = data[: content[1]]
                else:
                    data = _camera_xml(content[1]).encode()
            (root / pattern.format(stem)).write_bytes(data)
    frames = list(open_source(root))
    assert len(frames) == 2 and isinstance(frames[0], Frame)
    assert isinstance(frames[1], (Frame, SkippedFrame))
    if isinstance(frames[1], SkippedFrame):
        assert frames[1].index == 1 and frames[1].reason


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: tc.Person().update(0.0, np.zeros(3), np.zeros(17), np.zeros(3)), "joints"),
        (lambda: tc.Person().update(0.0, np.zeros((17, 3)), np.zeros((17, 1)), np.zeros(3)), "scores"),
        (lambda: tc.fit_plane(np.zeros(3), "LRLR"), "joints"),
        (lambda: tc.fit_planes(np.zeros((4, 3)), "LRLR"), "joints"),
        (lambda: tc.forecast_batch(np.zeros((3, 5)), [1.0]), "histories"),
        (lambda: tc.linear_assignment(np.zeros(3)), "cost"),
        (lambda: tc.lowpass_causal(np.zeros((3, 2))), "x"),
        (lambda: tc.fit_smoothing_spline(np.zeros((3, 2)), np.zeros(3)), "x"),
        (lambda: tc.JointGate(3).update(np.zeros(3)), "joints"),
        (lambda: tc.LowPass().filter(np.zeros((2, 2))), "x"),
        (lambda: tc.Tracker().update(0.0, np.zeros((17, 3)), np.zeros(17), np.zeros(3)), "joints"),
    ],
)
def test_an_array_with_the_wrong_number_of_dimensions_is_a_shape_error_naming_it(call, name):
    # It was a TypeError 'dimensionality mismatch: from=1, to=2' that named nothing.
    with pytest.raises(tc.ShapeError, match=f"`{name}` has shape"):
        call()


def _step_empty_frame(intrinsics, distortion):
    """A fresh tracker's step on a frame with nobody in it, through the given camera."""
    keypoints, depth = np.zeros((0, 17, 3)), np.zeros((4, 4), np.float32)
    return tc.Tracker().step(0.0, keypoints, depth, intrinsics, distortion, np.eye(4))


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: tc.Forecaster().update([0.0] * 4, 0.0), "pose"),
        (lambda: tc.ForecasterConfig("filter_spline", damping=[1.0] * 6), "damping"),
        (lambda: tc.ForecasterConfig("filter_spline", filter_components=[True] * 4), "filter_components"),
        (lambda: tc.shoulder_heading([0.0, 1.0], [1.0, 0.0, 0.0]), "left"),
        (lambda: tc.PersonConfig(surface_depth=(0.05,)), "surface_depth"),
        (lambda: _step_empty_frame((1.0, 1.0, 1.0), (0.0,) * 5), "intrinsics"),
        (lambda: _step_empty_frame((1.0, 1.0, 2.0, 2.0), (0.0,) * 4), "distortion"),
    ],
)
def test_a_sequence_of_the_wrong_length_is_a_shape_error_naming_it(call, name):
    # It was a plain ValueError 'expected a sequence of length 5 (got 4)' that named nothing and
    # that `except TorsocastError` did not catch.
    with pytest.raises(tc.ShapeError, match=f"`{name}` has shape"):
        call()


def test_a_pose_of_the_wrong_length_leaves_the_forecaster_as_it_was():
    f = tc.Forecaster()
    f.update([0.1, 0.2, 1.0, 0.3, 0.0], 0.0)
    before = f.history()
    with pytest.raises(tc.ShapeError):
        f.update([0.1, 0.2, 1.0, 0.3], 0.04)
    after = f.history()
    assert len(f) == 1 and f.last_time == 0.0
    np.testing.assert_array_equal(after[0], before[0])
    np.testing.assert_array_equal(after[1], before[1])


def test_batch_calls_in_threads_give_the_serial_results():
    # forecast_batch and fit_planes release the GIL while the core works.
    from concurrent.futures import ThreadPoolExecutor

    from torsocast.bench import walking_windows

    rng = np.random.default_rng(5)
    windows = [walking_windows(300, seed=s) for s in range(4)]
    frames = [
        rng.normal(0, 0.2, (500, 4, 3)) + [[[0, 0.2, 1.4], [0, -0.2, 1.4], [0, 0.1, 0.9], [0, -0.1, 0.9]]]
        for _ in range(4)
    ]

    def work(k):
        return tc.forecast_batch(windows[k], [0.4, 1.0]), tc.fit_planes(frames[k], "LRLR")["azimuth"]

    serial = [work(k) for k in range(4)]
    with ThreadPoolExecutor(4) as pool:
        parallel = list(pool.map(work, range(4)))
    for (fa, pa), (fb, pb) in zip(serial, parallel):
        np.testing.assert_array_equal(fa, fb)
        np.testing.assert_array_equal(pa, pb)


_HOSTILE_ARRAYS = st.one_of(
    st.lists(ANY_FLOAT, max_size=6).map(np.array),
    st.lists(st.lists(ANY_FLOAT, min_size=2, max_size=2), max_size=3).map(np.array),
    st.integers(-5, 5).map(lambda v: np.array(v)),
    st.text(max_size=5).map(np.array),
    st.just(np.zeros((4, 4))),
)


@SETTINGS
@given(
    key=st.sampled_from(["intrinsics", "distortion", "depth_scale", "camera_to_world", "time"]),
    value=_HOSTILE_ARRAYS,
)
def test_run_on_a_recording_with_any_calibration_arrays_exits_0_or_2(tmp_path_factory, key, value):
    # Never a traceback: a recording whose arrays cannot describe a camera is one line and exit 2.
    folder = tmp_path_factory.mktemp("recording")
    arrays: dict[str, Any] = {
        "color": np.zeros((2, 24, 32, 3), np.uint8),
        "depth": np.full((2, 24, 32), 2000, np.uint16),
        "time": np.array([0.0, 0.04]),
        "intrinsics": np.array([30.0, 30.0, 16.0, 12.0]),
    }
    arrays[key] = value
    np.savez(folder / "rec.npz", **arrays)
    code, _, err = run_cli(["run", str(folder / "rec.npz"), "--out", str(folder / "out")])
    assert code in (0, 2)
    if code == 2:
        assert len(err.strip().splitlines()) == 1, err


@SETTINGS
@given(
    rgb=st.lists(st.text(alphabet="0123456789. -abc/png\t#", max_size=20), max_size=4),
    depth=st.lists(st.text(alphabet="0123456789. -abc/png\t#", max_size=20), max_size=4),
)
def test_run_on_a_tum_folder_with_any_lists_exits_0_or_2(tmp_path_factory, rgb, depth):
    # Never a traceback: lists that pair nothing, or lines that do not parse, are one line, exit 2.
    folder = tmp_path_factory.mktemp("tum")
    (folder / "rgb.txt").write_text("\n".join(["0.0 rgb/0.png", *rgb]))
    (folder / "depth.txt").write_text("\n".join(["0.0 depth/0.png", *depth]))
    code, _, err = run_cli(["run", str(folder), "--out", str(folder / "out")])
    assert code in (0, 2), err


@settings(max_examples=40, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])
@given(
    rows=st.lists(st.lists(ANY_FLOAT.map(repr) | st.text(max_size=3), max_size=100), max_size=6),
    subjects=st.sampled_from(["9", "9,11", "x", "-1", ""]),
)
def test_eval_h36m_on_any_file_content_exits_0_or_2(tmp_path_factory, rows, subjects):
    # Never a traceback: a file it cannot use is left out and named, a bad option is one line.
    root = tmp_path_factory.mktemp("h36m")
    (root / "S9").mkdir()
    (root / "S9" / "walking_1.txt").write_text("\n".join(",".join(r) for r in rows))
    code, _, err = run_cli(
        ["eval", "h36m", "--data", str(root), "--subjects", subjects, "--out", str(root / "out")]
    )
    assert code in (0, 2), err


@SETTINGS
@given(values=st.lists(ANY_FLOAT, min_size=1, max_size=12), which=st.integers(0, 11))
def test_the_stateful_filters_take_any_value_whole_or_refuse_it_whole(values, which):
    # LowPass.step and JointGate.update keep state: a refused value leaves it as it was (the
    # filter then answers as a twin that was never given it).
    lp, twin = tc.LowPass(), tc.LowPass()
    for v in (0.1, 0.2, 0.15):
        lp.step(v)
        twin.step(v)
    for v in values:
        try:
            out = lp.step(v)
        except tc.TorsocastError:
            continue
        assert np.isfinite(out) and out == twin.step(v)
    assert lp.step(0.3) == twin.step(0.3)
    gate = tc.JointGate(4)
    gate.update(np.zeros((4, 3)))
    joints = np.zeros((4, 3))
    joints.flat[which] = values[0]
    twin_gate = tc.JointGate(4)
    twin_gate.update(np.zeros((4, 3)))
    gated: np.ndarray | None
    status: np.ndarray | None
    try:
        gated, status = gate.update(joints)
    except tc.TorsocastError:
        gated = status = None
    # Whatever this frame did, the gate's next answer is that of a gate given it or refused it.
    follow = np.full((4, 3), 0.01)
    if gated is None or status is None:
        np.testing.assert_array_equal(gate.update(follow)[0], twin_gate.update(follow)[0])
    else:
        assert status.shape == (4,)
        assert np.isfinite(gated).all() or np.isnan(gated).any()  # a joint kept, replaced or missing


@SETTINGS
@given(
    windows=st.lists(st.lists(ANY_FLOAT, min_size=5, max_size=5), min_size=50, max_size=50),
    horizons=st.lists(ANY_FLOAT, min_size=1, max_size=3),
)
def test_forecast_batch_is_finite_or_a_typed_error(windows, horizons):
    try:
        out = tc.forecast_batch(np.array([windows]), horizons)
    except tc.TorsocastError:
        return
    assert out.shape == (1, len(horizons), 5) and np.isfinite(out).all()


@SETTINGS
@given(
    joints=any_points(4),
    ys=st.lists(ANY_FLOAT, min_size=6, max_size=6),
    lam=ANY_FLOAT,
)
def test_batch_plane_fits_and_smoothing_splines_are_finite_or_typed_errors(joints, ys, lam):
    try:
        planes = tc.fit_planes(np.array([joints]), "LRLR")
    except tc.TorsocastError:
        planes = None
    if planes is not None:  # a frame that cannot be fitted is NaN in its row, said by `status`
        fitted = planes["status"] == 0
        for key in ("centre", "normal", "azimuth", "elevation", "rms_residual"):
            assert np.isfinite(planes[key][fitted]).all()
            assert np.isnan(planes[key][~fitted]).all()
    try:
        coefficients, knots = tc.fit_smoothing_spline(np.arange(6.0), np.array(ys), lam=lam)
    except tc.TorsocastError:
        return
    assert np.isfinite(coefficients).all() and np.isfinite(knots).all()
