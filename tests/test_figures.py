"""The figures: panels and series follow the data, schematics follow the model, files are
reproducible.  Figure functions are called directly on data built here; one workflow run
on a small dataset checks the rules, the file formats and byte-for-byte rebuilds."""

import contextlib
import functools
import importlib
import inspect
import re
import struct
from io import BytesIO
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg

from conftest import REPO, imported_after, run_snakemake
from lineload import models
from lineload.averaging import OUTLINE_COLUMNS, outline_to_tissue_mm
from lineload.figures import data, registry, schematics, style, supplements
from lineload.io import load_schema
from lineload.noise import NoiseModel
from lineload.rawdata.validation import read_table

NOTICE = "Made-up numbers for a test of the footer; they describe no finger at all, anywhere."
WINDOW_MM = 3.0


def noise_table(reading_sd_mm=0.008, tracing_sd_mm=0.006):
    """A noise table as the ``noise`` rule writes it; one reading's noise is the
    two together, sqrt(0.008**2 + 0.006**2) = 0.01 mm by default."""
    model = NoiseModel(reading_sd_mm, tracing_sd_mm)
    return pd.DataFrame({"parameter": list(model.as_dict()), "value": model.as_dict().values()})


def make_dataset(spec):
    """Averaged profiles, a fit table and a subject sheet from ``{id: (species, depths)}``.

    Profiles are ``depth (1 - x/e)**2`` with an extent e of 5 mm (monkeys) or 9 mm
    (humans); the fit table holds arbitrary but valid parameters for every model.
    """
    averaged, fits, sheet = [], [], []
    for subject, (species, depths_mm) in spec.items():
        sheet.append({"subject": subject, "species": species, "label": f"Finger {subject}"})
        extent_mm = 5.0 if species == "monkey" else 9.0
        for depth_mm in depths_mm:
            distance_mm = np.arange(0.05, extent_mm + 1e-9, 0.25)
            deflection_mm = depth_mm * (1 - distance_mm / extent_mm) ** 2
            averaged.append(
                pd.DataFrame(
                    {
                        "subject": subject,
                        "depth_mm": depth_mm,
                        "distance_mm": distance_mm,
                        "deflection_mm": deflection_mm,
                    }
                )
            )
            fits.append(
                {
                    "subject": subject,
                    "species": species,
                    "depth_mm": depth_mm,
                    "waterbed_L_mm": 2.5 * extent_mm,
                    "shifted_L_mm": 2.55 * extent_mm,
                    "arc_L_mm": 2.6 * extent_mm,
                    "boussinesq_A_mm": 0.3 * depth_mm,
                    "boussinesq_x0_mm": extent_mm,
                }
            )
    return pd.concat(averaged, ignore_index=True), pd.DataFrame(fits), pd.DataFrame(sheet)


PAPER_LIKE = {
    "M1": ("monkey", [0.5, 1.0, 1.5, 2.0]),
    "M2": ("monkey", [0.5, 1.0, 1.5, 2.0]),
    "M3": ("monkey", [0.5, 1.0, 1.5, 2.0]),
    "H1": ("human", [0.5, 1.0, 1.5, 2.0]),
    "H2": ("human", [0.5, 1.0, 1.5, 2.0]),
    "H3": ("human", [1.0, 2.0]),
}


def gids(ax, prefix):
    """gids of the lines of one panel that start with prefix."""
    return sorted(
        line.get_gid()
        for line in ax.get_lines()
        if line.get_gid() is not None and line.get_gid().startswith(prefix)
    )


def panels_by_title(fig):
    return {ax.get_title(loc="left"): ax for ax in fig.axes}


def depth_gids(kind, depths_mm):
    return sorted(f"{kind}:{d:g}" for d in depths_mm)


@pytest.mark.parametrize(
    ("figure_species", "ids"), [("monkey", ["M1", "M2", "M3"]), ("human", ["H1", "H2", "H3"])]
)
def test_species_figures_have_a_panel_per_subject_and_a_series_per_depth(figure_species, ids):
    averaged, fits, subjects = make_dataset(PAPER_LIKE)
    fig = data.figure_species_fits(averaged, fits, subjects, figure_species, WINDOW_MM)
    panels = panels_by_title(fig)
    assert len(fig.axes) == len(ids)
    assert set(panels) == {f"Finger {s} ({figure_species})" for s in ids}
    for subject in ids:
        ax = panels[f"Finger {subject} ({figure_species})"]
        depths_mm = PAPER_LIKE[subject][1]
        assert gids(ax, "data:") == depth_gids("data", depths_mm)
        assert gids(ax, "model:") == depth_gids("model", depths_mm)
    if figure_species == "human":  # the third human: 1 and 2 mm only
        assert gids(panels["Finger H3 (human)"], "data:") == ["data:1", "data:2"]


def test_species_figure_model_lines_are_the_fitted_waterbed():
    averaged, fits, subjects = make_dataset({"M9": ("monkey", [1.5])})
    fig = data.figure_species_fits(averaged, fits, subjects, "monkey", WINDOW_MM)
    (line,) = [ln for ln in fig.axes[0].get_lines() if ln.get_gid() == "model:1.5"]
    L_mm = float(fits["waterbed_L_mm"].iloc[0])
    np.testing.assert_allclose(
        line.get_ydata(), models.waterbed_deflection_mm(line.get_xdata(), 1.5, L_mm)
    )
    (points,) = [ln for ln in fig.axes[0].get_lines() if ln.get_gid() == "data:1.5"]
    np.testing.assert_allclose(points.get_xdata(), averaged["distance_mm"])
    # deflection downward: the axis is inverted, zero above the depth
    low, high = fig.axes[0].get_ylim()
    assert low > high


def test_panels_follow_a_different_dataset():
    spec = {"A": ("monkey", [0.75, 1.25, 3.0]), "B": ("human", [1.0]), "C": ("human", [0.5, 1.0])}
    averaged, fits, subjects = make_dataset(spec)
    monkeys = data.figure_species_fits(averaged, fits, subjects, "monkey", WINDOW_MM)
    assert len(monkeys.axes) == 1
    assert gids(monkeys.axes[0], "data:") == depth_gids("data", [0.75, 1.25, 3.0])
    assert gids(monkeys.axes[0], "model:") == depth_gids("model", [0.75, 1.25, 3.0])
    humans = data.figure_species_fits(averaged, fits, subjects, "human", WINDOW_MM)
    assert [ax.get_title(loc="left") for ax in humans.axes] == [
        "Finger B (human)",
        "Finger C (human)",
    ]
    assert gids(humans.axes[1], "model:") == ["model:0.5", "model:1"]
    # supplement: one row per species, one column per depth in the data
    residuals = supplements.figure_residuals(averaged, fits, subjects, WINDOW_MM)
    assert len(residuals.axes) == 2 * 5
    arcs = supplements.figure_arc_vs_parabola(fits)
    assert len(arcs.axes) == 2 * 5


