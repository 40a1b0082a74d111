"""What a replay of recorded detections can put right by the truth before tracking: upper
bounds and diagnostics, not results.

**The labels** (``--oracle-labels``). How much of the front/back flips is the keypoint model's
labelling of the body's sides, and how much the track's own choice of side? Replaying a split's
recorded detections with every wrong pair of labels exchanged answers it: whatever flips remain,
no cue to the labels (the face, the knees, a flip test of the detector) could remove. A pair is
judged on its lifted joints: the normal of the pair's line, (left - right) x up, on the side of
the person's true heading or not. The shoulders and the hips are judged each on their own; the
other pairs (eyes, ears, arms, legs) follow the shoulders, or the hips where the shoulders are
not both seen. The plane is fitted later, after the gate and the far joint's depth completion,
so the bound is approximate.

**The joints** (``--oracle-joints``). How many flips are the heading rules' own, and which
joints' measurements the rest come from? Each lifted joint of the named groups that the
detector saw is put at the true joint's 3D position (its centre, where the depth camera reads
the body's surface); everything else stays as recorded: which joints were seen, their scores,
the keypoints and the other joints.

**The pixels** (``--oracle-pixels``). How many flips would a perfect 2D keypoint model leave?
Each seen joint of the named groups has its keypoint put at the true joint's pixel (its centre
projected into the image) and is lifted again there, by the core's own depth lookup, from the
frame's depth image rendered again: the depth read at a joint's true pixel is whatever surface
shows there (a thigh in front of a hip, the near side of the body in profile). The flips left
are the depth's and the rules', not the keypoints'. It renders every frame again, so it takes
minutes where a replay takes seconds (the model is not run).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ...datasets import cmu
from ...keypoints import coco
from ...sources import Frame
from ...tracker import Tracker, TrackerConfig

F64 = npt.NDArray[np.float64]

#: The pairs judged on their own: the shoulders, then the hips.
JUDGED = ((coco.LEFT_SHOULDER, coco.RIGHT_SHOULDER), (coco.LEFT_HIP, coco.RIGHT_HIP))

#: The joint groups ``--oracle-joints`` puts at the truth: COCO keypoint -> CMU skeleton joint.
JOINT_GROUPS: dict[str, dict[int, int]] = {
    "shoulders": {coco.LEFT_SHOULDER: cmu.LEFT_SHOULDER, coco.RIGHT_SHOULDER: cmu.RIGHT_SHOULDER},
    "hips": {coco.LEFT_HIP: cmu.LEFT_HIP, coco.RIGHT_HIP: cmu.RIGHT_HIP},
    "legs": {
        coco.INDEX["left_knee"]: cmu.LEFT_KNEE,
        coco.INDEX["right_knee"]: cmu.RIGHT_KNEE,
        coco.INDEX["left_ankle"]: cmu.LEFT_ANKLE,
        coco.INDEX["right_ankle"]: cmu.RIGHT_ANKLE,
    },
}


@dataclass(frozen=True)
class Oracle:
    """What a replay puts right by the truth: the detector's left/right labels, the joint groups
    (names of :data:`JOINT_GROUPS`) put at their true positions, and those lifted from their
    true pixels. Empty: nothing."""

    labels: bool = False
    joints: tuple[str, ...] = ()
    pixels: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        for option, groups in (("--oracle-joints", self.joints), ("--oracle-pixels", self.pixels)):
            unknown = [g for g in groups if g not in JOINT_GROUPS]
            if unknown:
                known = ", ".join(JOINT_GROUPS)
                raise ValueError(f"{option}: unknown joint group {unknown[0]!r} (expected some of {known})")
        both = [g for g in self.pixels if g in self.joints]
        if both:
            raise ValueError(
                f"--oracle-joints and --oracle-pixels both name {both[0]!r}: a joint is put at "
                "the truth or lifted from its true pixel, not both"
            )

    def __bool__(self) -> bool:
        return self.labels or bool(self.joints) or bool(self.pixels)

    @classmethod
    def parse(cls, labels: bool, joints: str | None, pixels: str | None = None) -> Oracle:
        """From the command line: ``joints`` and ``pixels`` comma-separated lists of group
        names, or None."""

        def groups(text: str | None) -> tuple[str, ...]:
            return tuple(g.strip() for g in text.split(",")) if text else ()

        return cls(labels, groups(joints), groups(pixels))

    @property
    def options(self) -> str:
        """The command-line options that ask for it, as a user typed them."""
        asked = {"labels": self.labels, "joints": self.joints, "pixels": self.pixels}
        return " and ".join(f"--oracle-{o}" for o, on in asked.items() if on)

    def notes(self) -> list[str]:
        """What the report says it is."""
        out = []
        if self.labels:
            out.append(
                "the detector's left/right labels put right by the truth (--oracle-labels): "
                "a bound, not a result"
            )
        if self.joints:
            out.append(
                f"the seen {', '.join(self.joints)} joints put at the truth's (--oracle-joints): "
                "a diagnostic, not a result"
            )
        if self.pixels:
            out.append(
                f"the seen {', '.join(self.pixels)} joints lifted from their true pixels "
                "(--oracle-pixels): a diagnostic, not a result"
            )
        return out

    def apply(
        self,
        keypoints: F64,
        joints: F64,
        owner: list[int],
        truth: F64,
        skeletons: list[F64 | None],
        frame: Frame | None = None,
        config: TrackerConfig | None = None,
    ) -> None:
        """Puts, in place, one frame's recorded detections right as asked (``truth``: people x
        pose; ``skeletons``: each person's skeleton at that time, None where absent; ``frame``:
        the frame rendered again, with its depth image, and ``config`` the pipeline's, whose
        depth lookup lifts: both needed by the pixels' oracle only)."""
        if self.pixels:
            if frame is None or config is None:
                raise ValueError("--oracle-pixels needs each frame rendered again and the pipeline's config")
            lift_at_true_pixels(keypoints, joints, owner, skeletons, self.pixels, frame, config)
        if self.labels:
            put_labels_right(keypoints, joints, owner, truth)
        if self.joints:
            put_joints_at_truth(joints, owner, skeletons, self.joints)


