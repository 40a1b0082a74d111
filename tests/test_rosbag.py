"""ROS bags as a frame source, and the transform tree that places their camera: checked against
SciPy's rotations and against the rendered frames a bag was written from."""

from __future__ import annotations

import json
from io import BytesIO
from typing import Any

import numpy as np
import pytest
from PIL import Image as PILImage
from scipy.spatial.transform import Rotation, Slerp

from torsocast.cli import main
from torsocast.datasets import cmu
from torsocast.sources import Frame, SkippedFrame, open_source
from torsocast.sources.transforms import TransformLookupError, TransformTree, matrix
from torsocast.synthetic.mocap import MocapScene

rosbags = pytest.importorskip("rosbags", reason="the ROS bag source needs the rosbags package ('.[ros]')")
from rosbags.typesys import Stores, get_types_from_msg, get_typestore  # noqa: E402

from torsocast.sources.rosbag import RosBag  # noqa: E402

#: The bags' clock: a robot's stamps are seconds since 1970, not since the recording began.
EPOCH = 1.7e9


def test_a_dynamic_transform_is_interpolated_as_scipy_slerps_it():
    # world <- a (static) <- b (moving: five samples) <- camera (static), and a sibling branch
    # world <- c (static): b's pose between samples is the linear translation and SciPy's slerp.
    rng = np.random.default_rng(3)
    tree = TransformTree()
    statics = {name: (rng.normal(size=3), Rotation.random(random_state=k)) for k, name in enumerate("acx")}
    tree.add("world", "a", 0.0, statics["a"][0], statics["a"][1].as_quat(), static=True)
    tree.add("b", "camera", 0.0, statics["x"][0], statics["x"][1].as_quat(), static=True)
    tree.add("world", "c", 0.0, statics["c"][0], statics["c"][1].as_quat(), static=True)
    times = np.array([0.0, 0.1, 0.25, 0.3, 0.5])
    moves = rng.normal(size=(5, 3))
    turns = Rotation.random(5, random_state=9)
    for k in (3, 0, 4, 1, 2):  # out of order, as two topics' messages may come
        tree.add("a", "b", times[k], moves[k], turns[k].as_quat(), static=False)

    def rigid(translation, rotation):
        return matrix(translation, rotation.as_quat())

    slerp = Slerp(times, turns)
    for t in (0.0, 0.05, 0.2, 0.3, 0.42, 0.5):
        k = min(int(np.searchsorted(times, t, side="right")), 4)
        s = (t - times[k - 1]) / (times[k] - times[k - 1])
        move = moves[k - 1] + s * (moves[k] - moves[k - 1])
        a_b = rigid(move, slerp([t])[0])
        world_camera = rigid(*statics["a"]) @ a_b @ rigid(*statics["x"])
        np.testing.assert_allclose(tree.lookup("world", "camera", t), world_camera, atol=1e-12)
        # Across branches: the camera in c's coordinates.
        expected = np.linalg.inv(rigid(*statics["c"])) @ world_camera
        np.testing.assert_allclose(tree.lookup("c", "camera", t), expected, atol=1e-12)
    np.testing.assert_allclose(tree.lookup("camera", "camera", 0.2), np.eye(4))

    # Never extrapolated; unconnected frames, a second parent and a loop are refused by name.
    with pytest.raises(TransformLookupError, match=r"from b to a at 0.600000 s: it is known from 0.000000"):
        tree.lookup("world", "camera", 0.6)
    tree.lookup("world", "a", 0.6)  # a static transform holds at every time
    with pytest.raises(TransformLookupError, match="not connected"):
        tree.lookup("elsewhere", "camera", 0.2)
    with pytest.raises(ValueError, match="frame b has two parents, a and c"):
        tree.add("c", "b", 0.1, np.zeros(3), np.array([0, 0, 0, 1.0]), static=False)
    with pytest.raises(ValueError, match="closes a loop"):
        tree.add("camera", "world", 0.1, np.zeros(3), np.array([0, 0, 0, 1.0]), static=True)
    with pytest.raises(ValueError, match="not a unit quaternion"):
        tree.add("world", "d", 0.1, np.zeros(3), np.zeros(4), static=True)
    # A frame whose transforms were not kept is in the tree's shape, and not looked up.
    tree.connect("camera", "lens")
    assert "lens" in tree and tree.root("lens") == "world"
    with pytest.raises(TransformLookupError, match="the transform from lens to camera was not kept"):
        tree.lookup("world", "lens", 0.2)


def read(source) -> list[Frame]:
    """Every frame of ``source``, each of which must have been read (none skipped), with a camera."""
    out = list(source)
    assert all(isinstance(f, Frame) and f.camera is not None for f in out)
    return out


@pytest.fixture(scope="module")
def frames():
    walk = cmu.load_clip(cmu.bundled_clips()["test_walking_1"])
    return list(MocapScene(walk, fps=10.0))[:24]


