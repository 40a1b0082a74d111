"""Python-side benchmark: the Rust forecaster against a NumPy/SciPy implementation of the same
algorithm and against the thesis' 0.715 ms per forecast, in one run. Prints a Markdown table.

    python benches/bench_python.py          (needs scipy: pip install .[test])
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

import scipy_reference as ref  # noqa: E402
import torsocast as tc  # noqa: E402
from torsocast.bench import (  # noqa: E402
    THESIS_FORECAST_SECONDS,
    best_time,
    frame_step,
    measure,
    report,
    walking_windows,
)

HORIZONS = [0.4, 1.0, 2.0]


def main() -> None:
    n = 2000
    data = walking_windows(n)
    print("## Through the Python API\n")
    print(report(measure(n)))

    print("\n## Rust against the NumPy/SciPy reference (default config: zero-phase filter, N = 1)\n")
    config = tc.ForecasterConfig()
    loop_n = 200
    ref_plain = (
        best_time(lambda: [ref.forecast(w, HORIZONS) for w in data[:loop_n]], repeat=3, number=1) / loop_n
    )
    ref_cached = (
        best_time(lambda: [ref.forecast_fixed_grid(w, HORIZONS) for w in data[:loop_n]], repeat=3, number=1)
        / loop_n
    )
    single = best_time(frame_step(config, data[0], HORIZONS))
    const = tc.Forecaster(tc.ForecasterConfig("const"))
    const.update([0, 0, 1, 0, 1.5], 0.0)
    overhead = best_time(lambda: const.forecast([1.0]))
    batch = best_time(lambda: tc.forecast_batch(data, HORIZONS, config), repeat=3, number=1) / n
    # Same numbers out of both, so the timing compares equal work.
    np.testing.assert_allclose(
        tc.forecast_batch(data[:5], HORIZONS, config)[0], ref.forecast(data[0], HORIZONS), atol=1e-9
    )
    rows = [
        ("SciPy reference, per window (basis rebuilt per call)", ref_plain),
        ("SciPy reference, per window (basis cached)", ref_cached),
        ("thesis, per forecast (Python, i7-6700HQ)", THESIS_FORECAST_SECONDS),
        ("Rust Forecaster.update + forecast via Python, per frame", single),
        ("Rust forecast_batch, per window", batch),
        ("Python call overhead (Const forecast, no work)", overhead),
    ]
    print("| what | µs | SciPy-cached / this | thesis / this |")
    print("|---|---:|---:|---:|")
    for name, seconds in rows:
        speedups = f"{ref_cached / seconds:.3g}x | {THESIS_FORECAST_SECONDS / seconds:.3g}x"
        print(f"| {name} | {seconds * 1e6:.2f} | {speedups} |")
    print(
        "\nbatch speed-up over a Python loop of the SciPy reference: "
        f"{ref_cached / batch:.0f}x (cached basis), {ref_plain / batch:.0f}x (as written)"
    )


if __name__ == "__main__":
    main()
