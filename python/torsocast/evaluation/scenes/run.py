"""Runs the scenes benchmark: every scene's frames through the real pipeline and a real keypoint
model, scored against the truth."""

from __future__ import annotations

import hashlib
import time
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ...keypoints import Detections, KeypointModel, open_model
from ...pipeline import FrameResult, Pipeline
from ...progress import Progress
from ...sources import Frame
from ...synthetic.scenes import RenderedScene, SceneSpec
from .faults import NO_FAULTS, Faults
from .oracle import NO_ORACLE, Oracle
from .plan import FULL, QUICK, ROBOT_SPEED, Catalogue, Size, draw_scene, on_robot
from .score import SceneScore, Scorer, assign

HORIZONS = (0.4, 1.0, 2.0)
#: The records a run keeps, one CSV each: per person-frame, per forecast and horizon, per
#: person, per unseen track and frame.
TABLES = ("recovery", "forecasts", "identity", "unseen")
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
        """The bundled MoveNet and the YOLO-pose file ``yolo`` (None: no multi-person model;
        the command line resolves ``--yolo``, ``$TORSOCAST_YOLO`` and its default)."""
        multi = open_model(yolo) if yolo else None
        return cls(open_model(None), multi, Path(yolo).name if yolo else "")

    def for_scene(self, spec: SceneSpec) -> KeypointModel | None:
        """The model that runs ``spec``: MoveNet for one person, the multi-person model else."""
        return self.single if len(spec.actors) <= 1 else self.multi


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
    unseen: dict[str, list] = field(default_factory=lambda: defaultdict(list))  # type: ignore[type-arg]
    false_positives: int = 0
    frames: int = 0
    notes: list[str] = field(default_factory=list)
    models: dict[str, str] = field(default_factory=dict)
    picture: FrameResult | None = None
    """The frame drawn in the report: the one with the most people estimated."""

    def columns(self, table: str) -> dict[str, np.ndarray]:
        return {k: np.asarray(v) for k, v in getattr(self, table).items()}


def _cache_file(cache: Path, spec: SceneSpec, model: KeypointModel) -> Path:
    turns = [a.turn for a in spec.actors if a.turn]  # not in the repr (see Actor.turn)
    bursts = [a.bursts for a in spec.actors if a.bursts]
    pauses = [a.pauses for a in spec.actors if a.pauses]
    variant = getattr(model, "variant", "")
    variant = f" {variant}" if variant else ""
    # "lifted": the joints before the tracker dropped any (recordings of the joints as the
    # tracks took them replayed some frames otherwise than the live run).
    text = f"{spec!r} {type(model).__name__} {model.input_size}{variant} lifted"
    text += f" turns {turns}" if turns else ""
    text += f" bursts {bursts}" if bursts else ""
    text += f" pauses {pauses}" if pauses else ""
    text += f" robot {spec.robot!r}" if spec.robot is not None else ""  # not in the repr either
    key = hashlib.sha256(text.encode()).hexdigest()[:16]
    return cache / f"{spec.name}-{key}.npz"


def _replay_options(oracle: Oracle, faults: Faults) -> str:
    """The command-line options of what a replay was asked to do, as a user typed them."""
    return " and ".join(o for o in (oracle.options, faults.options) if o)


def _live(scene: RenderedScene, pipeline: Pipeline, record: dict[str, list] | None):  # type: ignore[no-untyped-def, type-arg]
    """Renders every frame and runs the whole pipeline; ``record`` keeps what a replay needs.
    Yields each frame's time, the frame, the pipeline's result, the detections' owners and who
    is visible."""
    for frame in scene:
        result = pipeline(frame)
        owner = assign(
            result.detections.keypoints, frame.extra["labels"], pipeline.tracker_config.person.min_score
        )
        visible = scene.visible(frame)
        if record is not None:
            record["keypoints"].append(result.detections.keypoints)
            record["joints"].append(pipeline.tracker.lifted)
            record["owner"].append(np.asarray(owner, dtype=np.int64))
            record["visible"].append(visible)
        yield frame.time, frame, result, owner, visible


