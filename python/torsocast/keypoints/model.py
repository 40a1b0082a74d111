"""The model interface, its detections, and :func:`open_model`."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Protocol

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]

FAMILIES = ("yolo-pose", "movenet")


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
    """What the pipeline needs of a keypoint model."""

    family: str
    input_size: int
    faces_on_backs: bool
    """The model finds a face on the back of a head (MoveNet does, on real people as on rendered
    ones): tracks then take no evidence from the nose about which way the chest faces."""

    def __call__(self, image: npt.NDArray[np.uint8]) -> Detections:
        """Every person in an ``(h, w, 3)`` uint8 RGB image."""
        ...


def session(path: str | Path, device: str = "cpu"):  # type: ignore[no-untyped-def]
    """An onnxruntime session on the CPU, or on CUDA when asked for and available."""
    import onnxruntime as ort

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such ONNX model file")
    if device == "cpu":
        providers = ["CPUExecutionProvider"]
    elif device == "cuda":
        if "CUDAExecutionProvider" not in ort.get_available_providers():
            raise RuntimeError(
                "device 'cuda' asked for, but this onnxruntime has no CUDA provider "
                f"(available: {ort.get_available_providers()}); install onnxruntime-gpu"
            )
        providers = ["CUDAExecutionProvider", "CPUExecutionProvider"]
    else:
        raise ValueError(f"device must be 'cpu' or 'cuda', got {device!r}")
    options = ort.SessionOptions()
    options.log_severity_level = 3  # the int8 MoveNet file warns about unused initialisers
    try:
        return ort.InferenceSession(str(path), options, providers=providers)
    except Exception as e:  # onnxruntime's errors share no base class of their own
        reason = str(e).splitlines()[0] if str(e) else type(e).__name__
        raise ValueError(f"{path}: not a model onnxruntime can load ({reason})") from e


def recognise(sess) -> str:  # type: ignore[no-untyped-def]
    """The family of a loaded model, from the shapes of its first input and output."""
    inputs, outputs = sess.get_inputs(), sess.get_outputs()
    in_shape, out_shape = list(inputs[0].shape), list(outputs[0].shape)
    if len(in_shape) == 4 and in_shape[1] == 3 and len(out_shape) == 3 and out_shape[1] == 56:
        return "yolo-pose"
    if len(in_shape) == 4 and in_shape[3] == 3 and out_shape[-2:] == [17, 3]:
        return "movenet"
    raise ValueError(
        f"unrecognised keypoint model: input {inputs[0].name} {in_shape}, output {outputs[0].name} "
        f"{out_shape}; supported: YOLOv8/YOLO11-pose ([1,3,S,S] -> [1,56,N]) and MoveNet "
        "SinglePose ([1,S,S,3] -> [1,1,17,3]); MoveNet MultiPose and others are not"
    )


def open_model(
    path: str | Path | None = None, family: str | None = None, device: str = "cpu", **thresholds: float
) -> KeypointModel:
    """Loads a keypoint model. ``path=None`` gives the bundled MoveNet Lightning (Apache-2.0);
    ``family`` (``"yolo-pose"`` or ``"movenet"``) skips recognition (for exports with
    unusual shapes); ``thresholds`` go to the
    family's decoder (``score``, ``iou`` for YOLO-pose; ``score`` for MoveNet)."""
    from .movenet import MoveNet, bundled_model
    from .yolo import YoloPose

    if family is not None and family not in FAMILIES:
        raise ValueError(f"family must be one of {FAMILIES}, got {family!r}")
    sess = session(bundled_model() if path is None else path, device)
    found = family or recognise(sess)
    return YoloPose(sess, **thresholds) if found == "yolo-pose" else MoveNet(sess, **thresholds)
