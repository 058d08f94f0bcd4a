"""The batch paths of the fits against the one-trial path and against brute force.

A trial's fit must not depend on the batch it is fitted in (alone, with others,
in small chunks), and it must be what its definition says: the global minimum of
the objective over the admissible range (checked on a dense grid with the model
functions themselves) and interval ends where the likelihood ratio crosses its
quantile.  Two code paths round the objective differently, so they are compared
to the tolerance that rounding allows (:mod:`numerics`), never to the last bit.
The profile preparation is exact arithmetic and must give the same bytes as the
per-depth code it replaced (``reference_averaging``).
"""

import math

import numpy as np
import pandas as pd
import pytest

import reference_averaging
from conftest import REPO
from lineload import averaging, io, models
from lineload.fitting import batch as fitting
from lineload.fitting import search, sensitivity
from lineload.rawdata.validation import check_no_duplicate_readings, read_columns, read_table
from lineload.simulation import synthetic
from lineload.simulation.coverage import TRUE_NOISE
from numerics import assert_rows_agree, fit_rounding_mm2, fit_row_tolerances

PROFILE_SCHEMA = io.load_schema("profiles")
SUBJECT_SCHEMA = io.load_schema("subjects")
# the reading grid of the study within the 3 mm fit window (tissue mm)
GRID_MM = np.round(np.r_[np.arange(0.05, 0.5001, 0.05), np.arange(0.75, 3.0001, 0.25)], 6)


def averaged_trials(raw_dir):
    """(subject, depth, distance, deflection) of each trial, prepared as prepare_profiles does."""
    subjects = read_table(raw_dir / "subjects.csv", SUBJECT_SCHEMA)
    trials = []
    for subject, magnification in zip(subjects["subject"], subjects["magnification"], strict=True):
        path = raw_dir / "profiles" / f"{subject}.csv"
        profile = read_columns(path, PROFILE_SCHEMA)
        check_no_duplicate_readings(profile, str(path))
        means = averaging.average_columns(
            averaging.tissue_columns(profile[0], subject, magnification)
        )
        for depth_mm in np.unique(means["depth_mm"]):
            rows = means["depth_mm"] == depth_mm
            x, y = means["distance_mm"][rows], means["deflection_mm"][rows]
            trials.append((subject, float(depth_mm), x, y))
    return trials


def write_scale_dataset(raw_dir):
    """The synthetic scale dataset of make_synthetic_data.py --monkeys 100 --humans 100."""
    for relative, text in synthetic.build_dataset(n_monkeys=100, n_humans=100).items():
        io.write_text(text, raw_dir / relative)
    return raw_dir


@pytest.fixture(scope="module")
def scale_raw(tmp_path_factory):
    return write_scale_dataset(tmp_path_factory.mktemp("scale") / "raw")


@pytest.fixture(scope="module")
def trials(scale_raw):
    """Every trial of the shipped data and every third of the scale dataset."""
    shipped = averaged_trials(REPO / "data" / "raw")
    scale = averaged_trials(scale_raw)[::3]
    assert len(shipped) >= 20 and len(scale) >= 250
    return shipped + scale


def edge_trials():
    """Trials that take the unusual paths, with different numbers of points."""
    flat = np.full(GRID_MM.size, 1.0)  # y = W0 everywhere: best waterbed L is infinite
    steep = 2.0 - 3.0 * GRID_MM  # wants L below the shifted fold sqrt(6) W0
    narrow = models.waterbed_deflection_mm(GRID_MM, 1.0, 2.0)  # wants L below max(x)
    exact = models.arc_deflection_mm(GRID_MM, 2.0, 10.0)  # noise-free: perfect arc
    return [
        (np.array([0.1, 5.0]), np.array([0.9, 0.0]), 1.0),  # one point in the window
        (np.array([0.1, 0.3]), np.array([0.9, 0.7]), 1.0),  # two points
        (np.array([0.1, 0.3, 0.6, 1.0]), np.array([0.9, 0.7, 0.5, 0.3]), 1.0),  # four
        (np.array([3.5, 5.0]), np.array([0.1, 0.0]), 1.0),  # none in the window
        (GRID_MM, flat, 1.0),
        (GRID_MM, steep, 2.0),
        (GRID_MM, narrow, 1.0),
        (GRID_MM, exact, 2.0),
        (np.r_[GRID_MM, 3.5, 4.0], np.r_[narrow, np.nan, 0.0], 1.0),  # NaN and beyond
    ]


