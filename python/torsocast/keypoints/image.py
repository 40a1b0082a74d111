"""Fitting an image into a model's square input, and mapping the model's coordinates back."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from PIL import Image


@dataclass(frozen=True)
class Letterbox:
    """``model = image * (scale_x, scale_y) + (pad_x, pad_y)``: the resize and padding applied."""

    scale_x: float
    scale_y: float
    pad_x: float
    pad_y: float

    def to_image(self, uv: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Model pixels ``(..., 2)`` back to original image pixels."""
        return (uv - np.array([self.pad_x, self.pad_y])) / np.array([self.scale_x, self.scale_y])


def check_rgb(image: npt.ArrayLike) -> npt.NDArray[np.uint8]:
    """An ``(h, w, 3)`` uint8 RGB image, or a clear error."""
    array = np.asarray(image)
    if array.ndim != 3 or array.shape[2] != 3 or array.shape[0] < 1 or array.shape[1] < 1:
        raise ValueError(f"expected an RGB image of shape (height, width, 3), got {array.shape}")
    if array.dtype != np.uint8:
        raise ValueError(f"expected a uint8 RGB image, got dtype {array.dtype}")
    return array


def letterbox(
    image: npt.NDArray[np.uint8], size: int, fill: int, centre: bool
) -> tuple[npt.NDArray[np.uint8], Letterbox]:
    """Resizes ``image`` to fit a ``size`` x ``size`` square keeping its aspect ratio (bilinear) and
    pads the rest with ``fill``: centred (YOLO's letterbox) or at the bottom and right."""
    h, w = image.shape[:2]
    scale = min(size / h, size / w)
    new_w, new_h = max(1, round(w * scale)), max(1, round(h * scale))
    resized = np.asarray(Image.fromarray(image).resize((new_w, new_h), Image.Resampling.BILINEAR))
    pad_x = (size - new_w) // 2 if centre else 0
    pad_y = (size - new_h) // 2 if centre else 0
    out = np.full((size, size, 3), fill, dtype=np.uint8)
    out[pad_y : pad_y + new_h, pad_x : pad_x + new_w] = resized
    # Rounding the size makes the two axes' scales differ slightly: keep both.
    return out, Letterbox(new_w / w, new_h / h, float(pad_x), float(pad_y))
