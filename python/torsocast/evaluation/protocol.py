"""Which windows of a pose series are forecast: the literature's 8 seeded windows per action, or
dense windows (every k-th start of every file).

A window is 50 samples of history (2 s at 25 Hz) followed by up to 50 samples of future; its
``start`` is the index of the first future sample, so the last observed sample is ``start - 1``.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..datasets.h36m import Sequence

HISTORY = 50
FUTURE = 50
#: Seed of ``find_indices_srnn`` (Martinez et al. 2017), drawn afresh for every action.
SRNN_SEED = 1234567890
SRNN_WINDOWS = 8


def srnn_starts(length_1: int, length_2: int) -> list[tuple[int, int]]:
    """The 8 seeded windows of an action as ``(subaction, start)``, from the 25 Hz lengths of its
    two subactions: ``RandomState(1234567890)`` draws ``randint(16, T - 150)`` alternately for
    subactions 1 and 2, and the future starts 50 samples after the draw."""
    rng = np.random.RandomState(SRNN_SEED)
    starts = []
    for i in range(SRNN_WINDOWS):
        sub, length = (1, length_1) if i % 2 == 0 else (2, length_2)
        starts.append((sub, int(rng.randint(16, length - 150)) + HISTORY))
    return starts


def dense_starts(length: int, every: int, history: int = HISTORY, future: int = FUTURE) -> range:
    """Every ``every``-th start with a full history and a full future inside the series."""
    if every < 1:
        raise ValueError(f"every must be a positive number of samples, got {every}")
    return range(history, length - future + 1, every)


@dataclass(frozen=True)
class Windows:
    """Windows cut from several sequences, stacked for :func:`torsocast.forecast_batch`."""

    history: npt.NDArray[np.float64]
    """``(n, 50, 5)`` poses before each start."""
    future: npt.NDArray[np.float64]
    """``(n, 50, 5)`` ground truth from each start on."""
    action: npt.NDArray[np.str_]
    sequence: npt.NDArray[np.str_]
    start: npt.NDArray[np.int64]
    skipped: int
    """Windows left out because a pose in them could not be computed (reported, never hidden)."""

    def __len__(self) -> int:
        return len(self.start)


def cut_windows(picks: Iterable[tuple[Sequence, int]]) -> Windows:
    """Cuts the window starting at ``start`` from each ``(sequence, start)``."""
    history, future, action, name, starts, skipped = [], [], [], [], [], 0
    for seq, start in picks:
        window = seq.poses[start - HISTORY : start + FUTURE]
        if len(window) != HISTORY + FUTURE or start < HISTORY:
            raise ValueError(f"{seq.name}: window at {start} leaves the sequence of {len(seq.poses)}")
        if not np.isfinite(window).all():
            skipped += 1
            continue
        history.append(window[:HISTORY])
        future.append(window[HISTORY:])
        action.append(seq.action)
        name.append(seq.name)
        starts.append(start)
    empty = np.empty((0, HISTORY, 5))
    return Windows(
        history=np.array(history) if history else empty,
        future=np.array(future) if future else empty,
        action=np.array(action, dtype=str),
        sequence=np.array(name, dtype=str),
        start=np.array(starts, dtype=np.int64),
        skipped=skipped,
    )


def select(sequences: list[Sequence], protocol: str, every: int = 10) -> Windows:
    """The windows of a protocol: ``"seeds"`` (8 per action with both subactions present) or
    ``"dense"`` (every ``every``-th start of every sequence)."""
    if protocol == "dense":
        return cut_windows((seq, s) for seq in sequences for s in dense_starts(len(seq.poses), every))
    if protocol == "seeds":
        by_key = {(seq.subject, seq.action, seq.subaction): seq for seq in sequences}
        picks = []
        for subject, action in dict.fromkeys((seq.subject, seq.action) for seq in sequences):
            first, second = by_key.get((subject, action, 1)), by_key.get((subject, action, 2))
            if first is None or second is None:
                continue
            for sub, start in srnn_starts(len(first.poses), len(second.poses)):
                picks.append((first if sub == 1 else second, start))
        return cut_windows(picks)
    raise ValueError(f"protocol must be 'seeds' or 'dense', got {protocol!r}")
