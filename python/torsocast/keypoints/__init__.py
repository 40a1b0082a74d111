"""2D human keypoint models (ONNX, run with onnxruntime): every person in a colour image as 17
COCO keypoints ``(u, v, score)`` in the image's own pixels.

:func:`open_model` recognises the family from the model's inputs and outputs (or takes it from the
caller) and returns a :class:`KeypointModel`: the YOLO-pose family (YOLOv8 and YOLO11, multi-person)
or MoveNet SinglePose.
"""

from .coco import KEYPOINTS, LEFT_RIGHT_PAIRS
from .loading import open_model
from .model import Detections, KeypointModel

__all__ = ["KEYPOINTS", "LEFT_RIGHT_PAIRS", "Detections", "KeypointModel", "open_model"]
