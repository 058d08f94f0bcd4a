"""The verdict calibration: truth without errors, counts, and the committed table."""

import csv

import numpy as np
import pandas as pd
import pytest

from conftest import REPO
from lineload.claims import FAILS, HOLDS, IDENTITY, UNTESTABLE
from lineload.claims.registry import TRUTH_NOT_COMPUTED
from lineload.io import config_defaults
from lineload.publishing import article
from lineload.simulation import calibration, synthetic
from lineload.simulation.rates import binomial_interval

PRIORS = {k: v for k, v in config_defaults("noise").items() if k != "max_trials"}
MAX_TRIALS = config_defaults("noise")["max_trials"]
WINDOW_MM = 3.0
COMMITTED = REPO / "docs" / "calibration"


def claims_of(seed, errors=True):
    table = calibration.reconstruction_claims(seed, WINDOW_MM, PRIORS, MAX_TRIALS, errors=errors)
    return dict(zip(table["claim"], table["verdict"], strict=True))


def test_error_free_readings_are_the_true_profile_on_the_same_grid():
    subject = synthetic.shipped_subjects()[0]
    read = synthetic.profile_table(subject, seed=7)
    true = synthetic.profile_table(subject, seed=7, errors=False)
    # the same reading grid: the errors change the values only
    assert read["distance_image_mm"].tolist() == true["distance_image_mm"].tolist()
    first = true[(true["depth_mm"] == subject.depths_mm[0]) & (true["side"] == "right")]
    trial = synthetic.trial_parameters(subject, subject.depths_mm[0])
    x_mm = first["distance_image_mm"].to_numpy() / synthetic.MAGNIFICATION
    expected = synthetic.true_reading_mm(x_mm[:-1], trial, "right", (0.0, 0.0, 0.0))
    np.testing.assert_allclose(
        first["deflection_image_mm"].to_numpy()[:-1] / synthetic.MAGNIFICATION,
        expected,
        rtol=1e-12,
        atol=1e-15,
    )
    # ... and the errors are there when asked for: readings differ by about their noise
    gap = (read["deflection_image_mm"] - true["deflection_image_mm"]) / synthetic.MAGNIFICATION
    assert 0.002 < float(np.std(gap)) < 0.05


def test_shipped_verdicts_and_their_truth_are_the_generators_list():
    # the claims of the shipped seed, with and without errors, analysed in memory as the
    # workflow analyses the files; data/built_in_verdicts.json states both
    # (the claims whose fits the reconstructions do not make, C12 and C13, are listed
    # with their truth not computed)
    built_in = {
        row["claim"]: row
        for row in synthetic.built_in_verdicts()
        if row["truth"] != TRUTH_NOT_COMPUTED
    }
    read, true = claims_of(synthetic.DEFAULT_SEED), claims_of(synthetic.DEFAULT_SEED, False)
    assert read == {claim: row["verdict"] for claim, row in built_in.items()}
    assert true == {claim: row["truth"] for claim, row in built_in.items()}
    # the truth never hedges: without errors every rule commits
    assert UNTESTABLE not in true.values()


def rows(*entries):
    """Rows as verdict_study writes them: (dataset, claim, truth, verdict)."""
    opposite = {HOLDS: FAILS, FAILS: HOLDS}
    return [
        {"dataset": d, "claim": c, "truth": t, "verdict": v, "wrong": v == opposite.get(t)}
        for d, c, t, v in entries
    ]


