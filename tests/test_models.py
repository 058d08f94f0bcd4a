"""The model equations against their analytic identities and limits."""

import numpy as np
import pytest

from lineload import models


@pytest.mark.parametrize("depth_mm, L_mm", [(0.5, 10.0), (1.0, 12.5), (2.0, 15.0), (1.3, 4.0)])
class TestWaterbedParabola:
    def test_ends(self, depth_mm, L_mm):
        W = models.waterbed_deflection_mm([0.0, L_mm], depth_mm, L_mm)
        assert W[0] == pytest.approx(depth_mm)
        assert W[1] == pytest.approx(0.0, abs=1e-12)

    def test_zero_net_area(self, depth_mm, L_mm):
        # Simpson's rule is exact for a quadratic
        X = np.linspace(0.0, L_mm, 3)
        W = models.waterbed_deflection_mm(X, depth_mm, L_mm)
        area = (L_mm / 6.0) * (W[0] + 4 * W[1] + W[2])
        assert area == pytest.approx(0.0, abs=1e-12 * depth_mm * L_mm)

    def test_zero_crossing_at_third(self, depth_mm, L_mm):
        W = models.waterbed_deflection_mm([L_mm / 3.0], depth_mm, L_mm)
        assert W[0] == pytest.approx(0.0, abs=1e-12)
        # positive (downward) inside, negative (bulge) outside
        X = np.linspace(0, L_mm, 301)
        W = models.waterbed_deflection_mm(X, depth_mm, L_mm)
        assert np.all(W[X < L_mm / 3 - 1e-9] > 0)
        assert np.all(W[(X > L_mm / 3 + 1e-9) & (X < L_mm - 1e-9)] < 0)
        assert W.min() == pytest.approx(-depth_mm / 3.0, rel=1e-4)

    def test_largest_shift_at_third(self, depth_mm, L_mm):
        X = np.linspace(0.0, L_mm, 30001)
        U = models.waterbed_shift_mm(X, depth_mm, L_mm)
        assert U[0] == 0.0 and U[-1] == pytest.approx(0.0, abs=1e-15)
        assert X[np.argmax(np.abs(U))] == pytest.approx(L_mm / 3.0, abs=L_mm / 15000)
        assert np.abs(U).max() == pytest.approx(8 * depth_mm**2 / (9 * L_mm), rel=1e-8)
        exact = models.waterbed_shift_mm([L_mm / 3.0], depth_mm, L_mm)[0]
        assert exact == pytest.approx(-8 * depth_mm**2 / (9 * L_mm), rel=1e-12)

    def test_uniform_strain(self, depth_mm, L_mm):
        # Green strain U' + (U'^2 + W'^2)/2 with U' << 1: U' + W'^2/2 = 2 W0^2 / L^2
        X = np.linspace(0.01, 0.99, 99) * L_mm
        h = 1e-6 * L_mm
        dU = (
            models.waterbed_shift_mm(X + h, depth_mm, L_mm)
            - models.waterbed_shift_mm(X - h, depth_mm, L_mm)
        ) / (2 * h)
        dW = (
            models.waterbed_deflection_mm(X + h, depth_mm, L_mm)
            - models.waterbed_deflection_mm(X - h, depth_mm, L_mm)
        ) / (2 * h)
        strain = dU + dW**2 / 2
        assert np.allclose(strain, models.waterbed_strain(depth_mm, L_mm), rtol=1e-6)

    def test_zero_beyond_wall(self, depth_mm, L_mm):
        X = np.array([1.01, 2.0, 10.0]) * L_mm
        assert np.all(models.waterbed_deflection_mm(X, depth_mm, L_mm) == 0)
        assert np.all(models.waterbed_shift_mm(X, depth_mm, L_mm) == 0)

    def test_load_angle_matches_slope(self, depth_mm, L_mm):
        h = 1e-7 * L_mm
        slope = (models.waterbed_deflection_mm([h], depth_mm, L_mm)[0] - depth_mm) / h
        assert np.tan(models.waterbed_load_angle_rad(depth_mm, L_mm)) == pytest.approx(
            -slope, rel=1e-5
        )


