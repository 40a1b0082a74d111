import sys
from pathlib import Path

import numpy as np
import pytest

# The independent SciPy reference lives beside the tests, not in the package.
sys.path.insert(0, str(Path(__file__).parent))


@pytest.fixture
def rng():
    return np.random.default_rng(20261122)


def walking_history(n=50, rate=25.0, seed=0):
    """A (n, 5) pose history: a person walking and turning, with sensor-like noise; azimuth
    wrapped into (-pi, pi] as a detector would report it."""
    r = np.random.default_rng(seed)
    t = np.arange(n) / rate
    az = 2.6 + 1.2 * t + 0.15 * np.sin(2 * np.pi * 1.8 * t) + 0.02 * r.normal(size=n)
    hist = np.stack(
        [
            0.9 * t + 0.01 * r.normal(size=n),
            0.3 * np.sin(t) + 0.01 * r.normal(size=n),
            1.1 + 0.02 * np.sin(2 * np.pi * 1.8 * t),
            np.angle(np.exp(1j * az)),
            np.pi / 2 + 0.05 * np.sin(2 * np.pi * 0.9 * t) + 0.01 * r.normal(size=n),
        ],
        axis=1,
    )
    return t, hist


#: The shared data folder beside the checkout (CI has it); TORSOCAST_SHARED overrides.
SHARED = Path(__import__("os").environ.get("TORSOCAST_SHARED", Path(__file__).parents[1] / ".." / "shared"))
H36M = SHARED / "data" / "h36m"


@pytest.fixture(scope="session")
def h36m_root():
    if not (H36M / "S5").is_dir():
        pytest.skip(f"Human3.6M files not found at {H36M} (research-only data, read from ../shared)")
    return H36M


def run_cli(argv):
    """``torsocast argv`` in this process: its exit code (argparse's refusals count as exits), and
    what it wrote to stdout and to stderr."""
    import contextlib
    import io

    from torsocast.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code: int | str | None
        try:
            code = main(argv)
        except SystemExit as e:
            code = e.code
    return code, out.getvalue(), err.getvalue()


def shared_path(*parts):
    """A file or folder of ../shared, or a skip that says what is missing and why."""
    path = SHARED.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"{path} not found (shared test data, read from ../shared, never copied)")
    return path


def pose_of(observation) -> np.ndarray:
    """The pose of an observation the test's frame must have given one."""
    assert observation is not None and observation.pose is not None
    return observation.pose


def readable_frames(source, count=None):
    """The first ``count`` frames of ``source`` (or all), every one of them read: a frame the
    source could not read fails the test that needs them."""
    from itertools import islice

    from torsocast.sources import Frame

    frames = list(islice(source, count))
    readable = [f for f in frames if isinstance(f, Frame)]
    assert len(readable) == len(frames), f"{len(frames) - len(readable)} frames could not be read"
    return readable


def turntable_frames(count=None):
    """The real turntable sequence's frames (its first ``count``, or all), every one read."""
    from torsocast.sources import open_source

    return readable_frames(open_source(shared_path("data", "rgbd", "turntable")), count)


@pytest.fixture(scope="session")
def yolo640():
    from torsocast.keypoints import open_model

    return open_model(shared_path("models", "yolo11n-pose.onnx"))


@pytest.fixture(scope="session")
def yolo320():
    from torsocast.keypoints import open_model

    return open_model(shared_path("models", "yolo11n-pose-320.onnx"))
