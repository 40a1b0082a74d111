"""Opening a keypoint model: an onnxruntime session, the model's family recognised from its
input and output shapes, and the family's decoder around it."""

from __future__ import annotations

from pathlib import Path

from .model import KeypointModel
from .movenet import MoveNet, bundled_model
from .yolo import YoloPose

FAMILIES = ("yolo-pose", "movenet")


#: Operators of an 8-bit quantized ONNX graph (QDQ or operator-oriented).
INT8_OPERATORS = (b"QuantizeLinear", b"QLinearConv", b"QLinearMatMul", b"ConvInteger", b"MatMulInteger")
#: CPU flags (Linux's /proc/cpuinfo) of the x86 8-bit dot products (VNNI, AVX-512 or AVX) that
#: onnxruntime's int8 kernels use in place of AVX2's saturating VPMADDUBSW.
INT8_DOT_PRODUCT_FLAGS = frozenset({"avx512_vnni", "avx_vnni"})


def int8_dot_product() -> bool:
    """Whether this CPU is free of the AVX2 int8 saturation: an x86 CPU with VNNI, or one that
    is not x86 with AVX2 (onnxruntime takes other kernels there; not measured here), or one
    whose /proc/cpuinfo cannot be read."""
    try:
        flags = set(Path("/proc/cpuinfo").read_text().split())
    except OSError:
        return True
    return "avx2" not in flags or bool(flags & INT8_DOT_PRODUCT_FLAGS)


def quantized(path: Path) -> bool:
    """Whether the ONNX file holds an 8-bit quantized graph (its operator names are stored as
    plain strings)."""
    data = path.read_bytes()
    return any(op in data for op in INT8_OPERATORS)


def session(path: str | Path, device: str = "cpu"):  # type: ignore[no-untyped-def]
    """An onnxruntime session on the CPU, or on CUDA when asked for and available.

    An 8-bit quantized model on an x86 CPU with AVX2 and no VNNI runs with onnxruntime's
    basic graph optimisations only: its fused int8 convolutions would use
    AVX2's VPMADDUBSW, whose 16-bit intermediate sums saturate, and the bundled MoveNet then
    places keypoints measurably worse (README: the turntable table). Unfused, the quantized
    weights are dequantised once and the convolutions run in float, half as slow again."""
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
    # The CPU first: elsewhere the model file need not be read twice.
    if device == "cpu" and not int8_dot_product() and quantized(path):
        options.graph_optimization_level = ort.GraphOptimizationLevel.ORT_ENABLE_BASIC
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
    if family is not None and family not in FAMILIES:
        raise ValueError(f"family must be one of {FAMILIES}, got {family!r}")
    sess = session(bundled_model() if path is None else path, device)
    found = family or recognise(sess)
    return YoloPose(sess, **thresholds) if found == "yolo-pose" else MoveNet(sess, **thresholds)
