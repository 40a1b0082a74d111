"""One frame of a source, and the interface every source implements."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import numpy.typing as npt
from PIL import Image

from ..camera import Camera


@dataclass
class Frame:
    """A colour image, optionally with a depth image registered to it."""

    index: int
    time: float
    """Seconds, strictly increasing within a source."""
    color: npt.NDArray[np.uint8]
    """``(h, w, 3)`` RGB."""
    depth: npt.NDArray[np.float32] | None
    """``(h, w)`` metres along the optical axis, 0 or NaN where there is no reading; None for a
    colour-only source."""
    camera: Camera | None
    """Intrinsics and pose of the colour camera; None for a colour-only source."""
    extra: dict[str, Any] = field(default_factory=dict)
    """Source-specific data, e.g. a ground-truth pose."""


@dataclass(frozen=True)
class SkippedFrame:
    """A frame a source could not read (a corrupt or missing file): yielded in its place, so
    that a stream goes on past it and the run reports it."""

    index: int
    time: float | None
    reason: str


#: Seconds: the furthest in time a depth image may lie from the colour image it is paired with.
PAIRING_TOLERANCE = 0.02


#: What reading one frame's files can raise: missing or unreadable files, images that are not
#: images or too large to decode, broken XML, numbers that do not parse.
READ_ERRORS = (OSError, ValueError, SyntaxError, EOFError, Image.DecompressionBombError)


class Source(Protocol):
    """Anything that yields frames in time order. A live sensor adapter implements the same two
    members (see ``docs/sources.md``)."""

    name: str

    def __len__(self) -> int:
        """Number of frames, or 0 when unknown (a live stream)."""
        ...

    def __iter__(self) -> Iterator[Frame | SkippedFrame]: ...


def depth_in_metres(raw: npt.NDArray[Any], scale: float) -> npt.NDArray[np.float32]:
    """A raw depth image in sensor units to metres, with 0 for "no reading"."""
    depth = raw.astype(np.float32) * np.float32(scale)
    depth[~np.isfinite(depth)] = 0.0
    return depth


def check_increasing(times: npt.NDArray[np.float64], name: str) -> None:
    if len(times) > 1 and not (np.diff(times) > 0).all():
        k = int(np.argmin(np.diff(times)))
        raise ValueError(
            f"{name}: time stamps must increase, but frame {k + 1} has {times[k + 1]} after {times[k]}"
        )
