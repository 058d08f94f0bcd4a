"""The noise model: measured from left-right differences, and the covariance it implies."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from lineload.io import config_defaults
from lineload.models import arc_deflection_mm, boussinesq_deflection_mm, waterbed_deflection_mm
from lineload.noise import (
    MEASURED,
    UNMEASURED,
    NoiseModel,
    constant_explained,
    draw_side_errors_mm,
    estimate_noise,
    model_from_rows,
    noise_rows,
    registration_rows,
    trial_differences,
    trial_models,
)
from lineload.simulation import coverage, synthetic

REPO = Path(__file__).resolve().parents[1]
GRID_MM = synthetic.reading_distances_mm(3.2)


def simulated_differences(truth, n_trials, seed, rotation_sd=0.0, asymmetry=0.0):
    """Left-right differences of ``n_trials`` parabolas read with ``truth``'s side errors.

    ``rotation_sd`` adds a rotation per trial; ``asymmetry`` makes the sides' spans
    differ by that fraction (a true, smooth difference between the sides).
    """
    rng = np.random.default_rng(seed)
    trials = []
    for _ in range(n_trials):
        L_mm = rng.uniform(8.0, 14.0)
        rotation = rng.normal(0.0, rotation_sd)
        left = 1.0 * (1 - GRID_MM / (L_mm * (1 + asymmetry))) ** 2 - rotation * GRID_MM
        right = 1.0 * (1 - GRID_MM / (L_mm * (1 - asymmetry))) ** 2 + rotation * GRID_MM
        left = left + draw_side_errors_mm(rng, GRID_MM, truth)
        right = right + draw_side_errors_mm(rng, GRID_MM, truth)
        trials.append(trial_differences(GRID_MM, left, right))
    return trials


TRUTH = NoiseModel(
    reading_sd_mm=0.008, tracing_sd_mm=0.006, tracing_length_mm=0.5, side_offset_sd_mm=0.005
)


def test_estimate_recovers_the_reading_and_tracing_errors():
    estimate = estimate_noise(simulated_differences(TRUTH, 150, seed=1))
    for name in ("reading_sd_mm", "tracing_sd_mm"):
        value, se = getattr(estimate.model, name), estimate.se[name]
        assert math.isfinite(se) and se > 0
        assert abs(value - getattr(TRUTH, name)) < 4 * se, name


def test_trials_sharing_a_grid_share_one_factorisation():
    # the likelihood factorises each distinct reading grid once; it must equal the sum
    # of every trial's own likelihood, on a dataset whose trials are read on three grids
    from lineload.noise import _covariances, _padded, _restricted_terms

    trials = simulated_differences(TRUTH, 12, seed=4)
    thinned = []
    for i, (x, d, slope) in enumerate(trials):
        keep = np.arange(x.size) % 3 != i % 3 if i % 4 else np.ones(x.size, dtype=bool)
        thinned.append((x[keep], d[keep], slope[keep]))
    trials = thinned
    x, d, design, real, grids, group = _padded(trials)
    assert len(grids[0]) == 4  # the full grid and three thinned ones
    theta = np.log([0.008, 0.006, 0.5])
    together = _restricted_terms(theta, d, design, grids, group)[0]
    alone = 0.0
    for trial in trials:
        _, d_one, design_one, _, grids_one, group_one = _padded([trial])
        alone += _restricted_terms(theta, d_one, design_one, grids_one, group_one)[0]
    # both whiten with the inverse Cholesky factor of the same matrices: rounding grows
    # with its condition number and with the number of terms summed
    condition = np.linalg.cond(_covariances(theta, *grids)).max()
    tolerance = np.finfo(float).eps * math.sqrt(condition) * real.sum() * abs(alone)
    assert abs(together - alone) <= tolerance
    # and a trial given another trial's grid would not agree
    wrong = group.copy()
    wrong[0], wrong[1] = group[1], group[0]
    assert group[0] != group[1]
    misassigned = _restricted_terms(theta, d, design, grids, wrong)[0]
    assert abs(misassigned - alone) > 100 * tolerance


def test_rotation_and_a_smooth_asymmetry_are_not_taken_for_noise():
    # the same reading errors with and without large rotations and sides of different
    # spans (a line and a parabola in their difference): the fixed effects take those
    # exactly, so the measured noise does not change (to the optimiser's precision)
    white = NoiseModel(reading_sd_mm=0.008)
    plain = estimate_noise(simulated_differences(white, 80, seed=2)).model
    trials = simulated_differences(white, 80, seed=2, rotation_sd=0.01, asymmetry=0.05)
    disturbed = estimate_noise(trials).model
    for name in ("reading_sd_mm", "tracing_sd_mm"):
        assert getattr(disturbed, name) == pytest.approx(getattr(plain, name), rel=1e-4)
    assert plain.reading_sd_mm == pytest.approx(0.008, rel=0.1)
    assert plain.tracing_sd_mm < plain.reading_sd_mm / 2  # mostly independent, as drawn
    # the differences themselves are far from white noise of 0.008 mm: without the fixed
    # effects the rotation and the asymmetry would count as noise (the check can fail)
    raw = np.concatenate([d for _, d, _ in trials])
    assert np.std(raw) / math.sqrt(2) > 3 * 0.008


def test_the_side_offsets_and_the_rotation_are_not_measured():
    """Their traces in a trial's difference (a constant, a line) are nearly reproduced by
    the terms each trial must leave free, so the fit reports neither, whatever their size;
    the noise table says so and names the prior that stands for each."""
    offsets = NoiseModel(reading_sd_mm=0.004, side_offset_sd_mm=0.01)
    estimate = estimate_noise(simulated_differences(offsets, 100, seed=3, rotation_sd=0.005))
    assert estimate.model.side_offset_sd_mm == 0.0
    assert estimate.model.rotation_sd == 0.0
    assert set(estimate.se) == set(MEASURED)
    # the offsets and rotations went into the fixed effects, not into the reading error
    # (its SE from 100 trials of about 16 differences is a few per cent)
    assert estimate.model.reading_sd_mm == pytest.approx(0.004, rel=0.15)
    rows = {r["parameter"]: r for r in noise_rows(estimate, PRIORS)}
    for name in UNMEASURED:
        assert rows[name]["source"].startswith("not measured"), name
        assert math.isnan(rows[name]["se"])
    assert rows["side_offset_sd_mm"]["value"] == 0.0
    # where one side alone was read, the shared tilt's prior stands for the rotation
    assert rows["rotation_sd"]["value"] == PRIORS["shared_tilt_sd"]


@pytest.mark.parametrize("deflection", [arc_deflection_mm, waterbed_deflection_mm])
def test_a_constant_is_not_told_from_the_other_terms_of_a_membrane_difference(deflection):
    """Why the side offsets are not measured: on the reading grid inside the window, a
    slope, a parabola and a multiple of a membrane's slope (the wedge term, the slope as
    trial_differences takes it from the mean) reproduce a constant to within a few parts
    in ten thousand of its sum of squares, over the paper's depths and spans; the
    residual of a 4 um side offset is then well under the 0.1 um a reading could show.
    The same measure on a log-shaped profile, whose slope is far from a line near the
    wedge, leaves a part a difference could see: the check can come out the other way."""
    x = GRID_MM[GRID_MM <= 3.0]
    for depth_mm in (0.5, 1.0, 2.0):
        for L_mm in (8.0, 12.0, 16.0):
            w = deflection(x, depth_mm, L_mm)
            distance, _, slope = trial_differences(x, w, w)
            assert 1.0 - constant_explained(distance, slope) < 2e-4, (depth_mm, L_mm)
    w = boussinesq_deflection_mm(x, 0.3, 5.0)
    distance, _, slope = trial_differences(x, w, w)
    assert 1.0 - constant_explained(distance, slope) > 1e-2


def test_average_covariance_matches_the_spread_of_simulated_averages():
    # every error of the model, drawn many times: the covariance of the left-right mean
    # is what average_covariance_mm2 says, entry by entry, within Monte-Carlo error
    model = NoiseModel(
        reading_sd_mm=0.008,
        tracing_sd_mm=0.005,
        tracing_length_mm=0.5,
        side_offset_sd_mm=0.004,
        rotation_sd=0.001,
        shared_offset_sd_mm=0.005,
        shared_tilt_sd=0.001,
        depth_sd_mm=0.02,
    )
    x = GRID_MM[::3]
    depth_mm = 1.0
    profile = depth_mm * (1 - x / 10.0) ** 2
    rng = np.random.default_rng(4)
    n = 20000
    draws = np.empty((n, x.size))
    for i in range(n):
        rotation = rng.normal(0.0, model.rotation_sd)
        shared = (
            rng.normal(0.0, model.shared_offset_sd_mm) + rng.normal(0.0, model.shared_tilt_sd) * x
        )
        scale = rng.normal(0.0, model.depth_sd_mm) / depth_mm
        left = draw_side_errors_mm(rng, x, model) - rotation * x
        right = draw_side_errors_mm(rng, x, model) + rotation * x
        draws[i] = 0.5 * (left + right) + shared + scale * profile
    empirical = np.cov(draws.T)
    predicted = model.average_covariance_mm2(x, np.full(x.size, 2), profile, depth_mm)
    # an entry's sampling SD is about sqrt((s_ii s_jj + s_ij^2) / n)
    diagonal = np.diag(predicted)
    spread = np.sqrt((np.outer(diagonal, diagonal) + predicted**2) / n)
    assert np.all(np.abs(empirical - predicted) < 5 * spread)
    # leaving out the shared parts would be refuted by the same draws
    partial = NoiseModel(**{**model.as_dict(), "shared_offset_sd_mm": 0.0, "depth_sd_mm": 0.0})
    missing = partial.average_covariance_mm2(x, np.full(x.size, 2), profile, depth_mm)
    assert np.any(np.abs(empirical - missing) > 5 * spread)


#: The config's priors (their schema defaults).
PRIORS = {k: v for k, v in config_defaults("noise").items() if k != "max_trials"}


def test_the_side_offsets_fold_into_the_shared_offset_where_both_sides_were_read():
    """The mean of two sides carries half the side offsets' variance as a constant, as the
    shared offset is: stated as one prior, sqrt(shared**2 + side**2 / 2), the covariance
    of a mean read on both sides is the same matrix."""
    model = NoiseModel(
        reading_sd_mm=0.008,
        tracing_sd_mm=0.005,
        side_offset_sd_mm=0.004,
        shared_offset_sd_mm=0.005,
        depth_sd_mm=0.01,
    )
    stated = model.as_stated()
    assert stated.side_offset_sd_mm == 0.0
    assert stated.shared_offset_sd_mm == pytest.approx(math.sqrt(0.005**2 + 0.004**2 / 2))
    x = GRID_MM[::3]
    profile = (1 - x / 10.0) ** 2
    both = np.full(x.size, 2)
    np.testing.assert_allclose(
        stated.average_covariance_mm2(x, both, profile, 1.0),
        model.average_covariance_mm2(x, both, profile, 1.0),
        rtol=1e-12,
    )
    # registration alone would leave out a part of the constant the mean carries
    alone = model.with_priors(side_offset_sd_mm=0.0).average_covariance_mm2(x, both, profile, 1.0)
    assert np.all(alone < model.average_covariance_mm2(x, both, profile, 1.0))


def test_noise_table_reads_back_and_refuses_a_bad_value():
    estimate = estimate_noise(simulated_differences(TRUTH, 30, seed=5))
    rows = noise_rows(estimate, PRIORS)
    model = model_from_rows(rows)
    assert model.reading_sd_mm == estimate.model.reading_sd_mm
    assert model.depth_sd_mm == 0.01
    sources = {r["parameter"]: r["source"] for r in rows}
    assert sources["depth_sd_mm"].startswith("prior") and sources["reading_sd_mm"].startswith(
        "measured"
    )
    assert sources["wedge_position_sd_mm"].startswith("prior")
    bad = [dict(r) for r in rows]
    bad[0]["value"] = "-1"
    with pytest.raises(ValueError, match="reading_sd_mm"):
        model_from_rows(bad)
    with pytest.raises(ValueError, match="lacks"):
        model_from_rows(rows[1:])


def test_too_few_trials_are_refused():
    with pytest.raises(ValueError, match="at least two trials"):
        estimate_noise(simulated_differences(TRUTH, 1, seed=6))


def test_a_slice_of_the_committed_coverage_study_reproduces():
    # dataset 0 of the first scenario and model, rerun: the same intervals as the
    # committed table, to the precision of the noise estimate's optimiser (L-BFGS-B's
    # default ftol 2.2e-9 leaves the noise parameters good to about sqrt(ftol) = 5e-5
    # relative; the interval ends move less than that, bounded here by 1e-3 of L)
    path = REPO / "docs" / "calibration" / "coverage_trials.csv"
    with open(path, newline="") as handle:
        committed = [
            r
            for r in csv.DictReader(handle)
            if r["scenario"] == coverage.SCENARIOS[0].name
            and r["model"] == "waterbed"
            and r["dataset"] == "0"
        ]
    seed = 2026  # the calibration config's seed (docs/calibration/coverage.md)
    rows = coverage.coverage_rows("waterbed", (seed, 0, 0, 0))
    assert len(rows) == len(committed) == 26
    for new, old in zip(rows, committed, strict=True):
        assert new["true"] == pytest.approx(float(old["true"]), rel=1e-9)  # 10 digits written
        for end in ("low", "high"):
            assert new[end] == pytest.approx(float(old[end]), rel=1e-3)


def test_a_digitised_trials_registration_replaces_the_shared_offset_prior():
    estimate = estimate_noise(simulated_differences(TRUTH, 30, seed=5))
    rows = noise_rows(estimate, PRIORS) + registration_rows(
        [("P1", 1.0, 0.0015, "P1.json")], estimate.n_trials, estimate.n_differences
    )
    dataset = model_from_rows(rows)  # the trial's row does not touch the dataset's model
    assert dataset.shared_offset_sd_mm == PRIORS["shared_offset_sd_mm"]
    models = trial_models(rows, [("P1", 1.0), ("P1", 2.0), ("M1", 1.0)])
    assert models[0].shared_offset_sd_mm == 0.0015
    assert models[0].reading_sd_mm == dataset.reading_sd_mm
    assert models[1] == dataset and models[2] == dataset
    assert rows[-1]["scope"] == "P1 at 1 mm" and "registration" in rows[-1]["source"]
    # the covariance of that trial's mean is smaller by the offsets' difference alone
    x = GRID_MM[:10]
    gap = dataset.average_covariance_mm2(x, np.full(10, 2), x, 1.0) - models[
        0
    ].average_covariance_mm2(x, np.full(10, 2), x, 1.0)
    assert np.allclose(gap, PRIORS["shared_offset_sd_mm"] ** 2 - 0.0015**2)
    bad = [*rows[:-1], {**rows[-1], "value": "-1"}]
    with pytest.raises(ValueError, match="P1 at 1 mm"):
        trial_models(bad, [("P1", 1.0)])
    # a dataset prior such as the wedge's position cannot be set per trial
    wedge = [*rows[:-1], {**rows[-1], "parameter": "wedge_position_sd_mm"}]
    with pytest.raises(ValueError, match="expected shared_offset_sd_mm"):
        trial_models(wedge, [("P1", 1.0)])


def test_the_bootstrap_reads_and_fits_each_trial_with_its_own_noise():
    # two copies of one fitted trial; the first has its own, far larger shared offset
    # (as a photographed trial carries its registration error): its replicates are read
    # with it and its intervals honour it, so they come out wider than the second's
    grid = synthetic.reading_distances_mm(3.5)
    base = NoiseModel(reading_sd_mm=0.005, tracing_sd_mm=0.003, tracing_length_mm=0.3)
    own = base.with_priors(shared_offset_sd_mm=0.03)
    trial = {"species": "monkey", "depth_mm": 1.0, "distance_mm": grid, "waterbed": {"L_mm": 12.0}}
    rows = coverage.bootstrap_study(
        [{**trial, "noise": own}, trial, trial], 7, 3, base, models=("waterbed",)
    )
    width = {0: [], 1: []}
    for i, row in enumerate(rows):
        if i % 3 < 2:
            width[i % 3].append(row["high"] - row["low"])
    assert min(width[0]) > 3 * max(width[1])


def test_a_digitised_trials_own_reading_error_replaces_the_datasets():
    """A photographed trial's readings carry the digitiser's own error: it takes the place
    of the dataset's measured reading error for that trial (not added to it), and its
    mean's covariance moves by exactly the difference on the diagonal."""
    estimate = estimate_noise(simulated_differences(TRUTH, 30, seed=5))
    rows = noise_rows(estimate, PRIORS) + registration_rows(
        [("P1", 1.0, 0.0015, "P1.json", 0.02), ("P2", 1.0, 0.0015, "P2.json", None)],
        estimate.n_trials,
        estimate.n_differences,
    )
    assert [r["parameter"] for r in rows if r["scope"] != "dataset"] == [
        "shared_offset_sd_mm",
        "reading_sd_mm",
        "shared_offset_sd_mm",
    ]
    dataset = model_from_rows(rows)
    own, without = trial_models(rows, [("P1", 1.0), ("P2", 1.0)])
    assert own.reading_sd_mm == 0.02 and without.reading_sd_mm == dataset.reading_sd_mm
    x = GRID_MM[:10]
    sides = np.array([2, 2, 2, 2, 2, 1, 1, 2, 2, 2])
    gap = own.average_covariance_mm2(x, sides, x, 1.0) - without.average_covariance_mm2(
        x, sides, x, 1.0
    )
    expected = np.diag((0.02**2 - dataset.reading_sd_mm**2) / sides)
    np.testing.assert_allclose(gap, expected, rtol=0, atol=1e-15)


