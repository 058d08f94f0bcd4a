"""C12's geometry margin, and how often its rule is wrong on a small simulated set.

The elastic fits take the finger's section as a nuisance over the library's eight; a finger
whose section is none of them still leaves a misfit that the layered fit's two extra
parameters can take up, and would be read as a layer. This measures that leak and scores the
rule (:mod:`lineload.claims.elastic`) on simulated fingers.

1. **Margin** (``elastic_layer_margin.csv``): homogeneous fingers whose sections the library
   does not hold (drawn from the same stated ranges with seed :data:`MARGIN_SEED`, not the
   library's 36), solved by the finite-element solver at a coarse grade (:data:`GRADE`; the
   library's is 0.4) at the library's four depths, read noise-free at the reading grid's
   distances inside the default fit window and fitted from the committed library. ``g`` is
   the part of the misfit the layer removes, a fraction of the depth; the margin is the
   largest times :data:`SAFETY`, rounded up (config ``claims: elastic_margin``).
2. **Error rates** (``elastic_layer_errors.csv``): with independent noise of
   :data:`NOISE_SD_MM` on each averaged point, :data:`REPLICATES` draws per finger, each
   finger's four depths one species' dataset: the trial calls and the species verdicts
   (:func:`lineload.claims.elastic.species_verdict`) on homogeneous fingers (library
   sections; other sections drawn with :data:`SCORE_SEED`, solved as above) and layered ones
   (library-made at ratios between the library's nodes; the off-library sections at ratio
   2 and 5, the species' default layer thickness); the same fits judged again with the
   rule's noise stated at half and twice the noise added, and at half the margin.

Run: ``python docs/calibration/scripts/elastic_layer_margin.py`` (under a minute; writes the two
tables into docs/calibration/ and prints the margin).
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from lineload.claims.elastic import LAYERED, layer_call, species_verdict
from lineload.claims.verdicts import FAILS, HOLDS
from lineload.elastic import materials, solver
from lineload.elastic import mesh as meshing
from lineload.elastic.geometry import SPECIES
from lineload.elastic.library import LibraryGrid, library_sections
from lineload.elastic.wedge import Wedge
from lineload.fitting.elastic import RATIO_REFINEMENT, find_block, fit_elastic, library_blocks
from lineload.io import config_defaults
from lineload.rawdata.readings import reading_distances_mm

REPO = Path(__file__).resolve().parents[3]
OUT = REPO / "docs" / "calibration"
#: Seeds of the off-library sections (the library's is 36).
MARGIN_SEED, SCORE_SEED, NOISE_SEED = 3612, 3613, 12
#: Off-library sections per species for the margin and for the scoring.
MARGIN_SECTIONS, SCORE_SECTIONS = 6, 4
#: The solver's grade for the off-library fingers (coarser than the library's).
GRADE = 0.5
#: The margin is the largest gain measured times this, rounded up to half a percent of W0:
#: twelve sections per species do not find the worst one.
SAFETY = 1.25
#: Noise of one averaged point (mm), independent, and noise draws per finger.
NOISE_SD_MM, REPLICATES = 0.005, 25
#: The rule's noise taken as these multiples of the noise added (how the verdicts move
#: when the noise model is wrong).
STATED_SD_MULTIPLES = (0.5, 2.0)
#: Layered library-made fingers: nodes of the fine ratio grid halfway between library nodes.
LIBRARY_NODES = (1, 3, 5)
#: The off-library layered fingers' ratios.
OFF_LIBRARY_RATIOS = (2.0, 5.0)


def grid():
    return LibraryGrid.from_config(config_defaults("elastic"))


def window_distances_mm():
    schema = yaml.safe_load((REPO / "workflow" / "schemas" / "config.schema.yaml").read_text())
    window_mm = float(schema["properties"]["fit_window_mm"]["default"])
    x = reading_distances_mm(window_mm)
    return x[(x > 0) & (x <= window_mm)]


def off_library_sections(species, seed, count):
    """Sections drawn as the library's are, with another seed; the default (the library's
    first) left out."""
    return library_sections(species, replace(grid(), seed=seed, sections=count + 1))[1:]


def solved_profiles(species, section, ratio, x_mm):
    """A finger's profiles at the library's depths, read at ``x_mm``: {depth: deflection}."""
    wedge = Wedge()
    thickness_mm = SPECIES[species].outer_layer_thickness.value_mm
    mesh = meshing.finger_mesh(
        section, thickness_mm, solver.FINEST_PER_TIP_RADIUS * wedge.tip_radius_mm, GRADE
    )
    material = materials.TwoLayer(1.0, ratio, thickness_mm)
    depths = grid().depths_mm
    series = solver.solve_depths(mesh, section, material, wedge, depths)
    return {d: s.deflection_at_mm(x_mm) for d, s in zip(depths, series, strict=True)}


def margin_study(blocks, x_mm):
    rows = []
    for species in ("monkey", "human"):
        for number, section in enumerate(
            off_library_sections(species, MARGIN_SEED, MARGIN_SECTIONS)
        ):
            for depth_mm, y in solved_profiles(species, section, 1.0, x_mm).items():
                fit = fit_elastic(x_mm, y, find_block(blocks, species, depth_mm))
                improvement = fit["homogeneous_sse_mm2"] - fit["layered_sse_mm2"]
                rows.append(
                    {
                        "species": species,
                        "section": number,
                        "length_mm": round(section.length_mm, 3),
                        "height_mm": round(section.height_mm, 3),
                        "pad_thickness_mm": round(section.pad_thickness_mm, 3),
                        "depth_mm": depth_mm,
                        "homogeneous_rmse_mm": round(fit["homogeneous_rmse_mm"], 6),
                        "layered_rmse_mm": round(fit["layered_rmse_mm"], 6),
                        "layered_modulus_ratio": round(fit["layered_modulus_ratio"], 4),
                        "gain": round(math.sqrt(max(improvement, 0) / x_mm.size) / depth_mm, 6),
                    }
                )
    return pd.DataFrame(rows)


def fingers(blocks, x_mm):
    """Every scored finger: (species, kind, label, truly layered, {depth: noise-free profile})."""
    for species in ("monkey", "human"):
        for g in (2, 5):
            profiles = {
                d: find_block(blocks, species, d).curves_at(x_mm)[g, 1, 0] for d in grid().depths_mm
            }
            yield species, "homogeneous, library section", f"section {g}", False, profiles
            for node in LIBRARY_NODES:
                k = node * RATIO_REFINEMENT + RATIO_REFINEMENT // 2
                profiles = {
                    d: find_block(blocks, species, d).curves_at(x_mm)[g, 1, k]
                    for d in grid().depths_mm
                }
                ratio = find_block(blocks, species, 1.0).ratios[k]
                yield (
                    species,
                    "layered, library section",
                    f"section {g} ratio {ratio:.2f}",
                    True,
                    profiles,
                )
        for number, section in enumerate(off_library_sections(species, SCORE_SEED, SCORE_SECTIONS)):
            profiles = solved_profiles(species, section, 1.0, x_mm)
            yield species, "homogeneous, other section", f"section {number}", False, profiles
            for ratio in OFF_LIBRARY_RATIOS:
                profiles = solved_profiles(species, section, ratio, x_mm)
                label = f"section {number} ratio {ratio:g}"
                yield species, "layered, other section", label, True, profiles


def error_study(blocks, x_mm, margin, significance):
    """The calls and verdicts with the noise stated right and stated wrong (the rule's ``s``
    taken as :data:`STATED_SD_MULTIPLES` times the noise actually added), and at half the
    margin: the same fits judged each way."""
    rng = np.random.default_rng(NOISE_SEED)
    ways = {"": (1.0, margin)}
    ways.update({f"_sd_x{m:g}": (m, margin) for m in STATED_SD_MULTIPLES})
    ways["_half_margin"] = (1.0, margin / 2)
    rows = []
    for species, kind, label, layered, profiles in fingers(blocks, x_mm):
        calls = {way: [] for way in ways}
        verdicts = {way: [] for way in ways}
        for _ in range(REPLICATES):
            found = {way: [] for way in ways}
            for depth_mm, truth in profiles.items():
                y = truth + rng.normal(0, NOISE_SD_MM, truth.size)
                fit = fit_elastic(x_mm, y, find_block(blocks, species, depth_mm))
                for way, (multiple, way_margin) in ways.items():
                    call = layer_call(
                        fit["homogeneous_sse_mm2"],
                        fit["layered_sse_mm2"],
                        x_mm.size,
                        (multiple * NOISE_SD_MM) ** 2,
                        depth_mm,
                        way_margin,
                        significance,
                    )["call"]
                    found[way].append(call)
            for way in ways:
                calls[way] += found[way]
                verdicts[way].append(species_verdict(found[way]))
        row = {
            "species": species,
            "finger": kind,
            "label": label,
            "truly_layered": layered,
            "trials": len(calls[""]),
            "datasets": len(verdicts[""]),
        }
        for way in ways:
            row[f"trials_called_layered{way}"] = sum(c == LAYERED for c in calls[way])
            row[f"holds{way}"] = sum(v == HOLDS for v in verdicts[way])
            row[f"does_not_hold{way}"] = sum(v == FAILS for v in verdicts[way])
            row[f"cannot_be_checked{way}"] = sum(v not in (HOLDS, FAILS) for v in verdicts[way])
        rows.append(row)
    return pd.DataFrame(rows)


def main():
    blocks = library_blocks(pd.read_csv(REPO / config_defaults("elastic")["library_file"]))
    x_mm = window_distances_mm()
    margin_table = margin_study(blocks, x_mm)
    margin_table.to_csv(OUT / "elastic_layer_margin.csv", index=False)
    largest = float(margin_table["gain"].max())
    margin = math.ceil(SAFETY * largest * 200) / 200  # rounded up to half a percent of W0
    print(f"largest gain {largest:.4f} of W0 over {len(margin_table)} profiles: margin {margin}")
    significance = config_defaults("claims")["significance"]
    errors = error_study(blocks, x_mm, margin, significance)
    errors.to_csv(OUT / "elastic_layer_errors.csv", index=False)
    print(errors.to_string())


if __name__ == "__main__":
    main()
