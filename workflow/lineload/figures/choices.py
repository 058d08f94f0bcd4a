"""Which subjects and depths Figures 1 and 2 show: as configured, else chosen from the data.

The paper shows one monkey and one human, at 1 mm depth in Figure 2.  A lab's
dataset need not have that depth, nor those subjects, so an unset choice
(``figures: example_subjects: []``, ``example_depth_mm: null`` and the
``outline_*`` keys) is made here from what was measured, and said in words for
the figure job's log and, when it departs from the paper, in the figure.

The figure jobs and the article job make these choices (:func:`figure_settings`)
from the depths the raw-data check found; this module imports only the standard
library.  A choice the data cannot satisfy raises a :class:`ChoiceError` whose
message names the config key.
"""

from __future__ import annotations

from dataclasses import dataclass

from lineload.paper import EXAMPLE_DEPTH_MM, SPECIES

__all__ = [
    "CHOICE_KEYS",
    "Choice",
    "ChoiceError",
    "example_choice",
    "figure_settings",
    "nearest_depth",
    "outline_choice",
]

#: The ``figures:`` config keys that name what Figures 1 and 2 show (unset: chosen here).
CHOICE_KEYS = ("example_subjects", "example_depth_mm", "outline_subjects", "outline_depth_mm")


class ChoiceError(ValueError):
    """A configured figure choice that the data cannot satisfy (message names the key)."""


@dataclass(frozen=True)
class Choice:
    """Subjects and depth of a figure, and how they were chosen.

    Attributes
    ----------
    subjects : list of str
        One panel each, in order; empty when the data have none to show.
    depth_mm : float or None
        The depth shown; None when there is nothing to show.
    log : str
        One line for the figure job's log: what was chosen and why.
    note : str
        A sentence for the figure itself when the depth is not the paper's
        (empty otherwise).
    """

    subjects: list
    depth_mm: float | None
    log: str
    note: str = ""


def _mm(values):
    return ", ".join(f"{v:g}" for v in sorted(values))


def nearest_depth(depths_mm, target_mm=EXAMPLE_DEPTH_MM):
    """The depth nearest a target (mm); of two equally near, the deeper one.

    Parameters
    ----------
    depths_mm : iterable of float
    target_mm : float, optional

    Returns
    -------
    float or None
        None when there are no depths.
    """
    depths_mm = sorted({float(d) for d in depths_mm})
    if not depths_mm:
        return None
    return min(depths_mm, key=lambda d: (round(abs(d - target_mm), 9), -d))


def _first_of_each_species(candidates, species_of):
    """The first subject of each species among candidates, in the order of species_of."""
    chosen = {}
    for subject, species in species_of.items():
        if subject in candidates:
            chosen.setdefault(species, subject)
    return [chosen[s] for s in sorted(chosen, key=_species_order)]


def _species_order(species):
    return SPECIES.index(species) if species in SPECIES else len(SPECIES)


def _species_words(subjects, species_of):
    kinds = [species_of[s] for s in subjects]
    return " and ".join(f"the first {k}" for k in kinds)


def example_choice(species_of, depths_mm, subjects=(), depth_mm=None, paper_mm=EXAMPLE_DEPTH_MM):
    """Figure 2: the subjects and the depth shown.

    Parameters
    ----------
    species_of : dict of str to str
        Subject id -> species, in subject-sheet order.
    depths_mm : dict of str to list of float
        Depths measured per subject.
    subjects : sequence of str, optional
        ``figures: example_subjects``; empty: chosen here.
    depth_mm : float or None, optional
        ``figures: example_depth_mm``; None: chosen here.
    paper_mm : float, optional
        The paper's depth (1 mm).

    Returns
    -------
    Choice
        Unset subjects are the first subject of each species with a profile at
        the depth.  An unset depth is the measured depth nearest the paper's
        (ties: the deeper) among those that give a panel to as many species
        as any depth does; with subjects set, among the depths they all have.

    Raises
    ------
    ChoiceError
        A named subject not in the sheet or without a profile at a set depth,
        or named subjects that share no depth.
    """
    key = "config, key 'figures/example_subjects'"
    for subject in subjects:
        if subject not in species_of:
            raise ChoiceError(f"{key}: subject {subject!r} is not in subjects.csv")
    if subjects and depth_mm is not None:
        for subject in subjects:
            if depth_mm not in depths_mm.get(subject, ()):
                raise ChoiceError(
                    f"{key}: subject {subject!r} has no profile at {depth_mm:g} mm "
                    f"(figures/example_depth_mm); its depths: {_mm(depths_mm[subject])}"
                )
        how = "as set in the config"
        return Choice(
            list(subjects),
            depth_mm,
            f"figure2: {', '.join(subjects)} at {depth_mm:g} mm, both {how}",
            _set_note(depth_mm, paper_mm),
        )
    if subjects:
        common = set.intersection(*(set(depths_mm.get(s, ())) for s in subjects))
        if not common:
            raise ChoiceError(
                f"{key}: {', '.join(subjects)} share no depth; set figures/example_depth_mm "
                "to a depth of each, or name other subjects"
            )
        chosen = nearest_depth(common, paper_mm)
        return Choice(
            list(subjects),
            chosen,
            f"figure2: {', '.join(subjects)} as set in the config, at {chosen:g} mm: the depth "
            f"nearest the paper's {paper_mm:g} mm that they all have ({_mm(common)})",
            _chosen_note(chosen, paper_mm),
        )
    if depth_mm is not None:
        chosen_subjects = _first_of_each_species(
            [s for s in species_of if depth_mm in depths_mm.get(s, ())], species_of
        )
        if not chosen_subjects:
            return Choice(
                [],
                depth_mm,
                f"figure2: no subject has a profile at {depth_mm:g} mm (set in the config)",
            )
        return Choice(
            chosen_subjects,
            depth_mm,
            f"figure2: {', '.join(chosen_subjects)} "
            f"({_species_words(chosen_subjects, species_of)} of subjects.csv with a profile "
            f"at that depth) at {depth_mm:g} mm, as set in the config",
            _set_note(depth_mm, paper_mm),
        )
    measured = {d for s in species_of for d in depths_mm.get(s, ())}
    if not measured:
        return Choice([], None, "figure2: no profiles in this dataset")

    def covered(depth):
        return len({species_of[s] for s in species_of if depth in depths_mm.get(s, ())})

    most = max(covered(d) for d in measured)
    chosen = nearest_depth([d for d in measured if covered(d) == most], paper_mm)
    chosen_subjects = _first_of_each_species(
        [s for s in species_of if chosen in depths_mm.get(s, ())], species_of
    )
    return Choice(
        chosen_subjects,
        chosen,
        f"figure2: {', '.join(chosen_subjects)} ({_species_words(chosen_subjects, species_of)} "
        f"of subjects.csv with a profile at that depth) at {chosen:g} mm: the measured depth "
        f"nearest the paper's {paper_mm:g} mm (measured: {_mm(measured)})",
        _chosen_note(chosen, paper_mm),
    )