def write_bag(
    path,
    frames,
    ros=2,
    encoding="bgr8",
    drive=(0.0, 0.0, 0.0),
    extra=(),
    depth_lag=0.003,
    mount="base_link",
    without_depth=(),
    compressed_depth=False,
    tf_type="tf2_msgs/msg/TFMessage",
):
    """``frames`` as a robot records them: colour (``encoding``, rows padded) and registered
    depth in millimetres (stamped ``depth_lag`` s later) in the RealSense driver's topics, its
    camera info, the camera's optical frame on the robot (``/tf_static``, below ``mount``) and the
    robot in ``odom`` at 50 Hz (``/tf``), driving at ``drive`` m/s from the first frame's pose;
    a ROS 1 bag (``ros`` 1), or a ROS 2 one in SQLite (2) or MCAP storage. ``extra``: more
    (topic, message type, [(stamp, message)]) to record; the frames numbered in
    ``without_depth`` have no depth image; with ``compressed_depth`` (True or "png", or "rvl") the
    depth is recorded as image_transport's compressedDepth alone; ``tf_type`` is the transforms'
    message (a ROS 1 bag of before tf2 records tf's own ``tf/msg/tfMessage``)."""
    store = get_typestore(Stores.ROS1_NOETIC if ros == 1 else Stores.ROS2_HUMBLE)
    if ros == 1:  # Noetic's store lacks tf2's message; a ROS 1 bag carries its definition
        tf = "geometry_msgs/TransformStamped[] transforms"
        store.register(get_types_from_msg(tf, tf_type))
    T = store.types
    writer: Any
    serialize: Any
    if ros in (2, "mcap"):
        from rosbags.rosbag2 import StoragePlugin
        from rosbags.rosbag2 import Writer as Writer2

        storage = StoragePlugin.MCAP if ros == "mcap" else StoragePlugin.SQLITE3
        writer, serialize = Writer2(path, version=9, storage_plugin=storage), store.serialize_cdr
    else:
        from rosbags.rosbag1 import Writer as Writer1

        writer, serialize = Writer1(path), store.serialize_ros1

    def header(t, frame="camera_color_optical_frame"):
        seconds, nanoseconds = divmod(int(round(t * 1e9)), 10**9)
        time = T["builtin_interfaces/msg/Time"](sec=seconds, nanosec=nanoseconds)
        fields = {"seq": 0} if ros == 1 else {}
        return T["std_msgs/msg/Header"](**fields, stamp=time, frame_id=frame)

    def image(t, pixels, encoding, pad=4):
        h, w = pixels.shape[:2]
        rows = pixels.reshape(h, -1).view(np.uint8)
        data = np.zeros((h, rows.shape[1] + pad), np.uint8)
        data[:, : rows.shape[1]] = rows
        return T["sensor_msgs/msg/Image"](
            header=header(t),
            height=h,
            width=w,
            encoding=encoding,
            is_bigendian=0,
            step=data.shape[1],
            data=data.reshape(-1),
        )

    def transform(t, parent, child, pose):
        q = Rotation.from_matrix(pose[:3, :3]).as_quat()
        return T["geometry_msgs/msg/TransformStamped"](
            header=header(t, parent),
            child_frame_id=child,
            transform=T["geometry_msgs/msg/Transform"](
                translation=T["geometry_msgs/msg/Vector3"](x=pose[0, 3], y=pose[1, 3], z=pose[2, 3]),
                rotation=T["geometry_msgs/msg/Quaternion"](x=q[0], y=q[1], z=q[2], w=q[3]),
            ),
        )

    camera = np.asarray(frames[0].camera.camera_to_world)
    on_robot = np.eye(4)
    on_robot[:3, :3] = Rotation.from_euler("z", 0.3).as_matrix() @ camera[:3, :3]
    on_robot[:3, 3] = [0.2, 0.0, 1.1]
    robot = camera @ np.linalg.inv(on_robot)  # odom <- base_link at the first frame
    start = EPOCH + frames[0].time
    k = frames[0].camera.intrinsics
    height, width = frames[0].color.shape[:2]
    info = {"height": height, "width": width, "binning_x": 0, "binning_y": 0, "distortion_model": "plumb_bob"}
    calib = np.array([k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1.0]), np.zeros(5), np.eye(3).ravel(), np.zeros(12)
    info |= dict(zip(("k", "d", "r", "p") if ros != 1 else ("K", "D", "R", "P"), calib))
    roi = T["sensor_msgs/msg/RegionOfInterest"](x_offset=0, y_offset=0, height=0, width=0, do_rectify=False)
    camera_info = T["sensor_msgs/msg/CameraInfo"](header=header(start), **info, roi=roi)
    mounted = T[tf_type](transforms=[transform(start, mount, "camera_color_optical_frame", on_robot)])
    messages = [
        ("/camera/color/camera_info", "sensor_msgs/msg/CameraInfo", [(start, camera_info)]),
        ("/tf_static", tf_type, [(start, mounted)]),
    ]
    drives = []
    for t in np.arange(start - 0.1, EPOCH + frames[-1].time + 0.1, 0.02):
        moved = robot.copy()
        moved[:3, 3] += np.asarray(drive) * (t - start)
        wheel = np.eye(4)
        wheel[:3, :3] = Rotation.from_euler("y", 5.0 * (t - start)).as_matrix()  # a joint on /tf too
        robot_now = [transform(t, "odom", "base_link", moved), transform(t, "base_link", "wheel", wheel)]
        drives.append((t, T[tf_type](transforms=robot_now)))
    messages.append(("/tf", tf_type, drives))
    pictures = []
    depths = []
    for k, f in enumerate(frames):
        t = EPOCH + f.time
        pixels = f.color[..., ::-1] if encoding == "bgr8" else f.color
        pictures.append((t, image(t, np.ascontiguousarray(pixels), encoding)))
        mm = np.round(1000 * f.depth).astype(np.uint16)
        if k in without_depth:
            continue
        if compressed_depth == "rvl":
            size = np.array([mm.shape[1], mm.shape[0]], "<u4").tobytes()
            data = np.frombuffer(bytes(12) + size + rvl_encode(mm), np.uint8)
            packed = T["sensor_msgs/msg/CompressedImage"](
                header=header(t + depth_lag), format="16UC1; compressedDepth rvl", data=data
            )
            depths.append((t + depth_lag, packed))
        elif compressed_depth:
            png = BytesIO()
            PILImage.fromarray(mm).save(png, "PNG")
            data = np.frombuffer(bytes(12) + png.getvalue(), np.uint8)
            packed = T["sensor_msgs/msg/CompressedImage"](
                header=header(t + depth_lag), format="16UC1; compressedDepth png", data=data
            )
            depths.append((t + depth_lag, packed))
        else:
            depths.append((t + depth_lag, image(t + depth_lag, mm, "16UC1")))
    messages.append(("/camera/color/image_raw", "sensor_msgs/msg/Image", pictures))
    if compressed_depth:
        topic = "/camera/aligned_depth_to_color/image_raw/compressedDepth"
        messages.append((topic, "sensor_msgs/msg/CompressedImage", depths))
    else:
        messages.append(("/camera/aligned_depth_to_color/image_raw", "sensor_msgs/msg/Image", depths))
    messages.extend(extra)
    with writer:
        for topic, kind, stamped in messages:
            connection = writer.add_connection(topic, kind, typestore=store)
            for t, message in stamped:
                writer.write(connection, int(round(t * 1e9)), serialize(message, kind))
    return path


