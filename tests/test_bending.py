"""The bending skin: its limits, its constraints, an independent solution, and its fit."""

import numpy as np
import pytest
from scipy import stats
from scipy.integrate import quad, solve_bvp

from conftest import reading_grid_mm
from lineload.bending import (
    WALLS,
    bending_coefficients,
    bending_deflection_mm,
    bending_load_per_tension,
)
from lineload.bending_exact import bending_finite_profile
from lineload.fitting.bending import BENDING_LENGTH_BOUNDS_MM, fit_bending, fit_bending_trials
from lineload.models import arc_deflection_mm, waterbed_deflection_mm

L_MM, DEPTH_MM = 12.0, 1.0


@pytest.mark.parametrize("wall", WALLS)
def test_a_vanishing_bending_length_gives_the_papers_parabola(wall):
    """Inner solution at the load: W'(0) = 0 turns the membrane's slope -4 W0 / L over
    ``l_b``, ``W ~ W0 - (4 W0 / L)(X - l_b + l_b exp(-X / l_b))``, which lies above the
    kinked parabola by ``(4 W0 / L) l_b (1 - exp(-X / l_b))``: the largest difference
    tends to ``4 W0 l_b / L`` and the profile to eq. 19 at first order in ``l_b``."""
    x = np.linspace(0.0, L_MM, 400_001)
    ratios = []
    for lb_mm in (1e-4, 1e-5):
        difference = bending_deflection_mm(x, DEPTH_MM, L_MM, lb_mm, wall) - (
            waterbed_deflection_mm(x, DEPTH_MM, L_MM)
        )
        ratios.append(np.max(np.abs(difference)) / (DEPTH_MM * lb_mm / L_MM))
    # the correction to the leading term is of order l_b / L (1e-5 and 1e-6 here), and
    # the grid's spacing (3e-5 mm) resolves the layer's peak to better than 1e-3
    assert ratios == pytest.approx([4.0, 4.0], rel=2e-3)
    coefficients = bending_coefficients(L_MM / 1e-6, wall)
    assert coefficients[:3] == pytest.approx([1.0, -4.0, 3.0], rel=1e-5)


@pytest.mark.parametrize("wall", WALLS)
@pytest.mark.parametrize("lb_mm", [0.01, 0.3, 3.0, 24.0])
def test_the_core_keeps_its_volume_and_the_ends_their_conditions(wall, lb_mm):
    def profile(x):
        return bending_deflection_mm(x, DEPTH_MM, L_MM, lb_mm, wall)

    area, error = quad(profile, 0.0, L_MM, points=[lb_mm, L_MM - lb_mm], limit=400)
    assert abs(area) <= 1e-10 * DEPTH_MM * L_MM + 10 * error
    assert profile(0.0) == pytest.approx(DEPTH_MM, abs=1e-12)
    assert profile(L_MM) == pytest.approx(0.0, abs=1e-12)
    # second-order one-sided differences at the ends: error h**2 |third derivative| / 3,
    # bounded by the exponential terms' (kappa**3 (|e| + |g|) W0 / L**3); rounding adds
    # about eps W0 sum|coefficients| / h (the terms cancel when l_b >~ L)
    h = 1e-4 * min(lb_mm, L_MM)
    kappa = L_MM / lb_mm
    a, b, c, e, g = bending_coefficients(kappa, wall)
    third = kappa**3 * (abs(e) + abs(g)) * DEPTH_MM / L_MM**3
    size = abs(a) + abs(b) + abs(c) + abs(e) + abs(g)
    tolerance = h**2 * third + 8 * np.finfo(float).eps * size * DEPTH_MM / h

    def slope(at, step):
        return (-3 * profile(at) + 4 * profile(at + step) - profile(at + 2 * step)) / (2 * step)

    assert slope(0.0, h) == pytest.approx(0.0, abs=tolerance)
    if wall == "clamped":
        assert slope(L_MM, -h) == pytest.approx(0.0, abs=tolerance)
    else:  # no moment at the wall: the second derivative is zero there
        curvature = (profile(L_MM) - 2 * profile(L_MM - h) + profile(L_MM - 2 * h)) / h**2
        assert curvature == pytest.approx(0.0, abs=tolerance / h)
    assert np.all(profile(np.array([L_MM * 1.01, 2 * L_MM])) == 0.0)


