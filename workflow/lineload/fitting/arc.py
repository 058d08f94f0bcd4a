"""The exact waterbed: the zero-area circular arc with W0 held at the depth, L searched."""

from __future__ import annotations

from lineload.fitting.search import _fit_curve_chunk, _in_blocks
from lineload.models import arc_deflection_mm, arc_geometry

__all__ = ["fit_arc_chunk"]


def _arc_objective(trials, depth_mm):
    """:func:`_curve_objective` of the arc, its circle solved once per (W0, L)."""

    def objective(L_mm, rows):
        geometry = arc_geometry(depth_mm[rows, None], L_mm)

        def evaluate(part):
            r = rows[part]
            model = arc_deflection_mm(
                trials.x[r, None, :],
                depth_mm[r, None, None],
                L_mm[part, :, None],
                geometry={name: values[part, :, None] for name, values in geometry.items()},
            )
            return trials.chi2(trials.y[r, None, :] - model, r)

        return _in_blocks(evaluate, rows.size, L_mm.shape[1], trials.width)

    return objective


def fit_arc_chunk(trials, depth_mm):
    """The exact arc fitted to a chunk of trials, ``W0 = depth_mm``, L searched from ``max(x)``."""
    objective = _arc_objective(trials, depth_mm)
    return _fit_curve_chunk("arc", arc_deflection_mm, objective, trials, depth_mm, trials.x_max)
