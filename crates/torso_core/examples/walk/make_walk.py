"""Writes the recording that ``cargo run --example replay`` reads: 2 s of the bundled CMU walk
``test_walking_1`` rendered as RGB-D by torsocast's demo camera, the bundled MoveNet's keypoints
on each colour frame, and the depth images, at 7.5 frames per second.

    python crates/torso_core/examples/walk/make_walk.py

The depth is kept at a quarter of the rendered 640x480 (every fourth pixel, so each value is a
real reading) to keep the recording small; the keypoints and intrinsics are scaled to match.
Format (``README.md`` beside this file): ``camera.txt``, ``detections.txt``, ``depth/NNNN.pgm``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from torsocast.keypoints import open_model
from torsocast.synthetic.mocap import MocapScene

HERE = Path(__file__).resolve().parent
SCALE = 4
FRAMES = 15


def main() -> None:
    scene = MocapScene.from_clip("test_walking_1", fps=7.5)
    model = open_model()
    camera = scene.camera
    assert camera is not None
    k = camera.intrinsics
    (HERE / "depth").mkdir(exist_ok=True)
    lines = ["# frame time_s person then u v score for the 17 COCO keypoints (pixels of the depth image)"]
    for frame in list(scene)[:FRAMES]:
        found = model(frame.color)
        for person, points in enumerate(found.keypoints):
            uv = (points[:, :2] - SCALE // 2) / SCALE  # as the intrinsics below
            values = np.column_stack([uv, points[:, 2]]).ravel()
            lines.append(f"{frame.index} {frame.time:.6f} {person} " + " ".join(f"{v:.3f}" for v in values))
        assert frame.depth is not None
        small = frame.depth[SCALE // 2 :: SCALE, SCALE // 2 :: SCALE]
        millimetres = np.clip(np.nan_to_num(small) * 1000.0, 0, 65535).round().astype(">u2")
        height, width = millimetres.shape
        with open(HERE / "depth" / f"{frame.index:04d}.pgm", "wb") as f:
            f.write(f"P5\n{width} {height}\n65535\n".encode())
            f.write(millimetres.tobytes())
    (HERE / "detections.txt").write_text("\n".join(lines) + "\n")
    # Pixel centres: full-resolution pixel SCALE j + SCALE / 2 is low-resolution pixel j.
    fx, fy = k.fx / SCALE, k.fy / SCALE
    cx, cy = (k.cx - SCALE // 2) / SCALE, (k.cy - SCALE // 2) / SCALE
    pose = np.asarray(camera.camera_to_world)
    text = [
        "# fx fy cx cy (pixels of the depth image)",
        f"{fx:.6f} {fy:.6f} {cx:.6f} {cy:.6f}",
        "# Brown-Conrady k1 k2 p1 p2 k3",
        " ".join(f"{v:.9f}" for v in k.coefficients),
        "# camera_to_world: the top three rows of the 4x4 optical-to-world transform (REP-103 world)",
        *(" ".join(f"{v:.9f}" for v in row) for row in pose[:3]),
    ]
    (HERE / "camera.txt").write_text("\n".join(text) + "\n")


if __name__ == "__main__":
    main()