@pytest.mark.parametrize("wall", WALLS)
@pytest.mark.parametrize("lb_mm", [0.24, 1.2, 6.0])
def test_the_closed_form_matches_a_numerical_solution_of_the_equation(wall, lb_mm):
    """``l_b**2 W'''' - W'' + p / N = 0`` with the volume as a fifth state, solved by
    collocation (scipy's solve_bvp) with p / N unknown: an independent route to the same
    profile."""

    def rhs(x, y, p):
        # y = W, W', W'', W''', integral of W
        return np.vstack([y[1], y[2], y[3], (y[2] - p[0]) / lb_mm**2, y[0]])

    def ends(ya, yb, p):
        far = yb[1] if wall == "clamped" else yb[2]
        return np.array([ya[0] - DEPTH_MM, ya[1], yb[0], far, ya[4], yb[4]])

    x = np.linspace(0.0, L_MM, 2001)
    guess = np.vstack([waterbed_deflection_mm(x, DEPTH_MM, L_MM), *np.zeros((4, x.size))])
    solution = solve_bvp(rhs, ends, x, guess, p=[6 * DEPTH_MM / L_MM**2], tol=1e-10,
                         max_nodes=200_000)  # fmt: skip
    assert solution.success, solution.message
    closed = bending_deflection_mm(x, DEPTH_MM, L_MM, lb_mm, wall)
    assert np.max(np.abs(solution.sol(x)[0] - closed)) <= 1e-7 * DEPTH_MM
    # the pressure: p / N = W'' - l_b**2 W'''', i.e. 2 c W0 / L**2 in the closed form
    c = bending_coefficients(L_MM / lb_mm, wall)[2]
    assert solution.p[0] == pytest.approx(2 * c * DEPTH_MM / L_MM**2, rel=1e-6)


@pytest.mark.parametrize("wall", WALLS)
def test_the_load_tends_to_the_membranes(wall):
    """Eq. 3 in the small-slope limit: F = 2 N sin(theta0) ~ 8 N W0 / L; bending adds."""
    membrane = 8 * DEPTH_MM / L_MM
    near = bending_load_per_tension(DEPTH_MM, L_MM, 1e-6 * L_MM, wall)
    assert near == pytest.approx(membrane, rel=1e-5)
    stiffer = bending_load_per_tension(DEPTH_MM, L_MM, [0.1, 1.0, 3.0], wall)
    assert np.all(np.diff(stiffer) > 0) and stiffer[0] > membrane


def test_a_wrong_wall_or_length_is_refused():
    with pytest.raises(ValueError, match="wall must be one of clamped, pinned"):
        bending_coefficients(10.0, "free")
    with pytest.raises(ValueError, match="kappa"):
        bending_coefficients(0.0)


@pytest.mark.parametrize("lb_mm", [0.08, 0.4])
def test_the_fit_recovers_noiseless_parameters(lb_mm):
    x = reading_grid_mm(3.0)
    y = bending_deflection_mm(x, 1.5, 11.0, lb_mm)
    fit = fit_bending(x, y, 1.5)
    assert fit.params["L_mm"] == pytest.approx(11.0, rel=1e-6)
    assert fit.params["bending_length_mm"] == pytest.approx(lb_mm, rel=1e-5)
    assert fit.rmse_mm < 1e-8 and fit.n_params == 2


def test_intervals_cover_at_their_nominal_rate_on_the_papers_reading_grid():
    """200 noisy profiles at the paper's reading grid, the noise's covariance known: each
    95 % interval holds the truth a number of times a fair coin of 0.95 gives with
    probability 0.999 (the band is binomial, not a tolerance picked to pass)."""
    x = reading_grid_mm(3.0)
    sd_mm, n_trials = 0.005, 200
    truth = {"L_mm": 12.0, "bending_length_mm": 0.15}
    clean = bending_deflection_mm(x, DEPTH_MM, truth["L_mm"], truth["bending_length_mm"])
    rng = np.random.default_rng(2026)
    covered = dict.fromkeys(truth, 0)
    for _ in range(n_trials):
        y = clean + rng.normal(0.0, sd_mm, x.size)
        fit = fit_bending(x, y, DEPTH_MM, covariance_mm2=sd_mm**2 * np.eye(x.size))
        for name, value in truth.items():
            base = name.removesuffix("_mm")
            low, high = fit.params[f"{base}_ci_low_mm"], fit.params[f"{base}_ci_high_mm"]
            covered[name] += low <= value <= high
    low, high = stats.binom.ppf([0.0005, 0.9995], n_trials, 0.95)
    assert all(low <= count <= high for count in covered.values()), covered


