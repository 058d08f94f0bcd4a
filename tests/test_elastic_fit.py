"""The elastic finger's solution library and the fits by interpolation in it.

The library (data/elastic/library.csv) is checked against the solver that made it; the fits
against profiles of known ratio: made from the library with noise (recovery, coverage), and
solved directly off the library's grid (interpolation error).
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

from lineload.elastic import materials, solver
from lineload.elastic import mesh as meshing
from lineload.elastic.library import (
    LibraryGrid,
    grid_distances_mm,
    library_columns,
    library_rows,
    library_sections,
)
from lineload.elastic.wedge import Wedge
from lineload.fitting.elastic import (
    ELASTIC_COLUMNS,
    RATIO_REFINEMENT,
    find_block,
    fit_elastic,
    fit_elastic_trials,
    library_blocks,
)
from lineload.rawdata.readings import reading_distances_mm

REPO = Path(__file__).resolve().parents[1]
LIBRARY = REPO / "data" / "elastic" / "library.csv"
SCHEMA = REPO / "workflow" / "schemas" / "config.schema.yaml"
#: The mesh-convergence criterion of tests/test_elastic.py (grade 0.3 to 0.15 moves the
#: profile by at most 1.2 um, grade 0.4 to 0.3 by at most 2.7 um): a library or an
#: interpolation that adds less than this adds less than the mesh already does.
CONVERGED_MM = 0.005
#: Regenerating the library on this machine gives the same numbers to the CSV's rounding
#: (1 nm); another machine's linear algebra may move the last digits. A fifth of the
#: convergence criterion: a difference this large means other code or another mesh.
REGENERATES_MM = CONVERGED_MM / 5
#: Digitising noise on the averaged points (mm), as the small raw datasets carry.
NOISE_SD_MM = 0.005
#: The shipped reading grid inside the default 3 mm window.
WINDOW_MM = 3.0
DISTANCE_MM = reading_distances_mm(WINDOW_MM)
DISTANCE_MM = DISTANCE_MM[(DISTANCE_MM > 0) & (DISTANCE_MM <= WINDOW_MM)]


def _defaults(node):
    if node.get("type") == "object":
        return {k: _defaults(v) for k, v in node.get("properties", {}).items()}
    return node.get("default")


@cache
def config_grid():
    """The library's grid at the configuration's defaults (the committed library's)."""
    schema = yaml.safe_load(SCHEMA.read_text())
    return LibraryGrid.from_config(_defaults(schema["properties"]["elastic"]))


@cache
def library_table():
    return pd.read_csv(LIBRARY)


@cache
def blocks():
    return library_blocks(library_table())


# --- The library -----------------------------------------------------------------------------


def test_the_library_holds_the_configured_grid():
    grid, table = config_grid(), library_table()
    assert list(table.columns) == library_columns(grid.distances_mm())
    np.testing.assert_allclose(grid_distances_mm(table.columns), grid.distances_mm())
    per_species = grid.sections * grid.thicknesses * grid.ratios * len(grid.depths_mm)
    assert table.groupby("species").size().to_dict() == {
        "human": per_species,
        "monkey": per_species,
    }
    np.testing.assert_allclose(np.unique(table["modulus_ratio"]), grid.modulus_ratios(), rtol=1e-6)


@pytest.mark.parametrize("species", ["monkey", "human"])
def test_a_slice_of_the_library_regenerates(species):
    grid, table = config_grid(), library_table()
    ratios = grid.modulus_ratios()[[0, 4]]
    thickness_mm = grid.layer_thicknesses_mm(species)[:1]
    fresh = pd.DataFrame(library_rows(species, grid, [0, 5], thickness_mm, ratios))
    kept = table[table["species"] == species].merge(
        fresh[["section", "layer_thickness_mm", "modulus_ratio", "depth_mm"]],
        on=["section", "layer_thickness_mm", "modulus_ratio", "depth_mm"],
    )
    assert len(kept) == len(fresh) == 2 * 2 * len(grid.depths_mm)
    kept = kept.sort_values(["section", "modulus_ratio", "depth_mm"]).reset_index(drop=True)
    fresh = fresh.sort_values(["section", "modulus_ratio", "depth_mm"]).reset_index(drop=True)
    sizes = ["length_mm", "height_mm", "bone_length_mm", "bone_height_mm", "pad_thickness_mm"]
    np.testing.assert_allclose(kept[sizes], fresh[sizes], atol=1e-4)
    deflection = [c for c in table.columns if c.startswith("deflection_at_")]
    difference_mm = np.abs(kept[deflection].to_numpy() - fresh[deflection].to_numpy())
    assert difference_mm.max() < REGENERATES_MM
    force = "force_per_length_per_pulp_modulus_mm"
    np.testing.assert_allclose(kept[force], fresh[force], rtol=1e-4)
    # the check sees a library of another ratio: the neighbouring rows differ by far more
    other = kept.loc[kept["modulus_ratio"] != kept["modulus_ratio"].iloc[0], deflection]
    first = fresh.loc[fresh["modulus_ratio"] == fresh["modulus_ratio"].iloc[0], deflection]
    assert np.abs(other.to_numpy() - first.to_numpy()).max() > 10 * REGENERATES_MM


def test_homogeneous_rows_agree_across_the_layers_meshes():
    # ratio 1 is one solid whatever the layer's thickness: the three meshes (grid lines at
    # each thickness) differ only by discretisation. Measured: within the 5 um criterion in
    # 60 of the 64 sections and depths; up to 11 um at 1.5-2 mm depth, 0.7-1 mm from the
    # wedge, where the contact's edge falls between nodes. The criterion here is three
    # standard deviations of the digitising noise on a point, so that no mesh effect can
    # pass for signal at one point
    table = library_table()
    homogeneous = table[np.isclose(table["modulus_ratio"], 1.0)]
    deflection = [c for c in table.columns if c.startswith("deflection_at_")]
    spread_mm = homogeneous.groupby(["species", "section", "depth_mm"])[deflection].agg(
        lambda column: column.max() - column.min()
    )
    assert spread_mm.to_numpy().max() < 3 * NOISE_SD_MM
    assert np.median(spread_mm.to_numpy().max(axis=1)) < CONVERGED_MM
    assert spread_mm.to_numpy().max() > 0  # three meshes, not one profile copied


def test_an_incomplete_library_is_refused():
    table = library_table()
    with pytest.raises(ValueError, match="not a full grid"):
        library_blocks(table.iloc[1:])


# --- Interpolation ---------------------------------------------------------------------------


@pytest.mark.parametrize("species", ["monkey", "human"])
@pytest.mark.parametrize("node", [0, 3])
def test_interpolation_matches_a_direct_solve_between_the_library_ratios(species, node):
    # a ratio halfway (in ln) between two of the library's, the section and thickness of the
    # library, read at the reading grid's distances (not the library's): the spline in ln
    # ratio and the lines in ln x together miss the solver by less than the mesh's criterion
    # (measured: at most 2.3 um between ratios 1 and 1.45, 0.8 um further up)
    grid = config_grid()
    block = find_block(blocks(), species, 1.0)
    k = node * RATIO_REFINEMENT + RATIO_REFINEMENT // 2
    section_index, thickness_index = 5, 1
    section = library_sections(species, grid)[section_index]
    thickness_mm = float(block.thicknesses_mm[thickness_index])
    mesh = meshing.finger_mesh(
        section, thickness_mm, solver.FINEST_PER_TIP_RADIUS * Wedge().tip_radius_mm, grid.grade
    )
    material = materials.TwoLayer(1.0, float(block.ratios[k]), thickness_mm)
    direct = solver.solve_contact(mesh, section, material, Wedge(), 1.0)
    curves = block.curves_at(DISTANCE_MM)[list(block.sections).index(section_index)]
    error_mm = np.abs(curves[thickness_index, k] - direct.deflection_at_mm(DISTANCE_MM))
    assert error_mm.max() < CONVERGED_MM
    # the check can fail: the library's own neighbouring ratio is much further off
    node_mm = np.abs(curves[thickness_index, k - 8] - direct.deflection_at_mm(DISTANCE_MM))
    assert node_mm.max() > 2 * CONVERGED_MM


# --- Fits ------------------------------------------------------------------------------------


def _noisy_fits(species, depth_mm, section, thickness, k, replicates, seed, covariance=None):
    block = find_block(blocks(), species, depth_mm)
    truth = block.curves_at(DISTANCE_MM)[section, thickness, k]
    rng = np.random.default_rng(seed)
    fits = [
        fit_elastic(DISTANCE_MM, truth + rng.normal(0, NOISE_SD_MM, truth.size), block, covariance)
        for _ in range(replicates)
    ]
    return block.ratios[k], pd.DataFrame(fits)


#: The noise's own covariance: independent points of the stated SD.
KNOWN_MM2 = NOISE_SD_MM**2 * np.eye(DISTANCE_MM.size)


def _covers(fits, ratio):
    return (fits["layered_ratio_ci_low"] <= ratio) & (ratio <= fits["layered_ratio_ci_high"])


@pytest.mark.parametrize("covariance", [None, KNOWN_MM2], ids=["unknown", "known"])
@pytest.mark.parametrize(("species", "depth_mm", "node"), [("human", 1.0, 4), ("monkey", 1.5, 2)])
def test_layered_ratio_is_recovered_with_an_interval_that_covers(
    species, depth_mm, node, covariance
):
    # library-made profiles (a section and thickness of the library, a ratio between two of
    # its nodes) with noise: the estimate centres on the truth and the 95 % interval (noise
    # of unknown size, or its covariance given) covers it at about its rate (200
    # replicates: a coverage of 0.95 has a Monte-Carlo error of 0.015, so 0.90 is more than
    # three of those below)
    k = node * RATIO_REFINEMENT + RATIO_REFINEMENT // 2
    ratio, fits = _noisy_fits(species, depth_mm, 3, 1, k, 200, seed=36, covariance=covariance)
    assert np.median(fits["layered_modulus_ratio"]) == pytest.approx(ratio, rel=0.05)
    assert _covers(fits, ratio).mean() >= 0.90
    # the complement: a ratio half as large again is hardly ever inside
    assert _covers(fits, 1.5 * ratio).mean() <= 0.10
    # the layered finger describes them better than the homogeneous one, beyond AICc's cost
    assert (fits["layered_aicc"] < fits["homogeneous_aicc"]).mean() >= 0.95


def test_the_interval_grows_with_the_covariance_as_the_sandwich_says():
    # a covariance four times larger doubles the interval's width in ln(ratio) (the rise
    # allowed is proportional to it; the sum of squares is quadratic near its minimum), and
    # an understated one shrinks it and loses coverage: how the interval moves when the
    # noise model is wrong. (At a quarter of the covariance the width, 0.018 in ln ratio,
    # is below the fine grid's 0.023 steps: not compared, only its coverage)
    k = 4 * RATIO_REFINEMENT + RATIO_REFINEMENT // 2
    ratio, known = _noisy_fits("human", 1.0, 3, 1, k, 100, seed=11, covariance=KNOWN_MM2)
    _, doubled = _noisy_fits("human", 1.0, 3, 1, k, 100, seed=11, covariance=4 * KNOWN_MM2)
    _, halved = _noisy_fits("human", 1.0, 3, 1, k, 100, seed=11, covariance=KNOWN_MM2 / 4)

    def width(fits):
        return np.log(fits["layered_ratio_ci_high"] / fits["layered_ratio_ci_low"])

    assert np.median(width(doubled) / width(known)) == pytest.approx(2.0, rel=0.1)
    assert np.median(width(halved)) < np.median(width(known))
    # about half the width: a normal estimate inside +-0.98 of its SD, 67 % of the time;
    # the ends found on the ratio's fine grid widen so narrow an interval (measured 76-81 %
    # at ratios 3-17), so the check is that it falls well below what the stated covariance
    # keeps, beyond the spread of 100 trials (a binomial SD of 0.03-0.04)
    assert _covers(halved, ratio).mean() <= 0.85 < 0.9 <= _covers(known, ratio).mean()


@pytest.mark.parametrize("species", ["monkey", "human"])
def test_a_homogeneous_profile_is_fitted_as_homogeneous(species):
    # ratio 1 with noise: the ratio's interval reaches down to 1 at about its rate, the
    # layer's two extra parameters do not pay for themselves in AICc, and the homogeneous
    # fit's residual is the noise
    ratio, fits = _noisy_fits(species, 1.0, 3, 1, 0, 200, seed=7)
    assert ratio == 1.0
    assert (fits["layered_ratio_ci_low"] == 1.0).mean() >= 0.90
    assert (fits["homogeneous_aicc"] < fits["layered_aicc"]).mean() >= 0.75
    assert np.median(fits["homogeneous_rmse_mm"]) == pytest.approx(NOISE_SD_MM, rel=0.2)
    # the complement: a layered profile (ratio 2.1) is not read as homogeneous
    _, layered = _noisy_fits(species, 1.0, 3, 1, 2 * RATIO_REFINEMENT, 200, seed=7)
    assert (layered["layered_ratio_ci_low"] == 1.0).mean() <= 0.05


def test_trials_without_a_library_block_or_points_get_a_note():
    x = DISTANCE_MM
    block = find_block(blocks(), "human", 1.0)
    y = block.curves_at(x)[0, 0, 0]
    rows = fit_elastic_trials(
        [x, x, x[:4], x], [y, y, y[:4], y], ["human", "human", "human", "cat"],
        [1.0, 1.25, 1.0, 1.0], WINDOW_MM, blocks(),
    )  # fmt: skip
    assert set(rows[0]) | {"subject", "species"} == set(ELASTIC_COLUMNS)
    assert rows[0]["elastic_note"] == ""
    assert rows[0]["elastic_layered_ratio_ci_low"] == 1.0
    assert "1.25 mm" in rows[1]["elastic_note"]
    assert "fewer than" in rows[2]["elastic_note"]
    assert "cat" in rows[3]["elastic_note"]
    assert np.isnan(rows[1]["elastic_layered_modulus_ratio"])
    far = fit_elastic_trials([x], [y], ["human"], [1.0], 10.0, blocks())[0]
    assert "past the library" in far["elastic_note"]


# --- Figures (drawn by functions not yet in the registry) ------------------------------------


def _library_made_dataset():
    """Two subjects (a monkey, a human) at 1 and 2 mm from library profiles with noise, their
    elastic fits, and the subject sheet."""
    from lineload.fitting.elastic import ELASTIC_COLUMNS

    rng = np.random.default_rng(5)
    points, x_all, y_all, species_all, depth_all, keys = [], [], [], [], [], []
    for subject, species, k in (("M1", "monkey", 40), ("H1", "human", 72)):
        for depth_mm in (1.0, 2.0):
            block = find_block(blocks(), species, depth_mm)
            y = block.curves_at(DISTANCE_MM)[3, 1, k] + rng.normal(0, NOISE_SD_MM, DISTANCE_MM.size)
            points += [
                {"subject": subject, "depth_mm": depth_mm, "distance_mm": xi, "deflection_mm": yi}
                for xi, yi in zip(DISTANCE_MM, y, strict=True)
            ]
            x_all.append(DISTANCE_MM)
            y_all.append(y)
            species_all.append(species)
            depth_all.append(depth_mm)
            keys.append((subject, species))
    rows = fit_elastic_trials(x_all, y_all, species_all, depth_all, WINDOW_MM, blocks())
    elastic = pd.DataFrame(
        [{"subject": s, "species": p, **row} for (s, p), row in zip(keys, rows, strict=True)]
    )[ELASTIC_COLUMNS]
    subjects = pd.DataFrame(
        {"subject": ["M1", "H1"], "species": ["monkey", "human"], "label": ["Monkey 1", "Human 1"]}
    )
    return pd.DataFrame(points), elastic, subjects


def test_the_examples_draw_each_fit_from_the_library_at_its_parameters():
    import matplotlib.pyplot as plt

    from lineload.figures.elastic import figure_elastic_examples

    averaged, elastic, subjects = _library_made_dataset()
    fig = figure_elastic_examples(averaged, elastic, library_table(), subjects, WINDOW_MM)
    try:
        axes = [ax for ax in fig.axes if any(line.get_gid() == "data" for line in ax.lines)]
        assert len(axes) == 2
        for ax, (subject, depth_mm) in zip(axes, [("M1", 1.0), ("H1", 1.0)], strict=True):
            row = elastic[(elastic["subject"] == subject) & (elastic["depth_mm"] == depth_mm)]
            data = next(line for line in ax.lines if line.get_gid() == "data")
            x, y = data.get_xdata(), data.get_ydata()
            for name in ("homogeneous", "layered"):
                curve = next(line for line in ax.lines if line.get_gid() == f"elastic:{name}")
                at_points = np.interp(np.log(x), np.log(curve.get_xdata()), curve.get_ydata())
                sse = float(np.sum((y - at_points) ** 2))
                # the drawn curve is the fitted one: its sum of squares is the table's (to the
                # 300-point curve's interpolation and the ratio's refinement)
                expected = float(row[f"elastic_{name}_sse_mm2"].iloc[0])
                assert sse == pytest.approx(expected, rel=0.05)
    finally:
        plt.close(fig)


def test_the_ratio_figure_marks_estimates_at_the_librarys_end_open():
    import matplotlib.pyplot as plt

    from lineload.figures.elastic import figure_elastic_ratios

    _, elastic, subjects = _library_made_dataset()
    elastic.loc[0, "elastic_layered_ratio_at_bound"] = 1.0
    fig = figure_elastic_ratios(elastic, subjects)
    try:
        gids = [line.get_gid() for ax in fig.axes for line in ax.lines if line.get_gid()]
        assert gids.count("ratio-bound:M1") == 1
        assert gids.count("ratio:M1") == 1 and gids.count("ratio:H1") == 2
    finally:
        plt.close(fig)
    empty = figure_elastic_ratios(elastic.iloc[0:0], subjects)
    plt.close(empty)


def test_a_broken_library_stops_the_job_with_one_message_naming_it(tmp_path):
    import runpy

    script = runpy.run_path(str(REPO / "workflow" / "scripts" / "fit_elastic.py"), run_name="x")
    broken = tmp_path / "library.csv"
    library_table().iloc[1:].to_csv(broken, index=False)
    output = tmp_path / "elastic_fits.csv"
    with pytest.raises(SystemExit, match=r"library\.csv: not the elastic finger's .*full grid"):
        script["fit_elastic"]([], str(broken), None, str(output), [], WINDOW_MM)
    assert not output.exists()
