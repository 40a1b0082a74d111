"""Forecaster, baselines and batch call against the independent SciPy reference."""

import itertools
from typing import Any

import numpy as np
import pytest

import scipy_reference as ref
import torsocast as tc
from conftest import walking_history

HORIZONS = [0.0, 0.04, 0.4, 1.0, 2.0]

SPLINE_CASES: list[dict[str, Any]] = [
    dict(filter=f, degree=d, lambda_unit=u, extrapolation=e, lam=lam)
    for f, d, u, e, lam in itertools.product(
        ["off", "causal", "zero_phase"],
        [0, 1, 2, 3],
        ["samples", "seconds"],
        ["polynomial", "linear", "damped"],
        [0.5],
    )
] + [
    dict(),
    dict(degree=3, lam=0.01, filter_components=[True] * 5),
    dict(degree=4, lam=3.0),
    dict(extrapolation="damped", damping=(0.0, 0.2, float("inf"), 3.0, 0.7)),
]
BASELINES: list[dict[str, Any]] = [
    dict(method="const"),
    dict(method="constant_velocity"),
    dict(method="constant_velocity", velocity_window=0.4),
]


def run(cfg, t, hist, weights=None):
    f = tc.Forecaster(tc.ForecasterConfig(**cfg))
    for k in range(len(t)):
        f.update(hist[k], t[k], 1.0 if weights is None else weights[k])
    return f.forecast(HORIZONS)


def close(a, b):
    # Cubic and quartic extrapolation 2 s ahead amplifies rounding (see MAX_DEGREE): relative bound.
    np.testing.assert_allclose(a, b, rtol=1e-8, atol=1e-9)


@pytest.mark.parametrize("cfg", SPLINE_CASES + BASELINES, ids=str)
def test_full_history_equals_reference(cfg):
    t, hist = walking_history()
    close(run(cfg, t, hist), ref.forecast(hist, HORIZONS, **cfg))


@pytest.mark.parametrize("cfg", SPLINE_CASES, ids=str)
def test_confidence_weights_enter_the_fit_as_in_the_reference(cfg):
    t, hist = walking_history(seed=3)
    w = np.random.default_rng(4).uniform(0.2, 1.0, size=len(t))
    close(run(cfg, t, hist, w), ref.forecast(hist, HORIZONS, weights=w, **cfg))


@pytest.mark.parametrize("n", [2, 5, 9, 23])
def test_partial_history_during_warm_up(n):
    t, hist = walking_history(n=n)
    configs: list[dict[str, Any]] = [dict(), dict(degree=3, lam=0.2, filter="causal"), *BASELINES]
    for cfg in configs:
        close(run(cfg, t, hist), ref.forecast(hist, HORIZONS, **cfg))


@pytest.mark.parametrize("cfg", SPLINE_CASES, ids=str)
def test_fast_path_equals_general_path(cfg):
    t, hist = walking_history(seed=7)
    fast = run(dict(cfg, fast_path=True), t, hist)
    general = run(dict(cfg, fast_path=False), t, hist)
    tol = 1e-9 * max(1.0, np.abs(general).max()) if cfg.get("degree", 1) > 3 else 1e-9
    np.testing.assert_allclose(fast, general, rtol=0, atol=tol)


def test_azimuth_is_unwrapped_and_forecast_continuously():
    t = np.arange(50) / 25
    hist = np.zeros((50, 5))
    hist[:, 3] = np.angle(np.exp(1j * (3.0 + 2.0 * t)))  # crosses +-pi at t ~ 0.07
    hist[:, 4] = np.pi / 2
    out = run(dict(filter="off", extrapolation="linear"), t, hist)
    np.testing.assert_allclose(out[:, 3], 3.0 + 2.0 * (t[-1] + np.array(HORIZONS)), atol=1e-9)
    np.testing.assert_allclose(tc.wrap_angle(out[:, 3]), np.angle(np.exp(1j * out[:, 3])))


def test_gaps_are_filled_and_reported_and_long_gaps_restart():
    f = tc.Forecaster()
    assert f.update([0, 0, 1, 0, 1.5], 10.00) == (0, False)
    assert f.update([0.08, 0, 1, 0, 1.5], 10.083) == (1, False)  # one 25 Hz slot missing, jittered
    poses, weights = f.history()
    np.testing.assert_allclose(poses[:, 0], [0, 0.04, 0.08])
    np.testing.assert_array_equal(weights, [1, 0, 1])
    assert f.last_time == pytest.approx(10.08)
    assert f.update([0, 0, 1, 0, 1.5], 11.0) == (0, True)
    assert len(f) == 1


def test_batch_equals_per_track_forecasts_and_the_reference():
    windows = np.stack([walking_history(seed=s)[1] for s in range(20)])
    configs: list[dict[str, Any]] = [dict(), dict(degree=2, lam=2.0, filter="causal"), *BASELINES]
    for cfg in configs:
        config = tc.ForecasterConfig(**cfg)
        batch = tc.forecast_batch(windows.astype(np.float32), HORIZONS, config)
        assert batch.shape == (20, len(HORIZONS), 5) and batch.dtype == np.float64
        t = np.arange(50) / 25
        for i in (0, 7, 19):
            w32 = windows[i].astype(np.float32).astype(np.float64)
            np.testing.assert_allclose(batch[i], run(cfg, t, w32), atol=1e-12)
            close(batch[i], ref.forecast(w32, HORIZONS, **cfg))


def test_default_config_is_the_thesis_setting():
    c = tc.ForecasterConfig()
    assert (c.rate_hz, c.history, c.capacity, c.filter_order, c.cutoff_hz, c.degree, c.lam) == (
        25.0,
        2.0,
        50,
        2,
        5.0,
        1,
        1.0,
    )
    assert c.filter_components == [False, False, False, True, True]
    assert tc.Forecaster().config.method == "filter_spline"


