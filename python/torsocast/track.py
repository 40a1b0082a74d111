"""One tracked person: the thesis' per-person chain (section 3.2) on 3D keypoints.

Each frame: undo a left/right swap of the detector, gate every joint against its previous
position, fit the torso plane (or, without enough torso joints, take the azimuth from the
shoulders), and feed the pose to the person's forecaster on its fixed-rate grid.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from . import wrap_angle
from ._core import Forecaster, ForecasterConfig, JointGate, TorsocastError, fit_plane, shoulder_heading
from .keypoints import coco

F64 = npt.NDArray[np.float64]

#: How far below the shoulders' midpoint the torso centre sits before the track has measured it
#: (half the shoulder-to-hip distance of an adult).
SHOULDER_TO_CENTRE = 0.25


def live_forecaster() -> ForecasterConfig:
    """The thesis' forecaster with its Butterworth low-pass on all five pose components at 1 Hz.
    The thesis filters only the angles (its mocap positions are clean) at 5 Hz; a keypoint
    detector's centres jitter by centimetres, and with N = 1 the spline interpolates, so the
    forecast continues the last noisy step. On the bundled CMU training walks seen through the
    demo's camera and MoveNet, the median centre error 1 s ahead drops from 79 to 42 cm (holding
    still: 100 cm); 0.7 to 2 Hz were tried (docs/demo.md)."""
    return ForecasterConfig(cutoff_hz=1.0, filter_components=[True] * 5)


@dataclass(frozen=True)
class TrackConfig:
    """Per-person parameters (defaults: the thesis' where it gives them)."""

    forecaster: ForecasterConfig = field(default_factory=live_forecaster)
    gate_threshold: float = 0.10
    """Largest accepted joint displacement between frames (m); the thesis' 10 cm assumes about
    25 frames per second."""
    gate_max_replacements: int = 10
    min_score: float = 0.3
    """Keypoints scored below this are missing (NaN)."""
    swap_ratio: float = 0.5
    """A frame's left/right labels are swapped back when the swapped pairing moves the joints
    less than this fraction of the labelled one."""
    min_swap_motion: float = 0.10
    """…and the labelled pairing moves them more than this (m): below it the two are noise."""
    face_score: float = 0.3
    """A face keypoint above this score means the face is seen (used when a track starts)."""


@dataclass
class Observation:
    """What a track made of one frame."""

    pose: F64 | None
    """``[x, y, z, azimuth, elevation]`` in the world frame (azimuth wrapped to (-π, π]); None
    when there was nothing to estimate it from."""
    estimate: str
    """``"plane"`` (torso plane), ``"shoulders"`` (azimuth from the shoulder line, elevation held)
    or ``"none"``."""
    swapped: bool
    """The detector's left and right labels were swapped back in this frame."""
    joint_status: npt.NDArray[np.uint8]
    """Per joint: 0 measured, 1 replaced by its previous position, 2 lost (:class:`JointStatus`)."""
    weight: float
    """Confidence weight given to the forecaster (mean score of the torso joints used)."""
    grid: dict[str, object]
    """What the forecaster's time grid did: ``{"filled": slots interpolated before this sample,
    "restarted": history cleared after a long gap, "skipped": the slot already had a sample}``."""


def swap_sides(points: F64) -> F64:
    """The keypoints with every left/right pair exchanged."""
    out = points.copy()
    for left, right in coco.LEFT_RIGHT_PAIRS:
        out[[left, right]] = points[[right, left]]
    return out


def pair_motion(current: F64, previous: F64) -> tuple[float, float]:
    """Mean displacement of the left/right joints seen in both frames, labelled as given and with
    the labels exchanged (NaN when no pair is seen in both)."""
    pairs = np.array(coco.LEFT_RIGHT_PAIRS)
    both = np.isfinite(current[pairs]).all(axis=(1, 2)) & np.isfinite(previous[pairs]).all(axis=(1, 2))
    if not both.any():
        return float("nan"), float("nan")
    cur, prev = current[pairs[both]], previous[pairs[both]]
    same = np.linalg.norm(cur - prev, axis=2).mean()
    crossed = np.linalg.norm(cur - prev[:, ::-1], axis=2).mean()
    return float(same), float(crossed)


class Track:
    """One person's state across frames."""

    def __init__(self, track_id: int, config: TrackConfig | None = None) -> None:
        self.id = track_id
        self.config = config or TrackConfig()
        self.gate = JointGate(17, self.config.gate_threshold, self.config.gate_max_replacements)
        self.forecaster = Forecaster(self.config.forecaster)
        self.previous: F64 | None = None
        self.body_motion = np.zeros(3)  # summed body displacement: the gate works relative to it
        self.centre_offset: F64 | None = None  # plane centre minus shoulder midpoint, learned
        self.last_pose: F64 | None = None  # for the elevation a shoulders-only frame holds

    def correct_sides(self, joints: F64, scores: F64, camera_position: F64) -> bool:
        """Whether this frame's labels must be exchanged. With a previous frame, the pairing that
        moves the joints less wins; a new track has none, so the face decides: a detector that
        sees a back without a face usually labels it as a front, so a plane facing the camera
        with no face in sight is taken as swapped (and a face on a plane facing away, too)."""
        c = self.config
        if self.previous is not None:
            same, crossed = pair_motion(joints, self.previous)
            if np.isfinite(same):
                return bool(same > c.min_swap_motion and crossed < c.swap_ratio * same)
        try:
            plane = fit_plane(joints[list(coco.TORSO)], coco.TORSO_SIDES)
        except TorsocastError:
            return False
        to_camera = camera_position - plane.centre
        facing = float(plane.normal @ to_camera) / np.linalg.norm(to_camera)
        if abs(facing) < 0.3:  # side view: neither cue is reliable
            return False
        face_seen = bool(scores[[coco.NOSE, coco.LEFT_EYE, coco.RIGHT_EYE]].max() > c.face_score)
        return bool(face_seen != (facing > 0))

    def gated(self, joints: F64) -> tuple[F64, npt.NDArray[np.uint8]]:
        """The gate applied to the joints' motion relative to the body's: at 1.3 m/s and 30 frames
        per second every joint of a walker moves 4 cm a frame, and an absolute gate holds a
        rejected joint still while the body walks away from it until it is lost. The body's
        motion is the median displacement of the joints seen in this frame and the last, robust to
        the one joint that jumps and unaffected by which joints happen to be seen."""
        if self.previous is not None:
            both = np.isfinite(joints).all(axis=1) & np.isfinite(self.previous).all(axis=1)
            if both.any():
                self.body_motion += np.median(joints[both] - self.previous[both], axis=0)
        gated, status = self.gate.update(joints - self.body_motion)
        return gated + self.body_motion, status

    def update(self, t: float, joints: F64, scores: F64, camera_position: F64) -> Observation:
        """One frame: ``joints (17, 3)`` in the world frame (NaN where missing), their ``scores``."""
        c = self.config
        joints = np.where((scores >= c.min_score)[:, None], joints, np.nan)
        swapped = self.correct_sides(joints, scores, camera_position)
        if swapped:
            joints, scores = swap_sides(joints), swap_sides(scores[:, None])[:, 0]
        gated, status = self.gated(joints)
        self.previous = gated
        pose, estimate, weight = self.torso_pose(gated, status, scores)
        grid: dict[str, object] = {"filled": 0, "restarted": False, "skipped": False}
        if pose is not None:
            last = self.forecaster.last_time
            if last is not None and t - last < 0.5 / c.forecaster.rate_hz:
                grid["skipped"] = True  # a faster camera than the grid: this slot has a sample
            else:
                filled, restarted = self.forecaster.update(list(pose), t, weight)
                grid.update(filled=filled, restarted=restarted)
            self.last_pose = pose
        pose_out = None if pose is None else np.r_[pose[:3], wrap_angle(pose[3]), pose[4]]
        return Observation(pose_out, estimate, swapped, status, weight, grid)

    def torso_pose(
        self, joints: F64, status: npt.NDArray[np.uint8], scores: F64
    ) -> tuple[F64 | None, str, float]:
        """The plane where three torso joints are usable, else the shoulder heading."""
        torso = list(coco.TORSO)
        # Replaced joints are last frame's positions: they count, at half weight.
        weights = np.where(status[torso] == 0, scores[torso], 0.5 * scores[torso])
        usable = np.isfinite(joints[torso]).all(axis=1)
        try:
            plane = fit_plane(joints[torso], coco.TORSO_SIDES, weights)
        except TorsocastError:
            plane = None
        left, right = joints[coco.LEFT_SHOULDER], joints[coco.RIGHT_SHOULDER]
        shoulders_seen = bool(np.isfinite(left).all() and np.isfinite(right).all())
        if plane is not None:
            centre = np.asarray(plane.centre)
            if shoulders_seen and usable[2:].all():
                self.centre_offset = centre - 0.5 * (left + right)
            return np.r_[centre, plane.azimuth, plane.elevation], "plane", float(weights[usable].mean())
        if shoulders_seen:
            try:
                heading = shoulder_heading(list(left), list(right))
            except TorsocastError:
                return None, "none", 0.0
            offset = (
                self.centre_offset
                if self.centre_offset is not None
                else np.array([0, 0, -SHOULDER_TO_CENTRE])
            )
            elevation = self.last_pose[4] if self.last_pose is not None else np.pi / 2
            return (
                np.r_[np.asarray(heading[0]) + offset, heading[1], elevation],
                "shoulders",
                float(weights[:2].mean()),
            )
        return None, "none", 0.0

    def forecast(self, horizons: list[float]) -> F64 | None:
        """``(len(horizons), 5)`` poses ahead of the last grid sample, azimuth wrapped; None until
        the history holds enough samples."""
        if not horizons or len(self.forecaster) < self.forecaster.min_samples:
            return None
        out = self.forecaster.forecast(horizons)
        out[:, 3] = wrap_angle(out[:, 3])
        return out
