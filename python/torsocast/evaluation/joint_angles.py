"""The motion-prediction literature's own measure of a whole-body forecast, to check the HMP
baseline against the paper it comes from: on each action's 8 seeded windows, the Euclidean
distance between the forecast's and the truth's joint angles as Euler angles (the root's
translation and rotation left out), averaged over the windows, at 80, 160, 320 and 400 ms
(Martinez et al. 2017, table 1; its reference code's ``translate.py`` and ``baselines.py``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from ..datasets import h36m
from ..datasets.kinematics import expmap_to_rotmat, rotmat_to_euler
from . import hmp, protocol

F64 = npt.NDArray[np.float64]

MILLISECONDS = (80, 160, 320, 400)
#: The forecast steps (from 0, 40 ms apart) of :data:`MILLISECONDS`.
STEPS = (1, 3, 7, 9)
#: A channel that moves less than this over a window is left out of its error (the reference
#: code's rule: the channels of joints that never move, and the root's, zeroed first).
STILL = 1e-4


def euler(frames: F64) -> F64:
    """``(n, 99)`` frames with every joint's exponential map as Euler angles and the root's six
    channels at zero."""
    out = np.array(frames, dtype=np.float64)
    n = len(out)
    out[:, 3:] = rotmat_to_euler(expmap_to_rotmat(out[:, 3:].reshape(n, 32, 3))).reshape(n, 96)
    out[:, :6] = 0.0
    return out


def window_error(truth: F64, forecast: F64, moving: F64) -> F64:
    """Per step, the distance between the Euler angles of ``truth`` and ``forecast`` over the
    channels that move in ``moving`` (the reference code takes the truth's for its baselines and
    the forecast's for its network)."""
    used = np.flatnonzero(np.std(moving, axis=0) > STILL)
    return np.sqrt(((truth[:, used] - forecast[:, used]) ** 2).sum(axis=1))


def evaluate(sequences: Sequence[h36m.Sequence], model: hmp.Model) -> dict[str, dict[str, list[float]]]:
    """For each action of ``sequences`` with both subactions, zero velocity's and ``model``'s
    errors at :data:`MILLISECONDS` over its seeded windows (:func:`.protocol.select`'s
    ``"seeds"``, the frames each sequence keeps)."""
    windows = protocol.select(list(sequences), "seeds")
    by_name = {s.name: s for s in sequences}
    steps = STEPS[-1] + 1
    out: dict[str, dict[str, list[float]]] = {}
    for action in dict.fromkeys(windows.action):
        picks = np.flatnonzero(windows.action == action)
        frames = [by_name[windows.sequence[i]].frames for i in picks]
        starts = [int(windows.start[i]) for i in picks]
        history = np.stack([f[start - protocol.HISTORY : start] for f, start in zip(frames, starts)])
        forecasts = model.forecast(history, str(action), steps)
        held, learned = [], []
        for f, start, seen, forecast in zip(frames, starts, history, forecasts):
            truth = euler(f[start : start + steps])
            last = euler(np.repeat(seen[-1:], steps, axis=0))
            held.append(window_error(truth, last, truth))
            predicted = euler(forecast)
            learned.append(window_error(truth, predicted, predicted))
        out[str(action)] = {
            "zero_velocity": [float(v) for v in np.mean(held, axis=0)[list(STEPS)]],
            "hmp": [float(v) for v in np.mean(learned, axis=0)[list(STEPS)]],
        }
    return out
