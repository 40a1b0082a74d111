"""Per-joint gating against a plain-Python statement of the rule."""

import numpy as np
import pytest

import torsocast as tc


def reference_gate(frames, threshold, max_replacements):
    """The thesis rule (section 3.2) plus the 'lost after too many replacements' limit."""
    prev = [None] * frames.shape[1]
    run = [0] * frames.shape[1]
    out, codes = np.empty_like(frames), np.empty(frames.shape[:2], dtype=np.uint8)
    for f, frame in enumerate(frames):
        for j, x in enumerate(frame):
            finite = np.isfinite(x).all()
            if prev[j] is not None and finite and np.linalg.norm(x - prev[j]) <= threshold:
                code = 0
            elif prev[j] is not None and run[j] < max_replacements:
                code = 1
            elif prev[j] is None and finite:
                code = 0
            else:
                code = 2
            if code == 0:
                prev[j], run[j], out[f, j] = x, 0, x
            elif code == 1:
                run[j] += 1
                out[f, j] = prev[j]
            else:
                prev[j], run[j], out[f, j] = None, 0, np.nan
            codes[f, j] = code
    return out, codes


def test_gate_follows_the_rule_on_noisy_tracks_with_jumps_and_holes(rng):
    frames = np.cumsum(rng.normal(scale=0.04, size=(300, 6, 3)), axis=0)
    frames[rng.random((300, 6)) < 0.08] += rng.normal(scale=0.5, size=3)  # outliers
    frames[rng.random((300, 6)) < 0.1] = np.nan  # missing
    gate = tc.JointGate(6, threshold=0.1, max_replacements=3)
    ref_out, ref_codes = reference_gate(frames, 0.1, 3)
    for f in range(300):
        out, codes = gate.update(frames[f])
        np.testing.assert_array_equal(codes, ref_codes[f])
        np.testing.assert_array_equal(out, ref_out[f])
    assert {0, 1, 2} <= set(np.unique(ref_codes))


def test_gate_rejects_bad_shapes_without_changing_state():
    gate = tc.JointGate(2)
    gate.update([[0, 0, 0], [1, 1, 1]])
    with pytest.raises(tc.ShapeError, match="joints"):
        gate.update([[0, 0, 0]])
    _, codes = gate.update([[0.05, 0, 0], [1, 1, 1.05]])
    assert list(codes) == [tc.JointStatus.MEASURED] * 2
    with pytest.raises(tc.InvalidArgumentError, match="threshold"):
        tc.JointGate(3, threshold=0.0)


def test_a_joint_count_beyond_any_skeleton_is_refused_not_allocated():
    # 10**12 joints ended the interpreter (allocation failure, SIGABRT).
    with pytest.raises(tc.InvalidArgumentError, match="n_joints"):
        tc.JointGate(10**12)
    with pytest.raises(tc.InvalidArgumentError, match="n_joints"):
        tc.JointGate(1025)
    assert tc.JointGate(1024).n_joints == 1024


def test_a_cut_off_too_low_to_design_is_refused_instead_of_forecasting_nan():
    with pytest.raises(tc.InvalidArgumentError, match="cutoff_hz"):
        tc.Forecaster(tc.ForecasterConfig(cutoff_hz=1e-9))
    f = tc.Forecaster(tc.ForecasterConfig(cutoff_hz=25.0 * 1e-5))
    for k in range(50):
        f.update([0.04 * k, 0.0, 1.0, 0.1, 1.5], k / 25, 1.0)
    assert np.isfinite(f.forecast([0.4, 2.0])).all()
