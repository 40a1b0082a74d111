"""The HMP baseline (Martinez et al.'s GRU in NumPy): its gradients against finite differences, its
residual start against zero velocity, its training against a motion zero velocity cannot follow,
and its whole-body forecasts turned into torso poses exactly as the truth is."""

import json
from dataclasses import replace

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from conftest import run_cli
from torsocast import wrap_angle
from torsocast.datasets import h36m
from torsocast.datasets.kinematics import rotmat_to_euler, rotmat_to_expmap
from torsocast.evaluation import hmp, joint_angles
from torsocast.evaluation.h36m import evaluate, load
from torsocast.evaluation.methods import method_configs


def _small(rng, inputs=5, units=7):
    w = hmp.Weights.initial(inputs, units, rng)
    w = hmp.Weights(*[a.astype(np.float64) for a in w.arrays()])
    w.gates_bias[:] = rng.normal(size=w.gates_bias.shape)
    return w


def test_gradients_match_central_differences():
    rng = np.random.default_rng(0)
    w = _small(rng)
    history, future = rng.normal(size=(3, 6, 5)), rng.normal(size=(3, 4, 5))
    _, grads = hmp.loss_and_gradients(w, history, future)
    eps = 1e-6
    for array, grad in zip(w.arrays(), grads):
        numeric = np.zeros_like(array)
        for i in np.ndindex(array.shape):
            old = array[i]
            array[i] = old + eps
            up = hmp.loss_and_gradients(w, history, future)[0]
            array[i] = old - eps
            down = hmp.loss_and_gradients(w, history, future)[0]
            array[i] = old
            numeric[i] = (up - down) / (2 * eps)
        np.testing.assert_allclose(grad, numeric, rtol=1e-5, atol=1e-9)


def test_with_no_output_map_the_forecast_holds_the_last_frame():
    rng = np.random.default_rng(1)
    w = _small(rng)
    w.out[:] = 0.0
    w.out_bias[:] = 0.0
    history = rng.normal(size=(2, hmp.HISTORY, 5))
    predicted = hmp.predict(w, history, 7)
    np.testing.assert_allclose(predicted, np.repeat(history[:, -1:], 7, axis=1), atol=1e-6)


def _waves(rng, takes=4, frames=400, channels=6):
    t = np.arange(frames)[:, None]
    out = []
    for _ in range(takes):
        period = rng.uniform(20, 40, channels)
        phase = rng.uniform(0, 2 * np.pi, channels)
        out.append(("walking", np.sin(2 * np.pi * t / period + phase)))
    return out


def test_training_learns_a_motion_that_zero_velocity_cannot():
    rng = np.random.default_rng(2)
    takes = _waves(rng)
    settings = hmp.Training(units=32, iterations=600, steps=10, learning_rate=0.05)
    model = hmp.train(takes, ["walking"], (1,), settings)
    assert model.losses[-50:].mean() < 0.5 * model.losses[:50].mean()
    _, frames = _waves(np.random.default_rng(3), takes=1)[0]
    starts = range(hmp.HISTORY, 300, 17)
    history = np.stack([frames[s - hmp.HISTORY : s] for s in starts])
    truth = np.stack([frames[s : s + 10] for s in starts])
    forecast = model.forecast(history, "walking", 10)
    held = np.repeat(history[:, -1:], 10, axis=1)
    assert np.abs(forecast - truth).mean() < 0.5 * np.abs(held - truth).mean()


def test_a_model_round_trips_through_a_file_and_a_bad_file_is_refused(tmp_path):
    rng = np.random.default_rng(4)
    model = hmp.train(_waves(rng), ["walking"], (1,), hmp.Training(units=8, iterations=100, steps=5))
    model.save(tmp_path / "m")  # named as given, no suffix added
    again = hmp.Model.load(tmp_path / "m")
    history = _waves(rng, takes=1)[0][1][None, : hmp.HISTORY]
    np.testing.assert_array_equal(
        model.forecast(history, "walking", 5), again.forecast(history, "walking", 5)
    )
    assert again.describe()["trained_on_subjects"] == [1]
    np.save(tmp_path / "other.npy", np.zeros(3))
    with pytest.raises(ValueError, match="not an HMP model"):
        hmp.Model.load(tmp_path / "other.npy")
    with pytest.raises(ValueError, match="not trained on action 'eating'"):
        model.forecast(history, "eating", 5)
    with pytest.raises(ValueError, match="history must be"):
        model.forecast(history[:, :10], "walking", 5)


def test_a_long_training_hands_over_the_model_so_far(monkeypatch):
    monkeypatch.setattr(hmp, "CHECKPOINT_EVERY", 40)
    saved = []
    model = hmp.train(
        _waves(np.random.default_rng(6)),
        ["walking"],
        (1,),
        hmp.Training(units=4, iterations=100, steps=5),
        checkpoint=lambda so_far: saved.append((so_far.iterations, len(so_far.losses))),
    )
    assert saved == [(40, 40), (80, 80)]
    assert model.iterations == 100 and len(model.losses) == 100


