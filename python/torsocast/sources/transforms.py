"""A tree of time-stamped rigid transforms, as a ROS bag's ``/tf`` and ``/tf_static`` give them,
and the transform between two of its frames at a time: what a source needs to place its camera
in the world frame at each image's stamp (``Camera.camera_to_world``).

Like ROS tf2, each frame has one parent; a dynamic transform is interpolated between the two
samples either side of the time asked (the translation linearly, the rotation along the
shortest arc) and never extrapolated; a static one holds at every time.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]


class TransformLookupError(LookupError):
    """No transform between the two frames at that time: they are not connected, or a dynamic
    transform on the way has no samples either side of it."""


def rotation_matrix(quaternion: F64) -> F64:
    """The rotation of a quaternion ``[x, y, z, w]`` (ROS's order; normalised here)."""
    x, y, z, w = np.asarray(quaternion, dtype=np.float64) / np.linalg.norm(quaternion)
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def slerp(q0: F64, q1: F64, s: float) -> F64:
    """The unit quaternion a share ``s`` of the way from ``q0`` to ``q1`` along the shorter arc."""
    q0, q1 = q0 / np.linalg.norm(q0), q1 / np.linalg.norm(q1)
    dot = float(q0 @ q1)
    if dot < 0.0:  # q and -q are the same rotation: take the short way round
        q1, dot = -q1, -dot
    if dot > 1.0 - 1e-9:
        q = q0 + s * (q1 - q0)
        return q / np.linalg.norm(q)  # type: ignore[no-any-return]
    angle = np.arccos(dot)
    return (np.sin((1 - s) * angle) * q0 + np.sin(s * angle) * q1) / np.sin(angle)  # type: ignore[no-any-return]


def matrix(translation: F64, quaternion: F64) -> F64:
    """The 4x4 transform of a translation and a rotation quaternion ``[x, y, z, w]``."""
    out = np.eye(4)
    out[:3, :3] = rotation_matrix(quaternion)
    out[:3, 3] = translation
    return out


@dataclass
class _Edge:
    """A child frame's transform into its parent: its samples (time, translation, quaternion),
    and their times apart, kept in order for a binary search."""

    parent: str
    static: bool
    samples: list[tuple[float, F64, F64]] = field(default_factory=list)
    times: list[float] = field(default_factory=list)
    _sorted: bool = True

    def add(self, t: float, translation: F64, quaternion: F64) -> None:
        if self.times and t < self.times[-1]:
            self._sorted = False
        self.samples.append((t, translation, quaternion))
        self.times.append(t)

    def at(self, t: float, child: str) -> F64:
        if self.static:
            _, translation, quaternion = self.samples[-1]
            return matrix(translation, quaternion)
        if not self._sorted:
            self.samples.sort(key=lambda s: s[0])
            self.times = [s[0] for s in self.samples]
            self._sorted = True
        times = self.times
        k = bisect.bisect_left(times, t)
        if k < len(times) and times[k] == t:
            return matrix(self.samples[k][1], self.samples[k][2])
        if k == 0 or k == len(times):
            raise TransformLookupError(
                f"no transform from {child} to {self.parent} at {t:.6f} s: it is known from "
                f"{times[0]:.6f} to {times[-1]:.6f} s, and is not extrapolated"
            )
        (t0, p0, q0), (t1, p1, q1) = self.samples[k - 1], self.samples[k]
        s = (t - t0) / (t1 - t0)
        return matrix(p0 + s * (p1 - p0), slerp(q0, q1, s))


@dataclass
class TransformTree:
    """Transforms between frames, each child frame with one parent (see the module's docstring).
    The tree's shape (``parents``) may hold frames whose transforms were not kept (:meth:`connect`:
    a robot's every joint, where only the camera's chain is wanted)."""

    parents: dict[str, str] = field(default_factory=dict)
    edges: dict[str, _Edge] = field(default_factory=dict)

    def connect(self, parent: str, child: str) -> None:
        """``child`` hangs from ``parent``, its transform not (yet) given. Refuses a frame given a
        second parent, and a frame its own ancestor."""
        known = self.parents.get(child)
        if known is None:
            if parent == child or child in self.ancestors(parent):
                raise ValueError(f"the transform from {child} to {parent} closes a loop in the tree")
            self.parents[child] = parent
        elif known != parent:
            raise ValueError(f"frame {child} has two parents, {known} and {parent}")

    def add(self, parent: str, child: str, t: float, translation: F64, quaternion: F64, static: bool) -> None:
        """A sample of ``child``'s pose in ``parent`` at ``t`` (maps ``child`` coordinates into
        ``parent``'s). Refuses what :meth:`connect` refuses, and a transform that is not finite
        or whose quaternion is not a rotation."""
        translation, quaternion = np.asarray(translation, float), np.asarray(quaternion, float)
        if not (np.isfinite(translation).all() and np.isfinite(quaternion).all() and np.isfinite(t)):
            raise ValueError(f"the transform from {child} to {parent} at {t} s is not finite")
        if not 0.5 < np.linalg.norm(quaternion) < 1.5:
            raise ValueError(
                f"the transform from {child} to {parent} at {t} s has rotation {quaternion.tolist()}, "
                "not a unit quaternion [x, y, z, w]"
            )
        self.connect(parent, child)
        edge = self.edges.setdefault(child, _Edge(parent, static))
        edge.add(float(t), translation, quaternion)

    def __contains__(self, frame: str) -> bool:
        return frame in self.parents or frame in self.parents.values()

    def ancestors(self, frame: str) -> list[str]:
        """``frame``, its parent, its parent's parent, ... up to its tree's root."""
        chain = [frame]
        while chain[-1] in self.parents:
            chain.append(self.parents[chain[-1]])
        return chain

    def root(self, frame: str) -> str:
        """The frame at the top of ``frame``'s tree."""
        return self.ancestors(frame)[-1]

    def lookup(self, target: str, source: str, t: float) -> F64:
        """The 4x4 transform that maps ``source`` coordinates into ``target``'s at time ``t``."""
        up_source, up_target = self.ancestors(source), self.ancestors(target)
        common = next((f for f in up_source if f in up_target), None)
        if common is None:
            raise TransformLookupError(f"frames {source} and {target} are not connected by the transforms")
        out, back = np.eye(4), np.eye(4)
        for frame in up_source[: up_source.index(common)]:  # source -> common
            out = self._edge(frame).at(t, frame) @ out
        for frame in up_target[: up_target.index(common)]:  # target -> common
            back = self._edge(frame).at(t, frame) @ back
        return np.linalg.inv(back) @ out  # type: ignore[no-any-return]

    def _edge(self, child: str) -> _Edge:
        edge = self.edges.get(child)
        if edge is None:
            raise TransformLookupError(f"the transform from {child} to {self.parents[child]} was not kept")
        return edge
