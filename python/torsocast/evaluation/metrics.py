"""Forecast errors per window and step, and their summaries.

Angles are compared as angles: the azimuth error is the absolute difference wrapped into
[0, 180] degrees, so a forecast that has turned by a full circle is not penalised. Elevation is in
[0, 180] degrees by construction and compared directly. Position error is the Euclidean distance
between forecast and true torso centre.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .. import wrap_angle

F64 = npt.NDArray[np.float64]

#: Horizons of the thesis' tables, in 25 Hz steps: 400 ms, 1 s, 2 s.
HORIZONS = (10, 25, 50)
QUANTITIES = ("azimuth", "elevation", "position")
UNITS = {"azimuth": "deg", "elevation": "deg", "position": "cm"}


@dataclass(frozen=True)
class StepErrors:
    """``(windows, steps)`` errors of one method: degrees for the angles, centimetres for position."""

    azimuth: F64
    elevation: F64
    position: F64

    def of(self, quantity: str) -> F64:
        return {"azimuth": self.azimuth, "elevation": self.elevation, "position": self.position}[quantity]


def step_errors(forecast: F64, truth: F64) -> StepErrors:
    """Errors of ``(n, steps, 5)`` forecasts against the true poses at the same steps."""
    azimuth = np.abs(wrap_angle(forecast[..., 3] - truth[..., 3]))
    return StepErrors(
        azimuth=np.degrees(azimuth),
        elevation=np.degrees(np.abs(forecast[..., 4] - truth[..., 4])),
        position=100.0 * np.linalg.norm(forecast[..., :3] - truth[..., :3], axis=-1),
    )


def window_mean(errors: F64, horizon: int) -> F64:
    """Per window, the mean error over steps 1 to ``horizon`` (the thesis' figure)."""
    return errors[:, :horizon].mean(axis=1)


def window_end(errors: F64, horizon: int) -> F64:
    """Per window, the error at step ``horizon``."""
    return errors[:, horizon - 1]
