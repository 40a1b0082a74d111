"""Two runs of the scenes benchmark on the same scenes, compared.

A change to the tracking code moves the flip rate by a few tenths of a point, which is less than
the spread of the split's draw of scenes. Both runs saw the same scenes, so the question is
paired: drawing the scenes again with replacement, the same draw for both runs, how far does the
difference of their flip rates move? ``torsocast eval compare BEFORE AFTER`` reads the
``recovery.csv`` of each run's output folder, and where both have one their ``forecasts.csv``:
the change of each motion category's and view bin's median forecast error per component and
horizon, with its interval over the same draws, and where both recorded their forecast
intervals, how many motion category cells each run's intervals hold calibrated; and where both
have an ``unseen.csv``, the change of the median error of the poses reported for tracks kept
unseen, by how long they went unseen. Pairs of runs on
other scenes (another ``--seed``) can be pooled with the first (``--also BEFORE AFTER``): the
draws then take scenes from all of them. A replay with sensor faults scores fewer frames than
one without; ``--common`` compares each pair on the person-frames both runs hold
(:func:`common`).
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from .score import COMPONENTS, FLIP_DEG, FLIP_SOURCES, POSE_COMPONENTS
from .tables import (
    CALIBRATED,
    CHECKED_AXES,
    INTERVAL,
    SCALE,
    TILTED_DEG,
    Columns,
    central,
    coverage_cells,
    coverage_table,
    covered,
    groups,
    scene_draws,
    scene_percentile_draws,
)

#: The rows of the two runs must describe the same person-frames.
KEYS = ("scene", "t", "actor")


def _records(path: Path, needed: tuple[str, ...]) -> list[dict[str, str]]:
    """The rows of a benchmark record ``path``, refused without one of the ``needed`` columns."""
    with path.open(newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise ValueError(f"{path}: no records")
    missing = [k for k in needed if k not in rows[0]]
    if missing:
        raise ValueError(f"{path}: not a scenes benchmark record (no {', '.join(missing)} column)")
    return rows


def read(folder: str | Path) -> Columns:
    """A run's ``recovery.csv`` as columns."""
    rows = _records(Path(folder) / "recovery.csv", (*KEYS, "estimated", "azimuth"))
    return {k: np.array([r[k] for r in rows]) for k in rows[0]}


def common(before: Columns, after: Columns) -> tuple[Columns, Columns]:
    """Both runs' records of the person-frames both of them hold, in each run's order: a replay
    with sensor faults (``--drop``, ``--stall``) scores only the frames it gave the tracker, and
    against a replay without them it compares on those. Refuses runs that share none."""

    keys = [list(zip(*(cols[k] for k in KEYS))) for cols in (before, after)]
    shared = set(keys[0]) & set(keys[1])
    if not shared:
        raise ValueError("the runs share no person-frame (scene, time and person)")
    kept = [_rows(cols, np.array([k in shared for k in mine])) for cols, mine in zip((before, after), keys)]
    return kept[0], kept[1]


def within(cols: Columns, scenes: np.ndarray) -> Columns:
    """The records of ``cols`` of the given scenes: with :func:`common`, a scene whose people
    were in view only while a replay's camera stalled has no person-frame left to compare, and
    its forecasts go with it."""
    return _rows(cols, np.isin(cols["scene"], scenes))


def _rows(cols: Columns, keep: np.ndarray) -> Columns:
    """The rows of ``cols`` that ``keep`` marks, every column alike."""
    return {name: values[keep] for name, values in cols.items()}


def pool(runs: list[Columns]) -> Columns:
    """The records of runs on different scenes (draws of other seeds) as one: the columns all
    of them hold, end to end. Refuses runs that share a scene (it would count twice)."""
    seen: set[str] = set()
    for cols in runs:
        names = set(np.unique(cols["scene"]).tolist())
        if names & seen:
            raise ValueError(f"the pooled runs share scenes ({sorted(names & seen)[0]} and others)")
        seen |= names
    keys = [k for k in runs[0] if all(k in cols for cols in runs[1:])]
    return {k: np.concatenate([cols[k] for cols in runs]) for k in keys}


#: The columns of ``forecasts.csv`` a comparison reads: two labels, then numbers.
FORECAST_COLUMNS = (
    "scene",
    "category",
    "view",
    "horizon",
    *(f"{m}_{c}" for m in ("forecast", "hold") for c in COMPONENTS),
)


