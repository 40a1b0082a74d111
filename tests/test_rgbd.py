"""The whole chain on real RGB-D data: the turntable sequence against its ground-truth rotation,
the `torsocast run` command, and the file sources."""

import json

import numpy as np
import pytest

from conftest import readable_frames, shared_path, turntable_frames
from torsocast.cli import main
from torsocast.keypoints import open_model
from torsocast.pipeline import Pipeline
from torsocast.sources import Frame, NpzRecording, TumFolder, open_source
from torsocast.sources.recording import write


def turntable_errors(model) -> tuple[np.ndarray, np.ndarray]:
    """Per frame: |azimuth error| (deg, NaN without an estimate) and the ground-truth turn (deg).
    The person faces the camera (world azimuth 180 degrees) at frame 0 and turns by the angle of
    R about the camera's vertical axis; the sign was measured (+1)."""
    pipeline = Pipeline(model)
    errors, turn = [], []
    for frame in turntable_frames():
        result = pipeline(frame)
        r = frame.extra["R"]
        truth = np.arctan2(r[0, 2], r[0, 0])
        obs = result.people[0].observation if result.people else None
        pose = obs.pose if obs is not None else None
        errors.append(abs(np.angle(np.exp(1j * (pose[3] - np.pi - truth)))) if pose is not None else np.nan)
        turn.append(np.degrees(truth) % 360)
    return np.degrees(errors), np.array(turn)


def check_turntable(errors, turn, median, p90, worst, back_median):
    seen = np.isfinite(errors)
    back = (turn > 120) & (turn < 240) & seen
    assert (~seen).sum() <= 4
    assert np.median(errors[seen]) < median
    assert np.percentile(errors[seen], 90) < p90
    # No 180-degree flip anywhere, and the back view is as good as the front.
    assert errors[seen].max() < worst
    assert np.median(errors[back]) < back_median


def test_turntable_azimuth_follows_the_turn_with_yolo(yolo320):
    # Measured: median 4.3, 90th percentile 13.6, worst 17.9, back view median 5.9 degrees, every
    # frame with an estimate. Before the far joint's depth was completed from the learned
    # shoulder width (profile views: the far shoulder's depth is read from the near side), the
    # 90th percentile was 24.1 and the worst 35.3. Thresholds leave 25 to 50 % margin.
    check_turntable(*turntable_errors(yolo320), median=6.0, p90=18.0, worst=25.0, back_median=8.0)


def test_turntable_azimuth_follows_the_turn_with_the_bundled_movenet():
    # Measured: median 3.8, 90th percentile 12.0, worst 15.5, back view median 6.1 degrees; 1
    # frame without an estimate (on the whole image, before MoveNet ran on a crop around the
    # last frame's person: 4.6, 10.8, 20.3, 6.4 and none).
    check_turntable(*turntable_errors(open_model()), median=6.0, p90=16.0, worst=26.0, back_median=9.0)


def test_a_steady_turn_is_forecast_not_held():
    # The turntable turns about 107 deg/s: holding the heading errs by about 43 degrees 0.4 s
    # ahead. Measured with the bundled MoveNet: a median error of 8.0 degrees over the 85 frames
    # with an estimate whose target instant is in the sequence on an AMD CPU without VNNI, 6.2
    # over 84 on CPUs with it, an Intel and an AMD alike (MoveNet's int8 kernels differ; issue
    # target: under 10; 19.0 before the steady-turn prior). The history's steady turn is
    # continued from the track's first second.
    pipeline = Pipeline(open_model(), (0.4,))
    frames = turntable_frames()
    times = np.array([f.time for f in frames])
    truth = np.array([np.arctan2(f.extra["R"][0, 2], f.extra["R"][0, 0]) + np.pi for f in frames])
    forecast, held = [], []
    for frame in frames:
        result = pipeline(frame)
        if not result.forecasts:
            continue
        d, ahead = next(iter(result.forecasts.items()))
        person = result.people[d]
        if person.observation is None or person.observation.pose is None:
            continue  # the held heading needs an estimate in this frame
        k = int(np.argmin(abs(times - person.last_time - 0.4)))
        if abs(times[k] - person.last_time - 0.4) > 0.02:
            continue
        forecast.append(abs(np.angle(np.exp(1j * (ahead[0, 3] - truth[k])))))
        held.append(abs(np.angle(np.exp(1j * (person.observation.pose[3] - truth[k])))))
    assert len(forecast) > 70
    assert np.degrees(np.median(forecast)) < 10.0
    assert np.degrees(np.median(held)) > 35.0


