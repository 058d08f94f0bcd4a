"""The report's table pages: values with the digits their uncertainty supports."""

import math

from lineload.reportpages import error_columns, table_page, with_supported_digits

COLUMNS = [
    "subject",
    "pretension_N_per_mm",
    "pretension_se_N_per_mm",
    "prestrain",
    "prestrain_se",
    "arc_L_mm",
    "arc_L_ci_low_mm",
    "arc_L_ci_high_mm",
    "chi2",
]


def test_each_value_finds_its_standard_error_or_its_interval():
    assert error_columns(COLUMNS) == {
        "pretension_N_per_mm": ("pretension_se_N_per_mm",),
        "prestrain": ("prestrain_se",),
        "arc_L_mm": ("arc_L_ci_low_mm", "arc_L_ci_high_mm"),
    }


def test_values_keep_two_significant_digits_of_their_uncertainty():
    row = ["M1", 0.0840843, 0.00165539, 0.43899, 0.10645, 12.3456, 11.9, 12.8, 2.791041644]
    (shown,) = with_supported_digits(COLUMNS, [row])
    # SE 0.0017 -> 4 decimals; SE 0.11 -> 2; half-width 0.45 -> 2
    assert shown[1:8] == ["0.0841", "0.0017", "0.44", "0.11", "12.35", "11.90", "12.80"]
    assert shown[8] == row[8]  # no uncertainty: left as it was (6 significant digits shown)
    # an error that is not there (NaN, an open interval) leaves the value as it was
    open_row = [*row[:5], 12.3456, 11.9, math.inf, 2.0]
    (shown,) = with_supported_digits(COLUMNS, [open_row])
    assert shown[5] == 12.3456
    page = table_page("t", COLUMNS, [row])
    assert '<td class="num">0.0841</td>' in page and "0.0840843" not in page
