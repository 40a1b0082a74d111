"""Multi-person tracking: detections to tracks by their 3D torso centres.

Each frame, the cost of giving detection j to track i is the distance between the track's last
torso centre and the detection's; the optimal assignment (Hungarian, ``torso_core::assignment``)
is taken, and pairs further apart than ``gate`` are refused. An unmatched detection opens a
tentative track, which is confirmed (and given the next integer id) after ``min_hits`` matched
frames; a track unmatched for ``max_missing`` seconds is dropped (a tentative one at its first
miss).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from ._core import InvalidArgumentError, NonFiniteError, ShapeError, TimeNotIncreasingError, linear_assignment
from .keypoints import coco
from .track import F64, Observation, Track, TrackConfig


@dataclass(frozen=True)
class TrackerConfig:
    gate: float = 0.6
    """Largest torso-centre distance (m) between a track and its detection in one frame: a
    walking person covers 0.6 m in 0.4 s."""
    min_hits: int = 3
    """Matched frames before a track is confirmed and reported with an id."""
    max_missing: float = 1.0
    """Seconds without a match after which a confirmed track is dropped."""
    track: TrackConfig = field(default_factory=TrackConfig)


_TORSO_MASK = np.isin(np.arange(17), coco.TORSO)


def detection_centres(joints: F64, scores: F64, min_score: float) -> F64:
    """Where each detection is, for association: ``(people, 3)``, the mean of its seen torso
    joints, else of every seen joint; a NaN row for a detection with no 3D joint at all."""
    seen = np.isfinite(joints).all(axis=2) & (scores >= min_score)
    use = np.where((seen & _TORSO_MASK).any(axis=1)[:, None], seen & _TORSO_MASK, seen)
    total = np.where(use[..., None], joints, 0.0).sum(axis=1)
    with np.errstate(invalid="ignore"):  # 0 / 0 for a detection with nothing seen: NaN, wanted
        return total / use.sum(axis=1)[:, None]  # type: ignore[no-any-return]


@dataclass
class Slot:
    """A track with its bookkeeping."""

    track: Track
    centre: F64
    hits: int = 1
    last_seen: float = 0.0
    confirmed: bool = False


@dataclass
class Result:
    """One detection's outcome in a frame."""

    detection: int
    """Index of the detection in the frame's :class:`~torsocast.keypoints.Detections`."""
    track_id: int | None
    """The confirmed track's id; None for a tentative track or an unplaceable detection."""
    observation: Observation | None
    track: Track | None


class Tracker:
    def __init__(self, config: TrackerConfig | None = None) -> None:
        self.config = config or TrackerConfig()
        self.slots: list[Slot] = []
        self.next_id = 1
        self._tentative = -1  # tentative tracks count down from -1; ids are given at confirmation
        self.last_t: float | None = None

    def update(
        self, t: float, joints: npt.NDArray[np.float64], scores: npt.NDArray[np.float64], camera_position: F64
    ) -> list[Result]:
        """One frame: ``joints (people, 17, 3)`` in the world frame and their ``scores``. Every
        argument is checked before anything changes: a refused frame leaves the tracker as it
        was."""
        c = self.config
        joints, scores = np.asarray(joints, dtype=np.float64), np.asarray(scores, dtype=np.float64)
        camera_position = np.asarray(camera_position, dtype=np.float64)
        if not np.isfinite(t):
            raise NonFiniteError(f"frame time must be finite, got {t}")
        if self.last_t is not None and not t > self.last_t:
            raise TimeNotIncreasingError(f"frame time {t} s is not after the last frame's {self.last_t} s")
        if joints.ndim != 3 or joints.shape[1:] != (17, 3) or scores.shape != joints.shape[:2]:
            raise ShapeError(
                "joints must be (people, 17, 3) and scores (people, 17), "
                f"got {joints.shape} and {scores.shape}"
            )
        if camera_position.shape != (3,) or not np.isfinite(camera_position).all():
            raise NonFiniteError(f"camera_position must be 3 finite numbers, got {camera_position}")
        bad = (scores < 0) | (scores > 1)
        if bad.any():
            raise InvalidArgumentError(f"scores must lie in 0..1 (NaN: not scored), got {scores[bad][0]:g}")
        self.last_t = t
        centres = detection_centres(joints, scores, c.track.min_score)
        placeable = np.flatnonzero(np.isfinite(centres[:, 0])).tolist()
        pairs = self.associate(centres[placeable])
        matched = {placeable[d]: s for s, d in pairs}
        results = [Result(i, None, None, None) for i in range(len(joints))]
        for d in placeable:
            slot = matched.get(d)
            if slot is None:
                slot = Slot(Track(self._tentative, c.track), centres[d], hits=0)
                self._tentative -= 1
                self.slots.append(slot)
            obs = slot.track.update(t, joints[d], scores[d], camera_position)
            slot.hits += 1
            slot.last_seen = t
            pose = obs.pose
            slot.centre = pose[:3] if pose is not None else centres[d]
            if not slot.confirmed and slot.hits >= c.min_hits:
                slot.confirmed = True
                slot.track.id = self.next_id
                self.next_id += 1
            results[d] = Result(d, slot.track.id if slot.confirmed else None, obs, slot.track)
        self.slots = [
            s for s in self.slots if s.last_seen == t or (s.confirmed and t - s.last_seen <= c.max_missing)
        ]
        return results

    def associate(self, centres: F64) -> list[tuple[Slot, int]]:
        """Optimal (slot, detection) pairs within the gate distance; ``centres (n, 3)``."""
        if not self.slots or not len(centres):
            return []
        tracks = np.array([s.centre for s in self.slots])
        cost = np.linalg.norm(tracks[:, None, :] - centres[None, :, :], axis=2)
        rows, cols = linear_assignment(np.where(cost <= self.config.gate, cost, 1e6))
        return [(self.slots[r], int(k)) for r, k in zip(rows, cols) if cost[r, k] <= self.config.gate]

    @property
    def tracks(self) -> list[Track]:
        """The confirmed tracks."""
        return [s.track for s in self.slots if s.confirmed]
