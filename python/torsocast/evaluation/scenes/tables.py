"""The benchmark's numbers: its records grouped by condition (view, distance, number of people,
motion category, frame rate; and the track's age and the torso's tilt) and reduced to the
tables of the report."""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any

import numpy as np

from .score import COMPONENTS, FLIP_DEG, FLIP_SOURCES, METHODS, YOUNG_FRAMES

Columns = dict[str, np.ndarray]
DISTANCE_EDGES = (1.0, 2.0, 3.0, 4.0)
#: The bins the edges make, nearest first.
DISTANCE_LABELS = ("under 1 m", "1-2 m", "2-3 m", "3-4 m", "4 m and more")
#: Conditions the tables are split by, in report order.
AXES = ("view", "distance", "people", "category", "fps")
#: Conditions whose every cell the forecast must not lose to holding still (issue's target).
CHECKED_AXES = ("category", "view")
#: Edges (s) of the bands of a track's age with its person a forecast is also given by: a young
#: track's forecast rests on a short history and few or no checks of its own (not a condition of
#: the scene, so no target's cell).
AGE_EDGES = (0.5, 1.0, 2.0)
AGE_LABELS = ("under 0.5 s", "0.5-1 s", "1-2 s", "2 s and more")
#: Edges (degrees) of the bands of how far the true torso leans from upright (`tilt`) the
#: records are also given by: the people who bend, crouch or lie are where the plane's azimuth
#: is least well conditioned (a condition of the person's pose, not of the scene: no target's
#: cell).
TILT_EDGES = (15.0, 30.0, 60.0)
TILT_LABELS = ("under 15 deg", "15-30 deg", "30-60 deg", "60 deg and more")
#: Edges (s) of the bands of how long a track had gone unseen when its pose was reported
#: (the forecast's horizons).
UNSEEN_EDGES = (0.4, 1.0)
UNSEEN_LABELS = ("under 0.4 s", "0.4-1 s", "1 s and more")
#: From this lean (degrees) on, a comparison gives the flips of a bent person's estimates apart.
TILTED_DEG = TILT_EDGES[1]
STATS: dict[str, Callable[[np.ndarray], float]] = {
    "median": lambda v: float(np.median(v)),
    "mean": lambda v: float(np.mean(v)),
    "p90": lambda v: float(np.percentile(v, 90)),
}
#: Resamples of the scenes behind a flip rate's interval (:func:`scene_interval`).
BOOTSTRAP = 1000
#: Central coverage of that interval.
INTERVAL = 0.9
#: Centre errors are reported in cm, angles in degrees.
SCALE = {"centre": 100.0, "azimuth": float(np.degrees(1.0)), "elevation": float(np.degrees(1.0))}
UNIT = {"centre": "cm", "azimuth": "deg", "elevation": "deg"}
#: The share of the truth an 80 % forecast interval must hold in every motion category, horizon
#: and component to count as calibrated (the issue's target).
CALIBRATED = (0.75, 0.85)
#: Edges (s) of the bands of a track's facing evidence (`facing_evidence`: seconds of the
#: labels' agreement) the flip rate is given by. The labels alone build about a second's worth
#: (the side decision's memory); more has been confirmed by another cue.
EVIDENCE_EDGES = (0.25, 0.5, 1.0, 2.0)


def view_bin(degrees: np.ndarray) -> np.ndarray:
    """45-degree bins by their centre: 0 is facing the camera, 180 turned away."""
    centre = (np.floor((np.asarray(degrees) + 22.5) / 45.0) * 45.0).astype(int)
    return np.where(centre <= -180, centre + 360, centre)  # type: ignore[no-any-return]


def distance_bin(metres: np.ndarray) -> np.ndarray:
    bins = np.searchsorted(DISTANCE_EDGES, metres, side="right")
    return np.asarray(DISTANCE_LABELS, dtype=object)[bins]  # type: ignore[no-any-return]


def age_bin(seconds: np.ndarray) -> np.ndarray:
    bins = np.searchsorted(AGE_EDGES, seconds, side="right")
    return np.asarray(AGE_LABELS, dtype=object)[bins]  # type: ignore[no-any-return]


def unseen_bin(seconds: np.ndarray) -> np.ndarray:
    bins = np.searchsorted(UNSEEN_EDGES, seconds, side="right")
    return np.asarray(UNSEEN_LABELS, dtype=object)[bins]  # type: ignore[no-any-return]


