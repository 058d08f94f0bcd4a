"""Photograph files as the data contract admits them: their size and levels checked from
the header, read as greyscale floats in [0, 1] (colour converted, alpha left out); the
field of view of a photograph (:class:`Scene`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from skimage import img_as_float64
from skimage.color import rgb2gray

__all__ = [
    "MAX_PIXELS",
    "MODE_WORDS",
    "READABLE_MODES",
    "ImageError",
    "Scene",
    "photograph_problem",
    "read_photograph",
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


class ImageError(ValueError):
    """An image that cannot be digitised; the message names it and says why."""


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
