"""The elastic fingertip fitted by interpolation in its solution library.

The finite-element finger (:mod:`lineload.elastic`) is too slow to solve inside a fit, so each
trial is fitted against the library (:mod:`lineload.elastic.library`): for the trial's species
and depth, profiles over sections (the geometry, drawn jointly from its stated ranges),
outer-layer thicknesses and modulus ratios. Two fits per trial, on the same points as the
paper's models (``0 < distance <= window``), least squares, as the paper reads its curves:

``homogeneous``
    modulus ratio 1; the section is the nuisance: the best of the library's sections.
``layered``
    the ratio free in [1, the library's largest]; the section and the layer's thickness are
    nuisances, the best of the library's for each ratio (a profile likelihood in the ratio).

Neither has an amplitude or a scale to fit: the wedge is driven by its depth and a profile's
shape does not depend on the modulus. The deflection between the library's ratios is a cubic
spline in ``ln ratio`` (evaluated once per block on a grid :data:`RATIO_REFINEMENT` times
finer), between its distances linear in ``ln x``, where a logarithmic profile is a straight
line.

Parameters counted for AICc: the section counts as one parameter (it moves the profile's far
reach, as the Boussinesq form's ``x0`` does), the ratio and the layer's thickness as one each:
1 for the homogeneous fit, 3 for the layered one. The nuisance is a discrete choice, not a
continuous parameter, so this count is a convention, stated where the table is described.

Interval of the ratio: the profile-likelihood interval, the ratios whose best sum of squares
(over sections and thicknesses) stays under a threshold above the minimum, as the bending
fit's. Without a covariance of the points the threshold is ``n ln(SSE / SSE_min) <= chi2``
(errors independent, of unknown variance). With one (``covariance_mm2``, the trial's noise
model, measured apart from the fit) it is the sandwich's: with ``J`` the curve's derivative in
``ln ratio`` at the estimate (the nuisances held), the estimate's variance is
``J'CJ / (J'J)^2`` and the sum of squares may rise by ``chi2 J'CJ / J'J``. ``chi2`` is the
95 % point of chi-square with one degree of freedom. An interval that reaches an end of the
library's ratios is flagged and runs to that end.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lineload.elastic.table import DEFLECTION_PREFIX, grid_distances_mm
from lineload.fitting.goodness import goodness_of_fit
from lineload.fitting.optimize import CHI2_1DOF_95
from lineload.fitting.windows import in_fit_window, window_covariance

__all__ = [
    "ELASTIC_COLUMNS",
    "LibraryBlock",
    "fit_elastic",
    "fit_elastic_trials",
    "fitted_curve_mm",
    "library_blocks",
    "with_elastic",
]

#: The fine grid in ``ln ratio`` has this many steps per step of the library's.
RATIO_REFINEMENT = 16
#: Depths of a trial and of the library are the same depth within this (mm).
DEPTH_TOLERANCE_MM = 1e-6
#: Parameters counted for AICc (see the module's notes).
N_PARAMS = {"homogeneous": 1, "layered": 3}


@dataclass(frozen=True)
class LibraryBlock:
    """The library's profiles of one species at one depth, on a fine grid of ratios.

    Attributes
    ----------
    species : str
    depth_mm : float
    log_distance : numpy.ndarray
        ``ln`` of the library's distances (mm), increasing, shape (X,).
    ratios : numpy.ndarray
        The fine grid of modulus ratios, shape (R,), the first 1.
    thicknesses_mm : numpy.ndarray
        The outer layer's thicknesses, shape (T,).
    sections : numpy.ndarray
        The sections' indices in the library, shape (G,).
    deflection_mm : numpy.ndarray
        Shape (G, T, R, X).
    force_per_modulus_mm : numpy.ndarray
        Force per unit length per unit pulp modulus (mm), shape (G, T, R).
    by_distance : numpy.ndarray
        The deflections with the distance first, shape (X, G * T * R), C-contiguous: a
        trial's distances gather whole rows, which is what makes a fit take about a
        millisecond.
    """

    species: str
    depth_mm: float
    log_distance: np.ndarray
    ratios: np.ndarray
    thicknesses_mm: np.ndarray
    sections: np.ndarray
    deflection_mm: np.ndarray
    force_per_modulus_mm: np.ndarray
    by_distance: np.ndarray

    @property
    def reach_mm(self):
        """The library's nearest and farthest distances (mm)."""
        return float(np.exp(self.log_distance[0])), float(np.exp(self.log_distance[-1]))

    def _rows_at(self, distance_mm):
        """Every profile at the given distances, shape (n, G * T * R): linear in ln x."""
        log_x = np.log(np.asarray(distance_mm, dtype=float))
        i = np.clip(np.searchsorted(self.log_distance, log_x) - 1, 0, self.log_distance.size - 2)
        left, right = self.log_distance[i], self.log_distance[i + 1]
        weight = ((log_x - left) / (right - left))[:, None]
        return self.by_distance[i] * (1 - weight) + self.by_distance[i + 1] * weight

    def curves_at(self, distance_mm):
        """Every profile of the block at the given distances (mm), shape (G, T, R, n)."""
        rows = self._rows_at(distance_mm)
        return np.moveaxis(rows.reshape(-1, *self.deflection_mm.shape[:3]), 0, -1)


