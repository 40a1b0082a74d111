"""A mocap clip seen by a virtual RGB-D camera: the source the demo runs on.

Each frame is the :mod:`~torsocast.synthetic.mannequin` rendered from the clip's joints at that
instant, with the ground-truth torso pose (the torso plane of the mocap shoulders and hips, as
the pipeline computes it from keypoints) in ``frame.extra["truth"]``.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import numpy.typing as npt

from ..camera import Camera, Intrinsics, level_camera
from ..datasets import cmu
from ..sources.frame import Frame
from .mannequin import Scene
from .scenes import torso_truth

F64 = npt.NDArray[np.float64]


def watching_camera(path: F64, distance: float = 4.0, side: float = 20.0, height: float = 1.2) -> Camera:
    """A Kinect-like camera ``height`` m up, ``distance`` m from the middle of a walk ``path``
    ``(frames, 3)``, placed ``side`` degrees off the walking direction (ahead of the walker and to
    its right) and looking at the middle, so that the walker comes towards it at an angle."""
    start, end = path[0, :2], path[-1, :2]
    middle = 0.5 * (start + end)
    heading = np.arctan2(*(end - start)[::-1])
    bearing = heading - np.radians(side)
    position = middle + distance * np.array([np.cos(bearing), np.sin(bearing)])
    look = np.arctan2(*(middle - position)[::-1])
    pitch = np.arctan2(height - 0.9, distance)  # aim at the torso, about 0.9 m up
    pose = level_camera(height, pitch)
    c, s = np.cos(look), np.sin(look)
    pose[:3, :3] = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]) @ pose[:3, :3]
    pose[:2, 3] = position
    return Camera(Intrinsics(525.0, 525.0, 319.5, 239.5), pose)


@dataclass
class MocapScene:
    """Frames at ``fps`` of ``joints (frames, 38, 3)`` recorded at ``rate_hz``, rendered from
    ``camera`` (default: :func:`watching_camera`)."""

    joints: F64
    rate_hz: float = cmu.RATE_HZ
    fps: float = 30.0
    camera: Camera | None = None
    scene: Scene = field(default_factory=Scene)
    seed: int = 0
    name: str = "mocap"

    def __post_init__(self) -> None:
        j = np.asarray(self.joints, dtype=np.float64)
        if j.ndim != 3 or j.shape[1:] != (38, 3) or not np.isfinite(j).all():
            raise ValueError(f"joints must be finite (frames, 38, 3), got shape {j.shape}")
        if not (0 < self.fps <= self.rate_hz):
            raise ValueError(f"fps must be in (0, {self.rate_hz}], got {self.fps}")
        self.joints = j
        if self.camera is None:
            self.camera = watching_camera(j[:, cmu.PELVIS])
        self.picks = np.arange(0, len(j), self.rate_hz / self.fps).round().astype(int)
        self.picks = self.picks[self.picks < len(j)]
        # The true torso pose at every mocap sample, not only at the rendered ones: a forecast is
        # checked against the instant it aims at.
        self.truth = torso_truth(j)

    @classmethod
    def from_clip(cls, clip: str | Path, **kwargs) -> MocapScene:  # type: ignore[no-untyped-def]
        """A bundled clip by name (see :func:`torsocast.datasets.cmu.bundled_clips`) or a file."""
        bundled = cmu.bundled_clips()
        path = bundled.get(str(clip), Path(clip))
        if not Path(path).is_file():
            raise FileNotFoundError(f"{clip}: neither a bundled clip ({', '.join(bundled)}) nor a file")
        kwargs.setdefault("name", Path(path).stem)
        return cls(cmu.load_clip(path), **kwargs)

    def __len__(self) -> int:
        return len(self.picks)

    def __iter__(self) -> Iterator[Frame]:
        assert self.camera is not None
        rng = np.random.default_rng(self.seed)
        rays = self.scene.rays(self.camera)
        background = self.scene.background(self.camera, rays)
        for index, k in enumerate(self.picks):
            frame = self.scene.render(self.joints[k], self.camera, rng, rays, background)
            yield Frame(
                index, k / self.rate_hz, frame.rgb, frame.depth, self.camera, {"truth": self.truth[k]}
            )
