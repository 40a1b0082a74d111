"""Mocap clips as the renderer's input: ``(frames, 38, 3)`` world joints in the CMU layout
(REP-103, z up, metres, feet on the floor at z = 0), from the CMU clips or from Human3.6M.

Human3.6M's 32-joint skeleton is mapped onto the CMU joints the mannequin is built from (pelvis,
hips, knees, ankles, toes, thorax, neck, head, shoulders, elbows, wrists, hands); its up axis is
estimated per sequence as :mod:`torsocast.datasets.h36m` does, and its feet are put on the floor.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from ..datasets import cmu, h36m

F64 = npt.NDArray[np.float64]

#: CMU joint <- Human3.6M joint, for the joints the mannequin uses.
H36M_TO_CMU = {
    cmu.PELVIS: 0,
    cmu.LEFT_HIP: 6,
    cmu.LEFT_KNEE: 7,
    cmu.LEFT_ANKLE: 8,
    cmu.LEFT_TOE: 9,
    cmu.LEFT_TOE_END: 10,
    cmu.RIGHT_HIP: 1,
    cmu.RIGHT_KNEE: 2,
    cmu.RIGHT_ANKLE: 3,
    cmu.RIGHT_TOE: 4,
    cmu.RIGHT_TOE_END: 5,
    cmu.THORAX: 13,
    cmu.HEAD_TOP: 15,
    cmu.LEFT_SHOULDER: 17,
    cmu.LEFT_ELBOW: 18,
    cmu.LEFT_WRIST: 19,
    cmu.LEFT_FINGERS: 22,
    cmu.RIGHT_SHOULDER: 25,
    cmu.RIGHT_ELBOW: 26,
    cmu.RIGHT_WRIST: 27,
    cmu.RIGHT_FINGERS: 30,
}
#: Height of the lowest foot joint over a clip (m): the CMU clips' toes come to 3.5 to 5 cm.
FOOT_CLEARANCE = 0.035


@dataclass(frozen=True)
class Motion:
    """One mocap clip, ready to place in a scene."""

    name: str
    category: str
    """What kind of motion: the CMU action, or the thesis' category of a Human3.6M action."""
    joints: F64
    """``(frames, 38, 3)`` world joints in the CMU layout."""
    rate_hz: float

    @property
    def duration(self) -> float:
        return (len(self.joints) - 1) / self.rate_hz


def cmu_motion(path: str | Path, action: str) -> Motion:
    """A CMU clip file (the floor is already at z = 0)."""
    path = Path(path)
    return Motion(f"cmu/{action}/{path.stem}", f"cmu {action}", cmu.load_clip(path), cmu.RATE_HZ)


def h36m_category(action: str) -> str:
    return next(c for c, actions in h36m.CATEGORIES.items() if action in actions).lower()


def h36m_to_cmu_layout(joints: F64) -> F64:
    """``(frames, 32, 3)`` Human3.6M joints to the ``(frames, 38, 3)`` CMU layout; joints the
    mannequin does not use are put at the pelvis. The neck and the centre of the head lie on the
    line from the thorax to Human3.6M's head joint and top of the head."""
    out = np.repeat(joints[:, :1], 38, axis=1)
    for c, h in H36M_TO_CMU.items():
        out[:, c] = joints[:, h]
    out[:, cmu.NECK] = joints[:, 13] + 0.7 * (joints[:, 14] - joints[:, 13])
    out[:, cmu.HEAD] = joints[:, 14] + 0.2 * (joints[:, 15] - joints[:, 14])
    return out


def h36m_motion(root: str | Path, subject: int, action: str, subaction: int) -> Motion:
    """One Human3.6M file at its 50 Hz, gravity-aligned, feet on the floor."""
    path = h36m.sequence_path(root, subject, action, subaction)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such Human3.6M file")
    joints = h36m.forward_kinematics(h36m.read_expmap(path))
    gravity = h36m.estimate_gravity(joints)
    world = h36m_to_cmu_layout(joints @ h36m.world_rotation(gravity.up).T)
    feet = world[
        :, [cmu.LEFT_TOE, cmu.LEFT_TOE_END, cmu.RIGHT_TOE, cmu.RIGHT_TOE_END, cmu.LEFT_ANKLE, cmu.RIGHT_ANKLE]
    ]
    world[..., 2] -= feet[..., 2].min() - FOOT_CLEARANCE
    name = f"h36m/S{subject}/{action}_{subaction}"
    return Motion(name, f"h36m {h36m_category(action)}", world, h36m.FILE_RATE_HZ)