def test_run_writes_json_lines_and_overlays(tmp_path, capsys):
    source = shared_path("data", "rgbd", "turntable")
    model = shared_path("models", "yolo11n-pose-320.onnx")
    out = tmp_path / "run"
    assert (
        main(
            ["run", str(source), "--model", str(model), "--out", str(out), "--overlay", "--plot"]
            + ["--horizons", "0.4,1", "--video"]
        )
        == 0
    )
    printed = capsys.readouterr().out
    assert "100 frames" in printed and "model" in printed and "tracking" in printed
    lines = [json.loads(line) for line in (out / "frames.jsonl").read_text().splitlines()]
    assert len(lines) == 100 and len(list((out / "overlay").glob("*.jpg"))) == 100
    assert (out / "topdown.png").stat().st_size > 1000
    assert all(line["schema"] == "torsocast.frame/1" for line in lines)
    last = lines[-1]["people"][0]
    assert last["id"] == 1 and last["estimate"] in ("plane", "shoulders")
    # The face in the front views confirms the labels' heading (measured: confident from the
    # twelfth frame, 87 of 100 frames); its evidence is in seconds.
    confident = [line["people"][0]["heading_confident"] for line in lines]
    assert sum(confident) > 50 and not any(confident[:5])
    assert last["heading_confident"] and last["facing_evidence"] > 1.0
    assert all(isinstance(line["people"][0]["heading_held"], bool) for line in lines)
    assert [f["horizon"] for f in last["forecast"]] == [0.4, 1.0]
    # Intervals come once the track has checked its forecasts: 80 % half-widths, per component
    # (the elevation's is 0 here: the hips are out of view and the shoulders hold it).
    for f in last["forecast"]:
        assert len(f["half_width80"]) == 5 and min(f["half_width80"]) >= 0 and f["half_width80"][3] > 0
    azimuths = np.unwrap(
        [line["people"][0]["azimuth"] for line in lines if line["people"][0]["azimuth"] is not None]
    )
    assert np.degrees(azimuths[-1] - azimuths[0]) == pytest.approx(355, abs=25)  # one full turn
    # Hidden far shoulders get their depth completed in the profile phases, never while facing.
    completed = [set(line["people"][0].get("completed") or ()) for line in lines]
    assert set().union(*completed) <= {5, 6} and sum(map(bool, completed)) >= 10
    assert not any(completed[:15]) and not any(completed[45:55])  # facing the camera, then away
    # The video holds the overlay pictures, at the rate of the frames' time stamps.
    cv2 = pytest.importorskip("cv2", reason="OpenCV (pip install '.[test]') reads the video back")
    video = cv2.VideoCapture(str(out / "overlay.avi"))
    times = [line["time"] for line in lines]
    assert video.get(cv2.CAP_PROP_FPS) == pytest.approx(99 / (times[-1] - times[0]), rel=1e-3)
    assert video.get(cv2.CAP_PROP_FRAME_COUNT) == 100
    video.set(cv2.CAP_PROP_POS_FRAMES, 50)
    ok, bgr = video.read()
    jpeg = cv2.imread(str(out / "overlay" / "000050.jpg"))
    assert ok and np.abs(bgr.astype(int) - jpeg).mean() < 1.0  # the same JPEG, decoded twice


def test_run_refuses_what_it_cannot_read(tmp_path, capsys):
    assert main(["run", str(tmp_path / "missing")]) == 2
    assert "no such file or folder" in capsys.readouterr().err
    assert main(["run", str(tmp_path)]) == 2
    assert "not a recognised source" in capsys.readouterr().err