def test_a_run_stopped_and_trained_on_is_the_run_that_never_stopped(monkeypatch, tmp_path):
    # The learning rate decays within both halves, and the checkpoint goes through a file.
    monkeypatch.setattr(hmp, "CHECKPOINT_EVERY", 7)
    takes = _waves(np.random.default_rng(8))
    settings = hmp.Training(units=4, iterations=12, steps=5, decay_every=5, seed=3)
    whole = hmp.train(takes, ["walking"], (1,), settings)
    stopped = tmp_path / "stopped.npz"
    hmp.train(takes, ["walking"], (1,), settings, checkpoint=lambda so_far: so_far.save(stopped))
    at_7 = hmp.Model.load(stopped)
    assert at_7.iterations == 7 and at_7.describe()["resumable"]
    resumed = hmp.train(takes, ["walking"], (1,), settings, resume=at_7)
    for a, b in zip(resumed.weights.arrays(), whole.weights.arrays()):
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(resumed.losses, whole.losses)
    # Trained on further than first asked: the run of that length.
    longer = replace(settings, iterations=15)
    np.testing.assert_array_equal(
        hmp.train(takes, ["walking"], (1,), longer, resume=resumed).losses,
        hmp.train(takes, ["walking"], (1,), longer).losses,
    )


def test_a_model_is_trained_on_only_as_it_was_trained(tmp_path):
    takes = _waves(np.random.default_rng(8))
    settings = hmp.Training(units=4, iterations=6, steps=5)
    model = hmp.train(takes, ["walking"], (1,), settings)
    refused = {
        "with units 4, not 5": (takes, (1,), replace(settings, units=5, iterations=9), model),
        "on subjects \\[1\\], not \\[6\\]": (takes, (6,), replace(settings, iterations=9), model),
        "not those the model was trained on": (takes[:2], (1,), replace(settings, iterations=9), model),
        "6 steps already": (takes, (1,), settings, model),
        "without its training state": (
            takes,
            (1,),
            replace(settings, iterations=9),
            replace(model, rng=None),
        ),
    }
    for why, (data, subjects, asked, resume) in refused.items():
        with pytest.raises(ValueError, match=why):
            hmp.train(data, ["walking"], subjects, asked, resume=resume)


@pytest.mark.parametrize("field", ["units", "iterations", "batch", "steps"])
def test_training_settings_refuse_nothing_to_train(field):
    with pytest.raises(ValueError, match=field):
        hmp.Training(**{field: 0})


def test_rotation_logarithm_matches_scipy():
    # Turned by less than 0.9 of a half turn (the root turns a few degrees a step).
    r = Rotation.from_rotvec(Rotation.random(50, random_state=5).as_rotvec() * 0.9)
    np.testing.assert_allclose(rotmat_to_expmap(r.as_matrix()), r.as_rotvec(), atol=1e-9)
    small = np.array([1e-9, -2e-9, 3e-9])
    np.testing.assert_allclose(rotmat_to_expmap(Rotation.from_rotvec(small).as_matrix()), small, rtol=1e-6)
    np.testing.assert_allclose(rotmat_to_expmap(np.eye(3)), np.zeros(3))


def test_euler_angles_are_the_literatures_scipys_and_its_gimbal_lock_branch():
    r = Rotation.random(40, random_state=7)
    matrices = r.as_matrix()
    # The reference code's rotmat2euler is SciPy's extrinsic x-y-z of the transposed matrix.
    expected = Rotation.from_matrix(np.swapaxes(matrices, 1, 2)).as_euler("xyz")
    np.testing.assert_allclose(rotmat_to_euler(matrices), expected, atol=1e-9)
    # At gimbal lock its special branch: the third angle zero, the first from the top row.
    quarter = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])
    np.testing.assert_allclose(rotmat_to_euler(quarter), [0.0, -np.pi / 2, 0.0], atol=1e-12)
    np.testing.assert_allclose(rotmat_to_euler(quarter.T), [np.pi, np.pi / 2, 0.0], atol=1e-12)


def test_zero_velocity_on_the_literatures_measure_is_martinez_et_als_table_1(h36m_root):
    # Their table 1's zero-velocity row for the actions S5 holds whole (radians, at 80 / 160 /
    # 320 / 400 ms): the windows, the conversion and the channels left out are theirs.
    published = {
        "walking": [0.39, 0.68, 0.99, 1.15],
        "eating": [0.27, 0.48, 0.73, 0.86],
        "smoking": [0.26, 0.48, 0.97, 0.95],
    }
    model = hmp.train(
        [("walking", h36m.read_frames(h36m_root, 5, "walking", 1))],
        h36m.ACTIONS,
        (1,),
        hmp.Training(units=4, iterations=1),
    )
    sequences, _ = load(h36m_root, (5,))
    errors = joint_angles.evaluate(sequences, model)
    for action, row in published.items():
        assert [round(v, 2) for v in errors[action]["zero_velocity"]] == row
        assert len(errors[action]["hmp"]) == 4 and np.all(np.isfinite(errors[action]["hmp"]))
    assert "discussion" not in errors  # only one of its subactions is in S5


