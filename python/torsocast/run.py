"""The main job: every frame of a source through the pipeline, written as JSON Lines (and
optionally overlay pictures), with frames per second and time per stage at the end."""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Callable, Sequence
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._core import TimeNotIncreasingError
from .avi import AviWriter
from .keypoints import KeypointModel
from .output import JsonLines
from .overlay import draw
from .pipeline import HORIZONS, BadFrameError, FrameResult, Pipeline
from .progress import Progress
from .sources import SkippedFrame, Source, world_frame_of


@dataclass
class Summary:
    frames: int
    seconds: float
    stages_ms: dict[str, float]
    people: int
    """Distinct confirmed track ids."""
    out: Path
    rejected: int = 0
    """Frames left out: their time stamp did not increase, or the model's output was unusable."""
    unreadable: int = 0
    """Frames the source could not read (corrupt or missing files): reported and skipped."""
    without_depth: int = 0
    """Frames given with no depth image (a colour-only source; a bag's colour image with no depth
    image near it): their people were detected, not placed in 3D."""
    latency_ms: tuple[float, float, float] | None = None
    """Median, 95th percentile and largest time from a frame handed to the pipeline to its result
    (the model, lifting, tracking and forecasting; not reading or writing), ms; None without a
    frame. What a robot waits, beside the mean per stage."""

    @property
    def fps(self) -> float:
        return self.frames / self.seconds if self.seconds > 0 else float("nan")

    def __str__(self) -> str:
        stages = ", ".join(f"{k} {v:.2f} ms" for k, v in self.stages_ms.items())
        rejected = (
            f" ({self.rejected} left out: time stamp not increasing or model output unusable)"
            if self.rejected
            else ""
        )
        if self.unreadable:
            rejected += f" ({self.unreadable} unreadable, skipped)"
        if self.without_depth:
            rejected += f" ({self.without_depth} without depth: people detected, not placed in 3D)"
        latency = ""
        if self.latency_ms is not None:
            median, p95, most = self.latency_ms
            latency = f"; latency median {median:.2f}, 95th percentile {p95:.2f}, largest {most:.2f} ms"
        return (
            f"{self.frames} frames{rejected} in {self.seconds:.1f} s ({self.fps:.1f} frames/s), "
            f"{self.people} tracked people; per frame: {stages}{latency}"
        )


def run(
    source: Source,
    model: KeypointModel,
    out: str | Path,
    horizons: Sequence[float] = HORIZONS,
    overlay: bool = False,
    progress: bool = True,
    observers: Sequence[Callable[[FrameResult], None]] = (),
    video: bool = False,
) -> Summary:
    """Writes ``out/frames.jsonl``, with ``overlay`` ``out/overlay/NNNNNN.jpg`` and with ``video``
    the same pictures as ``out/overlay.avi`` (Motion JPEG, :mod:`torsocast.avi`); every frame's
    result is also handed to each of ``observers`` (a plot, an evaluation). A frame whose time
    stamp is not after the previous one is left out (counted in the summary, and said on stderr
    once): the tracks stay as they were."""
    out = Path(out)
    pipeline = Pipeline(model, horizons)
    bar = Progress(len(source), f"run {source.name}") if progress and len(source) else None
    ids: set[int] = set()
    rejected = unreadable = without_depth = 0
    latencies: list[float] = []
    start = time.perf_counter()
    movie = AviWriter(out / "overlay.avi") if video else None
    if overlay:
        (out / "overlay").mkdir(parents=True, exist_ok=True)
    with JsonLines(out / "frames.jsonl", horizons, world_frame_of(source)) as jsonl, movie or nullcontext():
        for frame in source:
            if isinstance(frame, SkippedFrame):
                print(f"frame {frame.index} skipped: {frame.reason}", file=sys.stderr)
                unreadable += 1
                jsonl.skipped(frame)
                continue
            try:
                handed = time.perf_counter()
                result = pipeline(frame)
                latencies.append(time.perf_counter() - handed)
                without_depth += frame.depth is None
            except (TimeNotIncreasingError, BadFrameError) as e:
                if not rejected:
                    print(f"frame {frame.index} left out: {e}", file=sys.stderr)
                rejected += 1
                stamp = frame.time if math.isfinite(frame.time) else None
                jsonl.skipped(SkippedFrame(frame.index, stamp, f"left out: {e}"))
                continue
            if result.restarted_from is not None:
                back = result.restarted_from - frame.time
                print(
                    f"frame {frame.index}: its time {frame.time:g} s is {back:g} s before the previous "
                    "frame's: every track dropped, tracking starts again",
                    file=sys.stderr,
                )
            jsonl.write(result)
            ids.update(p.track_id for p in result.people if p.track_id is not None)
            if overlay or movie:
                picture = draw(result)
                if overlay:
                    picture.save(out / "overlay" / f"{frame.index:06d}.jpg", quality=90)
                if movie:
                    movie.write(picture, frame.time)
            for observe in observers:
                observe(result)
            if bar:
                bar(f"{len(result.detections)} people")
    seconds = time.perf_counter() - start
    latency = None
    if latencies:
        median, p95, most = np.percentile(1e3 * np.array(latencies), [50, 95, 100])
        latency = (float(median), float(p95), float(most))
    return Summary(
        pipeline.frames,
        seconds,
        pipeline.timing(),
        len(ids),
        out,
        rejected,
        unreadable,
        without_depth,
        latency,
    )
