"""The detector's left/right labels put right by the truth: an upper bound, not a result.

How much of the front/back flips is the keypoint model's labelling of the body's sides, and how
much the track's own choice of side? Replaying a split's recorded detections with every wrong
pair of labels exchanged answers it: whatever flips remain, no cue to the labels (the face, the
knees, a flip test of the detector) could remove. A pair is judged on its lifted joints: the
normal of the pair's line, (left - right) x up, on the side of the person's true heading or not.
The shoulders and the hips are judged each on their own; the other pairs (eyes, ears, arms,
legs) follow the shoulders, or the hips where the shoulders are not both seen. The plane is
fitted later, after the gate and the far joint's depth completion, so the bound is approximate.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from ...keypoints import coco

#: The pairs judged on their own: the shoulders, then the hips.
JUDGED = ((coco.LEFT_SHOULDER, coco.RIGHT_SHOULDER), (coco.LEFT_HIP, coco.RIGHT_HIP))


def pair_is_right(joints: npt.NDArray[np.float64], left: int, right: int, heading: float) -> bool | None:
    """Whether the normal of the line from ``right`` to ``left`` (world, z up), (left - right) x
    up, lies on the side of the true ``heading`` (azimuth, rad); None where either joint is not
    seen, or where the two lie one above the other (the line has no horizontal normal)."""
    if not np.isfinite(joints[[left, right]]).all():
        return None
    d = joints[left] - joints[right]
    if d[0] == 0.0 and d[1] == 0.0:
        return None
    normal = (d[1], -d[0])  # (left - right) x up, horizontally
    return bool(np.cos(np.arctan2(normal[1], normal[0]) - heading) > 0)


def put_labels_right(
    keypoints: npt.NDArray[np.float64],
    joints: npt.NDArray[np.float64],
    owner: list[int],
    truth: npt.NDArray[np.float64],
) -> int:
    """Exchanges, in place, the wrong left/right pairs of every detection owned by a person with
    a true pose (``owner``: person index or -1; ``truth``: people x pose); returns how many
    detections had a pair exchanged."""
    changed = 0
    for d, person in enumerate(owner):
        if person < 0 or not np.isfinite(truth[person]).all():
            continue
        verdict = {pair: pair_is_right(joints[d], *pair, truth[person][3]) for pair in JUDGED}
        if False not in verdict.values():
            continue  # nothing judged wrong (or nothing seen)
        shoulders, hips = verdict.values()
        rest = shoulders if shoulders is not None else hips
        for left, right in coco.LEFT_RIGHT_PAIRS:
            right_way = verdict.get((left, right))
            if not (rest if right_way is None else right_way):
                for a in (keypoints[d], joints[d]):
                    a[[left, right]] = a[[right, left]]
        changed += 1
    return changed
