"""Exponential maps and the forward kinematics both mocap formats share (row-vector convention of
the motion-prediction literature: ``xyz_j = offset_j R_parent + xyz_parent``,
``R_j = exp(r_j) R_parent``)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]


def expmap_to_rotmat(r: npt.ArrayLike) -> F64:
    """Rodrigues' formula for any number of exponential maps ``(..., 3)`` -> ``(..., 3, 3)``, with the
    ``θ + eps`` guard of the reference code so that a zero rotation gives the identity."""
    r = np.asarray(r, dtype=np.float64)
    theta = np.linalg.norm(r, axis=-1)[..., None, None]
    k = r / (theta[..., 0] + np.finfo(np.float32).eps)
    zero = np.zeros(k.shape[:-1])
    cross = np.stack(
        [
            np.stack([zero, -k[..., 2], k[..., 1]], -1),
            np.stack([k[..., 2], zero, -k[..., 0]], -1),
            np.stack([-k[..., 1], k[..., 0], zero], -1),
        ],
        -2,
    )
    return np.eye(3) + np.sin(theta) * cross + (1.0 - np.cos(theta)) * (cross @ cross)


def rotmat_to_expmap(rotation: F64) -> F64:
    """The exponential maps ``(..., 3)`` of rotations ``(..., 3, 3)`` turned by less than a half
    turn, the inverse of :func:`expmap_to_rotmat`."""
    rotation = np.asarray(rotation, dtype=np.float64)
    skew = np.stack(
        [
            rotation[..., 2, 1] - rotation[..., 1, 2],
            rotation[..., 0, 2] - rotation[..., 2, 0],
            rotation[..., 1, 0] - rotation[..., 0, 1],
        ],
        -1,
    )
    cos = np.clip((np.trace(rotation, axis1=-2, axis2=-1) - 1.0) / 2.0, -1.0, 1.0)
    theta = np.arccos(cos)[..., None]
    sin = np.sin(theta)
    # theta / sin(theta) tends to one for a small turn.
    scale = np.where(sin > 1e-12, theta / np.where(sin > 1e-12, sin, 1.0), 1.0)
    return 0.5 * scale * skew


def rotmat_to_euler(rotation: F64) -> F64:
    """The Euler angles ``(..., 3)`` of rotations ``(..., 3, 3)`` as the motion-prediction
    literature computes them (``rotmat2euler`` of its reference code, gimbal lock included),
    for the joint-angle error it reports."""
    rotation = np.asarray(rotation, dtype=np.float64)
    r02 = rotation[..., 0, 2]
    locked = np.abs(r02) == 1.0
    e2 = np.where(locked, -np.sign(r02) * np.pi / 2, -np.arcsin(np.clip(r02, -1.0, 1.0)))
    cos = np.where(locked, 1.0, np.cos(e2))
    e1 = np.where(
        locked,
        np.arctan2(rotation[..., 0, 1], r02),
        np.arctan2(rotation[..., 1, 2] / cos, rotation[..., 2, 2] / cos),
    )
    e3 = np.where(locked, 0.0, np.arctan2(rotation[..., 0, 1] / cos, rotation[..., 0, 0] / cos))
    return np.stack([e1, e2, e3], axis=-1)


def chain(parents: npt.ArrayLike, offsets: F64, root_rotation: F64, root_position: F64, local: F64) -> F64:
    """Global joint positions ``(frames, joints, 3)`` from the root's rotation ``(frames, 3, 3)`` and
    position ``(frames, 3)`` and every joint's local rotation ``(frames, joints, 3, 3)`` (the root's
    entry is not read); ``offsets (joints, 3)`` are in the parent's frame."""
    parents = np.asarray(parents)
    frames, joints = local.shape[:2]
    rotations = np.empty_like(local)
    xyz = np.empty((frames, joints, 3))
    rotations[:, 0] = root_rotation
    xyz[:, 0] = offsets[0] + root_position
    for j in range(1, joints):
        p = parents[j]
        xyz[:, j] = offsets[j] @ rotations[:, p] + xyz[:, p]
        rotations[:, j] = local[:, j] @ rotations[:, p]
    return xyz
