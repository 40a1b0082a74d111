"""The Motion-JPEG AVI writer, read back by OpenCV's demuxer and JPEG decoder (an independent
reader), and its file structure against the AVI layout."""

import struct

import numpy as np
import pytest
from PIL import Image

from torsocast import avi
from torsocast.avi import AviWriter

cv2 = pytest.importorskip("cv2", reason="OpenCV (pip install '.[test]') reads the videos back")


def picture(k, size=(160, 120)):
    """A frame whose colour and moving bar say which frame it is."""
    a = np.zeros((size[1], size[0], 3), dtype=np.uint8)
    a[...] = (20 * k % 256, 100, 255 - 20 * k % 256)
    a[:, 10 * k : 10 * k + 8] = 255
    return Image.fromarray(a)


def read_back(path):
    capture = cv2.VideoCapture(str(path))
    assert capture.isOpened()
    fps, count = capture.get(cv2.CAP_PROP_FPS), capture.get(cv2.CAP_PROP_FRAME_COUNT)
    frames = []
    while True:
        ok, bgr = capture.read()
        if not ok:
            break
        frames.append(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB))
    capture.release()
    return fps, count, frames


def test_opencv_reads_back_every_frame_at_the_rate_of_the_time_stamps(tmp_path):
    path = tmp_path / "v.avi"
    with AviWriter(path) as video:
        for k in range(12):
            video.write(picture(k), t=k / 15)
    fps, count, frames = read_back(path)
    assert fps == pytest.approx(15.0, rel=1e-3) and count == 12 and len(frames) == 12
    for k, frame in enumerate(frames):
        # JPEG at quality 90 on flat colours and a sharp bar: a few levels of error on average.
        assert np.abs(frame.astype(int) - np.asarray(picture(k))).mean() < 3.0, k
    assert video.paths == [path]


def test_the_riff_sizes_and_the_index_match_the_file(tmp_path):
    path = tmp_path / "v.avi"
    with AviWriter(path, fps=25.0) as video:
        for k in range(3):
            video.write(picture(k, (101, 75)))  # odd sizes: JPEG chunks may need padding
    data = path.read_bytes()
    assert data[:4] == b"RIFF" and data[8:12] == b"AVI "
    assert struct.unpack("<I", data[4:8])[0] == len(data) - 8
    movi = data.index(b"movi")
    (movi_size,) = struct.unpack("<I", data[movi - 4 : movi])
    idx1 = movi + movi_size
    assert data[idx1 : idx1 + 4] == b"idx1"
    entries = np.frombuffer(data[idx1 + 8 :], dtype="<u4").reshape(-1, 4)
    assert len(entries) == 3 and (entries[:, 1] == 0x10).all()  # every frame a key frame
    for _, _, offset, length in entries:
        chunk = movi + offset
        assert data[chunk : chunk + 4] == b"00dc"
        assert struct.unpack("<I", data[chunk + 4 : chunk + 8])[0] == length
        assert data[chunk + 8 : chunk + 10] == b"\xff\xd8"  # a JPEG starts here
    avih = data.index(b"avih") + 8
    us_per_frame, _, _, flags, frames = struct.unpack("<5I", data[avih : avih + 20])
    assert (us_per_frame, flags & 0x10, frames) == (40000, 0x10, 3)


def test_a_long_video_continues_in_numbered_files(tmp_path, monkeypatch):
    monkeypatch.setattr(avi, "MAX_FILE_BYTES", 8_000)  # a few frames per file
    with AviWriter(tmp_path / "long.avi", fps=10) as video:
        for k in range(10):
            video.write(picture(k))
    assert len(video.paths) >= 2 and video.paths[1].name == "long_001.avi"
    counts = [len(read_back(p)[2]) for p in video.paths]
    assert sum(counts) == 10 and all(p.stat().st_size <= 8_000 for p in video.paths)


def test_frames_of_another_size_and_bad_settings_are_refused(tmp_path):
    with AviWriter(tmp_path / "v.avi") as video:
        video.write(picture(0))
        with pytest.raises(ValueError, match="is \\(80, 60\\), the video is \\(160, 120\\)"):
            video.write(picture(1, (80, 60)))
    assert len(read_back(tmp_path / "v.avi")[2]) == 1
    with pytest.raises(ValueError, match="fps"):
        AviWriter(tmp_path / "w.avi", fps=0)
    with pytest.raises(ValueError, match="quality"):
        AviWriter(tmp_path / "w.avi", quality=100)