def test_the_models_frames_carry_the_files_root_and_give_the_true_poses(h36m_root):
    sequence = h36m.load_sequence(h36m_root, 5, "walkingdog", 1)
    for start in (60, 400, len(sequence.poses) - 50):
        poses = h36m.forecast_poses(sequence, start, sequence.frames[start : start + 50])
        truth = sequence.poses[start : start + 50]
        # Exact up to the exponential map's guard against a zero turn (a float32 epsilon).
        np.testing.assert_allclose(poses[:, [0, 1, 2, 4]], truth[:, [0, 1, 2, 4]], atol=1e-5)
        np.testing.assert_allclose(wrap_angle(poses[:, 3] - truth[:, 3]), 0.0, atol=1e-5)
    # The literature's plain even rows drop every second increment of the root: a walker carried
    # on by them covers about half the ground.
    walking = h36m.load_sequence(h36m_root, 5, "walking", 1)
    plain = h36m.read_expmap(h36m.sequence_path(h36m_root, 5, "walking", 1))[::2]
    drifted = h36m.forecast_poses(walking, 400, plain[400:450])
    walked = np.linalg.norm(walking.poses[449, :2] - walking.poses[399, :2])
    short = np.linalg.norm(drifted[-1, :2] - walking.poses[399, :2])
    assert walked > 1.0 and short == pytest.approx(walked / 2, rel=0.2)


def test_eval_runs_hmp_beside_the_thesis_methods_and_refuses_a_model_of_the_test_subject(h36m_root, tmp_path):
    if not (h36m_root / "S1").is_dir():
        pytest.skip("S1 files not found")
    model_path = tmp_path / "hmp.npz"
    code, out, _ = run_cli(
        [
            "eval",
            "train-hmp",
            "--data",
            str(h36m_root),
            "--units",
            "8",
            "--iterations",
            "100",
            "--out",
            str(model_path),
        ]
    )
    assert code == 0 and "trained on S1" in out
    code, out, _ = run_cli(
        [
            "eval",
            "h36m",
            "--data",
            str(h36m_root),
            "--protocol",
            "seeds",
            "--hmp",
            str(model_path),
            "--out",
            str(tmp_path / "r"),
        ]
    )
    assert code == 0
    report = json.loads((tmp_path / "r" / "report.json").read_text())
    assert set(report["results"]) == {*method_configs(), "hmp"}
    assert report["methods"]["hmp"]["config"]["trained_on_subjects"] == [1]
    hmp_row = next(line for line in out.splitlines() if line.startswith("| All |"))
    assert "–" not in hmp_row
    assert "HMP: a GRU of 8 units, trained here on S1 for 100 steps" in out
    assert "| walking | 0.39 / 0.68 / 0.99 / 1.15 |" in out  # the literature's measure beside it
    # Its errors are a forecast's: finite, and growing with the horizon.
    curve = report["results"]["hmp"]["categories"]["All"]["azimuth"]["curve"]
    assert np.all(np.isfinite(curve)) and curve[0] < curve[-1]

    seen = hmp.train(
        [("walking", h36m.read_frames(h36m_root, 5, "walking", 1))],
        h36m.ACTIONS,
        (5,),
        hmp.Training(units=4, iterations=1),
    )
    with pytest.raises(ValueError, match=r"trained on subject\(s\) \[5\]"):
        evaluate(h36m_root, (5,), "seeds", hmp_model=seen)
    code, _, err = run_cli(["eval", "h36m", "--data", str(h36m_root), "--hmp", str(tmp_path / "none.npz")])
    assert code == 2 and err.strip().startswith("--hmp:") and len(err.strip().splitlines()) == 1


def test_train_hmp_resumes_the_run_in_its_out_file_and_refuses_what_it_cannot(h36m_root, tmp_path):
    if not (h36m_root / "S1").is_dir():
        pytest.skip("S1 files not found")
    model_path = tmp_path / "hmp.npz"

    def train(iterations: int, *extra: str) -> tuple[int, str]:
        args = ["eval", "train-hmp", "--data", str(h36m_root), "--units", "4"]
        args += ["--iterations", str(iterations), "--out", str(model_path), *extra]
        code, _, err = run_cli(args)
        return code, err

    assert train(100)[0] == 0
    first = hmp.Model.load(model_path)
    assert train(200, "--resume")[0] == 0
    resumed = hmp.Model.load(model_path)
    assert resumed.iterations == 200
    np.testing.assert_array_equal(resumed.losses[:100], first.losses)
    for extra, why in [
        (("--resume",), "the model has had 200 steps already"),
        (("--resume", "--seed", "1"), "the model was trained with seed 0, not 1"),
    ]:
        code, err = train(200 if len(extra) == 1 else 300, *extra)
        assert code == 2 and why in err and len(err.strip().splitlines()) == 1, err
    model_path.unlink()
    code, err = train(100, "--resume")
    assert code == 2 and err.startswith("--resume:") and "does not exist" in err
    assert len(err.strip().splitlines()) == 1
