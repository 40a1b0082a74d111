"""NumPy ``.npz`` recordings: the simplest way to save what a live sensor saw.

Arrays (``T`` frames): ``color (T, h, w, 3) uint8`` RGB, ``depth (T, h, w)`` in sensor units,
``time (T,)`` seconds, ``intrinsics (4,)`` fx, fy, cx, cy of the colour image, and optionally
``distortion (≤5,)`` Brown-Conrady, ``depth_scale ()`` metres per unit (default 0.001) and
``camera_to_world (4, 4)``. :func:`write` writes exactly this.
"""

from __future__ import annotations

import zipfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import numpy.typing as npt

from ..camera import Camera, Intrinsics, level_camera
from .frame import Frame, check_increasing, depth_in_metres

REQUIRED = ("color", "depth", "time", "intrinsics")


class NpzRecording:
    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self.name = str(self.path)
        try:
            # Read every array now: a truncated file fails here, not in the middle of a run.
            with np.load(self.path) as archive:
                self.data = {name: archive[name] for name in archive.files}
        except (OSError, EOFError, ValueError, zipfile.BadZipFile) as e:
            raise ValueError(f"{self.path}: not a readable .npz recording ({e})") from e
        missing = [k for k in REQUIRED if k not in self.data]
        if missing:
            raise ValueError(f"{self.path}: missing arrays {missing} (a recording needs {list(REQUIRED)})")
        color, depth, time = self.data["color"], self.data["depth"], self.data["time"]
        if color.ndim != 4 or color.shape[3] != 3 or color.dtype != np.uint8:
            raise ValueError(
                f"{self.path}: color must be (T, h, w, 3) uint8, got {color.shape} {color.dtype}"
            )
        if depth.shape != color.shape[:3] or time.shape != color.shape[:1]:
            raise ValueError(
                f"{self.path}: depth {depth.shape} and time {time.shape} must match "
                f"color's (T, h, w) {color.shape[:3]}"
            )
        check_increasing(self._numbers("time", (len(time),)), self.name)
        fx, fy, cx, cy = self._numbers("intrinsics", (4,))
        distortion = tuple(self._numbers("distortion", None)) if "distortion" in self.data else ()
        pose = self._numbers("camera_to_world", (4, 4)) if "camera_to_world" in self.data else level_camera()
        scale = float(self._numbers("depth_scale", ())) if "depth_scale" in self.data else 0.001
        self.camera = Camera(Intrinsics(fx, fy, cx, cy, distortion), pose, scale)

    def _numbers(self, name: str, shape: tuple[int, ...] | None) -> npt.NDArray[np.float64]:
        """Array ``name`` as float64 numbers of ``shape`` (None: any one-dimensional), or a
        ValueError that names it."""
        value = self.data[name]
        if not (np.issubdtype(value.dtype, np.number) or value.dtype == np.bool_):
            raise ValueError(f"{self.path}: {name} must hold numbers, got {value.dtype}")
        if (shape is None and value.ndim != 1) or (shape is not None and value.shape != shape):
            expected = "one-dimensional" if shape is None else f"shaped {shape}"
            raise ValueError(f"{self.path}: {name} must be {expected}, got {value.shape}")
        return value.astype(np.float64)

    def __len__(self) -> int:
        return len(self.data["time"])

    def __iter__(self) -> Iterator[Frame]:
        color, depth, time = self.data["color"], self.data["depth"], self.data["time"]
        for i in range(len(time)):
            yield Frame(
                i, float(time[i]), color[i], depth_in_metres(depth[i], self.camera.depth_scale), self.camera
            )


def write(
    path: str | Path,
    color: npt.NDArray[np.uint8],
    depth: npt.NDArray[np.generic],
    time: npt.ArrayLike,
    camera: Camera,
) -> None:
    """Saves frames as a recording :class:`NpzRecording` reads back."""
    k = camera.intrinsics
    np.savez_compressed(
        path,
        color=color,
        depth=depth,
        time=np.asarray(time, dtype=np.float64),
        intrinsics=np.array([k.fx, k.fy, k.cx, k.cy]),
        distortion=np.array(k.distortion, dtype=np.float64),
        depth_scale=np.array(camera.depth_scale),
        camera_to_world=np.asarray(camera.camera_to_world),
    )
