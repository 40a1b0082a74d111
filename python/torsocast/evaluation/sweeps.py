"""Sweeps of the choices the thesis leaves open, on Human3.6M (``docs/reproduction.md``).

Three sweeps, each a table of "All" window-mean errors at 0.4, 1 and 2 s:

* plane joints: which joints the ground-truth and forecast torso plane is fitted through;
* gravity rule: how the up axis of each sequence is found (:data:`h36m.GRAVITY_RULES`);
* λ's time unit and value for N = 2 and 3 (λ in seconds = λ in samples / rate³);

and, for the column-label question of tables 5.4/5.5, the correlation over actions between our
Const at 400 ms and each of the thesis' columns.

The first two change the ground truth as well as the forecasts, so each row compares methods on
its own poses; the λ sweep shares one set of poses. Run it with::

    python -m torsocast.evaluation.sweeps --data ../shared/data/h36m [--subjects 5] [--out FILE.json]
"""

from __future__ import annotations

import argparse
import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._core import ForecasterConfig
from ..datasets import h36m
from . import thesis
from .h36m import evaluate
from .metrics import HORIZONS, QUANTITIES, UNITS

#: Plane joint sets: index -> side ("L", "R" or "C"), as :func:`h36m.torso_poses` takes them.
PLANE_JOINTS: dict[str, Mapping[int, str]] = {
    "hips, thorax, shoulders (default)": h36m.TORSO_JOINTS,
    "hips, shoulders": {1: "R", 6: "L", 17: "L", 25: "R"},
    "hips, spine, thorax, shoulders": {1: "R", 6: "L", 12: "C", 13: "C", 17: "L", 25: "R"},
    "shoulders, thorax, pelvis": {0: "C", 13: "C", 17: "L", 25: "R"},
}

#: The methods every sweep row reports: the baselines, the thesis' N = 1 and the default.
BASELINES: dict[str, ForecasterConfig] = {
    "const": ForecasterConfig("const"),
    "cvel_2s": ForecasterConfig("constant_velocity"),
    "cvel_0.4s": ForecasterConfig("constant_velocity", velocity_window=0.4),
    "zero_phase_n1": ForecasterConfig(extrapolation="polynomial"),
    "default": ForecasterConfig(),
}

#: λ values swept for N = 2 and 3, each in both units.
LAMBDAS = (1.0, 1e-2, 1e-4)


def lambda_methods() -> dict[str, ForecasterConfig]:
    """N = 2 and 3 (zero-phase filter) for every λ of :data:`LAMBDAS` in samples and in seconds,
    continued as the thesis does (polynomial) and as the default does (damped trend)."""
    out = {}
    for degree in (2, 3):
        for unit in ("samples", "seconds"):
            for lam in LAMBDAS:
                for rule in ("polynomial", "damped"):
                    name = f"n{degree} λ={lam:g} {unit} {rule}"
                    out[name] = ForecasterConfig(degree=degree, lam=lam, lambda_unit=unit, extrapolation=rule)
    return out


def _all(report: dict[str, Any]) -> dict[str, dict[str, list[float]]]:
    """Method -> quantity -> "All" window-mean errors at the table horizons."""
    return {
        method: {q: [result["categories"]["All"][q]["mean"][str(h)] for h in HORIZONS] for q in QUANTITIES}
        for method, result in report["results"].items()
    }


def _ranks(x: np.ndarray) -> np.ndarray:
    """Ranks with ties given their mean rank (as Spearman's coefficient needs)."""
    values, inverse = np.unique(x, return_inverse=True)
    order = np.argsort(np.argsort(x)).astype(float)
    return (
        np.array([order[inverse == inverse[i]].mean() for i in range(len(x))])
        if len(values) < len(x)
        else order
    )


