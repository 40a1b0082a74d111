"""Depth cameras: pinhole intrinsics with optional Brown-Conrady distortion, a robust depth per
keypoint, deprojection into the camera's optical frame (z forward, x right, y down), and the
camera-to-world transform into the gravity-aligned world frame of DESIGN.md (REP-103: x forward,
y left, z up).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

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
    def matrix(self) -> F64:
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    def _coefficients(self) -> F64:
        return np.pad(np.asarray(self.distortion, dtype=np.float64), (0, 5 - len(self.distortion)))

    def distort(self, xy: F64) -> F64:
        """Normalised undistorted ``(..., 2)`` to normalised distorted coordinates."""
        k1, k2, p1, p2, k3 = self._coefficients()
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
class DepthLookup:
    """How a keypoint's depth is read from the depth image.

    The median of the valid readings in a ``(2 radius + 1)²`` window around the keypoint, after
    dropping readings more than ``band`` behind the window's 25th percentile: a keypoint on a
    shoulder's edge sees half body, half wall, and the body is the nearer half. The 25th
    percentile rather than the minimum keeps single flying pixels at depth edges from choosing the
    band. Fewer than ``min_valid`` readings in the band gives NaN (no depth)."""

    radius: int = 3
    band: float = 0.15
    min_valid: int = 4
    min_depth: float = 0.2
    max_depth: float = 10.0

    def __post_init__(self) -> None:
        if (
            self.radius < 0
            or self.band <= 0
            or self.min_valid < 1
            or not 0 <= self.min_depth < self.max_depth
        ):
            raise ValueError(f"depth lookup parameters out of range: {self}")

    def __call__(self, depth: npt.NDArray[np.floating], uv: F64) -> F64:
        """Depth (m) at each pixel of ``uv (..., 2)`` in a depth image in metres; NaN where none."""
        shape = uv.shape[:-1]
        uv = uv.reshape(-1, 2)
        out = np.full(len(uv), np.nan)
        h, w = depth.shape
        inside = np.isfinite(uv).all(axis=1)
        inside[inside] = (
            (uv[inside] >= -0.5).all(axis=1) & (uv[inside, 0] < w - 0.5) & (uv[inside, 1] < h - 0.5)
        )
        if not inside.any():
            return out.reshape(shape)
        r = self.radius
        centre = np.rint(uv[inside]).astype(np.intp)
        offsets = np.arange(-r, r + 1)
        cols = np.clip(centre[:, 0, None, None] + offsets[None, None, :], 0, w - 1)
        rows = np.clip(centre[:, 1, None, None] + offsets[None, :, None], 0, h - 1)
        window = depth[rows, cols].reshape(len(centre), -1).astype(np.float64)
        window[~((window >= self.min_depth) & (window <= self.max_depth))] = np.inf
        # Sorted rows turn the percentile, the band and the median into index arithmetic
        # (np.nanpercentile and np.nanmedian cost about 1 ms per call here).
        window.sort(axis=1)
        count = np.isfinite(window).sum(axis=1)
        position = 0.25 * np.maximum(count - 1, 0)
        low = np.floor(position).astype(np.intp)
        high = np.minimum(low + 1, np.maximum(count - 1, 0))
        a = np.take_along_axis(window, low[:, None], 1)[:, 0]
        b = np.take_along_axis(window, high[:, None], 1)[:, 0]
        with np.errstate(invalid="ignore"):  # inf - inf in rows with no reading; masked below
            front = a + (position - low) * np.where(high > low, b - a, 0.0)
        kept = (window <= (front + self.band)[:, None]).sum(axis=1)
        lo = np.take_along_axis(window, np.maximum(kept - 1, 0)[:, None] // 2, 1)[:, 0]
        hi = np.take_along_axis(window, (kept // 2)[:, None], 1)[:, 0]
        result = np.where((count >= self.min_valid) & (kept >= self.min_valid), 0.5 * (lo + hi), np.nan)
        out[inside] = result
        return out.reshape(shape)


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


def level_camera(height: float = 0.0, pitch: float = 0.0) -> F64:
    """``camera_to_world`` of a camera ``height`` m above the world origin, looking along world +x,
    tilted down by ``pitch`` rad (positive = looking down)."""
    c, s = np.cos(pitch), np.sin(pitch)
    tilt = np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])  # about world y: +x towards -z
    out = np.eye(4)
    out[:3, :3] = tilt @ OPTICAL_TO_WORLD
    out[:3, 3] = [0.0, 0.0, height]
    return out
