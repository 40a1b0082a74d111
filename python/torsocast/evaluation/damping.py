"""Selection of the damped trend's time constants on a training subject (Human3.6M S1).

For every ``T`` of a grid, the default forecaster (N = 1 fit continued as
``d0 + d1 · T (1 - e^(-τ/T))``) runs with that ``T`` on every component; each quantity (position,
azimuth, elevation) then takes the ``T`` with the smallest sum of its window-mean errors at 0.4, 1
and 2 s, averaged over actions as the report does. The defaults of ``torso_core``
(``Extrapolation::DAMPED_H36M_S1``) are what this prints for S1:

    python -m torsocast.evaluation.damping --data ../shared/data/h36m
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .._core import ForecasterConfig, forecast_batch
from ..datasets.h36m import RATE_HZ
from . import metrics, protocol
from .h36m import average, load, summarise

GRID = (0.0, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, float("inf"))


def select(
    data: str | Path, subjects: Sequence[int] = (1,), every: int = 10, grid: Sequence[float] = GRID
) -> dict[str, tuple[float, list[float]]]:
    """Best time constant per quantity, with its action-averaged window-mean errors at the table
    horizons."""
    windows = protocol.select(load(data, subjects)[0], "dense", every)
    horizons = list(np.arange(1, protocol.FUTURE + 1) / RATE_HZ)
    actions = list(dict.fromkeys(windows.action))
    scores: dict[str, list[tuple[float, float, list[float]]]] = {q: [] for q in metrics.QUANTITIES}
    for t in grid:
        config = ForecasterConfig(extrapolation="damped", damping=[t] * 5)
        errors = metrics.step_errors(forecast_batch(windows.history, horizons, config), windows.future)
        overall = average([summarise(errors, windows.action == a) for a in actions])
        for quantity, score in scores.items():
            per_horizon = [overall[quantity]["mean"][str(h)] for h in metrics.HORIZONS]
            score.append((sum(per_horizon), t, per_horizon))
    return {q: min(score, key=lambda s: s[0])[1:] for q, score in scores.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", required=True, help="Human3.6M folder with S1/")
    parser.add_argument("--subjects", default="1")
    args = parser.parse_args()
    for quantity, (t, errors) in select(args.data, [int(s) for s in args.subjects.split(",")]).items():
        print(f"{quantity}: T = {t} s, window-mean errors at 0.4/1/2 s: {np.round(errors, 2).tolist()}")


if __name__ == "__main__":
    main()
