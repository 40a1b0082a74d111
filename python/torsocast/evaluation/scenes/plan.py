"""Which scenes the benchmark renders: the motions of each split and the random draw of scenes.

The development split uses Human3.6M S1 and the CMU train clips; the report split Human3.6M S5
and the CMU test walk (the CMU test clips of the other actions are kept back as unseen data and
never read). A scene draws, from its own seed: a sensor, a frame rate, the camera's height and
tilt, and one to six people, each a clip of a motion category drawn uniformly, turned to any
heading and placed 1 to 6 m from the camera inside its field of view, never nearer than
:data:`MIN_SEPARATION` to another person at the same instant. After these come a few scenes of
one to three people turning on the spot at a steady rate (the case of a steady turn, where a
heading forecast has a real trend to continue), then as many of people who turn on the spot and
stop, again and again (as people turn to look at something: a trend that ends), then as many of
walkers who stop and walk on (as people walk up to something, or to the robot: a walk that ends),
then as many of a person who turns round while a walker stands between them and the camera (as
people turn while someone passing hides them: a track that must take its person up again turned).
Any of these scenes can be seen from a robot that drives past the people instead
(:func:`on_robot`): the same people, the camera moving.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path

import numpy as np

from ...datasets import cmu, h36m
from ...synthetic.mannequin import random_outfit
from ...synthetic.motions import Motion, cmu_motion, h36m_category, h36m_motion
from ...synthetic.scenes import Actor, RobotPath, SceneSpec
from ...synthetic.sensor import SENSORS

SPLITS = ("dev", "report")
#: CMU folder and actions, Human3.6M subjects, of each split.
CMU_SPLITS = {
    "dev": ("train", ("basketball", "jumping", "running", "soccer", "walking")),
    "report": ("test", ("walking",)),
}
H36M_SUBJECTS = {"dev": 1, "report": 5}

FRAME_RATES = (10.0, 15.0, 30.0)
HEIGHT_M = (0.4, 1.6)
TILT_DEG = (-25.0, 10.0)
DISTANCE_M = (1.0, 6.0)
#: Closest two people's pelvises may come (m): nearer, their bodies would pass through each other.
MIN_SEPARATION = 0.7
#: Share of scenes with one person (the bundled single-person model's case).
SINGLE_SHARE = 1 / 3
MAX_PEOPLE = 6


#: Turning scenes: one to three people, each turning on the spot at a steady rate drawn from this
#: range (deg/s, either way) while acting out a clip of these categories (people who stay roughly
#: in place); the real turntable sequence turns at about 107 deg/s.
TURN_RATE_DEG = (30.0, 120.0)
TURNING_PEOPLE = 3
TURNING_MOTIONS = ("h36m constrained", "h36m high variance")
#: Scenes of people who turn and stop (the same people and clips as the turning scenes): each
#: turn through an angle drawn from this range (deg, either way) at a mean rate drawn from
#: :data:`TURN_RATE_DEG`, from rest to rest; between turns the person stands for a time drawn
#: from :data:`STOP_S` (s). The first turn starts at a time drawn from :data:`FIRST_TURN_S` (s,
#: scene time: some people are mid-turn when the scene starts).
TURN_ANGLE_DEG = (45.0, 180.0)
STOP_S = (0.5, 3.0)
FIRST_TURN_S = (-1.0, 2.0)
#: Scenes of walkers who stop and walk on: one to three people, each a clip of these categories
#: (people who walk), whose walk slows to rest over a ramp drawn from :data:`STOP_RAMP_S` (s; a
#: walker stops within a step or two), stands for a time drawn from :data:`STOP_S` and goes on
#: the same way; each stop comes after a walk of a time drawn from :data:`WALK_S` (s) and ends
#: with both feet on the ground (the clip's nearest frame where both ankles move slowest).
PAUSING_MOTIONS = ("cmu walking", "h36m pedestrian")
STOP_RAMP_S = (0.4, 0.8)
WALK_S = (0.5, 2.5)
#: Scenes of a person who turns while hidden: one person of :data:`TURNING_MOTIONS` stands at a
#: distance drawn from :data:`HIDDEN_DISTANCE_M` (m), and a walker of :data:`PAUSING_MOTIONS`
#: walks across the line of sight between them and the camera and stops on it (at a share of
#: that distance drawn from :data:`HIDER_SHARE`), at rest from a scene time drawn from
#: :data:`HIDE_AT_S` (s) for a time drawn from :data:`HIDDEN_STAND_S` (s). Halfway through
#: that stand the person is halfway through a turn round (an angle drawn from
#: :data:`HIDDEN_TURN_DEG`, either way, at a mean rate drawn from :data:`HIDDEN_TURN_RATE_DEG`:
#: deg, deg/s). The walker hides the person while slowing and walking off too: about one and a
#: half to three seconds in all, either side of how long a track is kept unseen.
HIDDEN_DISTANCE_M = (2.5, 6.0)
HIDER_SHARE = (0.4, 0.7)
HIDE_AT_S = (1.5, 2.5)
HIDDEN_STAND_S = (0.2, 1.4)
HIDDEN_TURN_DEG = (120.0, 180.0)
HIDDEN_TURN_RATE_DEG = (120.0, 240.0)
#: A robot driving past the people (:func:`on_robot`): at a speed drawn from :data:`ROBOT_SPEED`
#: (m/s, a service robot's pace near people), in a direction within :data:`ROBOT_ACROSS_DEG` of
#: across the static camera's line of sight (either way), panning its camera to and fro by an
#: amplitude drawn from :data:`ROBOT_PAN_DEG` (deg) over a period drawn from
#: :data:`ROBOT_PAN_PERIOD_S` (s). Over a 6 s scene it moves 1 to 4 m and sees every person from
#: views that change by tens of degrees while they stand still.
ROBOT_SPEED = (0.2, 0.6)
ROBOT_ACROSS_DEG = 45.0
ROBOT_PAN_DEG = (0.0, 20.0)
ROBOT_PAN_PERIOD_S = (4.0, 8.0)


@dataclass(frozen=True)
class Size:
    """How much a run renders: ``scenes`` of people as their clips move them, then ``turning``
    scenes of people turning on the spot, then ``stopping`` scenes of people who turn and stop,
    then ``pausing`` scenes of walkers who stop and walk on, then ``hiding`` scenes of a person
    who turns round while a walker hides them (each kind numbered after the ones before, so
    that adding it left them as they were)."""

    scenes: int
    duration: float
    """Seconds per scene."""
    turning: int = 0
    stopping: int = 0
    pausing: int = 0
    hiding: int = 0

    def scaled(self, scenes: int) -> Size:
        """``scenes`` scenes, with the other kinds in the same proportion."""
        share = scenes / self.scenes
        kinds = (round(n * share) for n in (self.turning, self.stopping, self.pausing, self.hiding))
        return Size(scenes, self.duration, *kinds)


FULL = Size(scenes=100, duration=6.0, turning=16, stopping=16, pausing=16, hiding=16)
#: No hiding scene: in 4 s the hidden person would barely be seen again.
QUICK = Size(scenes=8, duration=4.0, turning=1, stopping=1, pausing=1)

#: Where the data is looked for when no folder is given.
CMU_ENV, H36M_ENV = "TORSOCAST_CMU", "TORSOCAST_H36M"


def data_folder(given: str | Path | None, env: str) -> Path | None:
    """``given``, else the environment variable ``env``; None where neither is set."""
    folder = given or os.environ.get(env)
    return Path(folder) if folder is not None else None


@dataclass
class Catalogue:
    """The motions of one split by category, loaded when a scene first uses them."""

    split: str
    entries: dict[str, list[tuple[str, Callable[[], Motion]]]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    """What is missing or left out, for the report's first lines."""
    _loaded: dict[str, Motion] = field(default_factory=dict)

    @classmethod
    def find(cls, split: str, cmu_root: Path | None, h36m_root: Path | None) -> Catalogue:
        if split not in SPLITS:
            raise ValueError(f"split must be one of {SPLITS}, got {split!r}")
        out = cls(split)
        folder, actions = CMU_SPLITS[split]
        if cmu_root is None:
            out.notes.append(f"no CMU folder (--cmu or ${CMU_ENV}): CMU motions left out")
        else:
            for action in actions:
                files = sorted((cmu_root / folder / action).glob("*.txt"))
                if not files:
                    out.notes.append(f"{cmu_root / folder / action}: no clips")
                for path in files:
                    out.add(
                        f"cmu {action}",
                        f"cmu/{action}/{path.stem}",
                        partial(cmu_motion, path, action),
                    )
        subject = H36M_SUBJECTS[split]
        if h36m_root is None or not (pairs := h36m.available(h36m_root, subject)):
            out.notes.append(
                f"no Human3.6M S{subject} files (--h36m or ${H36M_ENV}): Human3.6M motions left out"
            )
        else:
            for action, sub in pairs:
                name = f"h36m/S{subject}/{action}_{sub}"
                load = partial(h36m_motion, h36m_root, subject, action, sub)
                out.add(f"h36m {h36m_category(action)}", name, load)
        if not out.entries:
            raise FileNotFoundError(f"no motions for the {split} split: " + "; ".join(out.notes))
        return out

    def add(self, category: str, name: str, load: Callable[[], Motion]) -> None:
        self.entries.setdefault(category, []).append((name, load))

    def motion(self, name: str) -> Motion:
        if name not in self._loaded:
            load = next(f for entries in self.entries.values() for n, f in entries if n == name)
            self._loaded[name] = load()
        return self._loaded[name]

    @property
    def motions(self) -> dict[str, Motion]:
        """The motions loaded so far, by name."""
        return dict(self._loaded)

    def draw(
        self,
        rng: np.random.Generator,
        avoid: frozenset[str] = frozenset(),
        categories: tuple[str, ...] | None = None,
    ) -> Motion:
        """A motion of a category drawn uniformly (so that rare categories are not drowned by
        the many Human3.6M files; among ``categories`` where the split has any of them), other
        than those in ``avoid`` where the category has others; a file that cannot be read is
        left out and noted."""
        while self.entries:
            names = sorted(self.entries)
            if categories is not None and any(c in self.entries for c in categories):
                names = [c for c in names if c in categories]
            category = names[int(rng.integers(len(names)))]
            entries = self.entries[category]
            fresh = [e for e in entries if e[0] not in avoid] or entries
            name, _ = fresh[int(rng.integers(len(fresh)))]
            try:
                return self.motion(name)
            except ValueError as e:  # e.g. a gravity estimate that fails its sanity check
                self.notes.append(f"{name} left out: {e}")
                entries[:] = [(n, f) for n, f in entries if n != name]
                if not entries:
                    del self.entries[category]
        raise FileNotFoundError(f"no readable motions for the {self.split} split")