def tilt_bin(degrees: np.ndarray) -> np.ndarray:
    bins = np.searchsorted(TILT_EDGES, degrees, side="right")
    return np.asarray(TILT_LABELS, dtype=object)[bins]  # type: ignore[no-any-return]


def condition(cols: Columns, axis: str) -> np.ndarray:
    if axis == "view":
        return view_bin(cols["view"])
    if axis == "distance":
        return distance_bin(cols["distance"])
    if axis == "age":
        return age_bin(cols["track_age"])
    if axis == "tilt":
        return tilt_bin(cols["tilt"])
    if axis == "unseen":
        return unseen_bin(cols["unseen_for"])
    return cols[axis]


def _order(axis: str, values: np.ndarray) -> list[Any]:
    unique = list(dict.fromkeys(values.tolist()))
    if axis == "view":
        return sorted(unique, key=lambda v: (v < 0, abs(v)))  # 0, 45, 90, 135, 180, -135 ...
    if axis == "distance":
        return [v for v in DISTANCE_LABELS if v in unique]
    if axis == "age":
        return [v for v in AGE_LABELS if v in unique]
    if axis == "tilt":
        return [v for v in TILT_LABELS if v in unique]
    if axis == "unseen":
        return [v for v in UNSEEN_LABELS if v in unique]
    return sorted(unique)


def groups(cols: Columns, axis: str | None) -> list[tuple[str, np.ndarray]]:
    """(label, row mask) per value of ``axis``; one group "all" for None."""
    n = len(next(iter(cols.values()))) if cols else 0
    if axis is None:
        return [("all", np.ones(n, dtype=bool))]
    values = condition(cols, axis)
    return [(str(v), values == v) for v in _order(axis, values)]


@functools.lru_cache(maxsize=8)
def _draws(scenes: int, seed: int) -> np.ndarray:
    """(:data:`BOOTSTRAP`, scenes) counts: how many times each scene is in each draw of
    ``scenes`` scenes with replacement. The same ``seed`` and count give the same draws, so two
    runs over the same scenes can be compared draw by draw. Built once per count and seed (a
    report or a comparison asks for the same draws hundreds of times), read-only."""
    picks = np.random.default_rng(seed).integers(0, scenes, (BOOTSTRAP, scenes))
    draws = np.stack([np.bincount(row, minlength=scenes) for row in picks]).astype(float)
    draws.setflags(write=False)
    return draws


def scene_draws(index: np.ndarray, scenes: int, hits: np.ndarray, seed: int = 0) -> np.ndarray:
    """The share of ``hits`` in each draw of the scenes (:func:`_draws`); ``index`` numbers each
    frame's scene (0 to ``scenes`` - 1). NaN for a draw without a frame."""
    frames = np.bincount(index, minlength=scenes).astype(float)
    counts = np.bincount(index, weights=hits.astype(float), minlength=scenes)
    weights = _draws(scenes, seed)
    with np.errstate(invalid="ignore"):
        return (weights @ counts) / (weights @ frames)


def scene_percentile_draws(
    index: np.ndarray, scenes: int, values: np.ndarray, q: float, seed: int = 0
) -> np.ndarray:
    """The ``q``-th percentile (0 to 100) of ``values`` in each draw of the scenes: every frame
    weighted by how often its scene was drawn (the lower value at a tie)."""
    order = np.argsort(values, kind="stable")
    sorted_values, sorted_index = values[order], index[order]
    out = np.full(BOOTSTRAP, np.nan)
    weights = _draws(scenes, seed)
    for start in range(0, BOOTSTRAP, 100):  # 100 draws at a time bounds the memory
        w = weights[start : start + 100][:, sorted_index]
        cumulative = np.cumsum(w, axis=1)
        total = cumulative[:, -1:] if len(values) else np.zeros((len(w), 1))
        at = (cumulative < q / 100 * total).sum(axis=1)
        good = total[:, 0] > 0
        out[start : start + 100][good] = sorted_values[np.minimum(at[good], len(values) - 1)]
    return out


def central(values: np.ndarray) -> tuple[float, float]:
    """The central :data:`INTERVAL` of ``values`` (NaN ignored)."""
    tail = 100 * (1 - INTERVAL) / 2
    low, high = np.nanpercentile(values, [tail, 100 - tail])
    return float(low), float(high)


