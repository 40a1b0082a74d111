"""Soak benchmark: one million frames of up to 20 people appearing, walking and leaving, through
the Python API (``Tracker.update`` with forecasts and intervals at 0.4 and 1 s, one call per
frame, 30 frames per second of stream time). Prints the process's resident memory after warm-up
and at the end (and every 100 000 frames), and the latency of the call: median, 99th
percentile, maximum.

    python benches/soak.py [--frames 1000000] [--seed 0]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import torsocast as tc

SLOTS = 20
FPS = 30.0
PAGE = 4096


def resident_mib() -> float:
    """Resident memory of this process (MiB), from /proc."""
    pages = int(Path("/proc/self/statm").read_text().split()[1])
    return pages * PAGE / 2**20


def template() -> np.ndarray:
    """17 COCO joints of an upright person facing +x, relative to the torso centre."""
    side = np.where(np.arange(17) % 2 == 1, 0.18, -0.18)
    side[0] = 0.0
    joints = np.zeros((17, 3))
    joints[:, 1] = side
    joints[:, 2] = 0.7 - 0.1 * np.arange(17)
    return joints


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--frames", type=int, default=1_000_000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    rng = np.random.default_rng(args.seed)
    body = template()
    tracker = tc.Tracker()
    # Each slot is a lane 1.5 m wide: a person walks along it for 2 to 20 s, then the lane is
    # empty for 0.5 to 5 s, and a new person starts.
    present = np.zeros(SLOTS, dtype=bool)
    until = rng.uniform(0.0, 3.0, SLOTS)
    start = np.zeros((SLOTS, 3))
    velocity = np.zeros((SLOTS, 3))
    since = np.zeros(SLOTS)
    # Written through now, so that its pages count in the first memory figure, not as growth.
    latency = np.full(args.frames, np.nan, dtype=np.float32)
    horizons = [0.4, 1.0]
    births, warm_up = 0, 3000
    rss_start = 0.0
    for k in range(args.frames):
        t = k / FPS
        ended = t >= until
        for s in np.flatnonzero(ended):
            present[s] = not present[s]
            if present[s]:
                births += 1
                start[s] = [rng.uniform(2.0, 8.0), -15.0 + 1.5 * s, 1.0]
                velocity[s] = [rng.uniform(-1.0, 1.0), 0.0, 0.0]
                since[s] = t
                until[s] = t + rng.uniform(2.0, 20.0)
            else:
                until[s] = t + rng.uniform(0.5, 5.0)
        here = np.flatnonzero(present)
        centres = start[here] + velocity[here] * (t - since[here])[:, None]
        joints = body[None] + centres[:, None, :] + rng.normal(0.0, 0.01, (len(here), 17, 3))
        scores = np.full((len(here), 17), 0.9)
        began = time.perf_counter()
        tracker.update(t, joints, scores, (0.0, 0.0, 1.0), horizons)
        latency[k] = time.perf_counter() - began
        if k == warm_up:
            rss_start = resident_mib()
        if k > 0 and k % 100_000 == 0:
            print(f"frame {k}: resident {resident_mib():.1f} MiB, {len(tracker)} live tracks", flush=True)
    rss_end = resident_mib()
    measured = latency[warm_up:] * 1e6
    print(
        f"\n{args.frames} frames ({args.frames / FPS / 3600:.1f} h of stream at {FPS:g} fps), {births} people"
    )
    print(f"resident memory after {warm_up} frames: {rss_start:.1f} MiB; at the end: {rss_end:.1f} MiB")
    print(
        f"Tracker.update latency (µs): median {np.median(measured):.1f}, "
        f"p99 {np.percentile(measured, 99):.1f}, max {measured.max():.1f}"
    )


if __name__ == "__main__":
    main()
