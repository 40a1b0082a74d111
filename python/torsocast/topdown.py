"""A top-down plot of the tracks: where each person walked, which way the torso faced, where the
forecaster says they will be, and where it put them while unseen (world x to the right, y up, 1 m
grid, the camera and its field of view). Drawn with Pillow, so it needs nothing beyond the
package's own dependencies."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt
from PIL import Image, ImageDraw, ImageFont

from .camera import Camera
from .overlay import COLOURS
from .pipeline import FrameResult

F64 = npt.NDArray[np.float64]

BACKGROUND, GRID, TRUTH = (255, 255, 255), (225, 225, 225), (150, 150, 150)
HEADING = 0.45  # m: drawn length of a heading arrow


def font(size: int = 14) -> ImageFont.ImageFont | ImageFont.FreeTypeFont:
    """Pillow's own scalable font where this Pillow has one (10.1 and later), else its bitmap."""
    try:
        return ImageFont.load_default(size=size)
    except TypeError:
        return ImageFont.load_default()


FONT = font()


@dataclass
class TrackHistory:
    times: list[float] = field(default_factory=list)
    poses: list[F64] = field(default_factory=list)
    forecasts: list[tuple[float, F64]] = field(default_factory=list)
    """(time made, ``(horizons, 5)``) of every frame that had one."""
    unseen: list[tuple[float, F64]] = field(default_factory=list)
    """(frame time, ``(5,)``) where the track's forecast put its person in each frame that did
    not show them."""


