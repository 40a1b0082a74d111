"""Video files, colour only: for looking at 2D keypoints, not for 3D poses (no depth). Needs
OpenCV (``pip install torsocast[video]``)."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import numpy as np

from .frame import Frame, SkippedFrame


class VideoFile:
    def __init__(self, path: str | Path) -> None:
        try:
            import cv2
        except ImportError as e:
            raise ImportError("reading video needs OpenCV: pip install 'torsocast[video]'") from e
        self.path = Path(path)
        self.name = str(self.path)
        if not self.path.is_file():
            raise FileNotFoundError(f"{self.path}: no such video file")
        capture = cv2.VideoCapture(str(self.path))
        if not capture.isOpened():
            raise ValueError(f"{self.path}: OpenCV cannot open this video")
        self.fps = capture.get(cv2.CAP_PROP_FPS) or 30.0
        self.frames = int(capture.get(cv2.CAP_PROP_FRAME_COUNT))
        capture.release()

    def __len__(self) -> int:
        return max(self.frames, 0)

    def __iter__(self) -> Iterator[Frame | SkippedFrame]:
        """Every frame; one that cannot be decoded (a damaged or truncated file) is a
        :class:`SkippedFrame`, and reading goes on from the next frame where the container says
        there are more (it seeks past the damage, so frames after it still come)."""
        import cv2

        capture = cv2.VideoCapture(str(self.path))
        index = 0
        try:
            while True:
                ok, bgr = capture.read()
                if ok:
                    rgb = np.asarray(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB), dtype=np.uint8)
                    yield Frame(index, index / self.fps, rgb, None, None)
                elif index < self.frames:
                    yield SkippedFrame(
                        index, index / self.fps, f"{self.path}: frame {index} cannot be decoded"
                    )
                    capture.set(cv2.CAP_PROP_POS_FRAMES, index + 1)
                else:
                    break
                index += 1
        finally:
            capture.release()
