"""Two runs of the scenes benchmark on the same scenes, compared.

A change to the tracking code moves the flip rate by a few tenths of a point, which is less than
the spread of the split's draw of scenes. Both runs saw the same scenes, so the question is
paired: drawing the scenes again with replacement, the same draw for both runs, how far does the
difference of their flip rates move? ``torsocast eval compare BEFORE AFTER`` reads the
``recovery.csv`` of each run's output folder.
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import Any

import numpy as np

from .tables import FLIP_DEG, INTERVAL, Columns, central, scene_draws

#: The rows of the two runs must describe the same person-frames.
KEYS = ("scene", "t", "actor")


def read(folder: str | Path) -> Columns:
    """A run's ``recovery.csv`` as columns."""
    path = Path(folder) / "recovery.csv"
    with path.open(newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no records")
    missing = [k for k in (*KEYS, "estimated", "azimuth") if k not in rows[0]]
    if missing:
        raise ValueError(f"{path}: not a scenes benchmark record (no {', '.join(missing)} column)")
    return {k: np.array([r[k] for r in rows]) for k in rows[0]}


def _flips(cols: Columns) -> tuple[np.ndarray, np.ndarray]:
    """Per person-frame: whether it had an estimate, and whether that estimate was flipped."""
    estimated = cols["estimated"] == "True"
    azimuth = np.degrees(np.where(estimated, cols["azimuth"].astype(float), 0.0))
    return estimated, estimated & (azimuth > FLIP_DEG)


def compare(before: Columns, after: Columns) -> dict[str, Any]:
    """Flip rates of both runs over their estimates, their difference and its paired interval;
    the same for the headings each calls confident, where both runs recorded it. Refuses runs of
    different person-frames."""
    for key in KEYS:
        if len(before[key]) != len(after[key]) or (before[key] != after[key]).any():
            raise ValueError(f"the runs are of different scenes or frames (their {key!r} columns differ)")
    out: dict[str, Any] = {"scenes": len(np.unique(before["scene"]))}
    scenes = before["scene"]
    measures = [("flips", None)]
    if "confident" in before and "confident" in after:
        measures.append(("flips_confident", "confident"))
    for name, pick in measures:
        rates, draws = [], []
        for cols in (before, after):
            estimated, flipped = _flips(cols)
            counted = estimated if pick is None else estimated & (cols[pick] == "True")
            rates.append(float(flipped[counted].mean()) if counted.any() else float("nan"))
            draws.append(scene_draws(scenes[counted], flipped[counted]))
        out[name] = {"before": rates[0], "after": rates[1], "change": rates[1] - rates[0]}
        out[name]["low"], out[name]["high"] = central(draws[1] - draws[0])
    return out


def markdown(result: dict[str, Any]) -> str:
    """The comparison as a Markdown table, with a line saying what it means."""
    head = f"| {result['scenes']} scenes | before | after | change | its {100 * INTERVAL:g} % interval |"
    lines = [head, "|---|---:|---:|---:|---:|"]
    for name, label in (("flips", "flips"), ("flips_confident", "flips where confident")):
        if name not in result:
            continue
        r = result[name]
        before, after = (f"{100 * r[k]:.2f} %" for k in ("before", "after"))
        change, low, high = (f"{100 * r[k]:+.2f}" for k in ("change", "low", "high"))
        lines.append(f"| {label} | {before} | {after} | {change} points | {low} to {high} |")
    r = result["flips"]
    verdict = (
        "the change in flips is larger than the draw of scenes explains"
        if r["low"] > 0 or r["high"] < 0
        else "the change in flips is within what the draw of scenes explains"
    )
    return "\n".join(lines) + f"\n\n{verdict}."
