"""The registry of model families: complete, consistent with the tables, and strict."""

import dataclasses

import numpy as np
import pytest

from lineload import models
from lineload.fitting import batch, families
from lineload.fitting.families import DEPTH, FAMILIES, Family, Parameter, checked, curve_mm

DISTANCE_MM = np.round(np.r_[np.arange(0.05, 0.5001, 0.05), np.arange(0.75, 3.0001, 0.25)], 6)
DEPTH_MM = 1.0
#: True parameters of each family's noise-free profile (a membrane wider than the window).
TRUE = {
    "waterbed": {"L_mm": 11.0},
    "waterbed_free_depth": {"L_mm": 11.0, "W0_mm": 0.8},
    "shifted": {"L_mm": 11.0},
    "arc": {"L_mm": 11.0},
    "boussinesq": {"A_mm": 0.3, "x0_mm": 4.0},
    "bending": {"L_mm": 11.0, "bending_length_mm": 0.2},
}


def test_every_family_of_the_outputs_is_registered_once():
    # the names the tables use, the engine's models and the fit table's groups all come
    # from the registry (or agree with it)
    solved = families.solved_families()
    assert set(solved) == set(models.MODEL_NAMES) == set(batch.MODELS)
    assert families.table_families() == models.TABLE_MODELS == batch.TABLE_MODELS
    assert set(TRUE) == set(FAMILIES)
    for name in families.table_families():
        entry = FAMILIES[name]
        columns = [entry.column(c) for c in entry.table_columns]
        assert set(columns) <= set(batch.FIT_COLUMNS)
        # each fitted parameter has its column, and the table has its colour to draw it
        assert all(entry.column(p.name) in columns for p in entry.parameters)
        assert entry.colour and entry.linestyle
    for name, entry in FAMILIES.items():
        assert entry.name == name
        assert all(p.unit == "mm" and p.name.endswith("_mm") for p in entry.parameters)


def test_the_bending_family_reads_the_bending_tables_columns():
    from lineload.fitting.bending import BENDING_COLUMNS

    entry = FAMILIES["bending"]
    assert [entry.column(p.name) for p in entry.parameters] == [
        "bending_L_mm",
        "bending_length_mm",
    ]
    assert set(entry.column(p.name) for p in entry.parameters) <= set(BENDING_COLUMNS)


@pytest.mark.parametrize("name", families.solved_families())
def test_each_solved_family_recovers_its_own_curve(name):
    # a noise-free profile of the registry's curve, fitted through the engine by name,
    # comes back through the registry's curve: arguments in the curve's order or not
    entry = FAMILIES[name]
    true = TRUE[name]
    args = [DEPTH_MM if a == DEPTH else true[a] for a in entry.arguments]
    profile_mm = entry.curve(DISTANCE_MM, *args)
    fit = batch.fit_batch([DISTANCE_MM], [profile_mm], [DEPTH_MM], models=(name,))[name]
    result = fit.result(0)
    for parameter, value in true.items():
        # exact (closed forms) or to the bounded search's tolerance (rtol 1e-9)
        assert result.params[parameter] == pytest.approx(value, rel=1e-6)
    row = {entry.column(p): v for p, v in result.params.items()}
    drawn = curve_mm(name, DISTANCE_MM, DEPTH_MM, row)
    assert np.max(np.abs(drawn - profile_mm)) < 1e-6 * DEPTH_MM


def test_the_bending_family_draws_what_its_fit_found():
    entry = FAMILIES["bending"]
    true = TRUE["bending"]
    profile_mm = entry.curve(DISTANCE_MM, DEPTH_MM, true["L_mm"], true["bending_length_mm"])
    fit = entry.fit(DISTANCE_MM, profile_mm, DEPTH_MM)
    row = {entry.column(p): v for p, v in fit.params.items()} | {"wall": "clamped"}
    drawn = curve_mm("bending", DISTANCE_MM, DEPTH_MM, row)
    assert np.max(np.abs(drawn - profile_mm)) < 1e-5 * DEPTH_MM
    # the wall is read from the row: a pinned wall draws another curve
    pinned = curve_mm("bending", DISTANCE_MM, DEPTH_MM, row | {"wall": "pinned"})
    assert np.max(np.abs(pinned - drawn)) > 1e-4