# ------------------------------------------------------------------ one trial, any batch


def test_a_trial_gets_the_same_fit_in_any_batch(trials, monkeypatch):
    # alone, in a batch, reversed in small chunks and small evaluation blocks
    subset = [(*t[2:], t[1]) for t in trials[:40]] + edge_trials()
    x, y, depth = zip(*subset, strict=True)
    together = fitting.fit_trials(x, y, depth, 3.0)
    alone = [fitting.fit_trial(*t, 3.0) for t in subset]
    monkeypatch.setattr(fitting, "CHUNK_TRIALS", 7)
    monkeypatch.setattr(search, "BLOCK_ELEMENTS", 1 << 10)
    reversed_ = fitting.fit_trials(x[::-1], y[::-1], depth[::-1], 3.0)[::-1]
    for rows in (reversed_, alone):
        assert_rows_agree(rows, together, x, y)


def test_the_agreement_check_can_fail(trials):
    subset = trials[:5]
    x, y, depth = ([t[k] for t in subset] for k in (2, 3, 1))
    rows = fitting.fit_trials(x, y, depth, 3.0)
    # one L moved by a tenth of its interval's half-width is far outside rounding
    moved = [dict(row) for row in rows]
    half = (rows[2]["arc_L_ci_high_mm"] - rows[2]["arc_L_ci_low_mm"]) / 2
    moved[2]["arc_L_mm"] += 0.1 * half
    with pytest.raises(AssertionError, match="arc_L_mm"):
        assert_rows_agree(moved, rows, x, y)
    moved = [dict(row) for row in rows]
    moved[0]["waterbed_L_ci_low_mm"] *= 1 + 1e-5
    with pytest.raises(AssertionError, match="waterbed_L_ci_low_mm"):
        assert_rows_agree(moved, rows, x, y)
    # the Boussinesq intervals' ends too, each a hundred times its derived tolerance
    for name in ("boussinesq_A_ci_low_mm", "boussinesq_x0_ci_high_mm"):
        moved = [dict(row) for row in rows]
        moved[1][name] += 100 * fit_row_tolerances(rows[1], x[1], y[1])[name]
        with pytest.raises(AssertionError, match=name):
            assert_rows_agree(moved, rows, x, y)
    # and the intervals made with a noise model (the sandwich's), as the tables have them
    rows = fitting.fit_trials(x, y, depth, 3.0, noise=TRUE_NOISE)
    names = ("arc_L_ci_low_mm", "waterbed_L_ci_high_mm", "boussinesq_A_ci_high_mm")
    for name in (*names, "boussinesq_x0_ci_low_mm"):
        tolerance = fit_row_tolerances(rows[1], x[1], y[1], sandwich=True)[name]
        assert 0 < tolerance < 1e-6 * abs(rows[1][name]), (name, tolerance)
        moved = [dict(row) for row in rows]
        moved[1][name] += 100 * tolerance
        with pytest.raises(AssertionError, match=name):
            assert_rows_agree(moved, rows, x, y, sandwich=True)


# ------------------------------------------------------------------ what a fit is


SEARCH_RANGE = {
    "waterbed": lambda x, depth: (x.max(), 1e6 * x.max()),
    "shifted": lambda x, depth: (max(x.max(), math.sqrt(6.0) * depth), 1000.0 * x.max()),
    "arc": lambda x, depth: (x.max(), 1000.0 * x.max()),
}
CURVES = {
    "waterbed": models.waterbed_deflection_mm,
    "shifted": models.shifted_deflection_mm,
    "arc": models.arc_deflection_mm,
}


