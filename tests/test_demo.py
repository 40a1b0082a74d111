"""The demo's parts and the demo itself: CMU forward kinematics against SciPy and the skeleton's
written facts, the mannequin renderer against closed forms, the top-down plot, and `torsocast
demo` end to end against the mocap ground truth."""

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from conftest import shared_path
from torsocast.camera import Camera, Intrinsics, level_camera
from torsocast.cli import main
from torsocast.datasets import cmu
from torsocast.synthetic.mannequin import Scene, _capsule
from torsocast.synthetic.mocap import MocapScene, watching_camera


class Replay:
    """Recorded frames as a source."""

    name = "replay"

    def __init__(self, frames):
        self.frames = frames

    def __len__(self):
        return len(self.frames)

    def __iter__(self):
        return iter(self.frames)


@pytest.fixture(scope="module")
def walk():
    return cmu.load_clip(cmu.bundled_clips()["test_walking_1"])


def test_bundled_clips_are_the_shared_files_unchanged():
    shared = shared_path("data", "cmu")
    bundled = cmu.bundled_clips()
    assert len(bundled) == 6
    for name, path in bundled.items():
        split, _, k = name.split("_")
        assert path.read_bytes() == (shared / split / "walking" / f"walking_{k}.txt").read_bytes()


def test_forward_kinematics_matches_a_scipy_rotation_chain():
    rows = cmu.read_clip(cmu.bundled_clips()["train_walking_4"])[:5]
    got = cmu.forward_kinematics(rows)
    for f, row in enumerate(rows):
        local = Rotation.from_rotvec(row[3:].reshape(38, 3)).as_matrix()
        xyz, rot = np.zeros((38, 3)), [None] * 38
        for j, p in enumerate(cmu.PARENTS):
            if p < 0:
                xyz[j], rot[j] = row[:3], local[0]
            else:
                xyz[j] = cmu.OFFSETS[j] @ rot[p] + xyz[p]
                rot[j] = local[j] @ rot[p]
        assert np.allclose(got[f], xyz, atol=1e-5)
    # The first line of CMU 07_01's file: root position (8.8721, 15.7511, -31.7081).
    assert got[0, 0] == pytest.approx([8.8721, 15.7511, -31.7081])


def test_a_walk_has_the_measured_proportions_and_faces_where_it_goes(walk):
    # Measured from the clip: widths in metres, 358 motion frames after the rest pose,
    # 3.845 m of horizontal path (of 359 frames), the floor at z = 0 (the lowest joint of all
    # files is 3.5 cm up; the toes of this one come to 4.6 cm).
    shoulders = np.linalg.norm(walk[:, cmu.LEFT_SHOULDER] - walk[:, cmu.RIGHT_SHOULDER], axis=1)
    hips = np.linalg.norm(walk[:, cmu.LEFT_HIP] - walk[:, cmu.RIGHT_HIP], axis=1)
    assert shoulders == pytest.approx(7.0432 * cmu.UNIT_M, abs=1e-3)
    assert hips == pytest.approx(3.2674 * cmu.UNIT_M, abs=1e-3)
    assert len(walk) == 358 and 0.03 < walk[..., 2].min() < 0.05
    steps = np.diff(walk[:, cmu.PELVIS, :2], axis=0)
    assert np.linalg.norm(steps, axis=1).sum() == pytest.approx(3.845, abs=0.03)
    # Forward = left x up in REP-103: the subject walks the way the chest faces.
    left = walk[:, cmu.LEFT_HIP] - walk[:, cmu.RIGHT_HIP]
    forward = np.cross(left, [0.0, 0.0, 1.0])[:, :2]
    velocity = walk[12:, cmu.PELVIS, :2] - walk[:-12, cmu.PELVIS, :2]
    cosine = (forward[6:-6] * velocity).sum(1) / np.linalg.norm(forward[6:-6], axis=1)
    assert (cosine / np.linalg.norm(velocity, axis=1) > 0.9).all()


