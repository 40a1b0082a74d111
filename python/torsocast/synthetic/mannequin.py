"""A shaded mannequin of capsules, ray-cast into a colour image, a registered depth image and a
label image that says which person each pixel shows.

It turns mocap joints into the RGB-D frames a real camera would give, so that the whole pipeline
(keypoint model included) runs on data with exact ground truth. The body is capsules between CMU
joints in an :class:`Outfit`'s colours, with a head that shows what keypoint models use to tell
front, back and the facing side in profile: eyes, a nose that stands out of the face, a mouth,
ears at the sides, and hair that covers the back and top of the head. Depth is the optical-axis
distance of the nearest surface before the sensor's faults (:mod:`.sensor`) are added: keypoints
are read off the body's surface, a few centimetres in front of the mocap joint centres.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from ..camera import Camera
from ..datasets import cmu
from .sensor import DepthNoise

F64 = npt.NDArray[np.float64]
RGB = tuple[int, int, int]

EYES, MOUTH = (25, 20, 20), (120, 40, 45)
FLOOR = ((150, 150, 140), (115, 115, 108))
SKY = (200, 210, 220)


@dataclass(frozen=True)
class Outfit:
    """The colours of one person."""

    skin: RGB = (224, 172, 140)
    shirt: RGB = (190, 50, 45)
    trousers: RGB = (45, 60, 110)
    shoes: RGB = (35, 35, 35)
    hair: RGB = (60, 40, 25)

    def colour(self, part: str) -> RGB:
        return EYES if part == "eyes" else MOUTH if part == "mouth" else getattr(self, part)  # type: ignore[no-any-return]


SKINS = ((224, 172, 140), (198, 134, 96), (141, 85, 54), (241, 194, 160), (110, 68, 45))
SHIRTS = (
    (190, 50, 45),
    (40, 120, 60),
    (230, 200, 60),
    (70, 70, 160),
    (235, 235, 235),
    (40, 40, 40),
    (200, 110, 40),
    (120, 60, 140),
)
TROUSERS = ((45, 60, 110), (60, 60, 60), (150, 130, 100), (25, 25, 30), (90, 110, 70))
SHOES = ((35, 35, 35), (230, 230, 230), (100, 60, 30))
HAIRS = ((60, 40, 25), (20, 18, 15), (150, 110, 60), (110, 50, 25), (170, 170, 170))


def random_outfit(rng: np.random.Generator) -> Outfit:
    """One of the palettes' combinations, so that the people of a scene look different."""

    def pick(options: tuple[RGB, ...]) -> RGB:
        return options[int(rng.integers(len(options)))]

    return Outfit(pick(SKINS), pick(SHIRTS), pick(TROUSERS), pick(SHOES), pick(HAIRS))


# Points the body is built from: the 38 CMU joints, then these derived ones.
(HIP_MID, SHOULDER_MID, HAIR_CENTRE, NOSE_BASE, NOSE_TIP, LEFT_EYE, RIGHT_EYE, MOUTH_CENTRE) = range(38, 46)
(LEFT_EAR, RIGHT_EAR, LEFT_CHEST, RIGHT_CHEST, LEFT_WAIST, RIGHT_WAIST) = range(46, 52)
LEFT_SLEEVE, RIGHT_SLEEVE = 52, 53

