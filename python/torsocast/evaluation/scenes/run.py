"""Runs the scenes benchmark: every scene's frames through the real pipeline and a real keypoint
model, scored against the truth."""

from __future__ import annotations

import os
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...keypoints import KeypointModel, open_model
from ...pipeline import FrameResult, Pipeline
from ...progress import Progress
from ...synthetic.scenes import RenderedScene, SceneSpec
from .plan import FULL, QUICK, Catalogue, Size, draw_scene
from .score import Scorer

HORIZONS = (0.4, 1.0, 2.0)
#: The multi-person model, when none is given: YOLO11n-pose at 640 (AGPL weights, not shipped).
YOLO_ENV = "TORSOCAST_YOLO"


@dataclass
class Models:
    """The bundled MoveNet for one-person scenes and a YOLO-pose model for crowds (None: scenes
    with several people are left out)."""

    single: KeypointModel
    multi: KeypointModel | None
    multi_name: str = ""

    @classmethod
    def open(cls, yolo: str | Path | None) -> Models:
        path = yolo or os.environ.get(YOLO_ENV)
        multi = open_model(path) if path else None
        return cls(open_model(None), multi, Path(path).name if path else "")


@dataclass
class Benchmark:
    """Everything one run measured: the records of all scenes, column name -> values."""

    split: str
    seed: int
    quick: bool
    specs: list[SceneSpec]
    recovery: dict[str, list] = field(default_factory=lambda: defaultdict(list))  # type: ignore[type-arg]
    forecasts: dict[str, list] = field(default_factory=lambda: defaultdict(list))  # type: ignore[type-arg]
    identity: dict[str, list] = field(default_factory=lambda: defaultdict(list))  # type: ignore[type-arg]
    false_positives: int = 0
    frames: int = 0
    notes: list[str] = field(default_factory=list)
    models: dict[str, str] = field(default_factory=dict)
    picture: FrameResult | None = None
    """The frame drawn in the report: the one with the most people estimated."""

    def columns(self, table: str) -> dict[str, np.ndarray]:
        return {k: np.asarray(v) for k, v in getattr(self, table).items()}


def run_scene(spec: SceneSpec, catalogue: Catalogue, model: KeypointModel, horizons=HORIZONS):  # type: ignore[no-untyped-def]
    """One scene through the pipeline; returns its :class:`~.score.SceneScore` and the frame with
    the most people estimated."""
    scene = RenderedScene(spec, {a.motion: catalogue.motion(a.motion) for a in spec.actors})
    pipeline = Pipeline(model, horizons)
    scorer = Scorer(scene, list(horizons), pipeline.tracker_config.track.min_score)
    best, best_count = None, 0
    for frame in scene:
        result = pipeline(frame)
        scorer(frame, result)
        count = len(result.forecasts)
        if count > best_count:
            best, best_count = result, count
    return scorer.finish(), best, len(scene)


def evaluate(
    catalogue: Catalogue,
    models: Models,
    seed: int = 0,
    quick: bool = False,
    size: Size | None = None,
    progress: bool = True,
) -> Benchmark:
    """Draws the split's scenes for ``seed`` and runs them all."""
    size = size or (QUICK if quick else FULL)
    specs = [draw_scene(catalogue, i, seed, size) for i in range(size.scenes)]
    bench = Benchmark(catalogue.split, seed, quick, [], notes=catalogue.notes)
    bench.models = {"one person": "MoveNet Lightning int8 (bundled)", "several people": models.multi_name}
    if models.multi is None:
        skipped = [s for s in specs if len(s.actors) > 1]
        specs = [s for s in specs if len(s.actors) <= 1]
        bench.notes.append(
            f"no multi-person model (--yolo or ${YOLO_ENV}): "
            f"{len(skipped)} scenes with several people left out"
        )
    bench.specs = specs
    bar = Progress(len(specs), f"eval scenes ({catalogue.split})") if progress else None
    best_count = 0
    for spec in specs:
        model = models.single if len(spec.actors) <= 1 else models.multi
        assert model is not None
        score, best, frames = run_scene(spec, catalogue, model)
        for table in ("recovery", "forecasts", "identity"):
            for key, values in getattr(score, table).items():
                getattr(bench, table)[key].extend(values)
        bench.false_positives += score.false_positives
        bench.frames += frames
        if best is not None and len(best.forecasts) > best_count:
            bench.picture, best_count = best, len(best.forecasts)
        if bar:
            bar(f"{spec.name}: {len(spec.actors)} people, {frames} frames")
    return bench
