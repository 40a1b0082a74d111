"""Human3.6M loader and evaluation protocol, on the real files (skipped without ../shared)."""

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import torsocast as tc
from torsocast.cli import main
from torsocast.datasets import h36m
from torsocast.evaluation import metrics, protocol
from torsocast.evaluation.h36m import evaluate
from torsocast.evaluation.methods import method_configs


def test_expmap_matches_scipy_rotvec(rng):
    r = rng.normal(size=(200, 3)) * 1.5
    r[0] = 0.0
    expected = Rotation.from_rotvec(r).as_matrix()
    assert np.allclose(h36m.expmap_to_rotmat(r), expected, atol=1e-6)


def test_azimuth_error_wraps_and_position_is_in_centimetres():
    truth = np.zeros((1, 2, 5))
    forecast = np.zeros((1, 2, 5))
    truth[0, :, 3] = np.radians([179.0, -179.0])
    forecast[0, :, 3] = np.radians([-179.0, 181.0 + 360.0])
    forecast[0, 1, :3] = [0.03, 0.04, 0.0]
    e = metrics.step_errors(forecast, truth)
    assert np.allclose(e.azimuth, [[2.0, 0.0]], atol=1e-9)
    assert np.allclose(e.position, [[0.0, 5.0]])


def test_srnn_seeds_match_the_published_draws():
    # The 8 draws of the SRNN protocol for walking and eating (start = draw + 50), as the
    # motion-prediction literature's seeded generator gives them.
    walking = [1087, 955, 1145, 332, 660, 304, 201, 54]
    eating = [1426, 374, 1087, 156, 1329, 955, 1145, 332]
    for (t1, t2), draws in (((1500, 1261), walking), ((1638, 1166), eating)):
        starts = protocol.srnn_starts(t1, t2)
        assert [s for _, s in starts] == [d + 50 for d in draws]
        assert [sub for sub, _ in starts] == [1, 2] * 4


def test_walking_skeleton_is_metric_sided_and_moves_at_walking_speed(h36m_root):
    channels = h36m.read_expmap(h36m_root / "S5" / "walking_1.txt")[:400]
    joints = h36m.forward_kinematics(channels)
    # Rigid bones keep their offsets' lengths (hip width, thigh); the spine flexes a little.
    assert np.allclose(np.linalg.norm(joints[:, 6] - joints[:, 1], axis=1), 0.265897, atol=1e-6)
    assert np.allclose(np.linalg.norm(joints[:, 2] - joints[:, 1], axis=1), 0.442895, atol=1e-6)
    assert np.allclose(np.linalg.norm(joints[:, 13] - joints[:, 0], axis=1), 0.485, atol=0.01)
    # 14.4 mm per 50 Hz frame = 0.72 m/s; the subject's left x up points where it walks.
    velocity = np.gradient(joints[:, 0], axis=0) * h36m.FILE_RATE_HZ
    speed = np.linalg.norm(velocity, axis=1)
    assert 0.6 < speed.mean() < 0.85
    gravity = h36m.estimate_gravity(
        h36m.forward_kinematics(h36m.read_expmap(h36m_root / "S5" / "walking_1.txt"))
    )
    facing = np.cross(joints[:, 6] - joints[:, 1], gravity.up)
    moving = speed > 0.3
    assert ((facing * velocity).sum(axis=1)[moving] > 0).mean() > 0.95


def test_gravity_uses_the_floor_when_walking_and_the_spine_when_seated(h36m_root):
    walking = h36m.estimate_gravity(
        h36m.forward_kinematics(h36m.read_expmap(h36m_root / "S5" / "walking_1.txt"))
    )
    assert walking.rule == "floor"
    assert walking.tilt_deg == pytest.approx(9.0, abs=0.3)  # measured from the toes' floor plane
    sitting = h36m.estimate_gravity(
        h36m.forward_kinematics(h36m.read_expmap(h36m_root / "S5" / "sitting_1.txt"))
    )
    assert sitting.rule == "spine" and sitting.floor_spine_angle_deg > 60.0
    # The forced rules the sweeps use; the floor of a seated sequence fails the sanity check.
    joints = h36m.forward_kinematics(h36m.read_expmap(h36m_root / "S5" / "sitting_1.txt"))
    assert np.allclose(h36m.estimate_gravity(joints, "spine").up, sitting.up)
    assert h36m.estimate_gravity(joints, "y").tilt_deg == 0.0
    with pytest.raises(ValueError, match="degrees from the data's"):
        h36m.estimate_gravity(joints, "floor")
    with pytest.raises(ValueError, match="not one of"):
        h36m.estimate_gravity(joints, "gravity")


def test_sequence_is_25_hz_upright_and_every_frame_has_a_plane(h36m_root):
    seq = h36m.load_sequence(h36m_root, 5, "walking", 2)
    assert len(seq.poses) == 1261  # ceil(2521 / 2): the 50 Hz take halved
    assert (seq.status == tc.PlaneStatus.OK).all()
    assert 80.0 < np.degrees(np.median(seq.poses[:, 4])) < 100.0
    # Walking turns: the unwrapped azimuth changes smoothly (no 180-degree sign flips).
    assert np.abs(np.diff(seq.poses[:, 3])).max() < np.radians(20.0)


