"""The thesis' learned baseline, HMP: the sequence-to-sequence GRU of Martinez, Black and Romero,
"On human motion prediction using recurrent neural networks" (CVPR 2017), written in NumPy so that
the evaluation needs no deep-learning framework.

The model is the paper's best ("Residual sup. (MA)": one model for every action, told the action):

- the input of a step is a 25 Hz frame of the exponential-map files, its channels normalised by
  the training set's mean and standard deviation (channels that never move are left out), with
  the action as a one-hot code appended;
- one GRU cell reads the 49 frames before the last observed one (the encoder), then, from the last
  observed frame on, predicts each next frame as its input plus a linear map of its state (the
  residual connection: the network learns the velocity) and is fed its own prediction (the
  sampling-based loss, which trains it on its own errors as it will meet them when forecasting);
- the loss is the mean squared error of the predicted frames' channels (the one-hot code's
  included, as in the reference code) over 400 ms, minimised by plain gradient descent with the
  gradient's norm clipped and the learning rate decayed in steps.

The forecast is of the whole body, root increments included; :func:`torsocast.datasets.h36m.forecast_poses`
turns it into torso poses the way the truth is made. Training is for a user to run on the
research-only data (``torsocast eval train-hmp``); the weights stay where the user puts them.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

F32 = npt.NDArray[np.float32]
F64 = npt.NDArray[np.float64]
#: The network's arrays: float32 to train, float64 to check its gradients.
Floats = npt.NDArray[np.floating[Any]]

#: A channel that moves less than this over the training set is left out (the reference code's rule).
STILL_STD = 1e-4
#: Frames read before the first forecast (2 s at 25 Hz); the encoder reads all but the last.
HISTORY = 50
#: Training steps between the models :func:`train` hands its ``checkpoint``.
CHECKPOINT_EVERY = 1000


@dataclass(frozen=True)
class Normaliser:
    """Per-channel mean and spread of the training frames, and which channels the model sees."""

    mean: F64
    """``(99,)``"""
    std: F64
    """``(99,)``"""
    used: npt.NDArray[np.int64]
    """Indices of the channels whose spread is at least :data:`STILL_STD`."""

    @classmethod
    def fit(cls, frames: F64) -> Normaliser:
        mean, std = frames.mean(axis=0), frames.std(axis=0)
        return cls(mean=mean, std=std, used=np.flatnonzero(std >= STILL_STD))

    def encode(self, frames: F64) -> F64:
        """``(..., 99)`` frames as the model's ``(..., len(used))`` channels."""
        return (frames[..., self.used] - self.mean[self.used]) / self.std[self.used]

    def decode(self, channels: F64) -> F64:
        """The model's channels as ``(..., 99)`` frames; the still channels at their mean."""
        frames = np.broadcast_to(self.mean, (*channels.shape[:-1], len(self.mean))).copy()
        frames[..., self.used] = channels * self.std[self.used] + self.mean[self.used]
        return frames


@dataclass
class Weights:
    """The GRU cell (TensorFlow's layout: the gates' kernel over ``[input, state]``, reset then
    update) and the linear map from its state to a frame's change."""

    gates: Floats
    """``(inputs + units, 2 units)``"""
    gates_bias: Floats
    candidate: Floats
    """``(inputs + units, units)``, applied to ``[input, reset * state]``"""
    candidate_bias: Floats
    out: Floats
    """``(units, inputs)``"""
    out_bias: Floats

    @property
    def units(self) -> int:
        return self.candidate.shape[1]

    @property
    def inputs(self) -> int:
        return self.out.shape[1]

    @classmethod
    def initial(cls, inputs: int, units: int, rng: np.random.Generator) -> Weights:
        """The reference code's start: Glorot-uniform kernels, gate biases at one (the cell begins
        by keeping its state), the output map uniform in +-0.04."""

        def glorot(rows: int, cols: int) -> Floats:
            limit = np.sqrt(6.0 / (rows + cols))
            return rng.uniform(-limit, limit, (rows, cols)).astype(np.float32)

        return cls(
            gates=glorot(inputs + units, 2 * units),
            gates_bias=np.ones(2 * units, np.float32),
            candidate=glorot(inputs + units, units),
            candidate_bias=np.zeros(units, np.float32),
            out=rng.uniform(-0.04, 0.04, (units, inputs)).astype(np.float32),
            out_bias=rng.uniform(-0.04, 0.04, inputs).astype(np.float32),
        )

    def arrays(self) -> list[Floats]:
        return [self.gates, self.gates_bias, self.candidate, self.candidate_bias, self.out, self.out_bias]


