"""Writes a scenes benchmark as Markdown (failures first), JSON, CSV records and figures."""

from __future__ import annotations

import csv
import json
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np

from .run import TABLES, Benchmark
from .score import BAD_LINE_DEG, COMPONENTS, FLIP_DEG, METHODS, YOUNG_FRAMES
from .tables import CALIBRATED, CHECKED_AXES, INTERVAL, UNIT, checked_cells, tables

METHOD_NAMES = {
    "forecast": "torsocast",
    "hold": "hold the estimate",
    "velocity": "constant velocity",
    "truth": "hold the truth",
}
AXIS_NAMES = {
    "all": "all",
    "view": "view (degrees from facing the camera)",
    "distance": "distance",
    "people": "people in the scene",
    "category": "motion category",
    "fps": "frame rate",
    "age": "track's age with the person",
    "tilt": "torso's tilt from upright",
}


def _f(value: float, digits: int = 1) -> str:
    return "–" if value is None or not np.isfinite(value) else f"{value:.{digits}f}"


def _pct(value: float) -> str:
    return "–" if not np.isfinite(value) else f"{100 * value:.1f} %"


def _interval(row: dict[str, Any]) -> str:
    """A flip rate's scene-bootstrap interval (:func:`~.tables.scene_interval`)."""
    return f"{100 * INTERVAL:g} % interval {_pct(row['flips_low'])} to {_pct(row['flips_high'])}"


def _h(h: float) -> str:
    return f"{h:g} s"


def headline(t: dict[str, Any]) -> list[str]:
    """Flip rate, azimuth error and the forecast against holding still, at each horizon."""
    rec = t["recovery"]["all"][0]
    views = [r for r in t["recovery"]["view"] if r["person_frames"]]
    worst = max(views, key=lambda r: r["flips"] if np.isfinite(r["flips"]) else -1) if views else None
    lines = [
        f"Torso estimates for {_pct(rec['estimated'])} of the visible person-frames; front/back flips "
        f"(azimuth error over {FLIP_DEG:g} degrees) in {_pct(rec['flips'])} of them "
        f"({_interval(rec)} over the scenes drawn again)"
        + (f", {_pct(worst['flips'])} in the worst view bin ({worst['group']} degrees)" if worst else "")
        + f"; {_pct(rec['flips_confident'])} of the {_pct(rec['confident'])} whose heading a cue other than "
        "the labels confirms (`heading_confident`)" + f"; azimuth error median {_f(rec['azimuth_median'])}, "
        f"90th percentile {_f(rec['azimuth_p90'])} degrees.",
        "",
        "| median error | " + " | ".join(_h(r["horizon"]) for r in t["forecasts"]["all"]) + " |",
        "|---|" + "---:|" * len(t["forecasts"]["all"]),
    ]
    for component in COMPONENTS:
        for method in ("forecast", "hold", "velocity"):
            cells = [_f(r[f"{method}_{component}_median"]) for r in t["forecasts"]["all"]]
            lines.append(
                f"| {component} ({UNIT[component]}), {METHOD_NAMES[method]} | " + " | ".join(cells) + " |"
            )
    return lines


def failures(t: dict[str, Any]) -> list[str]:
    """The report's first lines: where torsocast flips or forecasts worse than the references."""
    lines = []
    rec = t["recovery"]
    sure = rec["all"][0]
    all_flips = sure["flips"]
    bad_views = [r for r in rec["view"] if np.isfinite(r["flips"]) and r["flips"] > 0]
    sure_views = [r["flips_confident"] for r in rec["view"] if np.isfinite(r["flips_confident"])]
    worst_sure = max(sure_views, default=0.0)
    if all_flips > 0:
        lines.append(
            f"- **Front/back flips** in {_pct(all_flips)} of estimated person-frames "
            f"({_interval(sure)} over the scenes drawn again); by view bin: "
            + ", ".join(f"{r['group']}: {_pct(r['flips'])}" for r in bad_views)
            + f". Where the heading is confident ({_pct(sure['confident'])} of them): "
            + f"{_pct(sure['flips_confident'])}, {_pct(worst_sure)} in the worst view bin."
        )
    else:
        lines.append("- No front/back flip (no azimuth error over 90 degrees).")
    cells = checked_cells(t["forecasts"])
    for against in ("hold", "velocity"):
        lost = t["losses"][against]
        name = "holding the current estimate still" if against == "hold" else "constant velocity"
        if lost:
            worst = "; ".join(
                f"{r['axis']} {r['group']}, {r['component']} at {_h(r['horizon'])} ({r['stat']}): "
                f"{_f(r['forecast'])} vs {_f(r[against])} {UNIT[r['component']]}"
                for r in lost[:6]
            )
            beyond = sum(r["beyond"] for r in lost)
            lines.append(
                f"- **Forecast worse than {name}** in {len(lost)} of {cells} checked cells "
                f"({' or '.join(CHECKED_AXES)} x component x horizon x median or mean), {beyond} of them "
                f"by more than the draw of scenes explains ({100 * INTERVAL:g} % interval of the "
                f"difference above zero). Worst: {worst}."
            )
        else:
            lines.append(f"- The forecast is nowhere worse than {name} ({cells} cells checked).")
    calibration = t.get("coverage_cells")
    if calibration and calibration["cells"]:
        low, high = (f"{100 * b:g} %" for b in CALIBRATED)
        if calibration["outside"]:
            furthest = "; ".join(
                f"{c['group']}, {c['component']} at {_h(c['horizon'])}: {_pct(c['coverage'])}"
                for c in calibration["outside"][:6]
            )
            lines.append(
                f"- **Forecast intervals off calibration** in {len(calibration['outside'])} of "
                f"{calibration['cells']} cells (motion category x horizon x component): the truth "
                f"inside the 80 % interval less than {low} or more than {high} of the time; the "
                f"cells lie {100 * calibration['distance']:.1f} points from 80 % on average. "
                f"Furthest: {furthest}."
            )
        else:
            lines.append(
                f"- The forecast intervals hold the truth {low} to {high} of the time in every motion "
                f"category, horizon and component ({calibration['cells']} cells)."
            )
    return lines