def _fine_ratios(ratios):
    log_r = np.log(ratios)
    steps = (ratios.size - 1) * RATIO_REFINEMENT + 1
    return np.exp(np.linspace(log_r[0], log_r[-1], steps))


def library_blocks(table):
    """The library's blocks by species and depth.

    Parameters
    ----------
    table : pandas.DataFrame
        The library (:func:`lineload.elastic.library.library_columns`): every section,
        thickness and ratio at every depth of a species.

    Returns
    -------
    dict of (str, float) to LibraryBlock

    Raises
    ------
    ValueError
        When a species' rows do not form a full grid, or the ratios do not start at 1.
    """
    from scipy.interpolate import CubicSpline  # here: the fit table's job imports this

    distance_mm = grid_distances_mm(table.columns)
    columns = [c for c in table.columns if c.startswith(DEFLECTION_PREFIX)]
    blocks = {}
    for (species, depth_mm), rows in table.groupby(["species", "depth_mm"], sort=True):
        rows = rows.sort_values(["section", "layer_thickness_mm", "modulus_ratio"])
        sections = np.unique(rows["section"].to_numpy())
        thicknesses = np.unique(rows["layer_thickness_mm"].to_numpy(dtype=float))
        ratios = np.unique(rows["modulus_ratio"].to_numpy(dtype=float))
        shape = (sections.size, thicknesses.size, ratios.size)
        if len(rows) != np.prod(shape):
            raise ValueError(
                f"the library's {species} rows at {depth_mm} mm are not a full grid: "
                f"{len(rows)} rows for {shape[0]} sections x {shape[1]} thicknesses x "
                f"{shape[2]} ratios"
            )
        if not np.isclose(ratios[0], 1.0) or ratios.size < 4:
            raise ValueError(
                f"the library's {species} ratios must start at 1 (homogeneous) and number "
                f"at least 4 for a cubic spline, not {ratios.tolist()}"
            )
        values = rows[columns].to_numpy(dtype=float).reshape(*shape, distance_mm.size)
        force = rows["force_per_length_per_pulp_modulus_mm"].to_numpy(dtype=float).reshape(shape)
        fine = _fine_ratios(ratios)
        log_r, log_fine = np.log(ratios), np.log(fine)
        deflection_mm = CubicSpline(log_r, values, axis=2)(log_fine)
        blocks[(str(species), float(depth_mm))] = LibraryBlock(
            species=str(species),
            depth_mm=float(depth_mm),
            log_distance=np.log(distance_mm),
            ratios=fine,
            thicknesses_mm=thicknesses,
            sections=sections,
            deflection_mm=deflection_mm,
            force_per_modulus_mm=CubicSpline(log_r, force, axis=2)(log_fine),
            by_distance=np.ascontiguousarray(
                np.moveaxis(deflection_mm, -1, 0).reshape(distance_mm.size, -1)
            ),
        )
    return blocks


