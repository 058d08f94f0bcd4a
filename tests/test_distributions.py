"""The distribution functions of lineload.distributions against scipy.stats, and what the
claims' and the publishing jobs import."""

import numpy as np
import pytest
from scipy import stats

from conftest import imported_after
from lineload import distributions

PROBABILITIES = np.array([1e-12, 1e-6, 0.001, 0.025, 0.05, 0.3, 0.5, 0.8, 0.95, 0.975, 0.999])
DF = [1, 2, 3, 7.5, 30, 1e4]


def close(ours, theirs):
    # the same special function evaluated either way: agreement to a few units in the
    # last place (chi2.ppf goes through gammaincinv in both)
    np.testing.assert_allclose(ours, theirs, rtol=1e-12, atol=1e-300)


def test_normal_quantile_is_scipy_stats_norm_ppf():
    close(distributions.normal_quantile(PROBABILITIES), stats.norm.ppf(PROBABILITIES))
    # the tails and outside the support as there
    assert distributions.normal_quantile(0.0) == -np.inf
    assert distributions.normal_quantile(1.0) == np.inf
    assert np.isnan(distributions.normal_quantile(1.5))
    assert np.isnan(stats.norm.ppf(1.5))


@pytest.mark.parametrize("df", DF)
def test_student_t_is_scipy_stats_t(df):
    t_values = np.array([-40.0, -3.0, -0.5, 0.0, 0.7, 2.1, 9.0])
    close(distributions.student_t_survival(t_values, df), stats.t.sf(t_values, df))
    close(distributions.student_t_quantile(PROBABILITIES, df), stats.t.ppf(PROBABILITIES, df))


@pytest.mark.parametrize("df", DF)
def test_chi2_is_scipy_stats_chi2(df):
    values = np.array([0.0, 1e-3, 0.5, 1.0, 3.84, 12.0, 80.0])
    close(distributions.chi2_survival(values, df), stats.chi2.sf(values, df))
    close(distributions.chi2_quantile(PROBABILITIES, df), stats.chi2.ppf(PROBABILITIES, df))


def test_a_wrong_formula_would_be_caught():
    # the comparison above tells a lower tail from an upper one and one df from another
    with pytest.raises(AssertionError):
        close(distributions.student_t_survival(2.0, 5), stats.t.cdf(2.0, 5))
    with pytest.raises(AssertionError):
        close(distributions.chi2_quantile(0.95, 2), stats.chi2.ppf(0.95, 3))


#: What the publishing and claims jobs should import only when a rule runs.
WATCHED = ("scipy.stats", "scipy.special", "scipy.optimize")


def test_the_article_report_pages_and_claims_import_no_scipy():
    # they import the claims' rules (the workflow's code dependencies follow import
    # statements, so the package imports them all), but scipy, half a second of a job's
    # start, only when a rule needs it
    assert imported_after("import lineload.publishing.article", WATCHED) == []
    assert imported_after("import lineload.publishing.reportpages", WATCHED) == []
    assert imported_after("from lineload.claims import compute_claims", WATCHED) == []
    assert imported_after("import lineload.mechanics", WATCHED) == []


def test_a_rule_imports_what_it_needs_when_it_runs():
    # the checks above can fail: a quantile loads scipy.special, C7's root scipy.optimize
    quantile = "from lineload.distributions import normal_quantile as q; q(0.9)"
    assert imported_after(quantile, WATCHED) == ["scipy.special"]
    crossing = "from lineload.claims import waterbed_zero_crossing_mm as z; z(1.0, 3.0)"
    assert "scipy.optimize" in imported_after(crossing, WATCHED)
