"""Type stubs of the compiled module ``torsocast._core`` (checked against it by mypy's stubtest)."""

from collections.abc import Sequence
from typing import Literal

import numpy as np
import numpy.typing as npt
from typing_extensions import TypeAlias, final

__all__ = [
    "AmbiguousOrientationError",
    "CollinearJointsError",
    "DepthLookup",
    "Forecaster",
    "ForecasterConfig",
    "InvalidArgumentError",
    "JointGate",
    "LowPass",
    "JOINT_STATUS",
    "MAX_DEGREE",
    "MAX_HORIZON",
    "MIN_ORIENTATION_COSINE",
    "PLANE_STATUS",
    "NonFiniteError",
    "NotEnoughHistoryError",
    "NotPositiveDefiniteError",
    "Observation",
    "Person",
    "PersonConfig",
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
    "lowpass_causal",
    "lowpass_zero_phase",
    "shoulder_heading",
]

__version__: str
MAX_DEGREE: int
MIN_ORIENTATION_COSINE: float
MAX_HORIZON: float
PLANE_STATUS: dict[str, int]
JOINT_STATUS: dict[str, int]

_ArrayLike: TypeAlias = npt.ArrayLike
_F64: TypeAlias = npt.NDArray[np.float64]
# A list or a 1-D NumPy array: the binding reads any sequence of numbers.
_Floats: TypeAlias = Sequence[float] | npt.NDArray[np.floating]

class TorsocastError(ValueError): ...
class InvalidArgumentError(TorsocastError): ...
class ShapeError(TorsocastError): ...
class NonFiniteError(TorsocastError): ...
class TooFewJointsError(TorsocastError): ...
class CollinearJointsError(TorsocastError): ...
class AmbiguousOrientationError(TorsocastError): ...
class NotPositiveDefiniteError(TorsocastError): ...
class NotEnoughHistoryError(TorsocastError): ...
class TimeNotIncreasingError(TorsocastError): ...

@final
class TorsoPlane:
    @property
    def centre(self) -> _F64: ...
    @property
    def normal(self) -> _F64: ...
    @property
    def azimuth(self) -> float: ...
    @property
    def elevation(self) -> float: ...
    @property
    def rms_residual(self) -> float: ...
    @property
    def joints_used(self) -> int: ...

def fit_plane(joints: _ArrayLike, sides: str, weights: _ArrayLike | None = None) -> TorsoPlane: ...
def fit_planes(
    joints: _ArrayLike,
    sides: str,
    weights: _ArrayLike | None = None,
    min_orientation_cosine: float | None = None,
) -> dict[str, npt.NDArray[np.float64] | npt.NDArray[np.uint8]]: ...
def shoulder_heading(left: _Floats, right: _Floats) -> tuple[_F64, float]: ...
def body_frame(pose: _Floats) -> tuple[_F64, _F64]:
    """The body frame of ``pose`` ``[x, y, z, azimuth, elevation]`` in its world frame (REP-155's
    ``body_<id>``): the translation (the pose's centre) and the rotation as a unit quaternion
    ``[x, y, z, w]`` (ROS's order, ``w`` never negative). The frame's x axis points out of the
    chest (the pose's normal), z towards the head (in the vertical plane through the normal: the
    roll a five-component pose does not carry), y to the body's left. Raises
    ``NonFiniteError`` for a component that is not finite, ``InvalidArgumentError`` for an
    elevation outside 0 to π, ``ShapeError`` for a pose that is not five numbers."""

@final
class JointGate:
    def __new__(
        cls, n_joints: int, threshold: float | None = None, max_replacements: int | None = None
    ) -> JointGate: ...
    @property
    def n_joints(self) -> int: ...
    @property
    def threshold(self) -> float: ...
    @property
    def max_replacements(self) -> int: ...
    def update(self, joints: _ArrayLike) -> tuple[_F64, npt.NDArray[np.uint8]]: ...
    def reset(self) -> None: ...

def butter_lowpass(order: int, cutoff_hz: float, rate_hz: float) -> _F64: ...
def lowpass_causal(
    x: _ArrayLike, order: int | None = None, cutoff_hz: float | None = None, rate_hz: float | None = None
) -> _F64:
    """Causal Butterworth low-pass of a window from steady state at its first sample (SciPy's
    ``sosfilt`` with ``sosfilt_zi``); the thesis' filter (2nd order, 5 Hz at 25 Hz) for what is
    left out."""

