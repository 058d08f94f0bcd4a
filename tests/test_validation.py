"""Broken raw data (or config) is refused before any job runs, one clear line per problem.

Two layers:

* end to end: a real ``snakemake --cores 2`` on the small dataset of conftest
  with exactly one thing broken must exit non-zero, print exactly one
  ``Error: ...`` line naming file, line and column and what was expected, show
  no traceback and leave no results folder behind; a lab's export with
  several things broken gets every problem in one run, and files no subject
  reads get ``Warning:`` lines;
* unit: ``lineload.rawdata.validation`` called directly (fast), for typing, line
  numbers, the rules that span rows or files, and the plausibility of units.

Line numbers in the expectations are computed from where the test puts the
bad cell (the header is line 1), never copied from the program's output.
"""

from __future__ import annotations

import random
import re
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from conftest import refused_run, run_snakemake, write_small_dataset
from lineload.io import load_schema
from lineload.rawdata.validation import (
    InputError,
    Problems,
    check_dataset,
    check_deflection_near_wedge,
    check_depth_range,
    check_no_duplicate_readings,
    check_subjects,
    collecting,
    read_table,
    report_lines,
)

SCHEMAS = {name: load_schema(name) for name in ("subjects", "profiles", "outlines")}
PROFILE_KEYS = ("depth_mm", "side", "distance_image_mm")


# --------------------------------------------------------------------------- helpers


def read_lines(path):
    return Path(path).read_text().splitlines()


def write_lines(path, lines):
    Path(path).write_text("\n".join(lines) + "\n")


def find_line(path, predicate, nth=0):
    """1-based number of the ``nth`` data line (header excluded) satisfying ``predicate``."""
    hits = [i + 1 for i, text in enumerate(read_lines(path)) if i > 0 and predicate(text)]
    return hits[nth]


def set_cell(path, line_no, column, value):
    """Replace one cell (line ``line_no``, 1-based, header is 1) and return the old text."""
    lines = read_lines(path)
    header = lines[0].split(",")
    cells = lines[line_no - 1].split(",")
    j = header.index(column)
    old, cells[j] = cells[j], value
    lines[line_no - 1] = ",".join(cells)
    write_lines(path, lines)
    return old


def drop_column(path, column):
    lines = read_lines(path)
    j = lines[0].split(",").index(column)
    write_lines(path, [",".join(c for k, c in enumerate(t.split(",")) if k != j) for t in lines])


def write_outline(path, depths=(1.0,), bad_state_at=None, bad_state="relaxed"):
    """A valid outline file (resting and deformed traces); optionally one bad state.

    Returns the 1-based line of the bad row (or None).
    """
    path.parent.mkdir(parents=True, exist_ok=True)
    lines = ["depth_mm,state,x_image_mm,z_image_mm"]
    for depth in depths:
        for state in ("resting", "deformed"):
            for x in np.linspace(-60, 60, 7):
                lines.append(f"{depth:g},{state},{x:.3f},{-abs(x) / 10:.3f}")
    bad_line = None
    if bad_state_at is not None:
        bad_line = bad_state_at
        cells = lines[bad_line - 1].split(",")
        cells[1] = bad_state
        lines[bad_line - 1] = ",".join(cells)
    write_lines(path, lines)
    return bad_line


def reported_line(message):
    """The first 'line <n>' of a message (where the error is), as an int."""
    found = re.search(r"\bline (\d+)\b", message)
    return int(found.group(1)) if found else None


def error(call, *args, **kwargs):
    with pytest.raises(InputError) as caught:
        call(*args, **kwargs)
    return str(caught.value)


# ------------------------------------------------------------- end to end: one corruption


@dataclass
class Expect:
    file: str | None  # relative to the raw folder; None for config errors
    line: int | None  # None when the error is about the whole file
    columns: tuple = ()  # column names the message must name
    words: tuple = ()  # words of what was expected / what was found
    config: tuple = ()  # extra --config KEY=VALUE
    prefix: str | None = None  # required start of the message instead of the file


def _mk(raw):
    return raw / "profiles" / "MK.csv"


def _hu(raw):
    return raw / "profiles" / "HU.csv"


def _subjects(raw):
    return raw / "subjects.csv"


def _bad_number(column, value, *words, subject="MK", block="2,left,", offset=3):
    """A bad cell a few rows into a block of a profile (not its first row)."""

    def corrupt(raw):
        path = raw / "profiles" / f"{subject}.csv"
        n = find_line(path, lambda t: t.startswith(block), nth=offset)
        set_cell(path, n, column, value)
        return Expect(f"profiles/{subject}.csv", n, (column,), ("number", *words))

    return corrupt


def _bad_side(raw):
    n = find_line(_mk(raw), lambda t: t.startswith("2,right,"), nth=5)
    set_cell(_mk(raw), n, "side", "middle")
    return Expect(
        "profiles/MK.csv",
        n,
        ("side",),
        (*SCHEMAS["profiles"]["properties"]["side"]["enum"], "middle"),
    )


def _missing_column(raw):
    drop_column(_mk(raw), "side")
    return Expect("profiles/MK.csv", 1, ("side",), ("missing",))


def _empty_file(raw):
    _hu(raw).write_text("")
    return Expect("profiles/HU.csv", None, (), ("empty",))


def _header_only(raw):
    write_lines(_hu(raw), read_lines(_hu(raw))[:1])
    return Expect("profiles/HU.csv", None, (), ("row",))


def _duplicate_reading(raw):
    path = _mk(raw)
    lines = read_lines(path)
    first = find_line(path, lambda t: t.startswith("1,right,"), nth=4)
    copy = lines[first - 1].split(",")
    copy[3] = "99.999"  # same depth, side and distance, other deflection
    at = find_line(path, lambda t: t.startswith("2,left,"), nth=2)  # later in the file
    lines.insert(at - 1, ",".join(copy))
    write_lines(path, lines)
    return Expect("profiles/MK.csv", at, PROFILE_KEYS, ("duplicate", f"line {first}"))


def _missing_profile(raw):
    _hu(raw).unlink()
    n = find_line(_subjects(raw), lambda t: t.startswith("HU,"))
    return Expect("subjects.csv", n, ("subject",), ("profile", "HU.csv"))


def _bad_species(raw):
    n = find_line(_subjects(raw), lambda t: t.startswith("HU,"))
    set_cell(_subjects(raw), n, "species", "dog")
    return Expect(
        "subjects.csv",
        n,
        ("species",),
        (*SCHEMAS["subjects"]["properties"]["species"]["enum"], "dog"),
    )


def _bad_magnification(value):
    def corrupt(raw):
        n = find_line(_subjects(raw), lambda t: t.startswith("HU,"))
        set_cell(_subjects(raw), n, "magnification", value)
        return Expect("subjects.csv", n, ("magnification",), ("number", "> 0", value))

    return corrupt


