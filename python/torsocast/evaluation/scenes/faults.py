"""Sensor faults a replay of recorded detections can put into a split's frames: frames dropped,
one stall of the camera, time stamps that jitter, and a camera pose told late or with an error.
Unlike the oracles these give results: what the tracking and forecasting make of a robot's real
stream, where the camera or the computer drops frames when busy, a driver stalls, stamps come late
or early by a few milliseconds, and the robot's localisation lags the image and wavers.

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

**A pose told late** (``--pose-lag SECONDS``, with ``--robot``). The camera pose given with each
frame is the robot's from that long before the frame was taken: a localisation that runs behind
the camera, or a transform looked up at the wrong stamp. A robot that drives and pans then puts
everyone it sees where they were not, by its motion over the lag.

**A wavering heading** (``--pose-noise DEGREES``). The camera pose given with each frame is turned
about the vertical through the camera by an error drawn afresh for every frame (normal, of that
standard deviation): the jitter of a localiser's heading. Everyone seen moves with it, by their
distance times the error; a camera that stands still takes it too. The position is left exact: a
few centimetres there weigh less than a degree at the people's distance.

The recorded joints were lifted with the true pose; a replay with a pose fault moves them into the
world as the pose told would have put them, and tells the pipeline that pose. The scorer's views
and distances are from where the camera truly was.

Each scene draws its own faults from its name, so every run of a split, with any code, drops the
same frames: two replays with the same faults compare frame for frame (``eval compare``), and
one against a replay without them on the frames both hold (``eval compare --common``). A live
run takes no faults: they apply to recorded detections, as the oracles do.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ...camera import Camera
from ...synthetic.scenes import SceneSpec, yaw_matrix

#: Mean length (frames) of a run of dropped frames.
DROP_BURST = 2.0
#: Earliest time (s) into a scene that its stall starts: its people have tracks by then.
STALL_AFTER = 1.0


@dataclass(frozen=True)
class Faults:
    """What a replay does to each scene's frames: the share of frames dropped, the length (s)
    of its one stall, how far (s) each stamp may move either way, how late (s) the camera's pose
    is told and the standard deviation (degrees) of its heading's error. All zero: nothing."""

    drop: float = 0.0
    stall: float = 0.0
    jitter: float = 0.0
    pose_lag: float = 0.0
    pose_noise: float = 0.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.drop < 1.0:
            raise ValueError(f"--drop: expected a share of the frames from 0 to below 1, got {self.drop}")
        times = (("--stall", self.stall), ("--jitter", self.jitter), ("--pose-lag", self.pose_lag))
        for option, value in times:
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"{option}: expected a finite, non-negative time in seconds, got {value}")
        if not (math.isfinite(self.pose_noise) and self.pose_noise >= 0.0):
            expected = "expected a finite, non-negative angle in degrees"
            raise ValueError(f"--pose-noise: {expected}, got {self.pose_noise}")

    def __bool__(self) -> bool:
        return any(self._asked().values())

    def _asked(self) -> dict[str, float]:
        return {
            "drop": self.drop,
            "stall": self.stall,
            "jitter": self.jitter,
            "pose-lag": self.pose_lag,
            "pose-noise": self.pose_noise,
        }

    @property
    def pose(self) -> bool:
        """Whether the camera's pose is told otherwise than it was (late, or wavering)."""
        return bool(self.pose_lag or self.pose_noise)

    @property
    def options(self) -> str:
        """The command-line options that ask for them, as a user typed them."""
        return " ".join(f"--{o} {v:g}" for o, v in self._asked().items() if v)

    def notes(self, dropped: int, frames: int) -> list[str]:
        """What the report says they were (``dropped`` of ``frames`` frames never given)."""
        if not self:
            return []
        told = ", each with the camera's pose told as asked" if self.pose else ""
        return [
            f"sensor faults ({self.options}): {dropped} of {frames} frames dropped, "
            f"the rest given to the tracker as recorded{told}"
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

    def cameras(self, spec: SceneSpec) -> list[Camera] | None:
        """The camera the pipeline is told with each of ``spec``'s frames: the scene's own, from
        :attr:`pose_lag` before the frame and turned by a heading error of :attr:`pose_noise`;
        None where neither is asked (the scene's own, exactly)."""
        if not self.pose:
            return None
        if self.pose_lag and spec.robot is None:
            raise ValueError(
                f"--pose-lag {self.pose_lag:g}: {spec.name} is seen from a camera that stands still, "
                "whose pose is the same at every time (add --robot)"
            )
        # Drawn apart from the frames' faults: adding a pose fault drops and stamps the same frames.
        rng = np.random.default_rng(int(hashlib.sha256(f"{spec.name} pose".encode()).hexdigest()[:16], 16))
        errors = rng.normal(0.0, math.radians(self.pose_noise), len(spec.times))
        told = []
        for t, error in zip(spec.times, errors):
            camera = spec.camera(float(t) - self.pose_lag)
            if error:
                pose = np.array(camera.camera_to_world)
                pose[:3, :3] = yaw_matrix(float(error)) @ pose[:3, :3]  # about the camera's own vertical
                camera = dataclasses.replace(camera, camera_to_world=pose)
            told.append(camera)
        return told


NO_FAULTS = Faults()
