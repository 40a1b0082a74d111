"""Writes an evaluation (the dict of :func:`torsocast.evaluation.h36m.evaluate`) as Markdown
tables shaped like the thesis' tables 5.3 to 5.5, JSON, CSV, and figures like 5.1 to 5.3."""

from __future__ import annotations

import csv
import json
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from . import thesis
from .joint_angles import MILLISECONDS
from .metrics import HORIZONS, QUANTITIES, UNITS

HORIZON_NAMES = {10: "400 ms", 25: "1 s", 50: "2 s"}
#: Our method shown under each thesis column (HMP where a trained model was given).
THESIS_COLUMNS = {
    "Const": "const",
    "N = 1": "zero_phase_n1",
    "N = 2": "zero_phase_n2",
    "N = 3": "zero_phase_n3",
    "CVel (2s)": "cvel_2s",
    "CVel (0.4s)": "cvel_0.4s",
    "HMP": "hmp",
}
#: Methods drawn in the figures.
FIGURE_METHODS = (
    "const",
    "cvel_2s",
    "cvel_0.4s",
    "zero_phase_n1",
    "zero_phase_n2",
    "off_n1",
    "default",
    "hmp",
)


def _cell(ours: float | None, theirs: float | None) -> str:
    left = "–" if ours is None else f"{ours:.2f}"
    return left if theirs is None else f"{left} ({theirs:g})"


def _value(
    report: dict[str, Any], method: str | None, kind: str, group: str, quantity: str, h: int
) -> float | None:
    if method is None or method not in report["results"]:
        return None
    groups = report["results"][method][kind]
    return groups[group][quantity]["mean"][str(h)] if group in groups else None