def _unsafe_subject(raw):
    n = find_line(_subjects(raw), lambda t: t.startswith("HU,"))
    set_cell(_subjects(raw), n, "subject", "../x")
    # make the traversal real: profiles/../x.csv exists, so only the id's form is wrong
    shutil.copy(_hu(raw), raw / "x.csv")
    return Expect("subjects.csv", n, ("subject",), ("'../x'", "letters"))


def _ragged(extra):
    def corrupt(raw):
        path = _mk(raw)
        n = find_line(path, lambda t: t.startswith("1,right,"), nth=6)
        lines = read_lines(path)
        lines[n - 1] = lines[n - 1] + ",7" if extra else lines[n - 1].rsplit(",", 1)[0]
        write_lines(path, lines)
        return Expect("profiles/MK.csv", n, (), ("fields", "4", "5" if extra else "3"))

    return corrupt


def _duplicate_subject(raw):
    lines = read_lines(_subjects(raw))
    first = find_line(_subjects(raw), lambda t: t.startswith("MK,"))
    lines.append("MK,monkey,20,again")
    write_lines(_subjects(raw), lines)
    return Expect("subjects.csv", len(lines), ("subject",), ("MK", "unique", f"line {first}"))


def _bad_outline(raw):
    path = raw / "outlines" / "MK.csv"
    n = write_outline(path, depths=(1.0, 2.0), bad_state_at=11)
    return Expect(
        "outlines/MK.csv",
        n,
        ("state",),
        (*SCHEMAS["outlines"]["properties"]["state"]["enum"], "relaxed"),
    )


def _separated_by(separator, subject="MK"):
    """The whole profile written with another separator, as some spreadsheet exports do."""

    def corrupt(raw):
        path = raw / "profiles" / f"{subject}.csv"
        write_lines(path, [t.replace(",", separator) for t in read_lines(path)])
        name = {";": "semicolons", "\t": "tabs"}[separator]
        return Expect(f"profiles/{subject}.csv", 1, (), ("comma-separated", name))

    return corrupt


def _header_in_other_case(raw):
    lines = read_lines(_mk(raw))
    lines[0] = lines[0].replace("depth_mm", "Depth_mm")
    write_lines(_mk(raw), lines)
    return Expect("profiles/MK.csv", 1, ("depth_mm",), ("found 'Depth_mm'", "expected 'depth_mm'"))


def _file_named(name):
    def corrupt(raw):
        _hu(raw).rename(raw / "profiles" / name)
        n = find_line(_subjects(raw), lambda t: t.startswith("HU,"))
        return Expect(
            "subjects.csv",
            n,
            ("subject",),
            (f"expected {raw}/profiles/HU.csv", f"found {raw}/profiles/{name}"),
        )

    return corrupt


def _depths_in_micrometres(raw):
    path = _mk(raw)
    lines = read_lines(path)
    for i in range(1, len(lines)):
        cells = lines[i].split(",")
        cells[0] = f"{float(cells[0]) * 1000:g}"
        lines[i] = ",".join(cells)
    write_lines(path, lines)
    return Expect("profiles/MK.csv", 2, ("depth_mm",), ("micrometres", "1000", "10 mm"))


def _scaled_readings(factor, *words):
    """HU's readings multiplied by a factor (1/20: already in tissue mm; -1: upward positive)."""

    def corrupt(raw):
        path = _hu(raw)
        lines = read_lines(path)
        for i in range(1, len(lines)):
            cells = lines[i].split(",")
            cells[3] = f"{float(cells[3]) * factor:.4f}"
            lines[i] = ",".join(cells)
        write_lines(path, lines)
        # rows go depth by depth, left side first, distances ascending: the reading
        # nearest the wedge on the left is the first data line
        return Expect("profiles/HU.csv", 2, ("deflection_image_mm",), ("nearest", *words))

    return corrupt


def _set_reading(column, value, *words, subject="MK", block="2,left,", offset=3):
    """One reading of a profile set to ``value``; the message names ``words``."""

    def corrupt(raw):
        path = raw / "profiles" / f"{subject}.csv"
        n = find_line(path, lambda t: t.startswith(block), nth=offset)
        set_cell(path, n, column, value)
        return Expect(f"profiles/{subject}.csv", n, (column,), words)

    return corrupt


def _thin_trial(raw):
    """MK at 2 mm keeps two readings within the 3 mm window (the left side's first two)."""
    path = _mk(raw)
    lines = read_lines(path)
    kept, near_left = [lines[0]], 0
    for text in lines[1:]:
        depth, side, distance, _ = text.split(",")
        if depth == "2" and float(distance) / 20 <= 3.0:
            near_left += side == "left"
            if side != "left" or near_left > 2:
                continue
        kept.append(text)
    write_lines(path, kept)
    first = find_line(path, lambda t: t.startswith("2,"))
    return Expect(
        "profiles/MK.csv",
        first,
        ("distance_image_mm",),
        ("depth 2 mm 2 distances", "at least 5", "min_points_in_window"),
    )


def _magnification_beyond_a_photograph(raw):
    n = find_line(_subjects(raw), lambda t: t.startswith("HU,"))
    set_cell(_subjects(raw), n, "magnification", "1e6")
    return Expect("subjects.csv", n, ("magnification",), ("1000", "1e6"))


def _outline_point_beyond_any_finger(raw):
    path = raw / "outlines" / "MK.csv"
    write_outline(path, depths=(1.0, 2.0))
    set_cell(path, 6, "z_image_mm", "1e300")
    return Expect("outlines/MK.csv", 6, ("z_image_mm",), ("reach_max_mm", "fingertip"))


def _config(*settings, words):
    def refuse_config(raw):
        return Expect(None, None, (), words, config=settings, prefix="Error: config")

    return refuse_config


def _folders(setting, key, *words):
    """A results (or raw) folder where the workflow must not write: ``setting(raw)``
    gives the --config entry."""

    def refuse_config(raw):
        prefix = f"Error: config, key '{key}'"
        return Expect(None, None, (), words, config=(setting(raw),), prefix=prefix)

    return refuse_config