def _pelvis_path(actor: Actor, motion: Motion, times: np.ndarray) -> np.ndarray:
    """The actor's pelvis on the floor at scene ``times``, NaN where it is not in the scene."""
    k = np.rint(actor.clip_time(times) * motion.rate_hz).astype(int)
    ok = (k >= 0) & (k < len(motion.joints))
    pelvis = actor.place(motion)[np.clip(k, 0, len(motion.joints) - 1), cmu.PELVIS, :2]
    return np.where(ok[:, None], pelvis, np.nan)


def _turn_rate(rng: np.random.Generator) -> float:
    return float(rng.choice([-1.0, 1.0]) * np.radians(rng.uniform(*TURN_RATE_DEG)))


def _bursts(rng: np.random.Generator, duration: float) -> tuple[tuple[float, float, float], ...]:
    """Turns and stops until ``duration``: (start, duration, angle) of each turn (s, s, rad)."""
    out = []
    start = rng.uniform(*FIRST_TURN_S)
    while start < duration:
        angle = float(rng.choice([-1.0, 1.0]) * np.radians(rng.uniform(*TURN_ANGLE_DEG)))
        length = abs(angle) / np.radians(rng.uniform(*TURN_RATE_DEG))
        out.append((float(start), float(length), angle))
        start += length + rng.uniform(*STOP_S)
    return tuple(out)


