"""Scoring a rendered scene's frames against the truth: which detection is which person, and
one record per visible person and frame (recovery) and per forecast and horizon (forecasts).

A detection belongs to the person whose pixels most of its keypoints fall on (the renderer's
label image), so a detection with a wildly wrong 3D estimate still counts as that person's,
with its error, rather than as a miss. A person counts for recovery in a frame where at least
three of their four torso joints are in the image and not hidden by someone else.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from ... import Forecaster, ForecasterConfig, TorsocastError, wrap_angle
from ...pipeline import FrameResult
from ...synthetic.scenes import RenderedScene
from ...tracker import TrackOutcome

F64 = npt.NDArray[np.float64]

#: Keypoints on a person's pixels needed to say that a detection is that person.
MIN_VOTES = 3
#: Forecasts compared: the default live forecaster and three references. "truth" holds the true
#: pose still: what a perfect recovery followed by "the person stays where they are" would give.
METHODS = ("forecast", "hold", "velocity", "truth")
COMPONENTS = ("centre", "azimuth", "elevation")
#: The pose's components, each with its own 80 % interval.
POSE_COMPONENTS = ("x", "y", "z", "azimuth", "elevation")
#: Seconds a person must stay in view after their track ends for the track to count as lost.
LOST_AFTER = 1.0
#: Azimuth error beyond which an estimate is a front/back flip (degrees).
FLIP_DEG = 90.0
#: Torso line error beyond which a flipped estimate's plane is to blame (degrees): the line lies
#: nearer across the true one than along it.
BAD_LINE_DEG = 45.0
#: Why an estimate is flipped (:func:`flip_source`), in the order the rules are tried.
FLIP_SOURCES = ("bad plane", "born wrong", "turned wrong", "side lost")
#: A track's first frames with a person: where a track born on the wrong side shows.
YOUNG_FRAMES = 10


@dataclass
class TrackSide:
    """What one track has done with one person's heading so far (:func:`flip_source`), and
    since when (s) it has been with them (the age its forecasts are given by)."""

    frames: int = 0
    ever_right: bool = False
    turned_wrong: bool = False
    since: float | None = None


def flip_source(azimuth_error: float, reoriented: bool, side: TrackSide) -> str:
    """Why a track's estimate of a person is flipped (azimuth error over 90 degrees), or ``""``
    where it is not, updating ``side`` with this frame. The torso line more than 45 degrees off
    the truth's is a bad plane, whichever side it took; with a good line, a track that has not
    yet been on the right side with this person was born wrong, one whose last turn round
    (``reoriented``) took it to the wrong side turned wrong, and the rest lost the side with no
    turn (a stretch of bad planes carries the heading over)."""
    flipped = azimuth_error > np.radians(FLIP_DEG)
    side.frames += 1
    if reoriented:
        side.turned_wrong = flipped
    if not flipped:
        side.ever_right = True
        return ""
    if min(azimuth_error, np.pi - azimuth_error) > np.radians(BAD_LINE_DEG):
        return "bad plane"
    if not side.ever_right:
        return "born wrong"
    return "turned wrong" if side.turned_wrong else "side lost"


def assign(keypoints: F64, labels: npt.NDArray[np.int8], min_score: float) -> list[int]:
    """The person index of each detection ``(people, 17, 3)``, -1 where none; a person claimed
    by several detections keeps the one with the most keypoints on it."""
    h, w = labels.shape
    owner, votes = [], []
    for kp in keypoints:
        ok = (kp[:, 2] >= min_score) & np.isfinite(kp[:, :2]).all(axis=1)
        u, v = np.rint(kp[ok, 0]).astype(int), np.rint(kp[ok, 1]).astype(int)
        inside = (u >= 0) & (u < w) & (v >= 0) & (v < h)
        hits = labels[v[inside], u[inside]]
        counts = np.bincount(hits[hits >= 0].astype(int)) if (hits >= 0).any() else np.zeros(0, int)
        best = int(counts.argmax()) if counts.size else -1
        owner.append(best if best >= 0 and counts[best] >= MIN_VOTES else -1)
        votes.append(int(counts.max()) if counts.size else 0)
    for d, person in enumerate(owner):
        rivals = [e for e, p in enumerate(owner) if p == person and e != d]
        if person >= 0 and any(votes[e] > votes[d] or (votes[e] == votes[d] and e < d) for e in rivals):
            owner[d] = -1
    return owner


def view_angle(truth: F64, camera_xy: F64) -> float:
    """Degrees between where the torso faces and the direction to the camera: 0 facing it, 180
    turned away, +90 turned to the person's left (the camera sees their right side)."""
    to_camera = np.arctan2(camera_xy[1] - truth[1], camera_xy[0] - truth[0])
    return float(np.degrees(wrap_angle(truth[3] - to_camera)))


def tilt_angle(truth: F64) -> float:
    """Degrees the true torso plane leans from upright (its normal's elevation from the
    horizontal): 0 standing or sitting up straight, 90 bent double or lying down. A bent torso's
    normal has a short horizontal part, whose azimuth a small error of the plane turns far."""
    return float(abs(np.degrees(truth[4]) - 90.0))