CASES = {
    "text_in_number": _bad_number("deflection_image_mm", "abc", "'abc'"),
    "nan_in_number": _bad_number("distance_image_mm", "NaN", "NaN", subject="HU", block="1,right,"),
    "empty_number_cell": _bad_number("deflection_image_mm", "", "empty"),
    "inf_in_number": _bad_number("deflection_image_mm", "inf", "inf", block="1,left,", offset=8),
    # Python's float() reads both as numbers (99 and 12); a person does not
    "digit_separator_in_number": _bad_number(
        "deflection_image_mm", "9_9", "'9_9'", "digit separators", block="1,left,", offset=4
    ),
    "other_digits_in_number": _bad_number(
        "distance_image_mm",
        "\u0661\u0662",
        "digit separators",
        subject="HU",
        block="1,right,",
        offset=5,
    ),
    "negative_distance": _bad_number("distance_image_mm", "-1.000", ">= 0", "-1.000"),
    "zero_depth": _bad_number("depth_mm", "0", "> 0", offset=10),
    "negative_depth": _bad_number("depth_mm", "-1", "> 0", "-1", block="1,right,"),
    "bad_side": _bad_side,
    "missing_column": _missing_column,
    "empty_file": _empty_file,
    "header_only_file": _header_only,
    "duplicate_reading": _duplicate_reading,
    "subject_without_profile": _missing_profile,
    "bad_species": _bad_species,
    "zero_magnification": _bad_magnification("0"),
    "magnification_beyond_a_photograph": _magnification_beyond_a_photograph,
    "negative_magnification": _bad_magnification("-20"),
    "unsafe_subject_id": _unsafe_subject,
    "ragged_row_extra_field": _ragged(extra=True),
    "ragged_row_missing_field": _ragged(extra=False),
    "duplicate_subject_id": _duplicate_subject,
    "bad_outline_state": _bad_outline,
    "semicolon_separated": _separated_by(";"),
    "tab_separated": _separated_by("\t", subject="HU"),
    "header_in_other_case": _header_in_other_case,
    "file_name_in_capitals": _file_named("HU.CSV"),
    "file_name_other_case": _file_named("hu.csv"),
    "file_with_txt_extension": _file_named("HU.txt"),
    "depth_in_micrometres": _depths_in_micrometres,
    # magnitudes no fingertip has: refused with the limit, not fitted into infinities
    "distance_beyond_any_finger": _set_reading(
        "distance_image_mm", "1e300", "reach_max_mm", "fingertip"
    ),
    "distance_in_micrometres": _set_reading(
        "distance_image_mm", "40000", "reach_max_mm", "micrometres", subject="HU", block="1,"
    ),
    "deflection_far_beyond_the_depth": _set_reading(
        "deflection_image_mm", "1e6", "deflection_factor", "times the depth", offset=6
    ),
    "outline_point_beyond_any_finger": _outline_point_beyond_any_finger,
    "trial_too_thin_to_fit": _thin_trial,
    "readings_already_in_tissue_mm": _scaled_readings(1 / 20, "magnification", "should be 1"),
    "readings_upward_positive": _scaled_readings(-1, "upward positive"),
    "depth_beyond_a_configured_limit": lambda raw: Expect(
        "profiles/MK.csv",
        find_line(_mk(raw), lambda t: t.startswith("2,")),
        ("depth_mm",),
        ("between 0.05 and 1.5 mm", "got 2"),
        config=("input_checks__depth_max_mm=1.5",),
    ),
    "config_unknown_key": _config("colour=red", words=("colour",)),
    "config_wrong_type": _config("fit_window_mm=abc", words=("fit_window_mm", "number")),
    "config_not_positive": _config("fit_window_mm=0", words=("fit_window_mm", "0")),
    "config_beyond_its_range": _config(
        "figures__png_dpi=100000", words=("png_dpi", "maximum of 1200")
    ),
    "results_at_the_root": _folders(lambda raw: "results=/", "results", "root"),
    "results_inside_the_raw_folder": _folders(
        lambda raw: f"results={raw}/derived", "results", "inside the raw-data folder"
    ),
    "raw_inside_the_results_folder": _folders(
        lambda raw: f"results={raw.parent}", "raw_data", "inside the results folder"
    ),
}


#: One case of each way a refusal reaches the user through a real Snakemake run: a
#: profile's cell, a file's name, the sheet against the files, the sheet alone (start-up),
#: a plausibility rule, a config value the check reads, and the config itself.  Every
#: case's message is checked, in process, by the test after this one.
END_TO_END = (
    "text_in_number",
    "file_name_in_capitals",
    "subject_without_profile",
    "duplicate_subject_id",
    "readings_already_in_tissue_mm",
    "depth_beyond_a_configured_limit",
    "config_unknown_key",
    "config_wrong_type",
    "config_not_positive",
    "config_beyond_its_range",
    "results_at_the_root",
    "results_inside_the_raw_folder",
    "raw_inside_the_results_folder",
)


def check_message(message, raw, expect):
    """The one error line says what ``expect`` asks: file, line, columns and words."""
    if expect.file is not None:
        assert message.startswith(f"Error: {raw}/{expect.file}"), message
    if expect.prefix is not None:
        assert message.startswith(expect.prefix), message
    if expect.line is not None:
        assert reported_line(message) == expect.line, message
    else:
        assert reported_line(message) is None, message
    for column in expect.columns:
        assert column in message, (column, message)
    if len(expect.columns) == 1:
        assert f"column '{expect.columns[0]}'" in message, message
    if expect.file is not None:  # config messages are jsonschema's ("... is not of type ...")
        assert "expected" in message, message
    for word in expect.words:
        assert word in message, (word, message)


@pytest.mark.e2e
@pytest.mark.parametrize("name", END_TO_END)
def test_broken_input_is_refused_with_one_line(name, tmp_path, snakemake_available):
    raw = write_small_dataset(tmp_path / "raw")
    expect = CASES[name](raw)
    _, output, errors = refused_run(raw, tmp_path / "out", expect.config)
    assert len(errors) == 1, output
    check_message(errors[0], raw, expect)


def config_checks(settings):
    """The ``input_checks`` a ``--config input_checks__key=value`` list sets."""
    checks = {}
    for setting in settings:
        key, value = setting.split("=", 1)
        if key.startswith("input_checks__"):
            checks[key.removeprefix("input_checks__")] = float(value)
    return checks


@pytest.mark.parametrize(
    "name", [n for n in CASES if CASES[n].__name__ != "refuse_config"], ids=str
)
def test_every_broken_raw_folder_is_refused_by_the_check_with_one_line(name, tmp_path):
    """What the check job (rule check_raw_data) prints for each broken folder: the same
    function, called in process; the sheet is checked there too, as at start-up."""
    raw = write_small_dataset(tmp_path / "raw")
    expect = CASES[name](raw)
    schemas = {table: load_schema(table) for table in ("subjects", "profiles", "outlines")}
    schemas["forces"] = load_schema("forces")
    top = load_schema("config")["properties"]
    window = (top["fit_window_mm"]["default"], top["min_points_in_window"]["default"])
    with pytest.raises(InputError) as caught:
        check_dataset(str(raw), schemas, plausibility=config_checks(expect.config), window=window)
    lines = report_lines(caught.value)
    errors = [line for line in lines if line.startswith("Error: ")]  # warnings aside
    assert len(errors) == 1, lines
    check_message(errors[0], raw, expect)