@dataclass
class TopDown:
    """Collects every frame's confirmed tracks (call it with each :class:`FrameResult`), then
    :meth:`draw` plots them."""

    camera: Camera | None = None
    tracks: dict[int, TrackHistory] = field(default_factory=dict)

    def __call__(self, result: FrameResult) -> None:
        if self.camera is None:
            self.camera = result.frame.camera
        for i, person in enumerate(result.people):
            obs = person.observation
            if person.track_id is None or obs is None or obs.pose is None:
                continue
            history = self.tracks.setdefault(person.track_id, TrackHistory())
            history.times.append(result.frame.time)
            history.poses.append(obs.pose)
            if i in result.forecasts:
                history.forecasts.append((result.frame.time, result.forecasts[i]))
        for track in result.unseen:
            if track.id in self.tracks and track.pose is not None:
                self.tracks[track.id].unseen.append((result.frame.time, track.pose))

    def draw(self, size: int = 480, truth: F64 | None = None, every: float = 0.5) -> Image.Image:
        """The plot, ``size`` pixels square. Headings are drawn every ``every`` seconds; the last
        forecast of each track is drawn in full (a dashed line to each horizon, with its heading),
        earlier ones as a faint dot at the last horizon; where a track put its person while unseen,
        as rings. ``truth (n, 2+)`` is drawn as a grey path underneath (for data with ground
        truth, like the demo)."""
        paths = [np.array(h.poses)[:, :2] for h in self.tracks.values() if h.poses]
        paths += [f[-1:, :2] for h in self.tracks.values() for _, f in h.forecasts[-1:]]
        paths += [np.array([p for _, p in h.unseen])[:, :2] for h in self.tracks.values() if h.unseen]
        if truth is not None:
            paths.append(np.asarray(truth)[:, :2])
        if self.camera is not None:
            paths.append(np.asarray(self.camera.camera_to_world)[None, :2, 3])
        points = np.vstack(paths) if paths else np.zeros((1, 2))
        low, high = points.min(axis=0) - 0.7, points.max(axis=0) + 0.7
        scale = (size - 20) / float(max(high - low))
        centre = 0.5 * (low + high)

        def px(p: F64) -> tuple[float, float]:
            return (size / 2 + (p[0] - centre[0]) * scale, size / 2 - (p[1] - centre[1]) * scale)

        image = Image.new("RGB", (size, size), BACKGROUND)
        pen = ImageDraw.Draw(image)
        half = size / 2 / scale
        for k in range(int(np.floor(centre[0] - half)), int(np.ceil(centre[0] + half)) + 1):
            pen.line([px(np.array([k, centre[1] - half])), px(np.array([k, centre[1] + half]))], fill=GRID)
        for k in range(int(np.floor(centre[1] - half)), int(np.ceil(centre[1] + half)) + 1):
            pen.line([px(np.array([centre[0] - half, k])), px(np.array([centre[0] + half, k]))], fill=GRID)
        pen.text((6, size - 20), "from above: grid 1 m, world x right, y up", fill=TRUTH, font=FONT)
        if self.camera is not None:
            self._camera(pen, px)
        if truth is not None:
            pen.line([px(p) for p in np.asarray(truth)[:, :2]], fill=TRUTH, width=3)
        for track_id, h in self.tracks.items():
            self._track(pen, px, track_id, h, every)
        return image

    def _camera(self, pen: ImageDraw.ImageDraw, px) -> None:  # type: ignore[no-untyped-def]
        assert self.camera is not None
        pose = np.asarray(self.camera.camera_to_world)
        k = self.camera.intrinsics
        origin = pose[:2, 3]
        for u in (0.0, 2 * k.cx):  # the edges of the field of view
            ray = (pose[:3, :3] @ np.array([(u - k.cx) / k.fx, 0.0, 1.0]))[:2]
            pen.line([px(origin), px(origin + 1.5 * ray / np.linalg.norm(ray))], fill=(0, 0, 0))
        u, v = px(origin)
        pen.rectangle([u - 5, v - 5, u + 5, v + 5], fill=(0, 0, 0))
        pen.text((u + 8, v + 2), "camera", fill=(0, 0, 0), font=FONT)

    @staticmethod
    def _track(pen: ImageDraw.ImageDraw, px, track_id: int, h: TrackHistory, every: float) -> None:  # type: ignore[no-untyped-def]
        colour = COLOURS[track_id % len(COLOURS)]
        faint = tuple(int(255 - 0.35 * (255 - c)) for c in colour)
        poses = np.array(h.poses)
        next_dot = -np.inf
        for made, ahead in h.forecasts[:-1]:
            if made >= next_dot:
                u, v = px(ahead[-1, :2])
                pen.ellipse([u - 2, v - 2, u + 2, v + 2], fill=faint)
                next_dot = made + every
        pen.line([px(p) for p in poses[:, :2]], fill=colour, width=2)
        for _, pose in h.unseen:
            u, v = px(pose[:2])
            pen.ellipse([u - 4, v - 4, u + 4, v + 4], outline=colour, width=1)
        next_arrow = h.times[0]
        for t, pose in zip(h.times, poses):
            if t >= next_arrow:
                _arrow(pen, px, pose, colour)
                next_arrow = t + every
        if h.forecasts:
            _, ahead = h.forecasts[-1]
            start = poses[-1]
            for pose in ahead:
                _dashed(pen, px(start[:2]), px(pose[:2]), colour)
                _arrow(pen, px, pose, colour, hollow=True)
                start = pose
        u, v = px(poses[-1, :2])
        pen.text((u + 6, v - 18), f"#{track_id}", fill=colour, font=FONT)


def _arrow(pen: ImageDraw.ImageDraw, px, pose: F64, colour, hollow: bool = False) -> None:  # type: ignore[no-untyped-def]
    """A dot at the torso centre and a line along the azimuth the chest faces."""
    tip = pose[:2] + HEADING * np.array([np.cos(pose[3]), np.sin(pose[3])])
    u, v = px(pose[:2])
    pen.line([(u, v), px(tip)], fill=colour, width=3)
    pen.ellipse([u - 3, v - 3, u + 3, v + 3], outline=colour, fill=None if hollow else colour)


def _dashed(
    pen: ImageDraw.ImageDraw, a: tuple[float, float], b: tuple[float, float], colour, dash: float = 6.0
) -> None:  # type: ignore[no-untyped-def]
    length = float(np.hypot(b[0] - a[0], b[1] - a[1]))
    steps = max(int(length / dash), 1)
    for k in range(0, steps, 2):
        s, e = k / steps, min((k + 1) / steps, 1.0)
        pen.line(
            [
                (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])),
                (a[0] + e * (b[0] - a[0]), a[1] + e * (b[1] - a[1])),
            ],
            fill=colour,
            width=2,
        )