def find_block(blocks, species, depth_mm):
    """The block of a species at a depth, or None where the library has no such depth."""
    for (name, depth), block in blocks.items():
        if name == species and abs(depth - depth_mm) <= DEPTH_TOLERANCE_MM:
            return block
    return None


def fitted_curve_mm(block, distance_mm, section, thickness_mm, ratio):
    """A fitted finger's deflection (mm) at the given distances, from the library.

    Parameters
    ----------
    block : LibraryBlock
        The library's profiles of the trial's species and depth.
    distance_mm : array_like
        Distances inside the block's reach (mm).
    section : int
        The section's index in the library (``*_section`` of the fit table).
    thickness_mm : float
        The outer layer's thickness (mm; any of the block's for a homogeneous finger).
    ratio : float
        The modulus ratio, within the block's (1 for a homogeneous finger); between the fine
        grid's ratios the deflection is linear in ``ln ratio``.

    Returns
    -------
    numpy.ndarray
    """
    curves = block.curves_at(distance_mm)
    g = int(np.flatnonzero(block.sections == section)[0])
    t = int(np.argmin(np.abs(block.thicknesses_mm - thickness_mm)))
    log_r = np.log(block.ratios)
    position = np.interp(np.log(ratio), log_r, np.arange(log_r.size))
    k = min(int(position), log_r.size - 2)
    weight = position - k
    return curves[g, t, k] * (1 - weight) + curves[g, t, k + 1] * weight


def _interval(ratios, profile_sse, limit):
    """Ends of the ratios whose profile stays under the limit (linear crossings; the hull, should
    the profile dip under it more than once), and whether each end is the library's."""
    inside = np.flatnonzero(profile_sse <= limit)
    low_i, high_i = inside[0], inside[-1]
    log_r = np.log(ratios)

    def crossing(i_in, i_out):
        f_in, f_out = profile_sse[i_in] - limit, profile_sse[i_out] - limit
        t = f_in / (f_in - f_out)
        return float(np.exp(log_r[i_in] + t * (log_r[i_out] - log_r[i_in])))

    low = ratios[0] if low_i == 0 else crossing(low_i, low_i - 1)
    high = ratios[-1] if high_i == ratios.size - 1 else crossing(high_i, high_i + 1)
    return float(low), float(high), low_i == 0, high_i == ratios.size - 1


def _rise_allowed(curves, g, t, k, profile_min, n, log_step, covariance_mm2):
    """How far above its minimum the profile's sum of squares may rise inside the interval."""
    if covariance_mm2 is None:
        return profile_min * np.expm1(CHI2_1DOF_95 / n)
    last = curves.shape[2] - 1
    up, down = min(k + 1, last), max(k - 1, 0)
    slope = (curves[g, t, up] - curves[g, t, down]) / ((up - down) * log_step)
    norm = float(slope @ slope)
    if norm == 0.0:
        return np.inf
    return CHI2_1DOF_95 * float(slope @ np.asarray(covariance_mm2) @ slope) / norm


