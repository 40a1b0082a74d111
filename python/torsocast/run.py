"""The main job: every frame of a source through the pipeline, written as JSON Lines (and
optionally overlay pictures), with frames per second and time per stage at the end."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from .keypoints import KeypointModel
from .output import JsonLines
from .pipeline import FrameResult, Pipeline
from .progress import Progress
from .sources import Source


@dataclass
class Summary:
    frames: int
    seconds: float
    stages_ms: dict[str, float]
    people: int
    """Distinct confirmed track ids."""
    out: Path

    @property
    def fps(self) -> float:
        return self.frames / self.seconds if self.seconds > 0 else float("nan")

    def __str__(self) -> str:
        stages = ", ".join(f"{k} {v:.2f} ms" for k, v in self.stages_ms.items())
        return (
            f"{self.frames} frames in {self.seconds:.1f} s ({self.fps:.1f} frames/s), "
            f"{self.people} tracked people; per frame: {stages}"
        )


def run(
    source: Source,
    model: KeypointModel,
    out: str | Path,
    horizons: Sequence[float] = (0.4, 1.0),
    overlay: bool = False,
    progress: bool = True,
    observers: Sequence[Callable[[FrameResult], None]] = (),
) -> Summary:
    """Writes ``out/frames.jsonl`` and, with ``overlay``, ``out/overlay/NNNNNN.jpg``; every frame's
    result is also handed to each of ``observers`` (a plot, an evaluation)."""
    out = Path(out)
    pipeline = Pipeline(model, horizons)
    bar = Progress(len(source), f"run {source.name}") if progress and len(source) else None
    ids: set[int] = set()
    start = time.perf_counter()
    with JsonLines(out / "frames.jsonl", horizons) as jsonl:
        for frame in source:
            result = pipeline(frame)
            jsonl.write(result)
            ids.update(p.track_id for p in result.people if p.track_id is not None)
            if overlay:
                save_overlay(result, out / "overlay")
            for observe in observers:
                observe(result)
            if bar:
                bar(f"{len(result.detections)} people")
    return Summary(pipeline.frames, time.perf_counter() - start, pipeline.timing(), len(ids), out)


def save_overlay(result: FrameResult, folder: Path) -> None:
    from .overlay import draw

    folder.mkdir(parents=True, exist_ok=True)
    draw(result).save(folder / f"{result.frame.index:06d}.jpg", quality=90)
