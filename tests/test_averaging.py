"""Unit conversion and left/right averaging."""

import numpy as np
import pandas as pd
import pytest

from lineload.averaging import AVERAGED_COLUMNS, average_sides, to_tissue_mm


def raw(rows):
    return pd.DataFrame(
        rows, columns=["depth_mm", "side", "distance_image_mm", "deflection_image_mm"]
    )


def test_conversion_divides_image_units_by_magnification():
    profile = raw([(1.0, "left", 20.0, 18.0), (1.0, "right", 40.0, 10.0)])
    converted = to_tissue_mm(profile, "S1", 20.0)
    assert list(converted["distance_mm"]) == [1.0, 2.0]
    assert list(converted["deflection_mm"]) == [0.9, 0.5]
    # the commanded depth is already in tissue units
    assert list(converted["depth_mm"]) == [1.0, 1.0]
    assert (converted["subject"] == "S1").all()
    # the readings themselves are kept for the audit
    assert list(converted["distance_image_mm"]) == [20.0, 40.0]


@pytest.mark.parametrize("magnification", [0.0, -5.0])
def test_conversion_refuses_bad_magnification(magnification):
    with pytest.raises(ValueError):
        to_tissue_mm(raw([(1.0, "left", 1.0, 1.0)]), "S1", magnification)


def averaged(rows, magnification=1.0):
    return average_sides(to_tissue_mm(raw(rows), "S1", magnification))


def test_equal_distances_are_averaged():
    out = averaged(
        [
            (1, "left", 0.1, 0.90),
            (1, "right", 0.1, 0.80),
            (1, "left", 0.5, 0.50),
            (1, "right", 0.5, 0.46),
        ]
    )
    assert list(out.columns) == AVERAGED_COLUMNS
    assert np.allclose(out["deflection_mm"], [0.85, 0.48])
    assert list(out["n_sides"]) == [2, 2]
    assert set(out["left_source"]) == set(out["right_source"]) == {"measured"}


def test_missing_side_is_interpolated_within_its_readings():
    out = averaged(
        [
            (1, "left", 0.1, 0.9),
            (1, "left", 0.3, 0.7),
            (1, "left", 0.5, 0.5),
            (1, "right", 0.1, 0.8),
            (1, "right", 0.5, 0.4),
        ]
    )
    row = out[np.isclose(out["distance_mm"], 0.3)].iloc[0]
    # right side at 0.3 lies halfway between its readings 0.8 and 0.4
    assert row["right_mm"] == pytest.approx(0.6)
    assert row["right_source"] == "interpolated"
    assert row["left_source"] == "measured"
    assert row["deflection_mm"] == pytest.approx((0.7 + 0.6) / 2)
    assert row["n_sides"] == 2


def test_one_sided_value_outside_the_other_range_is_kept():
    out = averaged(
        [
            (1, "left", 0.05, 0.95),
            (1, "left", 0.1, 0.9),
            (1, "left", 4.0, 0.01),
            (1, "right", 0.1, 0.88),
            (1, "right", 3.0, 0.05),
        ]
    )
    first = out.iloc[0]
    assert first["distance_mm"] == pytest.approx(0.05)
    assert first["n_sides"] == 1 and first["right_source"] == "none"
    assert np.isnan(first["right_mm"])
    assert first["deflection_mm"] == pytest.approx(0.95)
    last = out.iloc[-1]
    assert last["distance_mm"] == pytest.approx(4.0) and last["n_sides"] == 1
    assert last["deflection_mm"] == pytest.approx(0.01)
    # 3.0 is read on the right only but lies inside the left readings: interpolated
    middle = out[np.isclose(out["distance_mm"], 3.0)].iloc[0]
    assert middle["left_source"] == "interpolated" and middle["n_sides"] == 2


def test_depths_are_kept_apart_and_row_order_does_not_matter():
    rows = [
        (1, "left", 0.1, 0.9),
        (1, "right", 0.1, 0.7),
        (2, "left", 0.1, 1.9),
        (2, "right", 0.1, 1.7),
        (2, "left", 0.2, 1.8),
        (2, "right", 0.2, 1.6),
    ]
    out = averaged(rows)
    shuffled = averaged([rows[i] for i in np.random.default_rng(0).permutation(len(rows))])
    pd.testing.assert_frame_equal(out, shuffled)
    assert list(out["depth_mm"]) == [1, 2, 2]
    assert np.allclose(out["deflection_mm"], [0.8, 1.8, 1.7])


def test_depth_read_on_one_side_only():
    out = averaged([(1, "left", 0.1, 0.9), (1, "left", 0.2, 0.8)])
    assert list(out["n_sides"]) == [1, 1]
    assert (out["right_source"] == "none").all()
    assert np.allclose(out["deflection_mm"], [0.9, 0.8])


def test_conversion_then_averaging_at_magnification_20():
    # readings that match only after division by 20 (0.1 mm = 2.0 image mm)
    out = averaged([(1, "left", 2.0, 18.0), (1, "right", 2.0, 17.0)], magnification=20.0)
    assert out["distance_mm"].tolist() == [0.1]
    assert out["deflection_mm"].iloc[0] == pytest.approx(0.875)
