"""The keypoint model interface and its detections."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]


@dataclass(frozen=True)
class Detections:
    """The people found in one image, most confident first."""

    keypoints: F64
    """``(people, 17, 3)``: u, v in original image pixels and the keypoint's score in [0, 1]."""
    boxes: F64
    """``(people, 4)``: x0, y0, x1, y1 in original image pixels."""
    scores: F64
    """``(people,)``: the person's detection score."""

    def __len__(self) -> int:
        return len(self.scores)

    @staticmethod
    def empty() -> Detections:
        return Detections(np.zeros((0, 17, 3)), np.zeros((0, 4)), np.zeros(0))


class KeypointModel(Protocol):
    """What the pipeline needs of a keypoint model. A model that keeps something from one frame
    to the next (MoveNet's crop around the last frame's person) also has ``reset()``, which the
    pipeline calls where a stream starts, and a ``variant`` text naming what its output depends
    on besides its input size (the scenes benchmark's recordings are keyed by it)."""

    family: str
    input_size: int
    faces_on_backs: bool
    """The model finds a face on the back of a head (MoveNet does, on real people as on rendered
    ones): tracks then take no evidence from the nose about which way the chest faces."""

    def __call__(self, image: npt.NDArray[np.uint8]) -> Detections:
        """Every person in an ``(h, w, 3)`` uint8 RGB image."""
        ...
