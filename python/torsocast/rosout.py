"""The tracks as a ROS 2 bag (``torsocast run --bag``; ``pip install 'torsocast[ros]'``), for
rviz, Foxglove or a robot's own replay, in REP-155's names:

- ``/tf`` (``tf2_msgs/TFMessage``): each confirmed person's body frame ``body_<id>`` in the world
  frame, stamped with the frame's time, as the JSON Lines' ``body_frame`` gives it: the people
  the frame showed, and the tracks kept unseen at their forecast for that time;
- ``/humans/bodies/tracked`` (``hri_msgs/IdsList``): the ids of the bodies the frame showed;
- ``/humans/bodies/<id>/forecast`` (``nav_msgs/Path``): where each body the frame showed is
  forecast to be, one pose per horizon, each stamped with the time it aims at (the horizon
  after the track's last sample on the forecaster's grid, as in the JSON Lines) and oriented as
  the body frame of the forecast pose: where people are about to walk, for a planner (rviz
  draws it as a path).

A frame the source could not read, or the pipeline left out, writes nothing.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .output import body_frame_of
from .pipeline import FrameResult
from .sources import WORLD_FRAME

TF_TOPIC, TRACKED_TOPIC, FORECAST_TOPIC = "/tf", "/humans/bodies/tracked", "/humans/bodies/{id}/forecast"
TF_MESSAGE, IDS_LIST, PATH = "tf2_msgs/msg/TFMessage", "hri_msgs/msg/IdsList", "nav_msgs/msg/Path"
#: hri_msgs' IdsList (ROS4HRI), which no ROS distribution's standard messages hold.
IDS_LIST_DEFINITION = "std_msgs/Header header\nstring[] ids\n"


def _nanoseconds(t: float) -> int:
    return int(round(t * 1e9))


class BodyBag:
    """Writes each frame's result (call it with each :class:`FrameResult`, inside ``with``) to a
    ROS 2 bag folder at ``path``, with transforms and paths in ``world_frame``, the forecasts'
    poses at ``horizons`` (the pipeline's, in seconds). A folder there
    is refused, unless ``replace`` and it holds a ROS 2 bag and nothing else (a previous run's)."""

    def __init__(
        self,
        path: str | Path,
        horizons: Sequence[float],
        world_frame: str = WORLD_FRAME,
        replace: bool = False,
    ) -> None:
        try:
            from rosbags.rosbag2 import Writer
            from rosbags.typesys import Stores, get_types_from_msg, get_typestore
        except ImportError as e:
            raise ImportError(
                "writing a ROS bag needs the rosbags package (pip install 'torsocast[ros]')"
            ) from e
        self.path = Path(path)
        if self.path.exists():
            files = list(self.path.iterdir()) if self.path.is_dir() else []
            bag = {f.name for f in files} >= {"metadata.yaml"} and all(
                f.is_file() and f.suffix in (".yaml", ".db3", ".mcap") for f in files
            )
            if not (replace and bag):
                raise FileExistsError(f"{self.path}: exists, and is not a ROS bag this could replace")
            for f in files:
                f.unlink()
            self.path.rmdir()
        self.world_frame = world_frame
        self.horizons = list(horizons)
        self.store = get_typestore(Stores.ROS2_HUMBLE)
        self.store.register(get_types_from_msg(IDS_LIST_DEFINITION, IDS_LIST))
        self.writer = Writer(self.path, version=9)
        self.connections: dict[str, Any] = {}

    def __enter__(self) -> BodyBag:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.writer.open()
        for topic, kind in ((TF_TOPIC, TF_MESSAGE), (TRACKED_TOPIC, IDS_LIST)):
            self.connections[topic] = self.writer.add_connection(topic, kind, typestore=self.store)
        return self

    def __call__(self, result: FrameResult) -> None:
        types = self.store.types
        shown = [
            (i, p.track_id, p.observation.pose, p.last_time)
            for i, p in enumerate(result.people)
            if p.track_id is not None and p.observation is not None and p.observation.pose is not None
        ]
        kept = [(u.id, u.pose) for u in result.unseen if u.pose is not None]
        t = result.frame.time
        transforms = []
        for track_id, pose in [*((j, q) for _, j, q, _ in shown), *kept]:
            placed = self._pose(pose)
            if placed is not None:
                at = placed.position
                transform = types["geometry_msgs/msg/Transform"](
                    translation=types["geometry_msgs/msg/Vector3"](x=at.x, y=at.y, z=at.z),
                    rotation=placed.orientation,
                )
                transforms.append(
                    types["geometry_msgs/msg/TransformStamped"](
                        header=self._header(t), child_frame_id=f"body_{track_id}", transform=transform
                    )
                )
        if transforms:
            self._write(TF_TOPIC, TF_MESSAGE, types[TF_MESSAGE](transforms=transforms), t)
        ids = types[IDS_LIST](header=self._header(t), ids=[str(j) for _, j, _, _ in shown])
        self._write(TRACKED_TOPIC, IDS_LIST, ids, t)
        for i, track_id, _, origin in shown:
            ahead = result.forecasts.get(i)
            if ahead is None or origin is None:
                continue
            # A forecast's horizons count from the track's last grid sample, not the frame's stamp.
            poses = [
                types["geometry_msgs/msg/PoseStamped"](header=self._header(origin + h), pose=placed)
                for h, pose in zip(self.horizons, ahead)
                if (placed := self._pose(pose)) is not None
            ]
            path = types[PATH](header=self._header(t), poses=poses)
            self._write(FORECAST_TOPIC.format(id=track_id), PATH, path, t)

    def _pose(self, pose: Any) -> Any:
        """The ``geometry_msgs/Pose`` of a torso pose's body frame; None for one the core refuses."""
        frame = body_frame_of(pose)
        if frame is None:
            return None
        (x, y, z), (qx, qy, qz, qw) = (v.tolist() for v in frame)
        types = self.store.types
        return types["geometry_msgs/msg/Pose"](
            position=types["geometry_msgs/msg/Point"](x=x, y=y, z=z),
            orientation=types["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw),
        )

    def _header(self, t: float) -> Any:
        """A header in the world frame stamped ``t`` (seconds)."""
        seconds, nanoseconds = divmod(_nanoseconds(t), 1_000_000_000)
        time = self.store.types["builtin_interfaces/msg/Time"](sec=seconds, nanosec=nanoseconds)
        return self.store.types["std_msgs/msg/Header"](stamp=time, frame_id=self.world_frame)

    def _write(self, topic: str, kind: str, message: Any, t: float) -> None:
        if topic not in self.connections:  # a body's forecast topic, from its first forecast
            self.connections[topic] = self.writer.add_connection(topic, kind, typestore=self.store)
        self.writer.write(self.connections[topic], _nanoseconds(t), self.store.serialize_cdr(message, kind))

    def __exit__(self, *exc: object) -> None:
        self.writer.close()