def _sigmoid(x: Floats) -> Floats:
    return 0.5 * (1.0 + np.tanh(0.5 * x))


@dataclass
class _Step:
    """What one cell step keeps for the backward pass."""

    xh: Floats
    x_rh: Floats
    h: Floats
    reset: Floats
    update: Floats
    candidate: Floats


def _cell(w: Weights, x: Floats, h: Floats) -> tuple[Floats, _Step]:
    xh = np.concatenate([x, h], axis=1)
    gates = _sigmoid(xh @ w.gates + w.gates_bias)
    reset, update = gates[:, : w.units], gates[:, w.units :]
    x_rh = np.concatenate([x, reset * h], axis=1)
    candidate = np.tanh(x_rh @ w.candidate + w.candidate_bias)
    return update * h + (1.0 - update) * candidate, _Step(xh, x_rh, h, reset, update, candidate)


def _run(w: Weights, encoder: Floats, first: Floats, steps: int) -> tuple[Floats, list[_Step], list[Floats]]:
    """Predicted frames ``(batch, steps, inputs)`` after the encoder's ``(batch, 49, inputs)`` and
    the last observed frame, each fed back as the next input; plus what the backward pass needs."""
    h = np.zeros((len(first), w.units), w.out.dtype)
    trace: list[_Step] = []
    for t in range(encoder.shape[1]):
        h, step = _cell(w, encoder[:, t], h)
        trace.append(step)
    x, states, outputs = first, [], []
    for _ in range(steps):
        h, step = _cell(w, x, h)
        trace.append(step)
        states.append(h)
        x = x + h @ w.out + w.out_bias
        outputs.append(x)
    return np.stack(outputs, axis=1), trace, states


def predict(w: Weights, history: Floats, steps: int) -> Floats:
    """``(batch, steps, inputs)`` frames after each ``(batch, 50, inputs)`` history."""
    return _run(w, history[:, :-1].astype(np.float32), history[:, -1].astype(np.float32), steps)[0]


def loss_and_gradients(w: Weights, history: Floats, future: Floats) -> tuple[float, list[Floats]]:
    """The mean squared error of the predicted ``future`` and its gradient for each of
    :meth:`Weights.arrays`, by backpropagation through time (through the fed-back predictions too)."""
    batch, steps, inputs = future.shape
    predicted, trace, states = _run(w, history[:, :-1], history[:, -1], steps)
    error = predicted - future
    loss = float(np.mean(error**2))
    d_predicted = (2.0 / error.size) * error
    units, encoder_steps = w.units, len(trace) - steps
    d_out = np.zeros_like(w.out)
    d_out_bias = np.zeros_like(w.out_bias)
    d_gates = np.empty((len(trace), batch, 2 * units), w.out.dtype)
    d_candidates = np.empty((len(trace), batch, units), w.out.dtype)
    d_h = np.zeros((batch, units), w.out.dtype)
    d_input = np.zeros((batch, inputs), w.out.dtype)
    for t in reversed(range(len(trace))):
        step = trace[t]
        if t >= encoder_steps:
            # A decoder step's prediction is its input plus the map of its state, and is the
            # next step's input: its gradient is its own error's and the next input's.
            k = t - encoder_steps
            d_y = d_predicted[:, k] + d_input
            d_out += states[k].T @ d_y
            d_out_bias += d_y.sum(axis=0)
            d_h = d_h + d_y @ w.out.T
        d_candidate = d_h * (1.0 - step.update) * (1.0 - step.candidate**2)
        d_update = d_h * (step.h - step.candidate) * step.update * (1.0 - step.update)
        d_x_rh = d_candidate @ w.candidate.T
        d_reset = d_x_rh[:, inputs:] * step.h * step.reset * (1.0 - step.reset)
        gates = np.concatenate([d_reset, d_update], axis=1)
        d_xh = gates @ w.gates.T
        d_gates[t], d_candidates[t] = gates, d_candidate
        d_h = d_h * step.update + d_x_rh[:, inputs:] * step.reset + d_xh[:, inputs:]
        if t >= encoder_steps:
            d_input = d_y + d_x_rh[:, :inputs] + d_xh[:, :inputs]
    xh = np.concatenate([s.xh for s in trace])
    x_rh = np.concatenate([s.x_rh for s in trace])
    d_gates_flat = d_gates.reshape(-1, 2 * units)
    d_candidates_flat = d_candidates.reshape(-1, units)
    grads = [
        xh.T @ d_gates_flat,
        d_gates_flat.sum(axis=0),
        x_rh.T @ d_candidates_flat,
        d_candidates_flat.sum(axis=0),
        d_out,
        d_out_bias,
    ]
    return loss, grads


