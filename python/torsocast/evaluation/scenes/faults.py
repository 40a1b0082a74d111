"""Sensor faults a replay of recorded detections can put into a split's frames: frames dropped,
one stall of the camera, time stamps that jitter. Unlike the oracles these give results: what the
tracking and forecasting make of a robot's real stream, where the camera or the computer drops
frames when busy, a driver stalls, and stamps come late or early by a few milliseconds.

**Dropped frames** (``--drop FRACTION``). That share of each scene's frames is never given to
the tracker; drops come in bursts of :data:`DROP_BURST` frames on average (a busy computer, a
lost USB packet), drawn frame by frame as a two-state chain so that the share holds.

**A stall** (``--stall SECONDS``). Once in each scene, at a time drawn at least
:data:`STALL_AFTER` into it, the camera sends nothing for that long: everyone may have moved,
turned or left with nothing to show it.

**Jittered stamps** (``--jitter SECONDS``). Each frame given to the tracker is stamped up to
that far either side of when it was taken (uniform), less than half a frame's interval, so the
stamps still increase. Records are kept at the time the frame was taken, and a forecast is
scored at the time it aims at on the stamp's clock, as a robot would use it.

Each scene draws its own faults from its name, so every run of a split, with any code, drops the
same frames: two replays with the same faults compare frame for frame (``eval compare``), and
one against a replay without them on the frames both hold (``eval compare --common``). A live
run takes no faults: they apply to recorded detections, as the oracles do.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ...synthetic.scenes import SceneSpec

#: Mean length (frames) of a run of dropped frames.
DROP_BURST = 2.0
#: Earliest time (s) into a scene that its stall starts: its people have tracks by then.
STALL_AFTER = 1.0


@dataclass(frozen=True)
class Faults:
    """What a replay does to each scene's frames: the share of frames dropped, the length (s)
    of its one stall and how far (s) each stamp may move either way. All zero: nothing."""

    drop: float = 0.0
    stall: float = 0.0
    jitter: float = 0.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.drop < 1.0:
            raise ValueError(f"--drop: expected a share of the frames from 0 to below 1, got {self.drop}")
        for option, value in (("--stall", self.stall), ("--jitter", self.jitter)):
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"{option}: expected a finite, non-negative time in seconds, got {value}")

    def __bool__(self) -> bool:
        return bool(self.drop or self.stall or self.jitter)

    @property
    def options(self) -> str:
        """The command-line options that ask for them, as a user typed them."""
        asked = {"drop": self.drop, "stall": self.stall, "jitter": self.jitter}
        return " ".join(f"--{o} {v:g}" for o, v in asked.items() if v)

    def notes(self, dropped: int, frames: int) -> list[str]:
        """What the report says they were (``dropped`` of ``frames`` frames never given)."""
        if not self:
            return []
        return [
            f"sensor faults ({self.options}): {dropped} of {frames} frames dropped, "
            "the rest given to the tracker as recorded"
        ]

    def frames(self, spec: SceneSpec) -> tuple[npt.NDArray[np.bool_], npt.NDArray[np.float64]]:
        """Which of ``spec``'s frames the tracker is given, and each frame's stamp."""
        times = np.asarray(spec.times, dtype=float)
        n = len(times)
        if 2.0 * self.jitter >= 1.0 / spec.fps:
            raise ValueError(
                f"--jitter {self.jitter:g}: {spec.name}'s frames come every {1.0 / spec.fps:.3f} s, "
                "and stamps moved by half that or more would not increase"
            )
        duration = float(times[-1]) if n else 0.0
        if self.stall and duration - STALL_AFTER <= self.stall:
            raise ValueError(
                f"--stall {self.stall:g}: {spec.name} lasts {duration:g} s, and a stall starts "
                f"{STALL_AFTER:g} s in and ends before the scene does"
            )
        rng = np.random.default_rng(int(hashlib.sha256(spec.name.encode()).hexdigest()[:16], 16))
        keep = np.ones(n, dtype=bool)
        # Two states, dropping or not: a run of drops ends with probability 1 / DROP_BURST per
        # frame, and one starts as often as keeps the share of dropped frames at `drop`.
        stay = 1.0 - 1.0 / DROP_BURST
        start = self.drop * (1.0 - stay) / (1.0 - self.drop)
        dropping = False
        for k, u in enumerate(rng.random(n)):
            dropping = u < (stay if dropping else start)
            keep[k] = not dropping
        if self.stall:
            begin = rng.uniform(STALL_AFTER, duration - self.stall)
            keep &= (times < begin) | (times >= begin + self.stall)
        stamps = times + rng.uniform(-self.jitter, self.jitter, n)
        return keep, stamps


NO_FAULTS = Faults()