@pytest.mark.e2e
def test_clean_dataset_runs_green(tmp_path, snakemake_available):
    """The unbroken dataset passes the same command: each refusal above is the corruption's."""
    raw = write_small_dataset(tmp_path / "raw")
    results = tmp_path / "out"

    proc = run_snakemake("fits", raw=str(raw), results=str(results))
    output = proc.stdout + proc.stderr
    assert proc.returncode == 0, output
    assert not [line for line in output.splitlines() if line.startswith("Error")], output
    table = pd.read_csv(results / "tables" / "fits.csv")
    assert sorted(set(zip(table["subject"], table["depth_mm"], strict=True))) == [
        ("HU", 1.0),
        ("MK", 1.0),
        ("MK", 2.0),
    ]

    again = run_snakemake("fits", "--dry-run", raw=str(raw), results=str(results))
    assert again.returncode == 0, again.stdout + again.stderr
    assert "Nothing to be done" in again.stdout + again.stderr


@pytest.mark.e2e
def test_target_goes_before_config(tmp_path, snakemake_available):
    """A target passed to run_snakemake must be a target, not a --config word."""
    raw = write_small_dataset(tmp_path / "raw")
    proc = run_snakemake("fits", "-n", raw=str(raw), results=str(tmp_path / "out"))
    output = proc.stdout + proc.stderr
    assert proc.returncode == 0, output
    assert "fits_table" in output
    # a dry run writes nothing: the new results folder is not even made
    assert not (tmp_path / "out").exists()


# ----------------------------------------------------------------------- unit: read_table


@pytest.fixture
def raw(tmp_path):
    return write_small_dataset(tmp_path / "raw")


def test_valid_profile_comes_back_typed(raw):
    path = raw / "profiles" / "MK.csv"
    table = read_table(path, SCHEMAS["profiles"])
    rows = [line.split(",") for line in read_lines(path)[1:]]

    header = read_lines(path)[0].split(",")
    assert len(table) == len(rows)
    for column in ("depth_mm", "distance_image_mm", "deflection_image_mm"):
        k = header.index(column)
        assert table[column].dtype == np.float64, column
        np.testing.assert_array_equal(table[column].to_numpy(), [float(r[k]) for r in rows])
    assert list(table["side"]) == [r[1] for r in rows]
    assert all(isinstance(v, str) for v in table["side"])


def test_valid_subjects_typed_and_extra_column_kept(raw):
    table = read_table(raw / "subjects.csv", SCHEMAS["subjects"])
    assert list(table["subject"]) == ["MK", "HU"]
    assert table["magnification"].dtype == np.float64
    assert list(table["magnification"]) == [20.0, 20.0]
    assert "label" in table.columns
    assert list(table["label"]) == ["monkey MK", "human HU"]


def test_extra_column_in_profile_kept_as_text(raw):
    path = raw / "profiles" / "HU.csv"
    lines = read_lines(path)
    write_lines(path, [lines[0] + ",note"] + [t + f",n{i:03d}" for i, t in enumerate(lines[1:])])
    table = read_table(path, SCHEMAS["profiles"])
    assert list(table["note"]) == [f"n{i:03d}" for i in range(len(lines) - 1)]
    assert table["distance_image_mm"].dtype == np.float64


def test_column_order_does_not_matter(raw):
    path = raw / "profiles" / "MK.csv"
    before = read_table(path, SCHEMAS["profiles"])
    order = [3, 1, 0, 2]
    write_lines(path, [",".join(t.split(",")[k] for k in order) for t in read_lines(path)])
    after = read_table(path, SCHEMAS["profiles"])
    pd.testing.assert_frame_equal(after[list(before.columns)], before)


def test_row_order_does_not_matter(raw):
    path = raw / "profiles" / "MK.csv"
    before = read_table(path, SCHEMAS["profiles"])
    depths_before = check_dataset(str(raw), SCHEMAS)["depths_mm"]
    lines = read_lines(path)
    body = lines[1:]
    random.Random(3).shuffle(body)
    assert body != lines[1:]
    write_lines(path, [lines[0], *body])

    after = read_table(path, SCHEMAS["profiles"])
    check_no_duplicate_readings(after, str(path))
    keys = list(before.columns)
    pd.testing.assert_frame_equal(
        after.sort_values(keys).reset_index(drop=True),
        before.sort_values(keys).reset_index(drop=True),
    )
    assert check_dataset(str(raw), SCHEMAS)["depths_mm"] == depths_before