@dataclass(frozen=True)
class Training:
    """The reference code's settings, but for the iterations: its 100 000 steps of a 1024-unit
    cell take hours on two CPU cores in NumPy, so the default is a tenth of them (the training
    loss had flattened by then on S1: docs/reproduction.md)."""

    units: int = 1024
    iterations: int = 10_000
    batch: int = 16
    #: Frames predicted in training (400 ms, the reference code's default and the thesis' window);
    #: a forecast runs the decoder on to 2 s, as the reference code's sampling does.
    steps: int = 10
    learning_rate: float = 0.005
    decay: float = 0.95
    decay_every: int = 10_000
    max_gradient_norm: float = 5.0
    seed: int = 0

    def __post_init__(self) -> None:
        for name in ("units", "iterations", "batch", "steps", "decay_every"):
            if getattr(self, name) < 1:
                raise ValueError(f"{name} must be at least 1, got {getattr(self, name)}")
        if not self.learning_rate > 0 or not 0 < self.decay <= 1 or not self.max_gradient_norm > 0:
            raise ValueError("learning_rate and max_gradient_norm must be positive and decay in (0, 1]")


@dataclass
class Model:
    """A trained HMP: its weights, how frames become its channels, and the actions it codes."""

    weights: Weights
    normaliser: Normaliser
    actions: tuple[str, ...]
    subjects: tuple[int, ...]
    """The subjects it was trained on."""
    iterations: int
    losses: F64
    """The training loss, one entry per iteration."""
    settings: Training | None = None
    """How it was trained, and ``rng``, its random generator's state after its last step: what
    training needs to go on from here (:func:`train`'s ``resume``). ``None`` in models saved
    before torsocast kept them, which cannot be resumed."""
    rng: dict[str, Any] | None = None

    def channels(self, frames: F64, action: str) -> F32:
        """``(..., frames, 99)`` 25 Hz frames of one action as the model's inputs."""
        return _channels(self.normaliser, self.actions, frames, action)

    def forecast(self, history: F64, action: str, steps: int) -> F64:
        """``(batch, steps, 99)`` frames after each ``(batch, 50, 99)`` history of ``action``."""
        if history.ndim != 3 or history.shape[1] != HISTORY or history.shape[2] != len(self.normaliser.mean):
            raise ValueError(f"history must be (batch, {HISTORY}, 99) frames, got {history.shape}")
        if action not in self.actions:
            raise ValueError(f"the model was not trained on action {action!r}; it knows {self.actions}")
        predicted = predict(self.weights, self.channels(history, action), steps)
        return self.normaliser.decode(predicted[..., : len(self.normaliser.used)].astype(np.float64))

    def describe(self) -> dict[str, object]:
        """What the model is, for a report."""
        return {
            "units": self.weights.units,
            "channels": len(self.normaliser.used),
            "actions": len(self.actions),
            "trained_on_subjects": list(self.subjects),
            "iterations": self.iterations,
            "final_loss": float(self.losses[-100:].mean()) if len(self.losses) else None,
            "resumable": self.settings is not None,
        }

    def save(self, path: str | Path) -> None:
        """Writes the model to ``path`` as it is named (NumPy's own would add ``.npz``), whole or
        not at all: a run stopped while a checkpoint is written keeps the one before."""
        w = self.weights
        arrays: dict[str, Any] = {
            "gates": w.gates,
            "gates_bias": w.gates_bias,
            "candidate": w.candidate,
            "candidate_bias": w.candidate_bias,
            "out": w.out,
            "out_bias": w.out_bias,
            "mean": self.normaliser.mean,
            "std": self.normaliser.std,
            "used": self.normaliser.used,
            "actions": np.array(self.actions),
            "subjects": np.array(self.subjects),
            "iterations": self.iterations,
            "losses": self.losses,
        }
        if self.settings is not None and self.rng is not None:
            # JSON: the generator's state holds integers wider than any NumPy integer.
            state = {"settings": asdict(self.settings), "rng": self.rng}
            arrays["training"] = np.array(json.dumps(state))
        partial = Path(f"{path}.partial")
        with open(partial, "wb") as file:
            np.savez(file, **arrays)
        partial.replace(path)

    @classmethod
    def load(cls, path: str | Path) -> Model:
        try:
            saved = np.load(path)
        except (OSError, ValueError) as e:
            raise ValueError(f"{path}: not an HMP model saved by torsocast ({e})") from e
        if not isinstance(saved, np.lib.npyio.NpzFile):
            raise ValueError(f"{path}: not an HMP model saved by torsocast (one array, not a model's)")
        with saved as z:
            try:
                weights = Weights(
                    *(z[k] for k in ("gates", "gates_bias", "candidate", "candidate_bias", "out", "out_bias"))
                )
                return cls(
                    weights=weights,
                    normaliser=Normaliser(z["mean"], z["std"], z["used"]),
                    actions=tuple(str(a) for a in z["actions"]),
                    subjects=tuple(int(s) for s in z["subjects"]),
                    iterations=int(z["iterations"]),
                    losses=z["losses"],
                    **_training_state(z),
                )
            except KeyError as e:
                raise ValueError(f"{path}: not an HMP model saved by torsocast (no {e})") from e


