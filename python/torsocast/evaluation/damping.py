"""Selection of the damped trend's time constants on a training subject (Human3.6M S1).

The N = 1 fit's value ``d0`` and slope ``d1`` at the last sample are read off two forecasts of
the tangent rule; a damped trend ``d0 + d1 · T (1 - e^(-τ/T))`` is then scored for every ``T`` of
a grid, one ``T`` per quantity (position, azimuth, elevation), by the sum of its window-mean
errors at 0.4, 1 and 2 s, averaged over actions as the report does. The defaults of
``torso_core`` (``Extrapolation::DAMPED_H36M_S1``) are what this prints for S1:

    python -m torsocast.evaluation.damping --data ../shared/data/h36m
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .._core import ForecasterConfig, forecast_batch
from . import metrics, protocol
from .h36m import load

GRID = (0.0, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, float("inf"))
#: Pose components each quantity's time constant applies to.
COMPONENTS = {"position": (0, 1, 2), "azimuth": (3,), "elevation": (4,)}


def carry(time_constant: float, tau: np.ndarray) -> np.ndarray:
    """How far a unit slope decaying with the time constant carries in ``tau`` seconds."""
    if time_constant == 0.0:
        return np.zeros_like(tau)
    if np.isinf(time_constant):
        return tau
    return -time_constant * np.expm1(-tau / time_constant)


def select(
    data: str | Path, subjects: Sequence[int] = (1,), every: int = 10, grid: Sequence[float] = GRID
) -> dict[str, tuple[float, list[float]]]:
    """Best time constant per quantity, with its action-averaged window-mean errors at the table
    horizons."""
    windows = protocol.select(load(data, subjects), "dense", every)
    tangent = forecast_batch(windows.history, [0.04, 0.08], ForecasterConfig(extrapolation="linear"))
    slope = (tangent[:, 1] - tangent[:, 0]) / 0.04
    value = tangent[:, 0] - 0.04 * slope
    tau = np.arange(1, protocol.FUTURE + 1) / 25.0
    actions = list(dict.fromkeys(windows.action))
    best: dict[str, tuple[float, list[float]]] = {}
    for quantity, components in COMPONENTS.items():
        scores = []
        for t in grid:
            forecast = np.repeat(value[:, None, :], len(tau), axis=1)
            for c in components:
                forecast[:, :, c] += slope[:, None, c] * carry(t, tau)[None, :]
            errors = metrics.step_errors(forecast, windows.future).of(quantity)
            per_horizon = [
                float(np.mean([metrics.window_mean(errors[windows.action == a], h).mean() for a in actions]))
                for h in metrics.HORIZONS
            ]
            scores.append((sum(per_horizon), t, per_horizon))
        _, t, per_horizon = min(scores, key=lambda s: s[0])
        best[quantity] = (t, per_horizon)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", required=True, help="Human3.6M folder with S1/")
    parser.add_argument("--subjects", default="1")
    args = parser.parse_args()
    for quantity, (t, errors) in select(args.data, [int(s) for s in args.subjects.split(",")]).items():
        print(f"{quantity}: T = {t} s, window-mean errors at 0.4/1/2 s: {np.round(errors, 2).tolist()}")


if __name__ == "__main__":
    main()
