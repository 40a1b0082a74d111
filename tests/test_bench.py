"""The crowds ``torsocast bench`` and ``benches/bench_pipeline.py`` time a frame of: every person
in them is a track, so a frame's cost is that of as many people as the table says."""

import numpy as np
import pytest

from torsocast.bench import crowd, frame_cost, frame_report, places


@pytest.mark.parametrize("people", [1, 10, 24])
def test_every_person_of_a_crowd_is_tracked(people):
    rng = np.random.default_rng(people)
    # Four seconds: the arc's person at the picture's edge is confirmed within them.
    frames = [crowd(people, k / 25, rng) for k in range(100)]
    seconds, tracks = frame_cost(frames)
    assert tracks == people and 0 < seconds < 1
    keypoints, depth = frames[0]
    assert keypoints.shape == (people, 17, 3) and depth.shape == (480, 640)
    # On the stand, each person's torso is seen apart: no two stand within a torso's width.
    where = places(people)
    gaps = np.linalg.norm(where[:, None] - where[None], axis=-1) + np.eye(people) * 9
    assert gaps.min() > 0.4


def test_the_report_is_a_table_of_the_crowds():
    text = frame_report([(1, 1.2e-5, 1), (50, 4.9e-4, 50)])
    assert text.splitlines()[0] == "| people | Tracker.step per frame (ms) | tracks |"
    assert "| 50 | 0.490 | 50 |" in text


def test_a_crowd_of_nobody_and_no_frames_are_refused():
    with pytest.raises(ValueError, match="at least one person"):
        crowd(0, 0.0, np.random.default_rng(0))
    with pytest.raises(ValueError, match="no frames"):
        frame_cost([])