def test_bad_input_raises_typed_errors_and_keeps_state():
    f = tc.Forecaster(tc.ForecasterConfig("constant_velocity"))
    with pytest.raises(tc.NotEnoughHistoryError):
        f.forecast([1.0])
    f.update([0, 0, 1, 0, 1.5], 0.0)
    with pytest.raises(tc.TimeNotIncreasingError, match="`t`"):
        f.update([0, 0, 1, 0, 1.5], 0.01)
    with pytest.raises(tc.NonFiniteError, match="pose"):
        f.update([0, np.nan, 1, 0, 1.5], 0.04)
    with pytest.raises(tc.InvalidArgumentError, match="weight"):
        f.update([0, 0, 1, 0, 1.5], 0.04, -1.0)
    with pytest.raises(tc.InvalidArgumentError, match="horizons"):
        f.forecast([-0.4])
    assert len(f) == 1
    with pytest.raises(tc.ShapeError):
        tc.forecast_batch(np.zeros((3, 50, 4)), [1.0])
    with pytest.raises(tc.NonFiniteError, match="histories"):
        tc.forecast_batch(np.full((2, 50, 5), np.nan), [1.0])


@pytest.mark.parametrize(
    "kwargs, name",
    [
        (dict(method="rnn"), "method"),
        (dict(filter="median"), "filter"),
        (dict(cutoff_hz=13.0), "cutoff_hz"),
        (dict(degree=5), "degree"),
        (dict(degree=2, lam=0.0), "lam"),
        (dict(rate_hz=0.0), "rate_hz"),
        (dict(history=-2.0), "history"),
        (dict(max_gap=float("nan")), "max_gap"),
        (dict(method="constant_velocity", velocity_window=0.0), "window"),
        (dict(lambda_unit="frames"), "lambda_unit"),
        (dict(extrapolation="damped", damping=(1.0, 1.0, -1.0, 1.0, 1.0)), "time_constants"),
        (dict(extrapolation="linear", damping=(1.0,) * 5), "extrapolation"),
    ],
)
def test_config_errors_name_the_argument(kwargs, name):
    with pytest.raises(tc.InvalidArgumentError, match=name):
        tc.ForecasterConfig(**kwargs)


def test_damped_config_reports_its_time_constants():
    assert tc.ForecasterConfig(extrapolation="damped").damping == list(ref.DAMPING_H36M_S1)
    config = tc.ForecasterConfig(extrapolation="damped", damping=(1, 2, 3, 4, 5))
    assert config.damping == [1.0, 2.0, 3.0, 4.0, 5.0] and "damping=[1.0, 2.0, 3.0, 4.0, 5.0]" in repr(config)
    assert tc.ForecasterConfig(extrapolation="linear").damping is None


def test_config_round_trips_through_the_forecaster():
    config = tc.ForecasterConfig("constant_velocity", velocity_window=0.4)
    back = tc.Forecaster(config).config
    assert (back.method, back.velocity_window, back.degree, back.filter) == (
        "constant_velocity",
        0.4,
        None,  # not a setting of this method
        None,
    )
    # A setting of another method would do nothing: it is refused, not ignored.
    refused: list[tuple[Any, dict[str, Any]]] = [
        ("const", {"lam": 2.0}),
        ("constant_velocity", {"degree": 3}),
        (None, {"velocity_window": 1.0}),
    ]
    for method, setting in refused:
        with pytest.raises(tc.InvalidArgumentError, match=next(iter(setting))):
            tc.ForecasterConfig(method, **setting)
    assert tc.ForecasterConfig("const").lam is None and tc.ForecasterConfig().lam == 1.0


def test_forecast_batch_reads_any_memory_layout_as_its_shape_says():
    # A Fortran-ordered array (any transposed view) is contiguous in the other order: it was
    # read as it lay in memory, giving wrong forecasts.
    rng = np.random.default_rng(5)
    histories = rng.normal(size=(4, 50, 5)).cumsum(axis=1)
    expected = tc.forecast_batch(histories, [0.4, 1.0])
    for layout in (np.asfortranarray(histories), histories.transpose(2, 1, 0).copy().transpose(2, 1, 0)):
        assert not layout.flags.c_contiguous
        assert np.array_equal(tc.forecast_batch(layout, [0.4, 1.0]), expected)
    assert np.array_equal(
        tc.forecast_batch(histories[:, ::2][:, :25], [0.4]),
        tc.forecast_batch(np.ascontiguousarray(histories[:, ::2][:, :25]), [0.4]),
    )


def test_a_horizon_beyond_an_hour_is_refused_not_carried_to_infinity():
    # The fuzz harness found a forecast at 1e308 s giving NaN (infinity times a zero weight).
    person = tc.Person()
    f = tc.Forecaster()
    for k in range(30):
        f.update([0.04 * k, 0.0, 1.0, 0.0, 1.5], k / 25)
    assert np.isfinite(f.forecast([tc.MAX_HORIZON])).all()
    for horizons in ([tc.MAX_HORIZON * 2], [1e308]):
        with pytest.raises(tc.InvalidArgumentError, match="horizons"):
            f.forecast(horizons)
        with pytest.raises(tc.InvalidArgumentError, match="horizons"):
            person.intervals(horizons)


def test_a_negative_velocity_window_is_refused():
    # It was accepted (the list of silently wrong inputs).
    with pytest.raises(tc.InvalidArgumentError, match="window"):
        tc.ForecasterConfig("constant_velocity", velocity_window=-1.0)