@pytest.mark.parametrize("depth_mm, L_mm", [(0.5, 10.0), (1.0, 12.5), (2.0, 10.0), (1.3, 4.0)])
class TestShiftedParabola:
    """Eq. 19 placed at the deformed position x = X + U(X) (eq. 20)."""

    def test_resting_position_inverts_the_shift(self, depth_mm, L_mm):
        X = np.linspace(0.0, L_mm, 201)
        x = X + models.waterbed_shift_mm(X, depth_mm, L_mm)
        assert np.allclose(models.resting_position_mm(x, depth_mm, L_mm), X, atol=1e-12 * L_mm)

    def test_is_eq_19_at_the_resting_position(self, depth_mm, L_mm):
        X = np.linspace(0.0, L_mm, 201)
        x = X + models.waterbed_shift_mm(X, depth_mm, L_mm)
        assert np.allclose(
            models.shifted_deflection_mm(x, depth_mm, L_mm),
            models.waterbed_deflection_mm(X, depth_mm, L_mm),
            atol=1e-12 * depth_mm,
        )

    def test_ends_and_zero_crossing(self, depth_mm, L_mm):
        W = models.shifted_deflection_mm([0.0, L_mm, 2.0 * L_mm], depth_mm, L_mm)
        assert W[0] == pytest.approx(depth_mm) and W[1] == pytest.approx(0.0, abs=1e-12)
        assert W[2] == 0.0  # beyond the wall nothing moves
        # the zero of W sits at X = L/3, seen at x = L/3 + U(L/3) = L/3 - 8 W0^2 / (9 L)
        x_zero = L_mm / 3.0 - 8.0 * depth_mm**2 / (9.0 * L_mm)
        assert models.shifted_deflection_mm(x_zero, depth_mm, L_mm) == pytest.approx(
            0.0, abs=1e-12 * depth_mm
        )

    def test_same_bulge_depth_as_eq_19(self, depth_mm, L_mm):
        # only the horizontal positions move: the deepest bulge is still -W0/3
        x = np.linspace(0.0, L_mm, 20001)
        W = models.shifted_deflection_mm(x, depth_mm, L_mm)
        assert W.min() == pytest.approx(-depth_mm / 3.0, rel=1e-6)


def test_shifted_parabola_of_a_flat_membrane_is_flat():
    x = np.array([0.0, 0.5, 3.0])
    assert np.all(models.shifted_deflection_mm(x, 1.0, np.inf) == 1.0)
    assert np.array_equal(models.resting_position_mm(x, 1.0, np.inf), x)


def test_shift_is_one_to_one_below_the_fold_only():
    depth_mm = 1.0
    fold_mm = np.sqrt(6.0) * depth_mm
    assert models.shift_is_one_to_one(depth_mm, fold_mm * 1.001)
    assert not models.shift_is_one_to_one(depth_mm, fold_mm * 0.999)
    # just inside: x(X) is increasing; just outside: it decreases near the load
    for L_mm, increasing in ((fold_mm * 1.001, True), (fold_mm * 0.999, False)):
        X = np.linspace(0.0, L_mm, 100001)
        x = X + models.waterbed_shift_mm(X, depth_mm, L_mm)
        assert bool(np.all(np.diff(x) > 0)) is increasing
    assert np.isnan(models.shifted_deflection_mm([0.5, 1.0], depth_mm, fold_mm * 0.999)).all()


def test_resting_position_converges_for_every_admissible_ratio():
    # k = 6 (W0/L)^2 anywhere in [0, 1), t = x/L anywhere in [0, 1]
    k = np.linspace(0.0, 1.0 - 1e-9, 401)[:, None]
    t = np.linspace(0.0, 1.0, 401)[None, :]
    L_mm = 1.0
    depth_mm = np.sqrt(k / 6.0) * L_mm
    X = np.stack([models.resting_position_mm(t[0], d, L_mm) for d in depth_mm[:, 0]])
    s = X / L_mm
    residual = s - k * s * (s - 1.0) ** 2 - t
    assert np.all(np.isfinite(X)) and np.max(np.abs(residual)) < 1e-13