def lowpass_zero_phase(
    x: _ArrayLike, order: int | None = None, cutoff_hz: float | None = None, rate_hz: float | None = None
) -> _F64:
    """Forward-backward Butterworth low-pass (SciPy's ``sosfiltfilt``); the thesis' filter for
    what is left out."""

@final
class LowPass:
    def __new__(
        cls, order: int | None = None, cutoff_hz: float | None = None, rate_hz: float | None = None
    ) -> LowPass: ...
    def step(self, x: float) -> float: ...
    def filter(self, x: _ArrayLike) -> _F64: ...
    def reset(self) -> None: ...
    @property
    def sos(self) -> _F64: ...

def fit_smoothing_spline(
    x: _ArrayLike, y: _ArrayLike, w: _ArrayLike | None = None, lam: float = 1.0, degree: int = 3
) -> tuple[_F64, _F64]: ...

@final
class ForecasterConfig:
    """Every forecasting choice (``torso_core::ForecasterConfig``), validated and frozen; every
    keyword left out takes the core's default (the thesis' forecaster with a damped
    continuation). :meth:`options` lists the names each option takes."""

    def __new__(
        cls,
        method: Literal["filter_spline", "const", "constant_velocity"] | None = None,
        *,
        rate_hz: float | None = None,
        history: float | None = None,
        max_gap: float | None = None,
        fast_path: bool | None = None,
        velocity_window: float | None = None,
        filter: Literal["off", "causal", "zero_phase"] | None = None,
        filter_order: int | None = None,
        cutoff_hz: float | None = None,
        filter_components: Sequence[bool] | None = None,
        degree: int | None = None,
        lam: float | None = None,
        lambda_unit: Literal["samples", "seconds"] | None = None,
        extrapolation: Literal["polynomial", "linear", "damped"] | None = None,
        damping: _Floats | None = None,
    ) -> ForecasterConfig: ...
    @staticmethod
    def options() -> dict[str, list[str]]:
        """The names each option takes: method, filter, lambda_unit, extrapolation."""
    def __getnewargs_ex__(self) -> tuple[tuple[()], dict[str, object]]: ...
    @property
    def method(self) -> str: ...
    @property
    def rate_hz(self) -> float: ...
    @property
    def history(self) -> float: ...
    @property
    def max_gap(self) -> float: ...
    @property
    def fast_path(self) -> bool: ...
    @property
    def velocity_window(self) -> float | None:
        """The constant-velocity window (s); None for the whole history or another method."""
    @property
    def filter(self) -> str | None:
        """The filter + spline settings (this one and those below) are None for the other
        methods, which have none; giving one to another method raises."""
    @property
    def filter_order(self) -> int | None: ...
    @property
    def cutoff_hz(self) -> float | None: ...
    @property
    def filter_components(self) -> list[bool] | None: ...
    @property
    def degree(self) -> int | None: ...
    @property
    def lam(self) -> float | None: ...
    @property
    def lambda_unit(self) -> str | None: ...
    @property
    def extrapolation(self) -> str | None: ...
    @property
    def damping(self) -> list[float] | None: ...
    @property
    def capacity(self) -> int: ...
    @staticmethod
    def live() -> ForecasterConfig: ...

@final
class Forecaster:
    def __new__(cls, config: ForecasterConfig | None = None) -> Forecaster: ...
    def update(self, pose: _Floats, t: float, weight: float = 1.0) -> tuple[int, bool]: ...
    def forecast(self, horizons: _Floats) -> _F64: ...
    def reset(self) -> None: ...
    def __len__(self) -> int: ...
    @property
    def capacity(self) -> int: ...
    @property
    def min_samples(self) -> int: ...
    @property
    def last_time(self) -> float | None: ...
    @property
    def config(self) -> ForecasterConfig: ...
    def history(self) -> tuple[_F64, _F64]: ...

def forecast_batch(
    histories: _ArrayLike, horizons: _Floats, config: ForecasterConfig | None = None
) -> _F64: ...
def linear_assignment(cost: _ArrayLike) -> tuple[npt.NDArray[np.uintp], npt.NDArray[np.uintp]]:
    """The pairs (rows, cols) that minimise the summed cost, every row or every column used once,
    rows increasing (as scipy.optimize.linear_sum_assignment)."""