def test_a_bending_length_below_the_first_reading_is_not_told_from_zero():
    """The paper's parabola (no bending) and a layer narrower than the first reading's
    distance leave the interval open down to the range's end, flagged as such; a layer
    several readings wide is resolved."""
    x = reading_grid_mm(3.0)
    rng = np.random.default_rng(5)
    noise = rng.normal(0.0, 0.005, x.size)
    covariance = 0.005**2 * np.eye(x.size)
    flat = fit_bending(x, waterbed_deflection_mm(x, 0.5, 12.0) + noise, 0.5, covariance)
    assert flat.params["bending_length_ci_low_mm"] == pytest.approx(BENDING_LENGTH_BOUNDS_MM[0])
    wide = fit_bending(x, bending_deflection_mm(x, 1.0, 12.0, 0.2) + noise, 1.0, covariance)
    assert 0.1 < wide.params["bending_length_ci_low_mm"] < 0.2
    assert wide.params["bending_length_at_bound"] == 0.0


# ------------------------------------------------------------ the finite-slope solution


def test_the_finite_slope_skin_tends_to_the_small_slope_one_as_the_depth_shrinks():
    """The small-slope step drops terms of relative order (W0 / L)**2: its error over W0
    falls a hundredfold when W0 falls tenfold."""
    errors = []
    for depth_mm in (0.02, 0.2):
        exact = bending_finite_profile(depth_mm, L_MM, 0.5)
        x = exact["distance_mm"]
        small = bending_deflection_mm(x, depth_mm, L_MM, 0.5)
        errors.append(np.max(np.abs(exact["deflection_mm"] - small)) / depth_mm)
        assert exact["load_per_H"] == pytest.approx(
            bending_load_per_tension(depth_mm, L_MM, 0.5), rel=5 * (depth_mm / L_MM) ** 2
        )
    assert errors[1] / errors[0] == pytest.approx(100.0, rel=0.05)
    assert errors[0] < 10 * (0.02 / L_MM) ** 2  # of that order, with a modest factor


@pytest.mark.parametrize("wall", WALLS)
def test_the_finite_slope_skin_tends_to_the_membranes_exact_arc(wall):
    """With l_b -> 0 the rod is the paper's membrane solved exactly, the zero-area arc;
    what is left is the layer at the load, of order W0 l_b / L as in the small-slope
    case (the arc's slope at the load is not small here: W0 / L = 1/6)."""
    depth_mm, L_mm = 2.0, 12.0
    ratios = []
    for lb_mm in (0.04, 0.02):
        exact = bending_finite_profile(depth_mm, L_mm, lb_mm, wall)
        x, w = exact["distance_mm"], exact["deflection_mm"]
        arc = arc_deflection_mm(x, depth_mm, L_mm)
        ratios.append(np.max(np.abs(w - arc)) / (depth_mm * lb_mm / L_mm))
        # the volume, without the small-slope step (trapezoids on a fine mesh)
        assert abs(np.trapezoid(w, x)) < 1e-6 * depth_mm * L_mm
    assert all(1.0 < ratio < 8.0 for ratio in ratios), ratios
    assert ratios[1] == pytest.approx(ratios[0], rel=0.2)  # first order in l_b


def test_the_papers_membrane_is_the_bending_fits_special_case():
    """The waterbed is the bending skin at l_b -> 0: on any profile, the bending fit's sum
    of squares is at most the waterbed's (plus the 0.1 um the range's end leaves)."""
    from lineload.fitting.batch import fit_waterbed

    x = reading_grid_mm(3.0)
    rng = np.random.default_rng(11)
    for _ in range(20):
        # profiles neither model makes: a log near the wedge on a parabola
        depth = rng.uniform(0.5, 2.0)
        y = (
            waterbed_deflection_mm(x, depth, rng.uniform(9, 16))
            - rng.uniform(0, 0.05) * np.log(x / 3.0)
            + rng.normal(0, 0.005, x.size)
        )
        bending, waterbed = fit_bending(x, y, depth), fit_waterbed(x, y, depth)
        assert bending.sse_mm2 <= waterbed.sse_mm2 + x.size * (1e-4) ** 2