#: (from point, to point, radius m, part); a sphere where both ends are one point.
BODY = (
    (cmu.LEFT_HIP, cmu.RIGHT_HIP, 0.10, "trousers"),
    (HIP_MID, SHOULDER_MID, 0.10, "shirt"),
    (LEFT_WAIST, LEFT_CHEST, 0.085, "shirt"),
    (RIGHT_WAIST, RIGHT_CHEST, 0.085, "shirt"),
    (cmu.LEFT_SHOULDER, cmu.RIGHT_SHOULDER, 0.06, "shirt"),
    (cmu.THORAX, cmu.NECK, 0.05, "skin"),
    (HAIR_CENTRE, HAIR_CENTRE, 0.102, "hair"),
    (cmu.HEAD, cmu.HEAD, 0.095, "skin"),
    (NOSE_BASE, NOSE_TIP, 0.016, "skin"),
    (LEFT_EYE, LEFT_EYE, 0.014, "eyes"),
    (RIGHT_EYE, RIGHT_EYE, 0.014, "eyes"),
    (MOUTH_CENTRE, MOUTH_CENTRE, 0.016, "mouth"),
    (LEFT_EAR, LEFT_EAR, 0.026, "skin"),
    (RIGHT_EAR, RIGHT_EAR, 0.026, "skin"),
    (cmu.LEFT_SHOULDER, LEFT_SLEEVE, 0.055, "shirt"),
    (cmu.LEFT_SHOULDER, cmu.LEFT_ELBOW, 0.045, "skin"),
    (cmu.LEFT_ELBOW, cmu.LEFT_WRIST, 0.04, "skin"),
    (cmu.LEFT_WRIST, cmu.LEFT_FINGERS, 0.04, "skin"),
    (cmu.RIGHT_SHOULDER, RIGHT_SLEEVE, 0.055, "shirt"),
    (cmu.RIGHT_SHOULDER, cmu.RIGHT_ELBOW, 0.045, "skin"),
    (cmu.RIGHT_ELBOW, cmu.RIGHT_WRIST, 0.04, "skin"),
    (cmu.RIGHT_WRIST, cmu.RIGHT_FINGERS, 0.04, "skin"),
    (cmu.LEFT_HIP, cmu.LEFT_KNEE, 0.075, "trousers"),
    (cmu.LEFT_KNEE, cmu.LEFT_ANKLE, 0.055, "trousers"),
    (cmu.LEFT_ANKLE, cmu.LEFT_TOE, 0.045, "shoes"),
    (cmu.LEFT_TOE, cmu.LEFT_TOE_END, 0.04, "shoes"),
    (cmu.RIGHT_HIP, cmu.RIGHT_KNEE, 0.075, "trousers"),
    (cmu.RIGHT_KNEE, cmu.RIGHT_ANKLE, 0.055, "trousers"),
    (cmu.RIGHT_ANKLE, cmu.RIGHT_TOE, 0.045, "shoes"),
    (cmu.RIGHT_TOE, cmu.RIGHT_TOE_END, 0.04, "shoes"),
)