#: The columns of ``forecasts.csv`` that hold each forecast's miss and interval, where it has them.
INTERVAL_COLUMNS = tuple(f"{m}_{a}" for a in POSE_COMPONENTS for m in ("miss", "half_width"))


def read_forecasts(folder: str | Path) -> Columns | None:
    """A run's ``forecasts.csv`` as columns (errors, horizons, misses and interval half-widths as
    numbers; the last two where the record has them); None without one."""
    path = Path(folder) / "forecasts.csv"
    if not path.is_file():
        return None
    rows = _records(path, FORECAST_COLUMNS)
    cols = {k: np.array([r[k] for r in rows]) for k in FORECAST_COLUMNS[:2]}
    numbers = [*FORECAST_COLUMNS[2:], *(k for k in INTERVAL_COLUMNS if k in rows[0])]
    for k in numbers:
        cols[k] = np.array([float(r[k]) for r in rows])
    return cols


#: The columns of ``unseen.csv`` a comparison reads: the scene, then numbers.
UNSEEN_COLUMNS = ("scene", "unseen_for", *(f"{m}_{c}" for m in ("forecast", "hold") for c in COMPONENTS))


def read_unseen(folder: str | Path) -> Columns | None:
    """A run's ``unseen.csv`` (the tracks kept unseen, each frame) as columns, empty where no
    track went unseen; None without one (a run of code that did not report them)."""
    path = Path(folder) / "unseen.csv"
    if not path.is_file():
        return None
    with path.open(newline="") as f:
        if not next(csv.reader(f), None):  # no header: the run had no unseen track to write
            return {k: np.array([], dtype=float if k != "scene" else str) for k in UNSEEN_COLUMNS}
    rows = _records(path, UNSEEN_COLUMNS)
    cols = {"scene": np.array([r["scene"] for r in rows])}
    for k in UNSEEN_COLUMNS[1:]:
        cols[k] = np.array([float(r[k]) for r in rows])
    return cols


def compare_coverage(pairs: list[tuple[Columns, Columns]]) -> dict[str, Any] | None:
    """Per run, its forecast intervals' calibration by motion category: the cells (category x
    horizon x component) whose intervals held the truth within :data:`~.tables.CALIBRATED`, and
    their mean distance from its middle (:func:`~.tables.coverage_cells`), each pair of runs
    (one draw of scenes) counted on its own and the pairs' counts added; and the share of the
    truth inside the intervals per pose component over every pair. None unless every run
    recorded its intervals."""
    if not all(k in cols for pair in pairs for cols in pair for k in INTERVAL_COLUMNS):
        return None
    out: dict[str, Any] = {}
    for side, name in enumerate(("before", "after")):
        counts = [coverage_cells(coverage_table(pair[side], "category")) for pair in pairs]
        cells = sum(c["cells"] for c in counts)
        distance = sum(c["distance"] * c["cells"] for c in counts) / cells if cells else float("nan")
        every = pool([pair[side] for pair in pairs])
        given = {axis: np.isfinite(every[f"half_width_{axis}"]) for axis in POSE_COMPONENTS}
        inside = {
            axis: covered(every, axis, given[axis]) if given[axis].any() else float("nan")
            for axis in POSE_COMPONENTS
        }
        out[name] = {
            "inside": [c["inside"] for c in counts],
            "cells": cells,
            "distance": distance,
            "components": inside,
        }
    return out


def coverage_markdown(result: dict[str, Any]) -> str:
    """The interval comparison in two lines: the calibrated cells and the share per component."""
    low, high = (f"{100 * b:g}" for b in CALIBRATED)
    counts = []
    for name in ("before", "after"):
        r = result[name]
        each = f" ({' + '.join(str(n) for n in r['inside'])})" if len(r["inside"]) > 1 else ""
        counts.append(f"{sum(r['inside'])} of {r['cells']}{each}")
    distances = " -> ".join(f"{100 * result[n]['distance']:.2f}" for n in ("before", "after"))
    shares = "; ".join(
        f"{axis} {100 * result['before']['components'][axis]:.1f} -> "
        f"{100 * result['after']['components'][axis]:.1f} %"
        for axis in POSE_COMPONENTS
    )
    return (
        f"Forecast interval cells (motion category x horizon x component) within {low} to {high} %: "
        f"{counts[0]} before, {counts[1]} after; mean distance from 80 %: {distances} points.\n"
        f"The truth inside the 80 % intervals: {shares}."
    )


def _flips(cols: Columns) -> tuple[np.ndarray, np.ndarray]:
    """Per person-frame: whether it had an estimate, and whether that estimate was flipped."""
    estimated = cols["estimated"] == "True"
    azimuth = np.degrees(np.where(estimated, cols["azimuth"].astype(float), 0.0))
    return estimated, estimated & (azimuth > FLIP_DEG)


