"""Penalised B-spline fit against make_smoothing_spline (cubic) and a dense solve (other degrees)."""

import numpy as np
import pytest
from scipy import interpolate

import torsocast as tc
from scipy_reference import smoothing_spline


@pytest.mark.parametrize("lam", [1e-4, 0.01, 1.0, 100.0])
def test_cubic_equals_make_smoothing_spline(lam, rng):
    x = np.sort(rng.uniform(0, 4, size=45))
    y = np.sin(1.7 * x) + 0.1 * rng.normal(size=45)
    w = rng.uniform(0.2, 2.0, size=45)
    knots, coeffs = tc.fit_smoothing_spline(x, y, w, lam=lam, degree=3)
    ref = interpolate.make_smoothing_spline(x, y, w, lam=lam)
    np.testing.assert_allclose(knots, ref.t, atol=0)
    ours = interpolate.BSpline(knots, coeffs, 3)
    inside = np.linspace(x[0], x[-1], 300)
    np.testing.assert_allclose(ours(inside), ref(inside), atol=1e-9)
    # Polynomial continuation past the last sample, as BSpline(extrapolate=True).
    ahead = x[-1] + np.linspace(0, 2, 20)
    np.testing.assert_allclose(ours(ahead), ref(ahead), rtol=1e-8, atol=1e-8)


@pytest.mark.parametrize("degree", [0, 1, 2, 4])
def test_other_degrees_equal_a_dense_solve_of_the_same_objective(degree, rng):
    x = np.arange(30) * 0.04
    y = np.cos(3 * x) + 0.05 * rng.normal(size=30)
    w = rng.uniform(0.5, 1.5, size=30)
    knots, coeffs = tc.fit_smoothing_spline(x, y, w, lam=0.3, degree=degree)
    ref = smoothing_spline(x, y, w, 0.3, degree)
    np.testing.assert_allclose(knots, ref.t, atol=0)
    np.testing.assert_allclose(coeffs, ref.c, atol=1e-8)


def test_degree_one_interpolates(rng):
    x = np.arange(10.0)
    y = rng.normal(size=10)
    knots, coeffs = tc.fit_smoothing_spline(x, y, degree=1, lam=5.0)
    np.testing.assert_allclose(interpolate.BSpline(knots, coeffs, 1)(x), y, atol=1e-12)


def test_spline_errors():
    with pytest.raises(tc.InvalidArgumentError, match="lam"):
        tc.fit_smoothing_spline([0, 1, 2], [1, 2, 3], lam=0.0, degree=2)
    with pytest.raises(tc.InvalidArgumentError, match="degree"):
        tc.fit_smoothing_spline([0, 1, 2], [1, 2, 3], degree=tc.MAX_DEGREE + 1)
    with pytest.raises(tc.InvalidArgumentError, match="`x`"):
        tc.fit_smoothing_spline([0, 2, 1], [1, 2, 3])
    with pytest.raises(tc.ShapeError, match="`y`"):
        tc.fit_smoothing_spline([0, 1, 2], [1, 2])
    with pytest.raises(tc.NotPositiveDefiniteError):
        tc.fit_smoothing_spline([0, 1, 2, 3], [1, 2, 3, 4], w=[0, 0, 0, 0], degree=3)
