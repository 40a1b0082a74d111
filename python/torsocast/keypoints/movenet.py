"""MoveNet SinglePose (Lightning or Thunder): the most prominent person of the image.

Input ``[1, S, S, 3]`` RGB (uint8 or int32 by export); output ``[1, 1, 17, 3]`` of (y, x, score)
as fractions of the square input. The image is padded to a square at the bottom and right first,
so that a fraction times the padded side is an original pixel.
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

    def __call__(self, image: npt.NDArray[np.uint8]) -> Detections:
        image = check_rgb(image)
        boxed, box = letterbox(image, self.input_size, 0, centre=False)
        (output,) = self.session.run(None, {self.input_name: boxed[None].astype(self.dtype)})
        yxs = output.reshape(17, 3).astype(np.float64)
        keypoints = np.column_stack([yxs[:, 1], yxs[:, 0], yxs[:, 2]])
        keypoints[:, :2] = box.to_image(keypoints[:, :2] * self.input_size)
        score = float(keypoints[:, 2].mean())
        if score < self.score:
            return Detections.empty()
        seen = keypoints[keypoints[:, 2] >= self.score, :2]
        seen = seen if len(seen) else keypoints[:, :2]
        corners = np.concatenate([seen.min(axis=0), seen.max(axis=0)])
        return Detections(keypoints[None], corners[None], np.array([score]))