@pytest.mark.parametrize("ros", [1, 2, "mcap"])
def test_a_bag_gives_back_the_frames_it_was_written_from(frames, tmp_path, ros):
    path = write_bag(tmp_path / ("walk.bag" if ros == 1 else "walk"), frames, ros=ros)
    bag = open_source(path)
    assert isinstance(bag, RosBag) and len(bag) == len(frames)
    assert (bag.color_topic, bag.world_frame) == ("/camera/color/image_raw", "odom")
    got_frames = read(bag)
    assert [f.index for f in got_frames] == list(range(len(frames)))
    for got, made in zip(got_frames, frames):
        assert got.depth is not None and got.camera is not None and made.camera is not None
        assert got.time == pytest.approx(EPOCH + made.time, abs=1e-6)
        np.testing.assert_array_equal(got.color, made.color)  # bgr8 with padded rows, as rendered
        np.testing.assert_allclose(got.depth, made.depth, atol=0.0005 + 1e-6)  # to the millimetre
        assert got.camera.intrinsics == made.camera.intrinsics
        # The optical frame on the robot, the robot in odom: the rendering camera.
        np.testing.assert_allclose(got.camera.camera_to_world, made.camera.camera_to_world, atol=1e-9)


@pytest.mark.parametrize("packing", ["png", "rvl"])
def test_a_bags_compressed_depth_reads_as_its_raw_depth(frames, tmp_path, packing):
    bag = RosBag(write_bag(tmp_path / "packed", frames[:2], compressed_depth=packing))
    assert bag.depth_topic == "/camera/aligned_depth_to_color/image_raw/compressedDepth"
    for got, made in zip(read(bag), frames):
        assert got.depth is not None
        np.testing.assert_allclose(got.depth, made.depth, atol=0.0005 + 1e-6)