def _replay(scene: RenderedScene, pipeline: Pipeline, path: Path, oracle: Oracle, faults: Faults):  # type: ignore[no-untyped-def]
    """The frames' detections and lifted joints as recorded, through the tracking stages only,
    as :func:`_live` yields them; with an ``oracle``, what it asks put right by the truth first
    (:mod:`.oracle`), and with ``faults`` the frames dropped and stamped as they say
    (:mod:`.faults`; the time yielded is still the frame's own)."""
    # Each item of an .npz is read (and decompressed) again on every access: read them once.
    with np.load(path) as archive:
        data = {name: archive[name] for name in archive.files}
    ends = np.cumsum(data["people"])
    # The pixels' oracle lifts from the depth images: the frames are rendered again.
    rendered = iter(scene) if oracle.pixels else None
    given, stamps = faults.frames(scene.spec)
    told = faults.cameras(scene.spec)
    for k, t in enumerate(scene.spec.times):
        again = next(rendered) if rendered is not None else None
        if not given[k]:
            continue
        rows = slice(ends[k] - data["people"][k], ends[k])
        keypoints, joints = data["keypoints"][rows], data["joints"][rows]
        owner = data["owner"][rows].tolist()
        truth = np.array([scene.truth_at(i, t) for i in range(len(scene.clips))]).reshape(-1, 5)
        if oracle:
            keypoints, joints = keypoints.copy(), joints.copy()  # put right in place
            skeletons = [scene.joints_at(i, float(t)) for i in range(len(scene.clips))]
            oracle.apply(keypoints, joints, owner, truth, skeletons, again, pipeline.tracker_config)
        camera = pose = scene.camera_at(float(t))
        if told is not None:
            # Lifted with the true pose: into the world as the pose told would have put them.
            pose = told[k]
            joints = pose.to_world(camera.to_optical(joints))
        detections = Detections(keypoints, np.zeros((len(keypoints), 4)), np.ones(len(keypoints)))
        frame = Frame(k, float(stamps[k]), np.zeros((1, 1, 3), np.uint8), None, pose)
        frame.extra["truth"] = truth
        frame.extra["camera"] = camera
        result = pipeline.track(frame, detections, joints, time.perf_counter())
        yield float(t), frame, result, owner, data["visible"][k]


def run_scene(
    spec: SceneSpec,
    catalogue: Catalogue,
    model: KeypointModel,
    horizons: Sequence[float] = HORIZONS,
    cache: Path | None = None,
    oracle: Oracle = NO_ORACLE,
    faults: Faults = NO_FAULTS,
) -> tuple[SceneScore, FrameResult | None, int]:
    """One scene through the pipeline: its :class:`~.score.SceneScore`, the frame with the most
    forecasts (None when replayed) and the number of frames the tracker was given. With a
    ``cache`` folder, the model's detections and the lifted joints of each frame are kept there,
    and a later run of the same scene with the same model replays them through the tracking
    stages alone (for changes after the model: tracking, the per-person chain, forecasting,
    scoring). With an ``oracle``, a replay puts what it asks right by the truth first
    (:mod:`.oracle`: bounds and diagnostics, not results); with ``faults``, it drops and stamps
    the frames as they say (:mod:`.faults`)."""
    scene = RenderedScene(spec, {a.motion: catalogue.motion(a.motion) for a in spec.actors})
    pipeline = Pipeline(model, horizons)
    scorer = Scorer(scene, list(horizons), pipeline.tracker_config.person.min_score)
    path = _cache_file(cache, spec, model) if cache is not None else None
    record: dict[str, list] | None = defaultdict(list) if path is not None else None  # type: ignore[type-arg]
    replaying = path is not None and path.is_file()
    if (oracle or faults) and not replaying:
        raise ValueError(
            f"{_replay_options(oracle, faults)} replays recorded detections, and {spec.name} has none "
            "in the cache"
        )
    frames = (
        _replay(scene, pipeline, path, oracle, faults)  # type: ignore[arg-type]
        if replaying
        else _live(scene, pipeline, record)
    )
    best, best_count, given = None, 0, 0
    for t, frame, result, owner, visible in frames:
        scorer(t, result, owner, visible, frame.extra["truth"], stamp=frame.time)
        given += 1
        if not replaying and len(result.forecasts) > best_count:
            best, best_count = result, len(result.forecasts)
    if path is not None and not replaying and record is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        np.savez_compressed(
            path,
            people=np.array([len(k) for k in record["keypoints"]]),
            keypoints=np.concatenate(record["keypoints"]).reshape(-1, 17, 3),
            joints=np.concatenate(record["joints"]).reshape(-1, 17, 3),
            owner=np.concatenate(record["owner"]),
            visible=np.array(record["visible"]).reshape(len(spec.times), len(spec.actors)),
        )
    return scorer.finish(), best, given