def _reference_covariance(model, x, sides, w, depth_mm):
    """The covariance of a left-right mean written out term by term, one trial."""
    n = x.size
    both = sides >= 2
    covariance = np.zeros((n, n))
    for i in range(n):
        for j in range(n):
            apart = abs(x[i] - x[j])
            if apart == 0:
                kernel = 1.0
            elif model.tracing_length_mm == 0:
                kernel = 0.0
            else:
                kernel = np.exp(-apart / model.tracing_length_mm)
            side = (
                model.reading_sd_mm**2 * (i == j)
                + model.tracing_sd_mm**2 * kernel
                + model.side_offset_sd_mm**2
            )
            # both sides read at both points: the mean halves each side's error
            shared = 2.0 if both[i] and both[j] else 1.0
            covariance[i, j] = side * shared / max(sides[i] * sides[j], 1.0)
            if i == j and not both[i]:
                covariance[i, j] += (model.rotation_sd * x[i]) ** 2
            scale_i = max(w[i], 0.0) / depth_mm if depth_mm > 0 else 0.0
            scale_j = max(w[j], 0.0) / depth_mm if depth_mm > 0 else 0.0
            covariance[i, j] += (
                model.shared_offset_sd_mm**2
                + model.shared_tilt_sd**2 * x[i] * x[j]
                + model.depth_sd_mm**2 * scale_i * scale_j
            )
    return covariance


