"""The whole per-frame chain: the keypoint model (here, onnxruntime), then one core call per frame
for the rest (depth lifting, tracking, one forecaster per person), with the time each takes."""

from __future__ import annotations

import copy
import time
from collections import defaultdict
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TypeVar

import numpy as np

from ._core import MAX_HORIZON, TimeNotIncreasingError, TorsocastError
from .keypoints import Detections, KeypointModel
from .sources import Frame
from .tracker import F64, Tracker, TrackerConfig, TrackOutcome

#: What :meth:`Pipeline.timing` reports: the model, and the core's call (lifting, tracking and
#: forecasting together).
STAGES = ("model", "tracking")

T = TypeVar("T")

#: Seconds ahead that a run forecasts unless told otherwise: the thesis' short and middle horizons.
HORIZONS = (0.4, 1.0)


class BadFrameError(ValueError):
    """A frame the pipeline cannot use (its model output is not keypoints); nothing changed."""


@dataclass(frozen=True)
class UnseenTrack:
    """A confirmed track the frame did not show (hidden, out of view, not detected), kept while
    its person may come back (``TrackerConfig.max_missing``): where its forecast puts the person
    at the frame's time."""

    id: int
    last_time: float
    """Grid time of the track's newest sample, about when its person was last seen."""
    pose: F64 | None
    """``(5,)`` the track's forecast for the frame's time; None while its history is too short
    to forecast."""
    half_width80: F64 | None
    """``(5,)`` half-widths of the 80 % interval around ``pose``; None while its history is too
    short for a line."""


@dataclass
class FrameResult:
    frame: Frame
    detections: Detections
    joints: F64 | None
    """``(people, 17, 3)`` world joints, None for a colour-only frame."""
    people: list[TrackOutcome]
    """One outcome per detection (empty for a colour-only frame)."""
    forecasts: dict[int, F64]
    """Detection index -> ``(horizons, 5)`` forecast of its confirmed track."""
    intervals: dict[int, F64] = field(default_factory=dict)
    """Detection index -> ``(horizons, 5)`` half-widths of the 80 % intervals around its
    forecast, once the track's history is long enough for a line."""
    restarted_from: float | None = None
    """The previous frame's time when this frame's clock went back by more than
    :attr:`Pipeline.restart_after`: every track was dropped and tracking started again."""
    unseen: list[UnseenTrack] = field(default_factory=list)
    """The confirmed tracks this frame did not show, in order of birth."""