@final
class Person:
    """One tracked person's per-frame chain (``torso_core::Person``): side decision, depth
    completion of hidden far joints, relative gate, torso plane, forecaster grid, self-check."""

    def __new__(cls, config: PersonConfig | None = None) -> Person: ...
    def update(
        self, t: float, joints: _ArrayLike, scores: _ArrayLike, camera_position: _ArrayLike
    ) -> Observation:
        """One frame: ``joints (17, 3)`` in the world frame (NaN where missing), their
        ``scores`` and where the camera is. A refused frame raises and changes nothing."""
    def forecast(self, horizons: _Floats) -> _F64 | None:
        """``(len(horizons), 5)`` poses ``horizons`` seconds after the last grid sample, moved
        with the latest estimate (so that holding still holds it), azimuth wrapped; None until
        the history holds enough samples."""
    def intervals(self, horizons: _Floats) -> _F64 | None:
        """``(len(horizons), 5)`` half-widths of the central 80 % intervals around
        :meth:`forecast`: the spread of the track's recent forecast errors times the multiple of
        it that covered 80 % of them and the truth's margin over them (a constant per component
        set on the scenes benchmark), or before any forecast was checked what the line through
        the history says; an angle's at most pi (every direction); None while the history is
        too short for a line."""
    def __len__(self) -> int: ...
    @property
    def last_time(self) -> float | None:
        """Grid time of the forecaster's newest sample; forecasts count from here."""
    @property
    def min_samples(self) -> int: ...
    @property
    def config(self) -> PersonConfig: ...

@final
class PersonConfig:
    """One track's parameters (``torso_core::PersonConfig``), frozen; every keyword left out
    takes the core's default. ``replace(**changes)`` gives a changed copy."""

    def __new__(
        cls,
        forecaster: ForecasterConfig | None = None,
        *,
        gate_threshold: float | None = None,
        gate_max_replacements: int | None = None,
        min_score: float | None = None,
        facing_memory: float | None = None,
        face_weight: float | None = None,
        knee_weight: float | None = None,
        motion_weight: float | None = None,
        self_check: bool | None = None,
        occlusion_ratio: float | None = None,
        surface_depth: _Floats | None = None,
    ) -> PersonConfig: ...
    @property
    def forecaster(self) -> ForecasterConfig:
        """The live tracking forecaster (``ForecasterConfig.live()`` unless given)."""
    @property
    def gate_threshold(self) -> float:
        """Largest accepted joint displacement between frames relative to the body's (m)."""
    @property
    def gate_max_replacements(self) -> int:
        """Frames a joint may be held over before it is lost; at a frame rate under 25 Hz, fewer:
        no longer than these frames last at 25 Hz (10: 0.4 s)."""
    @property
    def min_score(self) -> float:
        """Keypoints scored below this are missing (the one seen-keypoint rule of every stage)."""
    @property
    def facing_memory(self) -> float:
        """Time constant (s) over which the recent evidence for which way the chest faces is
        forgotten: what makes a heading confident (``heading_confident``, ``facing_evidence``).
        The side itself is decided on evidence forgotten as the heading moves, and only slowly
        with time; while the torso goes unseen, both are forgotten over this time constant."""
    @property
    def face_weight(self) -> float:
        """Weight of the nose standing in front of the shoulders, relative to the labels'."""
    @property
    def knee_weight(self) -> float:
        """Weight of the knees standing in front of their legs, relative to the labels'."""
    @property
    def motion_weight(self) -> float:
        """Weight of the walking direction, relative to the labels'."""
    @property
    def self_check(self) -> bool:
        """The track checks its forecasts against its own later samples and mixes the candidates."""
    @property
    def occlusion_ratio(self) -> float:
        """A pair shorter than this fraction of its learned width has its far joint's depth
        completed; 0 turns it off."""
    @property
    def surface_depth(self) -> tuple[float, float]:
        """How far (m) the shoulders' and the hips' joint centres lie behind the body's surface the
        depth camera sees, along its rays: (shoulders, hips); (0, 0) for joints that are joint
        centres already (mocap, a skeleton tracker's)."""
    def replace(self, **changes: object) -> PersonConfig: ...
    def __getnewargs_ex__(self) -> tuple[tuple[()], dict[str, object]]: ...

