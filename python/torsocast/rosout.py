"""The tracks as a ROS 2 bag (``torsocast run --bag``; ``pip install 'torsocast[ros]'``), for
rviz, Foxglove or a robot's own replay, in REP-155's names:

- ``/tf`` (``tf2_msgs/TFMessage``): each confirmed person's body frame ``body_<id>`` in the world
  frame, stamped with the frame's time, as the JSON Lines' ``body_frame`` gives it: the people
  the frame showed, and the tracks kept unseen at their forecast for that time;
- ``/humans/bodies/tracked`` (``hri_msgs/IdsList``): the ids of the bodies the frame showed.

A frame the source could not read, or the pipeline left out, writes nothing.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .output import body_frame_of
from .pipeline import FrameResult

TF_TOPIC, TRACKED_TOPIC = "/tf", "/humans/bodies/tracked"
TF_MESSAGE, IDS_LIST = "tf2_msgs/msg/TFMessage", "hri_msgs/msg/IdsList"
#: hri_msgs' IdsList (ROS4HRI), which no ROS distribution's standard messages hold.
IDS_LIST_DEFINITION = "std_msgs/Header header\nstring[] ids\n"


class BodyBag:
    """Writes each frame's result (call it with each :class:`FrameResult`, inside ``with``) to a
    ROS 2 bag folder at ``path``, with transforms whose parent is ``world_frame``. A folder there
    is refused, unless ``replace`` and it holds a ROS 2 bag and nothing else (a previous run's)."""

    def __init__(self, path: str | Path, world_frame: str = "world", replace: bool = False) -> None:
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
        t = result.frame.time
        types = self.store.types
        stamp_ns = int(round(t * 1e9))
        seconds, nanoseconds = divmod(stamp_ns, 1_000_000_000)
        time = types["builtin_interfaces/msg/Time"](sec=seconds, nanosec=nanoseconds)

        def header(frame_id: str) -> Any:
            return types["std_msgs/msg/Header"](stamp=time, frame_id=frame_id)

        shown = [
            (p.track_id, p.observation.pose)
            for p in result.people
            if p.track_id is not None and p.observation is not None and p.observation.pose is not None
        ]
        kept = [(u.id, u.pose) for u in result.unseen if u.pose is not None]
        transforms = []
        for track_id, pose in [*shown, *kept]:
            frame = body_frame_of(pose)
            if frame is None:
                continue
            (x, y, z), (qx, qy, qz, qw) = (v.tolist() for v in frame)
            transforms.append(
                types["geometry_msgs/msg/TransformStamped"](
                    header=header(self.world_frame),
                    child_frame_id=f"body_{track_id}",
                    transform=types["geometry_msgs/msg/Transform"](
                        translation=types["geometry_msgs/msg/Vector3"](x=x, y=y, z=z),
                        rotation=types["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw),
                    ),
                )
            )
        if transforms:
            self._write(TF_TOPIC, TF_MESSAGE, types[TF_MESSAGE](transforms=transforms), stamp_ns)
        ids = types[IDS_LIST](header=header(self.world_frame), ids=[str(i) for i, _ in shown])
        self._write(TRACKED_TOPIC, IDS_LIST, ids, stamp_ns)

    def _write(self, topic: str, kind: str, message: Any, stamp_ns: int) -> None:
        self.writer.write(self.connections[topic], stamp_ns, self.store.serialize_cdr(message, kind))

    def __exit__(self, *exc: object) -> None:
        self.writer.close()