def test_const_baseline_reproduces_the_reference_figures(h36m_root):
    # The data README's reference Const computation (dense, every 10th start, all S5 files,
    # window-mean error, pooled over windows).
    report = evaluate(h36m_root, [5], "dense", 10, {"const": tc.ForecasterConfig("const")})
    assert report["windows"]["total"] == 3150 and report["windows"]["skipped"] == 0
    pooled = report["results"]["const"]["pooled"]
    azimuth = [pooled["azimuth"]["mean"][h] for h in ("10", "25", "50")]
    elevation = [pooled["elevation"]["mean"][h] for h in ("10", "25", "50")]
    assert azimuth == pytest.approx([6.05, 12.08, 20.30], abs=0.02)
    assert elevation == pytest.approx([3.69, 6.64, 9.59], abs=0.02)


def test_eval_cli_writes_every_method_in_every_format(h36m_root, tmp_path, capsys):
    assert (
        main(["eval", "h36m", "--data", str(h36m_root), "--protocol", "seeds", "--out", str(tmp_path)]) == 0
    )
    printed = capsys.readouterr().out
    assert "Table 5.4" in printed and "(7.36)" in printed
    report = json.loads((tmp_path / "report.json").read_text())
    assert set(report["results"]) == set(method_configs())
    # 11 actions have both subactions in S5: 8 windows each.
    assert report["windows"]["total"] == 88
    assert set(report["categories"]) == {"Pedestrian", "Constrained", "High Variance", "All"}
    lines = (tmp_path / "report.csv").read_text().splitlines()
    groups = 11 + 4 + 1
    assert len(lines) == 1 + len(method_configs()) * groups * 3 * 2 * 3
    pngs = sorted(p.name for p in tmp_path.glob("*.png"))
    assert pngs == [
        f"error_vs_horizon_{c}.png" for c in ("all", "constrained", "high_variance", "pedestrian")
    ]


def test_eval_cli_refuses_a_folder_without_data(tmp_path, capsys):
    assert main(["eval", "h36m", "--data", str(tmp_path), "--out", str(tmp_path / "out")]) == 2
    assert "no Human3.6M files" in capsys.readouterr().err


def test_default_damping_is_what_selection_on_s1_picks(h36m_root):
    if not (h36m_root / "S1").is_dir():
        pytest.skip("S1 files not found")
    from torsocast.evaluation.damping import select

    best = select(h36m_root, [1])
    chosen = {q: t for q, (t, _) in best.items()}
    assert chosen == {"position": 1.5, "azimuth": 0.5, "elevation": 0.1}
    assert tc.ForecasterConfig().damping == [1.5, 1.5, 1.5, 0.5, 0.1]


def test_column_correlations_match_scipy(h36m_root):
    from scipy.stats import pearsonr, spearmanr

    from torsocast.evaluation import thesis
    from torsocast.evaluation.sweeps import column_correlations

    report = evaluate(h36m_root, [5], "dense", 20, {"const": tc.ForecasterConfig("const")})
    got = column_correlations(report)
    actions = report["results"]["const"]["actions"]
    for quantity in ("azimuth", "elevation"):
        names = [a for a in actions if a in thesis.TABLE_5_4[quantity]]
        ours = [actions[a][quantity]["mean"]["10"] for a in names]
        for i, column in enumerate(thesis.TABLE_5_4_COLUMNS):
            theirs = [thesis.TABLE_5_4[quantity][a][i] for a in names]
            assert got[quantity][column][0] == pytest.approx(pearsonr(ours, theirs)[0], abs=1e-12)
            assert got[quantity][column][1] == pytest.approx(spearmanr(ours, theirs)[0], abs=1e-12)


def test_eval_leaves_out_a_file_it_cannot_use_and_says_so(h36m_root, tmp_path, capsys):
    # A take whose up axis fails the sanity check, or a garbled file, stopped the whole
    # evaluation with a ValueError; it is now left out and named.
    subject = tmp_path / "S9"
    subject.mkdir()
    good = (h36m_root / "S5" / "walking_1.txt").read_text()
    (subject / "walking_1.txt").write_text(good)
    rows = np.array([line.split(",") for line in good.splitlines() if line.strip()], dtype=float)
    tilted = rows.copy()
    tilted[:, 3:6] = [0.0, 0.0, np.pi / 2]  # the root lies on its side every frame: no up axis
    tilted[1:, 3:6] = 0.0  # (root rotations are increments: only the first one turns it)
    (subject / "walking_2.txt").write_text("\n".join(",".join(map(str, r)) for r in tilted))
    (subject / "eating_1.txt").write_text("not,numbers\n")
    out = tmp_path / "out"
    assert main(["eval", "h36m", "--data", str(tmp_path), "--subjects", "9", "--out", str(out)]) == 0
    report = json.loads((out / "report.json").read_text())
    left_out = " ".join(report["left_out"])
    assert "S9/eating_1" in left_out and "S9/walking_2" in left_out and "gravity" in left_out
    assert [s["name"] for s in report["sequences"]] == ["S9/walking_1"]
    assert "Files left out" in capsys.readouterr().out