def _both_feet_down(motion: Motion) -> np.ndarray:
    """Per clip frame, the faster of the two ankles' speeds over the ground (m/s): where it is
    least, both feet are planted (a walker's double support), a pose a person stands in."""
    ankles = motion.joints[:, [cmu.LEFT_ANKLE, cmu.RIGHT_ANKLE], :2]
    speed = np.linalg.norm(np.gradient(ankles, 1.0 / motion.rate_hz, axis=0), axis=-1)
    return speed.max(axis=1)  # type: ignore[no-any-return]


def _rest_frame(feet: np.ndarray, k: int, window: int) -> int:
    """The clip frame within ``window`` frames of ``k`` where both ``feet`` (per frame, the faster
    ankle's speed: :func:`_both_feet_down`) move slowest."""
    return k + int(np.argmin(feet[k - window : k + window + 1])) - window


def _pauses(
    rng: np.random.Generator, motion: Motion, start: float, duration: float
) -> tuple[tuple[float, float, float], ...]:
    """Stops until ``duration`` of a walker whose clip starts ``start`` s in: (start, ramp,
    standing time) of each (s), each coming to rest on the clip frame within a quarter of a
    second of the drawn one where both feet move slowest."""
    window = int(round(0.25 * motion.rate_hz))
    if len(motion.joints) <= 2 * window:
        return ()  # too short a clip to stop in
    feet = _both_feet_down(motion)
    out: list[tuple[float, float, float]] = []
    # The first stop after a walk from when the person appears (a clip may start late).
    begin, lag = max(0.0, -start) + rng.uniform(*WALK_S), 0.0
    while begin < duration:
        ramp, hold = rng.uniform(*STOP_RAMP_S), rng.uniform(*STOP_S)
        # The clip time the walker comes to rest at: half the ramp after the slowing starts.
        k = int(round((start + begin - lag + ramp / 2) * motion.rate_hz))
        if not window <= k < len(feet) - window:
            break  # the clip ends (or has not started) there: walk on as recorded
        k = _rest_frame(feet, k, window)
        begin = k / motion.rate_hz - ramp / 2 - start + lag
        out.append((float(begin), float(ramp), float(hold)))
        lag += ramp + hold
        begin += 2 * ramp + hold + rng.uniform(*WALK_S)
    return tuple(out)


