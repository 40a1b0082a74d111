"""`torsocast forecast`: a recorded track in, one JSON object per row out, against closed forms;
and its refusals of bad input."""

import json

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from conftest import run_cli, shared_path
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


def test_forecast_skips_a_pose_too_large_to_filter_and_writes_valid_json(tmp_path, capsys):
    # A pose near 1e308 forecast as infinity and the command wrote the token Infinity, which
    # is not JSON.
    walk_csv(tmp_path / "walk.csv")
    with open(tmp_path / "walk.csv", "a") as f:
        f.write("\n2.0,1e308,0,1,0.5,1.5\n")
    assert main(["forecast", str(tmp_path / "walk.csv")]) == 0
    captured = capsys.readouterr()
    lines = [json.loads(line) for line in captured.out.splitlines()]  # every line parses
    assert len(lines) == 30 and "skipped" in captured.err and "= 1e308:" in captured.err


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["bench", "--windows", "0"], "--windows: expected a positive number"),
        (["run", "nowhere", "--fps", "inf"], "--fps: expected a positive, finite frame rate"),
    ],
)
def test_bad_numbers_on_the_command_line_are_one_line_and_exit_2(args, message, capsys):
    assert main(args) == 2
    assert message in capsys.readouterr().err


def test_a_negative_spline_degree_is_an_argument_error():
    with pytest.raises(SystemExit) as exit_code:
        main(["forecast", "-", "--degree", "-1"])
    assert exit_code.value.code == 2


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--horizons", "-1"], "--horizons: expected seconds > 0"),
        (["--horizons", "0.4,inf"], "--horizons: expected seconds > 0"),
        (["--horizons", "7200"], "and <= 3600"),  # the core's MAX_HORIZON: a polynomial runs away
        (["--out", "FILE"], "--out: cannot use"),
    ],
)
def test_run_and_demo_refuse_bad_horizons_and_an_output_that_is_a_file(args, message, tmp_path, capsys):
    # Each of these ended in a traceback (ValueError from the pipeline, FileExistsError).
    (tmp_path / "FILE").write_text("not a folder")
    args = [str(tmp_path / a) if a == "FILE" else a for a in args]
    out = [] if "--out" in args else ["--out", str(tmp_path / "out")]
    for command in (["run", str(tmp_path)], ["demo"]):
        assert main([*command, *args, *out]) == 2
        assert message in capsys.readouterr().err


def test_forecast_reads_a_byte_order_mark_and_refuses_what_has_no_rows(tmp_path, capsys):
    track = walk_csv(tmp_path / "walk.csv")
    body = "\n".join(",".join(map(str, r)) for r in track)
    (tmp_path / "bom.csv").write_text("\ufeff" + body, encoding="utf-8")  # the mark dropped row 1
    assert main(["forecast", str(tmp_path / "bom.csv")]) == 0
    assert len(capsys.readouterr().out.splitlines()) == len(track)
    # A ';'-separated file and UTF-16 text gave exit 0 and no output, or a traceback.
    (tmp_path / "semi.csv").write_text(body.replace(",", ";"))
    (tmp_path / "utf16.csv").write_text(body, encoding="utf-16")
    for name, message in (("semi.csv", "has no rows of 6 or 7"), ("utf16.csv", "is not UTF-8 text")):
        assert main(["forecast", str(tmp_path / name)]) == 2
        assert message in capsys.readouterr().err


@settings(max_examples=120, deadline=None, derandomize=True)
@given(
    rows=st.lists(
        st.lists(
            st.one_of(
                st.floats(allow_nan=True, allow_infinity=True).map(repr),
                st.text(alphabet=",;.-eE0123456789 nainf\t", max_size=12),
            ),
            max_size=8,
        ),
        max_size=12,
    ),
    separator=st.sampled_from([",", ";", "\t"]),
    args=st.lists(
        st.sampled_from(["--horizons", "0.4,1", "-1", "inf", "--method", "const", "--degree", "7"]),
        max_size=4,
    ),
)
def test_forecast_on_any_text_writes_json_or_says_one_line_and_exits_2(rows, separator, args):
    # Never a traceback: exit 0 with strict JSON lines, or exit 2 (argparse: a usage error).
    import tempfile

    text = "\n".join(separator.join(cells) for cells in rows)
    with tempfile.TemporaryDirectory() as folder:
        path = f"{folder}/track.csv"
        with open(path, "w") as f:
            f.write(text)
        code, out, err = run_cli(["forecast", path, *args])
    assert code in (0, 2), err

    def refuse(token):
        raise ValueError(f"{token} is not JSON")

    for line in out.splitlines():
        json.loads(line, parse_constant=refuse)  # strict JSON: no NaN or Infinity tokens
    if code == 2:
        assert err.strip()


