"""The whole per-frame chain of DESIGN.md: keypoint model, depth lifting, tracking with one
forecaster per person, with the time each stage takes."""

from __future__ import annotations

import dataclasses
import time
from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ._core import TimeNotIncreasingError
from .camera import DepthLookup
from .keypoints import Detections, KeypointModel
from .lifting import lift
from .sources import Frame
from .track import F64
from .tracker import Result, Tracker, TrackerConfig

STAGES = ("model", "lifting", "tracking", "forecasting")


class BadFrameError(ValueError):
    """A frame the pipeline cannot use (its model output is not keypoints); nothing changed."""


@dataclass
class FrameResult:
    frame: Frame
    detections: Detections
    joints: F64 | None
    """``(people, 17, 3)`` world joints, None for a colour-only frame."""
    people: list[Result]
    forecasts: dict[int, F64]
    """Detection index -> ``(horizons, 5)`` forecast of its confirmed track."""
    intervals: dict[int, F64] = field(default_factory=dict)
    """Detection index -> ``(horizons, 5)`` half-widths of the 80 % intervals around its
    forecast, once the track has checked its forecasts."""


@dataclass
class Pipeline:
    model: KeypointModel
    horizons: Sequence[float] = (0.4, 1.0)
    tracker_config: TrackerConfig = field(default_factory=TrackerConfig)
    lookup: DepthLookup = field(default_factory=DepthLookup)
    seconds: dict[str, float] = field(default_factory=lambda: defaultdict(float))
    frames: int = 0
    last_time: float | None = None

    def __post_init__(self) -> None:
        if any(not (np.isfinite(h) and h > 0) for h in self.horizons):
            raise ValueError(f"horizons must be positive seconds, got {list(self.horizons)}")
        if getattr(self.model, "faces_on_backs", False):
            # The nose is no evidence of the chest's side for a model that sees faces on backs.
            track = dataclasses.replace(self.tracker_config.track, face_weight=0.0)
            self.tracker_config = dataclasses.replace(self.tracker_config, track=track)
        self.tracker = Tracker(self.tracker_config)

    def __call__(self, frame: Frame) -> FrameResult:
        """One frame through every stage. A frame whose time stamp is not after the previous
        frame's raises :class:`~torsocast.TimeNotIncreasingError` before the model runs, and one
        whose model output is unusable raises :class:`BadFrameError`; either changes nothing."""
        if not np.isfinite(frame.time):
            raise BadFrameError(f"frame {frame.index}: its time stamp must be finite, got {frame.time}")
        if self.last_time is not None and not frame.time > self.last_time:
            raise TimeNotIncreasingError(
                f"frame {frame.index} at {frame.time} s is not after the previous frame's {self.last_time} s"
            )
        if frame.depth is not None and frame.depth.shape != frame.color.shape[:2]:
            raise BadFrameError(
                f"frame {frame.index}: depth {frame.depth.shape} is not registered to colour "
                f"{frame.color.shape[:2]} (the keypoints would read depth at the wrong pixels)"
            )
        clock = time.perf_counter()
        detections = self.model(frame.color)
        scores = detections.keypoints[..., 2]
        if ((scores < 0) | (scores > 1)).any():
            raise BadFrameError(
                f"frame {frame.index}: the keypoint model gave scores outside 0..1 "
                f"(from {np.nanmin(scores):g} to {np.nanmax(scores):g}); is it a keypoint model?"
            )
        self.last_time = frame.time
        clock = self._lap("model", clock)
        if frame.depth is None or frame.camera is None:
            self.frames += 1
            return FrameResult(frame, detections, None, [], {})
        joints = lift(detections.keypoints, frame.depth, frame.camera, self.lookup)
        # A keypoint the model barely believes in is missing, not a 3D joint.
        joints[detections.keypoints[..., 2] < self.tracker_config.track.min_score] = np.nan
        clock = self._lap("lifting", clock)
        return self.track(frame, detections, joints, clock)

    def track(self, frame: Frame, detections: Detections, joints: F64, clock: float) -> FrameResult:
        """The tracking and forecasting stages on already lifted joints."""
        assert frame.camera is not None
        position = np.asarray(frame.camera.camera_to_world)[:3, 3]
        people = self.tracker.update(frame.time, joints, detections.keypoints[..., 2], position)
        clock = self._lap("tracking", clock)
        forecasts, intervals = {}, {}
        for person in people:
            if person.track_id is not None and person.track is not None:
                ahead = person.track.forecast(list(self.horizons))
                if ahead is not None:
                    forecasts[person.detection] = ahead
                    spread = person.track.intervals(list(self.horizons))
                    if spread is not None:
                        intervals[person.detection] = spread
        self._lap("forecasting", clock)
        self.frames += 1
        return FrameResult(frame, detections, joints, people, forecasts, intervals)

    def _lap(self, stage: str, since: float) -> float:
        now = time.perf_counter()
        self.seconds[stage] += now - since
        return now

    def timing(self) -> dict[str, float]:
        """Mean milliseconds per frame of each stage that ran."""
        return {s: 1e3 * self.seconds[s] / max(self.frames, 1) for s in STAGES if s in self.seconds}
