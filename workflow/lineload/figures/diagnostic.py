"""A refused photograph pair drawn as the digitiser saw it: the diagnostic image.

When the digitiser refuses a pair (:class:`lineload.rawdata.photographs.ImageError`, or a
trial that is no plausible indentation, :func:`lineload.rawdata.photographs.trial_problem`),
the job that read it writes this image beside its log (:func:`beside`) and the refusal
names it.
Each refused pair is one panel: the photograph the problem was found in (grey), the
skin's edge as traced in each column (cyan, the loaded photograph's; yellow dashes, the
resting one's), the columns left out and why in short (red ticks along the top: glare,
no edge, an overlay), the region the wedge's apex was sought in (magenta box), the
apex seen there (orange dashes), the regions the config excludes (red hatching), the tip
placed (green line) and the columns
beyond ``reach_mm`` the two photographs are registered on (white dotted lines at the
limits), with the refusal's first words as the panel's title.

Standard library and matplotlib only (Agg, no pandas), so a raw-data check can draw it;
no time stamp or version string is written, so the same refusal gives the same bytes.
"""

from __future__ import annotations

import textwrap

import numpy as np

__all__ = ["MAX_PANELS", "Refusals", "beside", "draw_refusals"]

#: Refused pairs one image draws (one panel each); a job refusing more names the image
#: only for these.
MAX_PANELS = 6


def _grey(image):
    """The photograph as grey levels in 0-1 (colour averaged, alpha dropped)."""
    values = np.asarray(image)
    top = float(np.iinfo(values.dtype).max) if values.dtype.kind in "ui" else 1.0
    values = values.astype(float) / top
    if values.ndim == 3:
        values = values[..., :3].mean(axis=2)
    return values


def _panel(ax, image, seen, message):
    scene = seen["scene"]
    ppmm = scene.pixels_per_mm
    x0, z0 = scene.x0_mm, scene.z0_mm
    x1, z1 = x0 + scene.width_px / ppmm, z0 - scene.height_px / ppmm
    ax.imshow(_grey(image), cmap="gray", vmin=0, vmax=1, extent=(x0, x1, z1, z0), aspect="auto")
    x = scene.column_x_mm
    failed = seen.get("failed", 1)
    traced = seen.get("loaded_mm") if failed == 1 else seen.get("rest_mm")
    if traced is not None:
        ax.plot(x, traced, color="cyan", lw=0.6, label="edge traced")
    if failed == 1 and seen.get("rest_mm") is not None:
        ax.plot(x, seen["rest_mm"], color="yellow", lw=0.5, ls="--", label="resting edge")
    why = seen.get("why")
    if why is not None:
        left_out = np.flatnonzero(why != "")
        if left_out.size:
            ax.plot(
                x[left_out],
                np.full(left_out.size, z0 - 0.03 * (z0 - z1)),
                "|",
                color="red",
                ms=4,
                mew=0.6,
                label=f"columns left out ({left_out.size})",
            )
    for left, top, right, bottom in seen.get("exclude_px") or ():
        ax.fill_between(
            [x0 + left / ppmm, x0 + right / ppmm],
            z0 - top / ppmm,
            z0 - bottom / ppmm,
            facecolor="none",
            edgecolor="red",
            hatch="////",
            lw=0.5,
            label="excluded",
        )
    if seen.get("apex_region_mm") is not None:
        lo, hi = seen["apex_region_mm"]
        skin = traced[(x >= lo) & (x <= hi)] if traced is not None else np.array([])
        bottom = float(np.nanmax(skin)) if np.isfinite(skin).any() else z1
        ax.plot(
            [lo, hi, hi, lo, lo],
            [z0, z0, bottom, bottom, z0],
            color="magenta",
            lw=0.7,
            ls="--",
            label="apex sought",
        )
    if seen.get("apex_x_mm") is not None:
        ax.axvline(seen["apex_x_mm"], color="orange", lw=0.7, ls="--", label="apex seen")
    tip = seen.get("tip_x_mm")
    if tip is not None:
        ax.axvline(tip, color="lime", lw=0.7, label="tip placed")
        for side in (-1.0, 1.0):
            ax.axvline(tip + side * seen["reach_mm"], color="white", lw=0.6, ls=":")
    ax.set_xlim(x0, x1)
    ax.set_ylim(z1, z0)
    ax.set_xlabel("x (mm)", fontsize=6)
    ax.set_ylabel("z (mm)", fontsize=6)
    ax.tick_params(labelsize=5)
    ax.set_title("\n".join(textwrap.wrap(message, 150)[:3]), fontsize=5.5, loc="left")
    ax.legend(fontsize=5, loc="lower left", framealpha=0.6, ncols=3)


def draw_refusals(panels, path):
    """Write one PNG of the refused pairs in ``panels`` (at most :data:`MAX_PANELS`).

    Parameters
    ----------
    panels : list of tuple
        ``(image, seen, message)`` per refused pair: the photograph the problem was found
        in, what the digitiser saw (``seen`` of the error or the trial) and the refusal.
    path : str or os.PathLike
        The PNG's path (its folder is made).
    """
    import os

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    panels = list(panels)[:MAX_PANELS]
    fig = Figure(figsize=(7.0, 2.6 * len(panels)), dpi=100, layout="constrained")
    FigureCanvasAgg(fig)
    for ax, (image, seen, message) in zip(
        np.atleast_1d(fig.subplots(len(panels), 1)), panels, strict=True
    ):
        _panel(ax, image, seen, message)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, format="png", metadata={"Software": None})


def beside(log_path):
    """Where a job draws its refused pairs: a PNG of the same name beside its log.

    Not declared to Snakemake (which would leave an empty file where nothing was
    refused, and list it among the logs); the job removes a former run's itself."""
    import os

    return os.path.splitext(str(log_path))[0] + ".png"


class Refusals:
    """The refused pairs of one job, gathered for its diagnostic image at ``path``.

    :meth:`note` takes a refusal and returns its message ending with where the pair is
    drawn (the first :data:`MAX_PANELS` with something seen; the others unchanged);
    :meth:`write` draws them, and writes nothing when none was noted.
    """

    def __init__(self, path):
        self.path = str(path)
        self.panels = []

    def note(self, image, seen, message):
        if image is None or seen is None or len(self.panels) >= MAX_PANELS:
            return message
        self.panels.append((image, seen, message))
        return (
            f"{message}; what the digitiser saw is drawn in {self.path} (panel {len(self.panels)})"
        )

    def write(self):
        if self.panels:
            draw_refusals(self.panels, self.path)