def _clip_timing(rng: np.random.Generator, motion: Motion, duration: float) -> tuple[float, float]:
    """Where a scene of ``duration`` s plays ``motion``: the clip time at the scene's start, drawn
    (a clip shorter than the scene starts at a random moment of it: the person appears), and the
    clip time the person is placed and turned at, the scene's middle (within the clip)."""
    spare = motion.duration - duration
    start = float(rng.uniform(0.0, spare) if spare >= 0 else -rng.uniform(0.0, -spare))
    return start, float(np.clip(start + duration / 2, 0.0, motion.duration))


def _separation_times(size: Size) -> np.ndarray:
    """The scene times (s) at which people are kept :data:`MIN_SEPARATION` apart."""
    return np.arange(0.0, size.duration + 1e-9, 0.1)


def _apart(paths: list[np.ndarray], path: np.ndarray) -> bool:
    """Whether a pelvis ``path`` keeps :data:`MIN_SEPARATION` from each of ``paths`` (NaN where
    the person is absent) at every instant."""
    with np.errstate(invalid="ignore"):
        near = [np.nanmin(np.linalg.norm(path - other, axis=1), initial=np.inf) for other in paths]
    return all(d >= MIN_SEPARATION for d in near)


def _walker_at_rest(
    rng: np.random.Generator, walker: Motion, rest_at: float
) -> tuple[float, float, float] | None:
    """Where a walker's clip comes to rest, ``rest_at`` s into the scene after a stop's ramp
    drawn from :data:`STOP_RAMP_S`: (the clip time it starts at, the clip time it rests at,
    the ramp; s), resting on a frame where both feet are planted with the walk before it in the
    clip; None where the clip is too short."""
    ramp = rng.uniform(*STOP_RAMP_S)
    window = int(round(0.25 * walker.rate_hz))
    feet = _both_feet_down(walker)
    # The ramp plays half its length of the clip: so much walk is seen before the rest.
    first = int(np.ceil((rest_at - ramp / 2) * walker.rate_hz)) + window
    if first >= len(feet) - window:
        return None
    k = _rest_frame(feet, int(rng.integers(first, len(feet) - window)), window)
    rest = k / walker.rate_hz
    return rest - rest_at + ramp / 2, rest, float(ramp)


