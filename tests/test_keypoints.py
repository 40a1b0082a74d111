"""Keypoint models on real photos, against the reference keypoints in ../shared/data/images."""

from types import SimpleNamespace

import numpy as np
import pytest
from PIL import Image

from conftest import shared_path
from torsocast.keypoints import loading, open_model
from torsocast.keypoints.image import letterbox
from torsocast.keypoints.loading import recognise
from torsocast.keypoints.movenet import MoveNet, bundled_model, crop_region
from torsocast.keypoints.yolo import YoloPose, non_maximum_suppression

# README of ../shared/data/images: yolo11n-pose at 640, (u, v) of L/R shoulder, L/R hip.
WOMAN = [(1432.4, 621.2), (1418.7, 621.3), (1426.1, 742.9), (1403.6, 739.5)]
MAN = [(660.6, 165.3), (603.5, 163.8), (655.4, 292.7), (606.9, 291.3)]
TORSO = [5, 6, 11, 12]


def rgb(name):
    with Image.open(shared_path("data", "images", name)) as image:
        return np.asarray(image.convert("RGB"))


def test_yolo_finds_both_people_with_their_torso_where_the_reference_has_it(yolo640):
    found = yolo640(rgb("sports2d_060.png"))
    assert len(found) == 2
    assert found.scores == pytest.approx([0.89, 0.87], abs=0.03)
    for reference in (WOMAN, MAN):
        person = min(range(2), key=lambda i: np.abs(found.keypoints[i, 5, :2] - reference[0]).sum())
        torso = found.keypoints[person, TORSO]
        # Measured 0.2 to 1.1 px from the reference (Pillow's resize against OpenCV's).
        assert np.abs(torso[:, :2] - reference).max() < 3.0
        assert (torso[:, 2] > 0.9).all()
        x0, y0, x1, y1 = found.boxes[person]
        assert (x0 <= torso[:, 0]).all() and (torso[:, 0] <= x1).all() and (y0 <= torso[:, 1]).all()


def test_yolo_at_320_finds_the_same_torsos_coarser(yolo320):
    found = yolo320(rgb("sports2d_060.png"))
    assert len(found) == 2
    for reference in (WOMAN, MAN):
        person = min(range(2), key=lambda i: np.abs(found.keypoints[i, 5, :2] - reference[0]).sum())
        # Measured up to 10.4 px (a pixel of the 320 input is 5.5 image pixels).
        assert np.abs(found.keypoints[person, TORSO, :2] - reference).max() < 16.0


def test_bundled_movenet_finds_the_astronaut_and_is_recognised():
    model = open_model()
    assert model.family == "movenet" and model.input_size == 192
    found = model(rgb("astronaut.png"))
    assert len(found) == 1
    # YOLO at 640 (README): shoulders at (311.7, 249.6) and (104.0, 243.1); MoveNet's int8 output
    # lands within 20 px of them (measured 19.2), its scores are coarse.
    shoulders = found.keypoints[0, [5, 6], :2]
    assert np.abs(shoulders - [(311.7, 249.6), (104.0, 243.1)]).max() < 30.0
    assert (found.keypoints[0, [5, 6], 2] >= 0.3).all()


class FakeMoveNet:
    """An ONNX session standing in for MoveNet: it answers each run with the next of ``answers``
    (17 keypoints' (y, x) as fractions of its input, and one score for all) and keeps the
    images it was given."""

    def __init__(self, answers):
        self.answers, self.inputs = list(answers), []

    def get_inputs(self):
        return [SimpleNamespace(name="input", shape=[1, 192, 192, 3], type="tensor(uint8)")]

    def run(self, _outputs, feeds):
        self.inputs.append(feeds["input"][0])
        (y, x), score = self.answers.pop(0)
        out = np.zeros((1, 1, 17, 3))
        out[..., 0], out[..., 1], out[..., 2] = y, x, score
        out[0, 0, 1, :2] = y + 0.1, x + 0.05  # a second point, so the box has a size
        return [out]


