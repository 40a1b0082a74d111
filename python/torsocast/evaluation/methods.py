"""The forecasters an evaluation compares, by name: the thesis' baselines, its filter + spline
family in every variant the thesis leaves open (each continuing its last polynomial piece, as the
thesis does), and torsocast's default (the N = 1 fit continued as a damped trend)."""

from __future__ import annotations

from typing import Literal

from .._core import ForecasterConfig

FILTERS: tuple[Literal["zero_phase", "causal", "off"], ...] = ("zero_phase", "causal", "off")
DEGREES = (0, 1, 2, 3)


def method_configs() -> dict[str, ForecasterConfig]:
    """Every method of the comparison, in report order."""
    methods = {
        "const": ForecasterConfig("const"),
        "cvel_2s": ForecasterConfig("constant_velocity"),
        "cvel_0.4s": ForecasterConfig("constant_velocity", velocity_window=0.4),
    }
    for filt in FILTERS:
        for degree in DEGREES:
            methods[f"{filt}_n{degree}"] = ForecasterConfig(
                filter=filt, degree=degree, extrapolation="polynomial"
            )
    # Beyond the thesis: the default, the N = 1 fit with a damped trend chosen on S1.
    methods["default"] = ForecasterConfig()
    return methods


LABELS = {
    "const": "Const",
    "cvel_2s": "CVel (2s)",
    "cvel_0.4s": "CVel (0.4s)",
    "default": "torsocast default (N = 1, damped trend)",
    **{f"{f}_n{d}": f"N = {d}, {f.replace('_', '-')} filter" for f in FILTERS for d in DEGREES},
}
for _d in DEGREES:
    LABELS[f"off_n{_d}"] = f"N = {_d}, no filter"

#: The learned baseline (:mod:`torsocast.evaluation.hmp`), run where a trained model is given.
HMP_LABEL = "HMP (Martinez et al. 2017, trained here)"


def describe(config: ForecasterConfig) -> dict[str, object]:
    """A config's fields, for the JSON report."""
    fields = (
        "method",
        "rate_hz",
        "history",
        "velocity_window",
        "filter",
        "filter_order",
        "cutoff_hz",
        "degree",
        "lam",
        "lambda_unit",
        "extrapolation",
    )
    return {name: getattr(config, name) for name in fields}
