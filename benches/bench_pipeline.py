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

from torsocast.bench import K, crowd_frames, frame_cost
from torsocast.camera import Camera
from torsocast.keypoints import Detections, open_model
from torsocast.pipeline import Pipeline
from torsocast.sources import Frame, open_source


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
    frames = crowd_frames(n)
    model = Replay()
    pipeline = Pipeline(model, horizons=(0.4, 1.0))
    camera = Camera(K)
    color = np.zeros((480, 640, 3), dtype=np.uint8)
    through_pipeline = []
    for k, (keypoints, depth) in enumerate(frames):
        boxes = np.concatenate([keypoints[:, :, :2].min(axis=1), keypoints[:, :, :2].max(axis=1)], axis=1)
        model.next = Detections(keypoints, boxes, np.full(n, 0.9))
        before = pipeline.seconds["tracking"]
        pipeline(Frame(k, k / 25, color, depth, camera))
        through_pipeline.append(pipeline.seconds["tracking"] - before)
    bare, tracks = frame_cost(frames)
    return 1e3 * float(np.median(through_pipeline)), 1e3 * bare, tracks


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