def test_a_bad_clip_file_is_refused(tmp_path):
    path = tmp_path / "short.txt"
    path.write_text("1,2,3\n")
    with pytest.raises(ValueError, match="117"):
        cmu.read_clip(path)
    with pytest.raises(FileNotFoundError):
        MocapScene.from_clip(tmp_path / "none.txt")
    with pytest.raises(ValueError, match="38, 3"):
        MocapScene(np.zeros((10, 17, 3)))
    with pytest.raises(ValueError, match="finite"):
        MocapScene(np.full((10, 38, 3), np.nan))
    with pytest.raises(ValueError, match="fps"):
        MocapScene(np.zeros((10, 38, 3)), fps=240.0)


def test_capsules_render_at_their_closed_form_depth():
    camera = Camera(Intrinsics(500.0, 500.0, 50.0, 50.0))
    scene = Scene(width=101, height=101)
    rays = scene.rays(camera)
    depth, rgb = np.full((101, 101), np.inf), np.zeros((101, 101, 3))
    # A sphere of 0.1 m at 2 m: the centre pixel sees its front at 1.9 m; 20 px off the axis
    # (0.08 m at 2 m), the ray meets the sphere where z solves the quadratic.
    _capsule(rays, camera, np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, 2.0]), 0.1, (255, 0, 0), depth, rgb)
    assert depth[50, 50] == pytest.approx(1.9, abs=1e-9)
    d = rays[50, 70]
    s = 2 * d[2] - np.sqrt((2 * d[2]) ** 2 - (4 - 0.01))
    assert depth[50, 70] == pytest.approx(s * d[2], abs=1e-9)
    assert np.isinf(depth[50, 80]) and tuple(rgb[50, 50]) == (255, 0, 0)
    # A horizontal rod in front of it hides it, at the rod's radius from its axis.
    _capsule(
        rays, camera, np.array([-0.5, 0.0, 1.5]), np.array([0.5, 0.0, 1.5]), 0.05, (0, 0, 255), depth, rgb
    )
    assert depth[50, 50] == pytest.approx(1.45, abs=1e-9) and tuple(rgb[50, 50]) == (0, 0, 255)


def test_the_floor_is_at_its_closed_form_depth():
    camera = Camera(Intrinsics(300.0, 300.0, 80.0, 60.0), level_camera(1.5, 0.0))
    scene = Scene(width=161, height=121, noise=None)
    rgb, depth = scene.background(camera, scene.rays(camera))
    # A level camera 1.5 m up sees the floor at optical depth z where 1.5 / z = (v - cy) / fy.
    assert depth[110, 80] == pytest.approx(1.5 * 300.0 / 50.0)
    assert np.isinf(depth[40, 80])  # above the horizon: sky


def test_the_scene_source_renders_the_walker_where_the_truth_is(walk):
    source = MocapScene(walk, fps=10.0, scene=Scene(noise=None))
    frames = list(source)
    assert len(frames) == len(source) == 30 and frames[1].time == pytest.approx(0.1)
    camera = source.camera
    assert camera is not None
    for frame in frames[::7]:
        assert frame.depth is not None
        centre = frame.extra["truth"][:3]
        optical = camera.to_optical(centre)
        u, v = np.round(camera.intrinsics.project(optical)).astype(int)
        # The chest's surface, a torso's half-depth (under 0.2 m) in front of the plane's centre.
        assert 0.0 < optical[2] - frame.depth[v, u] < 0.2


def test_run_leaves_out_a_frame_that_repeats_a_time_stamp(walk, tmp_path, capsys):
    from torsocast.keypoints import open_model
    from torsocast.run import run

    frames = list(MocapScene(walk, fps=10.0))[:15]
    repeated = frames[:10] + [frames[9]] + frames[10:]  # a live driver delivering a frame twice

    summary = run(Replay(repeated), open_model(None), tmp_path, progress=False)
    assert summary.frames == len(frames) and summary.rejected == 1
    assert "1 left out" in str(summary) and "frame 9 left out" in capsys.readouterr().err
    records = [json.loads(line) for line in (tmp_path / "frames.jsonl").read_text().splitlines()]
    assert [r["time"] for r in records if "skipped" not in r] == [f.time for f in frames]
    left_out = [r for r in records if "skipped" in r]  # the repeated frame has its line, and why
    assert len(left_out) == 1 and left_out[0]["frame"] == 9 and "not after" in left_out[0]["skipped"]