def fit_elastic(distance_mm, deflection_mm, block, covariance_mm2=None):
    """Fit the homogeneous and the layered finger to one trial's averaged profile.

    Parameters
    ----------
    distance_mm, deflection_mm : array_like
        The trial's points to fit (mm), distances inside the block's reach.
    block : LibraryBlock
        The library's profiles of the trial's species and depth.
    covariance_mm2 : array_like, optional
        Covariance of the deflections (mm^2), measured apart from the fit: the ratio's
        interval honours it (the fit itself stays least squares).

    Returns
    -------
    dict
        ``homogeneous_*`` and ``layered_*`` values: the section (index in the library), the
        layer's thickness (layered), the ratio with its 95 % interval and whether each end is
        the library's, the force per unit length per unit pulp modulus (mm), and the sums of
        squares, RMSE, largest residual and AICc.
    """
    x = np.asarray(distance_mm, dtype=float)
    y = np.asarray(deflection_mm, dtype=float)
    near_mm, far_mm = block.reach_mm
    if x.size == 0 or x.min() < near_mm or x.max() > far_mm:
        raise ValueError(
            f"the points to fit must lie within the library's distances, {near_mm:g} to "
            f"{far_mm:g} mm"
        )
    rows = block._rows_at(x)  # (n, G * T * R)
    shape = block.deflection_mm.shape[:3]
    sse = np.einsum("nm,nm->m", y[:, None] - rows, y[:, None] - rows).reshape(shape)
    curves = np.moveaxis(rows.reshape(-1, *shape), 0, -1)  # (G, T, R, n), a view
    out = {}
    # homogeneous: ratio 1, any thickness (the same solid; the meshes differ only slightly)
    g, t = np.unravel_index(np.argmin(sse[:, :, 0]), sse.shape[:2])
    out.update(_measured("homogeneous", y - curves[g, t, 0], block, g, t, 0))
    # layered: the profile over the nuisances, then the ratio
    nuisance = sse.reshape(-1, sse.shape[2])
    profile = nuisance.min(axis=0)
    k = int(np.argmin(profile))
    g, t = np.unravel_index(int(np.argmin(nuisance[:, k])), sse.shape[:2])
    out.update(_measured("layered", y - curves[g, t, k], block, g, t, k))
    ratio = block.ratios[k]
    if 0 < k < profile.size - 1:
        f0, f1, f2 = profile[k - 1 : k + 2]
        curvature = f0 - 2 * f1 + f2
        if curvature > 0:
            step = np.log(block.ratios[1] / block.ratios[0])
            ratio = block.ratios[k] * np.exp(0.5 * step * (f0 - f2) / curvature)
    log_step = float(np.log(block.ratios[1] / block.ratios[0]))
    rise = _rise_allowed(curves, g, t, k, profile[k], x.size, log_step, covariance_mm2)
    low, high, low_end, high_end = _interval(block.ratios, profile, profile[k] + rise)
    out.update(
        {
            "layered_modulus_ratio": float(ratio),
            "layered_ratio_ci_low": min(low, float(ratio)),
            "layered_ratio_ci_high": max(high, float(ratio)),
            "layered_ratio_at_bound": float(k in (0, profile.size - 1)),
            "layered_ratio_ci_at_bound": float(low_end or high_end),
        }
    )
    return out


def _measured(name, residual_mm, block, g, t, k):
    measures = goodness_of_fit(residual_mm, N_PARAMS[name])
    row = {
        f"{name}_section": int(block.sections[g]),
        f"{name}_force_per_modulus_mm": float(block.force_per_modulus_mm[g, t, k]),
        **{f"{name}_{key}": value for key, value in measures.items()},
    }
    if name == "layered":
        row["layered_layer_thickness_mm"] = float(block.thicknesses_mm[t])
    return row


#: Columns of the elastic fits' table, one row per trial (units in the names; the flags are
#: 1 where the estimate, or an end of its interval, is the library's largest or smallest).
ELASTIC_COLUMNS = [
    "subject",
    "species",
    "depth_mm",
    "fit_window_mm",
    "n_points",
    "elastic_homogeneous_section",
    "elastic_homogeneous_force_per_modulus_mm",
    "elastic_homogeneous_sse_mm2",
    "elastic_homogeneous_rmse_mm",
    "elastic_homogeneous_max_abs_residual_mm",
    "elastic_homogeneous_aicc",
    "elastic_layered_modulus_ratio",
    "elastic_layered_ratio_ci_low",
    "elastic_layered_ratio_ci_high",
    "elastic_layered_ratio_at_bound",
    "elastic_layered_ratio_ci_at_bound",
    "elastic_layered_layer_thickness_mm",
    "elastic_layered_section",
    "elastic_layered_force_per_modulus_mm",
    "elastic_layered_sse_mm2",
    "elastic_layered_rmse_mm",
    "elastic_layered_max_abs_residual_mm",
    "elastic_layered_aicc",
    "elastic_note",
]