def test_covariances_of_many_trials_are_each_trials_own_and_zero_in_the_padding():
    from lineload.noise import NoiseModel, average_covariances_mm2

    rng = np.random.default_rng(4)
    models = [
        NoiseModel(
            reading_sd_mm=0.01, tracing_sd_mm=0.004, tracing_length_mm=0.4, depth_sd_mm=0.01
        ),
        NoiseModel(reading_sd_mm=0.02, rotation_sd=0.001, shared_offset_sd_mm=0.006),
        # a zero tracing length: white noise, not NaN
        NoiseModel(
            reading_sd_mm=0.005, tracing_sd_mm=0.003, tracing_length_mm=0.0, depth_sd_mm=0.01
        ),
    ]
    lengths = (7, 3, 5)
    width = max(lengths) + 2
    x = np.full((3, width), np.nan)
    sides = np.full((3, width), 7.0)  # the padding's values must not matter
    w = np.full((3, width), 99.0)
    for t, n in enumerate(lengths):
        x[t, :n] = np.sort(rng.uniform(0.05, 3.0, n))
        sides[t, :n] = rng.choice([1.0, 2.0], n)
        w[t, :n] = rng.uniform(0.0, 1.0, n)
    depth = np.array([1.0, 0.5, 2.0])
    together = average_covariances_mm2(models, x, sides, w, depth)
    for t, n in enumerate(lengths):
        alone = models[t].average_covariance_mm2(x[t, :n], sides[t, :n], w[t, :n], depth[t])
        np.testing.assert_array_equal(together[t, :n, :n], alone)
        assert np.all(together[t, n:, :] == 0.0) and np.all(together[t, :, n:] == 0.0)
        assert np.all(np.isfinite(alone))
        np.testing.assert_allclose(
            alone, _reference_covariance(models[t], x[t, :n], sides[t, :n], w[t, :n], depth[t]),
            rtol=1e-12, atol=0.0,
        )  # fmt: skip
        np.testing.assert_allclose(alone, alone.T)
        assert np.all(np.linalg.eigvalsh(alone) > 0)
    # and what goes in moves it: the rotation reaches one-sided points only
    one_sided = sides[1, :3] == 1.0
    plain = models[1].average_covariance_mm2(x[1, :3], sides[1, :3], w[1, :3], depth[1])
    turned = NoiseModel(reading_sd_mm=0.02, shared_offset_sd_mm=0.006).average_covariance_mm2(
        x[1, :3], sides[1, :3], w[1, :3], depth[1]
    )
    np.testing.assert_array_equal(np.diag(plain) > np.diag(turned), one_sided)