def test_a_frame_stamped_an_hour_ahead_costs_one_restart_not_the_following_hour(walk, tmp_path, capsys):
    # It used to make the pipeline refuse every frame of the following hour as out of order.
    import dataclasses

    from torsocast.keypoints import open_model
    from torsocast.run import run

    frames = list(MocapScene(walk, fps=10.0))[:20]
    stamped = frames[:8] + [dataclasses.replace(frames[8], time=3600.0)] + frames[9:]
    summary = run(Replay(stamped), open_model(None), tmp_path, progress=False)
    assert summary.frames == 20 and summary.rejected == 0
    # What each frame waited, beside the mean per stage: ordered, the largest at least the mean
    # wait, which the stages' means add up to.
    assert summary.latency_ms is not None
    median, p95, most = summary.latency_ms
    assert 0 < median <= p95 <= most and most >= sum(summary.stages_ms.values())
    assert f"latency median {median:.2f}, 95th percentile {p95:.2f}, largest {most:.2f} ms" in str(summary)
    err = capsys.readouterr().err
    assert "frame 9" in err and "tracking starts again" in err
    records = [json.loads(line) for line in (tmp_path / "frames.jsonl").read_text().splitlines()]
    ids = [p["id"] for r in records for p in r["people"] if p["id"] is not None]
    assert len(set(ids)) == 2 and ids[-1] == 2  # a new track after the restart; no id given twice
    assert records[-1]["people"][0]["forecast"] is not None


def test_a_walker_unseen_for_a_second_is_reported_where_the_walk_went_on(walk, tmp_path):
    import dataclasses

    from torsocast import InvalidArgumentError
    from torsocast.keypoints import open_model
    from torsocast.pipeline import Pipeline
    from torsocast.run import run

    # A second of frames without depth (no 3D joints: the track takes nothing) in the middle
    # of the walk: the confirmed track is kept and reported unseen, forecast to each frame's
    # time along the walk, and takes its person again afterwards.
    frames = list(MocapScene(walk, fps=10.0))
    gap = range(15, 25)
    frames = [dataclasses.replace(f, depth=None) if k in gap else f for k, f in enumerate(frames)]
    pipeline = Pipeline(open_model())
    results = []
    for f in frames:
        results.append(pipeline(f))
        if len(results) == 15:  # the track's intervals by id are those its outcome gave
            by_id = pipeline.tracker.intervals(1, list(pipeline.horizons))
            np.testing.assert_array_equal(by_id, results[-1].intervals[0])
            # A horizon that is no time ahead is refused by name, and nothing changes.
            with pytest.raises(InvalidArgumentError, match="horizons"):
                pipeline.tracker.intervals(1, [-0.4])
            np.testing.assert_array_equal(pipeline.tracker.intervals(1, list(pipeline.horizons)), by_id)
    assert all(not r.unseen for r in results[:15]) and pipeline.tracker.intervals(7, [0.4]) is None
    for k in gap:
        (track,) = results[k].unseen
        truth = np.asarray(frames[k].extra["truth"]).reshape(-1, 5)[0]
        assert track.id == 1 and track.last_time == pytest.approx(frames[14].time, abs=0.021)
        assert track.pose is not None and track.half_width80 is not None
        assert np.linalg.norm(track.pose[:2] - truth[:2]) < 0.1  # the walk goes on 1.2 m
        assert np.all(track.half_width80 > 0)
    assert [p.track_id for p in results[25].people] == [1] and not results[25].unseen

    # Unseen for longer than the tracker keeps a track (2 s), it is no longer reported.
    long_gap = [dataclasses.replace(f, depth=None) if k >= 3 else f for k, f in enumerate(frames)]
    pipeline = Pipeline(open_model())
    reported = [len(pipeline(f).unseen) for f in long_gap]
    # Last seen in frame 2 (0.2 s): reported up to 2 s later, then dropped.
    assert reported == [0] * 3 + [1] * 20 + [0] * (len(frames) - 23)

    # Each JSON Lines line lists them, with their body frame.
    run(Replay(frames), open_model(), tmp_path, progress=False)
    lines = [json.loads(line) for line in (tmp_path / "frames.jsonl").read_text().splitlines()]
    assert [len(line["unseen"]) for line in lines] == [0] * 15 + [1] * 10 + [0] * (len(frames) - 25)
    hidden = lines[20]["unseen"][0]
    assert hidden["id"] == 1 and hidden["body_frame"]["child_frame_id"] == "body_1"
    assert hidden["body_frame"]["translation"] == hidden["pose"][:3]