@final
class DepthLookup:
    """How a keypoint's depth is read from the depth image (``torso_core::depth``): the median
    of the valid readings in a ``(2 radius + 1)²`` window after dropping those more than
    ``band`` (m) behind the window's 25th percentile; fewer than ``min_valid`` readings gives
    NaN. Frozen; every keyword left out takes the core's default."""

    def __new__(
        cls,
        *,
        radius: int | None = None,
        band: float | None = None,
        min_valid: int | None = None,
        min_depth: float | None = None,
        max_depth: float | None = None,
    ) -> DepthLookup: ...
    @property
    def radius(self) -> int: ...
    @property
    def band(self) -> float: ...
    @property
    def min_valid(self) -> int: ...
    @property
    def min_depth(self) -> float: ...
    @property
    def max_depth(self) -> float: ...
    def __call__(self, depth: _ArrayLike, uv: _ArrayLike) -> _F64:
        """Depth (m) at each pixel of ``uv (..., 2)`` in a ``(h, w)`` depth image in metres;
        NaN where none."""
    def replace(self, **changes: object) -> DepthLookup: ...
    def __getnewargs_ex__(self) -> tuple[tuple[()], dict[str, object]]: ...

@final
class TrackerConfig:
    """Association, birth and drop rules (``torso_core::tracker::TrackerConfig``) with each
    track's :class:`PersonConfig` and the :class:`DepthLookup`. Frozen; every keyword left out
    takes the core's default."""

    def __new__(
        cls,
        *,
        gate: float | None = None,
        min_hits: int | None = None,
        max_missing: float | None = None,
        capacity: int | None = None,
        max_detections: int | None = None,
        person: PersonConfig | None = None,
        depth: DepthLookup | None = None,
    ) -> TrackerConfig: ...
    @property
    def gate(self) -> float:
        """Largest distance (m) between where a track's person is expected (the last torso
        centre, moved on at the track's walking velocity while unseen) and its detection's, or
        three times the track's recent distances between the two (root mean square, forgotten
        over a second) where that is wider, up to twice this; widened by 1 m per second the
        camera sent no frame (beyond 0.2 s between two frames) since the track was last
        matched."""
    @property
    def min_hits(self) -> int:
        """Matched frames before a track is confirmed and given an id."""
    @property
    def max_missing(self) -> float:
        """Seconds without a match after which a confirmed track is dropped."""
    @property
    def capacity(self) -> int:
        """Most tracks alive at once."""
    @property
    def max_detections(self) -> int:
        """Most detections in one frame."""
    @property
    def person(self) -> PersonConfig: ...
    @property
    def depth(self) -> DepthLookup: ...
    def replace(self, **changes: object) -> TrackerConfig: ...
    def __getnewargs_ex__(self) -> tuple[tuple[()], dict[str, object]]: ...