def compare(before: Columns, after: Columns) -> dict[str, Any]:
    """Per measure, both runs' values, their difference and its paired interval: the flip rate
    over the estimates, over the headings each run calls confident (where both recorded it),
    over the estimates of a torso leaning :data:`~.tables.TILTED_DEG` or more from upright
    (where both recorded the tilt),
    the share of the estimates flipped from each of :data:`~.score.FLIP_SOURCES` (where both
    recorded them), and the azimuth error's median and 90th percentile (degrees); the count of
    flipped estimates in each run (``flipped``) and the people whose count changed most
    (``people``, :func:`changed_people`). Refuses runs of different person-frames."""
    for key in KEYS:
        if len(before[key]) != len(after[key]) or (before[key] != after[key]).any():
            raise ValueError(f"the runs are of different scenes or frames (their {key!r} columns differ)")
    names, index = np.unique(before["scene"], return_inverse=True)
    out: dict[str, Any] = {"scenes": len(names)}

    def record(name: str, values: list[float], draws: list[np.ndarray]) -> None:
        low, high = central(draws[1] - draws[0])
        out[name] = {"before": values[0], "after": values[1], "change": values[1] - values[0]}
        out[name]["low"], out[name]["high"] = low, high

    runs = [(cols, *_flips(cols)) for cols in (before, after)]
    # Each measure's name, and which estimates it counts (None: all of them).
    measures: list[tuple[str, Callable[[Columns], np.ndarray] | None]] = [("flips", None)]
    if "confident" in before and "confident" in after:
        measures.append(("flips_confident", lambda cols: cols["confident"] == "True"))
    if "tilt" in before and "tilt" in after:
        measures.append(("flips_tilted", lambda cols: cols["tilt"].astype(float) >= TILTED_DEG))
    for name, pick in measures:
        rates, draws = [], []
        for cols, estimated, flipped in runs:
            counted = estimated if pick is None else estimated & pick(cols)
            rates.append(float(flipped[counted].mean()) if counted.any() else float("nan"))
            draws.append(scene_draws(index[counted], len(names), flipped[counted]))
        record(name, rates, draws)
    if "flip_source" in before and "flip_source" in after:
        for source in FLIP_SOURCES:
            rates, draws = [], []
            for cols, estimated, _ in runs:
                mine = (cols["flip_source"] == source)[estimated]
                rates.append(float(mine.mean()) if len(mine) else float("nan"))
                draws.append(scene_draws(index[estimated], len(names), mine))
            record(f"flips_{source}", rates, draws)
    out["flipped"] = [int(flipped.sum()) for _, _, flipped in runs]
    out["people"] = changed_people(before, runs[0][1], runs[0][2], runs[1][2])
    for name, q in (("azimuth_median", 50.0), ("azimuth_p90", 90.0)):
        values, draws = [], []
        for cols, estimated, _ in runs:
            error = np.degrees(cols["azimuth"][estimated].astype(float))
            values.append(float(np.percentile(error, q)) if len(error) else float("nan"))
            draws.append(scene_percentile_draws(index[estimated], len(names), error, q))
        record(name, values, draws)
    return out


def changed_people(
    cols: Columns, estimated: np.ndarray, before: np.ndarray, after: np.ndarray, most: int = 5
) -> list[dict[str, Any]]:
    """The people (scene and actor of the records ``cols``) whose count of flipped estimates
    changed most from ``before`` to ``after`` (per record: flipped or not), up to ``most`` of
    them, largest change first, each with its estimates in the first run: a change that moves
    the split's flips by a few tenths of a point may be one person's."""
    people, index = np.unique(
        np.char.add(np.char.add(cols["scene"], " actor "), cols["actor"]), return_inverse=True
    )
    count = [
        np.bincount(index, weights=w.astype(float), minlength=len(people)) for w in (estimated, before, after)
    ]
    change = count[2] - count[1]
    order = [i for i in np.argsort(-np.abs(change), kind="stable") if change[i] != 0][:most]
    return [
        {
            "person": str(people[i]),
            "estimates": int(count[0][i]),
            "before": int(count[1][i]),
            "after": int(count[2][i]),
        }
        for i in order
    ]