def _heading_of_walk(walker: Motion, rest: float) -> float:
    """The direction (rad) the walker's pelvis moves over the floor in the clip's second around
    clip time ``rest``."""
    k = int(round(rest * walker.rate_hz))
    half = int(round(0.5 * walker.rate_hz))
    a, b = max(k - half, 0), min(k + half, len(walker.joints) - 1)
    d = walker.joints[b, cmu.PELVIS, :2] - walker.joints[a, cmu.PELVIS, :2]
    return float(np.arctan2(d[1], d[0]))


def _hiding_pair(catalogue: Catalogue, rng: np.random.Generator, size: Size, half_fov: float) -> list[Actor]:
    """A person who turns round while a walker stands between them and the camera, and that
    walker (:data:`HIDDEN_DISTANCE_M` and the constants after it); no pair where 30 draws could
    not keep them :data:`MIN_SEPARATION` apart."""
    times = _separation_times(size)
    for _attempt in range(30):
        bearing = rng.uniform(-0.6, 0.6) * half_fov
        ray = np.array([np.cos(bearing), np.sin(bearing)])
        distance = rng.uniform(*HIDDEN_DISTANCE_M)
        walker = catalogue.draw(rng, categories=PAUSING_MOTIONS)
        rest_at = rng.uniform(*HIDE_AT_S)
        resting = _walker_at_rest(rng, walker, rest_at)
        if resting is None:
            continue
        start, rest, ramp = resting
        stand = rng.uniform(*HIDDEN_STAND_S)
        angle = float(rng.choice([-1.0, 1.0]) * np.radians(rng.uniform(*HIDDEN_TURN_DEG)))
        length = abs(angle) / np.radians(rng.uniform(*HIDDEN_TURN_RATE_DEG))
        across = _heading_of_walk(walker, rest) - bearing - rng.choice([-1.0, 1.0]) * np.pi / 2
        near = rng.uniform(*HIDER_SHARE) * distance * ray
        hider = Actor(
            walker.name,
            start,
            rest,
            float(-across),
            (float(near[0]), float(near[1])),
            random_outfit(rng),
            pauses=((rest_at - ramp, ramp, float(stand)),),
        )
        motion = catalogue.draw(rng, frozenset({walker.name}), TURNING_MOTIONS)
        clip_start, anchor = _clip_timing(rng, motion, size.duration)
        hidden = Actor(
            motion.name,
            clip_start,
            anchor,
            float(rng.uniform(-np.pi, np.pi)),
            (float(distance * ray[0]), float(distance * ray[1])),
            random_outfit(rng),
            bursts=((float(rest_at + (stand - length) / 2), float(length), angle),),
        )
        if _apart([_pelvis_path(hidden, motion, times)], _pelvis_path(hider, walker, times)):
            return [hidden, hider]
    return []


def _people(
    catalogue: Catalogue,
    rng: np.random.Generator,
    size: Size,
    people: int,
    half_fov: float,
    kinds: tuple[str, ...] | None,
    turning: bool,
    stopping: bool,
    pausing: bool,
) -> list[Actor]:
    """Up to ``people`` people of the motion categories ``kinds`` (any where None), each placed
    and turned at random as :func:`draw_scene` says, kept :data:`MIN_SEPARATION` apart (one
    that 30 draws could not place is left out)."""
    times = _separation_times(size)
    actors: list[Actor] = []
    paths: list[np.ndarray] = []
    for _ in range(people):
        for _attempt in range(30):
            avoid = frozenset(a.motion for a in actors)
            motion = catalogue.draw(rng, avoid, kinds)
            start, anchor = _clip_timing(rng, motion, size.duration)
            distance = rng.uniform(*DISTANCE_M)
            bearing = rng.uniform(-0.8, 0.8) * half_fov
            actor = Actor(
                motion.name,
                start,
                anchor,
                float(rng.uniform(-np.pi, np.pi)),
                (float(distance * np.cos(bearing)), float(distance * np.sin(bearing))),
                random_outfit(rng),
                turn=_turn_rate(rng) if turning else 0.0,
                bursts=_bursts(rng, size.duration) if stopping else (),
                pauses=_pauses(rng, motion, start, size.duration) if pausing else (),
            )
            path = _pelvis_path(actor, motion, times)
            if _apart(paths, path):
                actors.append(actor)
                paths.append(path)
                break
    return actors