def _training_state(saved: Any) -> dict[str, Any]:
    """A saved model's settings and generator state, where it has them."""
    if "training" not in saved:
        return {}
    state = json.loads(str(saved["training"]))
    return {"settings": Training(**state["settings"]), "rng": state["rng"]}


def _channels(normaliser: Normaliser, actions: tuple[str, ...], frames: F64, action: str) -> F32:
    code = np.zeros((*frames.shape[:-1], len(actions)))
    code[..., actions.index(action)] = 1.0
    return np.concatenate([normaliser.encode(frames), code], axis=-1).astype(np.float32)


def _clip(grads: list[Floats], max_norm: float) -> list[Floats]:
    norm = float(np.sqrt(sum(float(np.sum(g.astype(np.float64) ** 2)) for g in grads)))
    return grads if norm <= max_norm else [g * (max_norm / norm) for g in grads]


def train(
    takes: Sequence[tuple[str, F64]],
    actions: Sequence[str],
    subjects: Sequence[int],
    settings: Training = Training(),
    progress: Callable[[int, float], None] | None = None,
    checkpoint: Callable[[Model], None] | None = None,
    resume: Model | None = None,
) -> Model:
    """Trains on ``(action, (frames, 99) 25 Hz frames)`` takes as the reference code does: each
    step a batch of windows, each from a take drawn uniformly and a start drawn uniformly (from the
    17th frame on), 50 frames read and ``settings.steps`` predicted. ``progress(iteration, loss)``
    is called every 100 iterations, ``checkpoint(model so far)`` every
    :data:`CHECKPOINT_EVERY` (so that a long run stopped early leaves a model that says how far
    it got). ``resume``, such a model, is trained on from its last step to ``settings.iterations``
    on the same takes, as if the run had not stopped: the same model to the bit."""
    span = HISTORY + settings.steps
    usable = [(a, f) for a, f in takes if len(f) > 16 + span]
    if not usable:
        raise ValueError(f"no take is longer than {16 + span} frames")
    missing = {a for a, _ in usable} - set(actions)
    if missing:
        raise ValueError(f"takes of actions not in the list: {sorted(missing)}")
    normaliser = Normaliser.fit(np.concatenate([f for _, f in usable]))
    encoded = [_channels(normaliser, tuple(actions), f, a) for a, f in usable]
    rng = np.random.default_rng(settings.seed)
    losses = np.empty(settings.iterations)
    rate = settings.learning_rate
    if resume is None:
        w, start = Weights.initial(encoded[0].shape[1], settings.units, rng), 0
    else:
        _check_resumable(resume, settings, normaliser, tuple(actions), tuple(subjects))
        assert resume.rng is not None
        w, start = Weights(*(a.copy() for a in resume.weights.arrays())), resume.iterations
        rng.bit_generator.state = resume.rng
        losses[:start] = resume.losses
        for _ in range(start // settings.decay_every):  # the decays so far, one by one as made
            rate *= settings.decay

    def so_far(done: int) -> Model:
        state = dict(rng.bit_generator.state)
        return Model(w, normaliser, tuple(actions), tuple(subjects), done, losses[:done], settings, state)

    for i in range(start, settings.iterations):
        takes_drawn = rng.integers(len(encoded), size=settings.batch)
        starts = [int(rng.integers(16, len(encoded[k]) - span)) for k in takes_drawn]
        windows = np.stack([encoded[k][s : s + span] for k, s in zip(takes_drawn, starts)])
        loss, grads = loss_and_gradients(w, windows[:, :HISTORY], windows[:, HISTORY:])
        for array, grad in zip(w.arrays(), _clip(grads, settings.max_gradient_norm)):
            array -= rate * grad
        losses[i] = loss
        if (i + 1) % settings.decay_every == 0:
            rate *= settings.decay
        if progress is not None and (i + 1) % 100 == 0:
            progress(i + 1, float(losses[i - 99 : i + 1].mean()))
        if checkpoint is not None and (i + 1) % CHECKPOINT_EVERY == 0 and i + 1 < settings.iterations:
            checkpoint(so_far(i + 1))
    return so_far(settings.iterations)


def _check_resumable(
    model: Model,
    settings: Training,
    normaliser: Normaliser,
    actions: tuple[str, ...],
    subjects: tuple[int, ...],
) -> None:
    """Refuses, naming why, to go on with a model trained otherwise or on other data."""
    if model.settings is None or model.rng is None:
        raise ValueError("the model was saved without its training state, so it cannot be trained on")
    for name in (f.name for f in fields(Training) if f.name != "iterations"):
        had, asked = getattr(model.settings, name), getattr(settings, name)
        if had != asked:
            raise ValueError(f"the model was trained with {name} {had}, not {asked}")
    if model.subjects != subjects:
        raise ValueError(f"the model was trained on subjects {list(model.subjects)}, not {list(subjects)}")
    if model.actions != actions:
        raise ValueError("the model was trained on other actions")
    same_data = all(
        np.array_equal(a, b)
        for a, b in zip(
            (model.normaliser.mean, model.normaliser.std, model.normaliser.used),
            (normaliser.mean, normaliser.std, normaliser.used),
        )
    )
    if not same_data:
        raise ValueError(
            "the takes are not those the model was trained on (their channels' statistics differ)"
        )
    if model.iterations >= settings.iterations:
        raise ValueError(
            f"the model has had {model.iterations} steps already; ask for more than that to train it on"
        )