def _chosen_note(depth_mm, paper_mm):
    if depth_mm == paper_mm:
        return ""
    return (
        f"Shown at {depth_mm:g} mm, the measured depth nearest the paper's {paper_mm:g} mm "
        "(figures: example_depth_mm sets another)."
    )


def _set_note(depth_mm, paper_mm):
    if depth_mm == paper_mm:
        return ""
    return (
        f"Shown at {depth_mm:g} mm as set in the config (figures: example_depth_mm); "
        f"the paper shows {paper_mm:g} mm."
    )


def outline_choice(species_of, outlines_mm, subjects=(), depth_mm=None):
    """Figure 1: the subjects whose outlines are drawn, and the depth.

    Parameters
    ----------
    species_of : dict of str to str
        Subject id -> species, in subject-sheet order.
    outlines_mm : dict of str to list of float
        Depths outlined per subject that has an outline file.
    subjects : sequence of str, optional
        ``figures: outline_subjects``; empty: the first subject of each
        species with an outline file.
    depth_mm : float or None, optional
        ``figures: outline_depth_mm``; None: the smallest depth outlined for
        every chosen subject.

    Returns
    -------
    Choice
        With no subjects (and depth None) when the data hold no outlines.

    Raises
    ------
    ChoiceError
        A named subject without an outline file, or a depth not outlined for
        every chosen subject (or none shared).
    """
    for subject in subjects:
        if subject not in outlines_mm:
            raise ChoiceError(
                f"config, key 'figures/outline_subjects': subject {subject!r} has no outline "
                "file (outlines/<subject>.csv)"
            )
    how = "as set in the config"
    chosen = list(subjects)
    if not chosen:
        chosen = _first_of_each_species(list(outlines_mm), species_of)
        how = f"{_species_words(chosen, species_of)} of subjects.csv with an outline file"
    if not chosen:
        return Choice([], None, "figure1: no outline files in this dataset")
    common = set.intersection(*(set(outlines_mm[s]) for s in chosen))
    if depth_mm is None and common:
        depth = min(common)
        depth_how = "the smallest depth outlined for each"
    else:
        depth, depth_how = depth_mm, "as set in the config"
    if depth not in common:
        raise ChoiceError(
            "config, key 'figures/outline_depth_mm': expected a depth outlined for "
            f"{', '.join(chosen)} ({_mm(common)}), got {depth}"
        )
    return Choice(
        chosen, depth, f"figure1: {', '.join(chosen)} ({how}) at {depth:g} mm ({depth_how})"
    )


def figure_settings(species_of, depths_mm, outlines_mm, configured):
    """The subjects and depths of Figures 1 and 2 as figure settings, and why.

    Parameters
    ----------
    species_of : dict of str to str
        Subject id -> species, in subject-sheet order.
    depths_mm : dict of str to list of float
        Depths measured per subject (the raw-data check's ``depths_mm``).
    outlines_mm : dict of str to list of float
        Depths outlined per subject with an outline file (its ``outlines_mm``).
    configured : dict
        The config's ``figures`` keys of :data:`CHOICE_KEYS` (unset: ``[]``
        or None).

    Returns
    -------
    settings : dict
        ``example_subjects``, ``example_depth_mm``, ``example_note``,
        ``outline_subjects``, ``outline_depth_mm`` (the figure functions'
        arguments of these names).
    logs : dict of str to list of str
        Per figure group (``outlines``, ``fits``), what was chosen and why.

    Raises
    ------
    ChoiceError
        As :func:`outline_choice` and :func:`example_choice`.
    """
    outline = outline_choice(
        species_of, outlines_mm, configured["outline_subjects"], configured["outline_depth_mm"]
    )
    example = example_choice(
        species_of, depths_mm, configured["example_subjects"], configured["example_depth_mm"]
    )
    settings = {
        "example_subjects": example.subjects,
        "example_depth_mm": example.depth_mm,
        "example_note": example.note,
        "outline_subjects": outline.subjects,
        "outline_depth_mm": outline.depth_mm,
    }
    return settings, {"outlines": [outline.log], "fits": [example.log]}
