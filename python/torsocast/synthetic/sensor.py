"""Depth sensors as the benchmark renders them: the intrinsics of two common RGB-D cameras, and
the faults of their depth images.

A real depth image is not the exact distance to the nearest surface. Its noise grows with the
square of the distance (stereo and structured light by triangulation, time of flight through
its amplitude at range); it has holes where a surface is seen at a grazing angle and along depth
edges, where the projector's pattern or the reflected light does not come back; and pixels on a
silhouette that see both the person and the wall behind read a distance in between (flying
pixels). :class:`DepthNoise` adds those to a rendered depth image.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from ..camera import Intrinsics

F64 = npt.NDArray[np.float64]


@dataclass(frozen=True)
class DepthNoise:
    """Faults of a depth image; the defaults are those of a Kinect v2-class sensor."""

    sigma_1m: float = 0.0015
    """Standard deviation of the depth noise at 1 m (m); it grows with the square of the depth."""
    edge_jump: float = 0.10
    """A pixel whose depth differs from a neighbour's by more than this (m) is on a depth edge."""
    edge_holes: float = 0.4
    """Probability that a depth-edge pixel has no reading."""
    flying: float = 0.4
    """Probability that a depth-edge pixel with a reading reads a depth between the two sides."""
    grazing_deg: float = 78.0
    """Surfaces seen more obliquely than this (angle between the surface normal and the ray)..."""
    grazing_holes: float = 0.7
    """...have no reading with this probability."""
    quantum: float = 0.001
    """Depth steps of the raw image (m)."""

    def apply(self, depth: F64, fx: float, rng: np.random.Generator) -> F64:
        """The sensor's reading of an exact ``depth (h, w)`` (inf where nothing is hit) seen with
        focal length ``fx`` (px): metres, 0 where there is no reading."""
        z = depth.astype(np.float32)
        seen = np.isfinite(z)
        padded = np.pad(z, 1, mode="edge")
        neighbours = (padded[:-2, 1:-1], padded[2:, 1:-1], padded[1:-1, :-2], padded[1:-1, 2:])
        edge = np.zeros(z.shape, dtype=bool)
        behind = np.full(z.shape, -np.inf, dtype=np.float32)
        with np.errstate(invalid="ignore"):
            for n in neighbours:
                # A neighbour with nothing behind it (sky, inf) is as far as can be: an edge.
                jump = np.abs(n - z) > self.edge_jump
                edge |= jump
                np.maximum(behind, np.where(jump & np.isfinite(n), n, -np.inf), out=behind)
            edge &= seen
            gx = padded[1:-1, 2:] - padded[1:-1, :-2]
            gy = padded[2:, 1:-1] - padded[:-2, 1:-1]
            # One pixel spans z / fx metres; the depth change across it gives the surface's slope.
            grazing = (
                seen & ~edge & (np.hypot(gx, gy) * (0.5 * fx) > np.tan(np.radians(self.grazing_deg)) * z)
            )
        out = np.where(seen, z, 0.0).astype(np.float32)
        out += rng.standard_normal(z.shape, dtype=np.float32) * np.float32(self.sigma_1m) * out**2
        draw = rng.random(z.shape, dtype=np.float32)
        fly = edge & (draw < self.flying) & np.isfinite(behind)
        blend = rng.random(int(fly.sum()), dtype=np.float32)
        out[fly] = z[fly] + blend * (behind[fly] - z[fly])
        hole = (edge & ~fly & (draw < self.flying + (1 - self.flying) * self.edge_holes)) | (
            grazing & (draw < self.grazing_holes)
        )
        out[hole] = 0.0
        np.maximum(out, 0.0, out=out)
        if self.quantum > 0:
            out = np.round(out / np.float32(self.quantum)) * np.float32(self.quantum)
        return out.astype(np.float64)


@dataclass(frozen=True)
class Sensor:
    """An RGB-D camera: image size, intrinsics of the colour image the depth is registered to,
    and its depth faults."""

    name: str
    width: int
    height: int
    intrinsics: Intrinsics
    noise: DepthNoise


#: A Kinect v2 with colour registered to depth at the depth camera's resolution (512x424, 70.6
#: by 60 degrees), and a RealSense D435 with depth registered to its 640x480 colour stream (55 by
#: 43 degrees). The D435's stereo noise at range is larger than the time-of-flight Kinect's.
SENSORS = {
    "kinect_v2": Sensor("kinect_v2", 512, 424, Intrinsics(365.0, 365.0, 255.5, 211.5), DepthNoise()),
    "d435": Sensor(
        "d435", 640, 480, Intrinsics(615.0, 615.0, 319.5, 239.5), DepthNoise(sigma_1m=0.003, edge_holes=0.5)
    ),
}
