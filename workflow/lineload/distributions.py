"""The few distribution functions the claims and the mechanics use, from scipy.special.

``scipy.stats`` computes these with the same special functions (its ``norm``, ``t`` and
``chi2`` call ``ndtri``, ``stdtr``, ``stdtrit``, ``chdtrc`` and ``gammaincinv``), but
importing it takes about half a second, more than the rest of a claims or mechanics job
imports.  Each function here is the expression ``scipy.stats`` evaluates inside the
support (probabilities strictly between 0 and 1, degrees of freedom > 0, a chi-square
statistic >= 0; a test holds them to it); at and beyond those ends the special functions
answer, not ``scipy.stats``' own handling of them.  ``scipy.special`` is imported at the
first call, so that the claims' modules import without scipy.
"""

from __future__ import annotations

__all__ = [
    "chi2_quantile",
    "chi2_survival",
    "normal_quantile",
    "student_t_quantile",
    "student_t_survival",
]


def _special():
    """``scipy.special``, imported at the first call."""
    from scipy import special

    return special


def normal_quantile(probability):
    """Quantile of the standard normal distribution (``scipy.stats.norm.ppf``).

    Parameters
    ----------
    probability : float or array_like
        Lower-tail probability, in (0, 1).

    Returns
    -------
    float or numpy.ndarray
        ``z`` with ``P(Z <= z) = probability``.
    """
    return _special().ndtri(probability)


def student_t_survival(t_value, df):
    """Upper-tail probability of Student's t (``scipy.stats.t.sf``).

    Parameters
    ----------
    t_value : float or array_like
        The statistic.
    df : float or array_like
        Degrees of freedom (> 0).

    Returns
    -------
    float or numpy.ndarray
        ``P(T >= t_value)``.
    """
    return _special().stdtr(df, -t_value)


def student_t_quantile(probability, df):
    """Quantile of Student's t (``scipy.stats.t.ppf``).

    Parameters
    ----------
    probability : float or array_like
        Lower-tail probability, in (0, 1).
    df : float or array_like
        Degrees of freedom (> 0).

    Returns
    -------
    float or numpy.ndarray
        ``t`` with ``P(T <= t) = probability``.
    """
    return _special().stdtrit(df, probability)


def chi2_survival(value, df):
    """Upper-tail probability of the chi-square distribution (``scipy.stats.chi2.sf``).

    Parameters
    ----------
    value : float or array_like
        The statistic (>= 0).
    df : float or array_like
        Degrees of freedom (> 0).

    Returns
    -------
    float or numpy.ndarray
        ``P(X >= value)``.
    """
    return _special().chdtrc(df, value)


def chi2_quantile(probability, df):
    """Quantile of the chi-square distribution (``scipy.stats.chi2.ppf``).

    Parameters
    ----------
    probability : float or array_like
        Lower-tail probability, in (0, 1).
    df : float or array_like
        Degrees of freedom (> 0).

    Returns
    -------
    float or numpy.ndarray
        ``x`` with ``P(X <= x) = probability``.
    """
    return 2.0 * _special().gammaincinv(df / 2.0, probability)
