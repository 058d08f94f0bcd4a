"""C13 in the verdict calibration: judged when the reconstructions fit the bending skin."""

import pandas as pd

from lineload.claims import FAILS, HOLDS, UNTESTABLE
from lineload.io import config_defaults
from lineload.simulation import calibration
from lineload.simulation.rates import binomial_interval

PRIORS = {k: v for k, v in config_defaults("noise").items() if k != "max_trials"}
MAX_TRIALS = config_defaults("noise")["max_trials"]
WALL = config_defaults("bending")["wall"]


def test_the_bending_claim_is_judged_only_with_the_bending_fits():
    claims = {
        wall: calibration.reconstruction_claims((11, 0), 3.0, PRIORS, MAX_TRIALS, wall=wall)
        for wall in (None, WALL)
    }
    assert not set(calibration.BENDING_CLAIMS) & set(claims[None]["claim"])
    judged = claims[WALL].set_index("claim")
    for claim in calibration.BENDING_CLAIMS:
        # judged from the fits, not refused for want of them
        assert judged.loc[claim, "our_value"] != "no bending fits"
    # the other claims are the same either way: the bending fits only add columns
    same = claims[WALL][~claims[WALL]["claim"].isin(calibration.BENDING_CLAIMS)]
    pd.testing.assert_frame_equal(same.reset_index(drop=True), claims[None])


def _summary(entries):
    opposite = {HOLDS: FAILS, FAILS: HOLDS}
    rows = [
        {"dataset": d, "claim": "C13", "truth": t, "verdict": v, "wrong": v == opposite.get(t)}
        for d, (t, v) in enumerate(entries)
    ]
    return pd.DataFrame(calibration.summarise_verdicts(rows))


def test_an_undecided_truth_gives_no_error_rate_but_the_decided_share():
    summary = _summary([(UNTESTABLE, HOLDS), (UNTESTABLE, UNTESTABLE), (UNTESTABLE, FAILS)])
    sentence = calibration.claim_error_rates(summary)["C13"]
    assert sentence.startswith("its error-free truth is undecided in all 3 reconstructions")
    assert f"decided in 2 of them (95 % upper bound {100 * binomial_interval(2, 3)[1]:.1f} %)" in (
        sentence
    )
    # a decided truth keeps the error rate
    decided = calibration.claim_error_rates(_summary([(FAILS, HOLDS), (FAILS, FAILS)]))["C13"]
    assert decided.startswith("wrong in 1 of 2 reconstructions")