def evaluate(
    catalogue: Catalogue,
    models: Models,
    seed: int = 0,
    quick: bool = False,
    size: Size | None = None,
    progress: bool = True,
    cache: Path | None = None,
    oracle: Oracle = NO_ORACLE,
    picture: bool = True,
    faults: Faults = NO_FAULTS,
    robot: bool = False,
) -> Benchmark:
    """Draws the split's scenes for ``seed`` and runs them all (``cache``, ``oracle`` and
    ``faults``: see :func:`run_scene`; an oracle or faults need every scene recorded, and say so
    before any work, as faults a scene cannot take). With ``robot``, every scene is seen from a
    robot that drives past its people (:func:`~.plan.on_robot`), recorded apart from the scenes
    seen from a camera that stands still.
    Without ``picture``, a run whose every scene was replayed keeps no frame for the report's
    figure (it would render the most crowded scene again for it)."""
    size = size or (QUICK if quick else FULL)
    specs = [draw_scene(catalogue, i, seed, size) for i in range(size.scenes)]
    specs += [draw_scene(catalogue, size.scenes + i, seed, size, turning=True) for i in range(size.turning)]
    first = size.scenes + size.turning
    specs += [draw_scene(catalogue, first + i, seed, size, stopping=True) for i in range(size.stopping)]
    first += size.stopping
    specs += [draw_scene(catalogue, first + i, seed, size, pausing=True) for i in range(size.pausing)]
    first += size.pausing
    specs += [draw_scene(catalogue, first + i, seed, size, hiding=True) for i in range(size.hiding)]
    if robot:
        specs = [on_robot(s) for s in specs]
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
    if oracle or faults:
        missing = [
            s.name
            for s in specs
            if cache is None or not _cache_file(cache, s, models.for_scene(s)).is_file()  # type: ignore[arg-type]
        ]
        if missing:
            raise ValueError(
                f"{_replay_options(oracle, faults)} replays recorded detections: {len(missing)} of the "
                f"{len(specs)} scenes have none (run eval scenes with the same --cache first)"
            )
    bench.notes.extend(oracle.notes())
    if robot:
        bench.notes.append(
            f"every scene seen from a robot driving past its people at {ROBOT_SPEED[0]} to "
            f"{ROBOT_SPEED[1]} m/s and panning (--robot; its pose told to the pipeline exactly)"
        )
    for spec in specs:
        faults.frames(spec)  # a fault a scene cannot take is said now, not after the run
        faults.cameras(spec)
    bar = Progress(len(specs), f"eval scenes ({catalogue.split})") if progress else None
    best_count = 0
    for spec in specs:
        model = models.for_scene(spec)
        assert model is not None
        score, best, frames = run_scene(spec, catalogue, model, cache=cache, oracle=oracle, faults=faults)
        for table in TABLES:
            for key, values in getattr(score, table).items():
                getattr(bench, table)[key].extend(values)
        bench.false_positives += score.false_positives
        bench.frames += frames
        if best is not None and len(best.forecasts) > best_count:
            bench.picture, best_count = best, len(best.forecasts)
        if bar:
            bar(f"{spec.name}: {len(spec.actors)} people, {frames} frames")
    if picture and bench.picture is None and specs:
        # Every scene was replayed (no images): render the most crowded one again for the figure.
        crowd = max(specs, key=lambda s: len(s.actors))
        model = models.for_scene(crowd)
        assert model is not None
        _, bench.picture, _ = run_scene(crowd, catalogue, model)
    total = sum(len(s.times) for s in specs)
    bench.notes.extend(faults.notes(total - bench.frames, total))
    return bench