def table_5_3(report: dict[str, Any], quantity: str) -> str:
    """Per category and horizon: Const, N = 1, N = 2 (ours, thesis in brackets), and the thesis' HMP."""
    columns = ("Const", "N = 1", "N = 2", "HMP")
    head = "| category | " + " | ".join(f"{c} {HORIZON_NAMES[h]}" for h in HORIZONS for c in columns) + " |"
    lines = [head, "|---" + "|---:" * (len(columns) * len(HORIZONS)) + "|"]
    rows = [*report["categories"], "All (no filter)"]
    for group in rows:
        published = thesis.TABLE_5_3[quantity].get(group)
        cells = []
        for h in HORIZONS:
            for i, column in enumerate(columns):
                method = THESIS_COLUMNS[column]
                if group == "All (no filter)" and method and method.startswith("zero_phase"):
                    method = method.replace("zero_phase", "off")
                ours = _value(
                    report, method, "categories", "All" if group == "All (no filter)" else group, quantity, h
                )
                cells.append(_cell(ours, published[h][i] if published else None))
        lines.append(f"| {group} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def table_5_4(report: dict[str, Any], quantity: str, horizon: int = 10) -> str:
    """Per action at one horizon, with the columns of the thesis' tables 5.4 (azimuth) and 5.5."""
    columns = thesis.TABLE_5_4_COLUMNS
    lines = [
        "| action | windows | " + " | ".join(columns) + " |",
        "|---|---:" + "|---:" * len(columns) + "|",
    ]
    published = thesis.TABLE_5_4[quantity] if horizon == 10 else {}
    counts = report["windows"]["per_action"]
    for action in [*thesis.TABLE_5_4["azimuth"]]:
        kind, group = ("categories", "All") if action == "All" else ("actions", action)
        theirs = published.get(action)
        cells = [
            _cell(
                _value(report, THESIS_COLUMNS[c], kind, group, quantity, horizon),
                theirs[i] if theirs else None,
            )
            for i, c in enumerate(columns)
        ]
        n = sum(counts.values()) if action == "All" else counts.get(action, 0)
        lines.append(f"| {action} | {n} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def methods_table(report: dict[str, Any], group: str = "All", statistic: str = "mean") -> str:
    """Every method at every horizon for the three quantities, for one category."""
    head = "| method | " + " | ".join(
        f"{q[:3]} {HORIZON_NAMES[h]} ({UNITS[q]})" for q in QUANTITIES for h in HORIZONS
    )
    lines = [head + " |", "|---" + "|---:" * (len(QUANTITIES) * len(HORIZONS)) + "|"]
    for name, result in report["results"].items():
        values = result["categories"].get(group)
        if values is None:
            continue
        cells = [f"{values[q][statistic][str(h)]:.2f}" for q in QUANTITIES for h in HORIZONS]
        lines.append(f"| {report['methods'][name]['label']} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def joint_angles_table(errors: dict[str, dict[str, list[float]]]) -> str:
    """Zero velocity's and HMP's joint-angle errors per action, as Martinez et al.'s table 1."""
    steps = " / ".join(str(ms) for ms in MILLISECONDS)
    lines = [
        f"| action | zero velocity, {steps} ms | HMP, {steps} ms |",
        "|---|---|---|",
    ]
    for action, values in errors.items():
        held, learned = (" / ".join(f"{v:.2f}" for v in values[k]) for k in ("zero_velocity", "hmp"))
        lines.append(f"| {action} | {held} | {learned} |")
    return "\n".join(lines)


def markdown(report: dict[str, Any]) -> str:
    w = report["windows"]
    parts = [
        f"# Torso pose forecasting on Human3.6M: subjects {report['subjects']}, protocol "
        f"{report['protocol']}" + (f" (every {report['every']}th start)" if report["every"] else ""),
        f"{w['total']} windows ({w['skipped']} skipped for unfittable poses); 2 s history at 25 Hz. "
        "Figures are the mean absolute error over the forecast window unless marked 'end'; "
        "category and All rows average their actions. Thesis values in brackets.",
    ]
    if report.get("left_out"):
        parts.append("Files left out: " + "; ".join(report["left_out"]) + ".")
    if "hmp" in report["methods"]:
        model = report["methods"]["hmp"]
        config = model["config"]
        subjects = ", ".join(f"S{s}" for s in config["trained_on_subjects"])
        parts.append(
            f"HMP: a GRU of {config['units']} units, trained here on {subjects} for {config['iterations']} "
            f"steps (the thesis' saw six subjects for 100 000); {model['steps_without_plane']} of its "
            "forecast steps gave no oriented torso plane and carry the step before."
        )
    for quantity, number in (("azimuth", "5.3 (azimuth)"), ("elevation", "5.3 (elevation)")):
        parts += [f"## Table {number}, degrees", table_5_3(report, quantity)]
    for quantity, number in (("azimuth", "5.4"), ("elevation", "5.5")):
        parts += [f"## Table {number}: {quantity} at 400 ms per action, degrees", table_5_4(report, quantity)]
    if "hmp" in report["methods"]:
        parts += [
            "## HMP on the literature's measure: joint angles (Euler, radians), seeded windows",
            joint_angles_table(report["methods"]["hmp"]["joint_angles"]),
        ]
    for group in report["categories"]:
        parts += [f"## All methods, {group}: mean over the window", methods_table(report, group)]
    parts += ["## All methods, All: error at the window's end", methods_table(report, "All", "end")]
    return "\n\n".join(parts) + "\n"


def rows(report: dict[str, Any]) -> list[dict[str, Any]]:
    """The report in long form: one row per method, group, quantity, statistic and horizon."""
    out = []
    counts = report["windows"]["per_action"]
    for method, result in report["results"].items():
        for kind in ("actions", "categories", "pooled"):
            groups = {"pooled": result["pooled"]} if kind == "pooled" else result[kind]
            for group, values in groups.items():
                if kind == "actions":
                    n = counts[group]
                elif kind == "categories":
                    n = sum(counts[a] for a in report["categories"][group])
                else:
                    n = report["windows"]["total"]
                for quantity in QUANTITIES:
                    for statistic in ("mean", "end"):
                        for h in HORIZONS:
                            out.append(
                                {
                                    "method": method,
                                    "group_kind": kind,
                                    "group": group,
                                    "windows": n,
                                    "quantity": quantity,
                                    "unit": UNITS[quantity],
                                    "statistic": statistic,
                                    "horizon_steps": h,
                                    "horizon_s": h / report["rate_hz"],
                                    "value": values[quantity][statistic][str(h)],
                                }
                            )
    return out


def figures(report: dict[str, Any], out_dir: Path, methods: Sequence[str] = FIGURE_METHODS) -> list[Path]:
    """One PNG per category: error at each step from 40 ms to 2 s, a line per method."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = []
    rate = report["rate_hz"]
    for group in report["categories"]:
        fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
        for ax, quantity in zip(axes, QUANTITIES):
            for name in methods:
                if name not in report["results"]:
                    continue
                curve = report["results"][name]["categories"][group][quantity]["curve"]
                t = [1000.0 * (k + 1) / rate for k in range(len(curve))]
                ax.plot(t, curve, label=report["methods"][name]["label"])
            ax.set_xlabel("forecast horizon (ms)")
            ax.set_ylabel(f"{quantity} error ({UNITS[quantity]})")
            ax.set_title(quantity)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=8)
        subjects = ", ".join(f"S{s}" for s in report["subjects"])
        fig.suptitle(f"Human3.6M {subjects}, {group} ({report['protocol']} windows)")
        fig.tight_layout()
        path = out_dir / f"error_vs_horizon_{group.lower().replace(' ', '_')}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        paths.append(path)
    return paths


def write(report: dict[str, Any], out_dir: str | Path, draw: bool = True) -> list[Path]:
    """Writes report.md, report.json, report.csv and (with matplotlib) the figures."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / "report.md").write_text(markdown(report))
    (out / "report.json").write_text(json.dumps(report, indent=1))
    table = rows(report)
    with open(out / "report.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(table[0]))
        writer.writeheader()
        writer.writerows(table)
    written = [out / "report.md", out / "report.json", out / "report.csv"]
    if draw:
        written += figures(report, out)
    return written