def test_curve_mm_draws_nothing_without_a_finite_fit():
    row = {"waterbed_L_mm": np.nan, "boussinesq_A_mm": 0.3}
    assert curve_mm("waterbed", DISTANCE_MM, DEPTH_MM, row) is None
    assert curve_mm("boussinesq", DISTANCE_MM, DEPTH_MM, row) is None  # x0 missing
    assert curve_mm("arc", DISTANCE_MM, DEPTH_MM, None) is None
    with pytest.raises(KeyError, match="no model family 'parabola'"):
        curve_mm("parabola", DISTANCE_MM, DEPTH_MM, row)


def _entry(**changes):
    base = Family(
        name="plate",
        curve=models.waterbed_deflection_mm,
        arguments=(DEPTH, "L_mm"),
        parameters=(Parameter("L_mm", "mm", "half-width"),),
        solver=FAMILIES["waterbed"].solver,
        results=("L_mm",),
    )
    return dataclasses.replace(base, **changes)


def test_a_complete_entry_is_accepted():
    assert checked(_entry()).name == "plate"


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        ({"curve": None}, "its curve must be a function"),
        ({"curve": "lineload.models.waterbed_deflection_mm"}, "its curve must be a function"),
        ({"parameters": ()}, "names no fitted parameter"),
        ({"arguments": (DEPTH, "L")}, "are not its parameters"),
        ({"arguments": (DEPTH,)}, "are not arguments of its curve"),
        ({"curve": models.waterbed_strain}, "must take distance_mm"),
        ({"solver": None, "table_columns": ("L_mm",)}, "needs a solver"),
        ({"solver": None}, "needs a solver or a fit function"),
    ],
)
def test_an_incomplete_entry_is_refused(changes, message):
    with pytest.raises(ValueError, match=message):
        checked(_entry(**changes))


def test_the_fit_jobs_read_a_batch_in_sheet_order(tmp_path):
    from lineload.fitting.inputs import labelled_rows, read_batch

    averaged = tmp_path / "averaged.csv"
    averaged.write_text(
        "subject,depth_mm,distance_mm,deflection_mm,n_sides\n"
        "H1,1.0,0.1,0.9,2\nH1,1.0,0.2,0.8,1\n"
        "M1,1.5,0.1,1.4,2\nM1,0.5,0.1,0.4,2\nM1,0.5,0.2,0.3,2\n"
        "X9,0.5,0.1,0.4,2\n"
    )
    subjects = {"M1": {"species": "monkey"}, "H1": {"species": "human"}, "M2": {"species": "x"}}
    batch = read_batch(averaged, subjects)
    # the sheet's order, each subject's depths increasing; a subject outside the batch
    # (X9) and one without profiles (M2) have no trial
    assert list(zip(batch.subject, batch.depth_mm, strict=True)) == [
        ("M1", 0.5),
        ("M1", 1.5),
        ("H1", 1.0),
    ]
    assert batch.species == ["monkey", "monkey", "human"]
    assert batch.distance_mm[0].tolist() == [0.1, 0.2]
    assert batch.deflection_mm[2].tolist() == [0.9, 0.8]
    assert batch.n_sides[2].tolist() == [2.0, 1.0]
    assert batch.noise is None and read_batch(averaged, subjects, sides=False).n_sides is None
    rows = labelled_rows(batch, [{"n": k} for k in range(3)])
    assert rows[2] == {"subject": "H1", "species": "human", "n": 2}
    assert list(rows[0]) == ["subject", "species", "n"]
    with pytest.raises(ValueError):
        labelled_rows(batch, [{}])
