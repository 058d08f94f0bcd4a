"""The one list of the model families: what each curve is, how it is fitted and named.

One :class:`Family` per model the workflow fits, keyed as in the tables (the column
prefix of its parameters and the ``model`` cells).  An entry names the curve of the
ground floor (:mod:`lineload.models`, :mod:`lineload.bending`) and what the curve
takes after the distance, the fitted parameters with their units, the solver that
fits many trials at once (for the families of the batch engine,
:mod:`lineload.fitting.batch`), the fit table's columns it owns, and how figures draw
it.  Everything that chooses a curve, a solver or a column by the model's name reads
it here (:func:`family`, :func:`curve_mm`); ``docs/adding-a-model.md`` shows how a
family is added.

The entries are checked when this module is imported (:func:`checked`): a family
without a callable curve, without parameters, or whose curve's arguments name a
parameter it does not have, is refused there, not when a figure first draws it.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from lineload import models
from lineload.bending import bending_deflection_mm
from lineload.fitting.arc import fit_arc_chunk
from lineload.fitting.bending import fit_bending
from lineload.fitting.boussinesq import fit_boussinesq_chunk
from lineload.fitting.free_depth import fit_free_depth_chunk
from lineload.fitting.shifted import fit_shifted_chunk
from lineload.fitting.waterbed import fit_waterbed_chunk

__all__ = [
    "DEPTH",
    "FAMILIES",
    "Family",
    "Parameter",
    "checked",
    "curve_mm",
    "evaluate",
    "family",
    "solved_families",
    "table_families",
]

#: In :attr:`Family.arguments`: the trial's indentation depth, held as W0.
DEPTH = "depth"


@dataclass(frozen=True)
class Parameter:
    """One fitted parameter of a family.

    Attributes
    ----------
    name : str
        Its key in ``FitResult.params`` (units in the name, ``L_mm``).
    unit : str
        Its unit (``mm``; empty for a pure number).
    meaning : str
        What it is, in a few words.
    """

    name: str
    unit: str
    meaning: str


@dataclass(frozen=True)
class Family:
    """One model family.

    Attributes
    ----------
    name : str
        Key in the tables: the column prefix (``waterbed_L_mm``) and ``model`` cells.
    curve : callable
        ``curve(distance_mm, *arguments, **settings)``: downward deflection (mm).
    arguments : tuple of str
        What the curve takes after the distance, in order: :data:`DEPTH` (the
        trial's depth, W0 held) or the name of one of ``parameters``.
    parameters : tuple of Parameter
        The fitted parameters, the first the one whose variance ``prior_share``
        describes.
    solver : callable or None
        ``solver(trials, depth_mm)`` fitting a chunk of padded trials at once
        (:class:`lineload.fitting.windows._Trials`), returning a
        :class:`lineload.fitting.goodness._ChunkFit`; None for a family fitted by
        its own function (``fit``) outside the batch engine.
    results : tuple of str
        The solver's parameters with their interval ends, in ``FitResult.params``
        order (the columns of ``BatchFits.params``).
    min_points : int
        Fewest points a fit needs.
    table_columns : tuple of str
        Its columns in the fit table (:data:`lineload.fitting.batch.FIT_COLUMNS`),
        without the prefix, in order; empty for a family the table leaves out.
    fit : callable or None
        For a family outside the batch engine, the function fitting one trial.
    settings : tuple of (str, object)
        Keyword arguments of the curve read from a table row's column of that
        name, with the value used when the row has none (the bending skin's wall).
    colour, linestyle : str or None
        How figures draw it (Okabe-Ito palette); None for a family no figure draws.
    """

    name: str
    curve: Callable
    arguments: tuple[str, ...]
    parameters: tuple[Parameter, ...]
    solver: Callable | None = None
    results: tuple[str, ...] = ()
    min_points: int = 1
    table_columns: tuple[str, ...] = ()
    fit: Callable | None = None
    settings: tuple[tuple[str, object], ...] = ()
    colour: str | None = None
    linestyle: str | object | None = None
    notes: str = field(default="", repr=False)

    @property
    def n_params(self):
        """Number of free parameters (the noise variance not included)."""
        return len(self.parameters)

    @property
    def needs_depth(self):
        """Whether the curve holds W0 at the trial's depth."""
        return DEPTH in self.arguments

    def column(self, name):
        """Column of one of its values in a table: ``<family>_<name>``, or the name
        itself when it already starts with the family's (``bending_length_mm``)."""
        return name if name.startswith(f"{self.name}_") else f"{self.name}_{name}"


def checked(entry):
    """The family, if its entry is complete.

    Raises
    ------
    ValueError
        If the curve is not callable, there are no parameters, an argument is
        neither :data:`DEPTH` nor a parameter, a parameter is not an argument, the
        curve does not take ``distance_mm`` first, or a family of the fit table has
        no solver.
    """
    where = f"model family {entry.name!r}"
    if not callable(entry.curve):
        raise ValueError(f"{where}: its curve must be a function, got {entry.curve!r}")
    if not entry.parameters:
        raise ValueError(f"{where}: it names no fitted parameter")
    names = [p.name for p in entry.parameters]
    unknown = [a for a in entry.arguments if a != DEPTH and a not in names]
    if unknown:
        raise ValueError(f"{where}: the curve's arguments {unknown} are not its parameters")
    unused = [n for n in names if n not in entry.arguments]
    if unused:
        raise ValueError(f"{where}: the parameters {unused} are not arguments of its curve")
    taken = list(inspect.signature(entry.curve).parameters)
    if not taken or taken[0] != "distance_mm" or len(taken) <= len(entry.arguments):
        raise ValueError(
            f"{where}: its curve must take distance_mm and then {len(entry.arguments)} values"
        )
    if entry.table_columns and entry.solver is None:
        raise ValueError(f"{where}: a family of the fit table needs a solver")
    if entry.solver is None and entry.fit is None:
        raise ValueError(f"{where}: it needs a solver or a fit function")
    return entry


_L = Parameter("L_mm", "mm", "half-width of the membrane, load to wall")
_L_RESULTS = ("L_mm", "L_ci_low_mm", "L_ci_high_mm")
_MEASURE_COLUMNS = ("rmse_mm", "max_abs_residual_mm", "aicc")
#: The fit table's columns of a family fitting L with W0 held (followed across windows).
_L_COLUMNS = (
    "L_mm",
    "L_ci_low_mm",
    "L_ci_high_mm",
    "L_at_bound",
    "L_prior_share",
    "L_window_min_mm",
    "L_window_max_mm",
    *_MEASURE_COLUMNS,
)


#: Every model family, in the order of the sensitivity refits and of the fit table.
FAMILIES = {
    entry.name: checked(entry)
    for entry in (
        Family(
            name="waterbed",
            curve=models.waterbed_deflection_mm,
            arguments=(DEPTH, "L_mm"),
            parameters=(_L,),
            solver=fit_waterbed_chunk,
            results=_L_RESULTS,
            table_columns=_L_COLUMNS,
            colour="#0072B2",
            linestyle="-",
            notes="the paper's parabola (eq. 19) read at the measured position",
        ),
        Family(
            name="waterbed_free_depth",
            curve=models.waterbed_deflection_mm,
            arguments=("W0_mm", "L_mm"),
            parameters=(_L, Parameter("W0_mm", "mm", "deflection under the load, fitted")),
            solver=fit_free_depth_chunk,
            results=(*_L_RESULTS, "W0_mm"),
            min_points=2,
            colour="#56B4E9",
            notes="the parabola with W0 free: a sensitivity refit only",
        ),
        Family(
            name="shifted",
            curve=models.shifted_deflection_mm,
            arguments=(DEPTH, "L_mm"),
            parameters=(_L,),
            solver=fit_shifted_chunk,
            results=_L_RESULTS,
            table_columns=_L_COLUMNS,
            colour="#CC79A7",
            linestyle="-.",
            notes="eq. 19 placed at the deformed position x = X + U(X) (eqs 19-20)",
        ),
        Family(
            name="arc",
            curve=models.arc_deflection_mm,
            arguments=(DEPTH, "L_mm"),
            parameters=(_L,),
            solver=fit_arc_chunk,
            results=_L_RESULTS,
            table_columns=_L_COLUMNS,
            colour="#009E73",
            linestyle="--",
            notes="the exact finite-deformation waterbed, a zero-area circular arc",
        ),
        Family(
            name="boussinesq",
            curve=models.boussinesq_deflection_mm,
            arguments=("A_mm", "x0_mm"),
            parameters=(
                Parameter("A_mm", "mm", "drop in deflection per unit of ln distance"),
                Parameter("x0_mm", "mm", "distance at which the deflection is zero"),
            ),
            solver=fit_boussinesq_chunk,
            results=(
                "A_mm",
                "x0_mm",
                "A_ci_low_mm",
                "A_ci_high_mm",
                "x0_ci_low_mm",
                "x0_ci_high_mm",
            ),
            min_points=2,
            table_columns=(
                "A_mm",
                "x0_mm",
                "A_ci_low_mm",
                "A_ci_high_mm",
                "A_prior_share",
                "A_wedge_share",
                "x0_ci_low_mm",
                "x0_ci_high_mm",
                *_MEASURE_COLUMNS,
            ),
            colour="#D55E00",
            linestyle="-",
            notes="the modified Boussinesq (Flamant) half-space",
        ),
        Family(
            name="bending",
            curve=bending_deflection_mm,
            arguments=(DEPTH, "L_mm", "bending_length_mm"),
            parameters=(
                _L,
                Parameter("bending_length_mm", "mm", "sqrt(D / N), where the skin turns"),
            ),
            fit=fit_bending,
            min_points=4,
            settings=(("wall", "clamped"),),
            colour="#E69F00",
            linestyle=(0, (4, 1.5)),
            notes="tension with bending stiffness; its own table (bending.csv)",
        ),
    )
}


def family(name):
    """The registry's entry of a model family.

    Raises
    ------
    KeyError
        Naming the families there are, for a name that is not one of them.
    """
    try:
        return FAMILIES[name]
    except KeyError:
        raise KeyError(f"no model family {name!r}; there are {', '.join(FAMILIES)}") from None


def solved_families():
    """Names of the families the batch engine fits (those with a solver), in order."""
    return tuple(name for name, entry in FAMILIES.items() if entry.solver is not None)


def table_families():
    """Names of the families of the fit table (those with columns there), in order."""
    return tuple(name for name, entry in FAMILIES.items() if entry.table_columns)


def evaluate(name, distance_mm, depth_mm, params, **settings):
    """Deflection of a family at given parameters.

    Parameters
    ----------
    name : str
        The family (a key of :data:`FAMILIES`).
    distance_mm : array_like
        Distances from the wedge (mm).
    depth_mm : float
        The indentation depth (mm), W0 of the families that hold it.
    params : mapping
        Each of the family's parameters by its name (``{"L_mm": 11.0}``).
    **settings
        The curve's settings (:attr:`Family.settings`); their defaults otherwise.

    Returns
    -------
    numpy.ndarray
        Deflection (mm, downward positive).
    """
    entry = family(name)
    arguments = [depth_mm if a == DEPTH else params[a] for a in entry.arguments]
    return entry.curve(distance_mm, *arguments, **(dict(entry.settings) | settings))


def curve_mm(name, distance_mm, depth_mm, row):
    """Deflection of a fitted family at the given distances, its parameters read from a row.

    Parameters
    ----------
    name : str
        The family (a key of :data:`FAMILIES`).
    distance_mm : array_like
        Distances from the wedge (mm).
    depth_mm : float
        The trial's indentation depth (mm), W0 of the families that hold it.
    row : mapping or pandas.Series or None
        A table row with the family's columns (:meth:`Family.column`) and, where it
        has them, the curve's settings (:attr:`Family.settings`).

    Returns
    -------
    numpy.ndarray or None
        Deflection (mm, downward positive); None without a row or when a parameter
        in it is missing or not finite.
    """
    entry = family(name)
    if row is None:
        return None
    params = {}
    for parameter in entry.parameters:
        column = entry.column(parameter.name)
        value = row[column] if column in row else None
        if value is None or not np.isfinite(float(value)):
            return None
        params[parameter.name] = float(value)
    settings = {key: type(default)(row[key]) for key, default in entry.settings if key in row}
    return evaluate(name, distance_mm, depth_mm, params, **settings)
