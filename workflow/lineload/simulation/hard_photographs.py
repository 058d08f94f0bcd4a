"""Hard photographs: side views of a fingertip as a lab's bench takes them, for testing.

A second renderer, written apart from
:func:`lineload.simulation.photograph_render.render_photograph` so that the digitiser is not tested
only on pictures made the way it was built.  What differs from that renderer:

* the profile: each side of the wedge has its own membrane length ``L``; the shape is the
  exact zero-area circular arc (:func:`lineload.models.arc_deflection_mm`) or a blend of
  the small-slope parabola (eq. 19) with a logarithmic fall
  ``1 - ln(1 + k x / L) / ln(1 + k)`` (a Boussinesq-like ``ln(1 / x)`` kept finite at
  the wedge), steeper at the wedge than the parabola; at 2 mm depth the notch's sides are steep;
* the optics: anti-aliasing by the distance to the edge across it (not by sub-columns);
  a disc (defocus) or a Gaussian blur of several pixels; photon noise (Poisson, from a
  full-well count) and read noise; strong vignetting (radial) and a lighting gradient;
  a small camera rotation shared by both shots; gamma encoding; 8 or 16 bits; grey or
  colour;
* what a lab adds: a burned-in scale bar with end ticks, or a ruler, with or without a
  text label (drawn by Pillow after encoding, sharp, as software draws it), in a corner,
  above the skin or beside the wedge; the wedge seen in the resting view too, lifted
  clear of the skin; glare that may saturate; a shift of the finger between the shots.

Coordinates: tissue ``x`` to the right and ``z`` upward (mm), the wedge's tip at
``x = tip_x_mm``; image pixel ``(row, column)`` has its centre at ``u = (column + 0.5) /
ppmm``, ``v = -(row + 0.5) / ppmm`` before the camera's rotation about the image centre.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np
from scipy import ndimage

from lineload.models import arc_deflection_mm, waterbed_deflection_mm

__all__ = [
    "BAR_PLACES",
    "HardCase",
    "draw_case",
    "render_pair",
    "true_deflection_mm",
]

#: Where a lab puts its scale bar: the four corners (the lower two over the finger),
#: in the background above the skin near the wedge, and beside the wedge.
BAR_PLACES = (
    "top-left",
    "top-right",
    "bottom-left",
    "bottom-right",
    "above-skin",
    "beside-wedge",
)


@dataclass(frozen=True)
class HardCase:
    """One photographed trial and its camera (see the module's notes).

    Attributes
    ----------
    depth_mm : float
        Indentation depth (mm).
    L_left_mm, L_right_mm : float
        Each side's membrane length (mm).
    shape : str
        ``arc`` (exact circular arc) or ``blend`` (parabola and logarithmic fall).
    blend : float
        Share of the logarithmic fall in a ``blend`` (0-1).
    log_k : float
        Steepness of the logarithmic fall (``k`` in ``1 - ln(1 + k x / L) / ln(1 + k)``;
        its slope at the wedge is ``W0 k / (L ln(1 + k))``).
    radius_mm : float
        The resting finger's radius of curvature (mm).
    pixels_per_mm : float
        Scale.
    width_px, height_px : int
        Image size.
    tip_u_mm, skin_v_mm : float
        Where the wedge's tip and the resting skin's top lie in the unrotated image
        (mm from its left edge; mm below its top edge, as a positive number).
    blur : str
        ``disc`` (defocus) or ``gaussian``.
    blur_px : float
        The disc's radius or the Gaussian's SD (pixels).
    full_well : float
        Photons at full scale (photon noise); 0 for none.
    read_noise : float
        Read noise SD (fraction of full scale).
    vignetting : float
        Fraction of light lost at the image's corners (radial, quadratic).
    gradient : float
        Brightness changes by this fraction from left to right.
    rotation_deg : float
        The camera turned (degrees, counter-clockwise), the same for both shots.
    gamma : float
        Encoding exponent: the stored level is ``linear ** (1 / gamma)``.
    bits : int
        8 or 16.
    colour : bool
        RGB (skin reddish) or grey.
    bar : str or None
        Where the scale bar is drawn (:data:`BAR_PLACES`), or None.
    bar_kind : str
        ``bar`` (a line with end ticks) or ``ruler`` (ticks every 0.5 mm).
    label : bool
        A text label (``1 mm``) beside the bar.
    rest_gap_mm : float or None
        Height of the wedge's tip above the skin in the resting view; None: no wedge
        there.
    glare : float
        Brightening of the skin at the tip in the loaded view (fraction of full scale;
        above ``1 - skin`` it saturates).
    shift_mm : tuple of float
        ``(du, dv)``: how far the finger moved between the shots (the loaded view's).
    """

    depth_mm: float
    L_left_mm: float
    L_right_mm: float
    shape: str = "arc"
    blend: float = 0.5
    log_k: float = 8.0
    radius_mm: float = 20.0
    pixels_per_mm: float = 80.0
    width_px: int = 1600
    height_px: int = 420
    tip_u_mm: float = 10.0
    skin_v_mm: float = 2.5
    blur: str = "disc"
    blur_px: float = 3.0
    full_well: float = 5000.0
    read_noise: float = 0.005
    vignetting: float = 0.4
    gradient: float = 0.3
    rotation_deg: float = 0.0
    gamma: float = 2.2
    bits: int = 8
    colour: bool = False
    bar: str | None = "top-left"
    bar_kind: str = "bar"
    label: bool = True
    rest_gap_mm: float | None = 0.5
    glare: float = 0.3
    shift_mm: tuple = (0.0, 0.0)

    @property
    def L_mm(self):
        """Side -> membrane length."""
        return {"left": self.L_left_mm, "right": self.L_right_mm}


def true_deflection_mm(case, side, distance_mm):
    """The true downward deflection of one side at ``distance_mm`` from the tip (mm).

    Parameters
    ----------
    case : HardCase
    side : str
        ``left`` or ``right``.
    distance_mm : array_like
        Distances from the tip (mm, >= 0).

    Returns
    -------
    numpy.ndarray
        Zero beyond the side's ``L``.
    """
    d = np.abs(np.asarray(distance_mm, dtype=float))
    L_mm = case.L_mm[side]
    if case.shape == "arc":
        return arc_deflection_mm(d, case.depth_mm, L_mm)
    parabola = waterbed_deflection_mm(d, case.depth_mm, L_mm)
    s = np.clip(d / L_mm, 0.0, 1.0)
    fall = case.depth_mm * (1.0 - np.log1p(case.log_k * s) / np.log1p(case.log_k))
    return np.where(d <= L_mm, (1.0 - case.blend) * parabola + case.blend * fall, 0.0)


def _surface(case, x_mm, loaded):
    """Height of the skin (mm, up) at tissue ``x_mm``, and its slope."""
    rel = x_mm - case.tip_u_mm
    z = -(case.radius_mm - np.sqrt(np.maximum(case.radius_mm**2 - rel**2, 0.0)))
    if loaded:
        left = true_deflection_mm(case, "left", rel)
        right = true_deflection_mm(case, "right", rel)
        z = z - np.where(rel < 0, left, right)
    return z


def _pixel_tissue_mm(case, shift_mm):
    """Tissue (x, z) of every pixel centre: the image turned back by the camera's
    rotation about its centre, and moved back by the finger's shift."""
    ppmm = case.pixels_per_mm
    u = (np.arange(case.width_px) + 0.5)[None, :] / ppmm
    v = -(np.arange(case.height_px) + 0.5)[:, None] / ppmm
    uc, vc = case.width_px / ppmm / 2, -case.height_px / ppmm / 2
    theta = np.radians(case.rotation_deg)
    du, dv = u - uc, v - vc
    x = uc + du * np.cos(theta) + dv * np.sin(theta) - shift_mm[0]
    z = vc - du * np.sin(theta) + dv * np.cos(theta) - shift_mm[1]
    # tissue z = 0 at the resting skin's top, skin_v_mm below the image's top edge
    return x, z + case.skin_v_mm


def _coverage(height_mm, slope, ppmm):
    """Fraction of a pixel inside a region whose edge lies ``height_mm`` above the pixel
    centre (vertically) with the given slope: the distance across the edge, as a ramp
    one pixel wide."""
    across_px = height_mm * ppmm / np.sqrt(1.0 + slope**2)
    return np.clip(0.5 + across_px, 0.0, 1.0)


def _scene_linear(case, loaded, rng):
    """Reflectance of the scene (before light and optics), shape (h, w, 3) linear."""
    ppmm = case.pixels_per_mm
    shift = case.shift_mm if loaded else (0.0, 0.0)
    x, z = _pixel_tissue_mm(case, shift)
    step = 1e-3
    surface = _surface(case, x, loaded)
    slope = (_surface(case, x + step, loaded) - _surface(case, x - step, loaded)) / (2 * step)
    skin = _coverage(surface - z, slope, ppmm)
    # the wedge: its faces open upward from the tip (half-angle 20 deg)
    tip_z = -case.depth_mm if loaded else case.rest_gap_mm
    wedge = np.zeros_like(skin)
    if loaded or case.rest_gap_mm is not None:
        cot = 1.0 / np.tan(np.radians(20.0))
        bottom = tip_z + cot * np.abs(x - case.tip_u_mm)
        wedge = _coverage(z - bottom, cot, ppmm) * (1.0 - skin)
    background = np.clip(1.0 - skin - wedge, 0.0, 1.0)
    texture = ndimage.gaussian_filter(rng.standard_normal(skin.shape), 2.5)
    texture *= 0.03 / max(float(texture.std()), 1e-12)
    if case.colour:
        skin_rgb = np.array([0.55, 0.26, 0.2])
        back_rgb = np.array([0.86, 0.88, 0.93])
        wedge_rgb = np.array([0.5, 0.5, 0.48])
    else:
        skin_rgb, back_rgb, wedge_rgb = (np.full(3, level) for level in (0.28, 0.88, 0.52))
    skin_level = skin_rgb[None, None, :] * (1.0 + texture[..., None] / 0.28)
    if loaded and case.glare > 0:
        below = np.clip(surface - z, 0.0, None)
        glow = case.glare * np.exp(
            -0.5 * ((x - case.tip_u_mm) / 0.25) ** 2 - 0.5 * (below / 0.25) ** 2
        )
        skin_level = skin_level + glow[..., None]
    return (
        skin[..., None] * skin_level
        + wedge[..., None] * wedge_rgb[None, None, :]
        + background[..., None] * back_rgb[None, None, :]
    )


def _blurred(image, case):
    """The optics' blur: a disc of ``blur_px`` radius (defocus) or a Gaussian."""
    if case.blur == "gaussian":
        return ndimage.gaussian_filter(image, (case.blur_px, case.blur_px, 0))
    r = case.blur_px
    n = int(np.ceil(r))
    yy, xx = np.mgrid[-n : n + 1, -n : n + 1]
    # the disc's area in each kernel pixel, from 4 x 4 sub-samples
    sub = (np.arange(4) + 0.5) / 4 - 0.5
    inside = (
        (xx[..., None, None] + sub[None, None, :, None]) ** 2
        + (yy[..., None, None] + sub[None, None, None, :]) ** 2
    ) <= r * r
    kernel = inside.mean(axis=(2, 3))
    kernel /= kernel.sum()
    return np.stack(
        [ndimage.convolve(image[..., c], kernel, mode="nearest") for c in range(3)], axis=-1
    )


def _lit(image, case):
    """Vignetting (radial, quadratic, ``vignetting`` lost at the corners) and a
    left-to-right gradient."""
    h, w = case.height_px, case.width_px
    yy = (np.arange(h) + 0.5 - h / 2)[:, None]
    xx = (np.arange(w) + 0.5 - w / 2)[None, :]
    radius2 = (xx**2 + yy**2) / ((w / 2) ** 2 + (h / 2) ** 2)
    light = (1.0 - case.vignetting * radius2) * (1.0 + case.gradient * (xx / w))
    return image * light[..., None]


def _bar_box(case, tip_column, skin_row):
    """Top-left pixel of the scale bar's drawing and its length (pixels)."""
    ppmm = case.pixels_per_mm
    length = round(ppmm * (1.0 if case.width_px / ppmm < 20 else 2.0))
    margin = 25
    places = {
        "top-left": (margin, margin + 10),
        "top-right": (case.width_px - margin - length, margin + 10),
        "bottom-left": (margin, case.height_px - margin - 10),
        "bottom-right": (case.width_px - margin - length, case.height_px - margin - 10),
        # in the background above the skin, between the wedge and the view's edge
        "above-skin": (tip_column + int(1.5 * ppmm), max(skin_row - int(0.9 * ppmm), 20)),
        # just beside the wedge's face, level with its lower part
        "beside-wedge": (
            tip_column - int(0.9 * ppmm) - length,
            max(skin_row - int(0.5 * ppmm), 20),
        ),
    }
    return places[case.bar], length


def _draw_bar(image, case, tip_column, skin_row):
    """Burn the scale bar (and label) into an encoded image, as software does: sharp,
    in black over the background and in white over the finger."""
    from PIL import Image, ImageDraw

    (left, row), length = _bar_box(case, tip_column, skin_row)
    top = 2**case.bits - 1
    over_skin = case.bar.startswith("bottom")
    ink = top if over_skin else 0
    thick = max(2, round(case.pixels_per_mm * 0.04))
    tick = 4 * thick
    canvas = np.zeros(image.shape[:2], dtype=np.uint8)
    mask = Image.fromarray(canvas)
    draw = ImageDraw.Draw(mask)
    draw.rectangle([left, row, left + length, row + thick - 1], fill=255)
    ends = (0, length) if case.bar_kind == "bar" else range(0, length + 1, max(length // 4, 1))
    for k, at in enumerate(ends):
        height = tick if (case.bar_kind == "bar" or k % 2 == 0) else tick // 2
        draw.rectangle(
            [left + at - thick // 2, row - height, left + at + thick // 2, row], fill=255
        )
    if case.label:
        text = "1 mm" if length < 1.5 * case.pixels_per_mm else "2 mm"
        draw.text((left + length // 2 - 12, row + thick + 3), text, fill=255)
    painted = np.asarray(mask) > 0
    image[painted] = ink
    return image


def _encoded(linear, case, rng):
    """Photon and read noise, gamma encoding and quantisation to the case's bits."""
    signal = np.clip(linear, 0.0, None)
    if case.full_well > 0:
        signal = rng.poisson(signal * case.full_well) / case.full_well
    signal = signal + case.read_noise * rng.standard_normal(signal.shape)
    encoded = np.clip(signal, 0.0, 1.0) ** (1.0 / case.gamma)
    top = 2**case.bits - 1
    return np.rint(encoded * top).astype(np.uint8 if case.bits == 8 else np.uint16)


def render_pair(case, rng):
    """The resting and the loaded photograph of ``case``, and where the tip is.

    Parameters
    ----------
    case : HardCase
    rng : numpy.random.Generator
        Texture and noise.

    Returns
    -------
    tuple
        ``(rest, loaded, tip_column)``: two images (``(h, w)`` grey or ``(h, w, 3)``
        colour, uint8 or uint16) and the tip's column (pixel units, centre of column 0
        at 0.0) in the loaded image.
    """
    ppmm = case.pixels_per_mm
    theta = np.radians(case.rotation_deg)
    # where the tip lands in the loaded image: tissue -> image (rotation about centre)
    uc, vc = case.width_px / ppmm / 2, -case.height_px / ppmm / 2
    tx = case.tip_u_mm + case.shift_mm[0] - uc
    tz = -case.depth_mm - case.skin_v_mm + case.shift_mm[1] - vc
    tip_u = uc + tx * np.cos(theta) - tz * np.sin(theta)
    tip_column = tip_u * ppmm - 0.5
    skin_row = int(case.skin_v_mm * ppmm)
    images = []
    for loaded in (False, True):
        linear = _lit(_blurred(_scene_linear(case, loaded, rng), case), case)
        image = _encoded(linear, case, rng)
        if case.bar is not None:
            image = _draw_bar(image, case, round(tip_column), skin_row)
        images.append(image if case.colour else image[..., 0])
    return images[0], images[1], float(tip_column)


def draw_case(rng, **fixed):
    """A hard case drawn at random (what a lab's bench varies), any field fixed.

    Depths 0.5-2 mm; each side's ``L`` 6-12 mm on its own; arcs and blends; 60-100
    pixels a mm; disc or Gaussian blur of 1.5-4 pixels; 2,000-20,000 photons at full
    scale and read noise up to 1 %; 20-50 % vignetting; a gradient of 10-40 %; the
    camera turned by up to 0.5 deg; gamma 1 or 2.2; 8 or 16 bits; grey or colour; a
    scale bar in any of :data:`BAR_PLACES` (or none), as a bar or a ruler, labelled or
    not; the wedge in the resting view half the time; glare up to saturation; the finger
    moved by up to 50 um between the shots; a resting radius of 25-80 mm.
    """
    depth = float(rng.choice([0.5, 1.0, 1.5, 2.0]))
    L_left, L_right = rng.uniform(6.0, 12.0, size=2)
    ppmm = float(rng.uniform(60.0, 100.0))
    reach = max(L_left, L_right)
    width_mm = 2 * (reach + 2.5)
    radius = float(rng.uniform(25.0, 80.0))
    # tall enough that the finger's sides stay in view with 1 mm below them
    drop_mm = radius - np.sqrt(radius**2 - (width_mm / 2 + 0.5) ** 2)
    case = HardCase(
        depth_mm=depth,
        L_left_mm=float(L_left),
        L_right_mm=float(L_right),
        shape=str(rng.choice(["arc", "blend"])),
        blend=float(rng.uniform(0.2, 0.7)),
        log_k=float(rng.uniform(3.0, 15.0)),
        radius_mm=radius,
        pixels_per_mm=ppmm,
        width_px=int(width_mm * ppmm),
        height_px=int((1.8 + max(depth, drop_mm) + 1.0) * ppmm),
        tip_u_mm=width_mm / 2 + float(rng.uniform(-0.3, 0.3)),
        skin_v_mm=1.8,
        blur=str(rng.choice(["disc", "gaussian"])),
        blur_px=float(rng.uniform(1.5, 4.0)),
        full_well=float(rng.uniform(2000.0, 20000.0)),
        read_noise=float(rng.uniform(0.0, 0.01)),
        vignetting=float(rng.uniform(0.2, 0.5)),
        gradient=float(rng.uniform(0.1, 0.4)),
        rotation_deg=float(rng.uniform(-0.5, 0.5)),
        gamma=float(rng.choice([1.0, 2.2])),
        bits=int(rng.choice([8, 16])),
        colour=bool(rng.integers(2)),
        bar=[*BAR_PLACES, None][int(rng.integers(len(BAR_PLACES) + 1))],
        bar_kind=str(rng.choice(["bar", "ruler"])),
        label=bool(rng.integers(2)),
        rest_gap_mm=float(rng.uniform(0.2, 1.0)) if rng.integers(2) else None,
        glare=float(rng.uniform(0.1, 0.8)),
        shift_mm=(float(rng.uniform(-0.05, 0.05)), float(rng.uniform(-0.05, 0.05))),
    )
    if case.colour:  # the contract's colour is 8-bit (Pillow writes no 16-bit RGB)
        case = replace(case, bits=8)
    return replace(case, **fixed)
