"""Frame sources behind one interface (:class:`Source`): folders of colour + depth images, NumPy
recordings, ROS bags and video files. :func:`open_source` picks one from a path."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from .folder import CameraXmlFolder, TumFolder
from .frame import Frame, SkippedFrame, Source
from .recording import NpzRecording
from .rosbag import BagTopics, RosBag
from .video import VideoFile

VIDEO_SUFFIXES = (".mp4", ".avi", ".mov", ".mkv", ".webm")
#: The name of the fixed frame the camera is placed in, where a source names none.
WORLD_FRAME = "world"


def world_frame_of(source: Source) -> str:
    """The name of the fixed frame ``source`` places its camera in (``camera_to_world``): a ROS
    bag's (``odom``, say), else :data:`WORLD_FRAME`."""
    return getattr(source, "world_frame", None) or WORLD_FRAME


def open_source(path: str | Path, fps: float = 30.0, bag: BagTopics | None = None) -> Source:
    """The source a path names: a ``.npz`` recording, a ROS bag (a ROS 2 bag folder with
    ``metadata.yaml``, a ROS 1 ``.bag`` file), a video file, a TUM folder (``rgb.txt``) or a
    per-frame camera XML folder (``fps`` sets the frame spacing where the source has no time
    stamps). ``bag`` names a bag's topics and world frame; refused for any other source."""
    path = Path(path)
    ros1 = path.is_file() and path.suffix == ".bag"
    if ros1 or (path.is_dir() and (path / "metadata.yaml").is_file()):
        return RosBag(path, **dataclasses.asdict(bag or BagTopics()))
    if bag is not None and bag != BagTopics():
        raise ValueError(f"{path}: topics and a world frame are for ROS bags, and this is not one")
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
        f"{path}: not a recognised source (a .npz recording, a ROS bag, a video file, a TUM RGB-D "
        "folder with rgb.txt and depth.txt, or a folder of NNNN.jpg + NNNN_depth.png + NNNN_camera.xml)"
    )


__all__ = [
    "BagTopics",
    "CameraXmlFolder",
    "Frame",
    "NpzRecording",
    "RosBag",
    "SkippedFrame",
    "Source",
    "TumFolder",
    "VideoFile",
    "WORLD_FRAME",
    "open_source",
    "world_frame_of",
]