@final
class Tracker:
    """Every person in a stream (``torso_core::tracker::Tracker``): association by torso
    centre, track birth, confirmation and drop, one :class:`Person` chain per track, and with
    :meth:`step` the depth lookup and deprojection of the 2D keypoints. One call per frame."""

    def __new__(cls, config: TrackerConfig | None = None) -> Tracker: ...
    @property
    def config(self) -> TrackerConfig: ...
    @property
    def last_time(self) -> float | None:
        """Time of the last accepted frame."""
    def check_time(self, t: float) -> None:
        """Raises as :meth:`update` and :meth:`step` would for a frame at ``t`` (not finite, or
        not after the last frame), without changing anything."""
    def update(
        self,
        t: float,
        joints: _ArrayLike,
        scores: _ArrayLike,
        camera_position: _ArrayLike,
        horizons: _Floats | None = None,
    ) -> list[TrackOutcome]:
        """One frame of world ``joints (people, 17, 3)`` (NaN where missing) with ``scores
        (people, 17)``; forecasts at ``horizons`` for confirmed tracks. A refused frame raises
        and changes nothing."""
    def step(
        self,
        t: float,
        keypoints: _ArrayLike,
        depth: _ArrayLike,
        intrinsics: tuple[float, float, float, float],
        distortion: tuple[float, float, float, float, float],
        camera_to_world: _ArrayLike,
        horizons: _Floats | None = None,
    ) -> tuple[_F64, list[TrackOutcome]]:
        """One frame of 2D ``keypoints (people, 17, 3)`` ``(u, v, score)`` with the ``(h, w)``
        depth image (m) registered to them, the intrinsics ``(fx, fy, cx, cy)``, Brown-Conrady
        ``(k1, k2, p1, p2, k3)`` and the 4x4 ``camera_to_world``: the lifted world joints as
        the tracks took them (NaN where unseen, without depth, or lifted onto someone nearer the
        camera) and each detection's outcome. A refused frame raises and changes nothing."""
    @property
    def lifted(self) -> _F64:
        """The last frame's joints ``(people, 17, 3)`` as given to :meth:`update` or lifted by
        :meth:`step`, before the tracker dropped any read off someone nearer the camera:
        :meth:`update` with them tracks the frame again as it was tracked (what a recording of
        a stream keeps)."""
    @property
    def tracks(self) -> list[TrackState]:
        """The confirmed tracks, in order of birth."""
    def forecast(self, track_id: int, horizons: _Floats) -> _F64 | None:
        """The confirmed track's ``(len(horizons), 5)`` forecast; None for an unknown id or a
        history too short."""
    def intervals(self, track_id: int, horizons: _Floats) -> _F64 | None:
        """The ``(len(horizons), 5)`` half-widths of the 80 % intervals around the confirmed
        track's forecast; None for an unknown id or a history too short for a line."""
    def restart(self) -> None:
        """Drops every track and forgets the last frame's time, as for a new stream; ids go on
        counting."""
    def __copy__(self) -> Tracker:
        """A copy with every track's state."""
    def __deepcopy__(self, memo: object) -> Tracker: ...
    def __len__(self) -> int:
        """Live tracks, tentative ones included."""

@final
class TrackOutcome:
    """One detection's outcome in a frame."""

    @property
    def detection(self) -> int:
        """Index of the detection in the frame."""
    @property
    def track_id(self) -> int | None:
        """The confirmed track's id; None for a tentative track or a detection with no track."""
    @property
    def key(self) -> int | None:
        """Unique per track over the tracker's life, tentative tracks included."""
    @property
    def observation(self) -> Observation | None: ...
    @property
    def last_time(self) -> float | None:
        """Grid time of the track's newest sample: its forecasts count from here."""
    @property
    def forecast(self) -> _F64 | None:
        """``(len(horizons), 5)`` forecast of a confirmed track, once its history is long enough."""
    @property
    def intervals(self) -> _F64 | None:
        """``(len(horizons), 5)`` half-widths of the 80 % intervals around ``forecast``."""

@final
class TrackState:
    """A confirmed track as the tracker holds it now."""

    @property
    def id(self) -> int: ...
    @property
    def key(self) -> int: ...
    @property
    def last_time(self) -> float | None: ...
    @property
    def samples(self) -> int: ...

@final
class Observation:
    @property
    def pose(self) -> _F64 | None: ...
    @property
    def estimate(self) -> Literal["plane", "shoulders", "none"]: ...
    @property
    def swapped(self) -> bool: ...
    @property
    def reoriented(self) -> bool: ...
    @property
    def facing_evidence(self) -> float:
        """The track's recent weighed evidence for its heading after this frame, in seconds of
        the detector's labels agreeing (0 where the frame had no heading, or where the recent
        evidence is against a heading the longer evidence still holds)."""
    @property
    def heading_confident(self) -> bool:
        """A cue other than the detector's labels (the face, bent knees, the walking direction)
        confirms the heading's side (more evidence than the labels alone can build), the
        heading lies within 45 degrees of the track's recent heading, and the torso leans no
        more than 60 degrees from upright (a bent torso's azimuth is poorly conditioned)."""
    @property
    def heading_held(self) -> bool:
        """The frame's torso plane lay more than 45 degrees across the track's recent heading:
        ``pose`` reports the recent heading instead of the plane's azimuth (its centre and
        elevation are the plane's), and the track's forecasts start from it."""
    @property
    def joints(self) -> _F64: ...
    @property
    def completed(self) -> npt.NDArray[np.bool_]: ...
    @property
    def joint_status(self) -> npt.NDArray[np.uint8]: ...
    @property
    def weight(self) -> float: ...
    @property
    def grid(self) -> dict[str, int | bool]: ...
