"""The skin's upper edge in every column of a photograph, found by local contrast.

The skin is the dark region reaching the image's bottom edge, each column split at its
own Otsu threshold; near its top the edge is the deepest fall in brightness that stands
:data:`EDGE_NOISE_FACTOR` times above the column's own noise, refined to a fraction of a
pixel.  Boxes the sheet or config declares (``exclude_px``) are never read.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage
from skimage import filters

from lineload.rawdata.photographs.files import ImageError, _as_float

__all__ = ["EDGE_BAND_PX", "EDGE_NOISE_FACTOR", "excluded_mask", "skin_outline_mm"]


def skin_outline_mm(image, scene, smoothing_px=1.5, name="image"):
    """The skin's upper edge in every column, to a fraction of a pixel.

    Parameters
    ----------
    image : numpy.ndarray
        Greyscale (or colour) image of the finger against a brighter background.
    scene : Scene
        Scale and position of the image (its size must match).
    smoothing_px : float, optional
        Standard deviation of the Gaussian smoothing before the edge is sought.
    name : str, optional
        How messages name the image (its file).

    Returns
    -------
    tuple of numpy.ndarray
        ``z_mm`` of the edge in each column (NaN where no edge was found), and the
        contrast of that edge (the fall in brightness across it).

    Raises
    ------
    ImageError
        If the size differs from the scene's, or no column shows an edge.
    """
    return _outline_mm(_smoothed(image, scene, smoothing_px, name), scene, name)


def _smoothed(image, scene, smoothing_px, name):
    """The image as floats, checked against the scene's size, Gaussian-smoothed."""
    values = _as_float(image, name)
    if values.shape != (scene.height_px, scene.width_px):
        raise ImageError(
            f"{name}: expected {scene.height_px} x {scene.width_px} pixels as the sheet "
            f"says, got {values.shape[0]} x {values.shape[1]}"
        )
    return filters.gaussian(values, sigma=smoothing_px, preserve_range=True)


def _peak_offset(before, at, after):
    """Where a parabola through three samples around a maximum peaks, in samples from the
    middle one (within half a sample; 0 where they do not bend down)."""
    curvature = before - 2.0 * at + after
    bent = curvature < 0
    shift = np.where(bent, 0.5 * (before - after) / np.where(bent, curvature, -1.0), 0.0)
    return np.clip(shift, -0.5, 0.5)


#: An edge is taken where its fall in brightness from one row to the next (after the
#: smoothing) stands at least this many times above the noise of that fall down the same
#: columns (its robust SD, the columns being mostly plain background or skin).  Relative
#: to the image's own noise, so a soft (defocused), dim (vignetted) or gamma-encoded edge
#: that stands clear of its noise is an edge; a fixed fall per pixel is not, as it
#: depends on the blur.  Of a few hundred rows of Gaussian noise, the largest is about 3
#: SDs and one column in about 700 has one beyond 4.5 (400 rows times the normal tail
#: 3.4e-6); beyond 8, none in practice (6e-16 a row), and an image needs an edge in a
#: tenth of its columns.
EDGE_NOISE_FACTOR = 8.0


#: Rows either side of the dark region's top within which the edge is sought.
EDGE_BAND_PX = 12


def excluded_mask(boxes, shape, smoothing_px=1.5):
    """The pixels of the declared regions (config ``digitise: exclude_px``), grown by the
    smoothing's reach (3 SDs and a pixel), or None without any.

    Parameters
    ----------
    boxes : sequence of sequence of int
        ``[left, top, right, bottom]`` pixel columns and rows of each region, inclusive
        (a scale bar, a ruler or a label the lab's software burns in at the same place).
    shape : tuple of int
        The image's ``(height, width)``.
    smoothing_px : float, optional
        The smoothing before edges are sought.

    Returns
    -------
    numpy.ndarray of bool or None
    """
    if not boxes:
        return None
    grow = int(np.ceil(3 * smoothing_px)) + 1
    mask = np.zeros(shape[:2], dtype=bool)
    for left, top, right, bottom in boxes:
        mask[
            max(int(top) - grow, 0) : max(int(bottom) + grow + 1, 0),
            max(int(left) - grow, 0) : max(int(right) + grow + 1, 0),
        ] = True
    return mask


def _column_otsu(smooth):
    """Otsu's threshold of each column (the level that best splits it in two classes)."""
    ordered = np.sort(smooth, axis=0)
    height = ordered.shape[0]
    sums = np.cumsum(ordered, axis=0)[:-1]
    below = np.arange(1, height)[:, None]
    mean_low = sums / below
    mean_high = (sums[-1] + ordered[-1] - sums) / (height - below)
    between = below * (height - below) * (mean_high - mean_low) ** 2
    best = np.argmax(between, axis=0)
    columns = np.arange(ordered.shape[1])
    return 0.5 * (ordered[best, columns] + ordered[best + 1, columns])


