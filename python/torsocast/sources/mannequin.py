"""A shaded mannequin of capsules, ray-cast into a colour and a registered depth image.

It turns mocap joints into the RGB-D frames a real camera would give, so that the whole pipeline
(keypoint model included) runs on data that ships with torsocast and has exact ground truth.
The body is capsules between CMU joints with clothing colours, a head with hair and a face (the
keypoint models tell front from back by the face), standing on a checkered floor. Depth is the
optical-axis distance of the nearest surface, as a registered depth camera reports it: the
keypoints are read off the body's surface, a few centimetres in front of the mocap joint centres.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..camera import Camera
from ..datasets import cmu

F64 = npt.NDArray[np.float64]

SKIN, SHIRT, TROUSERS, SHOES = (224, 172, 140), (190, 50, 45), (45, 60, 110), (35, 35, 35)
HAIR, EYES = (60, 40, 25), (25, 20, 20)
FLOOR = ((150, 150, 140), (115, 115, 108))
SKY = (200, 210, 220)

# Points the body is built from: the 38 CMU joints, then these derived ones.
HIP_MID, SHOULDER_MID, HAIR_CENTRE, NOSE, LEFT_EYE, RIGHT_EYE = range(38, 44)
LEFT_CHEST, RIGHT_CHEST, LEFT_WAIST, RIGHT_WAIST, LEFT_SLEEVE, RIGHT_SLEEVE = range(44, 50)

#: (from point, to point, radius m, colour); a sphere where both ends are one point.
BODY = (
    (cmu.LEFT_HIP, cmu.RIGHT_HIP, 0.10, TROUSERS),
    (HIP_MID, SHOULDER_MID, 0.10, SHIRT),
    (LEFT_WAIST, LEFT_CHEST, 0.085, SHIRT),
    (RIGHT_WAIST, RIGHT_CHEST, 0.085, SHIRT),
    (cmu.LEFT_SHOULDER, cmu.RIGHT_SHOULDER, 0.06, SHIRT),
    (cmu.THORAX, cmu.NECK, 0.05, SKIN),
    (HAIR_CENTRE, HAIR_CENTRE, 0.10, HAIR),
    (cmu.HEAD, cmu.HEAD, 0.10, SKIN),
    (NOSE, NOSE, 0.02, SKIN),
    (LEFT_EYE, LEFT_EYE, 0.014, EYES),
    (RIGHT_EYE, RIGHT_EYE, 0.014, EYES),
    (cmu.LEFT_SHOULDER, LEFT_SLEEVE, 0.055, SHIRT),
    (cmu.LEFT_SHOULDER, cmu.LEFT_ELBOW, 0.045, SKIN),
    (cmu.LEFT_ELBOW, cmu.LEFT_WRIST, 0.04, SKIN),
    (cmu.LEFT_WRIST, cmu.LEFT_FINGERS, 0.04, SKIN),
    (cmu.RIGHT_SHOULDER, RIGHT_SLEEVE, 0.055, SHIRT),
    (cmu.RIGHT_SHOULDER, cmu.RIGHT_ELBOW, 0.045, SKIN),
    (cmu.RIGHT_ELBOW, cmu.RIGHT_WRIST, 0.04, SKIN),
    (cmu.RIGHT_WRIST, cmu.RIGHT_FINGERS, 0.04, SKIN),
    (cmu.LEFT_HIP, cmu.LEFT_KNEE, 0.075, TROUSERS),
    (cmu.LEFT_KNEE, cmu.LEFT_ANKLE, 0.055, TROUSERS),
    (cmu.LEFT_ANKLE, cmu.LEFT_TOE, 0.045, SHOES),
    (cmu.LEFT_TOE, cmu.LEFT_TOE_END, 0.04, SHOES),
    (cmu.RIGHT_HIP, cmu.RIGHT_KNEE, 0.075, TROUSERS),
    (cmu.RIGHT_KNEE, cmu.RIGHT_ANKLE, 0.055, TROUSERS),
    (cmu.RIGHT_ANKLE, cmu.RIGHT_TOE, 0.045, SHOES),
    (cmu.RIGHT_TOE, cmu.RIGHT_TOE_END, 0.04, SHOES),
)


def body_points(joints: F64) -> F64:
    """The 38 world joints of one frame plus the derived points :data:`BODY` refers to."""
    left = joints[cmu.LEFT_SHOULDER] - joints[cmu.RIGHT_SHOULDER]
    up = joints[cmu.HEAD_TOP] - joints[cmu.NECK]
    up /= np.linalg.norm(up)
    forward = np.cross(left, up)
    forward /= np.linalg.norm(forward)
    side = np.cross(up, forward)
    head = joints[cmu.HEAD]
    hips = 0.5 * (joints[cmu.LEFT_HIP] + joints[cmu.RIGHT_HIP])
    shoulders = 0.5 * (joints[cmu.LEFT_SHOULDER] + joints[cmu.RIGHT_SHOULDER])
    torso_up = shoulders - hips
    extra = [
        hips,
        shoulders,
        head - 0.025 * forward + 0.02 * up,
        head + 0.10 * forward - 0.01 * up,
        head + 0.088 * forward + 0.035 * side + 0.025 * up,
        head + 0.088 * forward - 0.035 * side + 0.025 * up,
        # The chest and waist are two flanks, so that the torso is wider than deep.
        shoulders + 0.55 * (joints[cmu.LEFT_SHOULDER] - shoulders) - 0.15 * torso_up,
        shoulders + 0.55 * (joints[cmu.RIGHT_SHOULDER] - shoulders) - 0.15 * torso_up,
        hips + 0.8 * (joints[cmu.LEFT_HIP] - hips) + 0.25 * torso_up,
        hips + 0.8 * (joints[cmu.RIGHT_HIP] - hips) + 0.25 * torso_up,
        # Short sleeves: the arms show skin against the shirt.
        joints[cmu.LEFT_SHOULDER] + 0.4 * (joints[cmu.LEFT_ELBOW] - joints[cmu.LEFT_SHOULDER]),
        joints[cmu.RIGHT_SHOULDER] + 0.4 * (joints[cmu.RIGHT_ELBOW] - joints[cmu.RIGHT_SHOULDER]),
    ]
    return np.vstack([joints, extra])


@dataclass(frozen=True)
class Scene:
    """What the virtual camera sees: its image size, and depth noise like a structured-light or
    time-of-flight sensor's (standard deviation ``noise * z²``)."""

    width: int = 640
    height: int = 480
    noise: float = 0.0015
    """Depth noise in metres at 1 m; it grows with the square of the distance."""
    max_range: float = 10.0

    def rays(self, camera: Camera) -> F64:
        """Unit ray of every pixel centre in the optical frame, ``(h, w, 3)``."""
        k = camera.intrinsics
        u, v = np.meshgrid(np.arange(self.width, dtype=np.float64), np.arange(self.height, dtype=np.float64))
        xy = k.undistort(np.stack([(u - k.cx) / k.fx, (v - k.cy) / k.fy], axis=-1))
        d = np.concatenate([xy, np.ones((self.height, self.width, 1))], axis=-1)
        return d / np.linalg.norm(d, axis=-1, keepdims=True)  # type: ignore[no-any-return]

    def background(self, camera: Camera, rays: F64) -> tuple[F64, F64]:
        """Colour and depth of the empty scene (the floor, and sky beyond ``max_range``), which
        a fixed camera can render once."""
        pose = np.asarray(camera.camera_to_world)
        depth = np.full((self.height, self.width), np.inf)
        rgb = np.empty((self.height, self.width, 3))
        self._floor(rays, pose[:3, :3], pose[:3, 3], depth, rgb)
        return rgb, depth

    def render(
        self,
        joints: F64,
        camera: Camera,
        rng: np.random.Generator | None = None,
        rays: F64 | None = None,
        background: tuple[F64, F64] | None = None,
    ) -> tuple[npt.NDArray[np.uint8], npt.NDArray[np.float32]]:
        """RGB ``(h, w, 3)`` and depth ``(h, w)`` in metres (0 = no reading) of one frame's world
        joints ``(38, 3)``; ``rays`` and ``background`` may be passed in when they are reused."""
        rays = self.rays(camera) if rays is None else rays
        rgb, depth = self.background(camera, rays) if background is None else background
        rgb, depth = rgb.copy(), depth.copy()
        pose = np.asarray(camera.camera_to_world)
        points = (body_points(joints) - pose[:3, 3]) @ pose[:3, :3]  # world -> optical
        for a, b, radius, colour in BODY:
            _capsule(rays, camera, points[a], points[b], radius, colour, depth, rgb)
        if rng is not None and self.noise > 0:
            seen = np.isfinite(depth)
            depth[seen] += rng.normal(0.0, 1.0, seen.sum()) * self.noise * depth[seen] ** 2
        depth[~np.isfinite(depth)] = 0.0
        return rgb.clip(0, 255).astype(np.uint8), depth.astype(np.float32)

    def _floor(self, rays: F64, rotation: F64, origin: F64, depth: F64, rgb: F64) -> None:
        """The plane z = 0 in a checker of 0.5 m squares, and sky beyond ``max_range``."""
        down = rays @ rotation.T
        falling = down[..., 2] < -1e-6
        s = np.full(depth.shape, np.inf)
        s[falling] = -origin[2] / down[falling, 2]
        hit = s * rays[..., 2] < self.max_range
        depth[hit] = (s * rays[..., 2])[hit]
        where = origin + s[hit][:, None] * down[hit]
        dark = (np.floor(2 * where[:, 0]) + np.floor(2 * where[:, 1])) % 2 > 0
        rgb[hit] = np.where(dark[:, None], FLOOR[1], FLOOR[0])
        rgb[~hit] = SKY


