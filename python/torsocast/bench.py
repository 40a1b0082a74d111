"""Latency measured on this machine: the forecasters through the Python API, and one frame of
the RGB-D pipeline outside the keypoint model (``Tracker.step``) for a crowd of synthetic people.

``torsocast bench`` prints both; ``benches/bench_python.py`` adds the SciPy reference beside the
first, ``benches/bench_pipeline.py`` the pipeline's own bookkeeping and the models beside the
second.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from functools import partial

import numpy as np

from . import wrap_angle
from ._core import Forecaster, ForecasterConfig, forecast_batch
from .camera import Camera, Intrinsics
from .tracker import Tracker

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


#: The crowd's camera: 640x480 pixels, level, at the world's origin.
K = Intrinsics(525.0, 525.0, 320.0, 240.0)
#: Frames of a crowd (8 s at 25 Hz): every track is confirmed and forecasting for most of them.
FRAMES = 200
PER_ROW = 10
#: Pixels across and up the picture per person on the stand: a torso 4 m away fits.
CELL = (64, 96)
#: People in the crowds ``torsocast bench`` times a frame of.
CROWDS = (1, 10, 50)


def places(n: int) -> np.ndarray:
    """Where ``n`` people stand, ``(n, 3)`` in the world frame of :data:`K`'s camera. Up to ten:
    on a 2-4 m arc across the picture, some partly behind others or out of view. More: on a
    stand's tiers, rows of ten across the picture, each row half a metre further back and high
    enough to be seen above the one in front, so that everyone is tracked (fifty on the arc
    would stand inside one another, and a person the tracker cannot tell apart costs less)."""
    if n < 1:
        raise ValueError(f"a crowd needs at least one person, got {n}")
    if n <= PER_ROW:
        return np.array([[2.0 + 2.0 * (i % 5) / 4, -1.2 + 2.4 * i / max(n - 1, 1), 0.0] for i in range(n)])
    rows = -(-n // PER_ROW)
    out = np.zeros((n, 3))
    for i in range(n):
        row, column = divmod(i, PER_ROW)
        across = min(n - PER_ROW * row, PER_ROW)
        u = K.cx + CELL[0] * (column - (across - 1) / 2)
        v = K.cy + CELL[1] * ((rows - 1) / 2 - row)  # the front row lowest in the picture
        x = 4.0 + 0.5 * row
        out[i] = x, -(u - K.cx) * x / K.fx, -(v - K.cy) * x / K.fy
    return out


def crowd(n: int, t: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """``n`` people standing at :func:`places` at time ``t``, slowly turning: their 17 keypoints
    ``(n, 17, 3)`` as a model would give them (a pixel's noise, score 0.9), and the depth image
    they would give (their torsos as boxes before a wall 8 m away)."""
    depth = np.full((480, 640), 8.0, dtype=np.float32)
    keypoints = np.zeros((n, 17, 3))
    for i, centre in enumerate(places(n)):
        yaw = np.pi + 0.5 * np.sin(0.5 * t + i)
        left = np.array([-np.sin(yaw), np.cos(yaw), 0.0])
        joints = centre + np.outer(np.linspace(-0.2, 0.2, 17), left)
        joints[:, 2] += np.linspace(0.3, -0.3, 17)
        optical = np.column_stack([-joints[:, 1], -joints[:, 2], joints[:, 0]])
        uv = K.project(optical)
        keypoints[i, :, :2] = uv + rng.normal(0, 0.5, size=(17, 2))
        keypoints[i, :, 2] = 0.9
        u0, v0 = np.clip(uv.min(axis=0) - 4, 0, [639, 479]).astype(int)
        u1, v1 = np.clip(uv.max(axis=0) + 4, 0, [639, 479]).astype(int)
        depth[v0 : v1 + 1, u0 : u1 + 1] = np.minimum(depth[v0 : v1 + 1, u0 : u1 + 1], centre[0])
    return keypoints, depth


def crowd_frames(n: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """:data:`FRAMES` frames of :func:`crowd`, each with a depth image of its own (so that it is
    read from memory, as a sensor's frame after the model has run)."""
    rng = np.random.default_rng(n)
    return [crowd(n, k / 25, rng) for k in range(FRAMES)]


def frame_cost(frames: list[tuple[np.ndarray, np.ndarray]]) -> tuple[float, int]:
    """Median seconds of one ``Tracker.step`` call over ``frames`` (25 Hz), with forecasts and
    intervals 0.4 and 1 s ahead, and the tracks confirmed at the end."""
    if not frames:
        raise ValueError("no frames to time")
    tracker, seconds = Tracker(), []
    intrinsics, to_world = (K.fx, K.fy, K.cx, K.cy), Camera(K).camera_to_world
    for k, (keypoints, depth) in enumerate(frames):
        start = time.perf_counter()
        tracker.step(k / 25, keypoints, depth, intrinsics, K.coefficients, to_world, [0.4, 1.0])
        seconds.append(time.perf_counter() - start)
    return float(np.median(seconds)), len(tracker.tracks)


def frame_report(rows: list[tuple[int, float, int]]) -> str:
    """``(people, seconds per frame, tracks)`` as a Markdown table."""
    lines = ["| people | Tracker.step per frame (ms) | tracks |", "|---:|---:|---:|"]
    lines += [f"| {n} | {seconds * 1e3:.3f} | {tracks} |" for n, seconds, tracks in rows]
    return "\n".join(lines)


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
