"""Columns near the wedge that glare has spoilt: saturated, weaker than the outline's
slope explains (an edge's contrast per row falls as ``1 / sqrt(1 + slope**2)``), or off
the outline traced in towards the tip.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

__all__ = ["GLARE_REACH_MM", "GLARE_SHARE", "TRACE_JUMP_PX"]

#: Within this distance of the tip (mm) a column's edge may be glare's (see
#: :data:`GLARE_SHARE`); glare is a bright spot where the wedge presses.
GLARE_REACH_MM = 1.0


#: A column within :data:`GLARE_REACH_MM` of the tip whose slope-corrected fall
#: (:func:`digitise_pair`) is below this share of the median 1-3 mm from the tip is
#: glare's.  Glare that brightens the skin by a third of the step between background and
#: skin lowers it to about 0.67; a steep side of the notch keeps about 1 once corrected
#: (its fall per pixel is ``1 / sqrt(1 + slope**2)`` of a level edge's).
GLARE_SHARE = 0.7


def _slope(x_mm, z_mm):
    """The outline's slope dz/dx in each column (over 9 columns; 0 where unknown)."""
    ok = np.isfinite(z_mm)
    if ok.sum() < 3:
        return np.zeros_like(x_mm)
    filled = np.interp(x_mm, x_mm[ok], z_mm[ok])
    filled = ndimage.uniform_filter1d(filled, 9, mode="nearest")
    return np.gradient(filled, x_mm)


def _saturated_near(image, z_mm, scene, rows):
    """Columns with a saturated pixel (any channel at full scale) within ``rows`` of the
    edge: glare burnt out, where no edge can be placed (the image's own bright
    background may saturate far from the skin without harm)."""
    values = np.asarray(image)
    if values.dtype.kind not in "ui":
        return np.zeros(z_mm.shape, dtype=bool)
    top = np.iinfo(values.dtype).max
    full = values >= top
    if full.ndim == 3:
        full = full[..., :3].any(axis=2)
    edge_row = np.where(np.isfinite(z_mm), (scene.z0_mm - z_mm) * scene.pixels_per_mm, -1e9)
    row = np.arange(full.shape[0])[:, None]
    band = np.abs(row - edge_row[None, :]) <= rows
    return (full & band).any(axis=0)


#: Pixels an edge may leave the line through the previous columns' edges (traced from
#: :data:`GLARE_REACH_MM` in towards the tip) before the trace stops there: an edge found
#: below burnt-out glare jumps far into the skin.
TRACE_JUMP_PX = 2.5


def _traced(x_mm, z_mm, tip_x_mm, pixel_mm, reach_mm=GLARE_REACH_MM):
    """Columns within ``reach_mm`` of the tip whose edge continues the outline traced in
    from ``reach_mm`` (each predicted by a line through the last 8 traced columns): a
    column past the first jump of more than :data:`TRACE_JUMP_PX` is not traced."""
    ok = np.ones(x_mm.shape, dtype=bool)
    for sign in (-1.0, 1.0):
        distance = sign * (x_mm - tip_x_mm)
        inward = np.flatnonzero((distance > 0) & (distance < reach_mm))
        inward = inward[np.argsort(-distance[inward])]
        xs, zs, broken = [], [], False
        for c in inward:
            if broken:
                ok[c] = False
                continue
            if not np.isfinite(z_mm[c]):
                continue
            if len(xs) >= 8:
                # the line through the last 8 traced edges, by hand (8 points, often)
                x8, z8 = np.asarray(xs[-8:]), np.asarray(zs[-8:])
                dx8 = x8 - x8.mean()
                a = float(dx8 @ (z8 - z8.mean()) / (dx8 @ dx8))
                predicted = z8.mean() + a * (x_mm[c] - x8.mean())
                if abs(z_mm[c] - predicted) > TRACE_JUMP_PX * pixel_mm:
                    broken = True
                    ok[c] = False
                    continue
            xs.append(x_mm[c])
            zs.append(z_mm[c])
    return ok