@pytest.mark.parametrize("where", ["second", "middle", "last"])
@pytest.mark.parametrize(
    ("table", "column", "value"),
    [
        ("profiles/MK.csv", "deflection_image_mm", "oops"),
        ("profiles/MK.csv", "distance_image_mm", "-3"),
        ("profiles/MK.csv", "side", "up"),
        ("profiles/MK.csv", "depth_mm", "0"),
        ("subjects.csv", "subject", "a/b"),
        ("subjects.csv", "species", "cat"),
        ("subjects.csv", "magnification", "nan"),
    ],
)
def test_message_names_the_bad_line_and_column(raw, table, column, value, where):
    path = raw / table
    n_lines = len(read_lines(path))
    line = {"second": 3, "middle": n_lines // 2 + 1, "last": n_lines}[where]
    set_cell(path, line, column, value)
    schema = SCHEMAS[table.split("/")[0].removesuffix(".csv")]
    message = error(read_table, path, schema, display_path="shown/" + table)
    assert message.startswith(f"shown/{table}, "), message
    assert reported_line(message) == line, message
    assert f"column '{column}'" in message
    assert "expected" in message and repr(value) in message


def test_first_of_several_bad_rows_is_reported(raw):
    path = raw / "profiles" / "HU.csv"
    set_cell(path, 9, "side", "top")
    set_cell(path, 20, "side", "bottom")
    message = error(read_table, path, SCHEMAS["profiles"])
    assert reported_line(message) == 9 and "'top'" in message


@pytest.mark.parametrize("value", ["", "  ", "NaN", "nan", "inf", "-inf", "1e400", "1,5", "abc"])
def test_every_non_finite_or_non_number_is_refused(raw, value):
    path = raw / "profiles" / "HU.csv"
    line = 6
    lines = read_lines(path)
    cells = lines[line - 1].split(",")
    cells[3] = f'"{value}"' if "," in value else value
    lines[line - 1] = ",".join(cells)
    write_lines(path, lines)
    message = error(read_table, path, SCHEMAS["profiles"])
    assert reported_line(message) == line, message
    assert "column 'deflection_image_mm'" in message and "number" in message


def test_spaces_around_cells_and_crlf_are_accepted(raw):
    path = raw / "profiles" / "HU.csv"
    lines = read_lines(path)
    spaced = [", ".join(t.split(",")) for t in lines]
    path.write_bytes(("\r\n".join(spaced) + "\r\n").encode())
    table = read_table(path, SCHEMAS["profiles"])
    assert len(table) == len(lines) - 1
    assert set(table["side"]) == {"left", "right"}
    assert table["depth_mm"].dtype == np.float64


def test_byte_order_mark_is_not_part_of_the_first_column(raw):
    """Spreadsheets save 'CSV UTF-8' with a BOM; the first column must still be found."""
    path = raw / "subjects.csv"
    path.write_bytes(b"\xef\xbb\xbf" + path.read_bytes())
    table = read_table(path, SCHEMAS["subjects"])
    assert list(table["subject"]) == ["MK", "HU"]


def test_missing_file(raw):
    message = error(read_table, raw / "profiles" / "ZZ.csv", SCHEMAS["profiles"], "p/ZZ.csv")
    assert message.startswith("p/ZZ.csv") and "not found" in message


@pytest.mark.parametrize("text", ["", "\n", "  \n\n"])
def test_empty_file(raw, text):
    path = raw / "profiles" / "HU.csv"
    path.write_text(text)
    message = error(read_table, path, SCHEMAS["profiles"])
    assert message.startswith(str(path)) and "empty" in message
    for column in SCHEMAS["profiles"]["required"]:
        assert column in message  # says which header was expected


@pytest.mark.parametrize("tail", ["", "\n", "\n\n  \n"])
def test_header_only_file(raw, tail):
    path = raw / "profiles" / "HU.csv"
    path.write_text(read_lines(path)[0] + tail)
    message = error(read_table, path, SCHEMAS["profiles"])
    assert message.startswith(str(path)) and "no data rows" in message
    assert "expected" in message


@pytest.mark.parametrize("column", SCHEMAS["profiles"]["required"])
def test_each_missing_required_column(raw, column):
    path = raw / "profiles" / "MK.csv"
    drop_column(path, column)
    message = error(read_table, path, SCHEMAS["profiles"])
    assert reported_line(message) == 1 and f"column '{column}'" in message
    assert "missing" in message


def test_column_named_twice(raw):
    path = raw / "subjects.csv"
    lines = read_lines(path)
    write_lines(path, [lines[0] + ",species"] + [t + ",human" for t in lines[1:]])
    message = error(read_table, path, SCHEMAS["subjects"])
    assert reported_line(message) == 1 and "column 'species'" in message and "twice" in message


@pytest.mark.parametrize("extra", [True, False])
def test_ragged_row_line(raw, extra):
    path = raw / "profiles" / "MK.csv"
    lines = read_lines(path)
    line = len(lines) - 4
    lines[line - 1] = lines[line - 1] + ",x" if extra else lines[line - 1].rsplit(",", 1)[0]
    write_lines(path, lines)
    message = error(read_table, path, SCHEMAS["profiles"])
    assert reported_line(message) == line, message
    assert "fields" in message


def test_outline_valid_and_bad_state(raw):
    path = raw / "outlines" / "MK.csv"
    write_outline(path, depths=(1.0, 2.0))
    table = read_table(path, SCHEMAS["outlines"])
    assert table["x_image_mm"].dtype == np.float64
    assert set(table["state"]) == {"resting", "deformed"}
    line = write_outline(path, depths=(1.0, 2.0), bad_state_at=17, bad_state="Resting")
    message = error(read_table, path, SCHEMAS["outlines"])
    assert reported_line(message) == line and "column 'state'" in message and "'Resting'" in message


# ------------------------------------------------------- unit: duplicate readings


HEADER = "depth_mm,side,distance_image_mm,deflection_image_mm\n"


def test_no_duplicates_in_clean_profile(raw):
    for subject in ("MK", "HU"):
        path = raw / "profiles" / f"{subject}.csv"
        check_no_duplicate_readings(read_table(path, SCHEMAS["profiles"]), str(path))


def test_same_distance_on_other_side_or_depth_is_not_a_duplicate(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text(HEADER + "1,left,2,5\n1,right,2,5\n2,left,2,5\n2,right,2,5\n1,left,3,5\n")
    check_no_duplicate_readings(read_table(path, SCHEMAS["profiles"]), "p.csv")


def test_duplicate_reading_names_both_lines(tmp_path):
    path = tmp_path / "p.csv"
    # line 5 repeats line 3 numerically ("1" == "1.0", "2" == "2.00"), other deflection
    path.write_text(HEADER + "1,left,1,5\n1,left,2,5\n1,right,2,5\n1.0,left,2.00,9\n")
    profile = read_table(path, SCHEMAS["profiles"])
    message = error(check_no_duplicate_readings, profile, "shown.csv")
    assert message.startswith("shown.csv, ")
    assert reported_line(message) == 5
    assert "line 3" in message
    for key in PROFILE_KEYS:
        assert key in message


def test_duplicate_reading_after_shuffle_names_the_later_line(tmp_path):
    path = tmp_path / "p.csv"
    path.write_text(HEADER + "2,right,4,1\n1,left,1,5\n1,right,2,5\n2,right,4,3\n1,left,3,5\n")
    message = error(check_no_duplicate_readings, read_table(path, SCHEMAS["profiles"]), "p")
    assert reported_line(message) == 5 and "line 2" in message


# ------------------------------------------------------------ unit: subjects sheet


def test_check_subjects_clean(raw):
    subjects = read_table(raw / "subjects.csv", SCHEMAS["subjects"])
    check_subjects(subjects, "s.csv", str(raw / "profiles"))


def test_check_subjects_duplicate_id(raw):
    path = raw / "subjects.csv"
    lines = read_lines(path)
    write_lines(path, [*lines, "ZZ,human,20,z", "HU,human,10,again"])
    (raw / "profiles" / "ZZ.csv").write_text((raw / "profiles" / "HU.csv").read_text())
    subjects = read_table(path, SCHEMAS["subjects"])
    message = error(check_subjects, subjects, "s.csv", str(raw / "profiles"))
    assert reported_line(message) == len(lines) + 2
    assert "'HU'" in message and f"line {find_line(path, lambda t: t.startswith('HU,'))}" in message
    assert "column 'subject'" in message


def test_check_subjects_missing_profile(raw):
    (raw / "profiles" / "HU.csv").unlink()
    subjects = read_table(raw / "subjects.csv", SCHEMAS["subjects"])
    message = error(check_subjects, subjects, "s.csv", str(raw / "profiles"), "P")
    assert message.startswith("s.csv, ")
    assert reported_line(message) == find_line(raw / "subjects.csv", lambda t: t.startswith("HU,"))
    assert "column 'subject'" in message and "P/HU.csv" in message


@pytest.mark.parametrize("subject", ["../x", "a b", "x.csv", "", "/etc/passwd", "é"])
def test_unsafe_subject_ids_are_refused(raw, subject):
    path = raw / "subjects.csv"
    set_cell(path, 3, "subject", subject)
    message = error(read_table, path, SCHEMAS["subjects"])
    assert reported_line(message) == 3 and "column 'subject'" in message


# --------------------------------------------------------------- unit: check_dataset


def test_check_dataset_clean(raw):
    dataset = check_dataset(str(raw), SCHEMAS)
    assert dataset["depths_mm"] == {"MK": [1.0, 2.0], "HU": [1.0]}
    assert dataset["outlines"] == {}
    assert list(dataset["subjects"]["subject"]) == ["MK", "HU"]


def test_check_dataset_reads_outlines(raw):
    write_outline(raw / "outlines" / "MK.csv", depths=(2.0, 1.0))
    write_outline(raw / "outlines" / "NOT_LISTED.csv")  # not a listed subject: not reported
    assert check_dataset(str(raw), SCHEMAS)["outlines"] == {"MK": [1.0, 2.0]}


def test_check_dataset_names_files_as_shown(raw):
    set_cell(raw / "profiles" / "HU.csv", 4, "side", "centre")
    message = error(check_dataset, str(raw), SCHEMAS, "data/raw/")
    assert message.startswith("data/raw/profiles/HU.csv, ")
    assert reported_line(message) == 4


def test_check_dataset_refuses_duplicate_reading_and_missing_sheet(raw):
    path = raw / "profiles" / "HU.csv"
    lines = read_lines(path)
    write_lines(path, [*lines, lines[7]])
    message = error(check_dataset, str(raw), SCHEMAS)
    assert reported_line(message) == len(lines) + 1 and "line 8" in message
    (raw / "subjects.csv").unlink()
    message = error(check_dataset, str(raw), SCHEMAS)
    assert message.startswith(f"{raw}/subjects.csv") and "not found" in message


# ----------------------------------------------- line numbers, encodings and ids that once broke


def test_line_number_after_a_blank_line(raw):
    path = raw / "profiles" / "MK.csv"
    lines = read_lines(path)
    lines.insert(5, "")  # blank line 6
    write_lines(path, lines)
    set_cell(path, 10, "side", "up")
    assert reported_line(error(read_table, path, SCHEMAS["profiles"])) == 10


def test_line_number_after_a_multiline_cell(raw):
    path = raw / "subjects.csv"
    lines = read_lines(path)
    lines[1] = lines[1].rsplit(",", 1)[0] + ',"two\nlines"'
    write_lines(path, lines)  # HU is now on line 4
    set_cell(path, 4, "species", "dog")
    assert reported_line(error(read_table, path, SCHEMAS["subjects"])) == 4


def test_file_not_in_utf8_is_an_input_error(raw):
    path = raw / "subjects.csv"
    path.write_bytes(path.read_text().replace("human HU", "Müller").encode("latin-1"))
    message = error(read_table, path, SCHEMAS["subjects"])
    assert message.startswith(str(path))
    assert "UTF-8" in message


def test_subject_id_starting_with_a_dash_is_refused(raw):
    path = raw / "subjects.csv"
    set_cell(path, 3, "subject", "-x")
    error(read_table, path, SCHEMAS["subjects"])


# ------------------------------------------- a new lab's export: every problem in one pass

LAB_DEPTHS = [0.75, 1.25, 1.75]


def write_lab_dataset(raw_dir):
    """Five subjects at 0.75, 1.25 and 1.75 mm, as a lab exported them (valid as written)."""
    return write_small_dataset(
        raw_dir,
        subjects={
            f"S-0{i}": ("monkey" if i <= 2 else "human", LAB_DEPTHS, 5.0 if i <= 2 else 9.0)
            for i in range(1, 6)
        },
    )


def make_messy(raw):
    """What went wrong in the lab's export, one thing per file; returns the expected errors
    as (file relative to raw, line, words) in the order the check reports them."""
    profiles = raw / "profiles"
    # S-01: a semicolon-separated export
    path = profiles / "S-01.csv"
    write_lines(path, [t.replace(",", ";") for t in read_lines(path)])
    # S-02: a header written in other capitals
    path = profiles / "S-02.csv"
    lines = read_lines(path)
    write_lines(path, [lines[0].replace("depth_mm", "Depth_mm"), *lines[1:]])
    # S-03: saved as S-03.CSV
    (profiles / "S-03.csv").rename(profiles / "S-03.CSV")
    # S-04: depths written in micrometres
    path = profiles / "S-04.csv"
    lines = read_lines(path)
    write_lines(
        path,
        [lines[0]]
        + [f"{float(t.split(',')[0]) * 1000:g}," + t.split(",", 1)[1] for t in lines[1:]],
    )
    # S-05: readings already in tissue mm, magnification 20 in the sheet
    path = profiles / "S-05.csv"
    lines = read_lines(path)
    scaled = []
    for t in lines[1:]:
        cells = t.split(",")
        cells[2] = f"{float(cells[2]) / 20:.4f}"
        cells[3] = f"{float(cells[3]) / 20:.4f}"
        scaled.append(",".join(cells))
    write_lines(path, [lines[0], *scaled])
    # and a profile file that no subject lists
    write_lines(profiles / "S-06.csv", read_lines(profiles / "S-04.csv")[:3])
    s03 = find_line(raw / "subjects.csv", lambda t: t.startswith("S-03,"))
    first_depth_line = {
        d: find_line(path, lambda t, d=d: t.startswith(f"{d:g},")) for d in LAB_DEPTHS
    }
    return [
        ("subjects.csv", s03, ("expected", "profiles/S-03.csv", "found", "profiles/S-03.CSV")),
        ("profiles/S-01.csv", 1, ("comma-separated", "semicolons")),
        ("profiles/S-02.csv", 1, ("column 'depth_mm'", "found 'Depth_mm'", "expected 'depth_mm'")),
        ("profiles/S-04.csv", 2, ("column 'depth_mm'", "got 750", "micrometres")),
        (
            "profiles/S-05.csv",
            first_depth_line[0.75],
            (
                "column 'deflection_image_mm'",
                "at depth 0.75 mm",
                "so do depths 1.25, 1.75 mm",
                "should be 1, not 20",
            ),
        ),
    ]


def test_what_is_messy_but_valid_passes_without_a_word(tmp_path):
    """CRLF, BOM, trailing spaces, 1.250 beside 1.25, extra columns, unsorted, one-sided."""
    raw = write_lab_dataset(tmp_path / "raw")
    path = raw / "profiles" / "S-03.csv"
    lines = read_lines(path)
    header, body = lines[0] + ",note", [t + ",ok " for t in lines[1:]]
    body = [t.replace("1.25,", "1.250,", 1) if i % 2 else t for i, t in enumerate(body)]
    body = [t for t in body if not t.startswith("1.75,right,")]  # one side only at 1.75
    random.Random(5).shuffle(body)
    text = "\r\n".join([header] + [t.replace(",", ", ") + "  " for t in body]) + "\r\n"
    path.write_bytes(b"\xef\xbb\xbf" + text.encode())
    dataset = check_dataset(str(raw), SCHEMAS)
    assert dataset["warnings"] == []
    assert dataset["depths_mm"]["S-03"] == LAB_DEPTHS


def test_every_problem_of_a_messy_export_is_reported_at_once(tmp_path):
    raw = write_lab_dataset(tmp_path / "raw")
    expected = make_messy(raw)
    with pytest.raises(InputError) as caught:
        check_dataset(str(raw), SCHEMAS, "lab")
    problems = caught.value.problems
    assert len(problems) == len(expected), problems
    for message, (file, line, words) in zip(problems, expected, strict=True):
        assert message.startswith(f"lab/{file}, "), message
        assert reported_line(message) == line, message
        for word in words:
            assert word in message, (word, message)
    (warning,) = caught.value.warnings
    assert warning.startswith("lab/profiles/S-06.csv: ") and "no subject 'S-06'" in warning


@pytest.mark.e2e
def test_a_messy_export_is_refused_with_every_problem_in_one_run(tmp_path, snakemake_available):
    raw = write_lab_dataset(tmp_path / "raw")
    expected = make_messy(raw)
    proc, output, errors = refused_run(raw, tmp_path / "out")
    assert proc.returncode == 1, output
    assert [e.split(",")[0] for e in errors] == [f"Error: {raw}/{f}" for f, _, _ in expected]
    warnings = [line for line in output.splitlines() if line.startswith("Warning: ")]
    assert warnings == [
        f"Warning: {raw}/profiles/S-06.csv: no subject 'S-06' in {raw}/subjects.csv reads "
        "this profile file; it is ignored"
    ]


def test_report_lines_cap_the_errors_and_say_how_many_more():
    error = InputError([f"f.csv, line {n}: bad" for n in range(2, 27)], ["w.csv: unread"])
    lines = report_lines(error, limit=20)
    assert lines[0] == "Warning: w.csv: unread"
    assert lines[1:21] == [f"Error: f.csv, line {n}: bad" for n in range(2, 22)]
    assert lines[21].startswith("... and 5 more errors not shown")
    assert len(lines) == 22
    assert report_lines(InputError(["one"])) == ["Error: one"]


@pytest.mark.e2e
def test_a_run_prints_at_most_twenty_errors(tmp_path, snakemake_available):
    subjects = {f"M{i:02d}": ("monkey", [1.0], 5.0) for i in range(1, 24)}
    raw = write_small_dataset(tmp_path / "raw", subjects=subjects)
    for subject in subjects:
        set_cell(raw / "profiles" / f"{subject}.csv", 3, "side", "middle")
    proc = run_snakemake(raw=str(raw), results=str(tmp_path / "out"))
    output = proc.stdout + proc.stderr
    assert proc.returncode == 1, output
    errors = [line for line in output.splitlines() if line.startswith("Error: ")]
    assert len(errors) == 20
    assert errors[0].startswith(f"Error: {raw}/profiles/M01.csv, line 3, column 'side'")
    assert "... and 3 more errors not shown" in output


def test_every_bad_cell_of_a_file_is_counted_and_each_column_reported(raw):
    path = raw / "profiles" / "HU.csv"
    for line in (4, 9, 12):
        set_cell(path, line, "side", "up")
    set_cell(path, 7, "distance_image_mm", "x")
    with pytest.raises(InputError) as caught:
        read_table(path, SCHEMAS["profiles"])
    side, distance = sorted(caught.value.problems, key=lambda m: "side" not in m)
    assert reported_line(side) == 4 and "2 more" in side and "lines 9, 12" in side
    assert reported_line(distance) == 7 and "'x'" in distance
    # with a collector, the table comes back (bad numbers as NaN) and nothing is raised
    found = Problems()
    table = read_table(path, SCHEMAS["profiles"], problems=found)
    assert len(found.errors) == 2 and np.isnan(table.loc[7, "distance_image_mm"])


@pytest.mark.parametrize(("separator", "name"), [(";", "semicolons"), ("\t", "tabs")])
def test_another_separator_is_named(raw, separator, name):
    path = raw / "subjects.csv"
    write_lines(path, [t.replace(",", separator) for t in read_lines(path)])
    message = error(read_table, path, SCHEMAS["subjects"])
    assert reported_line(message) == 1 and name in message and "comma" in message


@pytest.mark.parametrize("found", ["Depth_mm", "DEPTH_MM", " depth mm", "depth-mm"])
def test_a_header_name_that_differs_in_case_or_spaces_is_shown_as_found(raw, found):
    path = raw / "profiles" / "MK.csv"
    lines = read_lines(path)
    write_lines(path, [lines[0].replace("depth_mm", found), *lines[1:]])
    message = error(read_table, path, SCHEMAS["profiles"])
    assert f"found {found.strip()!r}, expected 'depth_mm'" in message
    assert reported_line(message) == 1 and "column 'depth_mm'" in message


@pytest.mark.parametrize("name", ["HU.CSV", "hu.csv", "HU.txt", "HU", "HU .csv", "Hu.Csv"])
def test_a_file_name_that_differs_in_case_or_extension_is_shown(raw, name):
    (raw / "profiles" / "HU.csv").rename(raw / "profiles" / name)
    subjects = read_table(raw / "subjects.csv", SCHEMAS["subjects"])
    message = error(check_subjects, subjects, "s.csv", str(raw / "profiles"), "P")
    assert f"expected P/HU.csv, found P/{name}" in message
    # no extra warning about the same file: its error says it all
    with pytest.raises(InputError) as caught:
        check_dataset(str(raw), SCHEMAS)
    assert caught.value.warnings == []


def test_files_no_subject_reads_are_named_in_warnings(raw):
    write_lines(raw / "profiles" / "XX.csv", read_lines(raw / "profiles" / "HU.csv"))
    (raw / "profiles" / "notes.txt").write_text("where the data came from\n")
    (raw / "profiles" / ".DS_Store").write_bytes(b"\0")
    write_outline(raw / "outlines" / "MK.CSV")
    write_outline(raw / "outlines" / "ZZ.csv")
    dataset = check_dataset(str(raw), SCHEMAS, "r")
    assert dataset["warnings"] == [
        "r/profiles/XX.csv: no subject 'XX' in r/subjects.csv reads this profile file; "
        "it is ignored",
        "r/profiles/notes.txt: no subject 'notes' in r/subjects.csv reads this profile file; "
        "it is ignored",
        "r/outlines/MK.CSV: named like the outline of subject 'MK' but not exactly "
        "r/outlines/MK.csv, so it is not read",
        "r/outlines/ZZ.csv: no subject 'ZZ' in r/subjects.csv reads this outline file; "
        "it is ignored",
    ]
    assert dataset["outlines"] == {}


@pytest.mark.parametrize(
    ("depth", "words"),
    [
        ("750", ("got 750", "micrometres", "0.75 mm")),
        ("20", ("got 20", "x20 enlargement", "1 mm of tissue")),
        ("0.001", ("got 0.001", "metres", "1 mm")),
        ("12", ("got 12", "tissue mm")),
    ],
)
def test_depth_outside_the_plausible_range_names_a_likely_unit(raw, depth, words):
    path = raw / "profiles" / "MK.csv"
    line = find_line(path, lambda t: t.startswith("2,"), nth=3)
    set_cell(path, line, "depth_mm", depth)
    profile = read_table(path, SCHEMAS["profiles"])
    message = error(check_depth_range, profile, "p.csv", 0.05, 10.0, 20.0)
    assert message.startswith(f"p.csv, line {line}, column 'depth_mm': expected a depth")
    for word in words:
        assert word in message, (word, message)


def test_a_narrower_range_of_the_lab_suggests_no_unit(raw):
    profile = read_table(raw / "profiles" / "MK.csv", SCHEMAS["profiles"])
    message = error(check_depth_range, profile, "p.csv", 0.05, 1.5, 20.0)
    assert "got 2" in message and "between 0.05 and 1.5 mm" in message
    assert "enlargement" not in message and "micrometres" not in message


@pytest.mark.parametrize(
    ("magnification", "scale", "words"),
    [
        (20.0, 1 / 20, ("should be 1, not 20",)),  # readings in tissue mm already
        (1.0, 1.0, ("magnification in subjects.csv (1;", "about 20 would match")),  # enlarged
        (20.0, -1.0, ("upward positive",)),  # sign
        (20.0, 1000.0, ("micrometres",)),
    ],
)
def test_deflection_far_from_the_depth_names_a_likely_cause(raw, magnification, scale, words):
    path = raw / "profiles" / "HU.csv"
    profile = read_table(path, SCHEMAS["profiles"])
    profile["deflection_image_mm"] *= scale
    message = error(check_deflection_near_wedge, profile, "p.csv", magnification, 3.0)
    assert message.startswith("p.csv, line 2, column 'deflection_image_mm': at depth 1 mm")
    for word in words:
        assert word in message, (word, message)


def test_deflection_within_the_factor_passes_and_the_factor_is_the_limit(raw):
    profile = read_table(raw / "profiles" / "HU.csv", SCHEMAS["profiles"])
    check_deflection_near_wedge(profile, "p.csv", 20.0, 3.0)
    check_deflection_near_wedge(profile, "p.csv", 20.0 * 2.9, 3.0)  # 1/2.9 of the depth
    error(check_deflection_near_wedge, profile, "p.csv", 20.0 * 3.1, 3.0)


def test_without_limits_the_check_uses_the_config_schemas_defaults(tmp_path):
    # the one source of the limits is the config schema: a distance just beyond its
    # reach_max_mm is refused, one just inside passes (a restated default would drift)
    reach_mm = load_schema("config")["properties"]["input_checks"]["properties"]["reach_max_mm"]
    for factor, refused in ((1.001, True), (0.999, False)):
        raw = write_small_dataset(tmp_path / f"raw{factor}")
        path = raw / "profiles" / "HU.csv"
        last = len(read_lines(path))  # a far reading at the edge of the right side
        set_cell(path, last, "distance_image_mm", f"{factor * reach_mm['default'] * 20:.6f}")
        if refused:
            assert "reach_max_mm" in error(check_dataset, str(raw), SCHEMAS)
        else:
            check_dataset(str(raw), SCHEMAS)


def test_a_check_that_raises_is_folded_into_the_pass():
    """New checks may collect (problems=...) or raise; check_dataset gets both."""
    found = Problems()
    with found.collect():
        raise InputError(["a.csv, line 3: first", "a.csv, line 9: second"], ["w"])
    found.error("b.csv", 2, "x", "third")
    assert found.errors == [
        "a.csv, line 3: first",
        "a.csv, line 9: second",
        "b.csv, line 2, column 'x': third",
    ]
    assert found.warnings == ["w"]
    with pytest.raises(InputError) as caught:
        found.raise_if_any()
    assert caught.value.problems == found.errors
    with collecting() as own:
        pass  # nothing found: nothing raised
    assert own.errors == []


def test_folders_apart_are_accepted_and_nested_ones_refused(tmp_path):
    from lineload.runtime.startup import folder_problem

    raw = tmp_path / "raw"
    # side by side, one named like the other's start, or relative: accepted
    for results in (tmp_path / "results", tmp_path / "raw2", tmp_path / "raw-results"):
        assert folder_problem(str(raw), str(results)) is None, results
    assert folder_problem("data/raw", "results") is None
    # the same folder, one inside the other (also through '..'), or the root: refused
    assert "is the raw-data folder" in folder_problem(str(raw), str(tmp_path / "x" / ".." / "raw"))
    assert "inside the raw-data folder" in folder_problem(str(raw), str(raw / "out"))
    assert "key 'raw_data'" in folder_problem(str(raw / "a"), str(raw))
    assert "root of the file system" in folder_problem(str(raw), "/")
    assert "home folder" in folder_problem(str(raw), str(Path.home()))
    # a results folder that cannot be made: under a file, or where nothing may be written
    (tmp_path / "a-file").write_text("x")
    said = folder_problem(str(raw), str(tmp_path / "a-file" / "results"))
    assert "cannot be made" in said and "is a file" in said


def test_a_results_folder_on_a_read_only_disk_is_refused_before_anything_runs(
    tmp_path, monkeypatch
):
    # root may write anywhere and CI runs as root, so the operating system's answer for a
    # read-only disk is played by os.access; the folder asked about is the nearest that exists
    from lineload.runtime import startup

    asked = []

    def read_only(path, mode):
        asked.append(Path(path))
        return False

    monkeypatch.setattr(startup.os, "access", read_only)
    said = startup.folder_problem(str(tmp_path / "raw"), str(tmp_path / "new" / "results"))
    assert asked == [tmp_path]
    assert said == (
        f"config, key 'results': {str(tmp_path / 'new' / 'results')!r} cannot be made, "
        f"{str(tmp_path)!r} cannot be written (read-only or no permission); expected a "
        "folder you can write to (--config results=...)"
    )


def test_a_huge_cell_is_echoed_cut_to_a_readable_length(tmp_path):
    raw = write_small_dataset(tmp_path / "raw")
    path = raw / "profiles" / "MK.csv"
    n = find_line(path, lambda t: t.startswith("2,left,"), nth=2)
    set_cell(path, n, "deflection_image_mm", "9" * 500 + "x" * 1_000_000)
    with pytest.raises(InputError) as caught:
        check_dataset(str(raw), {t: load_schema(t) for t in ("subjects", "profiles", "outlines")})
    (message,) = [line for line in report_lines(caught.value) if line.startswith("Error: ")]
    assert f"line {n}" in message and "(1000500 characters)" in message
    assert len(message) < 400, len(message)
