"""The forward error model shared by the generator and the coverage study."""

from __future__ import annotations

import numpy as np
import pytest

from lineload.noise import NoiseModel
from lineload.simulation import coverage, errors, readings, subjects
from lineload.simulation.errors import TrialErrors, read_side_mm

X_MM = np.linspace(0.05, 3.0, 60)
DEPTH_MM = 1.5


def _profile(x_mm):
    """A smooth true profile, depth at the tip, falling to zero at 4 mm."""
    return DEPTH_MM * np.clip(1.0 - np.asarray(x_mm) / 4.0, 0.0, None) ** 2


@pytest.mark.parametrize("side", ["left", "right"])
def test_without_errors_the_reading_is_the_truth(side):
    read = read_side_mm(_profile, X_MM, side, DEPTH_MM, TrialErrors())
    np.testing.assert_array_equal(read, _profile(X_MM))


def test_each_error_enters_as_documented():
    truth = _profile(X_MM)
    tol = 1e-12
    # a vertical offset raises both sides alike
    for side in ("left", "right"):
        read = read_side_mm(_profile, X_MM, side, DEPTH_MM, TrialErrors(offset_mm=0.01))
        np.testing.assert_allclose(read - truth, 0.01, atol=tol)
    # a rotation raises one side as much as it lowers the other: the mean cancels it
    left, right = (
        read_side_mm(_profile, X_MM, side, DEPTH_MM, TrialErrors(rotation=0.002))
        for side in ("left", "right")
    )
    np.testing.assert_allclose(left - truth, -0.002 * X_MM, atol=tol)
    np.testing.assert_allclose(0.5 * (left + right), truth, atol=tol)
    # a shared tilt adds t |x| to both sides: the mean keeps it
    left, right = (
        read_side_mm(_profile, X_MM, side, DEPTH_MM, TrialErrors(shared_tilt=0.001))
        for side in ("left", "right")
    )
    np.testing.assert_allclose(0.5 * (left + right) - truth, 0.001 * X_MM, atol=tol)
    # a depth error scales the profile: the true indentation is depth + error
    read = read_side_mm(_profile, X_MM, "left", DEPTH_MM, TrialErrors(depth_error_mm=0.015))
    np.testing.assert_allclose(read, truth * (1.0 + 0.015 / DEPTH_MM), rtol=1e-12)
    # a misplaced wedge: the left side's distances too long, the right's too short
    for side, sign in (("left", 1.0), ("right", -1.0)):
        read = read_side_mm(_profile, X_MM, side, DEPTH_MM, TrialErrors(wedge_shift_mm=0.02))
        np.testing.assert_allclose(read, _profile(X_MM + sign * 0.02), atol=tol)


def test_no_reading_lands_past_the_wedge_tip():
    """A shift larger than the distance reads the tip itself: the depth, not beyond it."""
    shift = TrialErrors(wedge_shift_mm=0.2)
    read = read_side_mm(_profile, X_MM, "right", DEPTH_MM, shift)
    past = X_MM < 0.2
    assert past.any()
    np.testing.assert_array_equal(read[past], DEPTH_MM)
    assert errors.SEEN_FLOOR_MM == 0.0
    np.testing.assert_array_equal(errors.seen_distance_mm(X_MM, "right", 0.2)[past], 0.0)


def test_the_boussinesq_form_stays_finite_at_the_tip():
    """The coverage study's Boussinesq truth is evaluated off the tip, where it is infinite."""
    value = coverage._true_profile("boussinesq", np.array([0.0]), 1.0, {"A_mm": 0.3, "x0_mm": 6})
    assert np.isfinite(value).all()


def test_the_coverage_study_reads_with_the_shared_model(monkeypatch):
    """Coverage's readings are the shared model's: replacing it changes them."""
    only_offset = NoiseModel(
        reading_sd_mm=0.0, tracing_sd_mm=0.0, side_offset_sd_mm=0.0, shared_offset_sd_mm=0.01
    )
    rng_args = 5
    params = {"L_mm": 12.0}
    trial = coverage._read_trial(
        np.random.default_rng(rng_args),
        "arc",
        params,
        X_MM,
        DEPTH_MM,
        only_offset,
        coverage.SCENARIOS[0],
    )
    offset = np.random.default_rng(rng_args).normal(0.0, 1.0, 5)[3] * 0.01
    truth = coverage._true_profile("arc", X_MM, DEPTH_MM, params)
    expected = np.round((truth + offset) / coverage.RESOLUTION_MM) * coverage.RESOLUTION_MM
    np.testing.assert_allclose(trial["left_mm"], expected, atol=1e-12)
    monkeypatch.setattr(
        coverage, "read_side_mm", lambda profile, x, *args, **kwargs: np.zeros_like(x)
    )
    zeroed = coverage._read_trial(
        np.random.default_rng(rng_args),
        "arc",
        params,
        X_MM,
        DEPTH_MM,
        only_offset,
        coverage.SCENARIOS[0],
    )
    assert not np.any(zeroed["left_mm"])


def test_the_generator_reads_with_the_shared_model(monkeypatch):
    """The shipped readings come from the shared model: replacing it changes them."""
    subject = subjects.shipped_subjects()[0]
    plain = readings.profile_table(subject)
    monkeypatch.setattr(
        readings, "read_side_mm", lambda profile, x, *args, **kwargs: np.zeros_like(x)
    )
    zeroed = readings.profile_table(subject)
    assert not np.array_equal(plain["deflection_image_mm"], zeroed["deflection_image_mm"])
    # only the edges (the registration error alone) are left
    assert np.count_nonzero(zeroed["deflection_image_mm"]) <= 2 * len(subject.depths_mm)