def test_summary_counts_each_verdict_and_only_opposite_ones_as_wrong():
    study = rows(
        (0, "C1", HOLDS, HOLDS),
        (1, "C1", HOLDS, FAILS),
        (2, "C1", HOLDS, UNTESTABLE),
        (3, "C1", HOLDS, HOLDS),
        (0, "C7", IDENTITY, IDENTITY),
        (1, "C7", IDENTITY, IDENTITY),
        (2, "C7", IDENTITY, IDENTITY),
        (3, "C7", IDENTITY, IDENTITY),
        (0, "C10", FAILS, FAILS),
        (1, "C10", FAILS, FAILS),
        (2, "C10", FAILS, HOLDS),
        (3, "C10", FAILS, UNTESTABLE),
    )
    summary = {row["claim"]: row for row in calibration.summarise_verdicts(study)}
    c1 = summary["C1"]
    assert (c1["n_holds"], c1["n_fails"], c1["n_untestable"], c1["n_wrong"]) == (2, 1, 1, 1)
    assert (c1["wrong_ci_low"], c1["wrong_ci_high"]) == pytest.approx(binomial_interval(1, 4))
    assert summary["C7"]["n_wrong"] == 0
    assert summary["C10"]["n_wrong"] == 1
    # datasets 1 and 2 each had a wrong verdict
    assert (summary["any"]["n_wrong"], summary["any"]["n_datasets"]) == (2, 4)
    # the article quotes each claim's rate beside its verdict; identities are not evidence
    coverage = pd.read_csv(COMMITTED / "coverage.csv")
    bootstrap = pd.read_csv(COMMITTED / "bootstrap.csv")
    facts = article._calibration_facts(
        pd.DataFrame(list(summary.values())), coverage, bootstrap=bootstrap
    )
    # each table's rows where they belong: the coverage study's scenarios, the bootstrap's
    assert {r["scenario"] for r in facts["coverage"]} == set(coverage["scenario"])
    assert len(facts["bootstrap"]["rows"]) == (bootstrap["species"] == "all").sum()
    assert facts["by_claim"]["C1"].startswith("wrong in 1 of 4 reconstructions")
    assert facts["by_claim"]["C1"].endswith("undecided in 1")
    assert "C7" not in facts["by_claim"]
    assert (facts["any_wrong"], facts["n_datasets"]) == ("2", "4")
    text = calibration.verdict_markdown(list(summary.values()), "snakemake calibration")
    assert "| C7 | identity | 4 | - | - | - | not evidence |" in text
    assert "2 of 4 datasets had at least one wrong verdict" in text


def test_a_slice_of_the_committed_verdict_calibration_reproduces():
    # the committed study (docs/calibration/verdicts*.md/csv) is seeded per dataset:
    # its first two datasets rerun alone to the same verdicts and truths
    with open(COMMITTED / "verdicts_datasets.csv", newline="") as handle:
        committed = [row for row in csv.DictReader(handle) if int(row["dataset"]) < 2]
    seed = 2026  # the calibration config's seed (docs/calibration/verdicts.md)
    assert f"seed: {seed}" in (COMMITTED / "verdicts.md").read_text()
    # the bending skin fitted with the schema's default walls (config bending: wall)
    rerun = calibration.verdict_study(seed, 2, WINDOW_MM, PRIORS, MAX_TRIALS, wall="clamped")
    assert [(r["dataset"], r["claim"], r["truth"], r["verdict"]) for r in rerun] == [
        (int(r["dataset"]), r["claim"], r["truth"], r["verdict"]) for r in committed
    ]
    # the committed summary is the summary of the committed datasets
    datasets = pd.read_csv(COMMITTED / "verdicts_datasets.csv", dtype={"claim": str})
    summary = pd.read_csv(COMMITTED / "verdicts.csv").set_index(["claim", "truth"])
    groups = datasets.groupby(["claim", "truth"])
    assert set(groups.groups) == set(summary.index[summary.index.get_level_values(0) != "any"])
    for (claim, truth), group in groups:
        row = summary.loc[(claim, truth)]
        assert row["n_datasets"] == len(group)
        assert row["n_wrong"] == group["wrong"].sum()
        if truth != "identity":
            assert row["n_holds"] == (group["verdict"] == HOLDS).sum()


def true_verdict(world, effect, seed):
    claim, _, family, _, placing = calibration.BOUNDARY_WORLDS[world]
    table = calibration.reconstruction_claims(
        seed, WINDOW_MM, PRIORS, MAX_TRIALS, placing, errors=False, subjects=family(effect)
    )
    return dict(zip(table["claim"], table["verdict"], strict=True))[claim]


def test_each_boundary_world_crosses_its_claims_boundary_where_the_study_says():
    # the committed effects of each world: on its failing side the claim's error-free
    # verdict is not 'holds', on its holding side, one bisection step away, it is
    summary = pd.read_csv(COMMITTED / "boundary.csv").drop_duplicates(["world", "side"])
    assert list(summary["world"].drop_duplicates()) == list(calibration.BOUNDARY_WORLDS)
    for world, group in summary.groupby("world", sort=False):
        effects = dict(zip(group["side"], group["effect"], strict=True))
        assert set(effects) == {"holding", "failing"}, world  # both directions planned
        _, _, _, (holds_at, fails_at), _ = calibration.BOUNDARY_WORLDS[world]
        step = (holds_at - fails_at) * 2.0**-12
        # one bisection step apart, to the 10 significant digits the table keeps
        assert effects["holding"] - effects["failing"] == pytest.approx(step, abs=1e-8)
        assert true_verdict(world, effects["failing"], (2026, 0)) != HOLDS, world
        assert true_verdict(world, effects["holding"], (2026, 0)) == HOLDS, world