def _skin_top_rows(smooth, excluded=None):
    """The first row of the skin in each column: the dark region that reaches the image's
    bottom edge (each column split at its own Otsu threshold, which follows vignetting
    and light gradients), with whatever it encloses (a scale bar or a label burned into
    the finger).  -1 where a column has no skin; 0 where the dark region reaches the top
    (a dark wedge joined to the skin at the notch).  ``excluded`` pixels (a declared
    region, :func:`excluded_mask`) count as dark: a box over the finger joins it."""
    width = smooth.shape[1]
    # every 4th column's threshold, a median over 13 of them, interpolated between
    every = np.arange(0, width, 4)
    coarse = ndimage.median_filter(_column_otsu(smooth[:, every]), size=13, mode="nearest")
    thresholds = np.interp(np.arange(width), every, coarse)
    dark = smooth < thresholds[None, :]
    if excluded is not None:
        dark |= excluded
    labels, count = ndimage.label(dark)
    touching = np.zeros(count + 1, dtype=bool)
    touching[labels[-1]] = True
    touching[0] = False
    skin = touching[labels]
    # what the skin encloses (not reaching the image's border) is skin too: labelled
    # rather than filled by scipy's binary_fill_holes, which is several times slower
    rest, count = ndimage.label(~skin)
    open_ = np.zeros(count + 1, dtype=bool)
    open_[np.concatenate([rest[0], rest[-1], rest[:, 0], rest[:, -1]])] = True
    skin |= (rest > 0) & ~open_[rest]
    return np.where(skin.any(axis=0), np.argmax(skin, axis=0), -1)


def _fall_noise(fall):
    """The noise of the fall between neighbouring rows in each column: its robust SD
    down the column, the median over about 51 neighbouring columns."""
    width = fall.shape[1]
    every = np.arange(0, width, 4)  # every 4th column, a median over 13, interpolated
    sample = fall[:, every]
    spread = 1.4826 * np.median(np.abs(sample - np.median(sample, axis=0)), axis=0)
    spread = ndimage.median_filter(spread, size=13, mode="nearest")
    return np.maximum(np.interp(np.arange(width), every, spread), 1e-6)


def _shown(value, limit, fmt="{:.3g}"):
    """``value`` printed with enough digits that it never reads as ``limit``."""
    text = fmt.format(value)
    digits = 3
    while text == fmt.format(limit) and digits < 12 and value != limit:
        digits += 1
        text = f"{value:.{digits}g}"
    return text


def _outline_mm(smooth, scene, name, excluded=None):
    """:func:`skin_outline_mm` of an image already smoothed (:func:`_smoothed`)."""
    z_mm, peak, _ = _edges(smooth, scene, name, excluded)
    return z_mm, peak


def _edges(smooth, scene, name, excluded=None):
    """The skin's edge in each column, its fall (contrast per pixel) and its noise.

    In each column the edge is sought within :data:`EDGE_BAND_PX` rows of the top of the
    dark region that reaches the image's bottom edge (:func:`_skin_top_rows`), or down
    the whole column where that region reaches the top (the wedge in the notch): the
    deepest local maximum of the fall there that stands :data:`EDGE_NOISE_FACTOR` times
    above the column's noise and at least half the strongest such fall of the column.
    No edge is sought in ``excluded`` pixels (:func:`excluded_mask`).
    """
    fall = smooth[:-1, :] - smooth[1:, :]  # > 0 where it darkens going down
    noise = _fall_noise(fall)
    strongest = fall.max(axis=0)
    ratio = strongest / noise
    height = fall.shape[0]
    top = _skin_top_rows(smooth, excluded)
    rows = np.arange(height)[:, None]
    whole = top <= 0
    allowed = whole[None, :] | (np.abs(rows - (top[None, :] - 1)) <= EDGE_BAND_PX)
    local = np.zeros_like(fall, dtype=bool)
    local[1:-1] = (fall[1:-1] >= fall[:-2]) & (fall[1:-1] > fall[2:])
    candidate = local & allowed & (fall > EDGE_NOISE_FACTOR * noise[None, :])
    if excluded is not None:  # a fall between rows r and r + 1 touching the region
        candidate &= ~(excluded[:-1] | excluded[1:])
    best = np.where(candidate, fall, -np.inf).max(axis=0)
    chosen = candidate & (fall >= 0.5 * best[None, :])
    deepest = np.where(chosen, rows, -1).max(axis=0)
    found = (deepest > 0) & (deepest < height - 1) & (top >= 0)
    if found.sum() < max(10, 0.1 * fall.shape[1]):
        typical = float(np.median(ratio))
        raise ImageError(
            f"{name}: no edge between skin and background: the strongest fall in "
            f"brightness down the median column is {float(np.median(strongest)):.4g} of full "
            f"scale a pixel, {_shown(typical, EDGE_NOISE_FACTOR)} times the image's own noise "
            f"in it ({float(np.median(noise)):.3g}); expected at least {EDGE_NOISE_FACTOR:g} "
            f"times in at least a tenth of the columns (found in {int(found.sum())} of "
            f"{fall.shape[1]}): is the finger in view (entering from the bottom), in focus, "
            "and against a brighter background?"
        )
    columns = np.arange(fall.shape[1])
    r = np.where(found, deepest, 1)
    at = fall[r, columns]
    # fall[r] lies between pixel rows r and r + 1: the edge at row r + 1 + offset
    # (rows counted from the top edge of the image, in pixel units)
    edge_rows = r + 1.0 + _peak_offset(fall[r - 1, columns], at, fall[r + 1, columns])
    z_mm = scene.z0_mm - edge_rows / scene.pixels_per_mm
    return np.where(found, z_mm, np.nan), np.where(found, at, np.nan), noise
