"""The batch paths against the one-trial code they replaced.

``reference_fits`` and ``reference_averaging`` hold the code as it was at commit
37aa67d (independent of lineload).  The batch fits must agree with it within a
relative 1e-8 on every trial of the shipped data, on a few hundred trials of a
synthetic scale dataset (100 monkeys, 100 humans) and on edge cases; the profile
preparation must give the same numbers and the same bytes.
"""

import math

import numpy as np
import pandas as pd
import pytest

import reference_averaging
import reference_fits
from conftest import REPO
from lineload import averaging, fitting, io, models, sensitivity, synthetic
from lineload.validation import check_no_duplicate_readings, read_columns, read_table

#: Largest relative difference allowed between the batch and the one-trial code.
RTOL = 1e-8
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


def relative_gap(actual, expected):
    """Largest relative difference; NaN must meet NaN and inf the same inf.

    Values below 1e-4 in size are compared absolutely (to RTOL * 1e-4): a slope of
    exactly flat data comes out as -0.0 in one code and -1.5e-16 in the other.
    """
    actual, expected = (np.asarray(v, dtype=float) for v in (actual, expected))
    assert np.array_equal(np.isnan(actual), np.isnan(expected))
    finite = np.isfinite(expected)
    assert np.array_equal(
        actual[~finite & ~np.isnan(expected)], expected[~finite & ~np.isnan(expected)]
    )
    assert np.all(np.isfinite(actual[finite]))
    scale = np.maximum(np.abs(actual[finite]), np.abs(expected[finite]))
    gap = np.abs(actual[finite] - expected[finite]) / np.maximum(scale, 1e-4)
    return float(gap.max(initial=0.0))


def assert_rows_agree(rows, expected_rows):
    assert [list(row) for row in rows] == [list(row) for row in expected_rows]
    for name in rows[0]:
        values = [row[name] for row in rows]
        expected = [row[name] for row in expected_rows]
        if isinstance(expected[0], str):
            assert values == expected, name
        else:
            assert relative_gap(values, expected) <= RTOL, (name, relative_gap(values, expected))


# ------------------------------------------------------------------ fits of the fit table


def test_fit_table_agrees_with_the_one_trial_code(trials):
    x, y, depth = ([t[k] for t in trials] for k in (2, 3, 1))
    rows = fitting.fit_trials(x, y, depth, 3.0)
    expected = [reference_fits.fit_trial(*args, 3.0) for args in zip(x, y, depth, strict=True)]
    assert_rows_agree(rows, expected)
    # the fits did run: most trials have finite L and intervals for every model
    for model in ("waterbed", "shifted", "arc"):
        assert np.mean([np.isfinite(row[f"{model}_L_ci_high_mm"]) for row in rows]) > 0.9


@pytest.mark.parametrize("window_mm", [2.0, math.inf])
def test_every_model_in_other_windows_agrees(trials, window_mm):
    subset = trials[::4]
    x, y, depth = ([t[k] for t in subset] for k in (2, 3, 1))
    fits = fitting.fit_windowed(x, y, depth, window_mm)
    for i, (xi, yi, di) in enumerate(zip(x, y, depth, strict=True)):
        keep = (xi > 0) & (xi <= window_mm) & np.isfinite(yi)
        for model in fitting.MODELS:
            reference = getattr(reference_fits, f"fit_{model}")
            args = (xi[keep], yi[keep]) + ((di,) if model in ("waterbed", "shifted", "arc") else ())
            expected = reference(*args)
            result = fits[model].result(i)
            for name, value in expected["params"].items():
                assert relative_gap(result.params[name], value) <= RTOL, (model, name)
            for name in ("sse_mm2", "rmse_mm", "max_abs_residual_mm", "aicc"):
                assert relative_gap(getattr(result, name), expected[name]) <= RTOL, (model, name)
            assert relative_gap(result.residual_mm, expected["residual_mm"]) <= 1e-6


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


