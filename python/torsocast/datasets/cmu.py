"""CMU motion-capture walking clips (the exp-map text format of Li et al. 2018) as 3D joints.

One frame per line, 117 numbers at 120 Hz: the root (Hips) position, absolute, y up, in CMU units,
then 38 exponential maps (joint 0 is the root's rotation, also absolute). The skeleton below is
that of DMGNN's ``_some_variables`` (offsets unscaled).
:func:`load_clip` turns a file into ``(frames, 38, 3)`` joints in metres in the REP-103 world
frame (x forward, y left, z up) that the rest of torsocast uses.

The CMU Graphics Lab data may be used freely, including in products: six walking clips ship with
torsocast as demo data (``torsocast/data/cmu/``, see the README there).
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path

import numpy as np
import numpy.typing as npt

from .kinematics import chain, expmap_to_rotmat

F64 = npt.NDArray[np.float64]

RATE_HZ = 120.0
#: Metres per CMU unit (the CMU convention, (1/0.45) inch; legs, hip width and walking speeds agree).
UNIT_M = 0.056444
COLUMNS = 3 + 38 * 3

PARENTS = np.array(
    [-1, 0, 1, 2, 3, 4, 5, 0, 7, 8, 9, 10, 11, 0, 13, 14, 15, 16, 17, 18, 15, 20, 21, 22, 23, 24, 25, 23]
    + [27, 15, 29, 30, 31, 32, 33, 34, 32, 36]
)
#: Offsets in the parent's frame, CMU units; the rest pose faces +z with the subject's left at +x.
OFFSETS = np.array(
    [
        [0, 0, 0],
        [0, 0, 0],
        [1.65674, -1.80282, 0.62477],
        [2.59720, -7.13576, 0],
        [2.49236, -6.84770, 0],
        [0.19704, -0.54136, 2.14581],
        [0, 0, 1.11249],
        [0, 0, 0],
        [-1.61070, -1.80282, 0.62476],
        [-2.59502, -7.12977, 0],
        [-2.46780, -6.78024, 0],
        [-0.23024, -0.63258, 2.13368],
        [0, 0, 1.11569],
        [0, 0, 0],
        [0.01961, 2.05450, -0.14112],
        [0.01021, 2.06436, -0.05921],
        [0, 0, 0],
        [0.00713, 1.56711, 0.14968],
        [0.03429, 1.56041, -0.10006],
        [0.01305, 1.62560, -0.05265],
        [0, 0, 0],
        [3.54205, 0.90436, -0.17364],
        [4.86513, 0, 0],
        [3.35554, 0, 0],
        [0, 0, 0],
        [0.66117, 0, 0],
        [0.53306, 0, 0],
        [0, 0, 0],
        [0.54120, 0, 0.54120],
        [0, 0, 0],
        [-3.49802, 0.75994, -0.32616],
        [-5.02649, 0, 0],
        [-3.36431, 0, 0],
        [0, 0, 0],
        [-0.73041, 0, 0],
        [-0.58887, 0, 0],
        [0, 0, 0],
        [-0.59786, 0, 0.59786],
    ]
)

# Joint roles in DMGNN's 38-joint CMU skeleton.
PELVIS, LEFT_HIP, LEFT_KNEE, LEFT_ANKLE, LEFT_TOE, LEFT_TOE_END = 0, 2, 3, 4, 5, 6
RIGHT_HIP, RIGHT_KNEE, RIGHT_ANKLE, RIGHT_TOE, RIGHT_TOE_END = 8, 9, 10, 11, 12
THORAX, NECK, HEAD, HEAD_TOP = 15, 17, 18, 19
LEFT_SHOULDER, LEFT_ELBOW, LEFT_WRIST, LEFT_FINGERS = 21, 22, 23, 25
RIGHT_SHOULDER, RIGHT_ELBOW, RIGHT_WRIST, RIGHT_FINGERS = 30, 31, 32, 34
#: Shoulders and hips, in the order of :data:`torsocast.keypoints.coco.TORSO`.
TORSO = (LEFT_SHOULDER, RIGHT_SHOULDER, LEFT_HIP, RIGHT_HIP)

#: CMU (x, y, z) with y up to REP-103 (x forward, y left, z up): a cyclic permutation, so a
#: rotation (left stays left).
CMU_TO_WORLD = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])

BUNDLED_DIR = "data/cmu"


def bundled_clips() -> dict[str, Path]:
    """The clips that ship with torsocast, by name (``test_walking_1``, ``train_walking_1`` ...)."""
    folder = Path(str(files("torsocast") / BUNDLED_DIR))
    return {p.stem: p for p in sorted(folder.glob("*.txt"))}


def read_clip(path: str | Path) -> F64:
    """The ``(frames, 117)`` numbers of a clip file, checked."""
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such CMU clip file")
    if not path.read_text().strip():
        raise ValueError(f"{path}: the clip file is empty")
    rows = np.loadtxt(path, delimiter=",", ndmin=2)
    if rows.shape[1] != COLUMNS:
        raise ValueError(f"{path}: expected {COLUMNS} comma-separated numbers per line, got {rows.shape[1]}")
    if len(rows) < 2 or not np.isfinite(rows).all():
        raise ValueError(f"{path}: needs at least two frames of finite numbers")
    return rows


def forward_kinematics(rows: F64) -> F64:
    """``(frames, 38, 3)`` joints in CMU units and axes (y up). Root position and rotation are
    absolute, unlike Human3.6M's increments."""
    rotations = expmap_to_rotmat(rows[:, 3:].reshape(len(rows), 38, 3))
    return chain(PARENTS, OFFSETS, rotations[:, 0], rows[:, :3], rotations)


def load_clip(path: str | Path) -> F64:
    """A clip as ``(frames, 38, 3)`` world joints in metres (REP-103, z up, floor near z = 0), at
    :data:`RATE_HZ`. The file's first line is the BVH rest pose (arms out, every rotation zero),
    not part of the motion: it is left out."""
    return forward_kinematics(read_clip(path)[1:]) @ CMU_TO_WORLD.T * UNIT_M