def test_a_species_without_subjects_gives_one_axis_that_says_so():
    averaged, fits, subjects = make_dataset({"A": ("monkey", [1.0])})
    fig = data.figure_species_fits(averaged, fits, subjects, "human", WINDOW_MM)
    assert len(fig.axes) == 1
    messages = [t.get_text() for t in fig.axes[0].texts if t.get_gid() == "message"]
    assert messages and "human" in messages[0]


def test_residuals_are_data_minus_each_fitted_model_inside_the_window():
    averaged, fits, subjects = make_dataset({"A": ("monkey", [1.0]), "B": ("human", [1.0])})
    fig = supplements.figure_residuals(averaged, fits, subjects, WINDOW_MM)
    assert len(fig.axes) == 2
    row = fits.set_index("subject").loc["A"]
    trial = averaged[(averaged["subject"] == "A") & (averaged["distance_mm"] <= WINDOW_MM)]
    expected = {
        "waterbed": models.waterbed_deflection_mm(trial["distance_mm"], 1.0, row["waterbed_L_mm"]),
        "shifted": models.shifted_deflection_mm(trial["distance_mm"], 1.0, row["shifted_L_mm"]),
        "arc": models.arc_deflection_mm(trial["distance_mm"], 1.0, row["arc_L_mm"]),
        "boussinesq": models.boussinesq_deflection_mm(
            trial["distance_mm"], row["boussinesq_A_mm"], row["boussinesq_x0_mm"]
        ),
    }
    lines = {ln.get_gid(): ln for ln in fig.axes[0].get_lines()}
    for model, values in expected.items():
        line = lines[f"residual:{model}:A"]
        np.testing.assert_allclose(line.get_xdata(), trial["distance_mm"])
        np.testing.assert_allclose(line.get_ydata(), trial["deflection_mm"] - values)
    assert "fit-window" in lines


def circle_outline(subject, depth_mm, radius_mm, half_width_mm):
    x_mm = np.linspace(-half_width_mm, half_width_mm, 81)
    resting = np.sqrt(radius_mm**2 - x_mm**2) - radius_mm
    deformed = resting - depth_mm * np.clip(1 - np.abs(x_mm) / half_width_mm, 0, None) ** 2
    return pd.concat(
        [
            pd.DataFrame(
                {
                    "subject": subject,
                    "depth_mm": depth_mm,
                    "state": "resting",
                    "x_mm": x_mm,
                    "z_mm": resting,
                }
            ),
            pd.DataFrame(
                {
                    "subject": subject,
                    "depth_mm": depth_mm,
                    "state": "deformed",
                    "x_mm": x_mm,
                    "z_mm": deformed,
                }
            ),
        ]
    )


def test_figure1_is_drawn_to_one_scale():
    outlines = pd.concat(
        [
            circle_outline("M1", 1.0, 8.0, 6.0),
            circle_outline("H1", 1.0, 45.0, 11.0),
            circle_outline("H1", 2.0, 45.0, 12.0),
        ]
    )
    subjects = pd.DataFrame(
        {"subject": ["M1", "H1"], "species": ["monkey", "human"], "label": ["Monkey 1", "Human 1"]}
    )
    fig = data.figure_outlines(outlines, subjects, ["M1", "H1"], 1.0)
    assert len(fig.axes) == 2
    for ax in fig.axes:
        assert ax.get_aspect() == 1.0
        assert any(p.get_gid() == "wedge" for p in ax.patches)
        styles = {ln.get_gid(): ln.get_linestyle() for ln in ax.get_lines()}
        assert styles == {"outline:resting": "--", "outline:deformed": "-"}
    assert fig.axes[0].get_xlim() == fig.axes[1].get_xlim()
    assert fig.axes[0].get_ylim() == fig.axes[1].get_ylim()
    # drawn, the two panels have the same size, so one mm is as long in both
    FigureCanvasAgg(fig).draw()
    sizes = [(ax.get_position().width, ax.get_position().height) for ax in fig.axes]
    assert sizes[0] == pytest.approx(sizes[1])
    # only the 1 mm outline of H1 is drawn, and the human is the wider one
    human_x = np.concatenate(
        [ln.get_xdata() for ln in fig.axes[1].get_lines() if ln.get_gid() == "outline:deformed"]
    )
    assert np.max(np.abs(human_x)) == pytest.approx(11.0)


def test_labels_and_notice_from_the_data_are_drawn_as_typed_whatever_they_hold():
    # '$\\foo$' is not valid mathtext: drawn as maths it stops the figure with a parse
    # error; from the data it must be drawn as typed, dollars and backslash included
    outlines = circle_outline("M1", 1.0, 8.0, 6.0)
    label = r"$\foo$ & 50 % <b>"
    subjects = pd.DataFrame({"subject": ["M1"], "species": ["monkey"], "label": [label]})
    fig = data.figure_outlines(outlines, subjects, ["M1"], 1.0)
    style.add_footer(fig, r"notice with $\bar$")
    FigureCanvasAgg(fig).draw()  # raised ValueError (ParseFatalException) before
    title = fig.axes[0].get_title(loc="left")
    assert title.startswith(label.replace("$", r"\$"))
    assert any(r"notice with \$\bar\$" in t.get_text() for t in fig.texts)
    # and unescaped, the same label does stop matplotlib: the test can fail
    fig.axes[0].set_title(label, loc="left")
    with pytest.raises(ValueError):
        FigureCanvasAgg(fig).draw()


def test_figure1_without_outlines_says_so():
    fig = data.figure_outlines(pd.DataFrame(), pd.DataFrame(), [], None)
    assert len(fig.axes) == 1
    assert [t.get_gid() for t in fig.axes[0].texts] == ["message"]


def test_figure2_uses_a_log_distance_axis_and_both_models():
    averaged, fits, subjects = make_dataset(PAPER_LIKE)
    fig = data.figure_examples(averaged, fits, subjects, ["M1", "H1"], 1.0, WINDOW_MM)
    assert len(fig.axes) == 2
    for ax in fig.axes:
        assert ax.get_xscale() == "log"
        assert gids(ax, "") == ["data", "fit-window", "model:boussinesq", "model:waterbed"]
    labels = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any("data" in label for label in labels)
    assert any("waterbed" in label for label in labels)
    assert any("Boussinesq" in label for label in labels)


