"""Do the keypoint models see the rendered people as they see real ones?

For one model, the mean keypoint score of the face (nose, eyes, ears), the shoulders and the
hips in front, profile and back views, and how often the shoulders are labelled the right way
round, on the real turntable sequence (a person turning through 360 degrees, with the turn
measured) and on single people rendered by the benchmark. A model that finds a face on the back
of a real head and not on the mannequin's, or that labels the sides of one and not the other
(or the reverse), would make the benchmark's flip rates a property of the renderer rather than
of torsocast.

``python -m torsocast.evaluation.scenes.realism --turntable DIR [--yolo PATH]`` prints the tables.
"""

from __future__ import annotations

import argparse
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import numpy.typing as npt

from ... import wrap_angle
from ...keypoints import KeypointModel, coco, open_model
from ...sources import SkippedFrame, open_source
from ...synthetic.scenes import RenderedScene
from .plan import CMU_ENV, H36M_ENV, Catalogue, Size, data_folder, draw_scene
from .score import assign, view_angle

F64 = npt.NDArray[np.float64]

#: Keypoint groups reported (COCO indices).
GROUPS = {"nose": (0,), "eyes": (1, 2), "ears": (3, 4), "shoulders": (5, 6), "hips": (11, 12)}
VIEWS = ("front", "profile", "back")


def view_class(degrees: float) -> str:
    """Front within 45 degrees of facing the camera, back within 45 of facing away."""
    a = abs(degrees)
    return "front" if a < 45 else "back" if a > 135 else "profile"


def turntable_views(folder: str | Path) -> Iterator[tuple[npt.NDArray[np.uint8], float]]:
    """Colour frames of the turntable and the person's view angle (0 at frame 0, facing)."""
    for frame in open_source(folder):
        if isinstance(frame, SkippedFrame):
            continue  # a frame that cannot be read has no view to score
        r = frame.extra["R"]
        yield frame.color, float(np.degrees(wrap_angle(np.arctan2(r[0, 2], r[0, 0]))))


def rendered_views(
    catalogue: Catalogue, seed: int, scenes: int, every: int = 3
) -> Iterator[tuple[npt.NDArray[np.uint8], float, npt.NDArray[np.int8]]]:
    """Frames of single-person benchmark scenes in which the person is visible, with the view
    angle and the label image."""
    for index in range(scenes):
        spec = draw_scene(catalogue, index, seed, Size(scenes, 3.0), people=1)
        scene = RenderedScene(spec, {a.motion: catalogue.motion(a.motion) for a in spec.actors})
        camera = np.asarray(scene.camera.camera_to_world)[:2, 3]
        for k, frame in enumerate(scene):
            if k % every == 0 and scene.visible(frame)[0]:
                yield frame.color, view_angle(frame.extra["truth"][0], camera), frame.extra["labels"]


def sides_right(keypoints: F64, view: str, min_score: float = 0.3) -> float:
    """Share of the detections ``(n, 17, 3)`` whose shoulders, both scored at least
    ``min_score``, are labelled the right way round in the image: the left shoulder on the
    camera's right from the front, on its left from behind (NaN for profile views, or none)."""
    if view == "profile":
        return float("nan")
    left, right = coco.LEFT_SHOULDER, coco.RIGHT_SHOULDER
    seen = (keypoints[:, [left, right], 2] >= min_score).all(axis=1)
    left_on_right = keypoints[seen, left, 0] > keypoints[seen, right, 0]
    return float(np.mean(left_on_right == (view == "front"))) if seen.any() else float("nan")


def summarise(samples: dict[str, list[F64]]) -> dict[str, dict[str, float]]:
    """View -> keypoint group -> mean score, ``sides`` (:func:`sides_right`) and ``frames``."""
    out = {}
    for view in VIEWS:
        rows = np.array(samples.get(view, [])).reshape(-1, 17, 3)
        out[view] = {
            g: float(rows[:, list(i), 2].mean()) if len(rows) else float("nan") for g, i in GROUPS.items()
        }
        out[view]["sides"] = sides_right(rows, view)
        out[view]["frames"] = float(len(rows))
    return out


def measure(
    model: KeypointModel, turntable: str | Path | None, catalogue: Catalogue, seed: int = 0, scenes: int = 12
) -> dict[str, dict[str, dict[str, float]]]:
    """``{"turntable": ..., "rendered": ...}`` (:func:`summarise`) of the most confident
    detection on the turntable and of the detection on the rendered person."""
    real: dict[str, list[F64]] = {}
    if turntable is not None:
        for image, view in turntable_views(turntable):
            found = model(image)
            if len(found):
                real.setdefault(view_class(view), []).append(found.keypoints[0])
    rendered: dict[str, list[F64]] = {}
    for image, view, labels in rendered_views(catalogue, seed, scenes):
        found = model(image)
        owner = assign(found.keypoints, labels, 0.3)
        if 0 in owner:
            rendered.setdefault(view_class(view), []).append(found.keypoints[owner.index(0)])
    return {"turntable": summarise(real), "rendered": summarise(rendered)}


def markdown(name: str, scores: dict[str, dict[str, dict[str, float]]]) -> str:
    columns = [*GROUPS, "sides"]
    lines = [
        f"| {name} | frames | " + " | ".join(GROUPS) + " | sides right |",
        "|---|---:|" + "---:|" * len(columns),
    ]
    for source, by_view in scores.items():
        for view in VIEWS:
            s = by_view[view]
            cells = " | ".join("–" if not np.isfinite(s[g]) else f"{s[g]:.2f}" for g in columns)
            lines.append(f"| {source}, {view} | {int(s['frames'])} | {cells} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--turntable", help="the turntable RGB-D folder")
    parser.add_argument("--yolo", help="also measure this YOLO-pose model")
    parser.add_argument("--cmu", help=f"CMU mocap folder (default: ${CMU_ENV})")
    parser.add_argument("--h36m", help=f"Human3.6M folder (default: ${H36M_ENV})")
    parser.add_argument("--scenes", type=int, default=12)
    args = parser.parse_args(argv)
    catalogue = Catalogue.find("dev", data_folder(args.cmu, CMU_ENV), data_folder(args.h36m, H36M_ENV))
    models = [("MoveNet (bundled)", None)] + ([(Path(args.yolo).stem, args.yolo)] if args.yolo else [])
    for name, path in models:
        print(markdown(name, measure(open_model(path), args.turntable, catalogue, scenes=args.scenes)) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