def body_points(joints: F64) -> F64:
    """The 38 world joints of one frame plus the derived points :data:`BODY` refers to."""
    left = joints[cmu.LEFT_SHOULDER] - joints[cmu.RIGHT_SHOULDER]
    up = joints[cmu.HEAD_TOP] - joints[cmu.NECK]
    up /= np.linalg.norm(up)
    forward = np.cross(left, up)
    forward /= np.linalg.norm(forward)
    side = np.cross(up, forward)  # the person's left
    head = joints[cmu.HEAD]
    hips = 0.5 * (joints[cmu.LEFT_HIP] + joints[cmu.RIGHT_HIP])
    shoulders = 0.5 * (joints[cmu.LEFT_SHOULDER] + joints[cmu.RIGHT_SHOULDER])
    torso_up = shoulders - hips
    extra = [
        hips,
        shoulders,
        # Hair: a sphere a little behind and above the face's, so that it covers the back and
        # the top of the head and leaves the face bare.
        head - 0.03 * forward + 0.025 * up,
        head + 0.08 * forward - 0.01 * up,
        head + 0.115 * forward - 0.02 * up,  # the nose stands out of the face: seen in profile
        head + 0.083 * forward + 0.035 * side + 0.025 * up,
        head + 0.083 * forward - 0.035 * side + 0.025 * up,
        head + 0.078 * forward - 0.05 * up,
        head + 0.095 * side - 0.005 * forward,
        head - 0.095 * side - 0.005 * forward,
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
class Rendered:
    """One rendered frame."""

    rgb: npt.NDArray[np.uint8]
    """``(h, w, 3)`` colour."""
    depth: npt.NDArray[np.float32]
    """``(h, w)`` metres along the optical axis as the sensor reports it, 0 where no reading."""
    labels: npt.NDArray[np.int8]
    """``(h, w)`` index of the person each pixel shows, -1 for the floor and the sky."""
    clean_depth: F64
    """``(h, w)`` the exact depth before the sensor's faults, inf where nothing is hit."""


@dataclass(frozen=True)
class Scene:
    """What the virtual camera sees: its image size, and the depth sensor's faults."""

    width: int = 640
    height: int = 480
    noise: DepthNoise | None = field(default_factory=DepthNoise)
    """The depth sensor's noise, holes and flying pixels; None for exact depth."""
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
        people: F64 | Sequence[F64],
        camera: Camera,
        rng: np.random.Generator | None = None,
        rays: F64 | None = None,
        background: tuple[F64, F64] | None = None,
        outfits: Sequence[Outfit] | None = None,
    ) -> Rendered:
        """One frame of the world joints ``(38, 3)`` of one person, or of several people
        ``(people, 38, 3)``, in their ``outfits`` (default: :class:`Outfit`'s colours). Sensor
        faults are drawn from ``rng`` (none without one); ``rays`` and ``background`` may be
        passed in when they are reused."""
        people = [np.asarray(people)] if np.ndim(people) == 2 else [np.asarray(p) for p in people]
        outfits = list(outfits) if outfits is not None else [Outfit()] * len(people)
        if len(outfits) != len(people):
            raise ValueError(f"{len(people)} people need as many outfits, got {len(outfits)}")
        rays = self.rays(camera) if rays is None else rays
        rgb, depth = self.background(camera, rays) if background is None else background
        rgb, depth = rgb.copy(), depth.copy()
        labels = np.full(depth.shape, -1, dtype=np.int8)
        pose = np.asarray(camera.camera_to_world)
        for index, (joints, outfit) in enumerate(zip(people, outfits)):
            points = (body_points(joints) - pose[:3, 3]) @ pose[:3, :3]  # world -> optical
            for a, b, radius, part in BODY:
                drawn = _capsule(rays, camera, points[a], points[b], radius, outfit.colour(part), depth, rgb)
                if drawn is not None:
                    rows, cols, mask = drawn
                    labels[rows, cols][mask] = index
        clean = depth.copy()
        if rng is not None and self.noise is not None:
            sensed = self.noise.apply(depth, camera.intrinsics.fx, rng)
        else:
            sensed = np.where(np.isfinite(depth), depth, 0.0)
        return Rendered(rgb.clip(0, 255).astype(np.uint8), sensed.astype(np.float32), labels, clean)

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
    colour: RGB,
    depth: F64,
    rgb: F64,
) -> tuple[slice, slice, npt.NDArray[np.bool_]] | None:
    """Draws one capsule (optical frame) where it is nearer than what ``depth`` holds, and returns
    where it drew (a window and a mask in it, an index for an image), None where it is out of
    view. Each pixel takes the axis point nearest its ray and the sphere of ``radius`` there:
    exact for the end caps, and within a fraction of the radius on the sides of the thin limbs."""
    if min(a[2], b[2]) < radius + 0.05:
        return None  # behind or touching the camera: not in view
    h, w = depth.shape
    ends = camera.intrinsics.project(np.array([a, b]))
    margin = radius * max(camera.intrinsics.fx, camera.intrinsics.fy) / min(a[2], b[2]) + 2
    u0, v0 = np.maximum(np.floor(ends.min(axis=0) - margin).astype(int), 0)
    u1, v1 = np.minimum(np.ceil(ends.max(axis=0) + margin).astype(int), [w - 1, h - 1])
    if u0 > u1 or v0 > v1:
        return None
    rows, cols = slice(v0, v1 + 1), slice(u0, u1 + 1)
    d = rays[rows, cols]
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
    window = depth[rows, cols]
    drawn = inside & (z < window)
    window[drawn] = z[drawn]
    normal = (s_hit[..., None] * d - nearest) / radius
    light = 0.3 + 0.7 * np.clip(-(normal * d).sum(axis=-1), 0.0, 1.0)  # a lamp at the camera
    rgb[rows, cols][drawn] = (np.asarray(colour, dtype=np.float64) * light[..., None])[drawn]
    return rows, cols, drawn