#: Nothing put right: a replay as recorded.
NO_ORACLE = Oracle()


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


def seen_true_joints(
    joints: F64, owner: list[int], skeletons: list[F64 | None], groups: tuple[str, ...]
) -> Iterator[tuple[int, int, F64]]:
    """Each seen (finite) joint of the :data:`JOINT_GROUPS` ``groups`` of every detection owned
    by a person (``owner``: person index or -1) with that person's true joint
    (``skeletons[person]``: the CMU skeleton, ``(38, 3)``; None: the person is absent, nothing
    given): ``(detection, keypoint, true position)``."""
    mapping = {c: j for g in groups for c, j in JOINT_GROUPS[g].items()}
    for d, person in enumerate(owner):
        skeleton = skeletons[person] if person >= 0 else None
        if skeleton is None:
            continue
        for c, j in mapping.items():
            if np.isfinite(joints[d, c]).all():
                yield d, c, skeleton[j]


def put_joints_at_truth(
    joints: F64, owner: list[int], skeletons: list[F64 | None], groups: tuple[str, ...]
) -> int:
    """Moves, in place, each of :func:`seen_true_joints` to the truth; returns how many moved."""
    moved = 0
    for d, c, truth in seen_true_joints(joints, owner, skeletons, groups):
        joints[d, c] = truth
        moved += 1
    return moved


def lift_at_true_pixels(
    keypoints: F64,
    joints: F64,
    owner: list[int],
    skeletons: list[F64 | None],
    groups: tuple[str, ...],
    frame: Frame,
    config: TrackerConfig,
) -> int:
    """Puts, in place, each of :func:`seen_true_joints` at its true pixel (the true joint
    projected into ``frame``'s image; the keypoint's score kept) and lifts it there with
    ``config``'s depth lookup from ``frame``'s depth image, as :meth:`Tracker.step` lifts
    keypoints: NaN where the pixel reads no depth or lies off the image, or the joint is behind
    the camera. Returns how many joints were lifted again."""
    assert frame.camera is not None and frame.depth is not None
    k = frame.camera.intrinsics
    asked = np.zeros((len(owner), len(coco.KEYPOINTS), 3))
    chosen: list[tuple[int, int]] = []
    for d, c, truth in seen_true_joints(joints, owner, skeletons, groups):
        optical = frame.camera.to_optical(truth)
        chosen.append((d, c))
        if optical[2] > 0.0:
            asked[d, c, :2] = k.project(optical)
            asked[d, c, 2] = 1.0
    if not chosen:
        return 0
    # A tracker of its own lifts them: the core's lookup and deprojection, none of its tracks.
    lifter = Tracker(config)
    lifter.step(
        frame.time,
        asked,
        frame.depth,
        (k.fx, k.fy, k.cx, k.cy),
        k.coefficients,
        frame.camera.camera_to_world,
        None,
    )
    lifted = lifter.lifted
    for d, c in chosen:
        keypoints[d, c, :2] = asked[d, c, :2]
        joints[d, c] = lifted[d, c] if asked[d, c, 2] > 0 else np.nan
    return len(chosen)
