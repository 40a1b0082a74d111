"""Butterworth design and filtering against scipy.signal."""

import numpy as np
import pytest
from scipy import signal

import torsocast as tc


@pytest.mark.parametrize("order", range(1, 9))
@pytest.mark.parametrize("cutoff", [0.3, 2.0, 5.0, 6.25, 9.0, 12.0])
def test_design_equals_scipy_butter(order, cutoff):
    ours = tc.butter_lowpass(order, cutoff, 25.0)
    ref = signal.butter(order, cutoff, fs=25.0, output="sos")
    assert ours.shape == ref.shape
    np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-10)


@pytest.mark.parametrize("order", [1, 2, 3, 4])
def test_causal_window_equals_sosfilt_from_steady_state(order, rng):
    x = rng.normal(size=80).cumsum()
    sos = signal.butter(order, 5.0, fs=25.0, output="sos")
    ref, _ = signal.sosfilt(sos, x, zi=signal.sosfilt_zi(sos) * x[0])
    np.testing.assert_allclose(tc.lowpass_causal(x, order=order), ref, atol=1e-12)


@pytest.mark.parametrize("order", [1, 2, 3, 5])
def test_zero_phase_equals_sosfiltfilt(order, rng):
    x = rng.normal(size=50).cumsum()
    sos = signal.butter(order, 4.0, fs=30.0, output="sos")
    np.testing.assert_allclose(
        tc.lowpass_zero_phase(x, order=order, cutoff_hz=4.0, rate_hz=30.0),
        signal.sosfiltfilt(sos, x),
        atol=1e-12,
    )


def test_zero_phase_of_a_short_window_pads_by_its_length_minus_one(rng):
    x = rng.normal(size=6)  # shorter than the default pad of 9
    sos = signal.butter(2, 5.0, fs=25.0, output="sos")
    np.testing.assert_allclose(tc.lowpass_zero_phase(x), signal.sosfiltfilt(sos, x, padlen=5), atol=1e-12)


def test_streaming_low_pass_equals_sosfilt_over_chunks(rng):
    x = rng.normal(size=60)
    lp = tc.LowPass(3, 5.0, 25.0)
    ys = np.r_[[lp.step(v) for v in x[:10]], lp.filter(x[10:])]
    sos = signal.butter(3, 5.0, fs=25.0, output="sos")
    np.testing.assert_allclose(ys, signal.sosfilt(sos, x, zi=signal.sosfilt_zi(sos) * x[0])[0], atol=1e-12)
    np.testing.assert_allclose(lp.sos, sos, atol=1e-12)


def test_float32_and_list_inputs_are_accepted(rng):
    x = rng.normal(size=30)
    ref = tc.lowpass_zero_phase(x.astype(np.float32).astype(np.float64))
    out = tc.lowpass_zero_phase(x.astype(np.float32))
    assert out.dtype == np.float64
    np.testing.assert_allclose(out, ref, atol=1e-12)
    np.testing.assert_allclose(tc.lowpass_causal(list(x)), tc.lowpass_causal(x))


def test_bad_filters_raise_value_errors_naming_the_argument():
    with pytest.raises(tc.InvalidArgumentError, match="cutoff_hz"):
        tc.butter_lowpass(2, 12.5, 25.0)
    with pytest.raises(ValueError, match="order"):
        tc.butter_lowpass(0, 5.0, 25.0)
    with pytest.raises(tc.NonFiniteError, match="`x`"):
        tc.lowpass_zero_phase([0.0, np.nan, 1.0])
    lp = tc.LowPass()
    with pytest.raises(tc.NonFiniteError):
        lp.step(float("inf"))


def test_a_refused_window_leaves_the_streaming_filter_as_it_was():
    # The check is the core's (LowPass::filter_window): no sample before the NaN is taken.
    lp, twin = tc.LowPass(), tc.LowPass()
    lp.filter([1.0, 2.0, 3.0])
    twin.filter([1.0, 2.0, 3.0])
    with pytest.raises(tc.NonFiniteError, match="index 1"):
        lp.filter([4.0, float("nan")])
    np.testing.assert_array_equal(lp.filter([5.0, 6.0]), twin.filter([5.0, 6.0]))
    assert tc.LowPass().sos.shape == tc.butter_lowpass(2, 5.0, 25.0).shape  # the thesis' default
