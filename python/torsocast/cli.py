"""Command line: ``torsocast demo``, ``run``, ``bench``, ``forecast`` and ``eval``."""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections.abc import Callable
from contextlib import nullcontext
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import COMPONENTS, MAX_DEGREE, Forecaster, ForecasterConfig, TorsocastError, __version__, wrap_angle
from ._core import MAX_HORIZON

if TYPE_CHECKING:
    from .pipeline import FrameResult

#: Bounds on the sizes a caller gives (the batch timing's windows hold 2 KB each; a scene takes
#: seconds to render).
MAX_WINDOWS = 100_000
MAX_SCENES = 10_000


def _bench(args: argparse.Namespace) -> int:
    from .bench import CROWDS, crowd_frames, frame_cost, frame_report, measure, report

    if not 1 <= args.windows <= MAX_WINDOWS:
        expected = f"expected a positive number of windows up to {MAX_WINDOWS}"
        print(f"--windows: {expected}, got {args.windows}", file=sys.stderr)
        return 2
    print(f"torsocast {__version__}: forecast latency on this machine ({args.windows} windows for the batch)")
    print(report(measure(args.windows)))
    print(
        "\nOne frame outside the keypoint model (depth lookup, tracking, every person's chain, forecasts "
        "and intervals 0.4 and 1 s ahead), synthetic people on a 640x480 depth image fresh each frame, "
        "median of 200 frames:"
    )
    print(frame_report([(n, *frame_cost(crowd_frames(n))) for n in CROWDS]))
    return 0


def _forecast(args: argparse.Namespace) -> int:
    """Reads `t,x,y,z,azimuth,elevation[,weight]` rows (one track) and writes one JSON object per row
    with the forecasts at the requested horizons."""
    horizons = _horizons(args.horizons, positive=False)
    if horizons is None:
        return 2
    spline = {"degree": args.degree, "filter": args.filter} if args.method == "filter_spline" else {}
    config = ForecasterConfig(args.method, rate_hz=args.rate, history=args.history, **spline)
    forecaster = Forecaster(config)
    try:
        # utf-8-sig: a byte-order mark is not part of the first row.
        source = sys.stdin if args.input == "-" else open(args.input, encoding="utf-8-sig")  # noqa: SIM115
    except OSError as e:
        print(f"torsocast forecast: {e}", file=sys.stderr)
        return 2
    rows = 0
    with source:
        try:
            for line_no, line in enumerate(source, 1):
                fields = line.strip().lstrip("\ufeff").split(",")
                if not line.strip() or line.startswith("#") or not _is_number(fields[0]):
                    continue
                if len(fields) not in (6, 7) or not all(map(_is_number, fields)):
                    print(f"line {line_no}: expected 6 or 7 comma-separated numbers", file=sys.stderr)
                    return 2
                rows += 1
                row = np.array(fields, dtype=float)
                try:
                    report = forecaster.update(row[1:6], row[0], row[6] if len(row) == 7 else 1.0)
                except TorsocastError as e:
                    print(f"line {line_no}: skipped: {e}", file=sys.stderr)
                    continue
                out: dict[str, object] = {"t": row[0], "filled": report[0], "restarted": report[1]}
                if len(forecaster) >= forecaster.min_samples:
                    pred = forecaster.forecast(horizons)
                    pred[:, 3] = wrap_angle(pred[:, 3])
                    out["forecast"] = {
                        f"{h:g}": dict(zip(COMPONENTS, map(float, p))) for h, p in zip(horizons, pred)
                    }
                print(json.dumps(out, allow_nan=False))
        except UnicodeDecodeError as e:
            print(f"torsocast forecast: {args.input} is not UTF-8 text ({e.reason})", file=sys.stderr)
            return 2
    if rows == 0:
        print(
            f"torsocast forecast: {args.input} has no rows of 6 or 7 comma-separated numbers "
            "(t,x,y,z,azimuth,elevation[,weight])",
            file=sys.stderr,
        )
        return 2
    return 0


