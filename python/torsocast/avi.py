"""Motion-JPEG AVI files written with Pillow alone, for the overlay video.

MJPEG in AVI is the one video format that needs no codec library to write: every frame is a JPEG
in a RIFF chunk, and every player (VLC, mpv, ffmpeg, OpenCV, Windows and macOS viewers) reads
it. The writer streams: frames go to disk as they come, the index and the header's counts and
frame rate are written at :meth:`AviWriter.close`. A RIFF file of the original AVI format stops at
1 GiB (OpenDML's extension lifts that but not every reader follows it), so a longer video
continues in ``name_001.avi``, ``name_002.avi``, ... (about 9 minutes of 640x480 at 30 frames/s
per file).
"""

from __future__ import annotations

import io
import struct
from pathlib import Path
from types import TracebackType
from typing import BinaryIO

from PIL import Image

#: Largest file before the writer continues in a new one (bytes); RIFF sizes are 32-bit, and
#: the original AVI readers take only the first 1 GiB.
MAX_FILE_BYTES = 1 << 30
_AVIF_HASINDEX = 0x10
_AVIIF_KEYFRAME = 0x10


class AviWriter:
    """``with AviWriter(path) as avi: avi.write(image, t)``; frames must share one size.

    The frame rate is ``fps`` when given, else the mean rate of the time stamps passed to
    :meth:`write` (a player shows frames evenly spaced at that rate)."""

    def __init__(self, path: str | Path, fps: float | None = None, quality: int = 90) -> None:
        if fps is not None and not fps > 0:
            raise ValueError(f"fps must be positive, got {fps}")
        if not 1 <= quality <= 95:
            raise ValueError(f"JPEG quality must be 1 to 95, got {quality}")
        self.path = Path(path)
        self.fps = fps
        self.quality = quality
        self.paths: list[Path] = []
        """Every file written so far, in order."""
        self.size: tuple[int, int] | None = None
        self.frames = 0
        self._first_time: float | None = None
        self._last_time: float | None = None
        self._file: _RiffFile | None = None

    def write(self, image: Image.Image, t: float | None = None) -> None:
        """Appends ``image`` (any Pillow mode; stored as RGB JPEG) taken at time ``t`` (s)."""
        if self.size is None:
            self.size = image.size
        elif image.size != self.size:
            raise ValueError(f"frame {self.frames} is {image.size}, the video is {self.size}")
        buffer = io.BytesIO()
        image.convert("RGB").save(buffer, format="JPEG", quality=self.quality)
        jpeg = buffer.getvalue()
        if self._file is None or self._file.would_exceed(len(jpeg)):
            self._next_file()
        assert self._file is not None
        self._file.add(jpeg)
        self.frames += 1
        if t is not None:
            self._first_time = t if self._first_time is None else self._first_time
            self._last_time = t

    def close(self) -> None:
        """Writes the index and the header's counts; the writer takes no more frames after."""
        if self._file is not None:
            self._file.finish(self._rate())
            self._file = None

    def __enter__(self) -> AviWriter:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, value: BaseException | None, tb: TracebackType | None
    ) -> None:
        self.close()

    def _rate(self) -> float:
        if self.fps is not None:
            return self.fps
        first, last = self._first_time, self._last_time
        if first is not None and last is not None and last > first and self.frames > 1:
            return (self.frames - 1) / (last - first)
        return 30.0

    def _next_file(self) -> None:
        if self._file is not None:
            self._file.finish(self._rate())
        n = len(self.paths)
        path = self.path if n == 0 else self.path.with_name(f"{self.path.stem}_{n:03d}{self.path.suffix}")
        path.parent.mkdir(parents=True, exist_ok=True)
        assert self.size is not None
        self._file = _RiffFile(path.open("wb"), self.size)
        self.paths.append(path)


class _RiffFile:
    """One AVI file: headers with placeholder counts, ``movi`` chunks, then ``idx1`` and the
    counts patched in."""

    def __init__(self, stream: BinaryIO, size: tuple[int, int]) -> None:
        self.stream = stream
        self.width, self.height = size
        self.index: list[tuple[int, int]] = []  # (offset from the 'movi' tag, JPEG length)
        self.largest = 0
        self._write_headers(rate=30.0)
        self.movi = self.stream.tell() - 4  # position of the 'movi' tag

    def would_exceed(self, jpeg_bytes: int) -> bool:
        index_bytes = 16 * (len(self.index) + 1)
        return bool(self.index) and self.stream.tell() + 8 + jpeg_bytes + 1 + index_bytes > MAX_FILE_BYTES

    def add(self, jpeg: bytes) -> None:
        self.index.append((self.stream.tell() - self.movi, len(jpeg)))
        self.stream.write(b"00dc" + struct.pack("<I", len(jpeg)) + jpeg + b"\0" * (len(jpeg) % 2))
        self.largest = max(self.largest, len(jpeg))

    def finish(self, rate: float) -> None:
        end_of_movi = self.stream.tell()
        entries = b"".join(
            b"00dc" + struct.pack("<III", _AVIIF_KEYFRAME, offset, length) for offset, length in self.index
        )
        self.stream.write(b"idx1" + struct.pack("<I", len(entries)) + entries)
        end = self.stream.tell()
        self.stream.seek(0)
        self._write_headers(rate)
        self.stream.seek(self.movi - 8)
        self.stream.write(b"LIST" + struct.pack("<I", end_of_movi - self.movi))
        self.stream.seek(4)
        self.stream.write(struct.pack("<I", end - 8))
        self.stream.close()

    def _write_headers(self, rate: float) -> None:
        frames, w, h = len(self.index), self.width, self.height
        scale = 1000
        avih = struct.pack(
            "<14I",
            round(1e6 / rate),  # microseconds per frame
            round(self.largest * rate),  # max bytes per second
            0,
            _AVIF_HASINDEX,
            frames,
            0,
            1,  # streams
            self.largest,
            w,
            h,
            0,
            0,
            0,
            0,
        )
        rate_fields = (scale, round(rate * scale), 0, frames, self.largest, -1, 0)
        strh = b"vidsMJPG" + struct.pack("<IHHIIIIIIiI4h", 0, 0, 0, 0, *rate_fields, 0, 0, w, h)
        strf = struct.pack("<IiiHH4sIiiII", 40, w, h, 1, 24, b"MJPG", w * h * 3, 0, 0, 0, 0)
        strl = _list(b"strl", _chunk(b"strh", strh) + _chunk(b"strf", strf))
        hdrl = _list(b"hdrl", _chunk(b"avih", avih) + strl)
        movi = b"LIST" + struct.pack("<I", 4) + b"movi"  # sizes patched in by finish()
        self.stream.write(b"RIFF" + struct.pack("<I", 0) + b"AVI " + hdrl + movi)


def _chunk(tag: bytes, data: bytes) -> bytes:
    return tag + struct.pack("<I", len(data)) + data + b"\0" * (len(data) % 2)


def _list(kind: bytes, data: bytes) -> bytes:
    return b"LIST" + struct.pack("<I", 4 + len(data)) + kind + data
