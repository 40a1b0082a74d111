"""Frame sources behind one interface (:class:`Source`): folders of colour + depth images, NumPy
recordings and video files. :func:`open_source` picks one from a path."""

from __future__ import annotations

from pathlib import Path

from .folder import CameraXmlFolder, TumFolder
from .frame import Frame, SkippedFrame, Source
from .recording import NpzRecording
from .video import VideoFile

VIDEO_SUFFIXES = (".mp4", ".avi", ".mov", ".mkv", ".webm")


def open_source(path: str | Path, fps: float = 30.0) -> Source:
    """The source a path names: a ``.npz`` recording, a video file, a TUM folder (``rgb.txt``) or
    a per-frame camera XML folder (``fps`` sets the frame spacing where the source has no time
    stamps)."""
    path = Path(path)
    if path.is_file() and path.suffix == ".npz":
        return NpzRecording(path)
    if path.is_file() and path.suffix.lower() in VIDEO_SUFFIXES:
        return VideoFile(path)
    if path.is_dir() and (path / "rgb.txt").is_file():
        return TumFolder(path)
    if path.is_dir() and any(path.glob("*_camera.xml")):
        return CameraXmlFolder(path, fps)
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such file or folder")
    raise ValueError(
        f"{path}: not a recognised source (a .npz recording, a video file, a TUM RGB-D folder with "
        "rgb.txt and depth.txt, or a folder of NNNN.jpg + NNNN_depth.png + NNNN_camera.xml)"
    )


__all__ = [
    "CameraXmlFolder",
    "Frame",
    "NpzRecording",
    "SkippedFrame",
    "Source",
    "TumFolder",
    "VideoFile",
    "open_source",
]