def _recovery_md(rows: list[dict[str, Any]], axis: str) -> list[str]:
    out = [
        f"| {AXIS_NAMES[axis]} | person-frames | estimated | flips | confident: share / flips "
        "| azimuth median / mean / p90 (deg) | elevation median / mean / p90 (deg) | X / Y / Z mean (cm) |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        az = " / ".join(_f(r[f"azimuth_{s}"]) for s in ("median", "mean", "p90"))
        el = " / ".join(_f(r[f"elevation_{s}"]) for s in ("median", "mean", "p90"))
        xyz = " / ".join(_f(r[f"{a}_mean"], 0) for a in "xyz")
        out.append(
            f"| {r['group']} | {r['person_frames']} | {_pct(r['estimated'])} | {_pct(r['flips'])} "
            f"| {_pct(r['confident'])} / {_pct(r['flips_confident'])} | {az} | {el} | {xyz} |"
        )
    return out


def _forecast_all_md(rows: list[dict[str, Any]]) -> list[str]:
    out = [
        "| component | horizon | forecasts | "
        + " | ".join(f"{METHOD_NAMES[m]} median / mean / p90" for m in METHODS)
        + " |",
        "|---|---|---:|" + "---:|" * len(METHODS),
    ]
    for component in COMPONENTS:
        for r in rows:
            cells = [
                " / ".join(_f(r[f"{m}_{component}_{s}"]) for s in ("median", "mean", "p90")) for m in METHODS
            ]
            out.append(
                f"| {component} ({UNIT[component]}) | {_h(r['horizon'])} | {r['forecasts']} | "
                + " | ".join(cells)
                + " |"
            )
    return out


def _forecast_by_md(rows: list[dict[str, Any]], axis: str, component: str) -> list[str]:
    out = [
        f"| {AXIS_NAMES[axis]} | horizon | forecasts | torsocast | hold | constant velocity "
        "| hold the truth |",
        "|---|---|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        ours = r[f"forecast_{component}_median"]
        mark = " ✗" if ours > r[f"hold_{component}_median"] else ""
        cells = [_f(r[f"{m}_{component}_median"]) for m in METHODS]
        cells[0] += mark
        out.append(f"| {r['group']} | {_h(r['horizon'])} | {r['forecasts']} | " + " | ".join(cells) + " |")
    return out


def _forecast_by_age_md(rows: list[dict[str, Any]]) -> list[str]:
    columns = [(c, m) for c in ("centre", "azimuth") for m in ("forecast", "hold", "velocity")]
    out = [
        "Every forecast by how long its track had been with the person when it was made: a young "
        "track's forecast rests on a short history and on few or none of its own checks.",
        "",
        f"| {AXIS_NAMES['age']} | horizon | forecasts | "
        + " | ".join(f"{c} ({UNIT[c]}): {METHOD_NAMES[m]} median / mean" for c, m in columns)
        + " |",
        "|---|---|---:|" + "---:|" * len(columns),
    ]
    for r in rows:
        cells = [" / ".join(_f(r[f"{m}_{c}_{s}"]) for s in ("median", "mean")) for c, m in columns]
        out.append(f"| {r['group']} | {_h(r['horizon'])} | {r['forecasts']} | " + " | ".join(cells) + " |")
    return out


def _flip_sources_md(rows: list[dict[str, Any]]) -> list[str]:
    out = [
        "Each flipped estimate by the first rule that explains it (`score.flip_source`): bad plane, "
        f"the torso line more than {BAD_LINE_DEG:g} degrees off the truth's; born wrong, a track not "
        "yet on the right side with this person; turned wrong, its last turn round took it to the "
        "wrong side; side lost, gone over with no turn. Young: in the track's first "
        f"{YOUNG_FRAMES} frames with the person.",
        "",
        "| source | flips | share of flips | young |",
        "|---|---:|---:|---:|",
    ]
    for r in rows:
        out.append(f"| {r['source']} | {r['flips']} | {_pct(r['share'])} | {r['young']} |")
    return out


def _flip_evidence_md(rows: list[dict[str, Any]]) -> list[str]:
    out = [
        "Flips by the facing evidence the track gave with the estimate (`facing_evidence`, in "
        "seconds of the labels' agreement: the labels alone build about a second's worth, more has "
        "been confirmed by another cue; a track that has just turned round starts again from "
        "little).",
        "",
        "| facing evidence | estimates | share of estimates | flips |",
        "|---|---:|---:|---:|",
    ]
    for r in rows:
        out.append(f"| {r['band']} | {r['estimates']} | {_pct(r['share'])} | {_pct(r['flips'])} |")
    return out


def _unseen_md(rows: list[dict[str, Any]]) -> list[str]:
    lines = [
        "Each confirmed track that a frame did not show (the person hidden, out of view or not "
        "detected) is reported with its forecast for the frame's time (`unseen`), for as long as the "
        "tracker keeps it; against the true pose of the person the track last showed, beside holding "
        "the track's last estimate of them. In view: the person's torso was in the image and not "
        "hidden, and no detection of them continued the track. Median / mean; centre cm, azimuth "
        "degrees.",
        "",
        "| unseen for | track-frames | in view | centre: reported | held | azimuth: reported | held |",
        "|---|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        cells = [
            f"{_f(r[f'{m}_{c}_median'])} / {_f(r[f'{m}_{c}_mean'])}"
            for c in ("centre", "azimuth")
            for m in ("forecast", "hold")
        ]
        lines.append(f"| {r['group']} | {r['n']} | {_pct(r['in_view'])} | " + " | ".join(cells) + " |")
    return lines


def markdown(bench: Benchmark, t: dict[str, Any], figures: list[str]) -> str:
    rec = t["recovery"]["all"][0]
    kind = "quick run" if bench.quick else "full run"
    lines = [
        f"# Scenes benchmark: {bench.split} split, seed {bench.seed} ({kind})",
        "",
        "Where torsocast is wrong or worse than a trivial rule, first:",
        "",
        *failures(t),
        "",
        f"{len(bench.specs)} scenes, {bench.frames} frames, {rec['person_frames']} person-frames with "
        f"the torso in view; detections on nobody: {bench.false_positives}. Models: one person, "
        f"{bench.models.get('one person')}; several, {bench.models.get('several people') or 'none'}. "
        "Every frame went through the real pipeline and model; nothing is simulated after the rendering.",
    ]
    if bench.notes:
        lines += ["", "Notes:", "", *[f"- {n}" for n in bench.notes]]
    lines += ["", "## Headline", "", *headline(t), "", "## Torso recovery", ""]
    lines.append(
        "Errors of the estimate against the true torso pose in every frame where at least three of "
        "the person's four torso joints are in the image and not hidden by someone else (the thesis' "
        "tables 5.1 and 5.2 give the same quantities on mocap). Flips: share of estimates with an "
        f"azimuth error over {FLIP_DEG:g} degrees."
    )
    for axis in ("all", "view", "distance", "people", "category", "fps", "tilt"):
        if axis not in t["recovery"]:
            continue  # records from before the torso's tilt was kept
        lines += ["", f"### By {AXIS_NAMES[axis]}" if axis != "all" else "### All", ""]
        lines += _recovery_md(t["recovery"][axis], axis)
    lines += ["", "### Where the flips come from", "", *_flip_sources_md(t["flip_sources"])]
    lines += ["", *_flip_evidence_md(t["flip_evidence"])]
    lines += ["", "## Forecasts", ""]
    lines.append(
        "Every forecast of a confirmed track against the true pose at the time it aims at, beside "
        "three references from the same instant: holding the current estimate still, constant "
        "velocity fitted to the track's estimates (the thesis' baseline over its 2 s history), and "
        "holding the *true* current pose still (what a perfect recovery would give without a "
        "forecaster). Centre: 3D distance."
    )
    lines += ["", "### All", "", *_forecast_all_md(t["forecasts"]["all"])]
    for axis in CHECKED_AXES:
        for component in COMPONENTS:
            lines += [
                "",
                f"### {component.capitalize()} by {AXIS_NAMES[axis]} "
                f"(median {UNIT[component]}; ✗: worse than hold)",
                "",
            ]
            lines += _forecast_by_md(t["forecasts"][axis], axis, component)
    if t["forecasts"].get("age"):
        lines += ["", f"### By the {AXIS_NAMES['age']}", "", *_forecast_by_age_md(t["forecasts"]["age"])]
    lines += ["", "## Forecast intervals", ""]
    lines.append(
        "Share of forecasts whose true pose fell inside the 80 % interval the track gave with it "
        "(`half_width80`: the spread of the track's own recent forecast errors, times the multiple of "
        "it that covered 80 % of them and the truth's margin over them); the centre is the "
        "mean over its x, y and z intervals. A calibrated interval covers 80 %; given: the share of "
        "forecasts that came with one (a track gives none while its history is too short for a line)."
    )
    for axis in ("all", "category", "view", "age"):
        if axis not in t["coverage"]:
            continue
        lines += ["", f"### {AXIS_NAMES[axis].capitalize()}" if axis != "all" else "### All", ""]
        lines += [
            f"| {AXIS_NAMES[axis]} | horizon | given | centre | azimuth | elevation |",
            "|---|---|---:|---:|---:|---:|",
        ]
        for r in t["coverage"][axis]:
            lines.append(
                f"| {r['group']} | {_h(r['horizon'])} | {_pct(r['with_interval'])} | {_pct(r['centre'])} "
                f"| {_pct(r['azimuth'])} | {_pct(r['elevation'])} |"
            )
    lines += [
        "",
        "## Tracking",
        "",
        "| group | people | visible frames | tracks | identity switches | lost tracks | ids taken |",
    ]
    lines.append("|---|---:|---:|---:|---:|---:|---:|")
    for axis in ("all", "people", "category"):
        for r in t["identity"][axis]:
            label = r["group"] if axis == "all" else f"{AXIS_NAMES[axis]}: {r['group']}"
            lines.append(
                f"| {label} | {r['people']} | {r['visible_frames']} | {r['tracks']} "
                f"| {r['switches']} | {r['lost']} | {r['taken']} |"
            )
    lines += [
        "",
        "Identity switches: times a person's reported track id changed. Lost tracks: tracks that "
        "ended while their person stayed in view for at least another second. Ids taken: ids a "
        "person was reported with that someone else in the scene had been reported with before "
        "(an id passed on to another person: a switch counts a person's own id changing, not "
        "the id they were given instead).",
    ]
    if t.get("unseen"):
        lines += ["", "## People unseen", "", *_unseen_md(t["unseen"])]
    if figures:
        lines += ["", "## Figures", ""] + [f"![{Path(f).stem}]({f})" for f in figures]
    return "\n".join(lines) + "\n"


def _write_csv(path: Path, cols: dict[str, list]) -> None:  # type: ignore[type-arg]
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(list(cols))
        writer.writerows(zip(*cols.values()))


def _clean(value: Any) -> Any:
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if np.isfinite(value) else None
    return value


def write(bench: Benchmark, out: str | Path, draw: bool = True) -> tuple[str, list[Path]]:
    """``out/report.md``, ``report.json``, ``scenes.json``, the records as ``recovery.csv``,
    ``forecasts.csv``, ``identity.csv``, and with ``draw`` the figures in ``out/figures/``;
    returns the Markdown and the files written."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t = tables(
        bench.columns("recovery"),
        bench.columns("forecasts"),
        bench.columns("identity"),
        bench.columns("unseen"),
    )
    written, figures = [], []
    if draw:
        from .figures import draw_all

        for path in draw_all(bench, t, out / "figures"):
            written.append(path)
            figures.append(f"figures/{path.name}")
    text = markdown(bench, t, figures)
    (out / "report.md").write_text(text)
    summary = {
        "split": bench.split,
        "seed": bench.seed,
        "quick": bench.quick,
        "scenes": len(bench.specs),
        "frames": bench.frames,
        "false_positives": bench.false_positives,
        "models": bench.models,
        "notes": bench.notes,
        "losses_to_hold": t["losses"]["hold"],
        "losses_to_velocity": t["losses"]["velocity"],
        "tables": t,
    }
    (out / "report.json").write_text(json.dumps(_clean(summary), indent=1))
    (out / "scenes.json").write_text(json.dumps(_clean([asdict(s) for s in bench.specs]), indent=1))
    for table in TABLES:
        _write_csv(out / f"{table}.csv", getattr(bench, table))
    written = (
        [out / "report.md", out / "report.json", out / "scenes.json"]
        + [out / f"{n}.csv" for n in TABLES]
        + written
    )
    return text, written