@pytest.mark.parametrize("model", ["waterbed", "shifted", "arc"])
def test_each_fit_is_the_global_minimum_and_its_interval_the_likelihood_crossing(trials, model):
    subset = trials[::7]
    x, y, depth = ([t[k] for t in subset] for k in (2, 3, 1))
    fits = fitting.fit_windowed(x, y, depth, 3.0, models=(model,))[model]
    checked = 0
    for i, (xi, yi, di) in enumerate(zip(x, y, depth, strict=True)):
        keep = (xi > 0) & (xi <= 3.0)
        xi, yi = xi[keep], yi[keep]
        fit = fits.result(i)
        L_best = fit.params["L_mm"]
        rounding = fit_rounding_mm2(yi, yi - fit.residual_mm)

        def sse(L_mm, xi=xi, yi=yi, di=di):
            model_mm = CURVES[model](xi[None, :], di, np.asarray(L_mm, dtype=float)[:, None])
            return np.sum((yi - model_mm) ** 2, axis=1)

        # brute force: a dense log grid over the whole admissible range finds nothing lower
        low, high = SEARCH_RANGE[model](xi, di)
        grid = np.geomspace(low * (1 + 1e-12), high, 4000)
        values = sse(grid)
        assert np.nanmin(values) >= fit.sse_mm2 - 2 * rounding, (i, model)
        # the interval's ends: n ln(SSE / SSE_min) = chi2, or an end at its bound
        n = xi.size
        for end in (fit.params["L_ci_low_mm"], fit.params["L_ci_high_mm"]):
            if not np.isfinite(end) or end <= low * (1 + 1e-8):
                continue
            statistic = n * np.log(sse([end])[0] / fit.sse_mm2)
            slack = n * 4 * rounding / fit.sse_mm2 + 1e-8
            assert abs(statistic - fitting.CHI2_1DOF_95) <= slack, (i, model, end)
            checked += 1
        assert fit.params["L_ci_low_mm"] <= L_best <= fit.params["L_ci_high_mm"]
    assert checked >= len(subset)


def test_edge_cases_take_the_documented_paths():
    x, y, depth = zip(*edge_trials(), strict=True)
    rows = fitting.fit_trials(x, y, depth, 3.0)
    one, two, four, none, flat, steep, narrow, exact, with_nan = rows
    assert one["n_points"] == 1 and np.isfinite(one["waterbed_L_mm"])
    assert np.isnan(one["boussinesq_A_mm"]) and np.isnan(one["waterbed_L_ci_low_mm"])
    assert np.isfinite(two["boussinesq_A_mm"]) and np.isnan(two["boussinesq_aicc"])
    # the AICc needs n >= k + 2 (k counts the noise variance): 4 for a parabola, 5 for a line
    assert np.isfinite(four["waterbed_aicc"]) and np.isnan(four["boussinesq_aicc"])
    assert none["n_points"] == 0
    flags = [k for k in none if k.endswith("_at_bound")]
    assert flags and not any(none[k] for k in flags)  # no fit is not a fit on a bound
    skip = ("depth_mm", "fit_window_mm", "n_points", *flags)
    numbers = [v for k, v in none.items() if k not in skip]
    assert all(np.isnan(v) for v in numbers)
    # a flat profile is a straight line in ln x: the regression fits it exactly
    assert abs(flat["boussinesq_A_mm"]) < 1e-12 and flat["boussinesq_rmse_mm"] < 1e-12
    assert flat["waterbed_L_mm"] == np.inf and np.isnan(flat["waterbed_L_ci_high_mm"])
    assert flat["waterbed_L_at_bound"]  # a flat membrane is the search's upper bound
    fold_mm = math.sqrt(6.0) * 2.0
    assert steep["shifted_L_mm"] == pytest.approx(fold_mm, rel=1e-6)
    assert steep["shifted_L_ci_low_mm"] == pytest.approx(fold_mm, rel=1e-6)
    assert steep["shifted_L_at_bound"]
    assert narrow["waterbed_L_mm"] == pytest.approx(GRID_MM.max())
    assert exact["arc_L_mm"] == pytest.approx(10.0, rel=1e-7)
    assert with_nan["n_points"] == GRID_MM.size
    assert with_nan["waterbed_L_mm"] == pytest.approx(narrow["waterbed_L_mm"])


def test_batch_input_is_checked():
    with pytest.raises(ValueError, match="trial 1"):
        fitting.fit_trials([[0.1, 0.2], [0.1, 0.2]], [[0.9, 0.8], [0.9]], [1.0, 1.0], 3.0)
    with pytest.raises(ValueError, match="> 0"):
        fitting.fit_batch([[0.0, 0.2]], [[0.9, 0.8]], [1.0])
    assert fitting.fit_trials([], [], [], 3.0) == []


