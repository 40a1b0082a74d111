"""``torsocast demo``: the main job on data that ships with the package, checked against ground
truth, shown as a picture and a table.

A CMU mocap walk (free data, bundled) is rendered as RGB-D frames by a virtual Kinect-like camera
(:mod:`torsocast.synthetic.mocap`); the bundled MoveNet model finds the person, the depth lifts the
keypoints to 3D, the tracker follows them and the forecaster looks ahead. Because the walk is
mocap, the true torso pose is known at every instant, so the demo reports how far the estimates
and the forecasts are from it (and how far "the person stays where they are" would be).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import numpy.typing as npt
from PIL import Image, ImageDraw

from . import wrap_angle
from .keypoints import open_model
from .overlay import draw
from .pipeline import HORIZONS, FrameResult
from .run import Summary, run
from .synthetic.mocap import MocapScene
from .topdown import FONT, TopDown

F64 = npt.NDArray[np.float64]

DEFAULT_CLIP = "test_walking_1"


@dataclass
class TruthCheck:
    """Compares every frame's estimate, and every forecast once its time has come, with the true
    torso pose ``truth (n, 5)`` sampled at ``rate_hz`` from time 0."""

    truth: F64
    rate_hz: float
    horizons: Sequence[float]
    azimuth_errors: list[float] = field(default_factory=list)
    centre_errors: list[float] = field(default_factory=list)
    missing: int = 0
    forecast_errors: dict[float, list[tuple[float, float, float, float]]] = field(default_factory=dict)
    """Horizon -> (centre error, azimuth error) of the forecast and of holding the current pose."""
    last: FrameResult | None = None
    """The latest frame whose every forecast could be checked (the picture shows it)."""

    def at(self, t: float) -> F64 | None:
        k = int(round(t * self.rate_hz))
        return self.truth[k] if 0 <= k < len(self.truth) else None

    def __call__(self, result: FrameResult) -> None:
        now = self.at(result.frame.time)
        person = next((p for p in result.people if p.observation is not None), None)
        pose = None if person is None or person.observation is None else person.observation.pose
        if pose is None or now is None:
            self.missing += 1
            return
        self.azimuth_errors.append(abs(float(wrap_angle(pose[3] - now[3]))))
        self.centre_errors.append(float(np.linalg.norm(pose[:2] - now[:2])))
        ahead = result.forecasts.get(person.detection) if person is not None else None
        if ahead is None or person is None or person.last_time is None:
            return
        origin = person.last_time  # forecasts count from the last grid sample
        checked = 0
        for h, predicted in zip(self.horizons, ahead):
            then = self.at(origin + h)
            if then is not None:
                checked += 1
                self.forecast_errors.setdefault(h, []).append(
                    (
                        float(np.linalg.norm(predicted[:2] - then[:2])),
                        abs(float(wrap_angle(predicted[3] - then[3]))),
                        float(np.linalg.norm(pose[:2] - then[:2])),
                        abs(float(wrap_angle(pose[3] - then[3]))),
                    )
                )
        if checked == len(self.horizons):
            self.last = result

    def table(self) -> str:
        az = np.degrees(self.azimuth_errors)
        lines = [
            f"torso estimate, {len(az)} frames ({self.missing} without one): azimuth error median "
            f"{np.median(az):.1f} deg, 90th percentile {np.percentile(az, 90):.1f} deg; centre error "
            f"median {100 * np.median(self.centre_errors):.0f} cm",
            "",
            "median errors of the forecasts against the true future pose, and of holding the current",
            "estimate still instead:",
            "",
            "| horizon | forecasts | centre | centre, held | azimuth | azimuth, held |",
            "|---|---|---|---|---|---|",
        ]
        for h, rows in sorted(self.forecast_errors.items()):
            e = np.median(np.array(rows), axis=0)
            lines.append(
                f"| {h:g} s | {len(rows)} | {100 * e[0]:.0f} cm | {100 * e[2]:.0f} cm "
                f"| {np.degrees(e[1]):.1f} deg | {np.degrees(e[3]):.1f} deg |"
            )
        return "\n".join(lines)


@dataclass
class DemoResult:
    summary: Summary
    check: TruthCheck
    picture: Path

    def __str__(self) -> str:
        return f"{self.summary}\n\n{self.check.table()}\n\npicture: {self.picture}"


def demo(
    out: str | Path = "demo",
    clip: str = DEFAULT_CLIP,
    horizons: Sequence[float] = HORIZONS,
    model: str | Path | None = None,
    overlay: bool = False,
    progress: bool = True,
    video: bool = False,
) -> DemoResult:
    """Runs the pipeline on a bundled walk (``clip``: a bundled name or a CMU file) and writes
    ``out/frames.jsonl`` and ``out/demo.png`` (the latest frame whose forecasts could all be
    checked, beside the top-down plot); ``overlay`` and ``video`` as in :func:`~torsocast.run.run`."""
    out = Path(out)
    source = MocapScene.from_clip(clip)
    check = TruthCheck(source.truth, source.rate_hz, list(horizons))
    plot = TopDown(source.camera)
    summary = run(source, open_model(model), out, horizons, overlay, progress, (check, plot), video)
    picture = out / "demo.png"
    compose(check.last, plot.draw(truth=check.truth), source.name).save(picture)
    return DemoResult(summary, check, picture)


def compose(result: FrameResult | None, plot: Image.Image, title: str) -> Image.Image:
    """The camera's view of ``result`` (with keypoints, torso normal and forecast heading) beside
    the top-down ``plot``, scaled to the same height, with a caption."""
    view = draw(result) if result is not None else Image.new("RGB", plot.size, (255, 255, 255))
    view = view.resize((round(view.width * plot.height / view.height), plot.height))
    caption = 24
    sheet = Image.new("RGB", (view.width + plot.width, plot.height + caption), (255, 255, 255))
    sheet.paste(view, (0, caption))
    sheet.paste(plot, (view.width, caption))
    ImageDraw.Draw(sheet).text(
        (6, 4),
        f"torsocast demo: {title}. Left: camera view, torso normal (thick) and forecast heading. "
        "Right: from above, truth (grey), track, forecast (dashed).",
        fill=(0, 0, 0),
        font=FONT,
    )
    return sheet