def test_figure2_says_when_its_depth_is_not_the_papers():
    averaged, fits, subjects = make_dataset({"A": ("monkey", [0.75, 1.25]), "B": ("human", [1.25])})
    note = "Shown at 1.25 mm, the measured depth nearest the paper's 1 mm (chosen from the data)."
    fig = data.figure_examples(averaged, fits, subjects, ["A", "B"], 1.25, WINDOW_MM, note)
    (text,) = [t for t in fig.findobj() if t.get_gid() == "note"]
    assert " ".join(text.get_text().split()) == note
    assert [ax.get_title(loc="left") for ax in fig.axes] == [
        "Finger A (monkey), 1.25 mm depth",
        "Finger B (human), 1.25 mm depth",
    ]
    plain = data.figure_examples(averaged, fits, subjects, ["A", "B"], 1.25, WINDOW_MM)
    assert not [t for t in plain.findobj() if t.get_gid() == "note"]


SCHEMATICS = [
    schematics.figure_channel_schematic,
    schematics.figure_material_point,
    schematics.figure_free_body,
]


def footer_texts(fig):
    return [t for t in fig.texts if t.get_gid() == "footer"]


@pytest.mark.parametrize(
    "draw",
    [
        *[lambda notice, f=f: f(0.15, notice) for f in SCHEMATICS],
        lambda notice: data.figure_species_fits(
            *make_dataset(PAPER_LIKE), "human", WINDOW_MM, notice
        ),
        lambda notice: data.figure_species_fits(
            *make_dataset({"A": ("monkey", [1.0])}), "monkey", WINDOW_MM, notice
        ),
        lambda notice: data.figure_outlines(pd.DataFrame(), pd.DataFrame(), [], None, notice),
    ],
)
def test_footer_appears_with_a_notice_only_and_clears_the_axes(draw):
    assert footer_texts(draw("")) == []
    fig = draw(NOTICE)
    (footer,) = footer_texts(fig)
    assert " ".join(footer.get_text().split()) == NOTICE
    assert footer.get_fontsize() >= 6
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    box = footer.get_window_extent(renderer)
    assert box.x0 >= 0 and box.x1 <= fig.bbox.width  # wrapped to the figure's width
    for ax in fig.axes:
        assert box.y1 <= ax.get_tightbbox(renderer).y0


@pytest.mark.parametrize("ratio", [0.1, 0.27])
def test_figure3_membrane_is_equation_19_at_the_stated_ratio(ratio):
    fig = schematics.figure_channel_schematic(ratio)
    (ax,) = fig.axes
    (membrane,) = [ln for ln in ax.get_lines() if ln.get_gid() == "membrane-deformed"]
    X, Z = membrane.get_xdata(), membrane.get_ydata()
    np.testing.assert_allclose(-Z, models.waterbed_deflection_mm(np.abs(X), ratio, 1.0), atol=1e-12)
    assert X.min() == -1.0 and X.max() == 1.0
    np.testing.assert_allclose(Z, Z[::-1])  # symmetric about OZ
    assert Z.min() == pytest.approx(-ratio)
    (rest,) = [ln for ln in ax.get_lines() if ln.get_gid() == "membrane-rest"]
    assert rest.get_linestyle() == "--" and membrane.get_linestyle() == "-"
    assert any(f"= {ratio:g}" in t.get_text() for t in ax.texts)


def test_figure4_point_moves_by_the_shift_of_equation_20():
    ratio, X_A = 0.2, schematics.MATERIAL_POINT_X_OVER_L
    factor = schematics.shift_exaggeration_for(ratio, X_A)
    assert factor > 1  # U is drawn magnified, and the figure says by how much
    fig = schematics.figure_material_point(ratio)
    lines = {ln.get_gid(): ln for ln in fig.axes[0].get_lines()}
    U = models.waterbed_shift_mm(X_A, ratio, 1.0)
    W = models.waterbed_deflection_mm(X_A, ratio, 1.0)
    assert lines["point-initial"].get_xydata().tolist() == [[X_A, 0.0]]
    np.testing.assert_allclose(lines["point-final"].get_xydata(), [[X_A + factor * U, -W]])
    legend_texts = [t for legend in fig.legends for t in legend.get_texts()]
    assert any(f"{factor:g}×" in t.get_text() for t in [*fig.axes[0].texts, *legend_texts])


def test_figure5_states_the_load_angle_of_the_solution():
    ratio = 0.1
    fig = schematics.figure_free_body(ratio)
    angle_deg = np.degrees(np.arctan(4 * ratio))  # slope of eq. 19 at the load is 4 W0 / L
    assert any(f"{angle_deg:.1f}°" in t.get_text() for ax in fig.axes for t in ax.texts)


def png_dpi(path):
    """Horizontal resolution in dots per inch from a PNG's pHYs chunk."""
    data = Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    position = 8
    while position < len(data):
        (length,) = struct.unpack(">I", data[position : position + 4])
        kind = data[position + 4 : position + 8]
        body = data[position + 8 : position + 8 + length]
        if kind == b"pHYs":
            per_metre, _, unit = struct.unpack(">IIB", body)
            assert unit == 1
            return per_metre * 0.0254
        if kind == b"IDAT":  # image data: the header chunks are over
            break
        position += 12 + length
    raise AssertionError(f"{path}: no pHYs chunk")


def png_width_px(path):
    return struct.unpack(">I", Path(path).read_bytes()[16:20])[0]


def test_save_figure_is_reproducible_and_carries_no_dates(tmp_path):
    fig = schematics.figure_channel_schematic(0.15, NOTICE)
    for name in ("a", "b"):
        style.save_figure(fig, tmp_path / f"{name}.pdf", tmp_path / f"{name}.png", 250)
        # laid out once, then no engine at all (not even the placeholder that
        # "none" leaves, with which every savefig draws the figure once more)
        assert fig.get_layout_engine() is None
    for ext in ("pdf", "png"):
        assert (tmp_path / f"a.{ext}").read_bytes() == (tmp_path / f"b.{ext}").read_bytes()
    pdf = (tmp_path / "a.pdf").read_bytes()
    for key in (b"CreationDate", b"ModDate", b"Producer", b"Creator"):
        assert key not in pdf
    assert b"Software" not in (tmp_path / "a.png").read_bytes()
    assert png_dpi(tmp_path / "a.png") == pytest.approx(250, abs=0.5)
    # matplotlib rounds the width in pixels down
    assert png_width_px(tmp_path / "a.png") == int(style.SCHEMATIC_MM / 25.4 * 250)


def embedded_fonts(pdf_path):
    """The PDF's embedded TrueType font programs (FontFile2), by font name."""
    from fontTools.ttLib import TTFont
    from pypdf import PdfReader

    fonts = {}
    for page in PdfReader(pdf_path).pages:
        for font in page["/Resources"]["/Font"].values():
            font = font.get_object()
            for descendant in font.get("/DescendantFonts", [font]):
                descriptor = descendant.get_object().get("/FontDescriptor")
                if descriptor is not None and "/FontFile2" in descriptor.get_object():
                    data = descriptor.get_object()["/FontFile2"].get_object().get_data()
                    fonts[str(descendant.get_object()["/BaseFont"])] = TTFont(BytesIO(data))
    return fonts