def _scene_indices(
    runs: tuple[Columns, Columns], scenes: np.ndarray, what: str
) -> tuple[np.ndarray, list[np.ndarray]]:
    """The scenes the draws are of (``scenes``, the runs' recovery records'), and each run's rows'
    index among them; a row of a scene not among them is refused."""
    names = np.unique(scenes)
    stray = sorted((set(runs[0]["scene"]) | set(runs[1]["scene"])) - set(names))
    if stray:
        raise ValueError(
            f"the runs' {what} are of scenes their recovery records do not hold: {', '.join(stray[:3])}"
        )
    return names, [np.searchsorted(names, cols["scene"]) for cols in runs]


def _median_change(
    runs: tuple[Columns, Columns],
    masks: list[np.ndarray],
    indices: list[np.ndarray],
    scenes: int,
    component: str,
) -> dict[str, float]:
    """Both runs' median error of ``component`` (in the report's units) over the rows ``masks``
    pick, the change, its paired interval over draws of the scenes (the same draws for both runs,
    each weighing its own rows of a drawn scene), and each run's median error of holding its own
    estimate still (``hold``, ``hold_after``)."""
    values, draws, holds = [], [], []
    for cols, index, m in zip(runs, indices, masks):
        error = SCALE[component] * cols[f"forecast_{component}"][m]
        values.append(float(np.median(error)))
        draws.append(scene_percentile_draws(index[m], scenes, error, 50.0))
        holds.append(float(np.median(SCALE[component] * cols[f"hold_{component}"][m])))
    low, high = central(draws[1] - draws[0])
    return {
        "before": values[0],
        "after": values[1],
        "change": values[1] - values[0],
        "low": low,
        "high": high,
        "hold": holds[0],
        "hold_after": holds[1],
    }


def compare_forecasts(before: Columns, after: Columns, scenes: np.ndarray) -> list[dict[str, Any]]:
    """Per motion category and per view bin (the axes the report checks against holding still),
    component and horizon: both runs' median forecast error and holding's, the change and its
    paired interval (:func:`_median_change`). A change to the forecaster alone leaves the
    forecasts' instants as they were; a change to the tracking may add or drop some, which the
    draws take as they come, down to every forecast of a scene (a track that is no longer
    confirmed). The draws are of ``scenes`` (the runs' recovery records'); a forecast of a scene
    not among them is refused."""
    names, indices = _scene_indices((before, after), scenes, "forecasts")
    out = []
    for axis in CHECKED_AXES:
        masks_after = dict(groups(after, axis))
        for group, in_before in groups(before, axis):
            for horizon in np.unique(before["horizon"]):
                masks = [in_before & (before["horizon"] == horizon)]
                masks.append(
                    masks_after.get(group, np.zeros(len(after["scene"]), bool))
                    & (after["horizon"] == horizon)
                )
                if not all(m.any() for m in masks):
                    continue
                for component in COMPONENTS:
                    change = _median_change((before, after), masks, indices, len(names), component)
                    cell = {"axis": axis, "group": group, "component": component, "horizon": float(horizon)}
                    out.append(cell | change)
    return out


def compare_unseen(before: Columns, after: Columns, scenes: np.ndarray) -> list[dict[str, Any]]:
    """Per band of time unseen, then over all, and per component: both runs' median error of the
    poses reported for tracks kept unseen, and of holding each track's last estimate, the change
    and its paired interval (:func:`_median_change`), with each run's count of track-frames
    (``n``, ``n_after``). Each run's tracking decides which tracks go unseen when, so the two
    runs' track-frames need not be the same ones. The draws are of ``scenes`` and of any other
    scene a run kept a track unseen in (one whose people the recovery records never held in view:
    out of the picture or hidden throughout)."""
    every = np.concatenate([scenes, before["scene"], after["scene"]])
    names, indices = _scene_indices((before, after), every, "unseen tracks")
    out = []
    for axis in ("unseen", None):
        masks_after = dict(groups(after, axis))
        for group, in_before in groups(before, axis):
            masks = [in_before, masks_after.get(group, np.zeros(len(after["scene"]), bool))]
            if not all(m.any() for m in masks):
                continue
            for component in COMPONENTS:
                change = _median_change((before, after), masks, indices, len(names), component)
                cell = {
                    "group": group,
                    "component": component,
                    "n": int(masks[0].sum()),
                    "n_after": int(masks[1].sum()),
                }
                out.append(cell | change)
    return out