def test_npz_recording_and_tum_folder_give_back_the_frames(tmp_path):
    frames = turntable_frames(3)
    depths = [f.depth for f in frames if f.depth is not None]
    camera = frames[0].camera
    assert len(depths) == 3 and camera is not None
    raw = np.stack([np.rint(d * 1000).astype(np.uint16) for d in depths])
    write(tmp_path / "rec.npz", np.stack([f.color for f in frames]), raw, [0.0, 0.05, 0.1], camera)
    back = readable_frames(NpzRecording(tmp_path / "rec.npz"))
    assert len(back) == 3 and back[2].time == 0.1
    assert np.array_equal(back[1].color, frames[1].color)
    assert back[1].depth is not None and np.allclose(back[1].depth, depths[1], atol=1e-6)
    assert back[0].camera is not None and back[0].camera.intrinsics == camera.intrinsics

    from PIL import Image

    tum = tmp_path / "tum"
    (tum / "rgb").mkdir(parents=True)
    (tum / "depth").mkdir()
    rgb_lines, depth_lines = [], []
    for k, (f, d) in enumerate(zip(frames, depths)):
        Image.fromarray(f.color).save(tum / "rgb" / f"{k}.png")
        Image.fromarray((d * 5000).astype(np.uint16)).save(tum / "depth" / f"{k}.png")
        rgb_lines.append(f"{100 + k / 30:.6f} rgb/{k}.png")
        depth_lines.append(f"{100 + k / 30 + 0.01:.6f} depth/{k}.png")
    depth_lines[2] = f"{100 + 2 / 30 + 0.05:.6f} depth/2.png"  # too far from its colour image
    (tum / "rgb.txt").write_text("# timestamp filename\n" + "\n".join(rgb_lines))
    (tum / "depth.txt").write_text("\n".join(depth_lines))
    source = open_source(tum)
    assert isinstance(source, TumFolder) and len(source) == 2 and source.unpaired == 1
    got = readable_frames(source)
    assert len(got) == 2
    assert got[1].depth is not None and np.allclose(got[1].depth, depths[1], atol=2e-4)
    assert got[1].time == pytest.approx(100 + 1 / 30)


def test_a_video_file_gives_its_frames_and_run_finds_both_people_in_2d(tmp_path, capsys):
    pytest.importorskip("cv2", reason="the video source needs OpenCV (pip install '.[test]')")
    from PIL import Image

    from torsocast.sources.video import VideoFile

    path = shared_path("data", "video", "sports2d-demo.mp4")
    video = VideoFile(path)
    assert (len(video), video.fps) == (230, 30.0)  # the video's README
    frames = {f.index: f for f in video if isinstance(f, Frame) and f.index in (0, 60)}
    assert sorted(frames) == [0, 60]
    for k, frame in frames.items():
        # ../images holds frames 0 and 60 of this video, decoded once: measured identical here.
        with Image.open(shared_path("data", "images", f"sports2d_{k:03d}.png")) as image:
            reference = np.asarray(image.convert("RGB"))
        assert frame.depth is None and frame.time == pytest.approx(k / 30)
        assert np.abs(frame.color.astype(int) - reference).mean() < 1.0
    model = shared_path("models", "yolo11n-pose-320.onnx")
    assert main(["run", str(path), "--model", str(model), "--out", str(tmp_path)]) == 0
    assert "230 frames" in capsys.readouterr().out
    lines = [json.loads(line) for line in (tmp_path / "frames.jsonl").read_text().splitlines()]
    assert len(lines) == 230 and lines[60]["time"] == pytest.approx(2.0)
    people = lines[60]["people"]
    assert len(people) == 2 and all("joints" not in p and p["id"] is None for p in people)  # 2D only
    # Where the images' README puts the two torsos (YOLO at 640); 320 is within 16 px of it.
    for shoulder in ([1432.4, 621.2], [660.6, 165.3]):  # left shoulders: woman, man
        found = min(np.abs(np.array(p["keypoints"][5][:2]) - shoulder).max() for p in people)
        assert found < 16.0


def test_depth_that_cannot_be_read_right_is_refused_with_a_reason(tmp_path):
    from PIL import Image

    from torsocast.pipeline import BadFrameError
    from torsocast.sources.folder import read_depth_png

    # An 8-bit depth PNG was read as millimetres; a TUM folder without a pairable depth image
    # gave a run of 0 frames and exit 0; depth at half the colour size was read at the wrong
    # pixels.
    Image.fromarray(np.full((4, 4), 200, np.uint8)).save(tmp_path / "eight.png")
    with pytest.raises(ValueError, match="16-bit"):
        read_depth_png(tmp_path / "eight.png")
    tum = tmp_path / "tum"
    tum.mkdir()
    (tum / "rgb.txt").write_text("100.0 rgb/0.png\n")
    (tum / "depth.txt").write_text("200.0 depth/0.png\n")
    with pytest.raises(ValueError, match="no colour image has a depth image within"):
        open_source(tum)
    frame = turntable_frames(1)[0]
    assert frame.depth is not None
    frame.depth = frame.depth[::2, ::2]
    pipeline = Pipeline(open_model())
    with pytest.raises(BadFrameError, match="not registered to colour"):
        pipeline(frame)
    assert pipeline.last_time is None