def on_robot(spec: SceneSpec) -> SceneSpec:
    """``spec`` seen from a robot that drives past its people (:data:`ROBOT_SPEED` and after),
    drawn from the scene's own seed: the same scene always gets the same path, and the people,
    the sensor and every other draw are those of ``spec``."""
    rng = np.random.default_rng([spec.seed, 1])
    speed = rng.uniform(*ROBOT_SPEED)
    direction = np.pi / 2 * rng.choice([-1.0, 1.0]) + np.radians(rng.uniform(-1.0, 1.0) * ROBOT_ACROSS_DEG)
    path = RobotPath(
        (float(speed * np.cos(direction)), float(speed * np.sin(direction))),
        float(np.radians(rng.uniform(*ROBOT_PAN_DEG))),
        float(rng.uniform(*ROBOT_PAN_PERIOD_S)),
        float(rng.uniform(0.0, 2 * np.pi)),
    )
    return replace(spec, robot=path)


def draw_scene(
    catalogue: Catalogue,
    index: int,
    seed: int,
    size: Size,
    people: int | None = None,
    turning: bool = False,
    stopping: bool = False,
    pausing: bool = False,
    hiding: bool = False,
) -> SceneSpec:
    """Scene ``index`` of a run with ``seed``: the same numbers give the same scene. A
    ``turning`` scene's people turn on the spot (:data:`TURN_RATE_DEG`), a ``stopping`` scene's
    turn on the spot and stop (:data:`TURN_ANGLE_DEG`, :data:`STOP_S`), a ``pausing`` scene's
    walk and stop (:data:`PAUSING_MOTIONS`, :data:`STOP_RAMP_S`, :data:`STOP_S`,
    :data:`WALK_S`), a ``hiding`` scene's two people are one who turns round while the other
    hides them (:data:`HIDDEN_DISTANCE_M`; ``people``, if given, must be 2); one kind at most."""
    if turning + stopping + pausing + hiding > 1:
        raise ValueError(
            "a scene's people turn steadily (turning), turn and stop (stopping), walk and stop "
            "(pausing) or turn while hidden (hiding): one kind, not several"
        )
    if hiding and people not in (None, 2):
        raise ValueError(
            f"a hiding scene has two people, one hidden and one who hides them; got people={people}"
        )
    rng = np.random.default_rng([seed, index])
    sensor = sorted(SENSORS)[int(rng.integers(len(SENSORS)))]
    fps = FRAME_RATES[int(rng.integers(len(FRAME_RATES)))]
    height, tilt = rng.uniform(*HEIGHT_M), rng.uniform(*TILT_DEG)
    intr = SENSORS[sensor].intrinsics
    half_fov = np.arctan2(SENSORS[sensor].width / 2, intr.fx)
    if hiding:
        actors = _hiding_pair(catalogue, rng, size, float(half_fov))
    else:
        kinds = TURNING_MOTIONS if turning or stopping else PAUSING_MOTIONS if pausing else None
        most = MAX_PEOPLE if kinds is None else TURNING_PEOPLE
        if people is None:
            people = 1 if rng.random() < SINGLE_SHARE else int(rng.integers(2, most + 1))
        turns = (turning, stopping, pausing)
        actors = _people(catalogue, rng, size, people, float(half_fov), kinds, *turns)
    return SceneSpec(
        f"{catalogue.split}-{seed}-{index:03d}",
        sensor,
        fps,
        float(height),
        float(tilt),
        size.duration,
        tuple(actors),
        seed=int(rng.integers(2**31)),
    )