@pytest.mark.parametrize(
    "content",
    [
        "",
        "hello world\n",
        ",".join(["0"] * 116) + "\n",
        (",".join(["0"] * 117) + "\n") + ",".join(["nan"] * 117) + "\n",
    ],
)
def test_demo_on_a_clip_it_cannot_read_says_one_line_and_exits_2(tmp_path, capsys, content):
    clip = tmp_path / "clip.txt"
    clip.write_text(content)
    assert main(["demo", "--clip", str(clip), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("torsocast demo:")


def _a_window_count(text):
    """Whether argparse's ``int`` reads ``text`` as a count `bench` takes (1 to 100 000)."""
    try:
        return 1 <= int(text) <= 100_000
    except ValueError:
        return False


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    windows=st.one_of(
        st.integers(max_value=0).map(str),
        st.integers(min_value=100_001, max_value=10**30).map(str),
        st.text(max_size=10).filter(lambda text: not _a_window_count(text)),
    )
)
def test_bench_on_any_window_count_it_cannot_use_says_one_line_and_exits_2(windows):
    # 10**20 windows ended in numpy's "Maximum allowed dimension exceeded" traceback, and a
    # billion would have filled the memory: the count is bounded.
    code, _, err = run_cli(["bench", "--windows", windows])
    assert code == 2 and err.strip() and "Traceback" not in err


@settings(max_examples=30, deadline=None, derandomize=True)
@given(
    split=st.sampled_from(["report", "dev", "nonsense"]),
    seed=st.one_of(st.integers(min_value=-(10**25), max_value=10**25).map(str), st.text(max_size=6)),
    scenes=st.sampled_from(["1", "0", "-4", "10001", "10" * 12, "one"]),
    folders=st.fixed_dictionaries(
        {
            option: st.sampled_from(["missing", "a file", "given"])
            for option in ("--cmu", "--h36m", "--yolo", "--cache", "--out")
        }
    ),
)
@example(
    split="report",
    seed="0",
    scenes="1",
    folders=dict.fromkeys(("--cmu", "--h36m", "--yolo", "--cache", "--out"), "given"),
)  # one that runs a scene
def test_eval_scenes_on_any_arguments_runs_or_says_one_line_and_exits_2(split, seed, scenes, folders):
    # A negative seed (numpy's "expected non-negative integer"), and --out or --cache naming a
    # file (FileExistsError, --out only after the whole run) ended in tracebacks.
    import tempfile
    from pathlib import Path

    found = {
        "--cmu": shared_path("data", "cmu"),
        "--h36m": shared_path("data", "h36m"),
        "--yolo": shared_path("models", "yolo11n-pose.onnx"),
    }
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "file").write_text("not a folder, not a model")
        argv = ["eval", "scenes", "--quick", "--split", split, "--seed", seed, "--scenes", scenes]
        for option, kind in folders.items():
            place = {"missing": f"{tmp}/missing", "a file": f"{tmp}/file"}.get(kind)
            argv += [option, str(place or found.get(option) or f"{tmp}/{option[2:]}")]
        code, _, err = run_cli(argv)
        written = (Path(argv[argv.index("--out") + 1]) / "report.md").is_file()
    assert code in (0, 2), err
    assert "Traceback" not in err
    assert written == (code == 0)  # a run writes its report; a refusal says why, in one line
    if code == 2:  # (or argparse's usage and its one line of error)
        lines = err.strip().splitlines()
        assert len(lines) == 1 or (lines[0].startswith("usage:") and "error:" in lines[-1]), err


@settings(max_examples=20, deadline=None, derandomize=True)
@given(
    clip=st.sampled_from(["test_walking_1", "train_walking_9", "", "FILE", "MISSING"]),
    model=st.sampled_from([None, "FILE", "MISSING"]),
    horizons=st.one_of(
        st.sampled_from(["0.4", "0.4,1", "0", "-1", "nan", "inf", "1e9", ",", ""]),
        st.text(alphabet="0123456789.,-e naif", max_size=8),
    ),
    out=st.sampled_from(["fresh", "FILE"]),
)
@example(clip="test_walking_1", model=None, horizons="0.4,1", out="fresh")  # one that runs
def test_demo_on_any_arguments_runs_or_says_one_line_and_exits_2(clip, model, horizons, out):
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "FILE").write_text("neither a clip, a model nor a folder")
        place = {"FILE": f"{tmp}/FILE", "MISSING": f"{tmp}/missing", "fresh": f"{tmp}/out"}
        argv = ["demo", "--clip", place.get(clip, clip), "--horizons", horizons, "--out", place[out]]
        if model is not None:
            argv += ["--model", place[model]]
        code, _, err = run_cli(argv)
        written = (Path(place[out]) / "frames.jsonl").is_file()
    assert code in (0, 2), err
    assert "Traceback" not in err
    assert written == (code == 0)
    if code == 2:
        lines = err.strip().splitlines()
        assert len(lines) == 1 or (lines[0].startswith("usage:") and "error:" in lines[-1]), err
