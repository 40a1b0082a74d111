"""Folders of colour and depth images.

Two layouts are recognised:

* **Per-frame camera XML** (as the project's turntable recording): ``NNNN.jpg`` (or ``.png``),
  ``NNNN_depth.png`` (16-bit, millimetres, registered to colour) and ``NNNN_camera.xml`` (OpenCV
  FileStorage with ``intrinsic`` and, optionally, a ground-truth ``R`` and ``t``, kept in
  ``frame.extra``). The layout has no time stamps: frames are ``1 / fps`` apart.
* **TUM RGB-D**: ``rgb.txt`` and ``depth.txt`` (``time path`` per line), depth PNGs at 5000 units
  per metre; every colour image is paired with the nearest depth image within ``max_difference``
  seconds (TUM's ``associate.py`` rule). TUM folders carry no intrinsics: give them.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path

import numpy as np
from PIL import Image

from ..camera import Camera, Intrinsics, level_camera
from .frame import PAIRING_TOLERANCE, READ_ERRORS, Frame, SkippedFrame, check_increasing, depth_in_metres

#: TUM's depth PNGs hold 5000 units per metre.
TUM_DEPTH_SCALE = 1.0 / 5000.0
#: The intrinsics TUM gives for its ROS default calibration (fr1/2/3 differ a little).
TUM_DEFAULT = Intrinsics(525.0, 525.0, 319.5, 239.5)


def read_rgb(path: Path) -> np.ndarray:
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"))


def read_depth_png(path: Path) -> np.ndarray:
    """A single-channel depth image of 16-bit (or wider) integers; an 8-bit or colour image is
    refused (read as depth, its values would be metres off)."""
    with Image.open(path) as image:
        depth = np.asarray(image)
    if depth.ndim != 2 or not (np.issubdtype(depth.dtype, np.integer) and depth.dtype.itemsize >= 2):
        raise ValueError(
            f"{path}: a depth image must be one channel of 16-bit integers, got {depth.dtype} "
            f"with shape {depth.shape}"
        )
    return depth


def opencv_matrix(root: ET.Element, name: str) -> np.ndarray | None:
    """A matrix of an OpenCV FileStorage XML document, or None when absent."""
    node = root.find(name)
    if node is None:
        return None
    rows, cols = int(node.findtext("rows", "0")), int(node.findtext("cols", "0"))
    data = np.array((node.findtext("data") or "").split(), dtype=np.float64)
    if data.size != rows * cols:
        raise ValueError(f"OpenCV matrix {name!r}: {data.size} values for {rows}x{cols}")
    return data.reshape(rows, cols)


class CameraXmlFolder:
    """The per-frame camera XML layout (see the module's docstring)."""

    def __init__(
        self, root: str | Path, fps: float = 30.0, camera_to_world: np.ndarray | None = None
    ) -> None:
        self.root = Path(root)
        self.name = str(self.root)
        if not fps > 0:
            raise ValueError(f"fps must be positive, got {fps}")
        # Every frame with any of its three files: one missing file skips its frame (reported)
        # without moving the later frames' time stamps.
        cameras = {p.name[: -len("_camera.xml")] for p in self.root.glob("*_camera.xml")}
        if not cameras:
            raise FileNotFoundError(f"{self.root}: no NNNN_camera.xml files")
        colours = {p.stem for p in self.root.glob("*.jpg")} | {p.stem for p in self.root.glob("*.png")}
        depths = {p.name[: -len("_depth.png")] for p in self.root.glob("*_depth.png")}
        self.stems = sorted(cameras | depths | (colours - {f"{d}_depth" for d in depths}))
        self.fps = fps
        self.camera_to_world = level_camera() if camera_to_world is None else camera_to_world

    def __len__(self) -> int:
        return len(self.stems)

    def color_path(self, stem: str) -> Path:
        for ext in (".jpg", ".png"):
            if (path := self.root / f"{stem}{ext}").is_file():
                return path
        raise FileNotFoundError(f"{self.root}: no colour image {stem}.jpg or {stem}.png")

    def __iter__(self) -> Iterator[Frame | SkippedFrame]:
        for index, stem in enumerate(self.stems):
            try:
                yield self.read(index, stem)
            except READ_ERRORS as e:
                yield SkippedFrame(index, index / self.fps, f"{stem}: {e}")

    def read(self, index: int, stem: str) -> Frame:
        root = ET.parse(self.root / f"{stem}_camera.xml").getroot()
        k = opencv_matrix(root, "intrinsic")
        if k is None:
            raise ValueError(f"{stem}_camera.xml has no 'intrinsic' matrix")
        distortion = opencv_matrix(root, "distortion")
        intrinsics = Intrinsics(
            k[0, 0], k[1, 1], k[0, 2], k[1, 2], () if distortion is None else tuple(distortion.ravel())
        )
        depth = depth_in_metres(read_depth_png(self.root / f"{stem}_depth.png"), 0.001)
        extra = {name: m for name in ("R", "t") if (m := opencv_matrix(root, name)) is not None}
        return Frame(
            index,
            index / self.fps,
            read_rgb(self.color_path(stem)),
            depth,
            Camera(intrinsics, self.camera_to_world),
            extra,
        )


def read_tum_list(path: Path) -> tuple[np.ndarray, list[str]]:
    times, names = [], []
    for line in path.read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            stamp, name = line.split()[:2]
            times.append(float(stamp))
            names.append(name)
    return np.array(times), names


class TumFolder:
    """The TUM RGB-D layout (see the module's docstring)."""

    def __init__(
        self,
        root: str | Path,
        intrinsics: Intrinsics = TUM_DEFAULT,
        camera_to_world: np.ndarray | None = None,
        max_difference: float = PAIRING_TOLERANCE,
    ) -> None:
        self.root = Path(root)
        self.name = str(self.root)
        rgb_times, rgb = read_tum_list(self.root / "rgb.txt")
        depth_times, depth = read_tum_list(self.root / "depth.txt")
        check_increasing(rgb_times, str(self.root / "rgb.txt"))
        if len(depth_times) == 0:
            raise ValueError(f"{self.root / 'depth.txt'} lists no images")
        nearest = np.abs(rgb_times[:, None] - depth_times[None, :]).argmin(axis=1)
        close = np.abs(rgb_times - depth_times[nearest]) <= max_difference
        self.pairs = [(rgb_times[i], rgb[i], depth[nearest[i]]) for i in np.flatnonzero(close)]
        self.unpaired = int((~close).sum())
        if not self.pairs:
            raise ValueError(
                f"{self.root}: no colour image has a depth image within {max_difference} s "
                f"({len(rgb_times)} colour, {len(depth_times)} depth)"
            )
        self.camera = Camera(intrinsics, level_camera() if camera_to_world is None else camera_to_world)

    def __len__(self) -> int:
        return len(self.pairs)

    def __iter__(self) -> Iterator[Frame | SkippedFrame]:
        for index, (time, rgb, depth) in enumerate(self.pairs):
            try:
                yield Frame(
                    index,
                    float(time),
                    read_rgb(self.root / rgb),
                    depth_in_metres(read_depth_png(self.root / depth), TUM_DEPTH_SCALE),
                    self.camera,
                )
            except READ_ERRORS as e:
                yield SkippedFrame(index, float(time), f"{rgb} / {depth}: {e}")