def test_memory_stays_small_for_thousands_of_trials():
    import tracemalloc

    rng = np.random.default_rng(5)
    n = 1500
    depth = rng.choice([0.5, 1.0, 1.5, 2.0], n)
    L = rng.uniform(8.0, 16.0, n)
    y = [
        models.waterbed_deflection_mm(GRID_MM, d, length) + rng.normal(0, 0.01, GRID_MM.size)
        for d, length in zip(depth, L, strict=True)
    ]
    tracemalloc.start()
    rows = fitting.fit_trials([GRID_MM] * n, y, depth, 3.0)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 100 * 2**20, peak / 2**20
    assert np.allclose([row["waterbed_L_mm"] for row in rows], L, rtol=0.1)


# ------------------------------------------------------------------ sensitivity and checks


def test_sensitivity_rows_batch_are_the_rows_of_each_trial(trials):
    subset = trials[:6]
    x, y, depth = ([t[k] for t in subset] for k in (2, 3, 1))
    windows = [2.0, 3.0, math.inf]
    batch = sensitivity.sensitivity_rows_batch(x, y, depth, windows)
    for rows, args in zip(batch, zip(x, y, depth, strict=True), strict=True):
        single = sensitivity.sensitivity_rows(*args, windows)
        assert [(r["model"], r["fit_window_mm"]) for r in rows] == [
            (r["model"], r["fit_window_mm"]) for r in single
        ]
        for row, expected in zip(rows, single, strict=True):
            for name, value in expected.items():
                if isinstance(value, str):
                    assert row[name] == value
                elif name.startswith("L_") or name == "L_mm":
                    half = (expected["L_ci_high_mm"] - expected["L_ci_low_mm"]) / 2
                    scale = half if np.isfinite(half) else abs(expected["L_mm"])
                    assert row[name] == pytest.approx(value, abs=1e-6 * scale, nan_ok=True)
                else:
                    assert row[name] == pytest.approx(value, rel=1e-6, abs=1e-12, nan_ok=True)


def test_trial_checks_batch_are_the_checks_of_each_trial(trials):
    subset = trials[::10]
    x, y, depth = ([t[k] for t in subset] for k in (2, 3, 1))
    checks = sensitivity.trial_checks_batch(x, y, depth, 3.0, 0.1)
    for check, args in zip(checks, zip(x, y, depth, strict=True), strict=True):
        single = sensitivity.trial_checks(*args, 3.0, 0.1)
        for name, value in single.items():
            assert check[name] == pytest.approx(value, rel=1e-6, abs=1e-12, nan_ok=True), name
    assert all(check["gap_shifted_mm"] > 0 for check in checks)


# ------------------------------------------------------------------ profile preparation


def test_conversion_and_averaging_agree_with_the_per_depth_code(scale_raw):
    subjects = read_table(scale_raw / "subjects.csv", SUBJECT_SCHEMA)
    pairs = list(zip(subjects["subject"], subjects["magnification"], strict=True))
    for subject, magnification in pairs[::10]:
        profile = read_table(scale_raw / "profiles" / f"{subject}.csv", PROFILE_SCHEMA)
        converted = averaging.to_tissue_mm(profile, subject, magnification)
        expected = reference_averaging.to_tissue_mm(profile, subject, magnification)
        pd.testing.assert_frame_equal(converted, expected)
        pd.testing.assert_frame_equal(
            averaging.average_sides(converted), reference_averaging.average_sides(expected)
        )
        # and with the rows shuffled (averaging does not rely on the sorted order)
        shuffled = converted.sample(frac=1.0, random_state=1).reset_index(drop=True)
        pd.testing.assert_frame_equal(
            averaging.average_sides(shuffled), reference_averaging.average_sides(shuffled)
        )


def csv_bytes(folder, write, *args):
    """The bytes ``write(*args, path)`` puts in a file."""
    path = folder / f"{write.__name__}.csv"
    write(*args[:1], path, *args[1:])
    return path.read_bytes()


