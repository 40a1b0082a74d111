"""Forecasting evaluation on Human3.6M: every method on the same windows, summarised per action,
per thesis category and overall.

Aggregation: an action's figure is the mean over its windows; a category's (and "All") is the mean
of its actions' figures, as the thesis' "All (average)" rows are; "pooled" is the mean over every
window, which weights actions by their length.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._core import ForecasterConfig, forecast_batch
from ..datasets import h36m
from . import hmp, joint_angles, metrics, protocol
from .methods import HMP_LABEL, LABELS, describe, method_configs

#: Forecast steps 1..50 of 40 ms: the per-step curve from 40 ms to 2 s.
STEPS = protocol.FUTURE

Progress = Callable[[str], None]


def load(
    data: str | Path,
    subjects: Sequence[int],
    progress: Progress | None = None,
    torso_joints: Mapping[int, str] = h36m.TORSO_JOINTS,
    gravity_rule: str = "auto",
) -> tuple[list[h36m.Sequence], list[str]]:
    """Every available file of the subjects as a pose series (plane joints and gravity rule as
    :func:`torsocast.datasets.h36m.load_sequence` takes them), and a line for each file left out
    because it cannot be read or fails the gravity check (a take whose up axis cannot be found is
    said and skipped, not fatal)."""
    pairs = [(s, a, sub) for s in subjects for a, sub in h36m.available(data, s)]
    if not pairs:
        raise FileNotFoundError(f"no Human3.6M files for subjects {list(subjects)} under {data}")
    sequences, left_out = [], []
    for subject, action, sub in pairs:
        name = f"S{subject}/{action}_{sub}"
        try:
            sequences.append(h36m.load_sequence(data, subject, action, sub, torso_joints, gravity_rule))
        except ValueError as e:
            left_out.append(f"{name}: {e}")
        if progress:
            progress(name)
    if not sequences:
        raise ValueError(f"no readable Human3.6M file for subjects {list(subjects)}: " + "; ".join(left_out))
    return sequences, left_out


def summarise(errors: metrics.StepErrors, mask: np.ndarray) -> dict[str, Any]:
    """Window-mean and end-of-window errors at the table horizons, and the per-step curve."""
    out: dict[str, Any] = {}
    for quantity in metrics.QUANTITIES:
        e = errors.of(quantity)[mask]
        out[quantity] = {
            "mean": {str(h): float(metrics.window_mean(e, h).mean()) for h in metrics.HORIZONS},
            "end": {str(h): float(metrics.window_end(e, h).mean()) for h in metrics.HORIZONS},
            "curve": [float(v) for v in e.mean(axis=0)],
        }
    return out


def average(summaries: list[dict[str, Any]]) -> dict[str, Any]:
    """Element-wise mean of several :func:`summarise` results (a category from its actions)."""
    first = summaries[0]
    if isinstance(first, dict):
        return {k: average([s[k] for s in summaries]) for k in first}
    if isinstance(first, list):
        return [float(v) for v in np.mean(summaries, axis=0)]  # type: ignore[return-value]
    return float(np.mean(summaries))  # type: ignore[return-value]


def groups(actions: Sequence[str]) -> dict[str, list[str]]:
    """The categories (and "All") over the actions that have windows."""
    present = [a for a in h36m.ACTIONS if a in set(actions)]
    out = {name: [a for a in members if a in present] for name, members in h36m.CATEGORIES.items()}
    out["All"] = present
    return {name: members for name, members in out.items() if members}


#: Windows forecast by the HMP model at once (its states are batch x units floats).
HMP_BATCH = 256


def hmp_forecasts(
    model: hmp.Model,
    sequences: Sequence[h36m.Sequence],
    windows: protocol.Windows,
    torso_joints: Mapping[int, str] = h36m.TORSO_JOINTS,
) -> tuple[np.ndarray, int]:
    """The HMP model's ``(n, 50, 5)`` torso poses for each window: it forecasts the whole body from
    the window's 50 frames, and the poses are made from its frames as the truth's are. A step
    whose forecast body gives no torso plane, or none whose side can be told, carries the step
    before (the last observed pose for the first); their count comes second."""
    by_name = {s.name: s for s in sequences}
    out = np.empty((len(windows), STEPS, 5))
    for action in dict.fromkeys(windows.action):
        members = np.flatnonzero(windows.action == action)
        for chunk in np.array_split(members, -(-len(members) // HMP_BATCH)):
            picks = [(by_name[windows.sequence[i]], int(windows.start[i])) for i in chunk]
            history = np.stack([seq.frames[start - protocol.HISTORY : start] for seq, start in picks])
            frames = model.forecast(history, str(action), STEPS)
            for i, (seq, start), forecast in zip(chunk, picks, frames):
                out[i] = h36m.forecast_poses(seq, start, forecast, torso_joints)
    carried = 0
    for step in range(STEPS):
        missing = ~np.isfinite(out[:, step]).all(axis=1)
        carried += int(missing.sum())
        out[missing, step] = out[missing, step - 1] if step else windows.history[missing, -1]
    return out, carried


def evaluate(
    data: str | Path,
    subjects: Sequence[int] = (5,),
    protocol_name: str = "dense",
    every: int = 10,
    methods: Mapping[str, ForecasterConfig] | None = None,
    progress: Progress | None = None,
    torso_joints: Mapping[int, str] = h36m.TORSO_JOINTS,
    gravity_rule: str = "auto",
    hmp_model: hmp.Model | None = None,
) -> dict[str, Any]:
    """Runs every method on the protocol's windows and returns the report as plain data (the JSON
    output holds exactly this). With ``hmp_model``, the HMP baseline too, which must not have
    been trained on a subject the evaluation tests."""
    methods = dict(methods) if methods is not None else method_configs()
    if hmp_model is not None:
        seen = sorted(set(hmp_model.subjects) & set(subjects))
        if seen:
            raise ValueError(
                f"the HMP model was trained on subject(s) {seen}, which this evaluation tests on"
            )
    sequences, left_out = load(data, subjects, progress, torso_joints, gravity_rule)
    windows = protocol.select(sequences, protocol_name, every)
    if len(windows) == 0:
        raise ValueError(f"protocol {protocol_name!r} found no windows in {len(sequences)} sequences")
    horizons = list(np.arange(1, STEPS + 1) / h36m.RATE_HZ)
    action_names = [a for a in h36m.ACTIONS if a in set(windows.action)]
    category_members = groups(action_names)
    hmp_poses, carried = (
        hmp_forecasts(hmp_model, sequences, windows, torso_joints) if hmp_model is not None else (None, 0)
    )

    def forecasts() -> Iterator[tuple[str, np.ndarray]]:
        for name, config in methods.items():
            yield name, forecast_batch(windows.history, horizons, config)
        if hmp_poses is not None:
            yield "hmp", hmp_poses

    results: dict[str, Any] = {}
    for name, forecast in forecasts():
        errors = metrics.step_errors(forecast, windows.future)
        per_action = {a: summarise(errors, windows.action == a) for a in action_names}
        results[name] = {
            "actions": per_action,
            "categories": {
                c: average([per_action[a] for a in members]) for c, members in category_members.items()
            },
            "pooled": summarise(errors, np.ones(len(windows), dtype=bool)),
        }
        if progress:
            progress(f"method {name}")
    described: dict[str, dict[str, Any]] = {
        name: {"label": LABELS.get(name, name), "config": describe(c)} for name, c in methods.items()
    }
    if hmp_model is not None:
        described["hmp"] = {
            "label": HMP_LABEL,
            "config": hmp_model.describe(),
            "steps_without_plane": carried,
            # The paper's own measure, to check the model against it.
            "joint_angles": joint_angles.evaluate(sequences, hmp_model),
        }
    return {
        "dataset": "Human3.6M (exponential-map files)",
        "data": str(data),
        "subjects": list(subjects),
        "protocol": protocol_name,
        "every": every if protocol_name == "dense" else None,
        "rate_hz": h36m.RATE_HZ,
        "history_steps": protocol.HISTORY,
        "horizons_steps": list(metrics.HORIZONS),
        "units": metrics.UNITS,
        "windows": {
            "total": len(windows),
            "skipped": windows.skipped,
            "per_action": {a: int((windows.action == a).sum()) for a in action_names},
        },
        "categories": category_members,
        "torso_joints": {str(j): side for j, side in torso_joints.items()},
        "left_out": left_out,
        "sequences": [
            {
                "name": s.name,
                "frames_25hz": len(s.poses),
                "gravity_rule": s.gravity.rule,
                "gravity_tilt_deg": s.gravity.tilt_deg,
                "floor_spine_angle_deg": s.gravity.floor_spine_angle_deg,
            }
            for s in sequences
        ],
        "methods": described,
        "results": results,
    }
