"""From photographs to readings: the skin's outline found in a side view of the finger.

The study read each profile by hand from two photographs of the fingertip seen along the
wedge, one at rest and one with the wedge pressed in.  This package does that step from
camera images (the example's images are made by
:mod:`lineload.simulation.photograph_render`):

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

Modules: ``files`` (reading a photograph as the contract admits it; :class:`Scene`),
``edges`` (the skin's outline), ``glare`` (columns spoilt near the wedge), ``apex`` (the
wedge's tip), ``uncertainty`` (the stated standard deviations) and ``digitise`` (a pair
read into readings, its quality record and its problems).  The names below are the
package's public face.

Coordinates: ``x`` along the image from left to right, ``z`` upward, both tissue mm;
pixel ``(row, column)`` has its centre at ``x = x0 + (column + 0.5) / ppmm`` and
``z = z0 - (row + 0.5) / ppmm``.  Deflection is downward positive, as in the models.
"""

from lineload.rawdata.photographs.digitise import (
    REGISTRATION_ROUGHNESS_MAX,
    TIP_PIXELS_MAX,
    DigitisedTrial,
    digitise_pair,
    digitise_photographs,
    own_reading_sd_mm,
    profile_rows,
    quality_record,
    trial_problem,
    truth_error_um,
)
from lineload.rawdata.photographs.edges import excluded_mask, skin_outline_mm
from lineload.rawdata.photographs.files import (
    MAX_PIXELS,
    ImageError,
    Scene,
    photograph_problem,
    read_photograph,
)

__all__ = [
    "MAX_PIXELS",
    "REGISTRATION_ROUGHNESS_MAX",
    "TIP_PIXELS_MAX",
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
    "skin_outline_mm",
    "trial_problem",
    "truth_error_um",
]
