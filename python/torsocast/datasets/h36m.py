"""Human3.6M exponential-map mocap (the text files of the motion-prediction literature) as torso
pose series.

The steps, each a function below:

1. :func:`read_expmap`: one frame per line, 99 numbers, 50 Hz.
2. :func:`integrate_root`: the root columns are per-frame *increments* (translation in the previous
   root frame, rotation relative to the previous frame); summing them gives the root trajectory in
   the first frame's pelvis frame.
3. :func:`forward_kinematics`: the 32-joint skeleton in that frame, in metres.
4. :func:`estimate_gravity`: that frame's +y is only roughly up (9 to 22 degrees off), so the up
   axis is estimated per sequence (floor plane of the toes, or the spine where they disagree).
5. :func:`torso_poses`: the joints rotated into a gravity-aligned frame (REP-103, z up), the torso
   plane of the Rust core per frame, and the pose ``(x, y, z, azimuth, elevation)`` at 25 Hz.

Human3.6M is licensed for research use only: these files are read from where the user keeps them
and never copied into this project.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from .._core import fit_planes
from .kinematics import chain, expmap_to_rotmat, rotmat_to_expmap

F64 = npt.NDArray[np.float64]

#: Rate of the files; the literature takes every second frame for 25 Hz.
FILE_RATE_HZ = 50.0
RATE_HZ = 25.0

#: Parent of each of the 32 joints (-1 for the root).
PARENTS = np.array(
    [-1, 0, 1, 2, 3, 4, 0, 6, 7, 8, 9, 0, 11, 12, 13, 14, 12, 16, 17, 18, 19, 20, 19, 22, 12]
    + [24, 25, 26, 27, 28, 27, 30]
)

#: Offset of each joint from its parent in the parent's frame, rest pose, y up (mm).
OFFSETS_MM = np.array(
    [
        [0, 0, 0],
        [-132.948591, 0, 0],
        [0, -442.894612, 0],
        [0, -454.206447, 0],
        [0, 0, 162.767078],
        [0, 0, 74.999437],
        [132.948826, 0, 0],
        [0, -442.894413, 0],
        [0, -454.206590, 0],
        [0, 0, 162.767426],
        [0, 0, 74.999948],
        [0, 0.1, 0],
        [0, 233.383263, 0],
        [0, 257.077681, 0],
        [0, 121.134938, 0],
        [0, 115.002227, 0],
        [0, 257.077681, 0],
        [0, 151.034226, 0],
        [0, 278.882773, 0],
        [0, 251.733451, 0],
        [0, 0, 0],
        [0, 0, 99.999627],
        [0, 100.000188, 0],
        [0, 0, 0],
        [0, 257.077681, 0],
        [0, 151.031437, 0],
        [0, 278.892924, 0],
        [0, 251.728680, 0],
        [0, 0, 0],
        [0, 0, 99.999888],
        [0, 137.499922, 0],
        [0, 0, 0],
    ]
)

#: The 15 actions, in the order of Martinez et al. (2017).
ACTIONS = (
    "walking",
    "eating",
    "smoking",
    "discussion",
    "directions",
    "greeting",
    "phoning",
    "posing",
    "purchases",
    "sitting",
    "sittingdown",
    "takingphoto",
    "waiting",
    "walkingdog",
    "walkingtogether",
)

#: The thesis' grouping of the actions (appendix A.1).
CATEGORIES: dict[str, tuple[str, ...]] = {
    "Pedestrian": ("walking", "walkingdog", "walkingtogether"),
    "Constrained": ("eating", "smoking", "phoning", "sitting", "sittingdown"),
    "High Variance": (
        "posing",
        "purchases",
        "discussion",
        "directions",
        "greeting",
        "takingphoto",
        "waiting",
    ),
}

#: Default torso joints and their side of the body: hips, thorax (neck base) and shoulders. 6 and 17
#: are the left hip and shoulder (the skeleton names them LeftUpLeg and LeftArm; the left hip's rest
#: offset is at +x, the body's left in the data's frame).
TORSO_JOINTS: dict[int, str] = {1: "R", 6: "L", 13: "C", 17: "L", 25: "R"}

#: Toe joints (right, left), whose positions over a sequence span the floor.
TOE_JOINTS = (4, 9)
PELVIS, THORAX = 0, 13

#: Largest angle between the floor normal and the pelvis-to-thorax direction for the floor to be
#: trusted; beyond it (seated sequences: 75 to 90 degrees) the feet do not span the floor.
MAX_FLOOR_SPINE_ANGLE_DEG = 15.0
#: Largest plausible angle between the estimated up axis and the data's +y (measured: 3 to 22).
MAX_TILT_DEG = 35.0


def read_expmap(path: str | Path) -> F64:
    """The ``(frames, 99)`` channels of one file, at 50 Hz."""
    text = Path(path).read_text()
    rows = [line for line in text.splitlines() if line.strip()]
    data = np.array([row.split(",") for row in rows], dtype=np.float64)
    if data.ndim != 2 or data.shape[1] != 99:
        raise ValueError(f"{path}: expected 99 comma-separated numbers per line, got shape {data.shape}")
    return data


def integrate_root(channels: F64) -> tuple[F64, F64]:
    """Root rotations ``(frames, 3, 3)`` and positions ``(frames, 3)`` (mm) in the first frame's
    pelvis frame: ``R_i = exp(ω_i) R_{i-1}`` and ``T_i = T_{i-1} + R_{i-1}ᵀ v_i`` (row-vector
    convention, as ``revert_coordinate_space`` of the reference code)."""
    increments = expmap_to_rotmat(channels[:, 3:6])
    rotations = np.empty_like(increments)
    positions = np.empty((len(channels), 3))
    rotation, position = np.eye(3), np.zeros(3)
    for i, (step, velocity) in enumerate(zip(increments, channels[:, :3])):
        position = position + rotation.T @ velocity
        rotation = step @ rotation
        rotations[i], positions[i] = rotation, position
    return rotations, positions


def forward_kinematics(channels: F64) -> F64:
    """Global joint positions ``(frames, 32, 3)`` in metres, in the first frame's pelvis frame
    (x the subject's initial left, y roughly up, z initial forward)."""
    return posed_joints(channels, *integrate_root(channels))


def posed_joints(channels: F64, root_rotation: F64, root_position: F64) -> F64:
    """Joint positions ``(frames, 32, 3)`` in metres of the frames' joint rotations about a root
    already placed (rotations ``(frames, 3, 3)``, positions ``(frames, 3)`` in mm)."""
    local = expmap_to_rotmat(channels[:, 3:].reshape(len(channels), 32, 3))
    return chain(PARENTS, OFFSETS_MM, root_rotation, root_position, local) / 1000.0


def continue_root(rotation: F64, position: F64, frames: F64) -> tuple[F64, F64]:
    """The root after each of ``frames`` (their first six channels, increments), from a root at
    ``rotation`` ``(3, 3)`` and ``position`` ``(3,)`` mm, as :func:`integrate_root` steps."""
    increments = expmap_to_rotmat(frames[:, 3:6])
    rotations, positions = np.empty((len(frames), 3, 3)), np.empty((len(frames), 3))
    for i, (step, velocity) in enumerate(zip(increments, frames[:, :3])):
        position = position + rotation.T @ velocity
        rotation = step @ rotation
        rotations[i], positions[i] = rotation, position
    return rotations, positions


def subsample(channels: F64, root_rotation: F64, root_position: F64) -> F64:
    """The file's every second row, its root increments composed over the two rows each step
    spans (the literature's even rows keep only one of the two, so a root carried on by them
    drifts from the file's). The first row keeps its own."""
    frames = channels[::2].copy()
    rotation, position = root_rotation[::2], root_position[::2]
    frames[1:, 3:6] = rotmat_to_expmap(rotation[1:] @ np.swapaxes(rotation[:-1], 1, 2))
    frames[1:, :3] = np.einsum("nij,nj->ni", rotation[:-1], position[1:] - position[:-1])
    return frames


@dataclass(frozen=True)
class Gravity:
    """The up axis of a sequence and how it was found."""

    up: F64
    """Unit vector, in the data's frame."""
    rule: str
    """``"floor"`` (normal of the toes' plane) or ``"spine"`` (mean pelvis-to-thorax direction)."""
    floor_spine_angle_deg: float
    """Angle between the two estimates: the floor is used where it is under 15 degrees."""
    tilt_deg: float
    """Angle between ``up`` and the data's +y, the sanity check (measured 3 to 22 degrees)."""


#: The rules :func:`estimate_gravity` knows; ``"auto"`` is the default, the others are there to
#: measure what the choice changes (``docs/reproduction.md``).
GRAVITY_RULES = ("auto", "floor", "spine", "y")


def estimate_gravity(joints: F64, rule: str = "auto") -> Gravity:
    """Up axis of a sequence of ``(frames, 32, 3)`` joints.

    The floor normal (least-squares plane through every toe position of the sequence) is the
    better estimate when the feet move over the floor; it is meaningless when they do not (a seated
    subject's toes barely move). The mean pelvis-to-thorax direction is always defined but leans
    with the subject's posture. So ``"auto"`` uses the floor only where it agrees with the spine
    within :data:`MAX_FLOOR_SPINE_ANGLE_DEG`, and the result must lie within :data:`MAX_TILT_DEG`
    of +y. ``"floor"`` and ``"spine"`` force one estimate, ``"y"`` takes the data's +y as it is.
    """
    if rule not in GRAVITY_RULES:
        raise ValueError(f"gravity rule {rule!r} is not one of {GRAVITY_RULES}")
    spine = (joints[:, THORAX] - joints[:, PELVIS]).mean(axis=0)
    spine /= np.linalg.norm(spine)
    toes = joints[:, TOE_JOINTS].reshape(-1, 3)
    _, _, vt = np.linalg.svd(toes - toes.mean(axis=0), full_matrices=False)
    floor = vt[2] * np.sign(vt[2] @ spine)
    angle = float(np.degrees(np.arccos(np.clip(floor @ spine, -1.0, 1.0))))
    if rule == "auto":
        rule = "floor" if angle <= MAX_FLOOR_SPINE_ANGLE_DEG else "spine"
    up = {"floor": floor, "spine": spine, "y": np.array([0.0, 1.0, 0.0])}[rule]
    tilt = float(np.degrees(np.arccos(np.clip(up[1], -1.0, 1.0))))
    if tilt > MAX_TILT_DEG:
        raise ValueError(
            f"gravity estimate is {tilt:.1f} degrees from the data's +y (rule {rule!r}); "
            f"more than {MAX_TILT_DEG} degrees means the skeleton or the rule is wrong"
        )
    return Gravity(up=up, rule=rule, floor_spine_angle_deg=angle, tilt_deg=tilt)


def world_rotation(up: F64) -> F64:
    """Rotation ``W`` (rows: world x, y, z in data coordinates) into a REP-103 frame with z along
    ``up``: x is the data's +z (the subject's initial forward) made horizontal, y = z × x. Without
    tilt it maps the data's (x left, y up, z forward) to (y, z, x), a proper rotation."""
    z = up / np.linalg.norm(up)
    forward = np.array([0.0, 0.0, 1.0])
    x = forward - (forward @ z) * z
    x /= np.linalg.norm(x)
    return np.stack([x, np.cross(z, x), z])


def torso_poses(
    joints: F64, up: F64, torso_joints: Mapping[int, str] = TORSO_JOINTS
) -> tuple[F64, npt.NDArray[np.uint8]]:
    """Pose series ``(frames, 5)``: torso centre (m) and the plane normal's azimuth (unwrapped over
    the series) and elevation (rad) in the gravity-aligned frame, plus the plane status per frame
    (:class:`torsocast.PlaneStatus`; NaN poses where it is not OK).

    Every frame's normal is oriented by the sign of its component along (left - right) × up, even
    when that component is tiny: mocap has no detector noise to flip it, and refusing such frames
    (as live tracking does) would drop the 5 % of S5 windows where the subject bends far forward,
    which are the hardest ones."""
    index = list(torso_joints)
    sides = "".join(torso_joints.values())
    world = joints[:, index] @ world_rotation(up).T
    planes = fit_planes(world, sides, min_orientation_cosine=0.0)
    poses = np.column_stack([planes["centre"], planes["azimuth"], planes["elevation"]]).astype(
        np.float64, copy=False
    )
    ok = np.isfinite(poses[:, 3])
    poses[ok, 3] = np.unwrap(poses[ok, 3])
    return poses, planes["status"].astype(np.uint8, copy=False)


@dataclass(frozen=True)
class Sequence:
    """One file as a torso pose series at 25 Hz."""

    subject: int
    action: str
    subaction: int
    poses: F64
    """``(frames, 5)``: x, y, z (m), azimuth (unwrapped), elevation (rad); NaN where no plane."""
    status: npt.NDArray[np.uint8]
    gravity: Gravity
    frames: F64
    """``(frames, 99)``: the file's rows the poses are of (every second one, its root increments
    over the 25 Hz step: :func:`subsample`), the input of a whole-body motion model."""
    root_rotation: F64
    """``(frames, 3, 3)``: the root at those rows, integrated over every row of the file."""
    root_position: F64
    """``(frames, 3)`` (mm)."""

    @property
    def name(self) -> str:
        return f"S{self.subject}/{self.action}_{self.subaction}"


def sequence_path(root: str | Path, subject: int, action: str, subaction: int) -> Path:
    return Path(root) / f"S{subject}" / f"{action}_{subaction}.txt"


def load_sequence(
    root: str | Path,
    subject: int,
    action: str,
    subaction: int,
    torso_joints: Mapping[int, str] = TORSO_JOINTS,
    gravity_rule: str = "auto",
) -> Sequence:
    """Reads one file and returns its torso pose series at 25 Hz (even rows of the 50 Hz file, as
    the literature does; the root is integrated at 50 Hz first, since its columns are increments)."""
    channels = _read_take(root, subject, action, subaction)
    root_rotation, root_position = integrate_root(channels)
    joints = posed_joints(channels, root_rotation, root_position)
    gravity = estimate_gravity(joints, gravity_rule)
    poses, status = torso_poses(joints[::2], gravity.up, torso_joints)
    return Sequence(
        subject,
        action,
        subaction,
        poses,
        status,
        gravity,
        subsample(channels, root_rotation, root_position),
        root_rotation[::2],
        root_position[::2],
    )


def read_frames(root: str | Path, subject: int, action: str, subaction: int) -> F64:
    """One file's 25 Hz frames as a whole-body motion model reads them (:func:`subsample`)."""
    channels = _read_take(root, subject, action, subaction)
    return subsample(channels, *integrate_root(channels))


def _read_take(root: str | Path, subject: int, action: str, subaction: int) -> F64:
    path = sequence_path(root, subject, action, subaction)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: no such Human3.6M file")
    return read_expmap(path)


def forecast_poses(
    sequence: Sequence, start: int, frames: F64, torso_joints: Mapping[int, str] = TORSO_JOINTS
) -> F64:
    """Torso poses ``(len(frames), 5)`` of ``frames`` forecast from 25 Hz sample ``start`` on (a
    whole-body model's output), made as the sequence's own poses are: the root carried on from
    the last observed sample by the forecast increments, the skeleton posed, the torso plane
    fitted in the sequence's gravity-aligned frame."""
    rotation, position = continue_root(
        sequence.root_rotation[start - 1], sequence.root_position[start - 1], frames
    )
    poses, _ = torso_poses(posed_joints(frames, rotation, position), sequence.gravity.up, torso_joints)
    return poses


def available(root: str | Path, subject: int) -> list[tuple[str, int]]:
    """The ``(action, subaction)`` pairs of a subject present under ``root``, in :data:`ACTIONS`
    order (several S5 files are missing from the distributed copy)."""
    return [
        (action, sub)
        for action in ACTIONS
        for sub in (1, 2)
        if sequence_path(root, subject, action, sub).is_file()
    ]