def test_a_world_that_does_not_bracket_its_boundary_is_refused(monkeypatch):
    claim, what, family, (holds_at, _), placing = calibration.BOUNDARY_WORLDS["sides-unequal"]
    # both ends where the claim holds: no boundary between them to find
    monkeypatch.setitem(
        calibration.BOUNDARY_WORLDS,
        "sides-unequal",
        (claim, what, family, (holds_at, 0.0), placing),
    )
    with pytest.raises(ValueError, match=r"C2 should hold at t = -0\.03 and not at t = 0\.0"):
        calibration.boundary_effect("sides-unequal", (2026, 0), WINDOW_MM, PRIORS, MAX_TRIALS)


def test_a_slice_of_the_committed_boundary_calibration_reproduces():
    # one world's bisection and first dataset rerun alone, as committed
    with open(COMMITTED / "boundary_datasets.csv", newline="") as handle:
        committed = [
            row
            for row in csv.DictReader(handle)
            if row["world"] == "sides-unequal" and row["dataset"] == "0"
        ]
    rerun = calibration.boundary_study("sides-unequal", 2026, 1, WINDOW_MM, PRIORS, MAX_TRIALS)
    assert [(r["side"], r["claim"], r["truth"], r["verdict"]) for r in rerun] == [
        (r["side"], r["claim"], r["truth"], r["verdict"]) for r in committed
    ]
    for new, old in zip(rerun, committed, strict=True):
        assert new["effect"] == pytest.approx(float(old["effect"]), abs=1e-9)
    # the committed summary counts the committed datasets, both errors
    datasets = pd.read_csv(COMMITTED / "boundary_datasets.csv")
    summary = pd.read_csv(COMMITTED / "boundary.csv")
    for _, row in summary.iterrows():
        group = datasets[
            (datasets["world"] == row["world"])
            & (datasets["side"] == row["side"])
            & (datasets["truth"] == row["truth"])
        ]
        assert row["n_datasets"] == len(group)
        assert row["n_holds"] == (group["verdict"] == HOLDS).sum()
        assert (
            row["n_wrong_holds"] == ((group["verdict"] == HOLDS) & (group["truth"] != HOLDS)).sum()
        )
        assert (
            row["n_wrong_fails"] == ((group["verdict"] == FAILS) & (group["truth"] != FAILS)).sum()
        )
        low, high = binomial_interval(row["n_wrong_fails"], row["n_datasets"])
        assert (row["wrong_fails_ci_low"], row["wrong_fails_ci_high"]) == pytest.approx((low, high))


def test_error_rates_name_each_claims_calibration_and_its_boundary():
    study = rows(
        (0, "C2", HOLDS, HOLDS),
        (1, "C2", HOLDS, FAILS),
        (0, "C7", IDENTITY, IDENTITY),
        (1, "C7", IDENTITY, IDENTITY),
    )
    verdicts = pd.DataFrame(calibration.summarise_verdicts(study))
    at_boundary = [
        {"world": "sides-unequal", "side": side, "effect": -0.1, **row}
        for side, row in zip(
            ("failing", "failing", "failing", "failing", "holding", "holding"),
            rows(
                (0, "C2", FAILS, HOLDS),
                (1, "C2", FAILS, FAILS),
                (2, "C2", UNTESTABLE, HOLDS),
                (3, "C2", HOLDS, HOLDS),  # this grid keeps the claim true: 'holds' is right
                (0, "C2", HOLDS, FAILS),  # wrong the other way
                (1, "C2", HOLDS, UNTESTABLE),
            ),
            strict=True,
        )
    ]
    for row in at_boundary:
        row["wrong_holds"] = row["verdict"] == HOLDS and row["truth"] != HOLDS
        row["wrong_fails"] = row["verdict"] == FAILS and row["truth"] != FAILS
    boundary = pd.DataFrame(calibration.summarise_boundary(at_boundary))
    assert list(boundary["side"]) == ["holding", "failing", "failing", "failing"]
    rates = calibration.claim_error_rates(verdicts, boundary)
    assert list(rates) == ["C2"]  # the identity is not evidence
    assert rates["C2"].startswith("wrong in 1 of 2 reconstructions")
    assert (
        "where the claim only just fails, 'holds' in 2 of 3 (95 % upper bound "
        f"{100 * binomial_interval(2, 3)[1]:.1f} %)"
    ) in rates["C2"]
    # the 'does not hold' of the holding-side world is counted too: 1 wrong of the 4
    # datasets whose truth is not 'does not hold'
    assert rates["C2"].endswith(
        "where the claim only just holds, 'does not hold' in 1 of 4 (95 % upper bound "
        f"{100 * binomial_interval(1, 4)[1]:.1f} %)"
    )
    # claims.md gets a section with them, and none without
    claims = pd.DataFrame(
        [{"claim": "C2", "statement": "s", "paper_location": "p", "paper_value": "v",
          "our_value": "o", "verdict": HOLDS, "reason": "r", "rule": "rule"}]
    )  # fmt: skip
    from lineload.claims import claims_markdown

    assert f"- **C2**: {rates['C2']}." in claims_markdown(claims, error_rates=rates)
    assert "How often each rule is wrong" not in claims_markdown(claims)


