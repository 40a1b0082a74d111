"""MoveNet SinglePose (Lightning or Thunder): the most prominent person of the image.

Input ``[1, S, S, 3]`` RGB (uint8 or int32 by export); output ``[1, 1, 17, 3]`` of (y, x, score)
as fractions of the square input. The image is padded to a square at the bottom and right first,
so that a fraction times the padded side is an original pixel.

In a stream, each frame is first run on a square crop around the person the last frame found
(as MoveNet's own tracking demo does): a person a few metres away fills a few dozen of the
model's input pixels in the whole image and several times that in the crop, and MoveNet's
left/right labels and limbs come out far more often right. Where the crop finds nobody, the
whole image is run in the same frame. The crop is only a hint, checked by the next frame's
scores: the pipeline's ``reset()`` at a new stream clears it, a frame refused after the model ran
still moves it.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

import numpy as np
import numpy.typing as npt

from .image import check_rgb, letterbox
from .model import Detections

#: The model that ships with the package (Apache-2.0, see ``models/NOTICE.md``).
BUNDLED = "movenet-lightning-int8.onnx"

#: The crop's side over the longer side of the last frame's keypoint box. Chosen on the scenes
#: benchmark's development split (docs/benchmark_log.md, "MoveNet on a crop around the last frame's
#: person").
CROP_MARGIN = 1.25
#: Smallest crop side (pixels), so that a few keypoints close together still leave room.
MIN_CROP = 32


def bundled_model() -> Path:
    path = Path(str(files("torsocast") / "models" / BUNDLED))
    if not path.is_file():
        raise FileNotFoundError(f"{path}: the bundled MoveNet model is missing from this install")
    return path


class MoveNet:
    """A MoveNet SinglePose ONNX model. It always answers with one skeleton; ``score`` is the mean
    keypoint score below which that skeleton counts as nobody (the int8 model's scores are coarse:
    about 0.3 to 0.5 on clear shoulders)."""

    family = "movenet"
    #: Measured on the real turntable sequence: nose score 0.57 in back views (0.70 in front).
    faces_on_backs = True

    def __init__(self, sess, score: float = 0.2) -> None:  # type: ignore[no-untyped-def]
        if not 0.0 <= score <= 1.0:
            raise ValueError(f"score threshold {score} is outside 0..1")
        self.session = sess
        inp = sess.get_inputs()[0]
        self.input_name = inp.name
        self.input_size = int(inp.shape[1])
        self.dtype = np.int32 if "int32" in inp.type else np.uint8
        self.score = score
        self._region: tuple[int, int, int] | None = None

    #: What a recording of this model's output depends on besides its input size.
    variant = f"crop {CROP_MARGIN:g}"

    def reset(self) -> None:
        """Forgets the last frame's person: the next frame is run on the whole image."""
        self._region = None

    def __call__(self, image: npt.NDArray[np.uint8]) -> Detections:
        image = check_rgb(image)
        keypoints = self._run(image, self._region) if self._region is not None else None
        if keypoints is None or keypoints[:, 2].mean() < self.score:
            keypoints = self._run(image, None)
        score = float(keypoints[:, 2].mean())
        if score < self.score:
            self._region = None
            return Detections.empty()
        seen = keypoints[keypoints[:, 2] >= self.score, :2]
        seen = seen if len(seen) else keypoints[:, :2]
        corners = np.concatenate([seen.min(axis=0), seen.max(axis=0)])
        self._region = crop_region(corners, image.shape[:2])
        return Detections(keypoints[None], corners[None], np.array([score]))

    def _run(
        self, image: npt.NDArray[np.uint8], region: tuple[int, int, int] | None
    ) -> npt.NDArray[np.float64]:
        """``(17, 3)`` keypoints in image pixels, from the whole image or from the square
        ``region`` ``(x0, y0, side)`` (black where it leaves the image)."""
        x0 = y0 = 0
        if region is not None:
            x0, y0, side = region
            h, w = image.shape[:2]
            crop = np.zeros((side, side, 3), np.uint8)
            xa, ya, xb, yb = max(x0, 0), max(y0, 0), min(x0 + side, w), min(y0 + side, h)
            if xb > xa and yb > ya:
                crop[ya - y0 : yb - y0, xa - x0 : xb - x0] = image[ya:yb, xa:xb]
            image = crop
        boxed, box = letterbox(image, self.input_size, 0, centre=False)
        (output,) = self.session.run(None, {self.input_name: boxed[None].astype(self.dtype)})
        yxs = output.reshape(17, 3).astype(np.float64)
        keypoints = np.column_stack([yxs[:, 1], yxs[:, 0], yxs[:, 2]])
        keypoints[:, :2] = box.to_image(keypoints[:, :2] * self.input_size) + np.array([x0, y0])
        return keypoints


def crop_region(corners: npt.NDArray[np.float64], shape: tuple[int, ...]) -> tuple[int, int, int] | None:
    """The square ``(x0, y0, side)`` centred on the box ``corners`` ``(x0, y0, x1, y1)``, its side
    :data:`CROP_MARGIN` times the box's longer side (at least :data:`MIN_CROP`); ``None`` where
    that is as long as the image's longer side (the whole image is no smaller)."""
    x0, y0, x1, y1 = corners
    side = max(CROP_MARGIN * max(x1 - x0, y1 - y0), MIN_CROP)
    if side >= max(shape[:2]):
        return None
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    return int(round(cx - side / 2)), int(round(cy - side / 2)), int(round(side))
