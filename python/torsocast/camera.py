"""Depth cameras as the sources describe them: pinhole intrinsics with optional Brown-Conrady
distortion, the depth image's scale, and the camera-to-world transform into the gravity-aligned
world frame (REP-103: x forward, y left, z up) from the camera's optical frame (z forward, x
right, y down).

The runtime lifts keypoints in the core (``Tracker.step``: :class:`DepthLookup`, deprojection);
the NumPy projections here serve whole images (the renderer's rays, the overlay's drawing).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from ._core import DepthLookup

F64 = npt.NDArray[np.float64]

#: Optical frame (z forward, x right, y down) to REP-103 (x forward, y left, z up), camera level.
OPTICAL_TO_WORLD = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])


@dataclass(frozen=True)
class Intrinsics:
    """Pinhole intrinsics of the image the keypoints and the (registered) depth live in."""

    fx: float
    fy: float
    cx: float
    cy: float
    distortion: tuple[float, ...] = ()
    """Brown-Conrady ``(k1, k2, p1, p2, k3)`` as OpenCV and RealSense order them (shorter tuples
    are zero-padded); empty for an undistorted image."""

    def __post_init__(self) -> None:
        values = (self.fx, self.fy, self.cx, self.cy, *self.distortion)
        if not all(np.isfinite(values)) or self.fx <= 0 or self.fy <= 0:
            raise ValueError(f"intrinsics need finite values and positive focal lengths, got {self}")
        if len(self.distortion) > 5:
            raise ValueError(
                f"distortion takes up to 5 coefficients (k1, k2, p1, p2, k3), got {len(self.distortion)}"
            )

    @property
    def coefficients(self) -> tuple[float, float, float, float, float]:
        """``(k1, k2, p1, p2, k3)``, zero-padded."""
        # Plain tuples, not NumPy: the pipeline reads this every frame.
        k = (*map(float, self.distortion), *(0.0,) * (5 - len(self.distortion)))
        return k  # type: ignore[return-value]

    @property
    def matrix(self) -> F64:
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    def distort(self, xy: F64) -> F64:
        """Normalised undistorted ``(..., 2)`` to normalised distorted coordinates."""
        k1, k2, p1, p2, k3 = self.coefficients
        x, y = xy[..., 0], xy[..., 1]
        r2 = x * x + y * y
        radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3))
        return np.stack(
            [
                x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
                y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y,
            ],
            axis=-1,
        )

    def undistort(self, xy: F64, iterations: int = 20) -> F64:
        """Inverse of :meth:`distort` by fixed-point iteration (as OpenCV's ``undistortPoints``):
        converges in a few steps for the mild distortion of depth cameras."""
        if not any(self.distortion):
            return xy
        guess = xy.copy()
        for _ in range(iterations):
            guess = guess + (xy - self.distort(guess))
        return guess

    def project(self, points: F64) -> F64:
        """Optical-frame points ``(..., 3)`` to pixels ``(..., 2)``."""
        xy = self.distort(points[..., :2] / points[..., 2:3])
        return xy * [self.fx, self.fy] + [self.cx, self.cy]

    def deproject(self, uv: F64, depth: F64) -> F64:
        """Pixels ``(..., 2)`` with their depth along the optical axis (m) to optical-frame points
        ``(..., 3)``; NaN depth gives NaN points."""
        xy = self.undistort((np.asarray(uv, dtype=np.float64) - [self.cx, self.cy]) / [self.fx, self.fy])
        z = np.asarray(depth, dtype=np.float64)[..., None]
        return np.concatenate([xy * z, z], axis=-1)


@dataclass(frozen=True)
class Camera:
    """Intrinsics, the depth image's scale, and where the camera is in the world."""

    intrinsics: Intrinsics
    camera_to_world: F64 = field(default_factory=lambda: level_camera(0.0))
    """4x4 transform from the optical frame to the world frame (default: level, at the origin)."""
    depth_scale: float = 0.001
    """Metres per depth unit of the raw image (0.001 for millimetres, 1/5000 for TUM)."""

    def __post_init__(self) -> None:
        t = np.asarray(self.camera_to_world, dtype=np.float64)
        if t.shape != (4, 4) or not np.isfinite(t).all():
            raise ValueError(f"camera_to_world must be a finite 4x4 matrix, got shape {t.shape}")
        if not np.allclose(t[:3, :3] @ t[:3, :3].T, np.eye(3), atol=1e-6) or np.linalg.det(t[:3, :3]) < 0:
            raise ValueError("camera_to_world's 3x3 block must be a rotation")
        if not (np.isfinite(self.depth_scale) and self.depth_scale > 0):
            raise ValueError(f"depth_scale must be positive, got {self.depth_scale}")

    def to_world(self, points: F64) -> F64:
        """Optical-frame points ``(..., 3)`` into the world frame."""
        t = np.asarray(self.camera_to_world)
        return points @ t[:3, :3].T + t[:3, 3]

    def to_optical(self, points: F64) -> F64:
        """World points ``(..., 3)`` into the optical frame (the inverse of :meth:`to_world`)."""
        t = np.linalg.inv(np.asarray(self.camera_to_world))
        return points @ t[:3, :3].T + t[:3, 3]  # type: ignore[no-any-return]


def level_camera(height: float = 0.0, pitch: float = 0.0) -> F64:
    """``camera_to_world`` of a camera ``height`` m above the world origin, looking along world +x,
    tilted down by ``pitch`` rad (positive = looking down)."""
    c, s = np.cos(pitch), np.sin(pitch)
    tilt = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # about world y: +x towards -z
    out = np.eye(4)
    out[:3, :3] = tilt @ OPTICAL_TO_WORLD
    out[:3, 3] = [0.0, 0.0, height]
    return out


__all__ = ["OPTICAL_TO_WORLD", "Camera", "DepthLookup", "Intrinsics", "level_camera"]
