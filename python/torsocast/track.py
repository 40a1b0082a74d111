"""One tracked person: the thesis' per-person chain (section 3.2) on 3D keypoints.

Each frame: undo a left/right swap of the detector, move a far shoulder or hip that the body
hides back to its depth (profile views), gate every joint against its previous position relative
to the body's motion, fit the torso plane (or, without enough torso joints,
take the azimuth from the shoulders), and feed the pose to the person's forecaster on its
fixed-rate grid. The chain runs in the core (``torso_core::person``), one call per person and
frame; this module holds its configuration and the track's id.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from ._core import ForecasterConfig, Observation, Person

F64 = npt.NDArray[np.float64]

__all__ = ["F64", "Observation", "Track", "TrackConfig", "live_forecaster"]


def live_forecaster() -> ForecasterConfig:
    """The thesis' forecaster with its Butterworth low-pass on all five pose components at 1 Hz.
    The thesis filters only the angles (its mocap positions are clean) at 5 Hz; a keypoint
    detector's centres jitter by centimetres, and with N = 1 the spline interpolates, so the
    forecast continues the last noisy step. On the bundled CMU training walks seen through the
    demo's camera and MoveNet, the median centre error 1 s ahead drops from 79 to 42 cm (holding
    still: 100 cm); 0.7 to 2 Hz were tried (docs/demo.md)."""
    return ForecasterConfig.live()


@dataclass(frozen=True)
class TrackConfig:
    """Per-person parameters (defaults: the thesis' where it gives them)."""

    forecaster: ForecasterConfig = field(default_factory=live_forecaster)
    gate_threshold: float = 0.10
    """Largest accepted joint displacement between frames relative to the body's (m); the
    thesis' 10 cm assumes about 25 frames per second."""
    gate_max_replacements: int = 10
    min_score: float = 0.3
    """Keypoints scored below this are missing (NaN)."""
    facing_memory: float = 1.0
    """Time constant (s) over which the evidence for which way the chest faces is forgotten
    (``torso_core::sides``: the labels, the nose and the walking direction are weighed)."""
    face_weight: float = 2.0
    """Weight of the nose standing in front of the shoulders, relative to the labels'."""
    motion_weight: float = 1.0
    """Weight of the walking direction, relative to the labels'."""
    self_check: bool = True
    """The track scores its forecasts at 0.4, 1 and 2 s against its own later samples and gives
    out, per pose component, the mix of holding still, the damped trend and the plain trend that
    erred least (``torso_core::selfcheck``); False gives the forecaster's output as it is."""
    occlusion_ratio: float = 0.8
    """A shoulder or hip pair measured shorter than this fraction of the width learned in
    frontal views has its far joint moved back along its camera ray to that width (profile
    views: the far joint's depth is read from the near side); 0 turns this off."""


class Track:
    """One person's state across frames: an id and the core's :class:`~torsocast.Person`."""

    def __init__(self, track_id: int, config: TrackConfig | None = None) -> None:
        self.id = track_id
        self.config = c = config or TrackConfig()
        self.person = Person(
            c.forecaster,
            gate_threshold=c.gate_threshold,
            gate_max_replacements=c.gate_max_replacements,
            min_score=c.min_score,
            facing_memory=c.facing_memory,
            face_weight=c.face_weight,
            motion_weight=c.motion_weight,
            self_check=c.self_check,
            occlusion_ratio=c.occlusion_ratio,
        )

    def update(self, t: float, joints: F64, scores: F64, camera_position: F64) -> Observation:
        """One frame: ``joints (17, 3)`` in the world frame (NaN where missing), their ``scores``.
        A time stamp that does not increase raises :class:`~torsocast.TimeNotIncreasingError`
        and leaves the track as it was."""
        return self.person.update(t, joints, scores, camera_position)

    def forecast(self, horizons: list[float]) -> F64 | None:
        """``(len(horizons), 5)`` poses ahead of the last grid sample, azimuth wrapped; None until
        the history holds enough samples."""
        return self.person.forecast(horizons) if horizons else None

    def intervals(self, horizons: list[float]) -> F64 | None:
        """``(len(horizons), 5)`` half-widths of the central 80 % intervals around
        :meth:`forecast`'s poses (the spread of the track's own recent forecast errors); None
        until the track has checked a forecast."""
        return self.person.intervals(horizons) if horizons else None

    @property
    def last_time(self) -> float | None:
        """Grid time of the forecaster's newest sample: forecasts count from here."""
        return self.person.last_time

    @property
    def samples(self) -> int:
        """Samples in the forecaster's history."""
        return len(self.person)