def unseen_markdown(cells: list[dict[str, Any]]) -> str:
    """The unseen tracks' comparison as a Markdown table (holding still: each run's own), each
    change beyond the draw marked."""
    head = "| time unseen | component | track-frames before / after | hold before / after | before | after |"
    lines = [
        f"{head} change | its {100 * INTERVAL:g} % interval | beyond the draw |",
        "|---|---|---:|---:|---:|---:|---:|---:|---|",
    ]
    for c in cells:
        change, low, high = (f"{c[k]:+.1f}" for k in ("change", "low", "high"))
        lines.append(
            f"| {c['group']} | {c['component']} | {c['n']} / {c['n_after']} "
            f"| {c['hold']:.1f} / {c['hold_after']:.1f} | {c['before']:.1f} | {c['after']:.1f} "
            f"| {change} | {low} to {high} | {_verdict(c)} |"
        )
    return (
        "\n".join(lines)
        + "\n\nMedian errors of the poses reported for tracks kept unseen (centre cm, angles deg)."
    )


def _verdict(cell: dict[str, Any]) -> str:
    """Whether a change lies beyond the draw of scenes, and which way."""
    return "better" if cell["high"] < 0 else "worse" if cell["low"] > 0 else ""


def forecasts_markdown(cells: list[dict[str, Any]]) -> str:
    """The forecast comparison as a Markdown table (holding still: the first run's), each change
    beyond the draw marked (the interval is printed rounded, and a bound that rounds to zero does
    not say on which side of it it lies), with a count of those changes and of the cells where
    each run is worse than holding its own estimate still."""
    head = "| motion category or view | component | horizon | hold | before | after | change |"
    lines = [
        f"{head} its {100 * INTERVAL:g} % interval | beyond the draw |",
        "|---|---|---:|---:|---:|---:|---:|---:|---|",
    ]
    verdicts = [_verdict(c) for c in cells]
    for c, verdict in zip(cells, verdicts):
        numbers = (f"{c[k]:.1f}" for k in ("hold", "before", "after"))
        change, low, high = (f"{c[k]:+.1f}" for k in ("change", "low", "high"))
        lines.append(
            f"| {c['group'] if c['axis'] == 'category' else 'view ' + c['group']} | {c['component']} "
            f"| {c['horizon']:g} s | {' | '.join(numbers)} "
            f"| {change} | {low} to {high} | {verdict} |"
        )
    better, worse = verdicts.count("better"), verdicts.count("worse")
    lost = [sum(c[k] > c[h] for c in cells) for k, h in (("before", "hold"), ("after", "hold_after"))]
    return "\n".join(lines) + (
        f"\n\nMedian forecast errors (centre cm, angles deg): {better} of {len(cells)} cells better and "
        f"{worse} worse by more than the draw of scenes explains; worse than holding still in "
        f"{lost[0]} before, {lost[1]} after."
    )


def markdown(result: dict[str, Any]) -> str:
    """The comparison as a Markdown table, with a line saying what it means for the flips and
    one naming the people whose flips changed most."""
    # The records hold only the scenes with someone in view; a split's others are not counted.
    scenes = f"{result['scenes']} scenes with someone in view"
    head = f"| {scenes} | before | after | change | its {100 * INTERVAL:g} % interval |"
    lines = [head, "|---|---:|---:|---:|---:|"]
    rows = (
        ("flips", "flips (%)", 100.0),
        ("flips_confident", "flips where confident (%)", 100.0),
        ("flips_tilted", f"flips where the torso leans {TILTED_DEG:g} degrees or more (%)", 100.0),
        *((f"flips_{s}", f"flips: {s} (% of estimates)", 100.0) for s in FLIP_SOURCES),
        ("azimuth_median", "azimuth error median (deg)", 1.0),
        ("azimuth_p90", "azimuth error 90th percentile (deg)", 1.0),
    )
    for name, label, scale in rows:
        if name not in result:
            continue
        r = result[name]
        before, after = (f"{scale * r[k]:.2f}" for k in ("before", "after"))
        change, low, high = (f"{scale * r[k]:+.2f}" for k in ("change", "low", "high"))
        lines.append(f"| {label} | {before} | {after} | {change} | {low} to {high} |")
    r = result["flips"]
    verdict = (
        "the change in flips is larger than the draw of scenes explains"
        if r["low"] > 0 or r["high"] < 0
        else "the change in flips is within what the draw of scenes explains"
    )
    before, after = result["flipped"]
    people = ", ".join(
        f"{p['person']} ({p['before']} -> {p['after']} of {p['estimates']})" for p in result["people"]
    )
    most = f"; changed most for {people}" if people else ""
    return "\n".join(lines) + f"\n\n{verdict}.\n\nFlipped estimates: {before} -> {after}{most}."