@pytest.mark.parametrize(
    ("ros", "tf_type"), [(2, "tf2_msgs/msg/TFMessage"), (1, "tf/msg/tfMessage")], ids=["tf2", "ros1-tf"]
)
def test_a_driving_robot_places_its_camera_where_the_transforms_put_it_at_each_stamp(
    frames, tmp_path, ros, tf_type
):
    drive = np.array([0.5, -0.2, 0.0])
    path = tmp_path / ("drive.bag" if ros == 1 else "drive")
    bag = RosBag(write_bag(path, frames, ros=ros, drive=drive, tf_type=tf_type))
    # The wheel's transforms are known to the tree's shape, and not kept: not the camera's chain.
    assert "wheel" in bag.tree and set(bag.tree.edges) == {"base_link", "camera_color_optical_frame"}
    for got, made in zip(read(bag), frames):
        assert got.camera is not None and made.camera is not None
        expected = np.array(made.camera.camera_to_world)
        expected[:3, 3] += drive * (made.time - frames[0].time)
        np.testing.assert_allclose(got.camera.camera_to_world, expected, atol=1e-9)


def depth_message(T, header, mm):
    """A 16UC1 Image message of the millimetres ``mm``, its rows unpadded."""
    return T["sensor_msgs/msg/Image"](
        header=header,
        height=mm.shape[0],
        width=mm.shape[1],
        encoding="16UC1",
        is_bigendian=0,
        step=mm.shape[1] * 2,
        data=mm.view(np.uint8).ravel(),
    )