def pose_errors(estimate: F64, truth: F64) -> tuple[float, float, float]:
    """Centre distance (m), azimuth and elevation errors (rad) of a pose against the truth."""
    return (
        float(np.linalg.norm(estimate[:3] - truth[:3])),
        abs(float(wrap_angle(estimate[3] - truth[3]))),
        abs(float(estimate[4] - truth[4])),
    )


@dataclass
class SceneScore:
    """The records of one scene: column name -> values."""

    recovery: dict[str, list] = field(default_factory=lambda: defaultdict(list))  # type: ignore[type-arg]
    forecasts: dict[str, list] = field(default_factory=lambda: defaultdict(list))  # type: ignore[type-arg]
    identity: dict[str, list] = field(default_factory=lambda: defaultdict(list))  # type: ignore[type-arg]
    unseen: dict[str, list] = field(default_factory=lambda: defaultdict(list))  # type: ignore[type-arg]
    false_positives: int = 0


def taken_ids(seen_ids: dict[int, list[tuple[float, int | None]]]) -> dict[int, int]:
    """Per person, how many of the ids they were reported with someone else in the scene had been
    reported with before them (``seen_ids``: per person, the frames' times and reported ids,
    None where none). A switch counts a person's own id changing; an id passed on to someone
    else is counted here, once, for the person it was passed to."""
    first: dict[int, dict[int, float]] = defaultdict(dict)
    for actor, seen in seen_ids.items():
        for t, i in seen:
            if i is not None:
                first[i].setdefault(actor, t)
    return {
        actor: sum(
            1
            for i in {i for _, i in seen if i is not None}
            if any(t < first[i][actor] for other, t in first[i].items() if other != actor)
        )
        for actor, seen in seen_ids.items()
    }


