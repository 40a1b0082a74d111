"""ROS bags (ROS 2 bag folders and ROS 1 ``.bag`` files), read with the ``rosbags`` package
(``pip install 'torsocast[ros]'``; no ROS installation needed).

What a robot records: a colour image topic (``sensor_msgs/Image`` in rgb8, bgr8, rgba8, bgra8 or
mono8, or ``sensor_msgs/CompressedImage`` in JPEG or PNG), a depth image topic registered to it
(``sensor_msgs/Image`` in 16UC1 millimetres or 32FC1 metres, as a RealSense's
``aligned_depth_to_color`` or a Kinect's registered depth, or image_transport's
``compressedDepth``, in PNG or RVL, of either), the colour camera's
``sensor_msgs/CameraInfo`` and the transforms (``/tf``, ``/tf_static``). Each colour image
becomes a frame at its header's stamp, with the depth image nearest in time (within
:data:`~.frame.PAIRING_TOLERANCE`; none nearer: a colour-only frame) and the camera's pose in the
world frame at that stamp, looked up from the image's ``frame_id`` (the camera's optical frame,
by ROS convention) through the transforms. The world frame is the one named, else ``odom``
where the transforms have it (REP-105's frame that moves smoothly with the robot), else the
root of the camera's tree. A bag without transforms gives the camera level at the origin
(:func:`~torsocast.camera.level_camera`), like the other sources. A topic is found by its type
where the bag has one candidate; where it has several, it must be named.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Collection, Iterator
from dataclasses import dataclass
from io import BytesIO
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
from PIL import Image as PILImage

from ..camera import Camera, Intrinsics, level_camera
from .frame import PAIRING_TOLERANCE, READ_ERRORS, Frame, SkippedFrame
from .transforms import F64, TransformLookupError, TransformTree

IMAGE, COMPRESSED = "sensor_msgs/msg/Image", "sensor_msgs/msg/CompressedImage"
CAMERA_INFO = "sensor_msgs/msg/CameraInfo"
#: The transforms' messages: tf2's, and ROS 1's tf of before tf2, which has the same fields.
TF = ("tf2_msgs/msg/TFMessage", "tf/msg/tfMessage")
COLOUR_ENCODINGS = ("rgb8", "bgr8", "rgba8", "bgra8", "mono8")
#: Depth encodings and their metres per unit.
DEPTH_ENCODINGS = {"16UC1": 0.001, "mono16": 0.001, "32FC1": 1.0}
#: Bytes before the PNG or RVL data in image_transport's compressedDepth (its ConfigHeader: the
#: format, then two floats of 32FC1's inverse-depth quantisation, unused for 16UC1).
COMPRESSED_DEPTH_HEADER = 12
#: The encodings image_transport's compressedDepth carries: 16UC1 as the millimetres themselves,
#: 32FC1 as a quantised inverse depth.
COMPRESSED_DEPTH_ENCODINGS = ("16UC1", "mono16", "32FC1")
#: How many colour images wait, at most, for a depth image stamped at or after them before the
#: oldest is paired with the nearest one so far: a bag's messages come in the order they were
#: received, not stamped. Also how many depth images are kept to pair with.
LOOKAHEAD = 8


def _reader(path: Path) -> tuple[Any, type[Exception]]:
    """A reader of the bag at ``path``, and the error its messages raise when they do not decode."""
    try:
        from rosbags.highlevel import AnyReader, AnyReaderError
        from rosbags.typesys import Stores, get_typestore
    except ImportError as e:
        raise ImportError(
            f"{path}: reading ROS bags needs the rosbags package (pip install 'torsocast[ros]')"
        ) from e
    try:
        # ROS 2 bags of Humble and before carry no message definitions: read them with Humble's.
        return AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)), AnyReaderError
    except AnyReaderError as e:
        raise ValueError(f"{path}: not a readable ROS bag ({e})") from e


def stamp(message: Any) -> float:
    """A message's header stamp in seconds."""
    t = message.header.stamp
    return float(t.sec) + 1e-9 * float(t.nanosec)