def test_write_columns_gives_the_bytes_of_write_csv(tmp_path):
    columns = {
        "subject": np.array(["M1", "a,b", 'q"uote', "x"], dtype=object),
        "value": np.array([0.1, np.nan, -0.0, 1e-300]),
        "big": np.array([1.0 / 3.0, 123456789012.0, np.inf, -np.inf]),
        "count": np.array([2, 1, 0, -3]),
        "flag": np.array([True, False, True, False]),
    }
    frame = pd.DataFrame(columns)
    assert csv_bytes(tmp_path, io.write_columns, columns) == csv_bytes(
        tmp_path, io.write_csv, frame
    )
    names = ["count", "subject", "value"]
    assert csv_bytes(tmp_path, io.write_columns, columns, names) == csv_bytes(
        tmp_path, io.write_csv, frame, names
    )


def test_plain_and_csv_module_reading_agree(tmp_path):
    text = (
        "depth_mm,side,distance_image_mm,deflection_image_mm\n"
        "1,left, 2.0 ,5\n\n,,,\n2.5,right,3,4.25\n1,left,4,5e-1\n"
    )
    plain = tmp_path / "plain.csv"
    plain.write_text(text)
    crlf = tmp_path / "crlf.csv"  # a carriage return sends the file to the csv module
    crlf.write_bytes(text.replace("\n", "\r\n").encode())
    quoted = tmp_path / "quoted.csv"
    quoted.write_text(text.replace("right", '"right"'))
    expected = read_table(plain, PROFILE_SCHEMA)
    assert list(expected.index) == [2, 5, 6]
    for other in (crlf, quoted):
        pd.testing.assert_frame_equal(read_table(other, PROFILE_SCHEMA), expected)
    columns, lines = read_columns(plain, PROFILE_SCHEMA)
    assert list(lines) == [2, 5, 6] and list(columns["side"]) == ["left", "right", "left"]


def test_duplicates_found_in_columns_as_in_the_table(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text(
        "depth_mm,side,distance_image_mm,deflection_image_mm\n"
        "2,right,4,1\n1,left,1,5\n1,right,0,5\n2,right,4,3\n1,right,-0.0,5\n"
    )
    messages = []
    for profile in (read_table(path, PROFILE_SCHEMA), read_columns(path, PROFILE_SCHEMA)):
        with pytest.raises(ValueError) as error:
            check_no_duplicate_readings(profile, "p.csv")
        messages.append(str(error.value))
    assert messages[0] == messages[1]
    assert "line 5" in messages[0] and "already given on line 2" in messages[0]
    path.write_text(
        "depth_mm,side,distance_image_mm,deflection_image_mm\n1,left,1,5\n1,right,1,5\n"
    )
    check_no_duplicate_readings(read_columns(path, PROFILE_SCHEMA), "p.csv")


def test_prepared_tables_are_byte_identical_to_the_per_depth_code(scale_raw, tmp_path):
    # the converted and averaged tables of a batch, as prepare_profiles.py writes them
    subjects = read_table(scale_raw / "subjects.csv", SUBJECT_SCHEMA)
    batch = list(zip(subjects["subject"], subjects["magnification"], strict=True))[:25]
    converted, expected_converted, expected_averaged = [], [], []
    for subject, magnification in batch:
        path = scale_raw / "profiles" / f"{subject}.csv"
        readings = averaging.tissue_columns(
            read_columns(path, PROFILE_SCHEMA)[0], subject, magnification
        )
        converted.append(readings)
        old = reference_averaging.to_tissue_mm(
            read_table(path, PROFILE_SCHEMA), subject, magnification
        )
        expected_converted.append(old)
        expected_averaged.append(reference_averaging.average_sides(old))
    # the whole batch averaged in one pass, and subject by subject: the same
    averaged = averaging.average_subjects(converted)
    one_by_one = [averaging.average_columns(readings) for readings in converted]
    for name in averaging.AVERAGED_COLUMNS:
        joined = np.concatenate([part[name] for part in one_by_one])
        assert np.array_equal(averaged[name], joined, equal_nan=joined.dtype.kind == "f")
    names = averaging.CONVERTED_COLUMNS
    columns = {name: np.concatenate([part[name] for part in converted]) for name in names}
    frame = pd.concat(expected_converted, ignore_index=True)
    assert csv_bytes(tmp_path, io.write_columns, columns, names) == csv_bytes(
        tmp_path, io.write_csv, frame, names
    )
    names = averaging.AVERAGED_COLUMNS
    frame = pd.concat(expected_averaged, ignore_index=True)
    assert csv_bytes(tmp_path, io.write_columns, averaged, names) == csv_bytes(
        tmp_path, io.write_csv, frame, names
    )