#: Where ``torsocast eval h36m`` looks when ``--data`` is not given.
H36M_ENV = "TORSOCAST_H36M"


def _h36m_files(args: argparse.Namespace) -> tuple[str, list[int], int] | None:
    """The data folder, the subjects and how many of their files are there; None (said) if any
    is missing or malformed."""
    from .datasets import h36m

    data = args.data or os.environ.get(H36M_ENV)
    if data is None:
        print(f"no Human3.6M data: pass --data DIR or set {H36M_ENV}", file=sys.stderr)
        return None
    try:
        subjects = [int(s) for s in args.subjects.split(",") if s.strip()]
    except ValueError:
        subjects = []
    if not subjects or any(s < 1 for s in subjects):
        print(
            f"--subjects: expected comma-separated subject numbers (5 for S5), got {args.subjects!r}",
            file=sys.stderr,
        )
        return None
    files = sum(len(h36m.available(data, s)) for s in subjects)
    if files == 0:
        print(
            f"{data}: no Human3.6M files for subjects {subjects} (expected S<n>/<action>_<1|2>.txt)",
            file=sys.stderr,
        )
        return None
    return data, subjects, files


def _eval_h36m(args: argparse.Namespace) -> int:
    from .evaluation import hmp, report
    from .evaluation.h36m import evaluate
    from .evaluation.methods import method_configs
    from .progress import Progress

    found = _h36m_files(args)
    if found is None:
        return 2
    data, subjects, files = found
    model = None
    if args.hmp is not None:
        try:
            model = hmp.Model.load(args.hmp)
        except ValueError as e:
            print(f"--hmp: {e}", file=sys.stderr)
            return 2
    if _out_folder(args.out) is None:
        return 2
    methods = method_configs()
    progress = Progress(files + len(methods) + (model is not None), f"eval h36m ({args.protocol})")
    try:
        result = evaluate(data, subjects, args.protocol, args.every, methods, progress, hmp_model=model)
    except (FileNotFoundError, ValueError) as e:
        print(f"torsocast eval h36m: {e}", file=sys.stderr)
        return 2
    for line in result["left_out"]:
        print(f"left out {line}", file=sys.stderr)
    print(report.markdown(result))
    draw = _can_draw()
    written = report.write(result, args.out, draw=draw)
    print(f"wrote {', '.join(str(p) for p in written)}", file=sys.stderr)
    return 0