def test_a_drivers_compressed_copy_and_its_sensors_own_depth_are_passed_over(frames, tmp_path):
    # As a RealSense driver records: the colour's JPEG copy beside the raw topic, the depth
    # sensor's own images (here half the colour's size) beside the ones registered to colour,
    # and a compressedDepth copy of those.
    T = get_typestore(Stores.ROS2_HUMBLE).types
    time = T["builtin_interfaces/msg/Time"](sec=int(EPOCH), nanosec=0)
    jpeg = BytesIO()
    PILImage.fromarray(frames[0].color).save(jpeg, "JPEG")
    data = np.frombuffer(jpeg.getvalue(), np.uint8)
    header = T["std_msgs/msg/Header"](stamp=time, frame_id="camera_color_optical_frame")
    copy = T["sensor_msgs/msg/CompressedImage"](header=header, format="jpeg", data=data)
    header = T["std_msgs/msg/Header"](stamp=time, frame_id="camera_depth_optical_frame")
    small = np.zeros((frames[0].color.shape[0] // 2, frames[0].color.shape[1] // 2), np.uint16)
    own = depth_message(T, header, small)
    png = BytesIO()
    PILImage.fromarray(np.zeros(frames[0].color.shape[:2], np.uint16)).save(png, "PNG")
    data = np.frombuffer(bytes(12) + png.getvalue(), np.uint8)
    packed = T["sensor_msgs/msg/CompressedImage"](
        header=header, format="16UC1; compressedDepth png", data=data
    )
    extra = [
        ("/camera/color/image_raw/compressed", "sensor_msgs/msg/CompressedImage", [(EPOCH, copy)]),
        ("/camera/depth/image_rect_raw", "sensor_msgs/msg/Image", [(EPOCH, own)]),
        # The registered depth's compressedDepth copy too.
        (
            "/camera/aligned_depth_to_color/image_raw/compressedDepth",
            "sensor_msgs/msg/CompressedImage",
            [(EPOCH, packed)],
        ),
    ]
    path = write_bag(tmp_path / "realsense", frames[:3], extra=extra)
    bag = RosBag(path)
    assert (bag.color_topic, bag.depth_topic) == (
        "/camera/color/image_raw",
        "/camera/aligned_depth_to_color/image_raw",
    )
    # Named, the copy is read (as JPEG), and the sensor's own depth is refused by its size.
    (first,) = read(RosBag(path, color_topic="/camera/color/image_raw/compressed"))
    assert np.abs(first.color.astype(int) - frames[0].color).mean() < 3
    with pytest.raises(
        ValueError, match=r"are 320x240, the colour images 640x480: the depth must be registered"
    ):
        RosBag(path, depth_topic="/camera/depth/image_rect_raw")


@pytest.mark.parametrize("ros", [1, 2])
def test_the_sensors_own_depth_at_the_colours_size_is_told_by_its_frame(frames, tmp_path, ros):
    # Both streams set to one size: only the optical frame in the header says which depth
    # images are the colour camera's pixels.
    store = get_typestore(Stores.ROS1_NOETIC if ros == 1 else Stores.ROS2_HUMBLE)
    T = store.types
    seconds, nanoseconds = divmod(int(round((EPOCH + frames[0].time) * 1e9)), 10**9)
    time = T["builtin_interfaces/msg/Time"](sec=seconds, nanosec=nanoseconds)
    fields = {"seq": 0} if ros == 1 else {}
    header = T["std_msgs/msg/Header"](**fields, stamp=time, frame_id="camera_depth_optical_frame")
    ones = np.full(frames[0].color.shape[:2], 1000, np.uint16)  # 1 m everywhere: not the scene's
    own = depth_message(T, header, ones)
    extra = [("/camera/depth/image_rect_raw", "sensor_msgs/msg/Image", [(EPOCH + frames[0].time, own)])]
    path = write_bag(
        tmp_path / ("same_size.bag" if ros == 1 else "same_size"), frames[:2], ros=ros, extra=extra
    )
    bag = RosBag(path)
    assert bag.depth_topic == "/camera/aligned_depth_to_color/image_raw"
    first = read(bag)[0]
    assert first.depth is not None
    np.testing.assert_allclose(first.depth, frames[0].depth, atol=5e-4)
    with pytest.raises(
        ValueError,
        match=r"in frame 'camera_depth_optical_frame', the colour images in 'camera_color_optical_frame'",
    ):
        RosBag(path, depth_topic="/camera/depth/image_rect_raw")


def test_a_colour_image_without_a_depth_image_near_it_is_a_colour_only_frame(frames, tmp_path, capsys):
    # Depth stamped 30 ms after each colour image at 10 frames/s: none within the 20 ms pairing.
    late = read(RosBag(write_bag(tmp_path / "late", frames[:5], depth_lag=0.03)))
    assert [f.depth for f in late] == [None] * 5
    near = read(RosBag(write_bag(tmp_path / "near", frames[:5], depth_lag=0.015)))
    assert [f.depth is None for f in near] == [False] * 5
    # The run says so: its people are detected, not placed in 3D.
    assert main(["run", str(tmp_path / "late"), "--out", str(tmp_path / "out")]) == 0
    assert "5 frames (5 without depth: people detected, not placed in 3D)" in capsys.readouterr().out


def test_a_bag_runs_as_its_frames_do(frames, tmp_path, capsys):
    # `torsocast run` on the bag writes what a run on the same frames (depth in mm) writes, but
    # for the world frame's name.
    from torsocast.sources.recording import write

    path = write_bag(tmp_path / "walk", frames)
    write(
        tmp_path / "walk.npz",
        np.stack([f.color for f in frames]),
        np.stack([np.round(1000 * f.depth).astype(np.uint16) for f in frames]),
        [EPOCH + f.time for f in frames],
        frames[0].camera,
    )
    for source, out in ((path, "bag"), (tmp_path / "walk.npz", "npz")):
        assert main(["run", str(source), "--out", str(tmp_path / out)]) == 0
    capsys.readouterr()
    text = {out: (tmp_path / out / "frames.jsonl").read_text() for out in ("bag", "npz")}
    # The bag names its world frame (odom); the recording does not.
    assert '"frame_id": "odom"' in text["bag"] and '"frame_id": "odom"' not in text["npz"]
    lines = {
        out: [json.loads(line) for line in text[out].replace('"odom"', '"world"').splitlines()]
        for out in text
    }
    tracked = [p for line in lines["bag"] for p in line["people"] if p["id"] is not None]
    assert len(tracked) >= len(frames) - 3 and lines["bag"] == lines["npz"]


def test_a_bags_topics_are_named_where_it_has_several_and_a_bad_image_is_skipped(frames, tmp_path, capsys):
    store = get_typestore(Stores.ROS2_HUMBLE)
    T = store.types
    time = T["builtin_interfaces/msg/Time"](sec=int(EPOCH) + 1, nanosec=0)
    header = T["std_msgs/msg/Header"](stamp=time, frame_id="camera_color_optical_frame")
    data = np.arange(50, dtype=np.uint8)  # not a JPEG
    broken = T["sensor_msgs/msg/CompressedImage"](header=header, format="jpeg", data=data)
    compressed = "/webcam/image_raw/compressed"  # another camera's
    extra = [(compressed, "sensor_msgs/msg/CompressedImage", [(EPOCH + 1, broken)])]
    path = write_bag(tmp_path / "two", frames, extra=extra)
    topics = rf"2 colour image topics \(/camera/color/image_raw, {compressed}\)"
    with pytest.raises(
        ValueError, match=rf"{topics}: name one with --color-topic \(color_topic= in Python\)"
    ):
        RosBag(path)
    with pytest.raises(ValueError, match="/nope is not a colour image topic"):
        RosBag(path, color_topic="/nope")
    with pytest.raises(ValueError, match="the transforms have no frame 'map'"):
        RosBag(path, color_topic="/camera/color/image_raw", world_frame="map")
    with pytest.raises(ValueError, match="'camera_color_optical_frame' is not connected to 'odom'"):
        RosBag(write_bag(tmp_path / "apart", frames[:2], mount="elsewhere"))
    # The compressed topic's one image does not decode: reported and skipped.
    (skipped,) = list(RosBag(path, color_topic=compressed))
    assert isinstance(skipped, SkippedFrame) and skipped.time == pytest.approx(EPOCH + 1)
    # The command line asks for the topic in one line, and takes it.
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "name one with --color-topic" in err
    assert main(["run", str(path), "--out", str(tmp_path / "out"), "--color-topic", compressed]) == 0
    assert f"frame 0 skipped: {compressed} at" in capsys.readouterr().err
    # A bag's options given for another source are refused.
    assert main(["run", str(tmp_path / "nothing.npz"), "--world-frame", "odom"]) == 2


def test_the_body_frames_are_written_as_a_ros_bag_that_reads_back_as_the_json_lines(frames, tmp_path, capsys):
    from rosbags.highlevel import AnyReader

    from torsocast.output import body_frame_of

    # Frames 12 to 15 without depth: the walker's track is kept unseen there, and still on /tf.
    source = write_bag(tmp_path / "walk", frames, without_depth=range(12, 16))
    out = tmp_path / "out"
    assert main(["run", str(source), "--out", str(out), "--bag"]) == 0
    lines = [json.loads(line) for line in (out / "frames.jsonl").read_text().splitlines()]
    expected: dict[int, dict[str, dict]] = {}
    shown: dict[int, list[str]] = {}
    paths: dict[tuple[str, int], list[tuple[float, list[float]]]] = {}
    for line in lines:
        stamp = int(round(line["time"] * 1e9))
        people = [p for p in line["people"] if p.get("body_frame")]
        frames_now = [p["body_frame"] for p in people] + [u["body_frame"] for u in line["unseen"]]
        assert {f["frame_id"] for f in frames_now} <= {"odom"}  # the source bag's world frame
        expected[stamp] = {f["child_frame_id"]: f for f in frames_now}
        shown[stamp] = [str(p["id"]) for p in people]
        for p in people:
            if p["forecast"] is not None:
                paths[(f"/humans/bodies/{p['id']}/forecast", stamp)] = [
                    (line["time"] + f["horizon"], f["pose"]) for f in p["forecast"]
                ]
    assert sum(len(line["unseen"]) for line in lines) >= 3 and len(paths) >= 10
    written: dict[int, dict[str, Any]] = {}
    tracked: dict[int, list[str]] = {}
    forecasts: dict[tuple[str, int], Any] = {}
    with AnyReader([out / "bodies"]) as bag:
        topics = {c.topic: c.msgtype for c in bag.connections}
        assert topics == {
            "/tf": "tf2_msgs/msg/TFMessage",
            "/humans/bodies/tracked": "hri_msgs/msg/IdsList",
            "/humans/bodies/1/forecast": "nav_msgs/msg/Path",
        }
        for conn, stamp, raw in bag.messages():
            message: Any = bag.deserialize(raw, conn.msgtype)
            if conn.topic == "/tf":
                written[stamp] = {tf.child_frame_id: tf for tf in message.transforms}
            elif conn.topic.endswith("tracked"):
                tracked[stamp] = list(message.ids)
            else:
                forecasts[(conn.topic, stamp)] = message

    def seconds(header):
        assert header.frame_id == "odom"  # the source bag's world frame
        return header.stamp.sec + 1e-9 * header.stamp.nanosec

    assert tracked == shown and set(written) == {t for t, f in expected.items() if f}
    for stamp, transforms in written.items():
        assert set(transforms) == set(expected[stamp])
        for child, tf in transforms.items():
            assert seconds(tf.header) == pytest.approx(stamp * 1e-9)
            p, q = tf.transform.translation, tf.transform.rotation
            np.testing.assert_allclose([p.x, p.y, p.z], expected[stamp][child]["translation"], atol=1e-4)
            np.testing.assert_allclose([q.x, q.y, q.z, q.w], expected[stamp][child]["rotation"], atol=1e-6)
    # Each forecast: a path of the poses at the horizons, stamped when they aim, oriented as the
    # body frame of the forecast pose.
    assert set(forecasts) == set(paths)
    for key, path in forecasts.items():
        assert seconds(path.header) == pytest.approx(key[1] * 1e-9)
        assert len(path.poses) == len(paths[key])
        for placed, (aim, pose) in zip(path.poses, paths[key]):
            # The horizons count from the track's last sample on the 25 Hz grid, within half a
            # step of the frame's stamp.
            assert seconds(placed.header) == pytest.approx(aim, abs=0.021)
            at, o = placed.pose.position, placed.pose.orientation
            np.testing.assert_allclose([at.x, at.y, at.z], pose[:3], atol=1e-4)
            frame = body_frame_of(np.array(pose))  # of the pose as the JSON Lines round it
            assert frame is not None
            np.testing.assert_allclose([o.x, o.y, o.z, o.w], frame[1], atol=1e-4)
    # A second run replaces the first's bag; a folder that is not a bag is never removed.
    assert main(["run", str(source), "--out", str(out), "--bag"]) == 0
    capsys.readouterr()
    (out / "bodies" / "notes.txt").write_text("mine")
    assert main(["run", str(source), "--out", str(out), "--bag"]) == 2
    assert "bodies: exists, and is not a ROS bag this could replace" in capsys.readouterr().err
    assert (out / "bodies" / "notes.txt").read_text() == "mine"


def test_camera_info_gives_the_intrinsics_and_refuses_a_distortion_it_cannot_model():
    from torsocast.sources.rosbag import intrinsics

    T = get_typestore(Stores.ROS2_HUMBLE).types

    def info(model, d, k=(500.0, 0, 320.0, 0, 510.0, 240.0, 0, 0, 1)):
        time = T["builtin_interfaces/msg/Time"](sec=0, nanosec=0)
        roi = T["sensor_msgs/msg/RegionOfInterest"](
            x_offset=0, y_offset=0, height=0, width=0, do_rectify=False
        )
        return T["sensor_msgs/msg/CameraInfo"](
            header=T["std_msgs/msg/Header"](stamp=time, frame_id="c"),
            height=480,
            width=640,
            distortion_model=model,
            d=np.array(d, float),
            k=np.array(k, float),
            r=np.eye(3).ravel(),
            p=np.zeros(12),
            binning_x=0,
            binning_y=0,
            roi=roi,
        )

    got = intrinsics(info("plumb_bob", [0.1, -0.05, 0.001, 0.002, 0.01]))
    assert (got.fx, got.fy, got.cx, got.cy) == (500.0, 510.0, 320.0, 240.0)
    assert got.distortion == (0.1, -0.05, 0.001, 0.002, 0.01)
    assert intrinsics(info("rational_polynomial", [0.1, 0, 0, 0, 0, 0, 0, 0])).distortion[0] == 0.1
    with pytest.raises(ValueError, match="distortion model 'equidistant' with 4 coefficients"):
        intrinsics(info("equidistant", [0.1, 0.0, 0.0, 0.0]))
    with pytest.raises(ValueError, match="k4 to k6 zero"):
        intrinsics(info("rational_polynomial", [0.1, 0, 0, 0, 0, 0.2, 0, 0]))
    with pytest.raises(ValueError, match="not a 3x3 camera matrix's 9"):
        intrinsics(info("plumb_bob", [], k=(500.0, 320.0)))


def rvl_encode(values):
    """image_transport's CompressRVL, step by step: the reference the decoder is checked against."""
    words, word, written = [], 0, 0

    def vle(value):
        nonlocal word, written
        while True:
            nibble = value & 7
            value >>= 3
            nibble |= 8 if value else 0
            word = ((word << 4) | nibble) & 0xFFFFFFFF
            written += 1
            if written == 8:
                words.append(word)
                word, written = 0, 0
            if not value:
                return

    flat, i, previous = [int(v) for v in np.ravel(values)], 0, 0
    while i < len(flat):
        zeros = 0
        while i < len(flat) and flat[i] == 0:
            zeros, i = zeros + 1, i + 1
        vle(zeros)
        nonzeros = 0
        while i + nonzeros < len(flat) and flat[i + nonzeros]:
            nonzeros += 1
        vle(nonzeros)
        for _ in range(nonzeros):
            delta = flat[i] - previous
            vle(((delta << 1) ^ (delta >> 31)) & 0xFFFFFFFF)
            previous, i = flat[i], i + 1
    if written:
        words.append((word << 4 * (8 - written)) & 0xFFFFFFFF)
    return np.array(words, "<u4").tobytes()


def test_rvl_decodes_what_image_transports_encoder_writes():
    from types import SimpleNamespace

    from torsocast.sources.rosbag import depth_image, rvl_decode

    # By hand: two zeros, one nonzero (5, zigzag 10: nibbles 0xA then 1): nibbles 2, 1, A, 1.
    assert rvl_encode([0, 0, 5]) == bytes([0x00, 0x00, 0xA1, 0x21])
    np.testing.assert_array_equal(rvl_decode(bytes([0x00, 0x00, 0xA1, 0x21]), 3), [0, 0, 5])
    rng = np.random.default_rng(3)
    mm = rng.integers(300, 9000, (48, 64)).astype(np.uint16)
    mm[rng.random(mm.shape) < 0.3] = 0  # holes
    mm[:5] = 0
    mm[-1, -7:] = [65535, 1, 0, 0, 40000, 2, 0]  # the largest steps either way, and a closing run
    np.testing.assert_array_equal(rvl_decode(rvl_encode(mm), mm.size), mm.ravel())
    size = np.array([64, 48], "<u4").tobytes()
    packed = SimpleNamespace(format="16UC1; compressedDepth rvl", data=bytes(12) + size + rvl_encode(mm))
    np.testing.assert_allclose(depth_image(packed), mm.astype(np.float32) / 1000, rtol=1e-6)
    a, b = np.float32(10100.0), np.float32(-1009.0)
    header = np.array([0], "<i4").tobytes() + np.array([a, b], "<f4").tobytes()
    inverse = SimpleNamespace(format="32FC1; compressedDepth rvl", data=header + size + rvl_encode(mm))
    expected = np.where(mm > 0, a / (mm.astype(np.float32) - b), 0)
    np.testing.assert_allclose(depth_image(inverse), expected, rtol=1e-6)
    with pytest.raises(ValueError, match="RVL stream ends after"):
        rvl_decode(rvl_encode(mm)[:40], mm.size)
    with pytest.raises(ValueError, match="holds no word for 3 pixels"):
        rvl_decode(b"", 3)
    with pytest.raises(ValueError, match="runs past the image's 3 pixels"):
        rvl_decode(rvl_encode([0, 0, 0, 7]), 3)
    lying = SimpleNamespace(
        format="16UC1; compressedDepth rvl",
        data=bytes(12) + np.array([4000, 4000], "<u4").tobytes() + bytes(8),
    )
    with pytest.raises(ValueError, match="says 4000x4000 pixels"):
        depth_image(lying)


def test_a_live_nodes_messages_convert_as_a_bags_do():
    # rclpy's messages carry no rosbags type name and hold their pixels as bytes: the converters
    # read them by their fields. Big-endian depth, and row padding, as a driver may send them.
    from types import SimpleNamespace

    from torsocast.sources.rosbag import colour_image, depth_image

    rgb = np.arange(2 * 3 * 3, dtype=np.uint8).reshape(2, 3, 3)
    padded = np.zeros((2, 11), np.uint8)
    padded[:, :9] = rgb[..., ::-1].reshape(2, 9)
    bgr = SimpleNamespace(encoding="bgr8", height=2, width=3, step=11, is_bigendian=0, data=padded.tobytes())
    np.testing.assert_array_equal(colour_image(bgr), rgb)
    mm = np.array([[1000, 0, 2500], [65535, 1, 42]], dtype=">u2")
    depth = SimpleNamespace(encoding="16UC1", height=2, width=3, step=6, is_bigendian=1, data=mm.tobytes())
    np.testing.assert_allclose(depth_image(depth), mm.astype(np.float32) / 1000)
    encoded = BytesIO()
    PILImage.fromarray(np.full((4, 4, 3), 200, np.uint8)).save(encoded, "PNG")
    png = SimpleNamespace(format="png", data=encoded.getvalue())
    np.testing.assert_array_equal(colour_image(png), np.full((4, 4, 3), 200, np.uint8))
    with pytest.raises(ValueError, match="depth format 'png' is not compressedDepth of 16UC1"):
        depth_image(png)
    # image_transport's compressedDepth of 16UC1: a 12-byte header, then a PNG of the millimetres.
    encoded = BytesIO()
    PILImage.fromarray(mm.astype(np.uint16)).save(encoded, "PNG")
    packed = SimpleNamespace(format="16UC1; compressedDepth png", data=bytes(12) + encoded.getvalue())
    np.testing.assert_allclose(depth_image(packed), mm.astype(np.float32) / 1000, rtol=1e-6)
    # Of 32FC1: a PNG of the inverse depth, quantised as image_transport's encoder does with its
    # defaults (depth_max 10 m, depth_quantization 100), the two floats in the header.
    metres = np.array([[0.5, 1.0, 2.25], [4.0, 6.5, 0.0], [np.nan, 12.0, 9.9]], np.float32)
    a = np.float32(100.0 * 101.0)
    b = np.float32(1.0 - a / 10.0)
    with np.errstate(invalid="ignore"):
        kept = (metres > 0) & (metres < 10.0)  # no reading, or beyond depth_max: 0
    inverse = np.where(kept, a / np.where(kept, metres, 1) + b, 0).astype(np.uint16)  # C++ truncates
    encoded = BytesIO()
    PILImage.fromarray(inverse).save(encoded, "PNG")
    header = np.array([0], "<i4").tobytes() + np.array([a, b], "<f4").tobytes()
    packed = SimpleNamespace(format="32FC1; compressedDepth png", data=header + encoded.getvalue())
    read = depth_image(packed)
    expected = np.where(kept, metres, 0)
    # One step of the inverse depth is depth squared over a: under 2 mm at 4 m, 4.2 mm at 6.5 m.
    np.testing.assert_allclose(read, expected, atol=float(6.5**2 / a) + 1e-6)
    assert read[1, 2] == 0 and read[2, 0] == 0 and read[2, 1] == 0
    with pytest.raises(ValueError, match="depth format '8UC3; compressedDepth png' is not"):
        depth_image(SimpleNamespace(format="8UC3; compressedDepth png", data=bytes(20)))
    with pytest.raises(ValueError, match="does not hold 2 rows of 9"):
        colour_image(
            SimpleNamespace(encoding="rgb8", height=2, width=3, step=9, is_bigendian=0, data=bytes(10))
        )