class TestArc:
    @pytest.mark.parametrize("delta", [0.01, 0.05, 0.1, 0.2, 0.3, 0.5])
    def test_passes_through_ends_and_encloses_zero_area(self, delta):
        L_mm = 12.0
        depth_mm = delta * L_mm
        x = np.linspace(0.0, L_mm, 200001)
        w = models.arc_deflection_mm(x, depth_mm, L_mm)
        assert w[0] == pytest.approx(depth_mm, rel=1e-9)
        assert w[-1] == pytest.approx(0.0, abs=1e-9 * depth_mm)
        assert np.trapezoid(w, x) == pytest.approx(0.0, abs=1e-6 * depth_mm * L_mm)

    @pytest.mark.parametrize("delta", [0.05, 0.2, 0.4])
    def test_is_a_circle(self, delta):
        L_mm, depth_mm = 10.0, delta * 10.0
        g = models.arc_geometry(depth_mm, L_mm)
        x = np.linspace(0, L_mm, 101)
        z = -models.arc_deflection_mm(x, depth_mm, L_mm)
        distance = np.hypot(x - g["centre_x_mm"], z - g["centre_z_mm"])
        assert np.allclose(distance, g["radius_mm"], rtol=1e-10)

    def test_tends_to_parabola(self):
        L_mm = 10.0
        x = np.linspace(0, L_mm, 4001)
        gaps = []
        for delta in [0.4, 0.2, 0.1, 0.05, 0.025, 0.0125]:
            depth_mm = delta * L_mm
            arc = models.arc_deflection_mm(x, depth_mm, L_mm)
            parabola = models.waterbed_deflection_mm(x, depth_mm, L_mm)
            gaps.append(np.max(np.abs(arc - parabola)) / depth_mm)
        gaps = np.array(gaps)
        assert np.all(np.diff(gaps) < 0)
        # the relative gap falls like delta^2: halving delta divides it by about 4
        assert np.allclose(gaps[1:] / gaps[:-1], 0.25, atol=0.03)
        assert gaps[-1] < 1e-3

    def test_curvature_matches_parabola_in_the_limit(self):
        # parabola curvature W'' = 6 W0 / L^2; circle curvature 1/R
        L_mm, depth_mm = 10.0, 0.01
        g = models.arc_geometry(depth_mm, L_mm)
        assert 1.0 / g["radius_mm"] == pytest.approx(6 * depth_mm / L_mm**2, rel=1e-3)

    def test_folded_arc_is_not_a_graph(self):
        assert not bool(models.arc_geometry(3.0, 3.0)["is_graph"])
        assert np.all(np.isnan(models.arc_deflection_mm([0.5, 1.0], 3.0, 3.0)))


class TestBoussinesq:
    def test_zero_at_x0_and_log_linear(self):
        x = np.array([0.1, 1.0, 10.0])
        w = models.boussinesq_deflection_mm(x, 0.3, 4.0)
        assert models.boussinesq_deflection_mm([4.0], 0.3, 4.0)[0] == 0.0
        # equal steps in log distance give equal drops of A ln 10
        assert np.allclose(-np.diff(w), 0.3 * np.log(10.0))


def test_every_fitted_model_is_named_once_and_styled():
    from lineload.figures import style, supplements
    from lineload.fitting import batch as fitting
    from lineload.fitting import sensitivity
    from lineload.publishing import tables

    assert set(fitting.MODELS) == set(models.MODELS) == set(supplements.REFIT_COLOURS)
    assert sensitivity.MODELS == models.MODELS
    assert set(models.TABLE_MODELS) <= set(models.MODELS)
    assert list(style.MODEL_COLOURS) == list(style.MODEL_NAMES) == list(models.TABLE_MODELS)
    for model in models.TABLE_MODELS:
        assert models.MODEL_NAMES[model].legend and style.MODEL_NAMES[model]
    assert [label for _, label in tables.MODELS] == ["waterbed", "exact arc", "Boussinesq"]