def test_pdf_fonts_drop_only_their_layout_tables(tmp_path, monkeypatch):
    from pypdf import PdfReader

    # the same figure with fontTools' own defaults, and as save_figure embeds it
    fig = schematics.figure_channel_schematic(0.15, NOTICE)
    style.save_figure(fig, tmp_path / "lean.pdf", tmp_path / "lean.png", 100)
    monkeypatch.setattr(style, "fonts_without_layout_tables", contextlib.nullcontext)
    fig = schematics.figure_channel_schematic(0.15, NOTICE)
    style.save_figure(fig, tmp_path / "full.pdf", tmp_path / "full.png", 100)
    lean, full = embedded_fonts(tmp_path / "lean.pdf"), embedded_fonts(tmp_path / "full.pdf")
    assert lean and sorted(lean) == sorted(full)  # TrueType fonts, embedded, the same ones
    for name, font in full.items():
        assert set(style.LAYOUT_TABLES) & set(font.keys()), name  # they had them
        assert set(lean[name].keys()) == set(font.keys()) - set(style.LAYOUT_TABLES), name
        # the same glyphs at the same indices; only glyphs reachable by substitution
        # (ligatures, which matplotlib never draws) come after them in the full font
        order = lean[name].getGlyphOrder()
        assert font.getGlyphOrder()[: len(order)] == order, name
    # every glyph drawn where it was: the page's drawing operators, byte for byte
    pages = [PdfReader(tmp_path / f"{kind}.pdf").pages[0] for kind in ("lean", "full")]
    assert pages[0].get_contents().get_data() == pages[1].get_contents().get_data()
    assert pages[0].extract_text() == pages[1].extract_text() and NOTICE in pages[0].extract_text()
    assert (tmp_path / "lean.png").read_bytes() == (tmp_path / "full.png").read_bytes()


def test_prepare_outline_converts_to_tissue_mm(tmp_path):
    raw = tmp_path / "M1.csv"
    raw.write_text(
        "depth_mm,state,x_image_mm,z_image_mm\n"
        "1,deformed,40,-30\n1,resting,-40,-8\n1,resting,40,-8\n1,deformed,-40,-31\n"
    )
    outline = read_table(raw, load_schema("outlines"))
    table = outline_to_tissue_mm(outline, "M1", 20.0)
    assert list(table.columns) == OUTLINE_COLUMNS and set(table["subject"]) == {"M1"}
    assert list(table["state"]) == ["deformed", "deformed", "resting", "resting"]
    np.testing.assert_allclose(table["x_mm"], table["x_image_mm"] / 20)
    np.testing.assert_allclose(table["z_mm"], table["z_image_mm"] / 20)
    assert list(table["x_mm"]) == [-2.0, 2.0, -2.0, 2.0]


FIGURE_NAMES = [figure.name for figure in registry.FIGURES]
#: The widths a figure may have: a journal's column, its double column (the article's
#: text width) and the schematics' narrower width (mm).
FIGURE_WIDTHS_MM = (style.SINGLE_COLUMN_MM, style.DOUBLE_COLUMN_MM, style.SCHEMATIC_MM)
FIGURE_FILES = [f"{name}.{ext}" for name in FIGURE_NAMES for ext in ("pdf", "png")]


@pytest.mark.e2e
def test_workflow_builds_every_figure(tmp_path, small_build):
    """Every figure in both formats at journal width; byte identity: test_determinism.py."""
    raw, out = small_build  # no NOTICE.txt in this raw folder: no footer
    builds = [out / "figures"]
    assert sorted(p.name for p in builds[0].iterdir()) == sorted(FIGURE_FILES)
    for name in FIGURE_FILES:
        first = builds[0] / name
        if name.endswith(".png"):
            assert png_dpi(first) >= 200
            width_in = png_width_px(first) / png_dpi(first)
            assert min(abs(width_in * 25.4 - w) for w in FIGURE_WIDTHS_MM) < 0.5, name
        else:
            assert first.read_bytes().startswith(b"%PDF")
    logs = out / "logs"
    for rule in ("figure_outlines", "figure_schematics", "figure_fits", "figure_supplements"):
        assert (logs / f"{rule}.log").is_file()
    # a notice with shell-awkward characters reaches the data figures intact (and changes
    # them); the schematics show no data and keep their own footer
    out = tmp_path / "notice"
    notice = 'Test data; it\'s "made up" & $HOME stays literal'
    process = run_snakemake(
        "figure_outlines", raw=raw, results=out, config=[f"data_notice={notice}"]
    )
    assert process.returncode == 0, process.stderr[-3000:]
    log = (out / "logs" / "figure_outlines.log").read_text()
    assert f"footer: {notice!r}" in log
    assert "footer: none" in (logs / "figure_outlines.log").read_text()
    with_footer = (out / "figures" / "figure1.png").read_bytes()
    assert with_footer != (builds[0] / "figure1.png").read_bytes()
    assert png_width_px(out / "figures" / "figure1.png") == png_width_px(builds[0] / "figure1.png")


def every_figure(notice):
    """Every registered figure, drawn as a job draws it: from one value per argument name."""
    averaged, fits, subjects = make_dataset(PAPER_LIKE)
    sensitivity, checks = sensitivity_inputs()
    mechanics, mechanics_trials = mechanics_inputs(fits, subjects)
    values = {
        "averaged": averaged,
        "fits": fits,
        "outlines": pd.concat(
            [circle_outline("M1", 1.0, 8.0, 6.0), circle_outline("H1", 1.0, 45.0, 11.0)]
        ),
        "sensitivity": sensitivity,
        "checks": checks,
        "mechanics": mechanics,
        "mechanics_trials": mechanics_trials,
        "subjects": subjects,
        "notice": notice,
        "fit_window_mm": WINDOW_MM,
        "example_subjects": ["M1", "H1"],
        "example_depth_mm": 1.0,
        "example_note": "",
        "outline_subjects": ["M1", "H1"],
        "outline_depth_mm": 1.0,
        "schematic_depth_ratio": 0.15,
        "noise_mm": None,
        "noise": noise_table(),
        "bending": bending_table(fits),
        "coverage": coverage_table(),
        "elastic": elastic_table(averaged, subjects),
        "elastic_library": elastic_library(),
    }
    assert set(values) == set(registry.ARGUMENTS)
    figures = {}
    for figure in registry.FIGURES:
        if figure.name == "supplement_coordinates":  # a fit table with intervals, for the checks
            figures[figure.name] = draw_registered(
                figure, {**values, "fits": coordinates_inputs()[0]}
            )
        else:
            figures[figure.name] = draw_registered(figure, values)
    return figures