@pytest.mark.filterwarnings("ignore:invalid value:RuntimeWarning:reference_fits")
def test_edge_cases_agree_with_the_one_trial_code():
    x, y, depth = zip(*edge_trials(), strict=True)
    rows = fitting.fit_trials(x, y, depth, 3.0)
    expected = [reference_fits.fit_trial(*t, 3.0) for t in edge_trials()]
    # a flat profile is a straight line in ln x: both regressions fit it exactly, and
    # its AICc, ln of an SSE that is 0 or rounding noise, means nothing (-inf here)
    for row in (rows[4], expected[4]):
        assert abs(row["boussinesq_A_mm"]) < 1e-12 and row["boussinesq_rmse_mm"] < 1e-12
        row["boussinesq_aicc"] = np.nan
    assert_rows_agree(rows, expected)
    one, two, four, none, flat, steep, narrow, exact, _ = rows
    assert one["n_points"] == 1 and np.isfinite(one["waterbed_L_mm"])
    assert np.isnan(one["boussinesq_A_mm"]) and np.isnan(one["waterbed_L_ci_low_mm"])
    assert np.isfinite(two["boussinesq_A_mm"]) and np.isnan(two["boussinesq_aicc"])
    # the AICc needs n >= k + 2 (k counts the noise variance): 4 for a parabola, 5 for a line
    assert np.isfinite(four["waterbed_aicc"]) and np.isnan(four["boussinesq_aicc"])
    assert none["n_points"] == 0
    numbers = [v for k, v in none.items() if k not in ("depth_mm", "fit_window_mm", "n_points")]
    assert all(np.isnan(v) for v in numbers)
    assert flat["waterbed_L_mm"] == np.inf and np.isnan(flat["waterbed_L_ci_high_mm"])
    fold_mm = math.sqrt(6.0) * 2.0
    assert steep["shifted_L_mm"] == pytest.approx(fold_mm, rel=1e-6)
    assert steep["shifted_L_ci_low_mm"] == pytest.approx(fold_mm, rel=1e-6)
    assert narrow["waterbed_L_mm"] == pytest.approx(GRID_MM.max())
    assert exact["arc_L_mm"] == pytest.approx(10.0, rel=1e-7)


def test_a_trial_gets_the_same_numbers_in_any_batch(trials, monkeypatch):
    # alone, in a batch, in small chunks and small evaluation blocks: bit for bit
    subset = [(*t[2:], t[1]) for t in trials[:40]] + edge_trials()
    x, y, depth = zip(*subset, strict=True)
    together = fitting.fit_trials(x, y, depth, 3.0)
    monkeypatch.setattr(fitting, "CHUNK_TRIALS", 7)
    monkeypatch.setattr(fitting, "BLOCK_ELEMENTS", 1 << 10)
    reversed_ = fitting.fit_trials(x[::-1], y[::-1], depth[::-1], 3.0)[::-1]
    alone = [fitting.fit_trial(*t, 3.0) for t in subset]
    for rows in (reversed_, alone):
        for row, expected in zip(rows, together, strict=True):
            assert list(row) == list(expected)
            for name, value in expected.items():
                assert row[name] == value or (np.isnan(row[name]) and np.isnan(value)), name


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
        assert_rows_agree(rows, single)
        for row in rows:
            keep = (args[0] > 0) & (args[0] <= row["fit_window_mm"]) & np.isfinite(args[1])
            reference = getattr(reference_fits, f"fit_{row['model']}")
            fixed = row["model"] in ("waterbed", "shifted", "arc")
            expected = reference(args[0][keep], args[1][keep], *((args[2],) if fixed else ()))
            for name, value in expected["params"].items():
                assert relative_gap(row[name], value) <= RTOL
            assert relative_gap(row["aicc"], expected["aicc"]) <= RTOL


def test_trial_checks_batch_agree_with_the_one_trial_code(trials):
    subset = trials[::10]
    x, y, depth = ([t[k] for t in subset] for k in (2, 3, 1))
    checks = sensitivity.trial_checks_batch(x, y, depth, 3.0, 0.1)
    expected = [
        reference_fits.trial_checks(*args, 3.0, 0.1) for args in zip(x, y, depth, strict=True)
    ]
    assert_rows_agree(checks, expected)
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
