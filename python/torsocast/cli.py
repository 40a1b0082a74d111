"""Command line: ``torsocast bench`` and ``torsocast forecast``."""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from . import COMPONENTS, Forecaster, ForecasterConfig, TorsocastError, __version__, wrap_angle


def _bench(args: argparse.Namespace) -> int:
    from .bench import measure, report

    print(f"torsocast {__version__}: forecast latency on this machine ({args.windows} windows for the batch)")
    print(report(measure(args.windows)))
    return 0


def _forecast(args: argparse.Namespace) -> int:
    """Reads `t,x,y,z,azimuth,elevation[,weight]` rows (one track) and writes one JSON object per row
    with the forecasts at the requested horizons."""
    horizons = [float(h) for h in args.horizons.split(",")]
    config = ForecasterConfig(
        args.method, degree=args.degree, filter=args.filter, rate_hz=args.rate, history=args.history
    )
    forecaster = Forecaster(config)
    source = sys.stdin if args.input == "-" else open(args.input)  # noqa: SIM115
    with source:
        for line_no, line in enumerate(source, 1):
            fields = line.strip().split(",")
            if not line.strip() or line.startswith("#") or not _is_number(fields[0]):
                continue
            row = np.array(fields, dtype=float)
            if len(row) not in (6, 7):
                print(f"line {line_no}: expected 6 or 7 comma-separated numbers", file=sys.stderr)
                return 2
            try:
                report = forecaster.update(row[1:6], row[0], row[6] if len(row) == 7 else 1.0)
            except TorsocastError as e:
                print(f"line {line_no}: skipped: {e}", file=sys.stderr)
                continue
            out: dict[str, object] = {"t": row[0], "filled": report[0], "restarted": report[1]}
            if len(forecaster) >= forecaster.min_samples:
                pred = forecaster.forecast(horizons)
                pred[:, 3] = wrap_angle(pred[:, 3])
                out["forecast"] = {
                    f"{h:g}": dict(zip(COMPONENTS, map(float, p))) for h, p in zip(horizons, pred)
                }
            print(json.dumps(out))
    return 0


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="torsocast", description=__doc__)
    parser.add_argument("--version", action="version", version=__version__)
    sub = parser.add_subparsers(dest="command", required=True)
    bench = sub.add_parser("bench", help="measure forecast latency of every forecaster on this machine")
    bench.add_argument("--windows", type=int, default=2000, help="windows in the batch timing")
    bench.set_defaults(run=_bench)
    fc = sub.add_parser("forecast", help="forecast a torso pose track read as CSV (t,x,y,z,az,el[,w])")
    fc.add_argument("input", help="CSV file, or - for standard input")
    fc.add_argument("--horizons", default="0.4,1.0,2.0", help="seconds ahead, comma-separated")
    fc.add_argument(
        "--method", default="filter_spline", choices=["filter_spline", "const", "constant_velocity"]
    )
    fc.add_argument("--degree", type=int, default=1)
    fc.add_argument("--filter", default="zero_phase", choices=["off", "causal", "zero_phase"])
    fc.add_argument("--rate", type=float, default=25.0, help="forecaster grid rate (Hz)")
    fc.add_argument("--history", type=float, default=2.0, help="history length (s)")
    fc.set_defaults(run=_forecast)
    args = parser.parse_args(argv)
    try:
        return int(args.run(args))
    except TorsocastError as e:
        print(f"torsocast: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