def scene_interval(scenes: np.ndarray, hits: np.ndarray, seed: int = 0) -> tuple[float, float]:
    """Central :data:`INTERVAL` interval of the share of ``hits`` when the scenes are drawn again
    with replacement (:func:`scene_draws`): frames of one scene err together (one person's
    track, one crowd), so the scene, not the frame, is the unit a rate varies by. ``scenes`` and
    ``hits`` are per frame; NaN for no frame."""
    if len(hits) == 0:
        return float("nan"), float("nan")
    names, index = np.unique(scenes, return_inverse=True)
    return central(scene_draws(index, len(names), hits, seed))


def recovery_table(cols: Columns, axis: str | None) -> list[dict[str, Any]]:
    """Per group: person-frames, share with an estimate, flip rate and the thesis' tables 5.1
    and 5.2 errors (centre X/Y/Z in cm, azimuth and elevation in degrees) over the estimated."""
    rows = []
    for label, mask in groups(cols, axis):
        est = mask & cols["estimated"].astype(bool)
        az = np.degrees(cols["azimuth"][est])
        el = np.degrees(cols["elevation"][est])
        row: dict[str, Any] = {
            "group": label,
            "person_frames": int(mask.sum()),
            "estimated": float(est.sum() / max(mask.sum(), 1)),
            "flips": float((az > FLIP_DEG).mean()) if len(az) else float("nan"),
        }
        # A frame whose heading a cue other than the labels confirms: what a robot may trust.
        sure = cols["confident"][est].astype(bool)
        row["confident"] = float(sure.mean()) if len(az) else float("nan")
        row["flips_confident"] = float((az[sure] > FLIP_DEG).mean()) if sure.any() else float("nan")
        row["flips_low"], row["flips_high"] = scene_interval(cols["scene"][est], az > FLIP_DEG)
        for name, values in (("azimuth", az), ("elevation", el)):
            for stat, f in STATS.items():
                row[f"{name}_{stat}"] = f(values) if len(values) else float("nan")
        for axis_name in ("x", "y", "z"):
            values = 100 * cols[axis_name][est]
            row[f"{axis_name}_mean"] = float(values.mean()) if len(values) else float("nan")
            row[f"{axis_name}_median"] = float(np.median(values)) if len(values) else float("nan")
        rows.append(row)
    return rows


def flip_source_table(cols: Columns) -> list[dict[str, Any]]:
    """Per :data:`~.score.FLIP_SOURCES` entry: the flipped person-frames it explains, their share
    of all flips, and how many of them fell in a track's first :data:`~.score.YOUNG_FRAMES`
    frames with the person."""
    sources = np.asarray(cols["flip_source"]).astype(str)
    young = np.asarray(cols["track_frames"]) <= YOUNG_FRAMES
    total = int((sources != "").sum())
    rows = []
    for source in FLIP_SOURCES:
        mine = sources == source
        rows.append(
            {
                "source": source,
                "flips": int(mine.sum()),
                "share": float(mine.sum() / total) if total else float("nan"),
                "young": int((mine & young).sum()),
            }
        )
    return rows


def flip_evidence_table(cols: Columns) -> list[dict[str, Any]]:
    """Per band of the facing evidence a track gave with its estimate (:data:`EVIDENCE_EDGES`):
    the estimates in it, their share of all estimates, and the share of them flipped: how far a
    robot may trust a heading by the evidence the track reports with it."""
    est = np.asarray(cols["estimated"]).astype(bool)
    evidence = np.asarray(cols["facing_evidence"], dtype=float)[est]
    flipped = np.degrees(np.asarray(cols["azimuth"], dtype=float)[est]) > FLIP_DEG
    edges = (0.0, *EVIDENCE_EDGES, np.inf)
    rows = []
    for low, high in zip(edges, edges[1:]):
        mine = (evidence >= low) & (evidence < high)
        rows.append(
            {
                "band": f"{low:g} s and more" if np.isinf(high) else f"{low:g}-{high:g} s",
                "estimates": int(mine.sum()),
                "share": float(mine.mean()) if len(evidence) else float("nan"),
                "flips": float(flipped[mine].mean()) if mine.any() else float("nan"),
            }
        )
    return rows


def forecast_table(cols: Columns, axis: str | None) -> list[dict[str, Any]]:
    """Per group and horizon: forecasts, and each method's median, mean and 90th percentile of
    each component's error (cm or degrees)."""
    rows: list[dict[str, Any]] = []
    if not cols:
        return rows
    for label, mask in groups(cols, axis):
        for h in sorted(set(cols["horizon"].tolist())):
            m = mask & (cols["horizon"] == h)
            if not m.any():
                continue
            row: dict[str, Any] = {"group": label, "horizon": h, "forecasts": int(m.sum())}
            rows.append(row | error_stats(cols, m, METHODS))
    return rows


