"""Side views of a finger as a camera takes them: the renderer of the photograph
example and of the digitiser's calibration (blur, sensor noise, uneven light, a
textured skin, glare near the wedge, 8- or 16-bit levels).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from skimage import filters

__all__ = ["BACKGROUND_LEVEL", "SKIN_LEVEL", "WEDGE_LEVEL", "Camera", "render_photograph"]

#: Brightness of the plain background, the skin and the wedge (fractions of full scale).
BACKGROUND_LEVEL = 0.88


SKIN_LEVEL = 0.22


WEDGE_LEVEL = 0.55


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