def test_the_batch_fits_each_trial_on_its_window_like_the_single_fit():
    x = reading_grid_mm(6.0)
    profiles = [bending_deflection_mm(x, d, 12.0, 0.2) for d in (0.5, 1.0)]
    rows = fit_bending_trials([x, x], profiles, [0.5, 1.0], 3.0)
    inside = x <= 3.0
    for row, y, depth in zip(rows, profiles, (0.5, 1.0), strict=True):
        single = fit_bending(x[inside], y[inside], depth)
        assert row["n_points"] == inside.sum()
        assert row["bending_L_mm"] == single.params["L_mm"]
        assert row["bending_length_mm"] == pytest.approx(0.2, rel=1e-5)
    few = fit_bending_trials([x[:3]], [profiles[0][:3]], [0.5], 3.0)[0]
    assert few["n_points"] == 3 and np.isnan(few["bending_L_mm"])


def test_the_polish_finds_the_minimum_scipys_least_squares_finds():
    """The fit's own Levenberg-Marquardt (which spares the jobs scipy.optimize's import)
    ends where scipy's bounded least squares ends, from the same start: the same sum of
    squares to 1e-12 of itself, inside the ranges and at a range's end alike."""
    from scipy.optimize import least_squares

    from lineload.fitting.bending import _polish, _Problem

    x = reading_grid_mm(3.0)
    rng = np.random.default_rng(13)
    ends = 0
    for k in range(30):
        depth = rng.uniform(0.5, 2.0)
        lb = np.exp(rng.uniform(np.log(0.01), np.log(0.5)))
        if k % 2:  # the paper's parabola: the fit ends at the bending length's lower end
            y = waterbed_deflection_mm(x, depth, rng.uniform(9, 16))
        else:
            y = bending_deflection_mm(x, depth, rng.uniform(9, 16), lb)
        y = y + rng.normal(0.0, 0.005, x.size)
        problem = _Problem(x, y, depth, "clamped", ((x.max(), 1000 * x.max()), (1e-4, 10.0)))
        start = np.log([rng.uniform(8, 18), rng.uniform(0.01, 1.0)])
        ours = _polish(problem, start)
        theirs = least_squares(
            problem.residual,
            start,
            bounds=(problem.low, problem.high),
            xtol=1e-13,
            ftol=1e-14,
            gtol=1e-14,
        ).x
        assert problem.sse(ours) <= problem.sse(theirs) * (1 + 1e-12)
        assert np.all(ours >= problem.low) and np.all(ours <= problem.high)
        ends += bool(np.isclose(ours[1], problem.low[1]))
    assert ends > 0  # some fits end at the bending length's lower end


def test_the_start_grid_is_fine_enough_to_find_the_global_minimum():
    """The fit starts from the best point of a coarse grid: on profiles of four shapes
    (the bending skin, the paper's parabola, the exact arc, a log near the wedge on a
    parabola) with 2-20 um of noise, a grid twice as fine each way ends at the same sum
    of squares.  The grid's own best point is worse on every one of them: the equality
    is the polish's work from the grid's start, not the grid's."""
    from lineload.fitting.bending import _START_GRID, _minimum, _Problem
    from lineload.models import arc_deflection_mm

    x = reading_grid_mm(3.0)
    rng = np.random.default_rng(1)
    for n in range(48):
        depth = rng.uniform(0.3, 2.0)
        L_mm = rng.uniform(6, 20)
        y = [
            bending_deflection_mm(x, depth, L_mm, np.exp(rng.uniform(np.log(1e-3), np.log(3)))),
            waterbed_deflection_mm(x, depth, L_mm),
            arc_deflection_mm(x, depth, max(L_mm, 8.0)),
            waterbed_deflection_mm(x, depth, L_mm) - rng.uniform(0, 0.05) * np.log(x / 3.0),
        ][n % 4] + rng.normal(0.0, rng.choice([0.002, 0.005, 0.02]), x.size)
        problem = _Problem(x, y, depth, "clamped", ((x.max(), 1000 * x.max()), (1e-4, 10.0)))
        fine = problem.sse(_minimum(problem, (2 * _START_GRID[0], 2 * _START_GRID[1])))
        assert problem.sse(_minimum(problem)) <= fine * (1 + 1e-9)
        grid_L = np.linspace(problem.low[0], problem.high[0], _START_GRID[0])
        grid_lb = np.linspace(problem.low[1], problem.high[1], _START_GRID[1])
        assert problem.sse_many(grid_L[:, None], grid_lb[None, :]).min() > fine * (1 + 1e-6)
