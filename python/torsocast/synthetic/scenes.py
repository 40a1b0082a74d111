"""Scenes of several people from mocap, seen by one virtual RGB-D camera.

Each person (an :class:`Actor`) is a mocap clip turned about the vertical and moved on the floor;
the camera stands at the world origin looking along +x, at a robot's height and tilt, or rides on
a robot that drives past the people and pans (a :class:`RobotPath`). Frames come at the camera's
rate and carry, besides colour and depth, which person each pixel shows and every person's true
torso pose: the plane through the mocap shoulders and hips, as the pipeline computes it from
keypoints.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from .._core import fit_planes
from ..camera import Camera, level_camera
from ..datasets import cmu
from ..keypoints import coco
from ..sources.frame import Frame
from .mannequin import Outfit, Scene
from .motions import Motion
from .sensor import SENSORS

F64 = npt.NDArray[np.float64]

#: Motion category of a person turning on the spot (:attr:`Actor.turn`), whatever the clip.
TURNING = "turning on the spot"
#: Motion category of a person who turns on the spot and stops, again and again
#: (:attr:`Actor.bursts`), whatever the clip.
TURNING_AND_STOPPING = "turning and stopping"
#: Motion category of a person whose walk stops and goes on, again and again
#: (:attr:`Actor.pauses`), whatever the clip.
WALKING_AND_STOPPING = "walking and stopping"


def torso_truth(joints: F64) -> F64:
    """``(frames, 5)`` torso poses ``(x, y, z, azimuth, elevation)`` of ``(frames, 38, 3)`` mocap
    joints: the plane through the shoulders and hips, as for detected keypoints. Every frame is
    oriented, bent far forward too (mocap has no detector noise to flip the normal's sign)."""
    torso = np.ascontiguousarray(joints[:, list(cmu.TORSO)])
    planes = fit_planes(torso, coco.TORSO_SIDES, min_orientation_cosine=0.0)
    return np.column_stack([planes["centre"], planes["azimuth"], planes["elevation"]])


def _burst_yaw(bursts: tuple[tuple[float, float, float], ...], t: F64) -> F64:
    """How far ``bursts`` of turning (scene time it starts, duration, angle: s, s, rad) have
    turned a person by scene times ``t``: each burst as a minimum-jerk profile, which starts and
    ends at rest as a person's turn does."""
    out = np.zeros_like(t, dtype=np.float64)
    for start, duration, angle in bursts:
        out += angle * _min_jerk((t - start) / duration)
    return out


def _min_jerk(u: F64) -> F64:
    """The minimum-jerk profile from 0 to 1 over ``u`` in 0..1 (clipped outside)."""
    u = np.clip(u, 0.0, 1.0)
    return u**3 * (10.0 - 15.0 * u + 6.0 * u**2)  # type: ignore[no-any-return]


def _min_jerk_area(u: F64) -> F64:
    """The integral of :func:`_min_jerk` from 0 to ``u`` in 0..1 (half at 1)."""
    u = np.clip(u, 0.0, 1.0)
    return u**4 * (2.5 - 3.0 * u + u**2)  # type: ignore[no-any-return]


def _pause_lag(pauses: tuple[tuple[float, float, float], ...], t: F64) -> F64:
    """How far ``pauses`` (scene time each starts, its ramp and its standing time: s) have held
    a clip back by scene times ``t`` (s): each pause slows the clip's playback from full speed
    to rest over its ramp (a minimum-jerk profile of the speed, as a walker's stop takes about a
    step), holds it for the standing time and speeds it up again over the ramp. A whole pause
    holds the clip back by its ramp plus its standing time."""
    t = np.asarray(t, dtype=np.float64)
    out = np.zeros_like(t)
    for begin, ramp, hold in pauses:
        slowing = ramp * _min_jerk_area((t - begin) / ramp)
        held = np.clip(t - begin - ramp, 0.0, hold)
        u = (t - begin - ramp - hold) / ramp
        going = ramp * (np.clip(u, 0.0, 1.0) - _min_jerk_area(u))
        out += slowing + held + going
    return out


def yaw_matrix(yaw: float) -> F64:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class RobotPath:
    """A camera on a robot that drives past the scene at a steady ``velocity`` (m/s over the
    floor, world x and y) and pans its view to and fro by up to ``pan`` rad over ``pan_period``
    seconds (from ``pan_phase``). It passes the static camera's place at the scene's middle, so
    the people placed for that camera are in view for most of the scene."""

    velocity: tuple[float, float]
    pan: float = 0.0
    pan_period: float = 1.0
    pan_phase: float = 0.0

    def __post_init__(self) -> None:
        values = (*self.velocity, self.pan, self.pan_period, self.pan_phase)
        if not np.isfinite(values).all() or self.pan_period <= 0:
            raise ValueError(f"a robot path needs finite values and a positive pan period, got {self}")

    def pose(self, t: float, duration: float) -> F64:
        """The rigid motion ``(4, 4)`` that takes the static camera's pose to the robot's at scene
        time ``t``: a yaw about the vertical through the camera, then the drive."""
        yaw = self.pan * np.sin(2 * np.pi * t / self.pan_period + self.pan_phase)
        out = np.eye(4)
        out[:3, :3] = yaw_matrix(float(yaw))
        out[:2, 3] = np.asarray(self.velocity) * (t - duration / 2)
        return out


@dataclass(frozen=True)
class Actor:
    """One person of a scene: ``motion`` (a name) played from ``start`` seconds into the clip at
    the scene's time 0, turned by ``yaw`` (rad) about the clip's pelvis at ``anchor`` seconds
    into the clip, and moved so that that pelvis stands at ``position`` (x, y) on the floor.

    With a ``turn`` rate (rad/s), the person turns on the spot instead: the pelvis stays at
    ``position`` while the body turns about it, by ``yaw`` at ``anchor`` and steadily from there
    (the clip's own walking and turning are kept relative to the pelvis). With ``bursts`` (scene
    time each starts, its duration and angle: s, s, rad), the same on the spot, turned by ``yaw``
    before the first burst and by each burst in turn (:func:`_burst_yaw`), standing between them
    (a ``turn`` rate or ``bursts``, not both).

    With ``pauses`` (scene time each starts, its ramp and its standing time: s), the clip's
    playback slows to rest, holds and goes on again (:func:`_pause_lag`): a walker who stops
    and walks on, the body still where it stopped (not with a ``turn`` rate or ``bursts``)."""

    motion: str
    start: float
    anchor: float
    yaw: float
    position: tuple[float, float]
    outfit: Outfit = field(default_factory=Outfit)
    # Left out of the repr so that the scenes drawn before turning existed keep their cache keys
    # (the scenes benchmark's cache names files by the spec's repr; it adds the turn itself).
    turn: float = field(default=0.0, repr=False)
    bursts: tuple[tuple[float, float, float], ...] = field(default=(), repr=False)
    pauses: tuple[tuple[float, float, float], ...] = field(default=(), repr=False)

    def __post_init__(self) -> None:
        if self.turn and self.bursts:
            raise ValueError("an actor turns steadily (turn) or in bursts (bursts), not both")
        if self.pauses and (self.turn or self.bursts):
            raise ValueError(
                "an actor walks and stops (pauses) or turns on the spot (turn, bursts), not both"
            )
        for burst in self.bursts:
            if len(burst) != 3 or not all(np.isfinite(burst)) or not burst[1] > 0.0:
                raise ValueError(f"a burst is (start, duration > 0, angle), finite; got {burst!r}")
        end = -np.inf
        for pause in self.pauses:
            if len(pause) != 3 or not all(np.isfinite(pause)) or not (pause[1] > 0.0 and pause[2] >= 0.0):
                raise ValueError(f"a pause is (start, ramp > 0, standing time >= 0), finite; got {pause!r}")
            if pause[0] < end:
                raise ValueError(f"pauses must follow one another without overlapping; got {self.pauses!r}")
            end = pause[0] + 2 * pause[1] + pause[2]

    def clip_time(self, t: float | F64) -> F64:
        """The clip's time (s) this actor shows at scene time(s) ``t``."""
        t = np.asarray(t, dtype=np.float64)
        return t + self.start - _pause_lag(self.pauses, t)  # type: ignore[no-any-return]

    def place(self, motion: Motion) -> F64:
        """The clip's joints ``(frames, 38, 3)`` where this actor puts them."""
        target = np.array([*self.position, 0.0])
        if self.turn or self.bursts:
            pelvis = motion.joints[:, cmu.PELVIS : cmu.PELVIS + 1] * [1.0, 1.0, 0.0]
            clip_time = np.arange(len(motion.joints)) / motion.rate_hz
            yaw = self.yaw + self.turn * (clip_time - self.anchor)
            yaw += _burst_yaw(self.bursts, clip_time - self.start)
            c, s = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
            x, y, z = np.moveaxis(motion.joints - pelvis, -1, 0)
            return np.stack([c * x - s * y, s * x + c * y, z], axis=-1) + target  # type: ignore[no-any-return]
        k = int(round(np.clip(self.anchor, 0.0, motion.duration) * motion.rate_hz))
        pivot = motion.joints[k, cmu.PELVIS] * [1.0, 1.0, 0.0]
        return (motion.joints - pivot) @ yaw_matrix(self.yaw).T + target  # type: ignore[no-any-return]


@dataclass(frozen=True)
class SceneSpec:
    """Everything that defines a scene; with its seed, the frames are the same on every run."""

    name: str
    sensor: str
    """A key of :data:`~torsocast.synthetic.sensor.SENSORS`."""
    fps: float
    height: float
    """Camera height above the floor (m)."""
    tilt_deg: float
    """Camera tilt: positive looks up, negative down."""
    duration: float
    actors: tuple[Actor, ...]
    seed: int = 0
    robot: RobotPath | None = field(default=None, repr=False)
    """The robot the camera rides on; None for a camera that stands still. Not in the repr,
    which keys the recordings of the scenes without one (a moving camera's are keyed apart)."""

    def camera(self, t: float = 0.0) -> Camera:
        """The camera at scene time ``t`` (the same at every time without a :attr:`robot`)."""
        sensor = SENSORS[self.sensor]
        pose = level_camera(self.height, -np.radians(self.tilt_deg))
        if self.robot is not None:
            # The still camera stands over the origin: the path's yaw turns it about its own
            # vertical, and the drive keeps its height.
            pose = self.robot.pose(t, self.duration) @ pose
        return Camera(sensor.intrinsics, pose)

    @property
    def times(self) -> F64:
        return np.arange(int(np.floor(self.duration * self.fps + 1e-9)) + 1) / self.fps


class RenderedScene:
    """A :class:`SceneSpec` as a frame source. ``motions`` maps the actors' motion names to
    clips. Each frame's ``extra`` holds ``labels`` (the person index of every pixel, -1 for
    none) and ``truth`` ``(actors, 5)`` (NaN rows for people not in the scene at that time)."""

    def __init__(self, spec: SceneSpec, motions: Mapping[str, Motion]) -> None:
        missing = [a.motion for a in spec.actors if a.motion not in motions]
        if missing:
            raise KeyError(f"scene {spec.name}: unknown motions {missing}")
        if spec.sensor not in SENSORS:
            raise ValueError(f"scene {spec.name}: sensor must be one of {list(SENSORS)}, got {spec.sensor!r}")
        self.spec, self.name = spec, spec.name
        self.camera = spec.camera()
        sensor = SENSORS[spec.sensor]
        self.scene = Scene(sensor.width, sensor.height, sensor.noise)
        self.clips = [motions[a.motion] for a in spec.actors]
        self.placed = [a.place(m) for a, m in zip(spec.actors, self.clips)]
        self.truths = [torso_truth(j) for j in self.placed]

    def __len__(self) -> int:
        return len(self.spec.times)

    def _clip(self, actor: int) -> Motion:
        """The clip of ``actor``; an index out of range (a negative one too, which Python would
        read from the end: another person's truth) is refused."""
        if not 0 <= actor < len(self.clips):
            raise IndexError(f"scene {self.name}: no actor {actor} (it has {len(self.clips)})")
        return self.clips[actor]

    def sample(self, actor: int, t: float | F64) -> npt.NDArray[np.intp]:
        """The clip sample actor ``actor`` shows at scene time ``t``; -1 where it is not there."""
        clip = self._clip(actor)
        k = np.rint(self.spec.actors[actor].clip_time(t) * clip.rate_hz).astype(np.intp)
        return np.where((k >= 0) & (k < len(clip.joints)), k, -1)

    def category(self, actor: int) -> str:
        """The motion category of ``actor``: its clip's, :data:`TURNING`,
        :data:`TURNING_AND_STOPPING` or :data:`WALKING_AND_STOPPING`."""
        clip = self._clip(actor)
        person = self.spec.actors[actor]
        if person.turn:
            return TURNING
        if person.bursts:
            return TURNING_AND_STOPPING
        return WALKING_AND_STOPPING if person.pauses else clip.category

    def truth_at(self, actor: int, t: float | F64) -> F64:
        """True torso pose(s) of ``actor`` at scene time(s) ``t``: ``(..., 5)``, NaN where absent."""
        k = self.sample(actor, t)
        return np.where((k >= 0)[..., None], self.truths[actor][np.maximum(k, 0)], np.nan)  # type: ignore[no-any-return]

    def joints_at(self, actor: int, t: float) -> F64 | None:
        """The skeleton of ``actor`` at scene time ``t`` as placed in the world (the CMU skeleton's
        joints, ``(38, 3)``), None where the actor is not in the scene then."""
        k = int(self.sample(actor, t))
        return self.placed[actor][k] if k >= 0 else None

    def camera_at(self, t: float) -> Camera:
        """The camera at scene time ``t``: :attr:`camera` for one that stands still."""
        return self.camera if self.spec.robot is None else self.spec.camera(t)

    def __iter__(self) -> Iterator[Frame]:
        rng = np.random.default_rng(self.spec.seed)
        rays = self.scene.rays(self.camera)  # in the optical frame: the same wherever it goes
        # The floor a still camera sees is rendered once; a moving one's with every frame.
        background = self.scene.background(self.camera, rays) if self.spec.robot is None else None
        outfits = [a.outfit for a in self.spec.actors]
        for index, t in enumerate(self.spec.times):
            camera = self.camera_at(float(t))
            samples = [int(self.sample(i, t)) for i in range(len(self.clips))]
            here = [i for i, k in enumerate(samples) if k >= 0]
            people = [self.placed[i][samples[i]] for i in here]
            frame = self.scene.render(people, camera, rng, rays, background, [outfits[i] for i in here])
            # Renderer index -> actor index; -1 (floor, sky) picks the appended -1.
            labels = np.asarray([*here, -1], dtype=np.int8)[frame.labels]
            truth = np.array([self.truth_at(i, t) for i in range(len(self.clips))]).reshape(-1, 5)
            extra = {"labels": labels, "truth": truth, "joints": people, "present": here}
            yield Frame(index, float(t), frame.rgb, frame.depth, camera, extra)

    def visible(self, frame: Frame, min_joints: int = 3) -> npt.NDArray[np.bool_]:
        """Which actors show at least ``min_joints`` of their four torso joints in ``frame``: in
        the image, in front of the camera, and not hidden by someone else (the joint's pixel
        shows the actor's own body, which in profile hides its far shoulder and hip from the
        camera but not from a detector)."""
        out = np.zeros(len(self.clips), dtype=bool)
        labels = frame.extra["labels"]
        camera = frame.camera
        assert camera is not None, "a rendered frame carries the camera it was seen from"
        h, w = labels.shape
        for joints, i in zip(frame.extra["joints"], frame.extra["present"]):
            optical = camera.to_optical(joints[list(cmu.TORSO)])
            ahead = optical[:, 2] > 0.1
            uv = camera.intrinsics.project(np.where(ahead[:, None], optical, 1.0))
            u, v = np.rint(uv).astype(int).T
            inside = ahead & (u >= 0) & (u < w) & (v >= 0) & (v < h)
            own = np.zeros(4, dtype=bool)
            own[inside] = labels[v[inside], u[inside]] == i
            out[i] = own.sum() >= min_joints
        return out
