"""From photographs to readings: the skin's outline found in a side view of the finger.

The study read each profile by hand from two photographs of the fingertip seen along the
wedge, one at rest and one with the wedge pressed in.  This module does that step from
camera images, and makes such images for the reconstruction:

* :func:`render_photograph` draws a side view of a finger whose surface is a given
  outline, with what a camera adds: blur, sensor noise, uneven lighting, a textured
  skin, glare near the wedge and 8- or 16-bit levels; the wedge is drawn in the loaded
  view;
* :func:`skin_outline_mm` finds the skin's upper edge in every column of an image to a
  fraction of a pixel: the image is smoothed (a Gaussian, scikit-image); the skin is the
  dark region that reaches the image's bottom edge (each column split at its own Otsu
  threshold, so vignetting and a light gradient do not matter), with whatever it
  encloses (a scale bar or label burned into the finger); near its top, the edge is the
  deepest strong fall in brightness going down the column, strong meaning many times
  the column's own noise (not a fixed level, which would depend on the blur); its
  position is refined by a parabola through the three samples of the derivative around
  it;
* :func:`digitise_pair` finds the wedge's tip (unless the sheet gives it) where the
  wedge's two faces meet, seen against the background above the skin, sought only
  around the notch, where the loaded outline lies furthest below the resting one (so a
  scale bar, ruler or label elsewhere is never taken for it; where no wedge is seen:
  where the two sides of the loaded outline's notch cross), registers the loaded
  outline on the resting one far from the wedge, where the load does not reach (a
  vertical and a horizontal shift, least squares; its residual is reported), leaves
  unread the columns near the tip that glare has spoilt (saturated, weakened beyond
  what the outline's slope explains, or off the outline traced in towards the tip) and
  records why for each reading left unread, and reads the deflection of each side at
  the given distances, each reading the straight line through the columns within a
  small window, taken at its distance; it states each reading's own uncertainty from
  both outlines' local scatter (their errors' correlation along the outline included),
  the registration's from what it left (least squares with correlated errors), and the
  apex's own error from the scatter of the faces.  docs/calibration/digitiser.md
  measures these stated uncertainties against rendered pairs
  (:mod:`lineload.simulation.digitiser`).

What a photograph may contain, and where, is in ``docs/photographs.md``.

Coordinates: ``x`` along the image from left to right, ``z`` upward, both tissue mm;
pixel ``(row, column)`` has its centre at ``x = x0 + (column + 0.5) / ppmm`` and
``z = z0 - (row + 0.5) / ppmm``.  Deflection is downward positive, as in the models.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from skimage import filters, img_as_float64
from skimage.color import rgb2gray

__all__ = [
    "BACKGROUND_LEVEL",
    "MAX_PIXELS",
    "SKIN_LEVEL",
    "WEDGE_LEVEL",
    "Camera",
    "DigitisedTrial",
    "ImageError",
    "Scene",
    "digitise_pair",
    "digitise_photographs",
    "excluded_mask",
    "own_reading_sd_mm",
    "photograph_problem",
    "profile_rows",
    "quality_record",
    "read_photograph",
    "render_photograph",
    "skin_outline_mm",
    "trial_problem",
    "truth_error_um",
]

#: The most pixels a photograph may have (data/README.md): 40 megapixels, a 7300 x 5500
#: camera with room to spare.  Checked from the file's header before it is decoded: a
#: small file may claim 40000 x 40000 pixels and take gigabytes once decoded.
MAX_PIXELS = 40_000_000

#: Pillow's image modes that hold a photograph this workflow reads: 8- or 16-bit grey,
#: 8-bit colour (with or without alpha).
READABLE_MODES = ("L", "I;16", "I;16B", "I;16L", "I;16N", "RGB", "RGBA")

#: What the other modes are, in words.
MODE_WORDS = {
    "1": "1-bit black and white",
    "LA": "greyscale with an alpha channel (LA)",
    "La": "greyscale with an alpha channel (La)",
    "PA": "palette colours with an alpha channel",
    "P": "palette colours (an indexed image)",
    "F": "32-bit floating point",
    "I": "32-bit integer",
    "CMYK": "CMYK colour",
    "YCbCr": "YCbCr colour",
    "LAB": "Lab colour",
    "HSV": "HSV colour",
    "RGBX": "RGB with a padding channel",
    "RGBa": "RGB with a premultiplied alpha channel",
}


def photograph_problem(path, name, max_pixels=MAX_PIXELS):
    """Why a file cannot be read as a photograph, from its header alone, or None.

    Nothing is decoded: the size and mode come from the header (Pillow's ``open``),
    so a file claiming more than ``max_pixels`` pixels is refused before it can take
    the machine's memory.

    Parameters
    ----------
    path : str
        The file.
    name : str
        How the message names it.
    max_pixels : int, optional
        The most pixels allowed (:data:`MAX_PIXELS`).

    Returns
    -------
    str or None
        One sentence naming the file, what it is and what was expected.
    """
    import re
    import warnings

    from PIL import Image, UnidentifiedImageError

    expected = "expected a PNG or TIFF of 8- or 16-bit grey or 8-bit colour"
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            with Image.open(path) as image:
                (width, height), mode = image.size, image.mode
    except Image.DecompressionBombError as error:
        claimed = re.search(r"\((\d+) pixels\)", str(error))
        size = f"{int(claimed.group(1)):,} pixels" if claimed else "too many pixels"
        return (
            f"{name} claims {size}; expected at most {max_pixels:,} (a decompression "
            "bomb, or a photograph far larger than a camera's)"
        )
    except UnidentifiedImageError:
        return f"{name} cannot be read as an image (not a format Pillow knows); {expected}"
    except OSError as error:  # a header cut short, or a device that is no file
        return f"{name} cannot be read as an image ({error}); {expected}"
    except Exception as error:  # any other reader failure: still one line
        return f"{name} cannot be read as an image ({type(error).__name__}: {error}); {expected}"
    if width * height > max_pixels:
        return (
            f"{name} is {width} x {height} pixels ({width * height:,}); expected at most "
            f"{max_pixels:,} (a decompression bomb, or a photograph far larger than a camera's)"
        )
    if mode not in READABLE_MODES:
        what = MODE_WORDS.get(mode, f"of Pillow's mode {mode!r}")
        return f"{name} is {what}; {expected}"
    return None


def read_photograph(path, name, max_pixels=MAX_PIXELS):
    """A photograph's pixels, after its header has passed :func:`photograph_problem`.

    Raises
    ------
    ImageError
        One sentence: the header's problem, or a file that cannot be decoded to its end
        (truncated or damaged).
    """
    import imageio.v3 as iio

    if problem := photograph_problem(path, name, max_pixels):
        raise ImageError(problem)
    try:
        return iio.imread(path)
    except Exception as error:  # a truncated or damaged file: any reader's failure
        raise ImageError(
            f"{name} cannot be decoded ({error}); is the file truncated or damaged? "
            "expected the whole photograph, as the camera wrote it"
        ) from None


#: Brightness of the plain background, the skin and the wedge (fractions of full scale).
BACKGROUND_LEVEL = 0.88
SKIN_LEVEL = 0.22
WEDGE_LEVEL = 0.55


class ImageError(ValueError):
    """An image that cannot be digitised; the message names it and says why."""


@dataclass(frozen=True)
class Camera:
    """What a camera adds to the scene (see :func:`render_photograph`).

    Attributes
    ----------
    blur_px : float
        Standard deviation of the Gaussian blur (pixels).
    noise_sd : float
        Sensor noise, standard deviation (fraction of full scale).
    lighting_gradient : float
        Brightness changes by this fraction from the left edge to the right edge, and
        by half of it from top to bottom.
    texture_sd : float
        Standard deviation of the skin's texture (fraction of full scale).
    texture_px : float
        Size of the texture's grain (pixels).
    glare : float
        Brightening of the skin at the wedge (fraction of full scale), falling off as a
        Gaussian of ``glare_mm`` along the skin and 0.3 mm into it.
    glare_mm : float
        Reach of the glare along the outline (mm).
    bits : int
        8 or 16: the levels of the image.
    """

    blur_px: float = 1.0
    noise_sd: float = 0.01
    lighting_gradient: float = 0.1
    texture_sd: float = 0.02
    texture_px: float = 3.0
    glare: float = 0.15
    glare_mm: float = 0.25
    bits: int = 8


@dataclass(frozen=True)
class Scene:
    """The field of view of a photograph.

    Attributes
    ----------
    pixels_per_mm : float
        Scale (pixels per tissue mm).
    x0_mm, z0_mm : float
        Tissue coordinates of the image's top left corner.
    width_px, height_px : int
        Size of the image.
    """

    pixels_per_mm: float
    x0_mm: float
    z0_mm: float
    width_px: int
    height_px: int

    @property
    def column_x_mm(self):
        """x of each column's centre (mm)."""
        return self.x0_mm + (np.arange(self.width_px) + 0.5) / self.pixels_per_mm


def _coverage(top_mm, scene, supersample=4):
    """Fraction of each pixel below a surface ``z = top_mm(x)`` (anti-aliased)."""
    ppmm = scene.pixels_per_mm
    offsets = (np.arange(supersample) + 0.5) / supersample
    x = scene.x0_mm + (np.arange(scene.width_px)[:, None] + offsets[None, :]) / ppmm
    surface_rows = (scene.z0_mm - top_mm(x.ravel()).reshape(x.shape)) * ppmm  # row units
    rows = np.arange(scene.height_px)[:, None, None]
    # the part of pixel row r (from r to r + 1) below the surface row s
    covered = np.clip(rows + 1.0 - surface_rows[None, :, :], 0.0, 1.0)
    return covered.mean(axis=2)


def render_photograph(surface_mm, scene, camera, rng, wedge_tip_mm=None, wedge_half_angle_deg=20.0):
    """A side view of a finger whose upper surface is ``surface_mm(x)``.

    Parameters
    ----------
    surface_mm : callable
        Height of the skin's surface (mm, upward) as a function of x (mm, an array).
    scene : Scene
        Field of view and scale.
    camera : Camera
        Blur, noise, lighting, texture, glare and levels.
    rng : numpy.random.Generator
        For the noise and the texture.
    wedge_tip_mm : tuple of float, optional
        ``(x, z)`` of the wedge's tip: the wedge is drawn above it (the loaded view).
    wedge_half_angle_deg : float, optional
        Half the wedge's opening angle.

    Returns
    -------
    numpy.ndarray
        ``(height, width)`` of ``uint8`` or ``uint16``.
    """
    skin = _coverage(surface_mm, scene)
    brightness = BACKGROUND_LEVEL * (1.0 - skin)
    texture = ndimage.gaussian_filter(
        rng.standard_normal((scene.height_px, scene.width_px)), camera.texture_px
    )
    texture *= camera.texture_sd / max(float(texture.std()), 1e-12)
    skin_level = SKIN_LEVEL + texture
    x = scene.column_x_mm[None, :]
    z = scene.z0_mm - (np.arange(scene.height_px)[:, None] + 0.5) / scene.pixels_per_mm
    if wedge_tip_mm is not None and camera.glare > 0:
        tip_x, tip_z = wedge_tip_mm
        depth_below = np.clip(surface_mm(scene.column_x_mm)[None, :] - z, 0.0, None)
        skin_level = skin_level + camera.glare * np.exp(
            -0.5 * ((x - tip_x) / camera.glare_mm) ** 2 - 0.5 * (depth_below / 0.3) ** 2
        )
    brightness += skin_level * skin
    if wedge_tip_mm is not None:
        tip_x, tip_z = wedge_tip_mm
        slope = np.tan(np.radians(wedge_half_angle_deg))

        def wedge_bottom(xs):  # the wedge's lower faces, as a surface seen from above
            return tip_z + np.abs(xs - tip_x) / slope

        above_faces = 1.0 - _coverage(wedge_bottom, scene)  # inside the wedge
        wedge = np.clip(above_faces - skin, 0.0, 1.0) * (1.0 - skin)
        brightness += (WEDGE_LEVEL - BACKGROUND_LEVEL) * wedge
    light = 1.0 + camera.lighting_gradient * (
        (x - scene.column_x_mm.mean()) / np.ptp(scene.column_x_mm)
        + 0.5 * (np.arange(scene.height_px)[:, None] / scene.height_px - 0.5)
    )
    image = filters.gaussian(brightness * light, sigma=camera.blur_px, preserve_range=True)
    image = image + camera.noise_sd * rng.standard_normal(image.shape)
    # quantised by hand: scikit-image's img_as_ubyte and img_as_uint refuse a float image
    # with values beyond [-1, 1], and the noise lifts some pixels above full scale; they
    # saturate here as a camera's do
    top = 2**camera.bits - 1
    dtype = np.uint8 if camera.bits == 8 else np.uint16
    return np.clip(np.rint(image * top), 0, top).astype(dtype)


def _as_float(image, name):
    """A greyscale image as floats in [0, 1]; colour is converted, anything else refused.

    The conversion is scikit-image's (``img_as_float64``, ``rgb2gray``); what it would
    accept and this refuses is checked first: 10- or 12-bit levels in a 16-bit file
    (scikit-image scales them by 65535 as well, leaving an image too dim for its edge
    to show), levels of other than 8 or 16 bits (the data contract's), and a float image
    with NaN or infinite values.  An alpha channel is left out, as ``rgb2gray`` wants.
    """
    image = np.asarray(image)
    colour = image.ndim == 3 and image.shape[2] in (3, 4)
    if image.ndim != 2 and not colour:
        raise ImageError(f"{name}: expected a greyscale or colour image, got shape {image.shape}")
    levels = image[..., :3] if colour else image
    if levels.dtype == np.uint16:
        top = int(levels.max()) if levels.size else 0
        if 0 < top < 4096:  # 10- or 12-bit levels in a 16-bit file: no edge would show
            raise ImageError(
                f"{name}: its levels reach only {top} of 65535, as 10- or 12-bit data "
                "stored in a 16-bit file do; expected levels over the full 16 bits "
                "(multiply 12-bit levels by 16, 10-bit ones by 64)"
            )
    elif levels.dtype != np.uint8 and not (levels.dtype.kind == "f" and np.isfinite(levels).all()):
        raise ImageError(f"{name}: expected 8- or 16-bit levels, got {image.dtype}")
    values = img_as_float64(levels)  # (a float image as it is: float64, not rescaled)
    return rgb2gray(values) if colour else values


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


#: How far from the notch (mm) the wedge's apex is sought (:func:`_wedge_apex_mm`).
APEX_SEARCH_MM = 1.0


@dataclass
class DigitisedTrial:
    """The readings of one trial and how well they were made.

    Attributes
    ----------
    readings : dict
        Side (``left``, ``right``) -> ``(distance_mm, deflection_mm)`` arrays.
    tip_x_mm : float
        Where the wedge's tip was placed (x, mm, in the loaded image).
    shift_mm : tuple of float
        ``(dx, dz)``: the loaded image's shift against the resting one.
    registration_rms_mm : float
        RMS of the far-field difference left after registration.
    edge_noise_mm : float
        The outline's own roughness (one column's edge, SD).
    reading_sd_mm : float
        The digitising uncertainty of one reading, the median over the trial's
        readings: its own (``reading_sds_mm``) and the registration's together.
    registration_sd_mm : float
        The registration's own error, an offset shared by every reading of the
        trial, both sides alike (the part of ``reading_sd_mm`` that left-right
        differences cannot see; the fits take it in place of the config's prior
        ``noise: shared_offset_sd_mm``).
    outlines : dict, optional
        ``x_mm`` of each column, the loaded outline (``loaded_mm``, NaN where unread)
        and the resting one moved onto it (``rest_mm``): what the quality figure draws.
    apex_x_mm : float, optional
        The wedge's apex as seen in the loaded image (None where no wedge is seen
        against the background): ``tip_x_mm`` itself unless the sheet gave the tip.
    pixel_mm : float, optional
        The size of a pixel (tissue mm).
    reading_sds_mm : dict, optional
        Side -> each reading's own SD (mm), the registration's shared error apart: the
        edge errors of both outlines averaged over its columns, at its place.
    tip_sd_mm : float, optional
        The apex's standard error (mm), from the scatter of each face's points about
        its line (None where no wedge is seen against the background).
    unread : dict, optional
        Side -> list of ``(distance_mm, reason)``: each distance of the grid left
        unread on that side, and why.
    seen : dict, optional
        What the digitiser saw, for a diagnostic image (:func:`digitise_pair`).
    """

    readings: dict
    tip_x_mm: float
    shift_mm: tuple
    registration_rms_mm: float
    edge_noise_mm: float
    reading_sd_mm: float
    registration_sd_mm: float = 0.0
    outlines: dict = None
    apex_x_mm: float | None = None
    pixel_mm: float | None = None
    reading_sds_mm: dict = None
    tip_sd_mm: float | None = None
    unread: dict = None
    seen: dict = None


def _roughness_mm(z_mm, window_px=25):
    """The outline's own roughness: SD of one column's edge about the outline's local
    trend (a moving quadratic), and the correlation of neighbouring columns' errors.

    Returns
    -------
    tuple of float
        ``(sd_mm, rho)``; NaN where the outline is too short.
    """
    from scipy.signal import savgol_filter

    ok = np.isfinite(z_mm)
    if ok.sum() < 3 * window_px:
        return float("nan"), float("nan")
    # columns without an edge filled in from their neighbours for the trend only
    index = np.arange(z_mm.size)
    filled = np.interp(index, index[ok], z_mm[ok])
    residual = (filled - savgol_filter(filled, window_px | 1, 2))[ok]
    # a quadratic over the window takes a share 3/window of the variance away
    sd = float(np.std(residual) / np.sqrt(1.0 - 3.0 / window_px))
    rho = float(np.corrcoef(residual[:-1], residual[1:])[0, 1])
    return sd, min(max(rho, 0.0), 0.99)


def _sample(x_mm, z_mm, at_mm, half_window_mm):
    """The outline at each point from the columns within ``half_window_mm`` of it: their
    straight line (least squares) at the point, their mean where they are too few or all
    at one place (NaN where a window holds no column with an edge: that reading is
    unreadable).

    The columns' mean alone would be the outline at their mean position, up to half a
    pixel from the point: on a slope of 0.2 at 10 um a pixel, a 1 um error that no
    smoothing removes.  The line through them takes the slope out.
    """
    ok = np.isfinite(z_mm)
    x, z = x_mm[ok], z_mm[ok]
    lo = np.searchsorted(x, at_mm - half_window_mm, side="left")
    hi = np.searchsorted(x, at_mm + half_window_mm, side="right")
    counts = hi - lo
    n = np.maximum(counts, 1)
    # sums over each window, about the point itself (well conditioned)
    windows = [slice(a, b) for a, b in zip(lo, hi, strict=True)]
    offsets = [x[w] - at for w, at in zip(windows, at_mm, strict=True)]
    sum_d = np.array([o.sum() for o in offsets])
    sum_dd = np.array([(o * o).sum() for o in offsets])
    sum_z = np.array([z[w].sum() for w in windows])
    sum_dz = np.array([(o * z[w]).sum() for o, w in zip(offsets, windows, strict=True)])
    spread = sum_dd - sum_d**2 / n
    slope = np.where(
        spread > 0, (sum_dz - sum_d * sum_z / n) / np.where(spread > 0, spread, 1.0), 0.0
    )
    value = sum_z / n - slope * sum_d / n
    return np.where(counts > 0, value, np.nan), counts


def digitise_pair(
    rest_image,
    loaded_image,
    scene,
    distances_mm,
    reach_mm,
    tip_x_mm=None,
    smoothing_px=1.5,
    window_mm=0.02,
    names=("rest", "loaded"),
    exclude_px=(),
):
    """Readings of both sides of the wedge from a resting and a loaded photograph.

    Parameters
    ----------
    rest_image, loaded_image : numpy.ndarray
        The two photographs, of the same size and scale.
    scene : Scene
        Their scale and field of view.
    distances_mm : array_like
        Distances from the wedge at which to read each side (mm, > 0).
    reach_mm : float
        Distance from the wedge beyond which the load does not reach: the outlines are
        registered there.
    tip_x_mm : float, optional
        x of the wedge's tip in the loaded image (from the sheet); found otherwise.
    smoothing_px : float, optional
        Smoothing before the edge is sought (:func:`skin_outline_mm`).
    window_mm : float, optional
        Half-width of the columns averaged into one reading.
    names : tuple of str, optional
        How messages name the two images (their files).
    exclude_px : sequence of sequence of int, optional
        Regions no edge or wedge is sought in, ``[left, top, right, bottom]`` pixels
        (:func:`excluded_mask`); a column whose edge would lie there is left unread.

    Returns
    -------
    DigitisedTrial

    Raises
    ------
    ImageError
        If an image has no edge, the wedge's tip cannot be found, or too little skin
        beyond ``reach_mm`` is in view to register the outlines.  Its ``seen`` holds what
        the digitiser saw up to then (as the trial's ``seen`` does): ``scene``,
        ``exclude_px``, ``reach_mm``, ``failed`` (0 or 1: which image), and as far as it
        got ``rest_mm`` and ``loaded_mm`` (each column's edge, NaN where none),
        ``notch_x_mm``, ``apex_region_mm`` (``x_lo, x_hi``: where the apex was sought),
        ``apex_x_mm``, ``tip_x_mm``, ``why`` (each column's reason for being left out,
        "" where kept): what :mod:`lineload.figures.diagnostic` draws.
    """
    seen = {"scene": scene, "exclude_px": list(exclude_px), "reach_mm": reach_mm, "failed": 0}
    try:
        return _digitise_pair(
            seen,
            rest_image,
            loaded_image,
            scene,
            distances_mm,
            reach_mm,
            tip_x_mm,
            smoothing_px,
            window_mm,
            names,
            exclude_px,
        )
    except ImageError as error:
        error.seen = seen
        raise


def _digitise_pair(
    seen,
    rest_image,
    loaded_image,
    scene,
    distances_mm,
    reach_mm,
    tip_x_mm,
    smoothing_px,
    window_mm,
    names,
    exclude_px,
):
    """:func:`digitise_pair`'s work; ``seen`` is filled in as it goes."""
    x = scene.column_x_mm
    excluded = excluded_mask(exclude_px, (scene.height_px, scene.width_px), smoothing_px)
    smooth_rest = _smoothed(rest_image, scene, smoothing_px, names[0])
    z_rest, _ = _outline_mm(smooth_rest, scene, names[0], excluded)
    seen.update(rest_mm=z_rest, failed=1)
    smooth_load = _smoothed(loaded_image, scene, smoothing_px, names[1])
    z_load, contrast_load, _ = _edges(smooth_load, scene, names[1], excluded)
    seen["loaded_mm"] = z_load
    why = np.where(np.isfinite(z_load), "", "no edge in the column")
    if excluded is not None:
        why = np.where(np.isfinite(z_load) | ~excluded.any(axis=0), why, "an excluded region")
    # the wedge is sought only where the load pressed the skin in: around the notch,
    # where the loaded outline lies furthest below the resting one (a scale bar, a ruler
    # or a label elsewhere is never taken for it)
    notch_x_mm = _notch_mm(x, z_rest, z_load)
    apex = _wedge_apex_mm(smooth_load, scene, z_load, smoothing_px, notch_x_mm, excluded)
    apex_x_mm, apex_sd_mm = apex if apex is not None else (None, None)
    seen.update(
        notch_x_mm=notch_x_mm,
        apex_region_mm=(notch_x_mm - APEX_SEARCH_MM, notch_x_mm + APEX_SEARCH_MM),
    )
    seen["apex_x_mm"] = apex_x_mm
    if tip_x_mm is None:
        tip_x_mm = apex_x_mm
        if tip_x_mm is None:  # no wedge seen against the background: the notch's tip
            tip_x_mm = _wedge_tip_mm(x, z_load, names[1], around_mm=notch_x_mm)
    # glare at the wedge brightens the skin: its edge's step shrinks and its place is
    # biased.  A steep edge's fall per pixel shrinks too (by about 1 / sqrt(1 + slope^2),
    # the blur spread along the column), so the fall is compared slope-corrected: within
    # GLARE_REACH_MM of the tip, a column whose corrected fall is below GLARE_SHARE of
    # the one 1-3 mm out, or whose skin just below the edge is saturated, is left unread
    # (as a hand reader starts past a glaring stretch)
    away = np.abs(x - tip_x_mm)
    corrected = contrast_load * np.sqrt(1.0 + _slope(x, z_load) ** 2)
    reference_columns = (away > 1.0) & (away < 3.0) & np.isfinite(corrected)
    reference = (
        float(np.median(corrected[reference_columns])) if reference_columns.any() else np.nan
    )
    weak = (away < GLARE_REACH_MM) & (corrected < GLARE_SHARE * reference)
    saturated = (away < GLARE_REACH_MM) & _saturated_near(
        loaded_image, z_load, scene, int(np.ceil(3 * smoothing_px)) + EDGE_BAND_PX
    )
    jumped = ~_traced(
        x, np.where(saturated | weak, np.nan, z_load), tip_x_mm, 1.0 / scene.pixels_per_mm
    )
    why = np.where(
        np.isfinite(z_load) & jumped,
        "glare or an overlay: the edge leaves the outline traced in towards the tip",
        why,
    )
    why = np.where(
        np.isfinite(z_load) & saturated,
        "glare: saturated pixels at the edge",
        np.where(
            np.isfinite(z_load) & weak,
            f"glare or the wedge above the edge: its slope-corrected contrast is below "
            f"{GLARE_SHARE:g} of the contrast 1-3 mm out",
            why,
        ),
    )
    why = np.where(
        (why == "no edge in the column") & (away < GLARE_REACH_MM),
        "no edge in the column, near the tip (glare as bright as the background?)",
        why,
    )
    seen.update(tip_x_mm=float(tip_x_mm), why=why)
    z_load = np.where(why == "", z_load, np.nan)
    far = np.isfinite(z_load) & (away > reach_mm)
    if far.sum() < 20 or not ((x[far] < tip_x_mm).any() and (x[far] > tip_x_mm).any()):
        ppmm = scene.pixels_per_mm
        sides = {
            side: int(np.sum(far & (sign * (x - tip_x_mm) > 0)))
            for side, sign in (("left", -1.0), ("right", 1.0))
        }
        raise ImageError(
            f"{names[1]}: too little skin in view beyond {reach_mm:g} mm of the wedge on "
            f"both sides to register the two photographs: the wedge's tip was placed at "
            f"pixel column {(tip_x_mm - scene.x0_mm) * ppmm - 0.5:.1f} "
            f"({'seen at its apex' if apex_x_mm is not None else 'from the notch'}, "
            f"the notch at column {(notch_x_mm - scene.x0_mm) * ppmm - 0.5:.0f}), leaving "
            f"{sides['left']} columns with an edge on the left and {sides['right']} on the "
            f"right beyond reach_mm (the image is {scene.width_px} columns, "
            f"{scene.width_px / ppmm:.2f} mm, wide); expected at least 20 in all, on both "
            "sides: widen the view, lower reach_mm, or check the tip (a tip_x_px from "
            "another photograph?)"
        )
    # the loaded outline against the resting one shifted by (dx, dz), least squares
    ok_rest = np.isfinite(z_rest)
    slope = np.gradient(z_rest[ok_rest], x[ok_rest])
    dx = dz = 0.0
    for _ in range(4):
        shifted = np.interp(x[far] - dx, x[ok_rest], z_rest[ok_rest])
        slope_at = np.interp(x[far] - dx, x[ok_rest], slope)
        design = np.column_stack([np.ones(far.sum()), -slope_at])
        residual = z_load[far] - shifted - dz
        step, *_ = np.linalg.lstsq(design, residual, rcond=None)
        dz += step[0]
        dx += step[1]
    final = z_load[far] - np.interp(x[far] - dx, x[ok_rest], z_rest[ok_rest]) - dz
    registration_rms = float(np.sqrt(np.mean(final**2)))
    rest_on_loaded = np.interp(x - dx, x[ok_rest], z_rest[ok_rest]) + dz
    deflection = np.where(np.isfinite(z_load), rest_on_loaded - z_load, np.nan)
    distances_mm = np.asarray(distances_mm, dtype=float)
    readings, unread = {}, {}
    columns = []
    for side, sign in (("left", -1.0), ("right", 1.0)):
        distance = sign * (x - tip_x_mm)
        keep = distance > 0
        d, w = distance[keep], deflection[keep]
        order = np.argsort(d)
        values, counts = _sample(d[order], w[order], distances_mm, window_mm)
        inside = np.isfinite(values)
        readings[side] = (distances_mm[inside], values[inside])
        columns.extend(counts[inside])
        unread[side] = [
            (round(float(at), 6), _unread_reason(d[order], why[keep][order], at, window_mm))
            for at in distances_mm[~inside]
        ]
    # each reading's own error: the mean over its columns of two outlines' edge errors,
    # and the registration's error, shared by every reading (_reading_sds_mm)
    rough = [_roughness_mm(z_rest), _roughness_mm(z_load)]
    edge = float(np.sqrt(np.nanmean([sd**2 for sd, _ in rough])))
    design = np.column_stack([np.ones(far.sum()), -np.interp(x[far] - dx, x[ok_rest], slope)])
    registration_sd = _registration_sd_mm(design, final, np.flatnonzero(far))
    own = _reading_sds_mm(x, z_rest, z_load, dx, tip_x_mm, readings, window_mm)
    totals = np.concatenate([np.hypot(own[side], registration_sd) for side in own])
    return DigitisedTrial(
        readings=readings,
        tip_x_mm=float(tip_x_mm),
        shift_mm=(float(dx), float(dz)),
        registration_rms_mm=registration_rms,
        edge_noise_mm=float(edge),
        reading_sd_mm=float(np.median(totals)) if totals.size else float(registration_sd),
        registration_sd_mm=float(registration_sd),
        outlines={"x_mm": x, "loaded_mm": z_load, "rest_mm": rest_on_loaded},
        apex_x_mm=None if apex_x_mm is None else float(apex_x_mm),
        pixel_mm=1.0 / scene.pixels_per_mm,
        reading_sds_mm=own,
        tip_sd_mm=None if apex_sd_mm is None else float(apex_sd_mm),
        unread=unread,
        seen=seen,
    )


#: How the digitiser states its uncertainties (docs/calibration/digitiser.md measures
#: them against rendered pairs): an outline's edge errors are its residual about a moving
#: quadratic over :data:`TREND_MM` of outline (long against the errors' own correlation,
#: which blur, smoothing and the skin's grain make a few pixels long: a shorter trend
#: follows them and hides their slow part; short against the profile's own bends), and
#: their local size is taken over :data:`LOCAL_SCATTER_MM` either side of a reading.
TREND_MM = 1.0
TREND_ORDER = 4
LOCAL_SCATTER_MM = 0.5


def _autocovariance(residual, blocks, max_lag):
    """Autocovariance of ``residual`` at lags 0..``max_lag``, pooled over the contiguous
    runs of column indices ``blocks`` (a gap between runs is not a lag)."""
    runs = np.split(residual, np.flatnonzero(np.diff(blocks) != 1) + 1)
    gamma = np.zeros(max_lag + 1)
    pairs = np.zeros(max_lag + 1)
    for run in runs:
        for lag in range(min(max_lag, run.size - 1) + 1):
            gamma[lag] += np.sum(run[: run.size - lag] * run[lag:])
            pairs[lag] += run.size - lag
    return gamma / np.maximum(pairs, 1.0)


def _correlation_lags(gamma):
    """The lags up to the first at which the autocovariance is no longer positive: the
    window of the integrated autocorrelation (beyond it the estimate is noise)."""
    stop = np.flatnonzero(gamma <= 0.0)
    return int(stop[0]) if stop.size else gamma.size


def _sandwich_covariance(design, residual, index, max_lag=200):
    """Covariance of a least-squares fit whose errors are correlated along the outline or
    the face: the sandwich ``(X'X)^-1 X' S X (X'X)^-1``, whose ``S`` holds the residual's
    own autocovariance up to its first non-positive lag (zero beyond).

    Parameters
    ----------
    design : numpy.ndarray
        ``(n, k)``: the fit's columns at each point.
    residual : numpy.ndarray
        What the fit left there.
    index : numpy.ndarray
        The points' integer places along the outline (columns) or the face (rows): gaps
        split the lags.
    """
    gamma = _autocovariance(residual, index, min(max_lag, residual.size // 4))
    lags = _correlation_lags(gamma)
    runs = np.split(np.arange(residual.size), np.flatnonzero(np.diff(index) != 1) + 1)
    middle = gamma[0] * design.T @ design
    for lag in range(1, lags):
        for run in runs:
            if run.size > lag:
                a, b = design[run[:-lag]], design[run[lag:]]
                middle += gamma[lag] * (a.T @ b + b.T @ a)
    bread = np.linalg.inv(design.T @ design)
    # the points' count over the correlation's integrated length: what is independent in
    # them, for a degrees-of-freedom correction of the residual's variance
    effective = residual.size * gamma[0] / max(gamma[0] + 2.0 * gamma[1:lags].sum(), 1e-300)
    return bread @ middle @ bread, float(effective)


def _registration_sd_mm(design, residual, columns, max_lag=200):
    """SD of the registration's vertical offset: least squares with errors correlated
    along the outline (:func:`_sandwich_covariance`).

    Parameters
    ----------
    design : numpy.ndarray
        ``(n, 2)``: the offset's and the shift's columns of the far columns.
    residual : numpy.ndarray
        What the registration left there (mm).
    columns : numpy.ndarray
        Their column indices (gaps split the lags).
    """
    variance = _sandwich_covariance(design, residual, columns, max_lag)[0][0, 0]
    return float(np.sqrt(max(variance, 0.0)))


def _trend_residual(z_mm, trend_px, split):
    """The outline's residual about a moving quadratic of ``trend_px`` columns, each
    side of column ``split`` on its own (a trend across the wedge's notch would take its
    bend for scatter); NaN where no edge was found."""
    from scipy.signal import savgol_filter

    residual = np.full(z_mm.shape, np.nan)
    for part in (slice(0, split), slice(split, z_mm.size)):
        z = z_mm[part]
        ok = np.isfinite(z)
        if ok.sum() < max(trend_px, 7):
            continue
        index = np.arange(z.size)
        filled = np.interp(index, index[ok], z[ok])
        window = min(trend_px, z.size) - (1 - min(trend_px, z.size) % 2)  # odd
        residual[part] = np.where(ok, filled - savgol_filter(filled, window, TREND_ORDER), np.nan)
    return residual


def _mean_variance_factor(residual, n_columns, trend_px):
    """How much larger the variance of a mean of ``n_columns`` edge errors is than the
    mean square of the same mean of their residual about the moving quadratic.

    The quadratic takes part of the errors with it, the more the longer they are
    correlated.  With the errors' correlation taken from the residual's own
    autocorrelation up to its first non-positive lag (zero beyond) and the moving
    quadratic's weights ``h`` (Savitzky-Golay), the mean's weights are ``b`` (``1/n``
    over ``n`` columns) on the errors and ``a = b - b * h`` on the residual: the factor
    is ``b' R b / a' R a``.
    """
    from scipy.linalg import toeplitz
    from scipy.signal import savgol_coeffs

    runs = np.isfinite(residual)
    if runs.sum() < 3 * trend_px:
        return float("nan")
    columns = np.flatnonzero(runs)
    gamma = _autocovariance(residual[runs], columns, min(trend_px, 200))
    lags = _correlation_lags(gamma)
    window = trend_px | 1
    h = savgol_coeffs(window, TREND_ORDER)
    b = np.zeros(window + n_columns - 1)
    b[window // 2 : window // 2 + n_columns] = 1.0 / n_columns
    a = b - np.convolve(np.ones(n_columns) / n_columns, h)  # the mean of the residual
    rho = np.zeros(b.size)
    rho[:lags] = gamma[:lags] / gamma[0]
    correlation = toeplitz(rho)
    return float((b @ correlation @ b) / (a @ correlation @ a))


def _local_variance(z_mm, n_columns, pixel_mm, split):
    """Each column's local variance (mm^2) of the mean of ``n_columns`` neighbouring
    columns' edge errors: the outline's residual about its moving quadratic
    (:func:`_trend_residual`), averaged over ``n_columns``, squared, averaged over
    ``LOCAL_SCATTER_MM`` either side and scaled for what the quadratic took
    (:func:`_mean_variance_factor`); NaN where too few columns."""
    trend_px = max(7, round(TREND_MM / pixel_mm))
    half_px = max(3, round(LOCAL_SCATTER_MM / pixel_mm))
    residual = _trend_residual(z_mm, trend_px, split)
    factor = _mean_variance_factor(residual, n_columns, trend_px)
    ok = np.isfinite(residual)
    means = ndimage.uniform_filter1d(np.where(ok, residual, 0.0), n_columns, mode="nearest")
    full = ndimage.uniform_filter1d(ok.astype(float), n_columns, mode="nearest") > 1 - 1e-9
    size = 2 * half_px + 1
    sums = ndimage.uniform_filter1d(np.where(full, means**2, 0.0), size, mode="nearest")
    counts = ndimage.uniform_filter1d(full.astype(float), size, mode="nearest")
    return np.where(counts * size >= 10, factor * sums / np.maximum(counts, 1e-12), np.nan)


def _reading_sds_mm(x, z_rest, z_load, dx, tip_x_mm, readings, window_mm):
    """Each reading's own SD (mm; the registration's shared error apart).

    A reading is the line through its columns of the resting outline's edge minus the
    loaded one's, taken at its distance (:func:`_sample`); the two photographs' errors
    are independent, so its variance is the sum of each outline's local variance of a
    mean over as many columns (:func:`_local_variance`), at the reading's columns (the
    resting outline's moved onto the loaded one's): a steep or glaring stretch, rougher
    than the rest, counts as rough as it is.  A line taken off its columns' centre
    varies more than their mean: by ``1 + n (x0 - mean)^2 / sum (x - mean)^2`` for
    independent errors (least squares), a bound for errors correlated along the outline.
    """
    pixel_mm = float(np.median(np.diff(x)))
    n = max(1, int(np.sum(np.abs(x - x[x.size // 2]) <= window_mm)))
    split = int(np.searchsorted(x, tip_x_mm))
    local = _local_variance(z_load, n, pixel_mm, split) + np.interp(
        x - dx, x, _local_variance(z_rest, n, pixel_mm, z_rest.size)
    )
    fallback = float(np.nanmax(local)) if np.isfinite(local).any() else float("nan")
    read = np.isfinite(z_load)
    sds = {}
    for side, sign in (("left", -1.0), ("right", 1.0)):
        variances = []
        for c in tip_x_mm + sign * readings[side][0]:
            at = float(np.nanmean(local[np.abs(x - c) <= max(window_mm, pixel_mm)]))
            columns = x[read & (np.abs(x - c) <= window_mm)]
            spread = float(np.sum((columns - columns.mean()) ** 2)) if columns.size else 0.0
            off = 1.0 + (columns.size * (c - columns.mean()) ** 2 / spread if spread > 0 else 0.0)
            variances.append((at if np.isfinite(at) else fallback) * off)
        sds[side] = np.sqrt(np.array(variances, dtype=float))
    return sds


def digitise_photographs(
    rest_image, loaded_image, pixels_per_mm, distances_mm, settings, tip_x_px=None, names=()
):
    """A pair read as the workflow reads it, from the sheet's values and the config's.

    Coordinates are the images' own (x from their left edge, z down from their top, in
    tissue mm at the sheet's scale); the tip, when the sheet gives its pixel column,
    is at that column's centre.

    Parameters
    ----------
    rest_image, loaded_image : numpy.ndarray
        The two photographs.
    pixels_per_mm : float
        Their scale (images.csv).
    distances_mm : array_like
        Where to read each side.
    settings : dict
        The config's ``digitise`` settings (``reach_mm``, ``smoothing_px``,
        ``window_mm``, ``exclude_px``).
    tip_x_px : float, optional
        The sheet's ``tip_x_px``; found in the image when None.
    names : tuple of str, optional
        How messages name the two images.

    Returns
    -------
    DigitisedTrial
    """
    height, width = np.shape(loaded_image)[:2]
    scene = Scene(pixels_per_mm, 0.0, 0.0, width, height)
    return digitise_pair(
        rest_image,
        loaded_image,
        scene,
        distances_mm,
        reach_mm=settings["reach_mm"],
        tip_x_mm=None if tip_x_px is None else (float(tip_x_px) + 0.5) / pixels_per_mm,
        smoothing_px=settings["smoothing_px"],
        window_mm=settings["window_mm"],
        exclude_px=settings.get("exclude_px", ()),
        names=tuple(names) or ("rest", "loaded"),
    )


#: How far (pixels) a tip given in the sheet may lie from the apex seen in the image:
#: the apex is found to within 0.35 pixel on 20 pairs with harder camera settings.
TIP_PIXELS_MAX = 3.0

#: How many times the outlines' own roughness the registration may leave beyond
#: reach_mm.  On the photograph example the residual is 1.9-2.4 times it; a pair whose
#: skin beyond reach_mm moved (reach 2 mm: 156-276 times), whose resting view is 3 %
#: zoomed (44-61 times) or whose scale is a quarter of the truth (195-212 times) is
#: far beyond.
REGISTRATION_ROUGHNESS_MAX = 10.0


def trial_problem(trial, depth_mm, deflection_factor, names=("rest", "loaded")):
    """Why a digitised trial is not a plausible indentation, or None.

    The checks a profile file gets (its readings within ``deflection_factor`` of the
    depth), and those only a pair of photographs can fail: no deflection at all (one
    photograph copied over the other), skin raised at the wedge (the two swapped), a
    registration that leaves many times the outlines' roughness (the skin beyond
    ``reach_mm`` moved, or the two photographs differ in scale).

    Parameters
    ----------
    trial : DigitisedTrial
    depth_mm : float
        The pair's depth (images.csv, tissue mm).
    deflection_factor : float
        The config's ``input_checks: deflection_factor``.
    names : tuple of str, optional
        How messages name the two photographs.

    Returns
    -------
    str or None
        One sentence naming the loaded photograph, what was found and the likely cause.
    """
    name = names[1]
    values = [trial.readings[side][1] for side in ("left", "right")]
    readings = np.concatenate(values)
    if readings.size == 0:
        return None  # nothing read: the digitiser said so already
    edge_mm = max(trial.edge_noise_mm, 1e-9)
    near_mm = float(np.mean([v[0] for v in values if v.size]))
    largest = float(np.max(np.abs(readings)))
    if largest < 5.0 * edge_mm or largest < depth_mm / 100.0:
        return (
            f"{name}: no deflection (at most {1000 * largest:.1f} um anywhere, at a depth of "
            f"{depth_mm:g} mm); expected the loaded outline pressed in: is one photograph "
            "copied over the other?"
        )
    if near_mm < 0 and -near_mm > depth_mm / deflection_factor:
        return (
            f"{name}: the skin at the wedge is raised by {-near_mm:.3f} mm against the "
            f"resting photograph, at a depth of {depth_mm:g} mm; expected it pressed down: "
            "are rest and loaded swapped?"
        )
    if trial.apex_x_mm is not None and trial.pixel_mm:
        off_px = (trial.tip_x_mm - trial.apex_x_mm) / trial.pixel_mm
        if abs(off_px) > TIP_PIXELS_MAX:
            return (
                f"{name}: the sheet's tip_x_px puts the wedge's tip {abs(off_px):.1f} pixels "
                f"{'right' if off_px > 0 else 'left'} of its apex as seen in the photograph "
                f"(pixel column {trial.apex_x_mm / trial.pixel_mm - 0.5:.1f}); expected them "
                f"within {TIP_PIXELS_MAX:g} pixels: a tip read from another photograph, or "
                "a typing error?"
            )
    ratio = trial.registration_rms_mm / edge_mm
    if ratio > REGISTRATION_ROUGHNESS_MAX:
        return (
            f"{name}: the two outlines beyond reach_mm differ by "
            f"{1000 * trial.registration_rms_mm:.1f} um after registration, {ratio:.0f} times "
            f"the outlines' own roughness ({1000 * edge_mm:.2f} um; expected at most "
            f"{REGISTRATION_ROUGHNESS_MAX:g} times): reach_mm too short (the load still "
            "moves the skin there), the two photographs at different scales (zoom, or a "
            "wrong pixels_per_mm), or not the same finger"
        )
    if near_mm > deflection_factor * depth_mm or largest > deflection_factor * depth_mm:
        return (
            f"{name}: deflected {max(near_mm, largest):.3f} mm at a depth of {depth_mm:g} mm, "
            f"more than {deflection_factor:g} times it; expected about the depth at the "
            "wedge: is the scale (pixels_per_mm) or the depth wrong?"
        )
    if near_mm < depth_mm / deflection_factor:
        return (
            f"{name}: deflected {near_mm:.3f} mm next to the wedge at a depth of "
            f"{depth_mm:g} mm, less than 1/{deflection_factor:g} of it; expected about the "
            "depth: is the scale (pixels_per_mm) or the depth wrong, or the loaded view "
            "not indented?"
        )
    return None


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


def _notch_mm(x_mm, z_rest_mm, z_load_mm):
    """x where the loaded outline lies furthest below the resting one (over 0.1 mm of
    columns): the notch the wedge made, before any registration (a shift between the
    shots moves the skin by far less than the wedge does)."""
    gap = z_rest_mm - z_load_mm
    ok = np.isfinite(gap)
    if ok.sum() < 10:
        ok = np.isfinite(z_load_mm)
        if ok.sum() < 10:
            return float(np.mean(x_mm))
        gap = -z_load_mm
    spacing = float(np.median(np.diff(x_mm)))
    filled = np.interp(x_mm, x_mm[ok], gap[ok])
    size = max(3, round(0.1 / spacing) | 1)
    return float(x_mm[np.argmax(ndimage.uniform_filter1d(filled, size, mode="nearest"))])


def _unread_reason(distance_mm, why, at_mm, half_window_mm):
    """Why the reading at ``at_mm`` has no column with an edge: the commonest reason of
    its columns, or that none of its columns is in view."""
    inside = np.abs(distance_mm - at_mm) <= half_window_mm
    if not inside.any():
        return "outside the view"
    reasons, counts = np.unique(why[inside], return_counts=True)
    return str(reasons[np.argmax(counts)])


def _robust_line(heights, columns, pixel_mm):
    """``x = a z + b`` through one face's points, points more than 3 robust SDs (at least
    a pixel) off dropped twice; its fit, the fit's covariance (the points' errors
    correlated down the face: :func:`_sandwich_covariance`), the kept points' count and
    their residual SD."""
    keep = np.ones(heights.size, dtype=bool)
    for _ in range(3):
        if keep.sum() < 10:
            return None
        a, b = np.polyfit(heights[keep], columns[keep], 1)
        residual = columns - (a * heights + b)
        spread = 1.4826 * np.median(np.abs(residual[keep]))
        keep = np.abs(residual) <= max(3.0 * spread, pixel_mm)
    if keep.sum() < 10:
        return None
    a, b = np.polyfit(heights[keep], columns[keep], 1)
    residual = columns[keep] - (a * heights[keep] + b)
    sd = float(np.std(residual, ddof=2))
    # rows' errors correlate through the smoothing and the blur: the fit's covariance is
    # the sandwich with the residual's own autocovariance down the face (an AR(1) chain
    # fitted to the lag-1 correlation alone overstated it: docs/calibration/digitiser.md)
    rows = np.rint((heights[0] - heights[keep]) / pixel_mm).astype(int)
    design = np.column_stack([heights[keep], np.ones(int(keep.sum()))])
    covariance, effective = _sandwich_covariance(design, residual, rows)
    # the residual's variance is that of the points about a line fitted to them, lower
    # than their errors' by the line's 2 parameters out of the effective count
    covariance = covariance * effective / max(effective - 2.0, 1.0)
    return a, b, covariance, int(keep.sum()), sd


def _wedge_apex_mm(
    smooth,
    scene,
    z_mm,
    smoothing_px,
    notch_x_mm,
    excluded=None,
    half_window_mm=1.5,
    search_mm=APEX_SEARCH_MM,
    centre_mm=0.3,
):
    """x of the wedge's apex, where its two faces meet, and its standard error; None if no
    wedge is seen.

    The wedge is sought only around the notch (``notch_x_mm``, :func:`_notch_mm`): above
    the skin within ``search_mm`` of the notch, its middle is the darkest column within
    ``centre_mm`` of it (where the wedge fills every row: a bar crossing its face
    further out may darken a column more), and an apex more than ``search_mm`` from the
    notch is no apex (None: the notch's own tip is taken instead; glare near the tip can
    put the notch 0.3 mm off).  In each
    row, its left face is the first strong fall in brightness met going left from that
    column (within ``half_window_mm``), its right face the first strong rise going right
    (each refined by a parabola); a straight line through each face's points (robustly:
    a scale bar's tick or a label in a row is dropped as an outlier), extended down to
    where they cross, gives the apex.  Its standard error comes from the scatter of the
    faces' points about their lines.  ``smooth`` is the loaded image as its outline was
    sought in (:func:`_smoothed`); ``excluded`` pixels (:func:`excluded_mask`) hold no
    face.
    """
    ppmm = scene.pixels_per_mm
    pixel_mm = 1.0 / ppmm
    x = scene.column_x_mm
    near = np.abs(x - notch_x_mm) <= search_mm + half_window_mm
    if not np.isfinite(z_mm[near]).any():
        return None
    skin_top = float(np.nanmax(z_mm[near]))
    last_row = int((scene.z0_mm - skin_top) * ppmm - 4 * smoothing_px)
    rows = np.arange(2, last_row)
    if rows.size < 10:
        return None
    lo_search = max(int((notch_x_mm - centre_mm - scene.x0_mm) * ppmm), 0)
    hi_search = min(int((notch_x_mm + centre_mm - scene.x0_mm) * ppmm) + 1, smooth.shape[1])
    if hi_search - lo_search < 3:
        return None
    centre = lo_search + int(np.argmin(smooth[rows, lo_search:hi_search].mean(axis=0)))
    rise = smooth[:, 1:] - smooth[:, :-1]  # between columns c and c + 1
    if excluded is not None:  # no face in a declared region
        rise = np.where(excluded[:, 1:] | excluded[:, :-1], 0.0, rise)
    reach = int(half_window_mm * ppmm)
    points = {-1.0: ([], []), 1.0: ([], [])}
    bounds, noise = {}, {}
    for sign in (-1.0, 1.0):
        lo, hi = (centre, centre + reach) if sign > 0 else (centre - reach, centre)
        bounds[sign] = lo, hi = max(lo, 1), min(hi, rise.shape[1] - 1)
        if hi - lo >= 4:  # the rise's noise over the rows and columns searched
            block = rise[rows, lo:hi]
            noise[sign] = 1.4826 * float(np.median(np.abs(block - np.median(block))))
    for row in rows:
        for sign in (-1.0, 1.0):
            lo, hi = bounds[sign]
            if hi - lo < 4:
                continue
            # the left face darkens going right, the right face brightens: both peak here
            segment = sign * rise[row, lo:hi]
            strong = max(5.0 * noise[sign], 0.3 * float(segment.max()), 1e-3)
            peaks = np.flatnonzero(
                (segment[1:-1] >= segment[:-2])
                & (segment[1:-1] > segment[2:])
                & (segment[1:-1] >= strong)
            )
            if peaks.size == 0:
                continue
            # the face is the first strong edge met going out from inside the wedge (a
            # scale bar's tick or a label further out may be stronger)
            c = int(peaks[0] if sign > 0 else peaks[-1]) + 1
            offset = float(_peak_offset(segment[c - 1], segment[c], segment[c + 1]))
            column = lo + c + 0.5 + offset  # between c and c + 1
            points[sign][0].append(scene.z0_mm - (row + 0.5) / ppmm)
            points[sign][1].append(scene.x0_mm + (column + 0.5) / ppmm)
    lines = []
    for sign in (-1.0, 1.0):
        heights, columns = (np.asarray(v) for v in points[sign])
        if heights.size < 10:
            return None
        fit = _robust_line(heights, columns, pixel_mm)
        if fit is None:
            return None
        a, b, covariance, kept, sd = fit
        if kept < 0.5 * heights.size or sd > pixel_mm or sign * a <= 0:
            return None  # not a straight face opening upward: no wedge seen
        lines.append((a, b, covariance))

    def apex(p):
        a1, b1, a2, b2 = p
        z = (b2 - b1) / (a1 - a2)
        return a1 * z + b1

    params = np.array([lines[0][0], lines[0][1], lines[1][0], lines[1][1]])
    covariance = np.zeros((4, 4))
    covariance[:2, :2], covariance[2:, 2:] = lines[0][2], lines[1][2]
    steps = 1e-6 * np.maximum(np.abs(params), 1.0)
    gradient = np.array(
        [
            (apex(params + np.eye(4)[k] * steps[k]) - apex(params - np.eye(4)[k] * steps[k]))
            / (2 * steps[k])
            for k in range(4)
        ]
    )
    apex_x_mm = float(apex(params))
    if not abs(apex_x_mm - notch_x_mm) <= search_mm:
        return None  # the faces met away from the notch: not the wedge's
    return apex_x_mm, float(np.sqrt(max(gradient @ covariance @ gradient, 0.0)))


def _wedge_tip_mm(x_mm, z_mm, name, near_mm=(0.1, 0.8), around_mm=None, search_mm=1.0):
    """x where the two sides of the loaded outline meet.

    The tip is first placed at the sharpest dip of the outline (where it lies furthest
    below the mean of the outline ``near_mm[1]`` either side: a finger's own curve dips
    far less than the wedge's notch), within ``search_mm`` of ``around_mm`` when given
    (:func:`_notch_mm`); lines fitted to each side of it, between ``near_mm`` of it, are
    then intersected.
    """
    ok = np.isfinite(z_mm)
    if ok.sum() < 10:
        raise ImageError(f"{name}: no skin outline to find the wedge in")
    xs, zs = x_mm[ok], z_mm[ok]
    span = near_mm[1]
    inner = (xs > xs[0] + span) & (xs < xs[-1] - span)
    if around_mm is not None and (inner & (np.abs(xs - around_mm) <= search_mm)).any():
        inner &= np.abs(xs - around_mm) <= search_mm
    if not inner.any():
        raise ImageError(f"{name}: the outline in view is too short to find the wedge in")
    dip = 0.5 * (np.interp(xs - span, xs, zs) + np.interp(xs + span, xs, zs)) - zs
    lowest = xs[inner][np.argmax(dip[inner])]
    # each side near the notch as a quadratic in x (the outline bends there), fitted
    # outside the first 0.1 mm, where the blur rounds the notch; where they cross is the tip
    fits = []
    for sign in (-1.0, 1.0):
        d = sign * (x_mm - lowest)
        pick = ok & (d > near_mm[0]) & (d < near_mm[1])
        if pick.sum() < 6:
            raise ImageError(
                f"{name}: the wedge was not found (no outline on both sides of the notch "
                f"at x = {lowest:.2f} mm; is the wedge pressed in, and in view?)"
            )
        fits.append(np.polyfit(x_mm[pick] - lowest, z_mm[pick], 2))
    left, right = fits
    slopes = (left[1], right[1])
    if not (left[1] < 0 < right[1]):
        raise ImageError(
            f"{name}: the wedge was not found (the outline does not fall to a notch: "
            f"slopes {left[1]:.3f} and {right[1]:.3f} either side of x = {lowest:.2f} mm)"
        )
    roots = np.roots(np.polysub(left, right))
    roots = roots[np.isreal(roots)].real
    roots = roots[np.abs(roots) < near_mm[0] + 0.05]
    if roots.size == 0:  # the two sides do not cross near the notch: their lines do
        return float(lowest + (right[2] - left[2]) / (slopes[0] - slopes[1]))
    return float(lowest + roots[np.argmin(np.abs(roots))])


def profile_rows(depth_mm, trial, magnification):
    """The readings of one digitised trial as rows of the profile contract.

    Parameters
    ----------
    depth_mm : float
        The trial's indentation depth.
    trial : DigitisedTrial
    magnification : float
        The subject's enlargement: readings are written in image units (tissue mm times
        it), as a hand reader's would be, so the workflow converts them alike.

    Returns
    -------
    list of tuple
        ``(depth_mm, side, distance_image_mm, deflection_image_mm)``, left side first,
        each side by distance.
    """
    rows = []
    for side in ("left", "right"):
        distance, deflection = trial.readings[side]
        for d, w in zip(distance, deflection, strict=True):
            rows.append((float(depth_mm), side, float(d) * magnification, float(w) * magnification))
    return rows


def truth_error_um(trial, truth, window_mm):
    """RMS difference (um) between the readings and the truth over the fit window, both
    sides together; None without a truth.

    Parameters
    ----------
    trial : DigitisedTrial
    truth : dict
        Side -> ``(distance_mm, deflection_mm)`` of the true profile (interpolated at
        the readings' distances).
    window_mm : float
        The fit window: readings at or within it count.
    """
    errors = []
    for side, (distance, deflection) in trial.readings.items():
        if side not in truth:
            continue
        inside = distance <= window_mm
        true = np.interp(distance[inside], *truth[side])
        errors.extend(deflection[inside] - true)
    if not errors:
        return None
    return float(1000 * np.sqrt(np.mean(np.square(errors))))


def own_reading_sd_mm(trial, window_mm):
    """The RMS of a trial's readings' own SDs within the fit window (both sides), or
    None where it states none: what the fits take as its ``reading_sd_mm``."""
    if not trial.reading_sds_mm:
        return None
    sds = np.concatenate(
        [
            trial.reading_sds_mm[side][trial.readings[side][0] <= window_mm]
            for side in ("left", "right")
        ]
    )
    return float(np.sqrt(np.mean(sds**2))) if sds.size else None


def quality_record(depth_mm, trial, truth=None, window_mm=3.0):
    """What a reviewer needs to judge one digitised trial, JSON-ready (mm and um); with
    a truth (side -> distances and deflections), the readings' RMS error against it over
    the fit window (``error_rms_um``, else None).  ``registration_sd_um`` and
    ``own_reading_sd_um`` (:func:`own_reading_sd_mm`) are what the fits take for the
    trial's shared offset and reading error (:func:`lineload.noise.registration_rows`)."""
    error = truth_error_um(trial, truth, window_mm) if truth else None
    own = own_reading_sd_mm(trial, window_mm)
    return {
        "error_rms_um": None if error is None else round(error, 3),
        "depth_mm": float(depth_mm),
        "tip_x_mm": round(trial.tip_x_mm, 6),
        "shift_x_mm": round(trial.shift_mm[0], 6),
        "shift_z_mm": round(trial.shift_mm[1], 6),
        "registration_rms_um": round(1000 * trial.registration_rms_mm, 3),
        "edge_noise_um": round(1000 * trial.edge_noise_mm, 3),
        "reading_sd_um": round(1000 * trial.reading_sd_mm, 3),
        "registration_sd_um": round(1000 * trial.registration_sd_mm, 3),
        # the readings' own SD over the fit window: the trial's reading_sd_mm in the fits
        "own_reading_sd_um": None if own is None else round(1000 * own, 3),
        "tip_sd_um": None if trial.tip_sd_mm is None else round(1000 * trial.tip_sd_mm, 3),
        "readings": {side: len(trial.readings[side][0]) for side in ("left", "right")},
        "unread": {
            side: [
                {"distance_mm": round(distance, 4), "reason": reason}
                for distance, reason in (trial.unread or {}).get(side, [])
            ]
            for side in ("left", "right")
        },
        "first_read_mm": {
            side: round(float(trial.readings[side][0][0]), 4)
            if len(trial.readings[side][0])
            else None
            for side in ("left", "right")
        },
    }