#: Fewest points a trial needs: AICc of the layered fit (3 parameters and the variance).
MIN_POINTS = N_PARAMS["layered"] + 3


def fit_elastic_trials(
    distance_mm, deflection_mm, species, depth_mm, window_mm, blocks, noise=None, n_sides=None
):
    """Fit both fingers to many trials, each on its points inside the fit window.

    Parameters
    ----------
    distance_mm, deflection_mm : sequence of array_like
        The averaged profile of each trial (mm).
    species : sequence of str
        Each trial's species.
    depth_mm : sequence of float
        Each trial's indentation depth (mm).
    window_mm : float
        Outer edge of the fitted region (mm), as for every other model.
    blocks : dict
        The library (:func:`library_blocks`).
    noise : sequence of lineload.noise.NoiseModel, optional
        One per trial: the ratio's interval honours each trial's covariance.
    n_sides : sequence of array_like, optional
        Sides read at each point (with ``noise``; 2 where not given).

    Returns
    -------
    list of dict
        One row per trial with the columns of :data:`ELASTIC_COLUMNS` but ``subject`` and
        ``species``; NaN, and a note saying why, where the library has no profiles of the
        trial's species and depth, the window reaches past the library, or too few points.
    """
    rows = []
    trials = zip(distance_mm, deflection_mm, species, depth_mm, strict=True)
    for number, (x, y, name, depth) in enumerate(trials):
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        keep = in_fit_window(x, window_mm) & np.isfinite(y)
        row = {"depth_mm": float(depth), "fit_window_mm": float(window_mm)}
        row["n_points"] = int(keep.sum())
        block = find_block(blocks, name, float(depth))
        note = ""
        if block is None:
            note = f"the library has no {name} profiles at {float(depth):g} mm"
        elif window_mm > block.reach_mm[1]:
            note = f"the fit window reaches past the library's {block.reach_mm[1]:g} mm"
        elif np.any(x[keep] < block.reach_mm[0]):
            note = f"points nearer the wedge than the library's {block.reach_mm[0]:g} mm"
        elif keep.sum() < MIN_POINTS:
            note = f"fewer than {MIN_POINTS} points in the fit window"
        columns = [c for c in ELASTIC_COLUMNS if c.startswith("elastic_") and c != "elastic_note"]
        if note:
            rows.append({**row, **dict.fromkeys(columns, np.nan), "elastic_note": note})
            continue
        covariance = None
        if noise is not None:
            sides = None if n_sides is None else n_sides[number]
            covariance = window_covariance(x, y, depth, window_mm, noise[number], sides)
        fitted = fit_elastic(x[keep], y[keep], block, covariance)
        rows.append(
            {
                **row,
                **{f"elastic_{key}": value for key, value in fitted.items()},
                "elastic_note": "",
            }
        )
    return rows


def with_elastic(fits, elastic):
    """The fit table with the elastic fits' columns beside it, row for row.

    Parameters
    ----------
    fits : pandas.DataFrame
        The fit table (``subject``, ``depth_mm``, ...).
    elastic : pandas.DataFrame
        A table with the ``elastic_*`` columns (:data:`ELASTIC_COLUMNS`) by subject and
        depth: the elastic fits' table, or a fit table that already carries them.

    Returns
    -------
    pandas.DataFrame
        ``fits`` in its order with the ``elastic_*`` columns of the same trial (NaN for a
        trial the elastic table lacks), replacing any it had.
    """
    columns = [c for c in elastic.columns if c.startswith("elastic_")]
    keep = fits.drop(columns=[c for c in columns if c in fits.columns])
    right = elastic[["subject", "depth_mm", *columns]].copy()
    right["_depth"] = np.round(right.pop("depth_mm").to_numpy(dtype=float) / DEPTH_TOLERANCE_MM)
    left = keep.assign(_depth=np.round(keep["depth_mm"].to_numpy(dtype=float) / DEPTH_TOLERANCE_MM))
    merged = left.merge(right, on=["subject", "_depth"], how="left")
    return merged.drop(columns="_depth").set_axis(fits.index)