def _capsule(
    rays: F64,
    camera: Camera,
    a: F64,
    b: F64,
    radius: float,
    colour: tuple[int, int, int],
    depth: F64,
    rgb: F64,
) -> None:
    """Draws one capsule (optical frame) where it is nearer than what ``depth`` holds. Each pixel
    takes the axis point nearest its ray and the sphere of ``radius`` there: exact for the end
    caps, and within a fraction of the radius on the sides of the thin limbs."""
    if min(a[2], b[2]) < radius + 0.05:
        return  # behind or touching the camera: not in view
    h, w = depth.shape
    ends = camera.intrinsics.project(np.array([a, b]))
    margin = radius * max(camera.intrinsics.fx, camera.intrinsics.fy) / min(a[2], b[2]) + 2
    u0, v0 = np.maximum(np.floor(ends.min(axis=0) - margin).astype(int), 0)
    u1, v1 = np.minimum(np.ceil(ends.max(axis=0) + margin).astype(int), [w - 1, h - 1])
    if u0 > u1 or v0 > v1:
        return
    d = rays[v0 : v1 + 1, u0 : u1 + 1]
    axis = b - a
    length2 = axis @ axis
    t = np.zeros(d.shape[:2])
    if length2 > 1e-12:
        along = d @ axis
        denom = length2 - along**2  # zero where the ray runs along the axis
        safe = np.where(denom > 1e-12, denom, 1.0)
        t = np.clip(np.where(denom > 1e-12, (along * (d @ a) - a @ axis) / safe, 0.0), 0.0, 1.0)
    nearest = a + t[..., None] * axis
    s = np.einsum("ijk,ijk->ij", d, nearest)
    miss2 = np.einsum("ijk,ijk->ij", nearest, nearest) - s**2
    inside = miss2 < radius * radius
    s_hit = s - np.sqrt(np.maximum(radius * radius - miss2, 0.0))
    z = s_hit * d[..., 2]
    window = depth[v0 : v1 + 1, u0 : u1 + 1]
    drawn = inside & (z < window)
    window[drawn] = z[drawn]
    normal = (s_hit[..., None] * d - nearest) / radius
    light = 0.3 + 0.7 * np.clip(-(normal * d).sum(axis=-1), 0.0, 1.0)  # a lamp at the camera
    rgb[v0 : v1 + 1, u0 : u1 + 1][drawn] = (np.asarray(colour, dtype=np.float64) * light[..., None])[drawn]
