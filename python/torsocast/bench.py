"""Latency of the forecasters through the Python API, measured on this machine.

``torsocast bench`` prints it; ``benches/bench_python.py`` adds the SciPy reference beside it.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from functools import partial

import numpy as np

from . import wrap_angle
from ._core import Forecaster, ForecasterConfig, forecast_batch

#: Per-forecast cost reported by the thesis (Python, Intel i7-6700HQ), for comparison.
THESIS_FORECAST_SECONDS = 0.715e-3

KINDS: dict[str, ForecasterConfig] = {
    "const": ForecasterConfig("const"),
    "constant velocity 2 s": ForecasterConfig("constant_velocity"),
    "constant velocity 0.4 s": ForecasterConfig("constant_velocity", velocity_window=0.4),
    "filter+spline N=1 (default)": ForecasterConfig(),
    "filter+spline N=1, general path": ForecasterConfig(fast_path=False),
    "filter+spline N=3": ForecasterConfig(degree=3),
}


def walking_windows(count: int, length: int = 50, rate_hz: float = 25.0, seed: int = 0) -> np.ndarray:
    """(count, length, 5) pose histories of people walking and turning, with noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(length) / rate_hz
    speed, turn, phase = rng.uniform(0.5, 1.5, (3, count, 1))
    out = np.empty((count, length, 5))
    out[..., 0] = speed * t + 0.01 * rng.normal(size=(count, length))
    out[..., 1] = 0.2 * np.sin(t + phase)
    out[..., 2] = 1.1 + 0.02 * np.sin(11.3 * t + phase)
    out[..., 3] = wrap_angle(turn * t + phase + 0.1 * np.sin(11.3 * t))
    out[..., 4] = np.pi / 2 + 0.05 * np.sin(5.6 * t + phase)
    return out


def best_time(fn: Callable[[], object], repeat: int = 7, number: int = 0) -> float:
    """Best mean seconds per call over `repeat` runs (`number` calls each; 0 = calibrate)."""
    if number == 0:
        number = 1
        while True:
            start = time.perf_counter()
            for _ in range(number):
                fn()
            if time.perf_counter() - start > 0.05:
                break
            number *= 2
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            fn()
        best = min(best, (time.perf_counter() - start) / number)
    return best


def frame_step(config: ForecasterConfig, walk: np.ndarray, horizons: list[float]) -> Callable[[], object]:
    """One frame of a track through the Python API: the next pose of ``walk`` (cycled, time
    always increasing) and a forecast at ``horizons``, on a history filled first. A forecaster
    keeps its fit until its history changes, so a forecast is only timed after an update."""
    f = Forecaster(config)
    k = 0

    def step() -> object:
        nonlocal k
        f.update(walk[k % len(walk)], k / config.rate_hz)
        k += 1
        return f.forecast(horizons) if len(f) >= f.min_samples else None

    for _ in range(len(walk)):
        step()
    return step


def measure(windows: int = 2000) -> list[tuple[str, float, float]]:
    """(kind, seconds per frame of one track (update and forecast calls), seconds per window in
    forecast_batch)."""
    data = walking_windows(windows)
    rows = []
    for name, config in KINDS.items():
        single = best_time(frame_step(config, data[0], [1.0]))
        batch = best_time(partial(forecast_batch, data, [0.4, 1.0, 2.0], config), repeat=3, number=1)
        rows.append((name, single, batch / windows))
    return rows


def report(rows: list[tuple[str, float, float]]) -> str:
    lines = [
        "| forecaster | update + forecast via Python (µs) | per window in forecast_batch (µs) "
        "| vs thesis 0.715 ms |",
        "|---|---:|---:|---:|",
    ]
    for name, single, batch in rows:
        ratio = THESIS_FORECAST_SECONDS / single
        lines.append(f"| {name} | {single * 1e6:.2f} | {batch * 1e6:.2f} | {ratio:.0f}x faster |")
    return "\n".join(lines)