def _compressed(message: Any) -> bool:
    """Whether an image message is a CompressedImage (it has a ``format``, not an ``encoding``):
    told by its fields, so that a live node's messages (rclpy's) convert as a bag's do."""
    return not hasattr(message, "encoding")


def colour_image(message: Any) -> npt.NDArray[np.uint8]:
    """An ``(h, w, 3)`` RGB image from a colour Image or CompressedImage message."""
    if _compressed(message):
        with PILImage.open(BytesIO(bytes(message.data))) as image:
            return np.asarray(image.convert("RGB"))
    if message.encoding not in COLOUR_ENCODINGS:
        raise ValueError(f"colour encoding {message.encoding!r} is not one of {', '.join(COLOUR_ENCODINGS)}")
    channels = {"mono8": 1, "rgb8": 3, "bgr8": 3}.get(message.encoding, 4)
    pixels = _rows(message, np.dtype(np.uint8), channels)
    if message.encoding == "mono8":
        return np.repeat(pixels, 3, axis=2)
    rgb = pixels[..., :3]
    return np.ascontiguousarray(rgb[..., ::-1] if message.encoding.startswith("bgr") else rgb)


def depth_image(message: Any) -> npt.NDArray[np.float32]:
    """An ``(h, w)`` depth image in metres, 0 where there is no reading, from a depth Image
    message or a ``compressedDepth`` one (image_transport's: a 12-byte header, then a PNG or an
    RVL stream of 16UC1's millimetres, or of 32FC1's inverse depth quantised by the header's two
    floats ``a`` and ``b``: depth ``a / (value - b)``, 0 for no reading)."""
    if _compressed(message):
        packed = _packed_depth(message.format)
        if packed is None or not _is_depth(message):
            encodings = ", ".join(COMPRESSED_DEPTH_ENCODINGS)
            raise ValueError(
                f"depth format {message.format!r} is not compressedDepth of {encodings} "
                f"(nor an Image in one of {', '.join(DEPTH_ENCODINGS)})"
            )
        encoding, packing = packed
        data = bytes(message.data)
        raw = _compressed_depth_values(packing, data[COMPRESSED_DEPTH_HEADER:]).astype(np.float32)
        if encoding == "32FC1":
            a, b = np.frombuffer(data[4:COMPRESSED_DEPTH_HEADER], dtype="<f4")
            with np.errstate(divide="ignore"):
                depth = np.where(raw > 0, a / (raw - b), np.float32(0.0)).astype(np.float32)
        else:
            depth = raw * np.float32(DEPTH_ENCODINGS["16UC1"])
    else:
        if message.encoding not in DEPTH_ENCODINGS:
            raise ValueError(
                f"depth encoding {message.encoding!r} is not one of {', '.join(DEPTH_ENCODINGS)}"
            )
        dtype = np.dtype(np.float32 if message.encoding == "32FC1" else np.uint16)
        raw = _rows(message, dtype.newbyteorder(">" if message.is_bigendian else "<"), 1)[..., 0]
        depth = raw.astype(np.float32) * np.float32(DEPTH_ENCODINGS[message.encoding])
    depth[~np.isfinite(depth) | (depth < 0)] = 0.0
    return depth


def _packed_depth(form: str) -> tuple[str, str] | None:
    """The encoding and the packing (``"png"`` or ``"rvl"``) of image_transport's compressedDepth
    format (``"16UC1; compressedDepth png"``; a format without the packing is PNG, as its decoder
    reads it); None for a format that is not compressedDepth."""
    if "compressedDepth" not in form:
        return None
    return form.split(";")[0].strip(), "rvl" if "compressedDepth rvl" in form else "png"


def _compressed_depth_values(packing: str, data: bytes) -> npt.NDArray[np.uint16]:
    """The ``(h, w)`` values image_transport's compressedDepth stores after its header: a PNG,
    or in RVL the width and height (two little-endian uint32) and then the RVL stream."""
    if packing != "rvl":
        with PILImage.open(BytesIO(data)) as image:
            return np.asarray(image, dtype=np.uint16)
    size = _rvl_size(data)
    if size is None:
        raise ValueError(f"compressedDepth in RVL of {len(data)} bytes holds no image size")
    height, width = size
    # The encoder's best ratio is four pixels a byte (its decoder checks the same bound).
    if width * height == 0 or width * height > 5 * len(data):
        raise ValueError(f"compressedDepth in RVL says {width}x{height} pixels in {len(data)} bytes")
    return rvl_decode(data[8:], width * height).reshape(height, width)


