"""Pictures of a frame's result: keypoints and skeleton, the torso normal as an arrow from the
torso centre, and the forecast heading at the last horizon (a thin white line from the forecast
centre), drawn on the colour image. A confirmed track the frame did not show is drawn where its
forecast puts the person: a ring as wide as the centre's 80 % interval, with its heading."""

from __future__ import annotations

import numpy as np
from PIL import Image, ImageDraw

from .pipeline import FrameResult, UnseenTrack
from .tracker import PersonConfig

#: Skeleton edges between COCO keypoints.
EDGES = (
    (5, 6),
    (5, 7),
    (7, 9),
    (6, 8),
    (8, 10),
    (5, 11),
    (6, 12),
    (11, 12),
    (11, 13),
    (13, 15),
    (12, 14),
    (14, 16),
)
COLOURS = ((230, 25, 75), (60, 180, 75), (0, 130, 200), (245, 130, 48), (145, 30, 180), (70, 240, 240))
ARROW = 0.35  # m: length of the drawn normal


def _heading(azimuth: float, elevation: float) -> np.ndarray:
    return np.array(
        [np.sin(elevation) * np.cos(azimuth), np.sin(elevation) * np.sin(azimuth), np.cos(elevation)]
    )


def _projector(camera):  # type: ignore[no-untyped-def]
    """World point -> pixel of ``camera``."""

    def to_pixel(p: np.ndarray) -> tuple[float, float]:
        return tuple(camera.intrinsics.project(camera.to_optical(p)))  # type: ignore[return-value]

    return to_pixel


def draw(result: FrameResult, min_score: float | None = None) -> Image.Image:
    """The colour image with every person drawn; a person's colour follows its track id. Keypoints
    scored below ``min_score`` (default: the tracker's, ``PersonConfig.min_score``) are left out."""
    if min_score is None:
        min_score = PersonConfig().min_score
    image = Image.fromarray(result.frame.color)
    pen = ImageDraw.Draw(image)
    camera = result.frame.camera
    for i, kp in enumerate(result.detections.keypoints):
        person = result.people[i] if result.people else None
        track_id = person.track_id if person is not None else None
        colour = COLOURS[(track_id or 0) % len(COLOURS)] if track_id else (200, 200, 200)
        for a, b in EDGES:
            if kp[a, 2] >= min_score and kp[b, 2] >= min_score:
                pen.line([tuple(kp[a, :2]), tuple(kp[b, :2])], fill=colour, width=3)
        for u, v, s in kp:
            if s >= min_score:
                pen.ellipse([u - 3, v - 3, u + 3, v + 3], fill=colour)
        obs = person.observation if person is not None else None
        if camera is None or obs is None or obs.pose is None:
            continue
        to_pixel = _projector(camera)
        centre = obs.pose[:3]
        start = to_pixel(centre)
        pen.line([start, to_pixel(centre + ARROW * _heading(obs.pose[3], obs.pose[4]))], fill=colour, width=5)
        ahead = result.forecasts.get(i)
        if ahead is not None:
            end = to_pixel(ahead[-1, :3] + ARROW * _heading(ahead[-1, 3], ahead[-1, 4]))
            pen.line([to_pixel(ahead[-1, :3]), end], fill=(255, 255, 255), width=2)
        label = f"#{track_id} " if track_id else ""
        pen.text(
            (start[0] + 6, start[1] + 6), f"{label}{np.degrees(obs.pose[3]):.0f}° {obs.estimate}", fill=colour
        )
    if camera is not None:
        for track in result.unseen:
            _unseen(pen, camera, track, result.frame.time, image.size)
    return image


def _unseen(pen: ImageDraw.ImageDraw, camera, track: UnseenTrack, t: float, size: tuple[int, int]) -> None:  # type: ignore[no-untyped-def]
    """A ring round where ``track``'s forecast puts its person, as wide as the 80 % interval of the
    centre's horizontal position (a small ring while the track has none); nothing where that point
    lies behind the camera or outside the picture."""
    if track.pose is None:
        return
    centre = track.pose[:3]
    depth = float(camera.to_optical(centre)[2])
    if depth <= 0.0:
        return
    u, v = _projector(camera)(centre)
    if not (0.0 <= u < size[0] and 0.0 <= v < size[1]):
        return
    colour = COLOURS[track.id % len(COLOURS)]
    spread = 0.0 if track.half_width80 is None else float(np.hypot(*track.half_width80[:2]))
    radius = max(camera.intrinsics.fx * spread / depth, 6.0)
    pen.ellipse([u - radius, v - radius, u + radius, v + radius], outline=colour, width=2)
    tip = _projector(camera)(centre + ARROW * _heading(track.pose[3], track.pose[4]))
    pen.line([(u, v), tip], fill=colour, width=2)
    pen.text((u + 6, v + 6), f"#{track.id} unseen {max(t - track.last_time, 0.0):.1f} s", fill=colour)
