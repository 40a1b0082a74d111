"""JSON Lines output: one object per frame.

Schema ``torsocast.frame/1`` (documented in ``docs/output.md``; a change of meaning bumps the
number). SI units and radians; azimuths wrapped to (-π, π]; NaN becomes null.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from pathlib import Path
from typing import IO, Any

import numpy as np

from ._core import InvalidArgumentError, NonFiniteError, body_frame
from .pipeline import FrameResult
from .sources import WORLD_FRAME, SkippedFrame

SCHEMA = "torsocast.frame/1"


def _clean(values: Any, digits: int = 4) -> Any:
    """Nested lists with NaN as None and floats rounded (millimetres, tenths of a milliradian)."""
    if isinstance(values, (np.ndarray, np.generic)):
        values = values.tolist()
    if isinstance(values, (list, tuple)):
        return [_clean(v, digits) for v in values]
    if isinstance(values, float):
        return None if not math.isfinite(values) else round(values, digits)
    return values


def record(result: FrameResult, horizons: Sequence[float], world_frame: str = WORLD_FRAME) -> dict[str, Any]:
    """The JSON object of one frame, its body frames' parent ``world_frame``."""
    det = result.detections
    people = []
    for i in range(len(det)):
        person: dict[str, Any] = {
            "id": None,
            "score": _clean(float(det.scores[i])),
            "box": _clean(det.boxes[i], 1),
            "keypoints": _clean(det.keypoints[i], 2),
        }
        if result.joints is not None:
            outcome = result.people[i]
            obs = outcome.observation
            person["id"] = outcome.track_id
            person["joints"] = _clean(result.joints[i])
            if obs is not None:
                person.update(
                    centre=_clean(obs.pose[:3]) if obs.pose is not None else None,
                    azimuth=_clean(float(obs.pose[3])) if obs.pose is not None else None,
                    elevation=_clean(float(obs.pose[4])) if obs.pose is not None else None,
                    estimate=obs.estimate,
                    swapped=obs.swapped,
                    heading_confident=obs.heading_confident,
                    heading_held=obs.heading_held,
                    facing_evidence=_clean(obs.facing_evidence, 2),
                    joint_status=obs.joint_status.tolist(),
                    completed=np.flatnonzero(obs.completed).tolist(),
                    weight=_clean(obs.weight),
                    grid=obs.grid,
                )
                if obs.pose is not None and outcome.track_id is not None:
                    person["body_frame"] = _body_frame(outcome.track_id, obs.pose, world_frame)
            ahead = result.forecasts.get(i)
            spread = result.intervals.get(i)
            person["forecast"] = (
                None
                if ahead is None
                else [
                    {
                        "horizon": h,
                        "pose": _clean(ahead[k]),
                        "half_width80": None if spread is None else _clean(spread[k]),
                    }
                    for k, h in enumerate(horizons)
                ]
            )
        people.append(person)
    unseen = [
        {
            "id": track.id,
            "last_time": _clean(track.last_time, 6),
            "pose": _clean(track.pose),
            "half_width80": _clean(track.half_width80),
            "body_frame": None if track.pose is None else _body_frame(track.id, track.pose, world_frame),
        }
        for track in result.unseen
    ]
    return {
        "schema": SCHEMA,
        "frame": result.frame.index,
        "time": _clean(result.frame.time, 6),
        "people": people,
        "unseen": unseen,
    }


def body_frame_of(pose: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The REP-155 body frame of a pose, (translation, quaternion ``[x, y, z, w]``); None for one
    the core refuses (a forecast whose elevation has left 0 to π: no upright direction to take
    the frame's roll from)."""
    try:
        return body_frame(pose)  # type: ignore[no-any-return]
    except (InvalidArgumentError, NonFiniteError):
        return None


def _body_frame(track_id: int, pose: np.ndarray, world_frame: str) -> dict[str, Any] | None:
    """The body frame ``body_<id>`` of a pose as a JSON object (:func:`body_frame_of`), in
    ``world_frame``."""
    frame = body_frame_of(pose)
    if frame is None:
        return None
    translation, rotation = frame
    return {
        "frame_id": world_frame,
        "child_frame_id": f"body_{track_id}",
        "translation": _clean(translation),
        "rotation": _clean(rotation, 6),
    }


class JsonLines:
    """Writes one :func:`record` per line to ``path`` (a context manager)."""

    def __init__(self, path: str | Path, horizons: Sequence[float], world_frame: str = WORLD_FRAME) -> None:
        self.path = Path(path)
        self.horizons = list(horizons)
        self.world_frame = world_frame
        self.file: IO[str] | None = None

    def __enter__(self) -> JsonLines:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.file = self.path.open("w")
        return self

    def write(self, result: FrameResult) -> None:
        assert self.file is not None, "use JsonLines as a context manager"
        self.file.write(json.dumps(record(result, self.horizons, self.world_frame), allow_nan=False) + "\n")

    def skipped(self, frame: SkippedFrame) -> None:
        """The line of a frame the source could not read: no people, and why."""
        assert self.file is not None, "use JsonLines as a context manager"
        line = {
            "schema": SCHEMA,
            "frame": frame.index,
            "time": frame.time,
            "people": [],
            "skipped": frame.reason,
        }
        self.file.write(json.dumps(line, allow_nan=False) + "\n")

    def __exit__(self, *exc: object) -> None:
        if self.file is not None:
            self.file.close()