def test_the_demo_camera_sees_the_walk_come_towards_it(walk):
    camera = watching_camera(walk[:, cmu.PELVIS])
    position = np.asarray(camera.camera_to_world)[:3, 3]
    distance = np.linalg.norm(walk[:, cmu.PELVIS, :2] - position[:2], axis=1)
    assert distance[0] > distance[-1] > 1.5 and position[2] == pytest.approx(1.2)


def test_demo_runs_on_bundled_data_and_matches_the_truth(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path), "--video"]) == 0
    printed = capsys.readouterr().out
    lines = [json.loads(line) for line in (tmp_path / "frames.jsonl").read_text().splitlines()]
    assert len(lines) == 90 and (tmp_path / "demo.png").stat().st_size > 10_000
    # Each confirmed track's pose is also its REP-155 body frame: x out of the chest at the
    # reported azimuth and elevation, the frame named after the track.
    framed = [p for line in lines for p in line["people"] if p["id"] is not None and p["centre"]]
    assert len(framed) > 80 and all(p["body_frame"]["child_frame_id"] == f"body_{p['id']}" for p in framed)
    assert all(p["body_frame"]["frame_id"] == "world" for p in framed)  # a source that names none
    for p in framed:
        x_axis = Rotation.from_quat(p["body_frame"]["rotation"]).apply([1.0, 0.0, 0.0])
        az, el = p["azimuth"], p["elevation"]
        normal = [np.sin(el) * np.cos(az), np.sin(el) * np.sin(az), np.cos(el)]
        np.testing.assert_allclose(x_axis, normal, atol=1e-3)
        assert p["body_frame"]["translation"] == p["centre"]
    assert not any("body_frame" in p for line in lines for p in line["people"] if p["id"] is None)
    assert (tmp_path / "overlay.avi").stat().st_size > 90 * 10_000  # 90 JPEGs of 640x480
    # Measured on test_walking_1 with the bundled MoveNet: azimuth error median 1.9 deg, 90th
    # percentile 5.3 deg; forecast centre error 0.4 s ahead 5 cm against 51 cm for holding
    # still, 1 s ahead 10 against 128 cm. The azimuth forecast is no worse than holding (issue
    # 13's demo target): on this straight walk no steady turn is seen, and every azimuth forecast
    # is the held estimate (2.8 and 2.4 deg both).
    median = float(printed.split("azimuth error median ")[1].split(" deg")[0])
    p90 = float(printed.split("90th percentile ")[1].split(" deg")[0])
    assert median < 6.0 and p90 < 14.0
    rows = [
        line.split("|")
        for line in printed.splitlines()
        if line.startswith("| 0.4 s") or line.startswith("| 1 s")
    ]
    for row in rows:
        forecast, held = (float(row[k].split()[0]) for k in (3, 4))
        assert forecast < 0.6 * held
        forecast, held = (float(row[k].split()[0]) for k in (5, 6))
        assert forecast <= held
    assert len(rows) == 2


def test_demo_refuses_an_unknown_clip(tmp_path, capsys):
    assert main(["demo", "--clip", "no_such_clip", "--out", str(tmp_path)]) == 2
    assert "bundled clips: test_walking_1" in capsys.readouterr().err


@pytest.mark.parametrize("axis", [0, 1])
def test_the_top_down_plot_draws_a_walk_along_its_world_axis(axis):
    from torsocast.overlay import COLOURS
    from torsocast.topdown import TopDown, TrackHistory

    poses = np.zeros((20, 5))
    poses[:, axis] = np.linspace(0.0, 3.0, 20)
    poses[:, 3] = np.pi / 2 * axis  # facing along the walk
    plot = TopDown(tracks={1: TrackHistory(list(np.arange(20) / 10), list(poses))})
    image = np.asarray(plot.draw(size=200))
    rows, cols = np.nonzero((image == COLOURS[1]).all(axis=2))
    width, height = np.ptp(cols), np.ptp(rows)
    # 3 m of walk across the plot's (3 + 2 * 0.7) m: about 130 of 200 pixels along its axis.
    assert (width, height)[axis] > 120 and (width, height)[1 - axis] < 40