def draw_registered(figure, values):
    function = getattr(importlib.import_module(figure.import_path), figure.function)
    return function(**{name: values[name] for name in figure.arguments}, **dict(figure.fixed))


def test_every_figure_fits_its_journal_width_and_keeps_legends_and_labels_on_the_page():
    figures = every_figure(NOTICE)
    assert list(figures) == FIGURE_NAMES
    for name, fig in figures.items():
        width_mm = fig.get_figwidth() * 25.4
        assert min(abs(width_mm - w) for w in FIGURE_WIDTHS_MM) < 1e-6, name
        canvas = FigureCanvasAgg(fig)
        fig.draw_without_rendering()
        renderer = canvas.get_renderer()
        page = fig.bbox
        boxes = [legend.get_window_extent(renderer) for legend in fig.legends]
        boxes += [ax.get_tightbbox(renderer) for ax in fig.axes]
        for box in boxes:
            assert box.x0 >= -1 and box.x1 <= page.x1 + 1, name
            assert box.y0 >= -1 and box.y1 <= page.y1 + 1, name
        sizes = {t.get_fontsize() for ax in fig.axes for t in ax.texts} | {
            t.get_fontsize() for legend in fig.legends for t in legend.get_texts()
        }
        # the tick labels too (a "small" one prints at 6.7 pt), those with text
        sizes |= {
            t.get_fontsize()
            for ax in fig.axes
            for t in ax.get_xticklabels() + ax.get_yticklabels()
            if t.get_text()
        }
        assert min(sizes) >= 7, name


# ------------------------------------------------ layouts from 1 to 8 depths, 1 to 12 subjects

#: The depths of a dataset with n depths: paper-like steps, never 1 mm itself unless n allows.
LAYOUT_DEPTHS = {
    1: [1.25],
    3: [0.75, 1.25, 1.75],
    4: [0.5, 1.0, 1.5, 2.0],
    6: [0.5, 0.75, 1.0, 1.25, 1.5, 1.75],
    8: [0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0],
}


