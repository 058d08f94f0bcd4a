"""The optional ``forces.csv``: typed cells, known trials, one force per trial.

A force belongs to a subject of the subject sheet at a depth of its profile, once; a
force above the config's ``input_checks: force_max_N`` is refused with its likely cause
(millinewtons written where newtons belong).
"""

from __future__ import annotations

import os
import re

from lineload.rawdata.errors import collecting
from lineload.rawdata.plausibility import plausibility_defaults
from lineload.rawdata.sheets import read_table
from lineload.trials import trial_key

__all__ = ["check_forces", "read_forces"]


def check_forces(
    raw_dir,
    schema,
    subjects,
    depths_mm,
    raw_dir_shown=None,
    problems=None,
    force_max_N=None,
    unknown_depths=(),
):
    """Check the optional ``forces.csv``: typed cells, known trials, one force per trial.

    Parameters
    ----------
    raw_dir : str
        The raw-data folder.
    schema : dict
        Row schema of ``forces.csv`` (``workflow/schemas/forces.schema.yaml``).
    subjects : pandas.DataFrame
        The checked subject sheet (:func:`read_table`).
    depths_mm : dict
        Subject -> depths of its profile file (mm).
    raw_dir_shown : str, optional
        How to name the folder in messages.
    problems : Problems, optional
        Collector to add problems to; without one, they are raised.
    force_max_N : float, optional
        Largest plausible force (config ``input_checks: force_max_N``; the
        schema's default if None).
    unknown_depths : collection of str, optional
        Subjects whose profile was refused: their depths are not known, so a
        force is not checked against them (one mistake, one line).

    Returns
    -------
    pandas.DataFrame or None
        The typed forces (index: line numbers), or None without the file (or,
        with a collector, when it cannot be read as a table).

    Raises
    ------
    InputError
        Without a collector, naming the line and column of each problem: a
        cell that breaks the schema (a force of zero or less, text), a force
        above ``force_max_N``, a subject not in the subject sheet, a depth with
        no profile for that subject, or a second force for the same subject
        and depth.
    """
    path = os.path.join(raw_dir, "forces.csv")
    if not os.path.isfile(path):
        return None
    shown = "/".join([(raw_dir_shown or raw_dir).rstrip("/"), "forces.csv"])
    with collecting(problems) as found:
        forces = read_table(path, schema, shown, found)
        if forces is None:
            return None
        known = set(subjects["subject"])
        id_rule = schema.get("properties", {}).get("subject", {}).get("pattern", "")
        if force_max_N is None:
            force_max_N = plausibility_defaults()["force_max_N"]
        for line, force in zip(forces.index, forces["force_N"], strict=True):
            if force == force and force > force_max_N:
                found.error(shown, line, "force_N", _force_message(force, force_max_N))
        seen = {}
        for line, subject, depth_mm in zip(
            forces.index, forces["subject"], forces["depth_mm"], strict=True
        ):
            if not re.search(id_rule, subject) or depth_mm != depth_mm:
                continue  # a cell the schema refused: reported already
            if subject not in known:
                found.error(
                    shown,
                    line,
                    "subject",
                    f"subject {subject!r} is not in subjects.csv; expected a listed subject",
                )
                continue
            profile_depths = depths_mm.get(subject, [])
            if subject in unknown_depths:
                pass  # its profile's problem is reported already
            elif not any(abs(depth_mm - d) <= 1e-9 * max(1.0, d) for d in profile_depths):
                listed = ", ".join(f"{d:g}" for d in profile_depths)
                found.error(
                    shown,
                    line,
                    "depth_mm",
                    f"no profile of subject {subject!r} at {depth_mm:g} mm; expected a depth of "
                    f"profiles/{subject}.csv ({listed})",
                )
                continue
            key = trial_key(subject, depth_mm)
            if key in seen:
                found.error(
                    shown,
                    line,
                    ["subject", "depth_mm"],
                    f"a second force for {subject!r} at {depth_mm:g} mm (the first is on line "
                    f"{seen[key]}); expected one force per subject and depth",
                )
            seen.setdefault(key, line)
    return forces


def _force_message(force_N, force_max_N):
    """What a force above the plausible limit is likely to be."""
    text = (
        f"expected a force of at most {force_max_N:g} N (config input_checks: force_max_N), "
        f"got {force_N:g}; "
    )
    if force_N / 1000 <= force_max_N:
        return text + f"it looks like millinewtons ({force_N:g} mN = {force_N / 1000:g} N)"
    return text + "force_N is in newtons"


def read_forces(path):
    """Read a checked ``forces.csv`` as ``subject``, ``depth_mm``, ``force_N``.

    Parameters
    ----------
    path : str or os.PathLike
        A file that passed :func:`check_forces`.

    Returns
    -------
    pandas.DataFrame
        The three columns (any others dropped), in file order, default index.
    """
    from lineload.io import load_schema

    table = read_table(path, load_schema("forces"))
    return table[["subject", "depth_mm", "force_N"]].reset_index(drop=True)


def _forces_schema():
    """The row schema of ``forces.csv`` (for callers that pass no ``forces`` schema)."""
    from lineload.io import load_schema

    return load_schema("forces")
