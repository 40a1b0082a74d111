"""2D keypoints to 3D joints: a robust depth per keypoint, deprojected, moved into the world."""

from __future__ import annotations

import numpy as np

from .camera import F64, Camera, DepthLookup


def lift(keypoints: F64, depth: np.ndarray, camera: Camera, lookup: DepthLookup | None = None) -> F64:
    """``(people, 17, 3)`` keypoints (u, v, score) to ``(people, 17, 3)`` world points (m), NaN
    where the depth image has no reading for a keypoint (a hole, the background, off the image)."""
    lookup = lookup or DepthLookup()
    uv = keypoints[..., :2]
    z = lookup(depth, uv)
    return camera.to_world(camera.intrinsics.deproject(uv, z))