def test_movenet_runs_on_a_crop_around_the_last_person_and_falls_back_to_the_whole_image():
    image = np.zeros((480, 640, 3), np.uint8)
    # The whole image is padded to 640 x 640: fraction f is pixel 640 f.
    session = FakeMoveNet([((0.5, 0.25), 0.9), ((0.5, 0.5), 0.9), ((0.5, 0.5), 0.05), ((0.5, 0.25), 0.9)])
    model = MoveNet(session)
    first = model(image)
    assert np.allclose(first.keypoints[0, 0, :2], [160.0, 320.0])
    # The box (160, 320)-(192, 384) is 64 px high: the crop is 80 px square around its centre.
    region = crop_region(first.boxes[0], image.shape)
    assert region == (136, 312, 80)
    second = model(image)  # on the crop: its centre is the box's centre
    assert np.allclose(second.keypoints[0, 0, :2], [176.0, 352.0])
    assert len(session.inputs) == 2
    # The crop finds nobody: the whole image is run in the same frame.
    third = model(image)
    assert len(session.inputs) == 4 and np.allclose(third.keypoints[0, 0, :2], [160.0, 320.0])
    # A box as large as the image is run whole; reset() forgets the last person.
    assert crop_region(np.array([0.0, 0.0, 600.0, 470.0]), image.shape) is None
    model.reset()
    session.answers.append(((0.5, 0.25), 0.9))
    model(image)
    assert np.array_equal(session.inputs[-1], session.inputs[0])  # the whole image again


def test_an_int8_model_runs_unfused_only_on_a_cpu_without_int8_dot_products(monkeypatch):
    # AVX2 alone saturates the fused int8 convolutions' 16-bit sums (an AMD EPYC here: the
    # bundled MoveNet's turntable 90th percentile 19.0 degrees fused, 12.0 unfused).
    import onnxruntime as ort

    def level():
        return loading.session(bundled_model()).get_session_options().graph_optimization_level

    assert loading.quantized(bundled_model())
    monkeypatch.setattr(loading, "int8_dot_product", lambda: False)
    assert level() == ort.GraphOptimizationLevel.ORT_ENABLE_BASIC
    monkeypatch.setattr(loading, "int8_dot_product", lambda: True)
    assert level() == ort.GraphOptimizationLevel.ORT_ENABLE_ALL


def test_a_float_model_is_not_taken_for_an_int8_one(tmp_path):
    assert not loading.quantized(shared_path("models", "yolo11n-pose-320.onnx"))
    with pytest.raises(FileNotFoundError, match="none.onnx"):
        loading.quantized(tmp_path / "none.onnx")


def test_family_is_recognised_from_the_model_and_checked():
    yolo = open_model(shared_path("models", "yolo11n-pose-320.onnx"))
    assert isinstance(yolo, YoloPose) and yolo.family == "yolo-pose" and yolo.input_size == 320
    assert recognise(yolo.session) == "yolo-pose"
    with pytest.raises(ValueError, match="family must be one of"):
        open_model(None, family="openpose")
    with pytest.raises(FileNotFoundError):
        open_model("no_such_model.onnx")


def test_image_checks_and_letterbox_inverse():
    model = open_model()
    with pytest.raises(ValueError, match="RGB image"):
        model(np.zeros((10, 10), dtype=np.uint8))
    with pytest.raises(ValueError, match="uint8"):
        model(np.zeros((10, 10, 3)))  # type: ignore[arg-type]  # the refusal under test
    image = np.zeros((100, 300, 3), dtype=np.uint8)
    boxed, box = letterbox(image, 60, 114, centre=True)
    assert boxed.shape == (60, 60, 3) and (boxed[:20] == 114).all() and (boxed[40:] == 114).all()
    assert box.to_image(np.array([[30.0, 30.0], [0.0, 20.0]])) == pytest.approx(
        np.array([[150.0, 50.0], [0.0, 0.0]])
    )


def test_non_maximum_suppression_keeps_the_best_of_each_overlapping_group():
    boxes = np.array([[0, 0, 10, 10], [1, 1, 11, 11], [20, 20, 30, 30], [0, 0, 10, 5]], dtype=float)
    scores = np.array([0.9, 0.95, 0.5, 0.8])
    # IoU(0, 1) = 81 / 119 = 0.68; IoU(1, 3) = 36 / 114 = 0.32; box 2 is alone.
    assert non_maximum_suppression(boxes, scores, 0.5).tolist() == [1, 3, 2]
    assert non_maximum_suppression(boxes, scores, 0.3).tolist() == [1, 2]
    assert non_maximum_suppression(boxes, scores, 0.7).tolist() == [1, 0, 3, 2]
