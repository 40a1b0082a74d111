"""torsocast: 3D torso pose of every person in an RGB-D stream, forecast up to 2 s ahead.

The per-frame engine (depth lookup and deprojection, association of detections to tracks, torso
plane, joint gating, Butterworth low-pass, penalised B-spline forecast) runs in the Rust crate
``torso_core`` through ``torsocast._core``; this package adds the keypoint model, the sources and
the names a Python user expects. Conventions: SI units and radians; world frame x forward, y left,
z up; a pose is ``[x, y, z, azimuth, elevation]``; a missing joint is NaN.
"""

from enum import IntEnum

from ._core import (
    MAX_DEGREE,
    MAX_HORIZON,
    AmbiguousOrientationError,
    CollinearJointsError,
    DepthLookup,
    Forecaster,
    ForecasterConfig,
    InvalidArgumentError,
    JointGate,
    LowPass,
    NonFiniteError,
    NotEnoughHistoryError,
    NotPositiveDefiniteError,
    Observation,
    Person,
    PersonConfig,
    ShapeError,
    TimeNotIncreasingError,
    TooFewJointsError,
    TorsocastError,
    TorsoPlane,
    Tracker,
    TrackerConfig,
    TrackOutcome,
    TrackState,
    __version__,
    body_frame,
    butter_lowpass,
    fit_plane,
    fit_planes,
    fit_smoothing_spline,
    forecast_batch,
    linear_assignment,
    lowpass_causal,
    lowpass_zero_phase,
    shoulder_heading,
)

#: Order of the components of a pose array's last axis.
COMPONENTS = ("x", "y", "z", "azimuth", "elevation")


class JointStatus(IntEnum):
    """Codes returned by :meth:`JointGate.update`."""

    MEASURED = 0
    REPLACED = 1
    LOST = 2


class PlaneStatus(IntEnum):
    """Codes in the ``status`` array of :func:`fit_planes`."""

    OK = 0
    TOO_FEW_JOINTS = 1
    COLLINEAR = 2
    AMBIGUOUS_ORIENTATION = 3


def wrap_angle(angle):  # type: ignore[no-untyped-def]
    """Wraps angles (scalars or arrays) into (-pi, pi], e.g. a forecast azimuth for display."""
    import numpy as np

    return np.arctan2(np.sin(angle), np.cos(angle))


__all__ = [
    "COMPONENTS",
    "MAX_DEGREE",
    "MAX_HORIZON",
    "AmbiguousOrientationError",
    "CollinearJointsError",
    "DepthLookup",
    "Forecaster",
    "ForecasterConfig",
    "InvalidArgumentError",
    "JointGate",
    "JointStatus",
    "LowPass",
    "NonFiniteError",
    "NotEnoughHistoryError",
    "NotPositiveDefiniteError",
    "Observation",
    "Person",
    "PersonConfig",
    "PlaneStatus",
    "ShapeError",
    "TimeNotIncreasingError",
    "TooFewJointsError",
    "TorsoPlane",
    "TorsocastError",
    "TrackOutcome",
    "TrackState",
    "Tracker",
    "TrackerConfig",
    "__version__",
    "body_frame",
    "butter_lowpass",
    "fit_plane",
    "fit_planes",
    "fit_smoothing_spline",
    "forecast_batch",
    "linear_assignment",
    "lowpass_causal",
    "lowpass_zero_phase",
    "shoulder_heading",
    "wrap_angle",
]