def layout_values(n_per_species, n_depths, notice=NOTICE):
    """One value per registry argument for a dataset of n subjects per species at n depths.

    Every subject has every depth; labels are as long as a lab might write them.  The
    refits behind the sensitivity and coordinates supplements use one subject per
    species (their layout depends on the depths, not on how many subjects there are).
    """
    depths = LAYOUT_DEPTHS[n_depths]
    spec = {
        f"{species[0].upper()}{i:02d}": (species, depths)
        for species in ("monkey", "human")
        for i in range(1, n_per_species + 1)
    }
    averaged, fits, subjects = make_dataset(spec)
    subjects["label"] = [
        f"{s['species'].capitalize()} {s['subject'][1:]}" for _, s in subjects.iterrows()
    ]
    trials = [
        (subject, species, depth, (10.0 if species == "monkey" else 14.0) + depth)
        for subject, species in (("M01", "monkey"), ("H01", "human"))
        for depth in depths
    ]
    sensitivity, checks = sensitivity_inputs(trials)
    with_intervals = checks.assign(
        waterbed_L_ci_low_mm=checks["waterbed_L_mm"] - 0.5,
        waterbed_L_ci_high_mm=checks["waterbed_L_mm"] + 0.5,
        shifted_L_ci_low_mm=checks["shifted_L_mm"] - 0.5,
        shifted_L_ci_high_mm=checks["shifted_L_mm"] + 0.5,
        arc_L_ci_low_mm=checks["arc_L_mm"] - 0.5,
        arc_L_ci_high_mm=checks["arc_L_mm"] + 0.5,
    )
    outlines = pd.concat(
        [
            circle_outline("M01", depths[0], 8.0, 6.0),
            circle_outline("H01", depths[0], 45.0, 11.0),
        ]
    )
    example_depth = depths[len(depths) // 2]
    mechanics, mechanics_trials = mechanics_inputs(fits, subjects)
    return {
        "averaged": averaged,
        "fits": fits,
        "outlines": outlines,
        "sensitivity": sensitivity,
        "checks": checks,
        "subjects": subjects,
        "notice": notice,
        "fit_window_mm": WINDOW_MM,
        "example_subjects": ["M01", "H01"],
        "example_depth_mm": example_depth,
        "example_note": (
            f"Shown at {example_depth:g} mm, the measured depth nearest the paper's 1 mm "
            "(figures: example_depth_mm sets another)."
        ),
        "outline_subjects": ["M01", "H01"],
        "outline_depth_mm": depths[0],
        "schematic_depth_ratio": 0.15,
        "noise_mm": None,
        "noise": noise_table(),
        "mechanics": mechanics,
        "mechanics_trials": mechanics_trials,
        "bending": bending_table(fits),
        "coverage": coverage_table(),
        "elastic": elastic_table(averaged, subjects),
        "elastic_library": elastic_library(),
    }, with_intervals


def coverage_table(n_trials=1040):
    """A coverage summary as the calibration writes it: every scenario, model and
    parameter, pooled, coverage falling as the priors' true sizes grow."""
    from lineload.simulation.coverage import CHECKED, SCENARIOS, described
    from lineload.simulation.rates import binomial_interval

    rows = []
    for scenario in SCENARIOS:
        for model, parameters in CHECKED.items():
            for parameter in parameters:
                covered = round(n_trials * min(0.96, 0.96 / scenario.prior_ratio**0.5))
                low, high = binomial_interval(covered, n_trials)
                rows.append(
                    {
                        "scenario": scenario.name,
                        "model": model,
                        "parameter": parameter,
                        "species": "all",
                        "depth_mm": "all",
                        "n_trials": n_trials,
                        "n_covered": covered,
                        "coverage": covered / n_trials,
                        "ci_low": low,
                        "ci_high": high,
                    }
                )
    return pd.DataFrame(described(rows))


@functools.cache
def elastic_library():
    """The committed library of elastic solutions (read once)."""
    return pd.read_csv(REPO / "data" / "elastic" / "library.csv")


def elastic_table(averaged, subjects):
    """The elastic fits of a test dataset, from the committed library: trials at depths the
    library lacks keep their note and no values, as a lab's would."""
    from lineload.fitting.elastic import ELASTIC_COLUMNS, fit_elastic_trials, library_blocks

    species = dict(zip(subjects["subject"], subjects["species"], strict=True))
    keys, x, y = [], [], []
    for (subject, depth_mm), trial in averaged.groupby(["subject", "depth_mm"], sort=False):
        keys.append((subject, species[subject], float(depth_mm)))
        x.append(trial["distance_mm"].to_numpy(float))
        y.append(trial["deflection_mm"].to_numpy(float))
    rows = fit_elastic_trials(
        x, y, [k[1] for k in keys], [k[2] for k in keys], WINDOW_MM,
        library_blocks(elastic_library()),
    )  # fmt: skip
    return pd.DataFrame(
        [{"subject": k[0], "species": k[1], **row} for k, row in zip(keys, rows, strict=True)]
    )[ELASTIC_COLUMNS]


def bending_table(fits):
    """A bending table for the figures: each trial's waterbed L, a bending length resolved
    in every other trial and at the range's end in the rest (one-sided interval)."""
    rows = []
    for k, (_, fit) in enumerate(fits.iterrows()):
        at_end = k % 2 == 1
        lb = 1e-4 if at_end else 0.05 * (1 + k % 3)
        rows.append(
            {
                "subject": fit["subject"],
                "species": fit["species"],
                "depth_mm": fit["depth_mm"],
                "wall": "clamped",
                "bending_L_mm": fit["waterbed_L_mm"],
                "bending_length_mm": lb,
                "bending_length_ci_low_mm": 1e-4 if at_end else lb / 2,
                "bending_length_ci_high_mm": 0.03 if at_end else lb * 2,
                "bending_length_at_bound": float(at_end),
            }
        )
    return pd.DataFrame(rows)


def drawn_texts(fig):
    """Draw the figure; every text a reader sees (titles, labels, tick labels of ticks
    inside the view, legend entries and titles, notes, footers) and its box in pixels."""
    from matplotlib.text import Text

    canvas = FigureCanvasAgg(fig)
    fig.draw_without_rendering()  # layout and text boxes, without rasterising the artists
    renderer = canvas.get_renderer()
    tick_labels, shown = set(), []
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            for tick in axis.get_major_ticks() + axis.get_minor_ticks():
                tick_labels.update({id(tick.label1), id(tick.label2)})
            if not (ax.axison and axis.get_visible()):
                continue
            for tick in axis._update_ticks():
                shown += [t for t in (tick.label1, tick.label2) if t.get_visible()]
    shown += [t for t in fig.findobj(Text) if id(t) not in tick_labels and t.get_visible()]
    shown = [t for t in shown if t.get_text().strip()]
    return [(t.get_text(), t.get_window_extent(renderer)) for t in shown]


def text_problems(fig, tolerance_px=0.5):
    """Texts that leave the page, and pairs of texts whose boxes overlap (as sentences)."""
    texts = drawn_texts(fig)
    page = fig.bbox
    problems = []
    for text, box in texts:
        if (
            box.x0 < page.x0 - tolerance_px
            or box.y0 < page.y0 - tolerance_px
            or box.x1 > page.x1 + tolerance_px
            or box.y1 > page.y1 + tolerance_px
        ):
            problems.append(f"off the page: {text!r}")
    for i, (text_a, a) in enumerate(texts):
        for text_b, b in texts[i + 1 :]:
            width = min(a.x1, b.x1) - max(a.x0, b.x0)
            height = min(a.y1, b.y1) - max(a.y0, b.y0)
            if width > tolerance_px and height > tolerance_px:
                problems.append(f"overlap: {text_a!r} / {text_b!r}")
    return problems


#: Subjects per species and depths of the datasets whose figures must lay out cleanly.
LAYOUT_EXTREMES = [(1, 1), (1, 8), (12, 1), (12, 8)]
#: Figures drawn from the model alone: the same for every dataset, checked once.
SCHEMATIC_NAMES = ("figure3", "figure4", "figure5")
#: Figures whose layout depends on how many subjects there are (the others are checked
#: on the one-subject datasets only: their panels follow the depths).
PER_SUBJECT_NAMES = (
    "figure2",
    "figure6",
    "figure7",
    "supplement_residuals",
    "supplement_mechanics",
)


@pytest.mark.parametrize(("n_subjects", "n_depths"), LAYOUT_EXTREMES)
def test_every_figure_keeps_its_text_on_the_page_and_apart(n_subjects, n_depths):
    """1 and 12 subjects per species, 1 and 8 depths: legends wrap, panels scale, no text
    leaves the page or runs into another, and every figure fits a journal page."""
    values, fits = layout_values(n_subjects, n_depths)
    figures = {}
    for figure in registry.FIGURES:
        if figure.name in SCHEMATIC_NAMES and (n_subjects, n_depths) != LAYOUT_EXTREMES[0]:
            continue
        if n_subjects > 1 and figure.name not in PER_SUBJECT_NAMES:
            continue
        given = {**values, "fits": fits} if figure.name == "supplement_coordinates" else values
        figures[figure.name] = draw_registered(figure, given)
    figure2 = registry.figure_named("figure2")
    figures["figure2, one subject"] = draw_registered(
        figure2, {**values, "example_subjects": ["M01"]}
    )
    if n_subjects == 12:
        many = [f"{kind}{i:02d}" for kind in "MH" for i in (1, 2, 3)] + ["M04"]
        figures["figure2, seven subjects"] = draw_registered(
            figure2, {**values, "example_subjects": many}
        )
    for name, fig in figures.items():
        width_mm, height_mm = fig.get_figwidth() * 25.4, fig.get_figheight() * 25.4
        assert min(abs(width_mm - w) for w in FIGURE_WIDTHS_MM) < 1e-6, name
        assert height_mm <= 240.0, (name, height_mm)  # a journal page, captions aside
        assert text_problems(fig) == [], name
        assert [t for t, _ in drawn_texts(fig) if SYMBOL_AS_LETTERS.search(t)] == [], name


#: A symbol with its subscript written as a plain letter or digit (W0, l_b, theta0):
#: the figures write W₀ and θ₀, and leave l_b to the caption.
SYMBOL_AS_LETTERS = re.compile(r"\b(?:W0|l_b|theta0|x0)\b")


def test_a_symbol_written_in_plain_letters_is_found():
    assert SYMBOL_AS_LETTERS.search("parabola, W0 = depth")
    assert SYMBOL_AS_LETTERS.search("bending length l_b (mm)")
    assert not SYMBOL_AS_LETTERS.search("parabola, W₀ = depth; W₀/L = 0.1; M10 at 1 mm")


SENSITIVITY_TRIALS = [
    ("A", "monkey", 1.0, 10.0),
    ("A", "monkey", 2.0, 11.0),
    ("B", "human", 1.0, 14.0),
]


def sensitivity_inputs(trials=SENSITIVITY_TRIALS, seed=4):
    """Sensitivity refits and checks of waterbed profiles with known L, as the rules write them."""
    from lineload.fitting import sensitivity as sens

    rng = np.random.default_rng(seed)
    rows, checks = [], []
    x = np.round(np.r_[np.arange(0.05, 0.5001, 0.05), np.arange(0.75, 6.01, 0.25)], 6)
    for subject, species, depth_mm, L_mm in trials:
        y = models.waterbed_deflection_mm(x, depth_mm, L_mm) + rng.normal(0, 0.01, x.size)
        for row in sens.sensitivity_rows(x, y, depth_mm, [2.0, 3.0, np.inf]):
            rows.append({"subject": subject, "species": species, **row})
        check = sens.trial_checks(x, y, depth_mm, 3.0, 0.1)
        checks.append({"subject": subject, "species": species, **check})
    return pd.DataFrame(rows), pd.DataFrame(checks)


def test_sensitivity_figure_has_a_point_per_trial_model_and_window():
    trials = SENSITIVITY_TRIALS
    refits, checks = sensitivity_inputs(trials)
    fig = supplements.figure_sensitivity(refits, checks)
    collections = {c.get_gid(): c for ax in fig.axes for c in ax.collections}
    for model in ("waterbed", "waterbed_free_depth", "shifted", "arc"):
        assert len(collections[f"L:{model}"].get_offsets()) == 3 * len(trials)
    assert "L:boussinesq" not in collections  # the log form has no L
    assert len(collections["aicc:boussinesq"].get_offsets()) == 3 * len(trials)
    shift = np.concatenate(
        [c.get_offsets()[:, 1] for ax in fig.axes for c in ax.collections if c.get_gid() == "shift"]
    )
    expected = [
        100 * 8 * depth**2 / (3 * L**2)
        for (_, _, depth, _), L in zip(trials, checks["waterbed_L_mm"], strict=True)
    ]
    assert sorted(shift) == pytest.approx(sorted(expected))


def coordinates_inputs():
    """A fit table with intervals and the per-trial checks, for the coordinates figure."""
    _, checks = sensitivity_inputs()
    fits = checks.assign(
        waterbed_L_ci_low_mm=checks["waterbed_L_mm"] - 0.5,
        waterbed_L_ci_high_mm=checks["waterbed_L_mm"] + 0.5,
        shifted_L_ci_low_mm=checks["shifted_L_mm"] - 0.5,
        shifted_L_ci_high_mm=checks["shifted_L_mm"] + 0.5,
        arc_L_ci_low_mm=checks["arc_L_mm"] - 0.5,
        arc_L_ci_high_mm=np.inf,  # an interval open above is drawn without failing
    )
    return fits, checks


@pytest.mark.parametrize(
    "noise",
    [{"noise_mm": 0.01}, {"noise": noise_table(0.008, 0.006)}, {"noise": noise_table(0.01, 0.0)}],
    ids=["configured", "measured", "reading-only"],
)
def test_coordinates_figure_has_a_point_per_trial_and_the_noise_line(noise):
    # one reading's noise, whether configured or measured (reading and tracing together)
    fits, checks = coordinates_inputs()
    fig = supplements.figure_coordinates(fits, checks, **noise)
    collections = {}
    for ax in fig.axes:
        for c in ax.collections:
            collections.setdefault(c.get_gid(), []).append(c.get_offsets())
    for model in ("shifted", "arc"):
        L_points = np.concatenate(collections[f"L:{model}"])
        assert sorted(L_points[:, 1]) == pytest.approx(sorted(checks[f"{model}_L_mm"]))
        gap_points = np.concatenate(collections[f"gap:{model}"])
        assert sorted(gap_points[:, 1]) == pytest.approx(sorted(checks[f"gap_{model}_mm"]))
    flat = [ln for ln in fig.axes[1].get_lines() if len(set(ln.get_ydata())) == 1]
    assert [ln.get_ydata()[0] for ln in flat] == [pytest.approx(0.01, rel=1e-12)]
    empty = supplements.figure_coordinates(fits.iloc[0:0], checks.iloc[0:0], noise_mm=0.01)
    assert len(empty.axes) == 1


# ---------------------------------------------------------------- the registry


def test_every_registered_figure_function_takes_exactly_its_arguments():
    for figure in registry.FIGURES:
        module = importlib.import_module(figure.import_path)
        function = getattr(module, figure.function, None)
        assert callable(function), f"{figure.name}: no {figure.import_path}.{figure.function}"
        parameters = inspect.signature(function).parameters
        fixed = [name for name, _ in figure.fixed]
        # called with keywords only: the names must match, the order need not
        assert sorted(parameters) == sorted([*figure.arguments, *fixed]), figure.name
        kinds = {p.kind for p in parameters.values()}
        assert kinds <= {inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY}
        assert set(figure.arguments) <= set(registry.ARGUMENTS), figure.name
        assert not set(fixed) & set(registry.ARGUMENTS), figure.name  # fixed is not a value


def test_registry_lists_each_figure_once_in_its_group():
    names = [figure.name for figure in registry.FIGURES]
    assert len(set(names)) == len(names)
    groups = {
        group: [f.name for f in registry.figures_in_group(group)] for group in registry.GROUPS
    }
    assert groups == {
        "outlines": ["figure1"],
        "schematics": ["figure3", "figure4", "figure5"],
        "fits": ["figure2", "figure6", "figure7"],
        "supplements": [  # in the article's order (its Figures 9-13)
            "supplement_coordinates",
            "supplement_residuals",
            "supplement_arc_vs_parabola",
            "supplement_sensitivity",
            "supplement_mechanics",
        ],
        "families": [  # the later model families in one job: Figures 14-17
            "supplement_bending",
            "supplement_bending_lengths",
            "supplement_elastic",
            "supplement_elastic_ratios",
        ],
        "calibration": ["supplement_coverage"],  # Figure 8
    }
    # the paper's figures in its order, then the supplements
    assert names[:7] == [f"figure{i}" for i in range(1, 8)]
    categories = [figure.category for figure in registry.FIGURES]
    assert categories == ["Paper figures"] * 7 + ["Supplement"] * 10
    for figure in registry.FIGURES:
        assert figure.module in (
            "data",
            "schematics",
            "supplements",
            "bending",
            "elastic",
            "calibration",
        ), figure.name
        assert figure.title and "\n" not in figure.title, figure.name
    used = {name for figure in registry.FIGURES for name in figure.arguments}
    assert used == set(registry.ARGUMENTS)  # no argument is described but never taken
    assert {argument.kind for argument in registry.ARGUMENTS.values()} == set(registry.KINDS)
    with pytest.raises(KeyError):
        registry.figures_in_group("figures")
    with pytest.raises(KeyError):
        registry.figure_named("figure8")


def test_each_group_reads_the_tables_its_figures_take():
    assert registry.file_arguments("outlines") == ("outlines",)
    assert registry.file_arguments("schematics") == ()
    assert registry.file_arguments("fits") == ("averaged", "fits")
    assert registry.file_arguments("supplements") == (
        "averaged",
        "fits",
        "sensitivity",
        "checks",
        "mechanics",
        "mechanics_trials",
        "noise",
    )
    # the schematics show no data: the data notice is not theirs (nor a reason to redraw)
    assert registry.arguments_of_group("schematics") == ("schematic_depth_ratio",)
    for figure in registry.figures_in_group("schematics"):
        assert dict(figure.fixed) == {"footer": registry.MODEL_FOOTER}
    assert registry.arguments_of_group("fits", "dataset") == ("subjects",)


def test_the_registry_imports_nothing_heavy():
    # Snakemake reads the registry while it parses the workflow
    statement = "import lineload.figures, lineload.figures.registry"
    assert imported_after(statement, ("matplotlib", "numpy", "pandas")) == []
    # the check can fail: the figures' style does import matplotlib
    assert imported_after("import lineload.figures.style", ("matplotlib",)) == ["matplotlib"]


# ---------------------------------------------------------------- forces on the wedge


def mechanics_inputs(fits, subjects, with_forces=True, prestrain=0.3):
    """Mechanics tables as the rule writes them, from forces of a pre-tensioned membrane."""
    from lineload import mechanics

    fits = fits.assign(
        arc_L_ci_low_mm=fits["arc_L_mm"] - 0.3, arc_L_ci_high_mm=fits["arc_L_mm"] + 0.3
    )
    forces = None
    if with_forces:
        u, v = mechanics.force_terms(fits["depth_mm"], fits["arc_L_mm"])
        forces = pd.DataFrame(
            {
                "subject": fits["subject"],
                "depth_mm": fits["depth_mm"],
                "force_N": 2 * 10.0 * 0.2 * (prestrain * u + v),  # l = 10 mm, E = 0.2 N/mm
            }
        )
    lengths = dict.fromkeys(subjects["subject"], 10.0)
    return mechanics.mechanics_tables(fits, forces, lengths, 0.005)


def test_mechanics_figure_draws_readings_both_models_and_the_fit_per_subject():
    _, fits, subjects = make_dataset(PAPER_LIKE)
    table, trials = mechanics_inputs(fits, subjects)
    fig = supplements.figure_mechanics(trials, table, subjects)
    panels = {t: ax for t, ax in panels_by_title(fig).items() if t}
    assert len(panels) == len(PAPER_LIKE)
    for subject, (species, depths) in PAPER_LIKE.items():
        ax = panels[f"Finger {subject} ({species})"]
        lines = {line.get_gid(): line for line in ax.get_lines() if line.get_gid()}
        assert set(lines) == {
            f"{kind}:{subject}" for kind in ("force", "stress_free", "tension_only", "fitted")
        }
        readings = lines[f"force:{subject}"]
        assert list(readings.get_xdata()) == depths
        rows = trials[trials["subject"] == subject]
        assert list(readings.get_ydata()) == pytest.approx(rows["force_N"].to_list())
        # both model curves start at the reading of the smallest depth
        for kind in ("stress_free", "tension_only"):
            assert lines[f"{kind}:{subject}"].get_ydata()[0] == pytest.approx(
                rows["force_N"].iloc[0]
            )
        # the stress-free membrane grows much faster than the readings of a pre-tensioned one
        assert lines[f"stress_free:{subject}"].get_ydata()[-1] > 2 * rows["force_N"].iloc[-1]
        assert list(lines[f"fitted:{subject}"].get_ydata()) == pytest.approx(
            rows["force_N"].to_list(), rel=1e-6
        )
        assert [p.get_gid() for p in ax.patches] == ["paper-range"]
    assert ax.get_xscale() == ax.get_yscale() == "log"


def test_mechanics_figure_without_forces_shows_ratios_against_the_papers_bound():
    _, fits, subjects = make_dataset(PAPER_LIKE)
    table, trials = mechanics_inputs(fits, subjects, with_forces=False)
    assert table.empty
    fig = supplements.figure_mechanics(trials, table, subjects)
    ax = panels_by_title(fig)["Finger M1 (monkey)"]
    lines = {line.get_gid(): line for line in ax.get_lines() if line.get_gid()}
    assert set(lines) == {"stress_free:M1", "tension_only:M1"}
    assert lines["stress_free:M1"].get_ydata()[0] == pytest.approx(1.0)
    band = ax.patches[0]  # the ratios the paper's 0.3-1 N allows
    assert (band.get_y(), band.get_y() + band.get_height()) == pytest.approx((1.0, 1.0 / 0.3))
    # one depth only: nothing to compare, the figure says so
    single = trials[trials["depth_mm"] == 1.0]
    assert len(supplements.figure_mechanics(single, table, subjects).axes) == 1


TWO_MONKEYS = {"M1": ("monkey", [1.0, 2.0]), "M2": ("monkey", [1.0, 2.0])}


@pytest.mark.parametrize("with_forces", [True, False])
@pytest.mark.parametrize("spec", [PAPER_LIKE, TWO_MONKEYS], ids=["paper-like", "two-monkeys"])
def test_mechanics_figures_y_label_stays_beside_its_panels(spec, with_forces):
    # one row of panels (the photograph example's two monkeys) is lower than the label
    # is long: centred on the figure, it ran up into the legend
    _, fits, subjects = make_dataset(spec)
    table, trials = mechanics_inputs(fits, subjects, with_forces=with_forces)
    fig = supplements.figure_mechanics(trials, table, subjects, "a notice for the footer")
    canvas = FigureCanvasAgg(fig)
    fig.draw_without_rendering()
    renderer = canvas.get_renderer()
    label = fig._supylabel.get_window_extent(renderer)
    panels = [ax.get_window_extent(renderer) for ax in fig.axes]
    assert min(p.y0 for p in panels) - 0.5 <= label.y0
    assert label.y1 <= max(p.y1 for p in panels) + 0.5
    (legend,) = fig.legends
    assert label.y1 < legend.get_window_extent(renderer).y0
    assert text_problems(fig) == []


def test_noted_legend_sits_above_with_the_note_as_its_title():
    from matplotlib.lines import Line2D

    with style.figure_style():
        fig = style.new_figure(style.SINGLE_COLUMN_MM, 60.0)
        fig.add_subplot()
        handles = [Line2D([], [], label=f"entry {k}") for k in range(5)]
        note = "a note long enough to be wrapped onto more than one line of a narrow figure " * 2
        legend = style.noted_legend(fig, handles, 3, note)
        n_columns = style.legend_columns(fig, handles, 3)  # the style's legend font
    assert fig.legends == [legend]
    assert legend.get_title().get_text() == style.wrapped_note(fig, note, 7.0)
    assert "\n" in legend.get_title().get_text()
    assert legend.get_title().get_fontsize() == 7.0
    assert legend._ncols == n_columns <= 3
    assert [t.get_text() for t in legend.get_texts()] == [h.get_label() for h in handles]