def error_stats(cols: Columns, mask: np.ndarray, methods: tuple[str, ...]) -> dict[str, float]:
    """Each of ``methods``' median, mean and 90th percentile of each component's error over the
    rows ``mask`` picks (cm or degrees), keyed ``method_component_stat``."""
    out = {}
    for method in methods:
        for component in COMPONENTS:
            values = SCALE[component] * cols[f"{method}_{component}"][mask]
            for stat, f in STATS.items():
                out[f"{method}_{component}_{stat}"] = f(values)
    return out


def covered(cols: Columns, axis: str, mask: np.ndarray) -> float:
    """The share of the forecasts ``mask`` picks whose truth fell inside their interval along
    pose component ``axis`` (``miss_`` within ``half_width_``)."""
    return float((cols[f"miss_{axis}"][mask] <= cols[f"half_width_{axis}"][mask]).mean())


def coverage_table(cols: Columns, axis: str | None) -> list[dict[str, Any]]:
    """Per group and horizon: the share of forecasts whose truth fell inside their 80 %
    interval, per component (the centre: the mean over x, y and z), among forecasts that had one."""
    rows: list[dict[str, Any]] = []
    if not cols or "half_width_x" not in cols:
        return rows
    for label, mask in groups(cols, axis):
        for h in sorted(set(cols["horizon"].tolist())):
            m = mask & (cols["horizon"] == h) & np.isfinite(cols["half_width_x"])
            if not m.any():
                continue
            row: dict[str, Any] = {"group": label, "horizon": h, "intervals": int(m.sum())}
            row["centre"] = float(np.mean([covered(cols, a, m) for a in "xyz"]))
            row["azimuth"] = covered(cols, "azimuth", m)
            row["elevation"] = covered(cols, "elevation", m)
            row["with_interval"] = float(m.sum() / max((mask & (cols["horizon"] == h)).sum(), 1))
            rows.append(row)
    return rows