def _unseen_frame(pose, half_width80, time=1.0):
    """A frame of an empty room from a level camera 1 m up, in which track 3 went unseen since
    0.4 s and is forecast at ``pose``."""
    from torsocast.keypoints.model import Detections
    from torsocast.pipeline import FrameResult, UnseenTrack
    from torsocast.sources.frame import Frame

    camera = Camera(Intrinsics(500.0, 500.0, 320.0, 240.0), level_camera(1.0))
    frame = Frame(0, time, np.zeros((480, 640, 3), np.uint8), None, camera)
    nobody = Detections(np.zeros((0, 17, 3)), np.zeros((0, 4)), np.zeros(0))
    track = UnseenTrack(3, time - 0.4, np.asarray(pose, float), np.asarray(half_width80, float))
    return FrameResult(frame, nobody, None, [], {}, unseen=[track])


def test_an_unseen_track_is_drawn_as_a_ring_as_wide_as_its_centre_interval():
    from torsocast.overlay import COLOURS, draw

    # 4 m ahead at the camera's height, the interval 0.3 m by 0.4 m: a ring of 500 * 0.5 / 4 px
    # round the image's centre.
    image = np.asarray(draw(_unseen_frame([4.0, 0.0, 1.0, np.pi, np.pi / 2], [0.3, 0.4, 0.1, 0.2, 0.1])))
    rows, cols = np.nonzero((image == COLOURS[3]).all(axis=2))
    radius = np.hypot(cols - 320.0, rows - 240.0)
    ring = np.abs(radius - 62.5) < 2.5
    sectors = np.unique((np.degrees(np.arctan2(rows - 240.0, cols - 320.0)[ring]) // 30).astype(int) % 12)
    assert len(sectors) == 12  # the whole ring
    assert not np.any((radius > 10) & (radius < 55))  # and nothing inside it but the heading

    # Behind the camera, or outside the picture: nothing drawn.
    for pose in ([-4.0, 0.0, 1.0, 0.0, np.pi / 2], [4.0, 6.0, 1.0, 0.0, np.pi / 2]):
        assert not np.asarray(draw(_unseen_frame(pose, [0.3, 0.4, 0.1, 0.2, 0.1]))).any()


def test_the_top_down_plot_draws_where_an_unseen_track_was_put():
    from torsocast.overlay import COLOURS
    from torsocast.topdown import TopDown, TrackHistory

    seen = np.array([0.0, 0.0, 1.0, 0.0, np.pi / 2])
    plot = TopDown(tracks={3: TrackHistory([0.6], [seen])})
    plot(_unseen_frame([3.0, 0.0, 1.0, 0.0, np.pi / 2], [0.3, 0.4, 0.1, 0.2, 0.1]))
    assert [t for t, _ in plot.tracks[3].unseen] == [1.0]
    image = np.asarray(plot.draw(size=200))
    rows, cols = np.nonzero((image == COLOURS[3]).all(axis=2))
    # The plot spans x from the camera at 0 to the unseen point at 3 m: that point is drawn there.
    assert cols.max() > 155


def test_a_frame_whose_model_scores_are_not_probabilities_is_left_out(walk, tmp_path, capsys):
    from torsocast.keypoints import open_model
    from torsocast.pipeline import BadFrameError, Pipeline
    from torsocast.run import run

    movenet = open_model()

    class Broken:
        """The bundled model, with keypoint scores of 169 in its fifth frame (as an ONNX file of
        another kind of model gives)."""

        family, input_size, faces_on_backs, calls = "movenet", 192, True, 0

        def __call__(self, image):
            found = movenet(image)
            self.calls += 1
            if self.calls == 5:
                found.keypoints[..., 2] = 169.0
            return found

    frames = list(MocapScene(walk, fps=10.0))[:10]
    summary = run(Replay(frames), Broken(), tmp_path, progress=False)
    assert summary.frames == 9 and summary.rejected == 1
    assert "keypoint scores from 0 to 1" in capsys.readouterr().err
    pipeline = Pipeline(Broken())
    for frame in frames[:4]:
        pipeline(frame)
    last = pipeline.last_time
    with pytest.raises(BadFrameError):
        pipeline(frames[4])
    assert pipeline.last_time == last  # refused: nothing changed, the frame's time is still free
    pipeline(frames[4])
