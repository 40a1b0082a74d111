"""Per-frame cost of the RGB-D pipeline outside the keypoint model (depth lifting, tracking and
forecasting: one core call, ``Tracker.step``) for 1, 10 and 50 people, through ``Pipeline`` and
through the bare ``Tracker.step`` call, and end-to-end frames per second on the turntable
sequence with each keypoint model found. Prints Markdown tables for benches/README.md.

    python benches/bench_pipeline.py [--shared ../shared]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from torsocast.camera import Camera, Intrinsics
from torsocast.keypoints import Detections, open_model
from torsocast.pipeline import Pipeline
from torsocast.sources import Frame, open_source
from torsocast.tracker import Tracker

K = Intrinsics(525.0, 525.0, 320.0, 240.0)
FRAMES = 200  # 8 s at 25 Hz: every track is confirmed and forecasting for most of it
PER_ROW = 10
CELL = (64, 96)  # pixels across and up the picture per person on the stand: a torso 4 m away fits


def places(n: int) -> np.ndarray:
    """Where ``n`` people stand, ``(n, 3)`` in the world frame of a level camera at its origin.
    Up to ten: on a 2-4 m arc across the picture, some partly behind others or out of view. More:
    on a stand's tiers, rows of ten across the picture, each row half a metre further back and
    high enough to be seen above the one in front, so that everyone is tracked (fifty on the arc
    would stand inside one another, and a person the tracker cannot tell apart costs less)."""
    if n <= PER_ROW:
        return np.array([[2.0 + 2.0 * (i % 5) / 4, -1.2 + 2.4 * i / max(n - 1, 1), 0.0] for i in range(n)])
    rows = -(-n // PER_ROW)
    out = np.zeros((n, 3))
    for i in range(n):
        row, column = divmod(i, PER_ROW)
        across = min(n - PER_ROW * row, PER_ROW)
        u = K.cx + CELL[0] * (column - (across - 1) / 2)
        v = K.cy + CELL[1] * ((rows - 1) / 2 - row)  # the front row lowest in the picture
        x = 4.0 + 0.5 * row
        out[i] = x, -(u - K.cx) * x / K.fx, -(v - K.cy) * x / K.fy
    return out


def crowd(n: int, t: float, rng: np.random.Generator) -> tuple[Detections, np.ndarray]:
    """``n`` people standing at :func:`places`, slowly turning, as detections with 17 keypoints,
    and the depth image they would give (their torsos as boxes before a wall at 8 m)."""
    depth = np.full((480, 640), 8.0, dtype=np.float32)
    keypoints = np.zeros((n, 17, 3))
    for i, centre in enumerate(places(n)):
        yaw = np.pi + 0.5 * np.sin(0.5 * t + i)
        left = np.array([-np.sin(yaw), np.cos(yaw), 0.0])
        joints = centre + np.outer(np.linspace(-0.2, 0.2, 17), left)
        joints[:, 2] += np.linspace(0.3, -0.3, 17)
        optical = np.column_stack([-joints[:, 1], -joints[:, 2], joints[:, 0]])
        uv = K.project(optical)
        keypoints[i, :, :2] = uv + rng.normal(0, 0.5, size=(17, 2))
        keypoints[i, :, 2] = 0.9
        u0, v0 = np.clip(uv.min(axis=0) - 4, 0, [639, 479]).astype(int)
        u1, v1 = np.clip(uv.max(axis=0) + 4, 0, [639, 479]).astype(int)
        depth[v0 : v1 + 1, u0 : u1 + 1] = np.minimum(depth[v0 : v1 + 1, u0 : u1 + 1], centre[0])
    boxes = np.concatenate([keypoints[:, :, :2].min(axis=1), keypoints[:, :, :2].max(axis=1)], axis=1)
    return Detections(keypoints, boxes, np.full(n, 0.9)), depth


class Replay:
    """A 'model' that returns precomputed detections, so that only the rest is timed."""

    family, input_size = "replay", 0
    faces_on_backs = False

    def __init__(self) -> None:
        self.next: Detections = Detections.empty()

    def __call__(self, image: np.ndarray) -> Detections:
        return self.next


def outside_model(n: int) -> tuple[float, float, int]:
    """Milliseconds per frame outside the model through ``Pipeline``, and in the bare
    ``Tracker.step`` call (medians over the frames), and the tracks confirmed at the end."""
    rng = np.random.default_rng(n)
    scenes = [crowd(n, k / 25, rng) for k in range(FRAMES)]
    model = Replay()
    pipeline = Pipeline(model, horizons=(0.4, 1.0))
    camera = Camera(K)
    color = np.zeros((480, 640, 3), dtype=np.uint8)
    through_pipeline = []
    for k, (detections, depth) in enumerate(scenes):
        model.next = detections
        before = pipeline.seconds["tracking"]
        pipeline(Frame(k, k / 25, color, depth, camera))
        through_pipeline.append(pipeline.seconds["tracking"] - before)
    tracker, bare = Tracker(), []
    intrinsics = K.fx, K.fy, K.cx, K.cy
    for i, (detections, depth) in enumerate(scenes):
        start = time.perf_counter()
        tracker.step(
            i / 25,
            detections.keypoints,
            depth,
            intrinsics,
            K.coefficients,
            camera.camera_to_world,
            [0.4, 1.0],
        )
        bare.append(time.perf_counter() - start)
    return 1e3 * float(np.median(through_pipeline)), 1e3 * float(np.median(bare)), len(tracker.tracks)


def end_to_end(shared: Path) -> list[tuple[str, float, dict[str, float]]]:
    rows = []
    models: list[tuple[str, Path | None]] = [("MoveNet Lightning int8 (bundled)", None)]
    for name in ("yolo11n-pose-320.onnx", "yolo11n-pose.onnx"):
        if (shared / "models" / name).is_file():
            models.append((name, shared / "models" / name))
    source = shared / "data" / "rgbd" / "turntable"
    for label, path in models:
        pipeline = Pipeline(open_model(path))
        # Frames per second over the whole sequence: a frame the source could not read would
        # leave a gap the figure does not show.
        read = list(open_source(source))
        frames = [f for f in read if isinstance(f, Frame)]
        if len(frames) != len(read):
            raise SystemExit(f"{source}: {len(read) - len(frames)} frames unreadable")
        pipeline(frames[0])  # warm-up: onnxruntime's first run allocates
        pipeline = Pipeline(pipeline.model)
        start = time.perf_counter()
        for frame in frames:
            pipeline(frame)
        rows.append((label, len(frames) / (time.perf_counter() - start), pipeline.timing()))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--shared", default=str(Path(__file__).resolve().parents[2] / "shared"))
    args = parser.parse_args()
    print("| people | outside the model, through Pipeline (ms) | the Tracker.step call alone (ms) | tracks |")
    print("|---:|---:|---:|---:|")
    for n in (1, 10, 50):
        through_pipeline, bare, tracks = outside_model(n)
        print(f"| {n} | {through_pipeline:.3f} | {bare:.3f} | {tracks} |")
    shared = Path(args.shared)
    if not (shared / "data" / "rgbd" / "turntable").is_dir():
        print(f"\nend-to-end skipped: {shared}/data/rgbd/turntable not found")
        return
    print("\n| model | frames/s (turntable, no decoding) | model | lifting, tracking, forecasting |")
    print("|---|---:|---:|---:|")
    for label, fps, t in end_to_end(shared):
        stages = " | ".join(f"{t[s]:.2f} ms" for s in ("model", "tracking"))
        print(f"| {label} | {fps:.1f} | {stages} |")


if __name__ == "__main__":
    main()
