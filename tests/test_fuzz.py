"""Fuzzing the raw-data check: seeded mutations of a raw folder, each refused in one line
(one per column it breaks) or accepted and then fitted to finite, plausible numbers.

The check (``lineload.rawdata.validation.check_dataset``) is what stands between a lab's files
and the fits, so it runs alone here, in process, on a few hundred mutated folders: the
kinds of mistake a spreadsheet, a script or a tired hand makes to a digitised profile
(magnitudes, types, encodings, missing and extra rows and columns, thin trials).  A
mutation the check accepts goes on through the workflow's own conversion, averaging and
fits, in memory, and every number those give must be finite and inside the check's own
limits; a mutation it refuses must be refused with one ``Error:`` line that names the file
(two when it swapped the values of two columns, each column then being wrong).
Anything else - a traceback, a second line about the same mistake, an infinite
L - fails the test with the mutation that caused it.
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from conftest import write_small_dataset
from lineload.averaging import average_subjects, tissue_columns
from lineload.fitting.batch import fit_trials
from lineload.io import load_schema
from lineload.rawdata.validation import InputError, check_dataset, read_columns, report_lines

#: Mutated folders per run; each is one seeded draw, so a failure names its number.
N_MUTATIONS = 300
SEED = 20
SCHEMAS = {name: load_schema(name) for name in ("subjects", "profiles", "outlines", "forces")}
TOP = load_schema("config")["properties"]
WINDOW = (TOP["fit_window_mm"]["default"], TOP["min_points_in_window"]["default"])
LIMITS = {k: v["default"] for k, v in TOP["input_checks"]["properties"].items()}

#: Cells people and programs write where a number belongs.
ODD_TEXT = (
    "", " ", "abc", "nan", "NaN", "inf", "-inf", "Infinity", "1_000", "0x1A", "1,5", "1.5.2",
    "\u0661\u0662", "1e", "--1", "+", "1e400", "-1e400", "TRUE", "null", "N/A", "\u00a01.5",
)  # fmt: skip


def _rows(path):
    return path.read_text(encoding="utf-8").splitlines()


def _write(path, lines, encoding="utf-8"):
    path.write_text("\n".join(lines) + "\n", encoding=encoding)


def _mutate(raw, rng):
    """Apply one random mutation to the folder; return a description of it and how many
    columns it breaks (one; two when two columns trade their values)."""
    files = [raw / "subjects.csv", raw / "profiles" / "MK.csv", raw / "profiles" / "HU.csv"]
    path = files[rng.integers(len(files))]
    lines = _rows(path)
    header = lines[0].split(",")
    line = int(rng.integers(1, len(lines)))  # a data line (0-based index)
    column = int(rng.integers(len(header)))
    cells = lines[line].split(",")
    kind = rng.choice(
        ["magnitude", "text", "encoding", "drop_row", "copy_row", "drop_column",
         "extra_column", "thin", "sign", "swap_columns"]
    )  # fmt: skip
    what = f"{path.relative_to(raw)}: {kind}"
    if kind == "magnitude":
        try:
            value = float(cells[column])
        except ValueError:
            value = 1.0
        exponent = int(rng.choice([-300, -12, -6, -3, 3, 6, 12, 300]))
        cells[column] = f"{value * 10.0**exponent:.6g}" if value else f"1e{exponent}"
        lines[line] = ",".join(cells)
        what += f" line {line + 1} {header[column]} x 1e{exponent}"
    elif kind == "text":
        cells[column] = str(rng.choice(ODD_TEXT))
        lines[line] = ",".join(cells)
        what += f" line {line + 1} {header[column]} = {cells[column]!r}"
    elif kind == "sign":
        cells[column] = "-" + cells[column].lstrip("-")
        lines[line] = ",".join(cells)
        what += f" line {line + 1} {header[column]} negated"
    elif kind == "encoding":
        encoding = str(rng.choice(["utf-16", "latin-1", "utf-8-sig"]))
        if encoding == "latin-1":
            lines[line] = lines[line].replace(",", ",\u00e9", 1)
        _write(path, lines, encoding)
        return what + f" as {encoding}", 1
    elif kind == "drop_row":
        del lines[line]
        what += f" line {line + 1}"
    elif kind == "copy_row":
        lines.insert(line, lines[line])
        what += f" line {line + 1}"
    elif kind == "drop_column":
        lines = [",".join(c for k, c in enumerate(t.split(",")) if k != column) for t in lines]
        what += f" {header[column]}"
    elif kind == "extra_column":
        lines = [t + (",note" if i == 0 else ",x") for i, t in enumerate(lines)]
    elif kind == "swap_columns":
        other = (column + 1) % len(header)
        swapped = [lines[0]]  # the values swapped under the same header
        for t in lines[1:]:
            c = t.split(",")
            c[column], c[other] = c[other], c[column]
            swapped.append(",".join(c))
        lines = swapped
        what += f" {header[column]} <-> {header[other]}"
    elif kind == "thin" and path.parent.name == "profiles":
        keep = int(rng.integers(0, 6))
        depth = lines[line].split(",")[0]
        near = [
            i
            for i, t in enumerate(lines[1:], 1)
            if t.split(",")[0] == depth and float(t.split(",")[2]) / 20 <= WINDOW[0]
        ]
        drop = set(near[keep:])
        lines = [t for i, t in enumerate(lines) if i not in drop]
        what += f" depth {depth} keeps {keep} readings in the window"
    _write(path, lines)
    return what, 2 if kind == "swap_columns" else 1


def _fitted_numbers(raw, dataset):
    """The accepted folder through conversion, averaging and fits, as the workflow does."""
    sheet = dataset["subjects"]
    converted = []
    for subject, magnification in zip(sheet["subject"], sheet["magnification"], strict=True):
        profile = read_columns(raw / "profiles" / f"{subject}.csv", SCHEMAS["profiles"])
        converted.append(tissue_columns(profile[0], subject, float(magnification)))
    averaged = average_subjects(converted)
    trials = {}
    for i, (subject, depth) in enumerate(
        zip(averaged["subject"], averaged["depth_mm"], strict=True)
    ):
        trials.setdefault((subject, float(depth)), []).append(i)
    rows = [np.array(r) for r in trials.values()]
    fitted = fit_trials(
        [averaged["distance_mm"][r] for r in rows],
        [averaged["deflection_mm"][r] for r in rows],
        [depth for _, depth in trials],
        WINDOW[0],
    )
    return averaged, fitted


def fuzz(clean_folder, work, check=check_dataset, n=N_MUTATIONS):
    """Run ``n`` seeded mutations through ``check`` (and the fits when it accepts).

    Returns ``(refused, accepted, problems)``: the counts and one line per mutation
    that was not refused in a line per broken column nor fitted to finite numbers.
    """
    rng = np.random.default_rng(SEED)
    refused, accepted, problems = 0, 0, []
    for k in range(n):
        raw = work / f"raw{k}"
        shutil.copytree(clean_folder, raw)
        mutation, broken = _mutate(raw, rng)
        what = f"mutation {k} ({mutation})"
        try:
            dataset = check(str(raw), SCHEMAS, plausibility=LIMITS, window=WINDOW)
        except InputError as error:
            errors = [line for line in report_lines(error) if line.startswith("Error: ")]
            refused += 1
            one_line = all("\n" not in e and e.startswith(f"Error: {raw}") for e in errors)
            if not 1 <= len(errors) <= broken or not one_line:
                problems.append(f"{what}: {errors}")
            continue
        except Exception as error:  # a traceback where a sentence belongs
            problems.append(f"{what}: {type(error).__name__}: {error}")
            continue
        accepted += 1
        try:
            averaged, fitted = _fitted_numbers(raw, dataset)
        except Exception as error:  # accepted, then broke the fits
            problems.append(f"{what}: accepted, then {type(error).__name__}: {error}")
            continue
        for name in ("distance_mm", "deflection_mm"):
            values = np.asarray(averaged[name], dtype=float)
            if not np.all(np.isfinite(values)) or np.abs(values).max() > LIMITS["reach_max_mm"]:
                problems.append(f"{what}: averaged {name} out of range")
        for row in fitted:
            for key in ("waterbed_L_mm", "arc_L_mm", "waterbed_rmse_mm", "boussinesq_A_mm"):
                if not math.isfinite(row[key]) or abs(row[key]) > 10 * LIMITS["reach_max_mm"]:
                    problems.append(f"{what}: {key} = {row[key]}")
    return refused, accepted, problems


@pytest.fixture(scope="module")
def clean_folder(tmp_path_factory):
    return write_small_dataset(tmp_path_factory.mktemp("fuzz") / "raw")


def test_every_mutation_is_refused_in_a_line_per_column_or_fitted_to_finite_numbers(
    clean_folder, tmp_path
):
    refused, accepted, problems = fuzz(clean_folder, tmp_path)
    assert not problems, "\n".join(problems)
    # both outcomes occur: the generator makes folders the check must refuse and ones it
    # must accept (a check that refused everything, or nothing, would fail here)
    assert refused > N_MUTATIONS // 4 and accepted > N_MUTATIONS // 10, (refused, accepted)


def test_the_fuzz_test_catches_a_check_that_lets_everything_through(clean_folder, tmp_path):
    import pandas as pd

    def no_check(raw, schemas, **_):
        return {"subjects": pd.read_csv(Path(raw) / "subjects.csv", dtype=str)}

    # without the check, mutated folders reach the fits: tracebacks and absurd numbers
    _, accepted, problems = fuzz(clean_folder, tmp_path, check=no_check, n=40)
    assert accepted >= 30
    assert len(problems) >= 10, problems
