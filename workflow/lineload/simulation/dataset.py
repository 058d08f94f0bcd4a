"""Writing the synthetic reconstruction: the files of its raw-data folder, as text.

:func:`build_dataset` returns every file of the shipped folder ``data/raw`` (or of
a scale dataset of drawn fingers) with fixed float formatting, sorted rows and no
time stamps; the CLI ``workflow/scripts/make_synthetic_data.py`` writes them.
Beside the files: the tables of true parameters printed in ``data/README.md``, and
the verdicts the generator builds into the shipped data.
"""

from __future__ import annotations

import pandas as pd

from lineload.claims.registry import built_in_verdicts as _registry_built_in_verdicts
from lineload.io import csv_text
from lineload.publishing.tables import markdown_table
from lineload.simulation.notices import DATA_NOTICE
from lineload.simulation.readings import force_table, outline_table, profile_table, trial_forces
from lineload.simulation.subjects import (
    DEFAULT_SEED,
    MAGNIFICATION,
    draw_subjects,
    shipped_subjects,
    trial_parameters,
)

__all__ = [
    "DATA_NOTICE",
    "build_dataset",
    "built_in_verdicts",
    "force_markdown",
    "membrane_markdown",
    "parameter_markdown",
    "parameter_table",
    "subject_markdown",
    "subjects_table",
]


def subjects_table(subjects, magnification=MAGNIFICATION):
    """The subject sheet: ``subject``, ``species``, ``magnification``, ``label``.

    ``contact_length_mm`` follows when every finger has one (the shipped ones).

    Parameters
    ----------
    subjects : list of SubjectParameters
    magnification : float, optional

    Returns
    -------
    pandas.DataFrame
    """
    table = pd.DataFrame(
        {
            "subject": [s.subject for s in subjects],
            "species": [s.species for s in subjects],
            "magnification": float(magnification),
            "label": [s.label for s in subjects],
        }
    )
    if all(s.contact_length_mm is not None for s in subjects):
        table["contact_length_mm"] = [s.contact_length_mm for s in subjects]
    return table


def parameter_table(subjects):
    """True-profile parameters of every trial (one row per subject and depth).

    Parameters
    ----------
    subjects : list of SubjectParameters

    Returns
    -------
    pandas.DataFrame
        ``subject``, ``species``, ``depth_mm``, ``extent_left_mm``,
        ``extent_right_mm``, ``exponent``, ``near_fraction``, ``near_exponent``.
    """
    rows = []
    for subject in subjects:
        for depth_mm in subject.depths_mm:
            trial = trial_parameters(subject, depth_mm)
            rows.append({"subject": subject.subject, "species": subject.species, **trial.__dict__})
    columns = [
        "subject",
        "species",
        "depth_mm",
        "extent_left_mm",
        "extent_right_mm",
        "exponent",
        "near_fraction",
        "near_exponent",
    ]
    return pd.DataFrame(rows)[columns]


def parameter_markdown(subjects):
    """The per-trial parameter table as Markdown, as printed in ``data/README.md``.

    Parameters
    ----------
    subjects : list of SubjectParameters

    Returns
    -------
    str
        A Markdown table ending with a newline.
    """
    headers = [
        "subject",
        "species",
        "depth (mm)",
        "edge left e_L (mm)",
        "edge right e_R (mm)",
        "p",
        "beta",
        "q",
    ]
    rows = [
        [
            row.subject,
            row.species,
            f"{row.depth_mm:.2f}",
            f"{row.extent_left_mm:.2f}",
            f"{row.extent_right_mm:.2f}",
            f"{row.exponent:.3f}",
            f"{row.near_fraction:.4f}",
            f"{row.near_exponent:g}",
        ]
        for row in parameter_table(subjects).itertuples(index=False)
    ]
    return markdown_table(headers, rows, "l" * len(headers))


def subject_markdown(subjects):
    """The per-subject parameters as a Markdown table, as printed in ``data/README.md``.

    Parameters
    ----------
    subjects : list of SubjectParameters

    Returns
    -------
    str
        A Markdown table ending with a newline.
    """
    headers = [
        "subject",
        "species",
        "depths (mm)",
        "e at 0.5 mm",
        "e at 2 mm",
        "p at 0.5 mm",
        "p at 2 mm",
        "beta at 2 mm",
        "a (left/right)",
        "resting radius (mm)",
    ]
    rows = [
        [
            s.subject,
            s.species,
            ", ".join(f"{d:g}" for d in s.depths_mm),
            f"{s.extent_shallow_mm:g}",
            f"{s.extent_deep_mm:g}",
            f"{s.exponent_shallow:g}",
            f"{s.exponent_deep:g}",
            f"{s.near_fraction_deep:g}",
            f"{s.side_asymmetry:+g}",
            "-" if s.resting_radius_mm is None else f"{s.resting_radius_mm:g}",
        ]
        for s in subjects
    ]
    return markdown_table(headers, rows, "l" * len(headers))


