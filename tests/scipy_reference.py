"""An independent NumPy/SciPy implementation of the thesis forecaster (chapter 3.3, Algorithm 1).

It shares no code with the Rust core: filters come from ``scipy.signal``, the B-spline basis from
``scipy.interpolate.BSpline``, the cubic fit from ``make_smoothing_spline`` and every other degree
from a dense solve of the same objective. The tests compare the Rust results with it, and the
Python benchmark times it against them.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy import interpolate, signal

MIN_RELATIVE_WEIGHT = 1e-9  # the floor the forecaster applies to relative weights


def knots_at_samples(x: np.ndarray, degree: int) -> np.ndarray:
    """Sample abscissae with the ends repeated to multiplicity degree + 1 (degree 0: one extra)."""
    if degree == 0:
        step = x[-1] - x[-2] if len(x) > 1 else 1.0
        return np.r_[x, x[-1] + step]
    return np.r_[[x[0]] * degree, x, [x[-1]] * degree]


def penalty_matrix(t: np.ndarray, degree: int) -> np.ndarray:
    """Dense Omega_jk = int B_j'' B_k'' by 8-point Gauss-Legendre on every knot interval."""
    m = len(t) - degree - 1
    omega = np.zeros((m, m))
    if degree < 2:
        return omega
    nodes, weights = np.polynomial.legendre.leggauss(8)
    second = [interpolate.BSpline(t, np.eye(m)[j], degree).derivative(2) for j in range(m)]
    for a, b in zip(t[:-1], t[1:]):
        if b <= a:
            continue
        pts = a + (b - a) * (nodes + 1) / 2
        # Just inside the interval, so the right end does not pick the next piece.
        d2 = np.array([s(pts) for s in second])
        omega += (d2 * weights * (b - a) / 2) @ d2.T
    return omega


@lru_cache(maxsize=64)
def _cached_geometry(n: int, degree: int, step: float):
    x = (np.arange(n) - (n - 1)) * step
    t = knots_at_samples(x, degree)
    design = interpolate.BSpline.design_matrix(x, t, degree).toarray()
    return x, t, design, penalty_matrix(t, degree)


def smoothing_spline(x, y, w, lam: float, degree: int) -> interpolate.BSpline:
    """min sum w (y - f(x))^2 + lam int f''^2 with knots at x; cubic via make_smoothing_spline."""
    x, y, w = (np.asarray(a, dtype=float) for a in (x, y, w))
    if degree == 3 and len(x) >= 5:
        return interpolate.make_smoothing_spline(x, y, w, lam=lam)
    t = knots_at_samples(x, degree)
    design = interpolate.BSpline.design_matrix(x, t, degree).toarray()
    a = design.T @ (w[:, None] * design) + lam * penalty_matrix(t, degree)
    return interpolate.BSpline(t, np.linalg.solve(a, design.T @ (w * y)), degree)


def lowpass(x: np.ndarray, mode: str, order: int, cutoff_hz: float, rate_hz: float) -> np.ndarray:
    if mode == "off":
        return x.copy()
    sos = signal.butter(order, cutoff_hz, fs=rate_hz, output="sos")
    if mode == "causal":
        return signal.sosfilt(sos, x, zi=signal.sosfilt_zi(sos) * x[0])[0]
    # SciPy's default pad length, shortened to n - 1 for windows that are too short for it.
    ntaps = 2 * len(sos) + 1 - min((sos[:, 2] == 0).sum(), (sos[:, 5] == 0).sum())
    padlen = min(3 * ntaps, len(x) - 1)
    return signal.sosfiltfilt(sos, x, padlen=padlen)


#: The time constants of torso_core's Extrapolation::DAMPED_H36M_S1, written out independently.
DAMPING_H36M_S1 = (1.5, 1.5, 1.5, 0.5, 0.1)


def forecast(history, horizons, weights=None, **cfg) -> np.ndarray:
    """Forecast (len(horizons), 5) from a (T, 5) history on a grid at cfg['rate_hz']."""
    history = np.array(history, dtype=float)
    history[:, 3] = np.unwrap(history[:, 3])
    n = len(history)
    rate = cfg.get("rate_hz", 25.0)
    step = 1.0 / rate
    horizons = np.asarray(horizons, dtype=float)
    method = cfg.get("method", "filter_spline")
    last = history[-1]
    if method == "const":
        return np.tile(last, (len(horizons), 1))
    if method == "constant_velocity":
        window = cfg.get("velocity_window")
        k = n - 1 if window is None else min(max(round(window * rate), 1), n - 1)
        velocity = (last - history[-1 - k]) / (k * step)
        return last + horizons[:, None] * velocity
    degree = cfg.get("degree", 1)
    lam = cfg.get("lam", 1.0)
    unit = 1.0 if cfg.get("lambda_unit", "samples") == "samples" else step
    components = cfg.get("filter_components", (False, False, False, True, True))
    w = np.ones(n) if weights is None else np.asarray(weights, dtype=float)
    w = np.maximum(w / w.mean(), MIN_RELATIVE_WEIGHT)
    x = (np.arange(n) - (n - 1)) * unit
    out = np.empty((len(horizons), 5))
    for c in range(5):
        y = history[:, c]
        if components[c]:
            y = lowpass(
                y,
                cfg.get("filter", "zero_phase"),
                cfg.get("filter_order", 2),
                cfg.get("cutoff_hz", 5.0),
                rate,
            )
        spline = smoothing_spline(x, y, w, lam, degree)
        tau = horizons / step * unit
        rule = cfg.get("extrapolation", "damped")
        if rule == "linear" and degree >= 1:
            out[:, c] = spline(0.0) + spline.derivative()(0.0) * tau
        elif rule == "damped" and degree >= 1:
            # Slope per second, carried T (1 - exp(-h / T)) seconds.
            T = cfg.get("damping") or DAMPING_H36M_S1
            carry = (
                horizons
                if np.isinf(T[c])
                else T[c] * -np.expm1(-horizons / T[c])
                if T[c] > 0
                else 0.0 * horizons
            )
            out[:, c] = spline(0.0) + spline.derivative()(0.0) * unit / step * carry
        else:
            out[:, c] = spline(tau, extrapolate=True)
    return out


def forecast_fixed_grid(history, horizons, **cfg) -> np.ndarray:
    """Same as :func:`forecast` with uniform weights, caching the basis and penalty per length:
    the fair way to write it for many windows of one length (used by the benchmark)."""
    history = np.array(history, dtype=float)
    history[:, 3] = np.unwrap(history[:, 3])
    n = len(history)
    rate = cfg.get("rate_hz", 25.0)
    step = 1.0 / rate
    degree, lam = cfg.get("degree", 1), cfg.get("lam", 1.0)
    unit = 1.0 if cfg.get("lambda_unit", "samples") == "samples" else step
    _, t, design, omega = _cached_geometry(n, degree, unit)
    components = cfg.get("filter_components", (False, False, False, True, True))
    y = history.copy()
    for c in range(5):
        if components[c]:
            y[:, c] = lowpass(
                y[:, c],
                cfg.get("filter", "zero_phase"),
                cfg.get("filter_order", 2),
                cfg.get("cutoff_hz", 5.0),
                rate,
            )
    coeffs = np.linalg.solve(design.T @ design + lam * omega, design.T @ y)
    tau = np.asarray(horizons, dtype=float) / step * unit
    spline = interpolate.BSpline(t, coeffs, degree)
    if cfg.get("extrapolation", "polynomial") == "linear" and degree >= 1:
        return spline(0.0) + np.outer(tau, spline.derivative()(0.0))
    return spline(tau, extrapolate=True)
