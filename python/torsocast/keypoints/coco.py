"""The 17 COCO keypoints every supported model outputs, in output order."""

from __future__ import annotations

KEYPOINTS = (
    "nose",
    "left_eye",
    "right_eye",
    "left_ear",
    "right_ear",
    "left_shoulder",
    "right_shoulder",
    "left_elbow",
    "right_elbow",
    "left_wrist",
    "right_wrist",
    "left_hip",
    "right_hip",
    "left_knee",
    "right_knee",
    "left_ankle",
    "right_ankle",
)
INDEX = {name: i for i, name in enumerate(KEYPOINTS)}
NOSE, LEFT_EYE, RIGHT_EYE = 0, 1, 2
LEFT_SHOULDER, RIGHT_SHOULDER, LEFT_HIP, RIGHT_HIP = 5, 6, 11, 12
#: The torso joints the plane is fitted through, with their sides for ``fit_plane``.
TORSO = (LEFT_SHOULDER, RIGHT_SHOULDER, LEFT_HIP, RIGHT_HIP)
TORSO_SIDES = "LRLR"
#: (left, right) index pairs: a detector that sees a back swaps every one of them at once.
LEFT_RIGHT_PAIRS = tuple((i, i + 1) for i in range(1, 17, 2))