def _eval_train_hmp(args: argparse.Namespace) -> int:
    from .datasets import h36m
    from .evaluation import hmp
    from .progress import Progress

    found = _h36m_files(args)
    if found is None:
        return 2
    data, subjects, _ = found
    try:
        settings = hmp.Training(units=args.units, iterations=args.iterations, seed=args.seed)
    except ValueError as e:
        print(f"torsocast eval train-hmp: {e}", file=sys.stderr)
        return 2
    out = Path(args.out)
    if not out.parent.is_dir():
        print(f"--out: {out.parent} is not a folder", file=sys.stderr)
        return 2
    resume = None
    if args.resume:
        if not out.is_file():
            print(f"--resume: {out} does not exist: there is no run to train on", file=sys.stderr)
            return 2
        try:
            resume = hmp.Model.load(out)
        except (OSError, ValueError) as e:
            print(f"--resume: {e}", file=sys.stderr)
            return 2
    takes = [(a, h36m.read_frames(data, s, a, sub)) for s in subjects for a, sub in h36m.available(data, s)]
    done = 0 if resume is None else resume.iterations
    progress = Progress(max(settings.iterations - done, 0) // 100, f"eval train-hmp ({settings.units} units)")
    try:
        model = hmp.train(
            takes,
            h36m.ACTIONS,
            subjects,
            settings,
            lambda i, loss: progress(f"loss {loss:.4f}"),
            lambda so_far: so_far.save(out),  # stopped early, the file holds the steps done
            resume,
        )
    except ValueError as e:
        print(f"torsocast eval train-hmp: {e}", file=sys.stderr)
        return 2
    model.save(out)
    trained_on = ", ".join(f"S{s}" for s in subjects)
    loss = model.losses[-100:].mean()
    resumed = "" if resume is None else f", resumed at step {resume.iterations}"
    print(f"wrote {out} (trained on {trained_on}{resumed}; mean loss over the last 100 steps {loss:.4f})")
    return 0


def _eval_scenes(args: argparse.Namespace) -> int:
    from .evaluation.scenes import report
    from .evaluation.scenes.faults import Faults
    from .evaluation.scenes.oracle import Oracle
    from .evaluation.scenes.plan import CMU_ENV, FULL, QUICK, Catalogue, data_folder
    from .evaluation.scenes.run import YOLO_ENV, Models, evaluate

    cmu_root = data_folder(args.cmu, CMU_ENV)
    h36m_root = data_folder(args.h36m, H36M_ENV)
    yolo = args.yolo or os.environ.get(YOLO_ENV)
    size = QUICK if args.quick else FULL
    if args.scenes is not None:
        if not 1 <= args.scenes <= MAX_SCENES:
            expected = f"expected a positive number up to {MAX_SCENES}"
            print(f"--scenes: {expected}, got {args.scenes}", file=sys.stderr)
            return 2
        size = size.scaled(args.scenes)
    if args.seed < 0:
        print(f"--seed: expected a number >= 0, got {args.seed}", file=sys.stderr)
        return 2
    # Said now, not after the whole run.
    if _out_folder(args.out) is None or (args.cache and _out_folder(args.cache, "--cache") is None):
        return 2
    try:
        oracle = Oracle.parse(args.oracle_labels, args.oracle_joints, args.oracle_pixels)
        faults = Faults(args.drop, args.stall, args.jitter, args.pose_lag, args.pose_noise)
        catalogue = Catalogue.find(args.split, cmu_root, h36m_root)
        models = Models.open(yolo)
    except (FileNotFoundError, ValueError, RuntimeError) as e:
        print(f"torsocast eval scenes: {e}", file=sys.stderr)
        return 2
    cache = Path(args.cache) if args.cache else None
    draw = not args.no_figures and _can_draw()
    try:
        bench = evaluate(
            catalogue,
            models,
            args.seed,
            args.quick,
            size,
            cache=cache,
            oracle=oracle,
            picture=draw,
            faults=faults,
            robot=args.robot,
        )
    except ValueError as e:
        print(f"torsocast eval scenes: {e}", file=sys.stderr)
        return 2
    text, written = report.write(bench, args.out, draw=draw)
    print(text)
    print(f"wrote {', '.join(str(p) for p in written)}", file=sys.stderr)
    return 0


def _eval_compare(args: argparse.Namespace) -> int:
    from .evaluation.scenes.compare import (
        common,
        compare,
        compare_coverage,
        compare_forecasts,
        compare_unseen,
        coverage_markdown,
        forecasts_markdown,
        markdown,
        pool,
        read,
        read_forecasts,
        read_unseen,
        unseen_markdown,
        within,
    )

    pairs = [(args.before, args.after), *(args.also or [])]
    try:
        runs = [(read(before), read(after)) for before, after in pairs]
        if args.common:
            runs = [common(*run) for run in runs]
        recovered = [pool([run[k] for run in runs]) for k in (0, 1)]
        result = compare(*recovered)
        # Forecasts are compared where every run recorded them.
        found = [[f for pair in pairs if (f := read_forecasts(pair[k])) is not None] for k in (0, 1)]
        whole = all(len(side) == len(pairs) for side in found)
        scenes = recovered[0]["scene"]
        if args.common:
            found = [[within(f, scenes) for f in side] for side in found]
        cells = compare_forecasts(pool(found[0]), pool(found[1]), scenes) if whole else None
        coverage = compare_coverage(list(zip(found[0], found[1]))) if whole else None
        # So are the tracks kept unseen.
        kept = [[u for pair in pairs if (u := read_unseen(pair[k])) is not None] for k in (0, 1)]
        if args.common:
            kept = [[within(u, scenes) for u in side] for side in kept]
        every = all(len(side) == len(pairs) for side in kept)
        unseen = compare_unseen(pool(kept[0]), pool(kept[1]), scenes) if every else None
    except (OSError, ValueError, KeyError) as e:
        print(f"torsocast eval compare: {e}", file=sys.stderr)
        return 2
    print(markdown(result))
    if cells is not None:
        print("\n" + forecasts_markdown(cells))
    if coverage is not None:
        print("\n" + coverage_markdown(coverage))
    if unseen:
        print("\n" + unseen_markdown(unseen))
    return 0


def _run(args: argparse.Namespace) -> int:
    from .keypoints import open_model
    from .run import run
    from .sources import BagTopics, open_source, world_frame_of

    horizons = _horizons(args.horizons)
    if horizons is None:
        return 2
    if not (np.isfinite(args.fps) and args.fps > 0):
        print(f"--fps: expected a positive, finite frame rate, got {args.fps}", file=sys.stderr)
        return 2
    if _out_folder(args.out) is None:
        return 2
    try:
        topics = BagTopics(args.color_topic, args.depth_topic, args.info_topic, args.world_frame)
        source = open_source(args.source, fps=args.fps, bag=topics)
        model = open_model(args.model, args.family, args.device)
    except (FileNotFoundError, ValueError, ImportError, RuntimeError) as e:
        print(f"torsocast run: {e}", file=sys.stderr)
        return 2
    from .topdown import TopDown

    plot = TopDown()
    observers: list[Callable[[FrameResult], None]] = [plot] if args.plot else []
    bag = None
    if args.bag:
        from .rosout import BodyBag

        try:
            bag = BodyBag(Path(args.out) / "bodies", horizons, world_frame_of(source), replace=True)
        except (ImportError, FileExistsError) as e:
            print(f"torsocast run: {e}", file=sys.stderr)
            return 2
    with bag or nullcontext():
        summary = run(
            source,
            model,
            args.out,
            horizons,
            args.overlay,
            observers=[*observers, *([bag] if bag else [])],
            video=args.video,
        )
    print(summary)
    written = [summary.out / "frames.jsonl"]
    if bag:
        written.append(bag.path)
    if args.overlay:
        written.append(summary.out / "overlay")
    if args.video:
        written.append(summary.out / "overlay.avi")
    if args.plot:
        written.append(summary.out / "topdown.png")
        plot.draw().save(written[-1])
    print(f"wrote {', '.join(map(str, written))}")
    return 0


def _demo(args: argparse.Namespace) -> int:
    from .datasets.cmu import bundled_clips
    from .demo import demo

    horizons = _horizons(args.horizons)
    if horizons is None or _out_folder(args.out) is None:
        return 2
    try:
        result = demo(args.out, args.clip, horizons, args.model, args.overlay, video=args.video)
    except (FileNotFoundError, ValueError) as e:
        print(f"torsocast demo: {e} (bundled clips: {', '.join(bundled_clips())})", file=sys.stderr)
        return 2
    print(result)
    return 0


def _can_draw() -> bool:
    """Whether the evaluations can draw their figures (matplotlib is an optional extra)."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        print("figures skipped: matplotlib is not installed (pip install 'torsocast[eval]')", file=sys.stderr)
        return False
    return True


def _horizons(text: str, positive: bool = True) -> list[float] | None:
    """The ``--horizons`` list, or None after saying what is wrong with it: seconds above 0
    (``positive``) or at least 0, up to the core's ``MAX_HORIZON``."""
    try:
        horizons = [float(h) for h in text.split(",") if h]
    except ValueError:
        print(f"--horizons: expected comma-separated seconds, got {text!r}", file=sys.stderr)
        return None
    if any(not ((h > 0 if positive else h >= 0) and h <= MAX_HORIZON) for h in horizons):
        bound = "> 0" if positive else ">= 0"
        print(f"--horizons: expected seconds {bound} and <= {MAX_HORIZON:g}, got {text!r}", file=sys.stderr)
        return None
    return horizons


def _out_folder(path: str, option: str = "--out") -> Path | None:
    """The folder ``option`` names, made if missing, or None after saying why it cannot be."""
    out = Path(path)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        print(f"{option}: cannot use {out} as the output folder: {e.strerror or e}", file=sys.stderr)
        return None
    return out


def _is_number(text: str) -> bool:
    try:
        float(text)
        return True
    except ValueError:
        return False


def main(argv: list[str] | None = None) -> int:
    from .pipeline import HORIZONS

    RUN_HORIZONS = ",".join(f"{h:g}" for h in HORIZONS)  # noqa: N806 (a constant of this parser)
    parser = argparse.ArgumentParser(prog="torsocast", description=__doc__)
    parser.add_argument("--version", action="version", version=__version__)
    sub = parser.add_subparsers(dest="command", required=True)
    dm = sub.add_parser(
        "demo",
        help="the main job on a bundled mocap walk seen by a virtual RGB-D camera, against ground truth",
    )
    dm.add_argument("--clip", default="test_walking_1", help="bundled CMU walking clip, or a CMU clip file")
    dm.add_argument("--model", help="ONNX keypoint model (default: the bundled MoveNet Lightning)")
    dm.add_argument("--horizons", default=RUN_HORIZONS, help="forecast horizons, seconds, comma-separated")
    dm.add_argument("--out", default="demo", help="folder for frames.jsonl and demo.png")
    dm.add_argument("--overlay", action="store_true", help="also draw every frame's result as a JPEG")
    dm.add_argument("--video", action="store_true", help="also write those pictures as overlay.avi")
    dm.set_defaults(run=_demo)
    rn = sub.add_parser("run", help="track and forecast every person in an RGB-D source")
    rn.add_argument(
        "source", help="folder (TUM or NNNN_camera.xml layout), .npz recording, ROS bag, or video"
    )
    rn.add_argument("--model", help="ONNX keypoint model (default: the bundled MoveNet Lightning)")
    rn.add_argument("--family", choices=["yolo-pose", "movenet"], help="model family (default: recognised)")
    rn.add_argument("--device", default="cpu", choices=["cpu", "cuda"])
    rn.add_argument("--horizons", default=RUN_HORIZONS, help="forecast horizons, seconds, comma-separated")
    rn.add_argument("--fps", type=float, default=30.0, help="frame rate of sources without time stamps")
    rn.add_argument("--out", default="out", help="folder for frames.jsonl and overlay/")
    rn.add_argument("--overlay", action="store_true", help="also draw every frame's result as a JPEG")
    rn.add_argument("--video", action="store_true", help="also write those pictures as overlay.avi (MJPEG)")
    rn.add_argument("--plot", action="store_true", help="also draw the tracks from above (topdown.png)")
    rn.add_argument(
        "--bag",
        action="store_true",
        help="also write the body frames as a ROS 2 bag (bodies/: /tf, REP-155 ids)",
    )
    bag = rn.add_argument_group("ROS bags", "needed only where the bag has more than one candidate")
    bag.add_argument("--color-topic", help="colour images (sensor_msgs/Image or CompressedImage)")
    bag.add_argument("--depth-topic", help="depth images registered to the colour images (16UC1 mm, 32FC1 m)")
    bag.add_argument("--info-topic", help="the colour camera's sensor_msgs/CameraInfo")
    bag.add_argument(
        "--world-frame", help="fixed frame to place the camera in (default: odom, else the tf root)"
    )
    rn.set_defaults(run=_run)
    bench = sub.add_parser(
        "bench",
        help="measure the latency of every forecaster and of a frame outside the keypoint model here",
    )
    bench.add_argument("--windows", type=int, default=2000, help="windows in the batch timing")
    bench.set_defaults(run=_bench)
    fc = sub.add_parser("forecast", help="forecast a torso pose track read as CSV (t,x,y,z,az,el[,w])")
    fc.add_argument("input", help="CSV file, or - for standard input")
    fc.add_argument("--horizons", default="0.4,1.0,2.0", help="seconds ahead, comma-separated")
    # Defaults and choices are the core's (ForecasterConfig), never written here.
    default, options = ForecasterConfig(), ForecasterConfig.options()
    fc.add_argument("--method", default=default.method, choices=options["method"])
    fc.add_argument(
        "--degree",
        type=int,
        default=default.degree,
        choices=range(MAX_DEGREE + 1),
        help=f"spline degree N (0 to {MAX_DEGREE}; filter_spline only)",
    )
    fc.add_argument(
        "--filter", default=default.filter, choices=options["filter"], help="low-pass (filter_spline only)"
    )
    fc.add_argument("--rate", type=float, default=default.rate_hz, help="forecaster grid rate (Hz)")
    fc.add_argument("--history", type=float, default=default.history, help="history length (s)")
    ev = sub.add_parser("eval", help="forecasting evaluation on a dataset")
    ev_sub = ev.add_subparsers(dest="dataset", required=True)
    h36 = ev_sub.add_parser("h36m", help="Human3.6M exponential-map files (research-only licence)")
    h36.add_argument("--data", help=f"folder with S1/, S5/... (default: ${H36M_ENV})")
    h36.add_argument(
        "--subjects", default="5", help="comma-separated subject numbers (5 is the test subject)"
    )
    h36.add_argument("--protocol", default="dense", choices=["seeds", "dense"])
    h36.add_argument("--every", type=int, default=10, help="dense protocol: a window every N samples")
    h36.add_argument("--out", default="eval_h36m", help="folder for report.md/.json/.csv and the figures")
    h36.add_argument(
        "--hmp", metavar="MODEL", help="an HMP model from 'torsocast eval train-hmp', run as one more method"
    )
    h36.set_defaults(run=_eval_h36m)
    from .evaluation.hmp import Training

    hmp_defaults = Training()
    th = ev_sub.add_parser(
        "train-hmp", help="train the thesis' learned baseline (Martinez et al.'s GRU) on Human3.6M subjects"
    )
    th.add_argument("--data", help=f"folder with S1/... (default: ${H36M_ENV})")
    th.add_argument(
        "--subjects", default="1", help="comma-separated training subjects (never 5, the test subject)"
    )
    th.add_argument("--units", type=int, default=hmp_defaults.units, help="GRU units (the paper's 1024)")
    th.add_argument(
        "--iterations", type=int, default=hmp_defaults.iterations, help="training steps of 16 windows"
    )
    th.add_argument("--seed", type=int, default=hmp_defaults.seed)
    th.add_argument(
        "--out", default="hmp.npz", help="where to write the model (keep it out of the repository)"
    )
    th.add_argument(
        "--resume",
        action="store_true",
        help="train on the model in --out (a run stopped early: its last checkpoint) up to --iterations, "
        "with the settings and data it was trained with",
    )
    th.set_defaults(run=_eval_train_hmp)
    sc = ev_sub.add_parser(
        "scenes", help="rendered RGB-D scenes of 1 to 6 people through the real pipeline, against the truth"
    )
    sc.add_argument(
        "--split", default="dev", choices=["dev", "report"], help="dev to tune on, report to publish"
    )
    sc.add_argument("--quick", action="store_true", help="a few short scenes (under 3 minutes on 2 cores)")
    sc.add_argument(
        "--seed", type=int, default=0, help="draws the scenes: the same seed gives the same report"
    )
    sc.add_argument(
        "--scenes",
        type=int,
        help="number of scenes (default: 8 with --quick, else 100), and the other kinds in proportion",
    )
    sc.add_argument(
        "--out", default="eval_scenes", help="folder for report.md/.json, the records and figures"
    )
    sc.add_argument(
        "--cmu",
        help="CMU mocap folder with train/ and test/ (default: $TORSOCAST_CMU)",
    )
    sc.add_argument("--h36m", help=f"Human3.6M folder with S1/ and S5/ (default: ${H36M_ENV})")
    sc.add_argument(
        "--yolo",
        help="YOLO-pose ONNX model for scenes of several people (default: $TORSOCAST_YOLO)",
    )
    sc.add_argument(
        "--cache",
        help="keep each scene's detections here and replay them on later runs (for changes after the model)",
    )
    sc.add_argument(
        "--no-figures",
        action="store_true",
        help="write the report and records without the figures (a replay of a --cache then renders "
        "no frame at all: the report's picture is the one frame a replay would render)",
    )
    sc.add_argument(
        "--oracle-labels",
        action="store_true",
        help="replay the --cache with the detector's left/right labels put right by the truth: "
        "how far any cue to the labels could take the flips (a bound, not a result)",
    )
    sc.add_argument(
        "--oracle-joints",
        metavar="GROUPS",
        help="replay the --cache with the seen joints of GROUPS (comma-separated: shoulders, hips, "
        "legs) put at the truth's 3D positions: which measurements the flips come from (a "
        "diagnostic, not a result)",
    )
    sc.add_argument(
        "--oracle-pixels",
        metavar="GROUPS",
        help="replay the --cache with the seen joints of GROUPS put at their true pixels and "
        "lifted there from the depth image rendered again: the flips a perfect 2D model would "
        "leave (a diagnostic, not a result; every frame is rendered again, so it takes minutes "
        "where a replay takes seconds)",
    )
    sc.add_argument(
        "--drop",
        type=float,
        default=0.0,
        metavar="FRACTION",
        help="replay the --cache with this share of each scene's frames never given to the tracker, "
        "dropped in bursts of two frames on average (a busy computer, a lost packet)",
    )
    sc.add_argument(
        "--stall",
        type=float,
        default=0.0,
        metavar="SECONDS",
        help="replay the --cache with the camera sending nothing for this long, once in each scene",
    )
    sc.add_argument(
        "--jitter",
        type=float,
        default=0.0,
        metavar="SECONDS",
        help="replay the --cache with each frame stamped up to this far either side of when it was "
        "taken (under half a frame's interval)",
    )
    sc.add_argument(
        "--pose-lag",
        type=float,
        default=0.0,
        metavar="SECONDS",
        help="replay the --cache (of --robot scenes) with the camera's pose told from this long "
        "before each frame was taken (a localisation that lags the image)",
    )
    sc.add_argument(
        "--pose-noise",
        type=float,
        default=0.0,
        metavar="DEGREES",
        help="replay the --cache with the camera's pose told turned about its vertical by an error "
        "of this standard deviation, drawn for every frame (a localiser's heading that wavers)",
    )
    sc.add_argument(
        "--robot",
        action="store_true",
        help="see every scene from a camera on a robot that drives past the people and pans, its "
        "pose told to the pipeline (the same people as without; rendered and recorded apart)",
    )
    sc.set_defaults(run=_eval_scenes)
    cp = ev_sub.add_parser(
        "compare",
        help="two runs of eval scenes on the same scenes: changes in flips, forecast errors and intervals",
    )
    cp.add_argument("before", help="the --out folder of the first run")
    cp.add_argument("after", help="the --out folder of the second run")
    cp.add_argument(
        "--also",
        nargs=2,
        action="append",
        metavar=("BEFORE", "AFTER"),
        help="a further pair of runs on other scenes (another --seed), pooled with the first; repeatable",
    )
    cp.add_argument(
        "--common",
        action="store_true",
        help="compare the flips on the person-frames both runs hold (a replay with --drop or --stall "
        "against one without); without it, runs of different frames are refused",
    )
    cp.set_defaults(run=_eval_compare)
    fc.set_defaults(run=_forecast)
    args = parser.parse_args(argv)
    try:
        return int(args.run(args))
    except TorsocastError as e:
        print(f"torsocast: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
