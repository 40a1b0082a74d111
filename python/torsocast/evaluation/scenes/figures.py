"""The benchmark's figures: azimuth error against the view angle (polar), forecast error against
the horizon, and one rendered frame with its keypoints, torso normals and forecast headings."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ...overlay import draw
from .report import METHOD_NAMES
from .run import Benchmark
from .score import COMPONENTS, METHODS
from .tables import UNIT


def draw_all(bench: Benchmark, t: dict[str, Any], folder: Path) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    if bench.picture is not None:
        path = folder / "scenes_frame.png"
        draw(bench.picture).save(path)
        written.append(path)
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.projections.polar import PolarAxes
    except ImportError:
        return written
    views = [r for r in t["recovery"]["view"] if r["person_frames"]]
    if views:
        fig = plt.figure(figsize=(5.5, 5))
        ax = fig.add_subplot(projection="polar")
        assert isinstance(ax, PolarAxes)
        order = sorted(views, key=lambda r: float(r["group"]) % 360)
        theta = np.radians([float(r["group"]) for r in order] + [float(order[0]["group"])])
        for key, style, label in (
            ("azimuth_median", "-o", "median"),
            ("azimuth_p90", "--o", "90th percentile"),
        ):
            values = [r[key] for r in order] + [order[0][key]]
            ax.plot(theta, values, style, label=f"azimuth error, {label} (deg)")
        flips = [100 * r["flips"] for r in order] + [100 * order[0]["flips"]]
        ax.plot(theta, flips, ":s", label="flips (% of frames)")
        ax.set_theta_zero_location("N")
        ax.set_title(f"Azimuth error by view ({bench.split} split)\n0 = facing the camera, 180 = turned away")
        ax.legend(loc="lower left", bbox_to_anchor=(-0.15, -0.2), fontsize=8)
        fig.tight_layout()
        path = folder / "scenes_view_polar.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)
    rows = t["forecasts"]["all"]
    if rows:
        fig, axes = plt.subplots(1, 3, figsize=(12, 3.6))
        horizons = [r["horizon"] for r in rows]
        for ax, component in zip(axes, COMPONENTS):
            for method in METHODS:
                ax.plot(
                    horizons,
                    [r[f"{method}_{component}_median"] for r in rows],
                    "-o",
                    label=METHOD_NAMES[method],
                )
            ax.set_xlabel("horizon (s)")
            ax.set_ylabel(f"median error ({UNIT[component]})")
            ax.set_title(component)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=8)
        fig.suptitle(f"Forecast error against the horizon ({bench.split} split)")
        fig.tight_layout()
        path = folder / "scenes_horizon.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        written.append(path)
    return written