def column_correlations(report: dict[str, Any], method: str = "const") -> dict[str, dict[str, list[float]]]:
    """Quantity -> thesis column of table 5.4/5.5 -> [Pearson, Spearman] correlation, over the
    actions both have, between ``method``'s window-mean error at 400 ms and that column. If the
    columns are shifted as the data README suspects, our Const should follow the "HMP" column."""
    actions = report["results"][method]["actions"]
    out: dict[str, dict[str, list[float]]] = {}
    for quantity in ("azimuth", "elevation"):
        names = [a for a in actions if a in thesis.TABLE_5_4[quantity]]
        ours = np.array([actions[a][quantity]["mean"]["10"] for a in names])
        out[quantity] = {}
        for i, column in enumerate(thesis.TABLE_5_4_COLUMNS):
            theirs = np.array([thesis.TABLE_5_4[quantity][a][i] for a in names])
            pearson = float(np.corrcoef(ours, theirs)[0, 1])
            spearman = float(np.corrcoef(_ranks(ours), _ranks(theirs))[0, 1])
            out[quantity][column] = [pearson, spearman]
    return out


def run(data: str | Path, subjects: Sequence[int] = (5,), every: int = 10) -> dict[str, Any]:
    """Every sweep on the dense protocol; plain data (the ``--out`` JSON)."""
    plane = {
        name: _all(evaluate(data, subjects, "dense", every, BASELINES, torso_joints=joints))
        for name, joints in PLANE_JOINTS.items()
    }
    gravity = {
        rule: _all(evaluate(data, subjects, "dense", every, BASELINES, gravity_rule=rule))
        for rule in h36m.GRAVITY_RULES
        if rule != "floor"  # fails its sanity check on seated sequences (the toes barely move)
    }
    shared = evaluate(data, subjects, "dense", every, {**BASELINES, **lambda_methods()})
    return {
        "subjects": list(subjects),
        "every": every,
        "units": UNITS,
        "plane_joints": plane,
        "gravity": gravity,
        "lambda": _all(shared),
        "column_correlations": column_correlations(shared),
    }


def markdown(sweeps: dict[str, Any]) -> str:
    """One table per sweep: a row per (variant, method)."""
    head = (
        "| variant | method | "
        + " | ".join(
            f"{q[:3]} {h * 40} ms" if h < 25 else f"{q[:3]} {h * 40 // 1000} s"
            for q in QUANTITIES
            for h in HORIZONS
        )
        + " |"
    )
    rule = "|---|---" + "|---:" * (len(QUANTITIES) * len(HORIZONS)) + "|"
    out = []
    for sweep in ("plane_joints", "gravity"):
        out += [f"### {sweep.replace('_', ' ')}", "", head, rule]
        for variant, methods in sweeps[sweep].items():
            for method, errors in methods.items():
                out.append(
                    f"| {variant} | {method} | "
                    + " | ".join(f"{v:.2f}" for q in QUANTITIES for v in errors[q])
                    + " |"
                )
        out.append("")
    out += ["### lambda", "", head, rule]
    for method, errors in sweeps["lambda"].items():
        out.append(
            f"| – | {method} | " + " | ".join(f"{v:.2f}" for q in QUANTITIES for v in errors[q]) + " |"
        )
    out += [
        "",
        "### Const at 400 ms per action against the columns of tables 5.4/5.5 (Pearson / Spearman)",
        "",
    ]
    out += ["| quantity | " + " | ".join(thesis.TABLE_5_4_COLUMNS) + " |"]
    out += ["|---" + "|---:" * len(thesis.TABLE_5_4_COLUMNS) + "|"]
    for quantity, columns in sweeps["column_correlations"].items():
        out.append(f"| {quantity} | " + " | ".join(f"{p:.2f} / {r:.2f}" for p, r in columns.values()) + " |")
    return "\n".join(out) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", required=True, help="Human3.6M folder with S5/")
    parser.add_argument("--subjects", default="5")
    parser.add_argument("--every", type=int, default=10)
    parser.add_argument("--out", help="also write the sweeps as JSON here")
    args = parser.parse_args()
    sweeps = run(args.data, [int(s) for s in args.subjects.split(",")], args.every)
    if args.out:
        Path(args.out).write_text(json.dumps(sweeps, indent=1))
    print(markdown(sweeps))


if __name__ == "__main__":
    main()