class Scorer:
    """Scores the frames of one scene as they come out of the pipeline."""

    def __init__(self, scene: RenderedScene, horizons: list[float], min_score: float) -> None:
        self.scene, self.horizons, self.min_score = scene, horizons, min_score
        self.score = SceneScore()
        self.velocity: dict[int, Forecaster] = {}
        self.seen_ids: dict[int, list[tuple[float, int | None]]] = defaultdict(list)
        self.sides: dict[tuple[int, int], TrackSide] = defaultdict(TrackSide)
        # Per confirmed track id: the person it last showed, and its last estimate of them.
        self.shown: dict[int, tuple[int, F64]] = {}
        spec = scene.spec
        self.conditions = {
            "scene": spec.name,
            "sensor": spec.sensor,
            "fps": spec.fps,
            "people": len(spec.actors),
        }

    def _row(self, table: dict[str, list], actor: int, t: float, truth: F64, camera_xy: F64) -> None:  # type: ignore[type-arg]
        """The conditions of a person-frame: ``camera_xy`` is where the frame was seen from."""
        for key, value in self.conditions.items():
            table[key].append(value)
        table["t"].append(t)
        table["actor"].append(actor)
        table["category"].append(self.scene.category(actor))
        table["view"].append(view_angle(truth, camera_xy))
        table["distance"].append(float(np.linalg.norm(truth[:2] - camera_xy)))
        table["tilt"].append(tilt_angle(truth))

    def __call__(
        self,
        t: float,
        result: FrameResult,
        owner: list[int],
        visible: npt.NDArray[np.bool_],
        truth: F64,
        stamp: float | None = None,
    ) -> None:
        """Scores one frame's ``result``, taken at ``t``: ``owner`` is the person index of each
        detection (-1 for none, :func:`assign`), ``visible`` which people count, ``truth`` their
        poses; ``stamp``, the time the tracker was told (``t`` where None)."""
        # Views and distances from where the frame was seen (a robot's camera moves); a replay
        # that tells the pipeline another pose keeps the true one in the frame's extra.
        camera = result.frame.extra.get("camera", result.frame.camera)
        assert camera is not None  # a scene's frames carry their camera
        camera_xy = np.asarray(camera.camera_to_world)[:2, 3]
        by_actor = {a: d for d, a in enumerate(owner) if a >= 0}
        self.score.false_positives += sum(1 for a in owner if a < 0)
        for tracked in result.people:  # the velocity reference sees what the tracks see
            obs = tracked.observation
            if obs is None or obs.pose is None or tracked.key is None:
                continue
            # Keyed by the track's key, unique over the tracker's life.
            f = self.velocity.setdefault(tracked.key, Forecaster(ForecasterConfig("constant_velocity")))
            try:
                f.update(obs.pose, t if stamp is None else stamp, 1.0)
            except TorsocastError:
                pass
        for index in np.flatnonzero(visible):
            actor = int(index)
            if not np.isfinite(truth[actor]).all():
                continue  # no true pose to score against (never for oriented mocap planes)
            d = by_actor.get(actor)
            person = result.people[d] if d is not None and d < len(result.people) else None
            observation = person.observation if person is not None else None
            if observation is not None and observation.pose is None:
                observation = None  # no estimate this frame: nothing of it is scored
            pose = observation.pose if observation is not None else None
            r = self.score.recovery
            self._row(r, actor, t, truth[actor], camera_xy)
            r["estimated"].append(pose is not None)
            r["confident"].append(observation is not None and bool(observation.heading_confident))
            r["facing_evidence"].append(
                float(observation.facing_evidence) if observation is not None else float("nan")
            )
            err = np.abs(pose - truth[actor]) if pose is not None else np.full(5, np.nan)
            err[3] = abs(float(wrap_angle(err[3])))
            for name, value in zip(POSE_COMPONENTS, err):
                r[name].append(float(value))
            source, frames = "", 0
            if observation is not None and person is not None and person.key is not None:
                side = self.sides[(person.key, actor)]
                if side.since is None:
                    side.since = t
                source = flip_source(float(err[3]), bool(observation.reoriented), side)
                frames = side.frames
            r["flip_source"].append(source)
            r["track_frames"].append(frames)
            track_id = person.track_id if person is not None else None
            self.seen_ids[actor].append((t, track_id))
            if pose is not None and person is not None and d in result.forecasts:
                spread = result.intervals.get(d)
                self._forecasts(actor, t, pose, result.forecasts[d], spread, person, camera_xy)
        # Every detection of a person, in view or not (a torso mostly out of the image or hidden
        # is still detected and tracked), is that track's last estimate of them.
        for d, tracked in enumerate(result.people):
            obs = tracked.observation
            if tracked.track_id is not None and obs is not None and obs.pose is not None and owner[d] >= 0:
                self.shown[tracked.track_id] = (owner[d], obs.pose)
        self._unseen(t, result, visible, truth, camera_xy)

    def _unseen(
        self, t: float, result: FrameResult, visible: npt.NDArray[np.bool_], truth: F64, camera_xy: F64
    ) -> None:
        """Each unseen track's pose for the frame (:attr:`FrameResult.unseen`) against the truth of
        the person it last showed, beside holding its last estimate of them."""
        u = self.score.unseen
        for track in result.unseen:
            if track.pose is None or track.id not in self.shown:
                continue
            actor, held = self.shown[track.id]
            if not np.isfinite(truth[actor]).all():
                continue
            self._row(u, actor, t, truth[actor], camera_xy)
            u["unseen_for"].append(t - track.last_time)
            u["in_view"].append(bool(visible[actor]))
            for method, guess in (("forecast", track.pose), ("hold", held)):
                for component, e in zip(COMPONENTS, pose_errors(guess, truth[actor])):
                    u[f"{method}_{component}"].append(e)

    def _forecasts(
        self,
        actor: int,
        t: float,
        pose: F64,
        ahead: F64,
        spread: F64 | None,
        person: TrackOutcome,
        camera_xy: F64,
    ) -> None:
        origin = person.last_time
        assert origin is not None and person.key is not None  # a forecast has both
        velocity = self.velocity.get(person.key)
        cv = None
        if velocity is not None and len(velocity) >= velocity.min_samples:
            cv = velocity.forecast(self.horizons)
        now = self.scene.truth_at(actor, origin)
        for k, (h, predicted) in enumerate(zip(self.horizons, ahead)):
            then = self.scene.truth_at(actor, origin + h)
            if not np.isfinite(then).all() or not np.isfinite(now).all() or cv is None:
                continue
            f = self.score.forecasts
            self._row(f, actor, t, now, camera_xy)
            f["horizon"].append(h)
            since = self.sides[(person.key, actor)].since
            f["track_age"].append(t - since if since is not None else 0.0)
            for method, guess in zip(METHODS, (predicted, pose, cv[k], now)):
                for component, e in zip(COMPONENTS, pose_errors(guess, then)):
                    f[f"{method}_{component}"].append(e)
            miss = np.abs(predicted - then)
            miss[3] = abs(float(wrap_angle(miss[3])))
            for axis, m, half in zip(
                POSE_COMPONENTS, miss, spread[k] if spread is not None else [np.nan] * 5
            ):
                f[f"miss_{axis}"].append(float(m))
                f[f"half_width_{axis}"].append(float(half))

    def finish(self) -> SceneScore:
        """Identity switches, lost tracks and taken ids of every person, once the scene is over."""
        taken = taken_ids(self.seen_ids)
        for actor, seen in self.seen_ids.items():
            ids = [(t, i) for t, i in seen if i is not None]
            switches = sum(1 for (_, a), (_, b) in zip(ids, ids[1:]) if a != b)
            last_visible = seen[-1][0]
            ends: dict[int, float] = {}
            for t, i in ids:
                ends[i] = t
            lost = sum(1 for end in ends.values() if last_visible - end >= LOST_AFTER)
            g = self.score.identity
            for key, value in self.conditions.items():
                g[key].append(value)
            g["actor"].append(actor)
            g["category"].append(self.scene.category(actor))
            g["visible_frames"].append(len(seen))
            g["tracks"].append(len(ends))
            g["switches"].append(switches)
            g["lost"].append(lost)
            g["taken"].append(taken[actor])
        return self.score