def _rvl_size(data: bytes) -> tuple[int, int] | None:
    """The (height, width) that compressedDepth's RVL data (after its header) begins with: the
    width and the height as two little-endian uint32; None where the data is too short."""
    if len(data) < 8:
        return None
    width, height = (int(v) for v in np.frombuffer(data[:8], "<u4"))
    return height, width


def rvl_decode(stream: bytes, pixels: int) -> npt.NDArray[np.uint16]:
    """Wilson's RVL ("Fast lossless depth image compression", 2017) as image_transport writes
    it: little-endian 32-bit words of eight nibbles, the first in the high bits; each value in
    nibbles of three bits, the lowest first, the fourth bit set where another follows; runs of a
    count of zeros, a count of nonzero pixels and each of those as the zigzagged difference
    from the nonzero pixel before. Decoded whole in NumPy, the runs walked in Python."""
    if len(stream) < 4:
        raise ValueError(f"RVL stream of {len(stream)} bytes holds no word for {pixels} pixels")
    # Each word's bytes from its most significant, each byte's high nibble first.
    octets = np.frombuffer(stream[: len(stream) // 4 * 4], np.uint8).reshape(-1, 4)[:, ::-1].ravel()
    nibbles = np.empty(2 * len(octets), np.int64)
    nibbles[0::2], nibbles[1::2] = octets >> 4, octets & 0xF
    last = nibbles < 8  # the last nibble of a value
    value_of = np.concatenate([[0], np.cumsum(last)[:-1]])
    first = np.flatnonzero(np.concatenate([[True], last[:-1]]))
    shift = 3 * (np.arange(len(nibbles)) - first[value_of])
    values = np.bincount(value_of, weights=(nibbles & 7) << shift).astype(np.int64)
    numbers = values.tolist()  # the runs are walked one by one: Python's ints are faster here
    starts, counts, firsts = [], [], []
    i = pixel = 0
    while pixel < pixels:
        if i + 2 > len(numbers) or i + 2 + numbers[i + 1] > len(numbers):
            raise ValueError(f"RVL stream ends after {pixel} of {pixels} pixels")
        zeros, nonzeros = numbers[i], numbers[i + 1]
        pixel += zeros
        if pixel + nonzeros > pixels:
            raise ValueError(f"RVL stream runs past the image's {pixels} pixels")
        starts.append(pixel)
        counts.append(nonzeros)
        firsts.append(i + 2)
        i += 2 + nonzeros
        pixel += nonzeros
    run = np.asarray(counts, np.int64)
    within = np.arange(int(run.sum())) - np.repeat(np.cumsum(run) - run, run)
    zigzag = values[np.repeat(np.asarray(firsts, np.int64), run) + within]
    out = np.zeros(pixels, np.uint16)
    out[np.repeat(np.asarray(starts, np.int64), run) + within] = (
        np.cumsum((zigzag >> 1) ^ -(zigzag & 1)) & 0xFFFF
    )
    return out


def _rows(message: Any, dtype: np.dtype, channels: int) -> npt.NDArray[Any]:  # type: ignore[type-arg]
    """The pixels of an Image message, ``(h, w, channels)``, its rows' padding (``step``) dropped."""
    h, w, step = int(message.height), int(message.width), int(message.step)
    row = w * channels * dtype.itemsize
    data = np.frombuffer(message.data, dtype=np.uint8)  # a bag's array, or rclpy's bytes
    if step < row or len(data) < h * step:
        raise ValueError(f"image data of {len(data)} bytes does not hold {h} rows of {row} (step {step})")
    rows = data[: h * step].reshape(h, step)[:, :row]
    return np.ascontiguousarray(rows).view(dtype).reshape(h, w, channels)


def intrinsics(message: Any) -> Intrinsics:
    """The pinhole intrinsics and Brown-Conrady distortion of a CameraInfo message."""
    k = np.asarray(getattr(message, "k", getattr(message, "K", None)), dtype=np.float64)
    d = [float(v) for v in getattr(message, "d", getattr(message, "D", []))]
    if k.shape != (9,):
        raise ValueError(f"camera info: k holds {k.size} numbers, not a 3x3 camera matrix's 9")
    model = message.distortion_model
    if model not in ("plumb_bob", "rational_polynomial", "") or any(d[5:]):
        raise ValueError(
            f"camera info: distortion model {model!r} with {len(d)} coefficients; expected plumb_bob's "
            "k1, k2, p1, p2, k3 (or rational_polynomial's with k4 to k6 zero)"
        )
    return Intrinsics(k[0], k[4], k[2], k[5], tuple(d[:5]) if any(d) else ())


@dataclass(frozen=True)
class BagTopics:
    """What to read from a bag, where its own types leave a choice: the topics (each needed only
    where the bag has more than one candidate) and the fixed frame the camera is placed in."""

    color_topic: str | None = None
    depth_topic: str | None = None
    info_topic: str | None = None
    world_frame: str | None = None


class RosBag:
    """Frames of a ROS bag (see the module's docstring and :class:`BagTopics`)."""

    def __init__(
        self,
        path: str | Path,
        color_topic: str | None = None,
        depth_topic: str | None = None,
        info_topic: str | None = None,
        world_frame: str | None = None,
    ) -> None:
        self.path = Path(path)
        self.name = str(self.path)
        self.reader, self._bad_message = _reader(self.path)
        try:
            with self.reader as bag:
                images = [c for c in bag.connections if c.msgtype in (IMAGE, COMPRESSED)]
                first = {c.topic: m for c in images if (m := self._first(c)) is not None}
                colours = [t for t, m in first.items() if _is_colour(m)]
                # image_transport's compressed copy of a raw topic the bag holds too: read the raw
                # unless named.
                raw = [t for t in colours if not _copy(t, "/compressed", colours)]
                self.color_topic = _pick(
                    "colour image", color_topic, colours if color_topic else raw, "--color-topic"
                )
                self.depth_topic = _depth_topic(first, self.color_topic, depth_topic)
                infos = [c.topic for c in bag.connections if c.msgtype == CAMERA_INFO]
                # The driver's convention: the colour image's camera info beside it in its namespace.
                beside = [t for t in infos if t.rsplit("/", 1)[0] == self.color_topic.rsplit("/", 1)[0]]
                info = _pick("camera info", info_topic, beside or infos, "--info-topic")
                message = self._first(next(c for c in bag.connections if c.topic == info))
                if message is None:
                    raise ValueError(f"topic {info} holds no camera info")
                self.intrinsics = intrinsics(message)
                self.camera_frame = _frame(first[self.color_topic])
                self._transforms(bag, world_frame)
                self.frames = sum(c.msgcount for c in bag.connections if c.topic == self.color_topic)
        except (KeyError, AttributeError) as e:
            raise ValueError(f"{self.path}: a message of an unexpected shape ({e})") from e
        except (ValueError, self._bad_message) as e:
            raise ValueError(f"{self.path}: {e}") from e

    def _world(self, named: str | None) -> str | None:
        """The frame the camera is placed in: the one named, else odom, else the camera's root;
        None where the bag has no transforms. Refused where the camera's frame is not below it."""
        if not self.tree.parents:
            if named is not None:
                raise ValueError(f"the bag has no transforms to place the camera in {named!r}")
            return None
        if named is not None and named not in self.tree:
            raise ValueError(f"the transforms have no frame {named!r}")
        world = named or ("odom" if "odom" in self.tree else self.tree.root(self.camera_frame))
        if self.tree.root(world) != self.tree.root(self.camera_frame):
            raise ValueError(
                f"the colour images' frame {self.camera_frame!r} is not connected to {world!r} by the "
                "transforms (name the fixed frame with --world-frame)"
            )
        return world

    def _first(self, connection: Any) -> Any:
        """The first message of a connection, None where it holds none."""
        for conn, _, raw in self.reader.messages(connections=[connection]):
            return self.reader.deserialize(raw, conn.msgtype)
        return None

    def _transforms(self, bag: Any, named: str | None) -> None:
        """The bag's transform tree (``tree``) and the frame the camera is placed in
        (``world_frame``, :meth:`_world`, decided on the tree's shape): the shape whole, the
        samples of the transforms above the camera's frame and the world frame alone, for a
        robot's ``/tf`` carries every joint it has, many times a second."""
        self.tree = TransformTree()
        for parent, child, *_ in self._tf(bag):
            self.tree.connect(parent, child)
        self.world_frame = self._world(named)
        if self.world_frame is None:
            return
        kept = set(self.tree.ancestors(self.camera_frame)) | set(self.tree.ancestors(self.world_frame))
        for parent, child, t, translation, quaternion, static in self._tf(bag):
            if child in kept:
                self.tree.add(parent, child, t, translation, quaternion, static)

    @staticmethod
    def _tf(bag: Any) -> Iterator[tuple[str, str, float, F64, F64, bool]]:
        """Every transform on ``/tf`` and ``/tf_static``: parent, child, stamp, translation,
        quaternion ``[x, y, z, w]``, and whether static."""
        for conn in [c for c in bag.connections if c.msgtype in TF]:
            static = conn.topic.endswith("tf_static")
            for _, _, raw in bag.messages(connections=[conn]):
                for tf in bag.deserialize(raw, conn.msgtype).transforms:
                    p, q = tf.transform.translation, tf.transform.rotation
                    yield (
                        tf.header.frame_id.lstrip("/"),
                        tf.child_frame_id.lstrip("/"),
                        stamp(tf),
                        np.array([p.x, p.y, p.z]),
                        np.array([q.x, q.y, q.z, q.w]),
                        static,
                    )

    def camera(self, t: float) -> Camera:
        """The colour camera at time ``t``: placed in the world frame by the transforms, or level
        at the origin where the bag has none."""
        if self.world_frame is None:
            return Camera(self.intrinsics, level_camera())
        return Camera(self.intrinsics, self.tree.lookup(self.world_frame, self.camera_frame, t))

    def __len__(self) -> int:
        return self.frames

    def __iter__(self) -> Iterator[Frame | SkippedFrame]:
        with self.reader as bag:
            wanted = [c for c in bag.connections if c.topic in (self.color_topic, self.depth_topic)]
            pending: deque[tuple[int, float, Any]] = deque()
            depths: deque[tuple[float, Any]] = deque(maxlen=LOOKAHEAD)
            index = 0
            for conn, _, raw in bag.messages(connections=wanted):
                try:
                    message = bag.deserialize(raw, conn.msgtype)
                    t = stamp(message)
                except (self._bad_message, AttributeError) as e:  # one bad frame, not the stream
                    if conn.topic == self.color_topic:
                        yield SkippedFrame(index, None, f"{conn.topic}: {e}")
                        index += 1
                    continue
                if conn.topic == self.color_topic:
                    pending.append((index, t, message))
                    index += 1
                else:
                    depths.append((t, message))
                # A colour image is paired once a depth image stamped at or after it has come,
                # or once LOOKAHEAD more colour images have come without one.
                while pending and ((depths and depths[-1][0] >= pending[0][1]) or len(pending) > LOOKAHEAD):
                    yield self._frame(*pending.popleft(), depths)
            while pending:
                yield self._frame(*pending.popleft(), depths)

    def _frame(
        self, index: int, t: float, message: Any, depths: deque[tuple[float, Any]]
    ) -> Frame | SkippedFrame:
        try:
            color = colour_image(message)
            depth = None
            if depths:
                nearest_t, nearest = min(depths, key=lambda d: abs(d[0] - t))
                if abs(nearest_t - t) <= PAIRING_TOLERANCE:
                    depth = depth_image(nearest)
                    if depth.shape != color.shape[:2]:
                        raise ValueError(
                            f"depth {depth.shape} is not the colour image's size {color.shape[:2]}: "
                            "the depth must be registered to the colour image"
                        )
            return Frame(index, t, color, depth, self.camera(t))
        except (*READ_ERRORS, TransformLookupError) as e:
            return SkippedFrame(index, t, f"{self.color_topic} at {t:.6f} s: {e}")


def _is_colour(message: Any) -> bool:
    if _compressed(message):
        return _packed_depth(message.format) is None
    return message.encoding in COLOUR_ENCODINGS


def _is_depth(message: Any) -> bool:
    if _compressed(message):
        packed = _packed_depth(message.format)
        return packed is not None and packed[0] in COMPRESSED_DEPTH_ENCODINGS
    return message.encoding in DEPTH_ENCODINGS


#: What a driver names the depth that is registered to its colour images.
REGISTERED_DEPTH = "a driver's aligned_depth_to_color or depth_to_rgb topic"


def _depth_topic(first: dict[str, Any], colour: str, named: str | None) -> str:
    """The depth topic registered to the ``colour`` topic: named, or the one depth topic whose
    images have the colour images' size and optical frame (a driver records its sensor's own
    depth beside the registered one: a RealSense's ``depth/image_rect_raw`` beside
    ``aligned_depth_to_color``, whose pixels are the colour camera's and carry its frame)."""
    size, frame = _size(first[colour]), _frame(first[colour])
    depths = {t: m for t, m in first.items() if _is_depth(m)}
    # As for the colour: a compressedDepth copy of a raw topic the bag holds too is passed over.
    raw = [t for t in depths if not _copy(t, "/compressedDepth", depths)]
    registered = [t for t in raw if _size(depths[t]) == size and _same_frame(_frame(depths[t]), frame)]
    candidates = list(depths) if named else registered or raw
    topic = _pick("depth image", named, candidates, "--depth-topic")
    shape, depth_frame = _size(depths[topic]), _frame(depths[topic])
    if size is not None and shape is not None and shape != size:
        (h, w), (dh, dw) = size, shape
        raise ValueError(
            f"the depth images of {topic} are {dw}x{dh}, the colour images {w}x{h}: the depth must be "
            f"registered to the colour image ({REGISTERED_DEPTH})"
        )
    if not _same_frame(depth_frame, frame):
        raise ValueError(
            f"the depth images of {topic} are in frame {depth_frame!r}, the colour images in {frame!r}: "
            f"the depth must be registered to the colour image ({REGISTERED_DEPTH})"
        )
    return topic


def _frame(message: Any) -> str:
    return str(message.header.frame_id).lstrip("/")


def _same_frame(a: str, b: str) -> bool:
    """Whether two images' frames are one; a bag that leaves either empty says nothing."""
    return not a or not b or a == b


def _size(message: Any) -> tuple[int, int] | None:
    """The (height, width) of an image message; None for a compressed one that does not decode
    (its frame is skipped when read)."""
    if not _compressed(message):
        return int(message.height), int(message.width)
    packed = _packed_depth(message.format)
    if packed is not None and packed[1] == "rvl":
        return _rvl_size(bytes(message.data)[COMPRESSED_DEPTH_HEADER:])
    skip = 0 if packed is None else COMPRESSED_DEPTH_HEADER
    try:
        with PILImage.open(BytesIO(bytes(message.data)[skip:])) as image:
            return image.height, image.width
    except READ_ERRORS:
        return None


def _copy(topic: str, suffix: str, topics: Collection[str]) -> bool:
    """Whether ``topic`` is image_transport's ``suffix`` copy of another of ``topics``."""
    return topic.endswith(suffix) and topic[: -len(suffix)] in topics


def _pick(what: str, named: str | None, candidates: list[str], flag: str) -> str:
    """The topic named, which must be a candidate, or the one candidate there is."""
    if named is not None:
        if named not in candidates:
            found = ", ".join(candidates) or "none"
            raise ValueError(f"{named} is not a {what} topic of the bag (found: {found})")
        return named
    if len(candidates) != 1:
        found = ", ".join(candidates) or "none"
        argument = flag.lstrip("-").replace("-", "_")
        raise ValueError(
            f"the bag has {len(candidates)} {what} topics ({found}): "
            f"name one with {flag} ({argument}= in Python)"
        )
    return candidates[0]