def test_a_slice_of_the_committed_mechanics_coverage_reproduces():
    # dataset 0 of the committed study reruns alone to the same estimates and verdicts
    committed = pd.read_csv(COMMITTED / "mechanics_coverage_subjects.csv")
    committed = committed[committed["dataset"] == 0]
    force_sd_N = config_defaults("mechanics")["force_sd_N"]
    rerun = pd.DataFrame(
        calibration.mechanics_study(2026, 1, WINDOW_MM, PRIORS, MAX_TRIALS, force_sd_N)
    )
    assert list(rerun["subject"]) == list(committed["subject"])
    assert list(rerun["parameter"]) == list(committed["parameter"])
    assert list(rerun["covered"]) == list(committed["covered"])
    # the fits behind them stop at a relative 1e-9 or finer; the CSV keeps 10 digits
    np.testing.assert_allclose(rerun["estimate"], committed["estimate"], rtol=1e-6)
    np.testing.assert_allclose(rerun["truth"], committed["truth"], rtol=1e-9)
    # the committed summary counts the committed subjects
    subjects = pd.read_csv(COMMITTED / "mechanics_coverage_subjects.csv")
    summary = pd.read_csv(COMMITTED / "mechanics_coverage.csv")
    for _, row in summary[summary["fit"] == "all"].iterrows():
        group = subjects[subjects["parameter"] == row["parameter"]]
        assert (row["n"], row["n_covered"]) == (len(group), group["covered"].sum())


@pytest.mark.e2e
def test_a_slice_of_the_committed_bootstrap_of_the_shipped_fits_reproduces(shipped_build, tmp_path):
    # the script of rule bootstrap, on the shipped build's tables, one replicate: the
    # committed replicate 0 of every model again
    import importlib.util
    from types import SimpleNamespace

    spec = importlib.util.spec_from_file_location(
        "run_bootstrap", REPO / "workflow" / "scripts" / "run_bootstrap.py"
    )
    script = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(script)
    _, results = shipped_build
    inputs = SimpleNamespace(
        fits=results / "tables" / "fits.csv",
        noise=results / "tables" / "noise.csv",
        averaged=sorted((results / "data" / "averaged").glob("*.csv")),
    )
    outputs = SimpleNamespace(
        trials=tmp_path / "trials.csv", summary=tmp_path / "s.csv", markdown=tmp_path / "b.md"
    )
    script.bootstrap(inputs, outputs, seed=2026, replicates=1, window_mm=WINDOW_MM, notice="")
    rerun = pd.read_csv(outputs.trials)
    committed = pd.read_csv(COMMITTED / "bootstrap_trials.csv")
    committed = committed[committed["dataset"] == 0].reset_index(drop=True)
    assert list(rerun["covered"]) == list(committed["covered"])
    assert list(rerun["parameter"]) == list(committed["parameter"])
    # interval ends from root searches and sandwich variances: agreement to far below the
    # noise, not to the last bit
    np.testing.assert_allclose(rerun[["low", "high"]], committed[["low", "high"]], rtol=1e-5)


@pytest.mark.parametrize(
    ("successes", "n"), [(0, 7), (1, 4), (2, 3), (3, 40), (38, 40), (40, 40), (11, 200)]
)
def test_binomial_interval_is_clopper_pearson(successes, n):
    """scipy's exact interval is the beta-quantile definition of Clopper and Pearson:
    low = B(0.025; k, n - k + 1) (0 when k = 0), high = B(0.975; k + 1, n - k) (1 when
    k = n); both computed by scipy's beta, so the tolerance is its quantile's precision."""
    from scipy.stats import beta

    low, high = binomial_interval(successes, n)
    expected_low = 0.0 if successes == 0 else beta.ppf(0.025, successes, n - successes + 1)
    expected_high = 1.0 if successes == n else beta.ppf(0.975, successes + 1, n - successes)
    assert low == pytest.approx(expected_low, abs=1e-10)
    assert high == pytest.approx(expected_high, abs=1e-10)
    # an interval at another level is another interval: the comparison can fail
    narrower = binomial_interval(successes, n, level=0.5)
    assert narrower[1] - narrower[0] < high - low


def test_binomial_interval_of_nothing_is_undefined():
    assert all(np.isnan(binomial_interval(0, 0)))