def awkward_trials(model, seed=5):
    """Trials on several grids (thinned, jittered, of 5 to 40 points, so that shorter
    ones are padded) and two flat ones whose slope column is dead."""
    rng = np.random.default_rng(seed)
    trials = []
    for k, (x, d, slope) in enumerate(simulated_differences(model, 12, seed=seed)):
        keep = slice(None, None, 1 + k % 3)
        x, d, slope = x[keep][: 5 + 3 * k], d[keep][: 5 + 3 * k], slope[keep][: 5 + 3 * k]
        if k % 4 == 1:  # a grid of its own
            x = x + rng.uniform(0.0, 0.01, x.size).cumsum()
        if k in (2, 7):  # a flat profile: its slope term is zero
            slope = np.zeros_like(slope)
        trials.append((x, d, slope))
    return trials


def test_the_score_is_the_derivative_of_the_restricted_likelihood():
    # the analytic gradient the optimiser uses, against central differences of the
    # objective (check_score), on regular trials and on awkward ones
    from lineload.noise import _padded, _restricted_terms

    model = NoiseModel(reading_sd_mm=0.008, tracing_sd_mm=0.006, tracing_length_mm=0.5)
    thetas = np.log([[0.008, 0.006, 0.5], [0.02, 0.001, 0.1], [0.003, 0.01, 2.0]])
    for trials in (simulated_differences(model, 30, seed=3), awkward_trials(model)):
        _, d, design, _, grids, group = _padded(trials)
        check_score(_restricted_terms, thetas, d, design, grids, group)
    # the awkward set is what it says: padding, several grids, dead slope columns
    _, d, design, real, grids, group = _padded(awkward_trials(model))
    assert not real.all() and len(grids[0]) > 3
    assert _restricted_terms(thetas[0], d, design, grids, group)[3][:, 2].sum() == 2


def check_score(terms, thetas, d, design, grids, group, step=1e-5):
    """Central differences err by about h^2 |f'''| / 6 (truncation; the third derivative
    by log-parameters taken as at most |f|) plus eps |f| / h (rounding): the bound is
    loose by a factor of ten or more, and a score off by 0.1 % exceeds it."""
    for theta in thetas:
        value, *_, score = terms(theta, d, design, grids, group, gradient=True)
        assert value == terms(theta, d, design, grids, group)[0]
        tolerance = 100 * np.finfo(float).eps * abs(value) / step + step**2 * abs(value)
        for k in range(3):
            e = np.eye(3)[k] * step
            central = (
                terms(theta + e, d, design, grids, group)[0]
                - terms(theta - e, d, design, grids, group)[0]
            ) / (2 * step)
            assert abs(score[k] - central) <= tolerance
            assert abs(1.001 * score[k] - central) > tolerance or abs(score[k]) < 1e-6
