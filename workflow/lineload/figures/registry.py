"""The one list of the workflow's figures: what each is, who draws it and from what.

Snakemake reads this module when it parses the workflow, so it imports nothing
but the standard library (no matplotlib, numpy or pandas).  A job that draws a
group of figures reads the files and settings named in :data:`ARGUMENTS` and
calls, for each :class:`Figure` of its group::

    function = getattr(importlib.import_module(figure.import_path), figure.function)
    function(**{name: values[name] for name in figure.arguments}, **dict(figure.fixed))

Every figure function takes exactly ``arguments`` and the names in ``fixed``
(``tests/test_figures.py`` checks it).
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "ARGUMENTS",
    "CATEGORIES",
    "FIGURES",
    "GROUPS",
    "KINDS",
    "Argument",
    "Figure",
    "arguments_of_group",
    "figure_named",
    "figures_in_group",
    "file_arguments",
    "report_label",
]

#: Kinds of figure argument: a results table a job reads, the subject sheet, a setting.
KINDS = ("file", "dataset", "setting")

#: The jobs that draw figures, each a group of figures drawn in one process.  A group
#: costs a process and matplotlib's start-up (about 0.8 s of CPU): the later model
#: families (the bending skin, the elastic finger) share one, whose figures are redrawn
#: when either family's table changes.
GROUPS = ("outlines", "schematics", "fits", "supplements", "families", "calibration")

#: Report categories of the figures.
CATEGORIES = ("Paper figures", "Supplement")


@dataclass(frozen=True)
class Argument:
    """One value a figure function takes.

    Attributes
    ----------
    kind : str
        ``file``: a results table the job reads (one or more CSV files, given to
        the function as one DataFrame); ``dataset``: the subject sheet;
        ``setting``: a value from the config or the raw folder.
    description : str
        What it is, with its unit.
    """

    kind: str
    description: str


#: Every argument name a figure function may take.
ARGUMENTS = {
    "averaged": Argument(
        "file",
        "averaged profiles of every subject (data/averaged/*.csv): subject, depth_mm, "
        "distance_mm, deflection_mm (mean of left and right, mm)",
    ),
    "fits": Argument("file", "the fit table, one row per subject and depth (tables/fits.csv)"),
    "outlines": Argument(
        "file",
        "outlines in tissue mm of the Figure 1 subjects (data/outlines/*.csv); "
        "None when the dataset has none",
    ),
    "sensitivity": Argument(
        "file", "refits per trial, model and fit window (tables/sensitivity.csv)"
    ),
    "checks": Argument(
        "file", "per-trial shift, reach and coordinate gaps (tables/trial_checks.csv)"
    ),
    "mechanics": Argument(
        "file",
        "the membrane fitted to each subject's forces (tables/mechanics.csv); may be empty",
    ),
    "mechanics_trials": Argument(
        "file",
        "per trial: exact-arc load angle and strain, force, fitted and stress-free forces "
        "(tables/mechanics_trials.csv)",
    ),
    "subjects": Argument(
        "dataset", "the subject sheet in its order: a DataFrame of subject, species, label"
    ),
    "notice": Argument("setting", "footer text on every figure; empty for none"),
    "fit_window_mm": Argument("setting", "outer edge of the fitted region (mm)"),
    "example_subjects": Argument("setting", "the subjects of Figure 2, one panel each, in order"),
    "example_depth_mm": Argument(
        "setting", "the indentation depth shown in Figure 2 (mm); None without profiles"
    ),
    "example_note": Argument(
        "setting",
        "a sentence printed under Figure 2 when its depth is not the paper's 1 mm "
        "(lineload.figures.choices); empty otherwise",
    ),
    "outline_subjects": Argument("setting", "the subjects of Figure 1, one panel each, in order"),
    "outline_depth_mm": Argument(
        "setting", "the indentation depth of the Figure 1 outlines (mm); None without outlines"
    ),
    "schematic_depth_ratio": Argument(
        "setting", "W0 / L at which Figures 3-5 draw the model (dimensionless)"
    ),
    "noise_mm": Argument(
        "setting", "digitising noise of one reading (mm) as configured; None: the noise table's"
    ),
    "noise": Argument("file", "the digitising noise, measured and priors (tables/noise.csv)"),
    "bending": Argument(
        "file", "the bending skin's fits, one row per subject and depth (tables/bending.csv)"
    ),
    "elastic": Argument(
        "file",
        "the elastic finger's fits, one row per subject and depth (tables/elastic_fits.csv)",
    ),
    "elastic_library": Argument(
        "file", "the elastic finger's solution library the fits were made from (elastic)"
    ),
    "coverage": Argument(
        "file",
        "the coverage study's summary as committed (docs/calibration/coverage.csv; "
        "snakemake calibration remakes it): coverage per scenario of errors, model and "
        "parameter, with the true/stated size of the priors",
    ),
}


@dataclass(frozen=True)
class Figure:
    """One figure of the workflow and how it is drawn.

    Attributes
    ----------
    name : str
        File stem under ``results/figures/`` (``figure2``, ``supplement_residuals``).
    group : str
        The job that draws it, one of :data:`GROUPS`.
    module : str
        ``data``, ``schematics``, ``supplements``, ``bending``, ``elastic`` or
        ``calibration``: the module ``lineload.figures.<module>`` that holds the function.
    function : str
        Name of the figure function in that module.
    arguments : tuple of str
        Keyword names the function takes, each a key of :data:`ARGUMENTS`.
    fixed : tuple of (str, object)
        Further keyword arguments with their values, the same in every run
        (e.g. ``(("species", "monkey"),)``).
    category : str
        Report category, one of :data:`CATEGORIES`.
    title : str
        What the figure shows, in one line.
    """

    name: str
    group: str
    module: str
    function: str
    arguments: tuple
    fixed: tuple = ()
    category: str = "Paper figures"
    title: str = ""

    @property
    def import_path(self):
        """Dotted path of the module that holds the function."""
        return f"lineload.figures.{self.module}"


#: Arguments of the figures drawn from the averaged profiles and the fit table
#: (Figures 6 and 7, the residual supplement).
_PROFILES_AND_FITS = ("averaged", "fits", "subjects", "fit_window_mm", "notice")

#: A space as wide as a digit (U+2007), which sorts before the digits.
FIGURE_SPACE = "\u2007"

#: The footer of the schematics: drawn from the equations, they show no data, so the data
#: notice is not theirs (a reader would take them for measurements).
MODEL_FOOTER = "Drawn from the model's equations; no measurements are shown."

#: Every figure: the paper's in its order, then the supplements in the article's order
#: (the article numbers them on from the paper's, and the report as the article does).
FIGURES = (
    Figure(
        "figure1",
        "outlines",
        "data",
        "figure_outlines",
        ("outlines", "subjects", "outline_subjects", "outline_depth_mm", "notice"),
        title="Resting and indented outlines of a monkey and a human fingertip, to one scale",
    ),
    Figure(
        "figure2",
        "fits",
        "data",
        "figure_examples",
        (
            "averaged",
            "fits",
            "subjects",
            "example_subjects",
            "example_depth_mm",
            "example_note",
            "fit_window_mm",
            "notice",
        ),
        title="One depth against log distance, with the waterbed and Boussinesq fits",
    ),
    Figure(
        "figure3",
        "schematics",
        "schematics",
        "figure_channel_schematic",
        ("schematic_depth_ratio",),
        fixed=(("footer", MODEL_FOOTER),),
        title="The waterbed model: a membrane over fluid in a rigid channel, under a line load",
    ),
    Figure(
        "figure4",
        "schematics",
        "schematics",
        "figure_material_point",
        ("schematic_depth_ratio",),
        fixed=(("footer", MODEL_FOOTER),),
        title="Where a point of the membrane moves: from (X, 0) to (X + U, W)",
    ),
    Figure(
        "figure5",
        "schematics",
        "schematics",
        "figure_free_body",
        ("schematic_depth_ratio",),
        fixed=(("footer", MODEL_FOOTER),),
        title="Force balance at the load and on a small piece of membrane",
    ),
    Figure(
        "figure6",
        "fits",
        "data",
        "figure_species_fits",
        _PROFILES_AND_FITS,
        fixed=(("species", "monkey"),),
        title="Every monkey at every depth, with its waterbed fit",
    ),
    Figure(
        "figure7",
        "fits",
        "data",
        "figure_species_fits",
        _PROFILES_AND_FITS,
        fixed=(("species", "human"),),
        title="Every human at every depth, with its waterbed fit",
    ),
    Figure(
        "supplement_coverage",
        "calibration",
        "calibration",
        "figure_coverage_misspecified",
        ("coverage", "notice"),
        category="Supplement",
        title="Coverage of the intervals when the errors' true sizes are not the stated ones",
    ),
    Figure(
        "supplement_coordinates",
        "supplements",
        "supplements",
        "figure_coordinates",
        ("fits", "checks", "noise", "noise_mm", "notice"),
        category="Supplement",
        title="What fitting in measured coordinates changes, against the reading noise",
    ),
    Figure(
        "supplement_residuals",
        "supplements",
        "supplements",
        "figure_residuals",
        _PROFILES_AND_FITS,
        category="Supplement",
        title="Data minus each fitted model inside the fit window, by species and depth",
    ),
    Figure(
        "supplement_arc_vs_parabola",
        "supplements",
        "supplements",
        "figure_arc_vs_parabola",
        ("fits", "notice"),
        category="Supplement",
        title="How far the small-slope parabola is from the exact arc at the fitted sizes",
    ),
    Figure(
        "supplement_sensitivity",
        "supplements",
        "supplements",
        "figure_sensitivity",
        ("sensitivity", "checks", "notice"),
        category="Supplement",
        title="Fitted size, model ranking, shift and reach across fit windows, trial by trial",
    ),
    Figure(
        "supplement_mechanics",
        "supplements",
        "supplements",
        "figure_mechanics",
        ("mechanics_trials", "mechanics", "subjects", "notice"),
        category="Supplement",
        title="Force on the wedge against depth: readings, stress-free and pre-tensioned membrane",
    ),
    Figure(
        "supplement_bending",
        "families",
        "bending",
        "figure_bending_examples",
        ("averaged", "fits", "bending", "subjects", "fit_window_mm", "notice"),
        category="Supplement",
        title="Every model family, the bending skin's included, on one subject per species",
    ),
    Figure(
        "supplement_bending_lengths",
        "families",
        "bending",
        "figure_bending_lengths",
        ("bending", "averaged", "subjects", "notice"),
        category="Supplement",
        title="The skin's fitted bending length by species and depth, with its interval",
    ),
    Figure(
        "supplement_elastic",
        "families",
        "elastic",
        "figure_elastic_examples",
        ("averaged", "elastic", "elastic_library", "subjects", "fit_window_mm", "notice"),
        category="Supplement",
        title="The homogeneous and the layered elastic finger on one subject per species",
    ),
    Figure(
        "supplement_elastic_ratios",
        "families",
        "elastic",
        "figure_elastic_ratios",
        ("elastic", "subjects", "notice"),
        category="Supplement",
        title="The layered finger's fitted modulus ratio by species and depth, with its interval",
    ),
)


def figure_named(name):
    """The registered figure with this file stem.

    Raises
    ------
    KeyError
        If no figure has that name.
    """
    for figure in FIGURES:
        if figure.name == name:
            return figure
    raise KeyError(f"no figure named {name!r}; known: {', '.join(f.name for f in FIGURES)}")


def report_label(figure):
    """How the report numbers a figure: as the article does (``Figure 2``, ``Figure 10``).

    The report sorts its labels as text, where "Figure 10" would come before "Figure 8":
    shorter numbers are padded with figure spaces (U+2007, as wide as a digit), which sort
    before digits, so the labels line up and come in order.

    Parameters
    ----------
    figure : Figure

    Returns
    -------
    str
    """
    number = FIGURES.index(figure) + 1
    return "Figure " + str(number).rjust(len(str(len(FIGURES))), FIGURE_SPACE)


def figures_in_group(group):
    """The figures one job draws, in registry order.

    Raises
    ------
    KeyError
        If the group is not one of :data:`GROUPS`.
    """
    if group not in GROUPS:
        raise KeyError(f"no figure group {group!r}; known: {', '.join(GROUPS)}")
    return tuple(figure for figure in FIGURES if figure.group == group)


def arguments_of_group(group, kind=None):
    """Argument names the figures of a group take, in :data:`ARGUMENTS` order.

    Parameters
    ----------
    group : str
        One of :data:`GROUPS`.
    kind : str, optional
        Only arguments of this kind (one of :data:`KINDS`).

    Returns
    -------
    tuple of str
    """
    wanted = {name for figure in figures_in_group(group) for name in figure.arguments}
    return tuple(
        name
        for name, argument in ARGUMENTS.items()
        if name in wanted and (kind is None or argument.kind == kind)
    )


def file_arguments(group):
    """The results tables a group's job reads (its inputs), in :data:`ARGUMENTS` order."""
    return arguments_of_group(group, "file")
