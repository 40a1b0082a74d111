"""`torsocast forecast`: a recorded track in, one JSON object per row out, against closed forms;
and its refusals of bad input."""

import json

import numpy as np
import pytest

from torsocast.cli import main


def walk_csv(path, rows=30, rate=25.0):
    """A track walking along x at 1 m/s while turning at 0.5 rad/s, as the CSV the command reads."""
    t = np.arange(rows) / rate
    track = np.column_stack([t, t, np.zeros(rows), np.ones(rows), 0.5 * t, np.full(rows, 1.5)])
    path.write_text("# t,x,y,z,azimuth,elevation\n" + "\n".join(",".join(map(str, r)) for r in track))
    return track


def test_forecast_prints_one_object_per_row_with_the_closed_form(tmp_path, capsys):
    track = walk_csv(tmp_path / "walk.csv")
    args = ["forecast", str(tmp_path / "walk.csv"), "--horizons", "0.4,1"]
    assert main([*args, "--method", "const"]) == 0
    lines = [json.loads(line) for line in capsys.readouterr().out.splitlines()]
    assert len(lines) == len(track) and lines[-1]["t"] == pytest.approx(track[-1, 0])
    # Const holds the last pose at every horizon.
    held = lines[-1]["forecast"]["1"]
    assert [held[k] for k in ("x", "azimuth", "elevation")] == pytest.approx(track[-1, [1, 4, 5]])
    assert main([*args, "--method", "constant_velocity"]) == 0
    ahead = json.loads(capsys.readouterr().out.splitlines()[-1])["forecast"]
    # Exact on a straight line: 1 m/s and 0.5 rad/s carried 0.4 and 1 s.
    assert ahead["0.4"]["x"] == pytest.approx(track[-1, 1] + 0.4)
    assert ahead["1"]["azimuth"] == pytest.approx(track[-1, 4] + 0.5)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--horizons", "0.4,soon"], "--horizons: expected comma-separated seconds"),
        (["--horizons", "-1"], "--horizons: expected seconds >= 0"),
    ],
)
def test_forecast_refuses_bad_horizons(tmp_path, capsys, args, message):
    walk_csv(tmp_path / "walk.csv")
    assert main(["forecast", str(tmp_path / "walk.csv"), *args]) == 2
    assert message in capsys.readouterr().err


def test_forecast_refuses_a_missing_file_and_a_malformed_row(tmp_path, capsys):
    assert main(["forecast", str(tmp_path / "missing.csv")]) == 2
    assert "missing.csv" in capsys.readouterr().err
    (tmp_path / "bad.csv").write_text("0,0,0,1,0,1.5\n0.04,0,0,one,0,1.5\n")
    assert main(["forecast", str(tmp_path / "bad.csv")]) == 2
    assert "line 2: expected 6 or 7 comma-separated numbers" in capsys.readouterr().err