def membrane_markdown(subjects):
    """The membrane of each finger with one, as a Markdown table, as printed in ``data/README.md``.

    Parameters
    ----------
    subjects : list of SubjectParameters

    Returns
    -------
    str
        A Markdown table ending with a newline (no rows if no finger has a membrane).
    """
    headers = [
        "subject",
        "contact length l (mm)",
        "stiffness E (N/mm)",
        "pre-strain N0/E",
        "pre-tension N0 (N/mm)",
    ]
    rows = [
        [
            s.subject,
            f"{s.contact_length_mm:g}",
            f"{s.stiffness_N_per_mm:g}",
            f"{s.prestrain:g}",
            f"{s.pretension_N_per_mm:.4f}",
        ]
        for s in subjects
        if s.contact_length_mm is not None
    ]
    return markdown_table(headers, rows, "l" * len(headers))


def force_markdown(subjects, seed=DEFAULT_SEED):
    """Every trial's membrane geometry and force as a Markdown table (``data/README.md``).

    Parameters
    ----------
    subjects : list of SubjectParameters
    seed : int, optional

    Returns
    -------
    str
        A Markdown table ending with a newline.
    """
    headers = [
        "subject",
        "depth (mm)",
        "arc L (mm)",
        "theta0 (rad)",
        "strain",
        "true force (N)",
        "force_N as written",
    ]
    rows = [
        [
            s.subject,
            f"{r['depth_mm']:.2f}",
            f"{r['L_mm']:.3f}",
            f"{r['load_angle_rad']:.4f}",
            f"{r['strain']:.5f}",
            f"{r['true_force_N']:.4f}",
            f"{r['force_N']:.3f}",
        ]
        for s in subjects
        if s.contact_length_mm is not None
        for r in trial_forces(s, seed)
    ]
    return markdown_table(headers, rows, "l" * len(headers))


def _csv_text(table, formats):
    """CSV text with one fixed format per column (:func:`lineload.io.csv_text` lines)."""
    columns = [column for column in formats if column in table.columns]
    cells = []
    for column in columns:
        fmt = formats[column]
        values = table[column].tolist()
        cells.append([format(v, fmt) if fmt else str(v) for v in values])
    return csv_text(columns, cells)


SUBJECT_FORMATS = {
    "subject": "",
    "species": "",
    "magnification": ".1f",
    "label": "",
    "contact_length_mm": ".1f",
}
FORCE_FORMATS = {"subject": "", "depth_mm": ".2f", "force_N": ".3f"}
PROFILE_FORMATS = {
    "depth_mm": ".2f",
    "side": "",
    "distance_image_mm": ".1f",
    "deflection_image_mm": ".1f",
}
OUTLINE_FORMATS = {"depth_mm": ".2f", "state": "", "x_image_mm": ".1f", "z_image_mm": ".1f"}


#: What the generator puts into the shipped reconstruction, claim by claim (the
#: verdict, its truth and how it comes about), is stated in each claim's registry entry
#: (``built_in``); written to ``data/built_in_verdicts.json`` by the generator's script.
built_in_verdicts = _registry_built_in_verdicts


def build_dataset(
    seed=DEFAULT_SEED, n_monkeys=None, n_humans=None, shuffle=False, magnification=MAGNIFICATION
):
    """Every file of a synthetic raw-data folder, as text.

    Parameters
    ----------
    seed : int, optional
        Dataset seed (1989 for the shipped data).
    n_monkeys, n_humans : int, optional
        Scale mode: that many fingers with drawn parameters.  Leave both
        ``None`` for the seven hand-chosen fingers of the shipped data.
    shuffle : bool, optional
        Shuffle the rows of each profile file (seeded).
    magnification : float, optional
        Enlargement factor written to the subject sheet and applied to readings.

    Returns
    -------
    dict of str to str
        Relative POSIX path (``NOTICE.txt``, ``subjects.csv``, ``forces.csv``
        when the fingers have membranes, ``profiles/M1.csv``,
        ``outlines/M1.csv``...) to file content, in a
        stable order.  ``NOTICE.txt`` marks the folder as synthetic: the
        workflow prints its first line under every figure and table.
    """
    if n_monkeys is None and n_humans is None:
        subjects = shipped_subjects()
    else:
        subjects = draw_subjects(n_monkeys or 0, n_humans or 0, seed)
    if not subjects:
        raise ValueError("a dataset needs at least one subject")
    files = {
        "NOTICE.txt": DATA_NOTICE,
        "subjects.csv": _csv_text(subjects_table(subjects, magnification), SUBJECT_FORMATS),
    }
    forces = force_table(subjects, seed)
    if len(forces):
        files["forces.csv"] = _csv_text(forces, FORCE_FORMATS)
    for subject in subjects:
        readings = profile_table(subject, seed, magnification, shuffle)
        files[f"profiles/{subject.subject}.csv"] = _csv_text(readings, PROFILE_FORMATS)
    for subject in subjects:
        if subject.resting_radius_mm is not None:
            files[f"outlines/{subject.subject}.csv"] = _csv_text(
                outline_table(subject, magnification), OUTLINE_FORMATS
            )
    return files