def coverage_cells(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """The cells (group x horizon x component) of :func:`coverage_table`'s ``rows``: how many
    held the truth within :data:`CALIBRATED` (``inside``) of how many (``cells``), their mean
    distance from the middle of that band (``distance``, a share), and those outside it,
    furthest first (``outside``: group, horizon, component and coverage)."""
    target = sum(CALIBRATED) / 2
    cells = [
        {"group": r["group"], "horizon": r["horizon"], "component": c, "coverage": r[c]}
        for r in rows
        for c in COMPONENTS
    ]
    low, high = CALIBRATED
    outside = [c for c in cells if not low <= c["coverage"] <= high]
    outside.sort(key=lambda c: -abs(c["coverage"] - target))
    return {
        "inside": len(cells) - len(outside),
        "cells": len(cells),
        "distance": float(np.mean([abs(c["coverage"] - target) for c in cells])) if cells else float("nan"),
        "outside": outside,
    }


def identity_table(cols: Columns, axis: str | None) -> list[dict[str, Any]]:
    """Per group: people, the tracks they were given, identity switches, lost tracks and ids
    taken from someone else."""
    rows: list[dict[str, Any]] = []
    if not cols:
        return rows
    for label, mask in groups(cols, axis):
        rows.append(
            {
                "group": label,
                "people": int(mask.sum()),
                "visible_frames": int(cols["visible_frames"][mask].sum()),
                "tracks": int(cols["tracks"][mask].sum()),
                "switches": int(cols["switches"][mask].sum()),
                "lost": int(cols["lost"][mask].sum()),
                "taken": int(cols["taken"][mask].sum()),
            }
        )
    return rows


def unseen_table(cols: Columns) -> list[dict[str, Any]]:
    """Per band of time unseen, then over all: the unseen tracks' reported poses and their last
    estimates held, against the truth (:func:`error_stats`), and the share whose person was in
    view."""
    rows: list[dict[str, Any]] = []
    if not cols:
        return rows
    for label, mask in [*groups(cols, "unseen"), *groups(cols, None)]:
        row: dict[str, Any] = {
            "group": label,
            "n": int(mask.sum()),
            "in_view": float(np.mean(cols["in_view"][mask])),
        }
        rows.append(row | error_stats(cols, mask, ("forecast", "hold")))
    return rows


TIE = 1e-9
"""Relative difference of two error statistics within which :func:`losses` counts them equal."""


def losses(forecast_rows: dict[str, list[dict[str, Any]]], against: str = "hold") -> list[dict[str, Any]]:
    """Cells of :data:`CHECKED_AXES` (category or view bin, component, horizon, median or mean)
    where the default forecast's error is larger than ``against``'s, worst ratio first. Errors
    equal to within floating-point rounding (:data:`TIE`, relative) are a tie, not a loss: a
    forecast that holds still computes its error apart from holding's and can differ from it in
    the last bits."""
    out = []
    for axis in CHECKED_AXES:
        for row in forecast_rows.get(axis, []):
            for component in COMPONENTS:
                for stat in ("median", "mean"):
                    ours, theirs = row[f"forecast_{component}_{stat}"], row[f"{against}_{component}_{stat}"]
                    if ours > theirs * (1.0 + TIE):
                        out.append(
                            {
                                "axis": axis,
                                "group": row["group"],
                                "component": component,
                                "horizon": row["horizon"],
                                "stat": stat,
                                "forecast": ours,
                                against: theirs,
                                "ratio": ours / theirs if theirs > 0 else float("inf"),
                            }
                        )
    return sorted(out, key=lambda r: -r["ratio"])


def loss_intervals(cols: Columns, lost: list[dict[str, Any]], against: str) -> list[dict[str, Any]]:
    """``lost`` (:func:`losses`) with each cell's paired :data:`INTERVAL` interval of the
    forecast's error statistic minus ``against``'s (``low``, ``high``, in the cell's unit) over
    draws of the scenes, and ``beyond``: the whole interval above zero, a loss the draw of scenes
    does not explain. Both statistics of a draw weigh the same frames the same way."""
    if not lost:
        return lost
    names, index = np.unique(cols["scene"], return_inverse=True)
    labels = {axis: np.array([str(v) for v in condition(cols, axis)]) for axis in CHECKED_AXES}
    weights = _draws(len(names), 0)
    out = []
    for cell in lost:
        m = (labels[cell["axis"]] == cell["group"]) & (cols["horizon"] == cell["horizon"])
        scale = SCALE[cell["component"]]
        ours = scale * cols[f"forecast_{cell['component']}"][m]
        theirs = scale * cols[f"{against}_{cell['component']}"][m]
        if cell["stat"] == "median":
            draws = [scene_percentile_draws(index[m], len(names), v, 50.0) for v in (ours, theirs)]
            difference = draws[0] - draws[1]
        else:
            frames = np.bincount(index[m], minlength=len(names)).astype(float)
            gap = np.bincount(index[m], weights=ours - theirs, minlength=len(names))
            with np.errstate(invalid="ignore"):
                difference = (weights @ gap) / (weights @ frames)
        low, high = central(difference)
        out.append({**cell, "low": low, "high": high, "beyond": low > 0})
    return out


def checked_cells(forecast_rows: dict[str, list[dict[str, Any]]]) -> int:
    return sum(len(forecast_rows.get(axis, [])) for axis in CHECKED_AXES) * len(COMPONENTS) * 2


def tables(
    recovery: Columns, forecasts: Columns, identity: Columns, unseen: Columns | None = None
) -> dict[str, Any]:
    """Every table of the report, by kind and by condition (None: all rows); the unseen tracks'
    where their records are given (runs before them kept none)."""
    axes: list[str | None] = [None, *AXES]
    # Records written before forecasts carried the track's age, or the torso's tilt, have no
    # tables by them.
    aged = ["age"] if "track_age" in forecasts else []
    recovery_tilted = ["tilt"] if "tilt" in recovery else []
    forecasts_tilted = ["tilt"] if "tilt" in forecasts else []
    out: dict[str, Any] = {
        "recovery": {str(a or "all"): recovery_table(recovery, a) for a in [*axes, *recovery_tilted]},
        "forecasts": {
            str(a or "all"): forecast_table(forecasts, a) for a in [*axes, *aged, *forecasts_tilted]
        },
        "identity": {str(a or "all"): identity_table(identity, a) for a in (None, "people", "category")},
        "coverage": {
            str(a or "all"): coverage_table(forecasts, a) for a in (None, "category", "view", *aged)
        },
        "flip_sources": flip_source_table(recovery),
        "flip_evidence": flip_evidence_table(recovery),
    }
    out["losses"] = {
        against: loss_intervals(forecasts, losses(out["forecasts"], against), against)
        for against in ("hold", "velocity")
    }
    out["coverage_cells"] = coverage_cells(out["coverage"]["category"])
    out["unseen"] = unseen_table(unseen or {})
    return out