def test_run_skips_frames_it_cannot_read_and_reports_them(tmp_path, capsys):
    # A truncated JPEG, a missing camera file, a garbage depth PNG and a PNG that claims
    # 30000x30000 pixels each ended the run in a traceback; a missing camera file also shifted
    # the later frames' time stamps.
    import shutil

    from PIL import Image

    turntable = shared_path("data", "rgbd", "turntable")
    folder = tmp_path / "frames"
    folder.mkdir()
    for k in range(7):
        for suffix in (".jpg", "_depth.png", "_camera.xml"):
            shutil.copy(turntable / f"{k:010d}{suffix}", folder / f"{k:010d}{suffix}")
    jpg = folder / "0000000001.jpg"
    jpg.write_bytes(jpg.read_bytes()[:2000])
    (folder / "0000000002_camera.xml").unlink()
    (folder / "0000000003_depth.png").write_bytes(b"not a png")
    bomb = folder / "0000000004.jpg"
    bomb.unlink()
    Image.new("1", (30000, 30000)).save(folder / "0000000004.png")
    out = tmp_path / "out"
    assert main(["run", str(folder), "--out", str(out)]) == 0
    captured = capsys.readouterr()
    assert "4 unreadable, skipped" in captured.out
    for k in (1, 2, 3, 4):
        assert f"frame {k} skipped" in captured.err
    lines = [json.loads(line) for line in (out / "frames.jsonl").read_text().splitlines()]
    assert [("skipped" in line) for line in lines] == [False, True, True, True, True, False, False]
    assert lines[5]["time"] == pytest.approx(5 / 30, abs=1e-6)  # not re-timed by the missing camera file


def test_run_refuses_a_model_or_recording_it_cannot_load(tmp_path, capsys):
    (tmp_path / "text.onnx").write_text("not a model")
    (tmp_path / "cut.npz").write_bytes(b"PK\x03\x04 cut short")
    turntable = str(shared_path("data", "rgbd", "turntable"))
    for args, message in (
        ([turntable, "--model", str(tmp_path / "text.onnx")], "not a model onnxruntime can load"),
        ([str(tmp_path / "cut.npz")], "not a readable .npz recording"),
    ):
        assert main(["run", *args, "--out", str(tmp_path / "out")]) == 2
        assert message in capsys.readouterr().err


def test_a_damaged_video_reports_the_frames_it_cannot_decode_and_goes_on(tmp_path):
    # It used to stop at the first frame OpenCV could not decode, as if the video had ended.
    pytest.importorskip("cv2")
    from torsocast.sources import SkippedFrame, open_source

    data = bytearray(shared_path("data", "video", "sports2d-demo.mp4").read_bytes())
    middle = len(data) // 2
    data[middle : middle + 20000] = np.random.default_rng(0).integers(0, 256, 20000, dtype=np.uint8).tobytes()
    damaged = tmp_path / "damaged.mp4"
    damaged.write_bytes(bytes(data))
    frames = list(open_source(damaged))
    skipped = [f for f in frames if isinstance(f, SkippedFrame)]
    decoded = [f.index for f in frames if not isinstance(f, SkippedFrame)]
    assert len(frames) == 230 and [f.index for f in frames] == list(range(230))
    assert skipped and "cannot be decoded" in skipped[0].reason
    assert max(decoded) > skipped[0].index  # frames after the damage still come


def test_a_frame_whose_image_the_model_cannot_take_is_a_bad_frame_and_changes_nothing():
    # A 2-D or float colour image raised a ValueError that ended a run with a traceback.
    from torsocast.camera import Camera, Intrinsics
    from torsocast.keypoints import open_model
    from torsocast.pipeline import BadFrameError, Pipeline
    from torsocast.sources import Frame

    pipeline = Pipeline(open_model(None))
    camera = Camera(Intrinsics(500.0, 500.0, 320.0, 240.0))
    depth = np.ones((480, 640), np.float32)
    for colour in (np.zeros((480, 640), np.uint8), np.zeros((480, 640, 3), np.float64)):
        with pytest.raises(BadFrameError, match="frame 0"):
            pipeline(Frame(0, 0.0, colour, depth, camera))  # type: ignore[arg-type]  # refused
        assert pipeline.last_time is None and pipeline.frames == 0
    pipeline(Frame(0, 0.0, np.zeros((480, 640, 3), np.uint8), depth, camera))
    assert pipeline.last_time == 0.0