@dataclass
class Pipeline:
    model: KeypointModel
    horizons: Sequence[float] = HORIZONS
    tracker_config: TrackerConfig = field(default_factory=TrackerConfig)
    seconds: dict[str, float] = field(default_factory=lambda: defaultdict(float))
    frames: int = 0
    restart_after: float = 10.0
    """Seconds a frame's time stamp may lie before the previous frame's and still be refused as
    out of order; a frame further back starts the stream again (every track dropped, ids go on
    counting): a recording replayed from its start, or the frames after one stamped far ahead,
    which would otherwise all be refused. A frame the tracker then refuses undoes the restart."""

    def __post_init__(self) -> None:
        if any(not (0 < h <= MAX_HORIZON) for h in self.horizons):
            raise ValueError(f"horizons must be seconds in (0, {MAX_HORIZON:g}], got {list(self.horizons)}")
        if getattr(self.model, "faces_on_backs", False):
            # The nose is no evidence of the chest's side for a model that sees faces on backs.
            person = self.tracker_config.person.replace(face_weight=0.0)
            self.tracker_config = self.tracker_config.replace(person=person)
        self.tracker = Tracker(self.tracker_config)
        self._reset_model()

    def __call__(self, frame: Frame) -> FrameResult:
        """One frame through every stage. A frame whose time stamp is not after the previous
        frame's raises :class:`~torsocast.TimeNotIncreasingError` before the model runs, and one
        whose model output is unusable raises :class:`BadFrameError`; either changes nothing."""
        # The tracker's time rule, asked before the model runs so that a refused frame costs none.
        restarted_from = None
        try:
            self.tracker.check_time(frame.time)
        except TimeNotIncreasingError as e:
            last = self.tracker.last_time
            if last is None or not last - frame.time > self.restart_after:
                raise TimeNotIncreasingError(f"frame {frame.index}: {e}") from e
            restarted_from = last
        except TorsocastError as e:
            raise BadFrameError(f"frame {frame.index}: {e}") from e
        if frame.depth is not None and frame.depth.shape != frame.color.shape[:2]:
            raise BadFrameError(
                f"frame {frame.index}: depth {frame.depth.shape} is not registered to colour "
                f"{frame.color.shape[:2]} (the keypoints would read depth at the wrong pixels)"
            )
        if restarted_from is not None:
            self._reset_model()
        clock = time.perf_counter()
        try:
            detections = self.model(frame.color)
        except ValueError as e:  # an image the model cannot take (not uint8 RGB): this frame only
            raise BadFrameError(f"frame {frame.index}: {e}") from e
        clock = self._lap("model", clock)
        before_restart = None
        if restarted_from is not None:
            before_restart = copy.copy(self.tracker)  # put back if the tracker refuses the frame
            self.tracker.restart()
        if frame.depth is None or frame.camera is None:
            # No 3D joints: the frame still passes the tracker (its time stamp, the model's
            # scores), which ages the tracks and opens none.
            unseen = np.full(detections.keypoints.shape, np.nan)
            self._tracked(
                frame,
                lambda: self.tracker.update(
                    frame.time, unseen, detections.keypoints[..., 2], [0.0, 0.0, 0.0]
                ),
                before_restart,
            )
            self.frames += 1
            return FrameResult(
                frame,
                detections,
                None,
                [],
                {},
                restarted_from=restarted_from,
                unseen=self._unseen(frame.time, []),
            )
        camera, depth = frame.camera, frame.depth
        k = camera.intrinsics
        joints, people = self._tracked(
            frame,
            lambda: self.tracker.step(
                frame.time,
                detections.keypoints,
                depth,
                (k.fx, k.fy, k.cx, k.cy),
                k.coefficients,
                camera.camera_to_world,
                list(self.horizons),
            ),
            before_restart,
        )
        result = self._finish(frame, detections, joints, people, clock)
        result.restarted_from = restarted_from
        return result

    @property
    def last_time(self) -> float | None:
        """Time of the last frame taken."""
        return self.tracker.last_time  # type: ignore[no-any-return]

    def _reset_model(self) -> None:
        """A new stream: a model that keeps something from frame to frame forgets it."""
        reset = getattr(self.model, "reset", None)
        if reset is not None:
            reset()

    def _tracked(self, frame: Frame, call: Callable[[], T], before_restart: Tracker | None) -> T:
        """``call``'s result; a frame the tracker refuses (it changed nothing) is a bad frame, and
        a restart for it is undone."""
        try:
            return call()
        except TorsocastError as e:
            if before_restart is not None:
                self.tracker = before_restart
            raise BadFrameError(f"frame {frame.index}: the tracker refused it: {e}") from e

    def track(self, frame: Frame, detections: Detections, joints: F64, clock: float) -> FrameResult:
        """The tracking and forecasting stages on already lifted joints (a replay of cached
        detections)."""
        assert frame.camera is not None
        position = np.asarray(frame.camera.camera_to_world)[:3, 3]
        scores = detections.keypoints[..., 2]
        people = self.tracker.update(frame.time, joints, scores, position, list(self.horizons))
        return self._finish(frame, detections, joints, people, clock)

    def _finish(
        self, frame: Frame, detections: Detections, joints: F64, people: list[TrackOutcome], clock: float
    ) -> FrameResult:
        unseen = self._unseen(frame.time, people)  # the core's forecasts: tracking time too
        self._lap("tracking", clock)
        self.frames += 1
        forecasts = {p.detection: p.forecast for p in people if p.forecast is not None}
        intervals = {p.detection: p.intervals for p in people if p.intervals is not None}
        return FrameResult(frame, detections, joints, people, forecasts, intervals, unseen=unseen)

    def _unseen(self, t: float, people: list[TrackOutcome]) -> list[UnseenTrack]:
        """The confirmed tracks that took no detection in the frame at ``t``, each forecast to ``t``."""
        shown = {p.track_id for p in people}
        unseen = []
        for track in self.tracker.tracks:
            if track.id in shown or track.last_time is None:
                continue
            # The grid slot of the last sample may lie a little after that frame's time.
            ahead = [max(t - track.last_time, 0.0)]
            pose = self.tracker.forecast(track.id, ahead)
            spread = self.tracker.intervals(track.id, ahead)
            unseen.append(
                UnseenTrack(
                    track.id,
                    track.last_time,
                    None if pose is None else pose[0],
                    None if spread is None else spread[0],
                )
            )
        return unseen

    def _lap(self, stage: str, since: float) -> float:
        now = time.perf_counter()
        self.seconds[stage] += now - since
        return now

    def timing(self) -> dict[str, float]:
        """Mean milliseconds per frame of each stage that ran."""
        return {s: 1e3 * self.seconds[s] / max(self.frames, 1) for s in STAGES if s in self.seconds}
