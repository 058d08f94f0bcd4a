"""The report's table pages: values with the digits their uncertainty supports."""

import math

from lineload.publishing.reportpages import error_columns, table_page, with_supported_digits

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


def test_headers_carry_words_and_units_and_values_the_articles_digits():
    from lineload.publishing.reportpages import column_label

    assert column_label("waterbed_L_ci_low_mm") == "waterbed L 95 % CI low (mm)"
    assert column_label("boussinesq_x0_mm") == "Boussinesq x₀ (mm)"
    assert column_label("pretension_se_N_per_mm") == "pretension SE (N/mm)"
    assert column_label("waterbed_aicc") == "waterbed AICc" and column_label("chi2") == "chi2"
    # L to 0.01 mm as the article prints it, even when its interval supports one decimal
    columns = ["waterbed_L_mm", "waterbed_L_ci_low_mm", "waterbed_L_ci_high_mm"]
    columns += ["waterbed_rmse_mm", "waterbed_aicc", "n_points"]
    (shown,) = with_supported_digits(columns, [[14.7213, 13.9, 15.6, 0.0123456, -157.72209, 20]])
    assert shown == ["14.72", "13.90", "15.60", "0.0123", "-157.7", 20]
    # a depth or a window, set with few digits, is shown as it was set
    (depth,) = with_supported_digits(["depth_mm"], [[0.5]])
    assert depth == ["0.5"]
    page = table_page("t", columns, [[14.7213, 13.9, 15.6, 0.0123456, -157.72209, 20]])
    assert '<th title="waterbed_rmse_mm">waterbed RMSE (mm)</th>' in page
