"""The YOLO-pose family (YOLOv8-pose and YOLO11-pose exports share one output layout).

Output ``[1, 56, N]``: per candidate box centre, size (cx, cy, w, h), the person score, then 17 x
(u, v, score), all in the letterboxed input's pixels, scores already through a sigmoid.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from .image import check_rgb, letterbox
from .model import F64, Detections

#: Ultralytics' letterbox fill.
PAD_VALUE = 114


def non_maximum_suppression(boxes: F64, scores: F64, iou: float) -> npt.NDArray[np.intp]:
    """Indices of the boxes ``(n, 4)`` (x0, y0, x1, y1) kept by greedy NMS, best score first."""
    order = np.argsort(-scores, kind="stable")
    areas = np.prod(np.clip(boxes[:, 2:] - boxes[:, :2], 0.0, None), axis=1)
    keep = []
    while order.size:
        best, rest = order[0], order[1:]
        keep.append(best)
        top_left = np.maximum(boxes[best, :2], boxes[rest, :2])
        bottom_right = np.minimum(boxes[best, 2:], boxes[rest, 2:])
        overlap = np.prod(np.clip(bottom_right - top_left, 0.0, None), axis=1)
        union = areas[best] + areas[rest] - overlap
        order = rest[overlap <= iou * union]
    return np.array(keep, dtype=np.intp)


class YoloPose:
    """A YOLO-pose ONNX model: letterbox, run, keep candidates above ``score``, NMS at ``iou``,
    undo the letterbox."""

    family = "yolo-pose"
    #: Measured on the real turntable sequence: nose score 0.02 in back views (1.00 in front).
    faces_on_backs = False

    def __init__(self, sess, score: float = 0.25, iou: float = 0.5) -> None:  # type: ignore[no-untyped-def]
        if not (0.0 <= score <= 1.0 and 0.0 < iou <= 1.0):
            raise ValueError(f"thresholds out of range: score {score} (0..1), iou {iou} (0..1]")
        self.session = sess
        self.input_name = sess.get_inputs()[0].name
        self.input_size = int(sess.get_inputs()[0].shape[2])
        self.score, self.iou = score, iou

    def __call__(self, image: npt.NDArray[np.uint8]) -> Detections:
        image = check_rgb(image)
        boxed, box = letterbox(image, self.input_size, PAD_VALUE, centre=True)
        tensor = (boxed.transpose(2, 0, 1)[None] / np.float32(255.0)).astype(np.float32)
        (output,) = self.session.run(None, {self.input_name: tensor})
        return self.decode(output[0].T.astype(np.float64), box)

    def decode(self, candidates: F64, box) -> Detections:  # type: ignore[no-untyped-def]
        """``(N, 56)`` candidates in model pixels to detections in image pixels."""
        candidates = candidates[candidates[:, 4] > self.score]
        if len(candidates) == 0:
            return Detections.empty()
        centre, size = candidates[:, :2], candidates[:, 2:4]
        boxes = np.hstack([centre - size / 2, centre + size / 2])
        keep = non_maximum_suppression(boxes, candidates[:, 4], self.iou)
        candidates, boxes = candidates[keep], boxes[keep]
        keypoints = candidates[:, 5:].reshape(-1, 17, 3).copy()
        keypoints[..., :2] = box.to_image(keypoints[..., :2])
        corners = box.to_image(boxes.reshape(-1, 2, 2)).reshape(-1, 4)
        return Detections(keypoints, corners, candidates[:, 4].copy())
