"""Figures 3-5: the waterbed model drawn from its own equations (19 and 20).

Nothing here reads data: each figure is drawn at one ratio ``W0 / L`` (the
``schematic_depth_ratio`` of :data:`lineload.figures.registry.ARGUMENTS`), in
units of the membrane half-width ``L``, and returns a
:class:`matplotlib.figure.Figure`.

gids: ``membrane-rest`` and ``membrane-deformed`` (Figures 3 and 4),
``point-initial`` and ``point-final`` (Figure 4), ``footer`` for the footer.
"""

from __future__ import annotations

import numpy as np
from matplotlib import patches
from matplotlib.lines import Line2D

from lineload import models
from lineload.figures.style import (
    DATA_COLOUR,
    MODEL_COLOURS,
    REST_COLOUR,
    SCHEMATIC_MM,
    add_footer,
    new_figure,
    styled,
)

__all__ = [
    "MATERIAL_POINT_X_OVER_L",
    "figure_channel_schematic",
    "figure_free_body",
    "figure_material_point",
    "shift_exaggeration_for",
]

#: Initial coordinate X / L of the material point A that Figure 4 follows.
MATERIAL_POINT_X_OVER_L = 0.2


# ---------------------------------------------------------------- drawing helpers


def _membrane(depth_ratio, n_points=801):
    """Whole membrane (X from -L to L, L = 1) at rest and deformed by eq. 19."""
    X = np.linspace(-1.0, 1.0, n_points)
    W = models.waterbed_deflection_mm(np.abs(X), depth_ratio, 1.0)
    return X, W


def _arrow(ax, start, end, colour="black", width=0.9, head=6.0, **kwargs):
    ax.annotate(
        "",
        xy=end,
        xytext=start,
        arrowprops={
            "arrowstyle": f"-|>,head_length={head / 10:.2f},head_width={head / 20:.2f}",
            "color": colour,
            "linewidth": width,
            "shrinkA": 0,
            "shrinkB": 0,
        },
        **kwargs,
    )


def _dimension(ax, start, end, text, text_offset=(0.0, 0.0), colour="0.25", **text_kwargs):
    """A double-headed dimension arrow with a label at its middle."""
    ax.annotate(
        "",
        xy=end,
        xytext=start,
        arrowprops={
            "arrowstyle": "<|-|>,head_length=0.35,head_width=0.15",
            "color": colour,
            "linewidth": 0.6,
            "shrinkA": 0,
            "shrinkB": 0,
        },
    )
    middle = ((start[0] + end[0]) / 2 + text_offset[0], (start[1] + end[1]) / 2 + text_offset[1])
    ax.text(*middle, text, color=colour, **text_kwargs)


def _same_box_aspect(limits):
    """Widen the y-limits of some panels so every panel has the same height/width.

    Parameters
    ----------
    limits : list of ((x_lo, x_hi), (y_lo, y_hi))

    Returns
    -------
    list of ((x_lo, x_hi), (y_lo, y_hi))
        Equal-aspect panels of equal shape, so their titles line up.
    """
    ratio = max((y[1] - y[0]) / (x[1] - x[0]) for x, y in limits)
    out = []
    for x, y in limits:
        grow = ratio * (x[1] - x[0]) - (y[1] - y[0])
        out.append((x, (y[0] - grow / 2, y[1] + grow / 2)))
    return out


# ---------------------------------------------------------------- Figure 3


@styled
def figure_channel_schematic(schematic_depth_ratio, footer=""):
    """Figure 3: the waterbed model, drawn from eq. 19 at a given W0/L.

    A membrane of half-width ``L`` spans a rigid channel filled with
    incompressible fluid.  The load ``F`` on the axis OZ pushes the membrane
    down by ``W0``; the fluid pressure ``p`` pushes it back up, and the
    membrane bulges beyond ``X = L/3`` to keep the fluid's area.

    Parameters
    ----------
    schematic_depth_ratio : float
        W0 / L at which the deformed membrane is drawn (0 < ratio <= 0.4).
    footer : str
        Footer text; empty for none (the workflow writes that the figure is drawn
        from the equations: the data notice is not a schematic's).

    Returns
    -------
    matplotlib.figure.Figure
        Axes in units of L; the deformed membrane (gid ``membrane-deformed``)
        is ``Z = -W(|X|)`` with W from :func:`lineload.models.waterbed_deflection_mm`.
    """
    r = float(schematic_depth_ratio)
    X, W = _membrane(r)
    floor = -(r + 0.32)
    top = 0.42
    wall = 0.07
    fig = new_figure(SCHEMATIC_MM, 70.0)
    ax = fig.add_subplot()
    fluid = patches.Polygon(
        np.column_stack([np.r_[X, 1.0, -1.0], np.r_[-W, floor, floor]]),
        closed=True,
        facecolor="#d6e9f5",
        edgecolor="none",
        zorder=0,
    )
    ax.add_patch(fluid)
    ax.text(0.5, floor + 0.09, "incompressible fluid", ha="center", va="center", color="0.25")
    for x0 in (-1.0 - wall, 1.0):
        ax.add_patch(
            patches.Rectangle(
                (x0, floor - wall),
                wall,
                top - 0.05 - floor + wall,
                facecolor="0.85",
                edgecolor="0.3",
                hatch="////",
                linewidth=0.6,
            )
        )
    ax.add_patch(
        patches.Rectangle(
            (-1.0 - wall, floor - wall),
            2 + 2 * wall,
            wall,
            facecolor="0.85",
            edgecolor="0.3",
            hatch="////",
            linewidth=0.6,
        )
    )
    ax.text(1.0 + wall / 2, top - 0.02, "rigid wall", ha="center", va="bottom")
    ax.text(-1.0 - wall / 2, top - 0.02, "rigid wall", ha="center", va="bottom")
    ax.plot(
        [-1.0, 1.0],
        [0.0, 0.0],
        color=REST_COLOUR,
        linestyle="--",
        linewidth=1.0,
        gid="membrane-rest",
    )
    ax.plot(X, -W, color=DATA_COLOUR, linewidth=1.5, gid="membrane-deformed")
    # load axis OZ and the load F
    ax.plot([0, 0], [floor, top], color="0.35", linestyle="-.", linewidth=0.6, zorder=1)
    ax.text(0.015, top, "Z", ha="left", va="top")
    ax.text(-0.02, 0.015, "O", ha="right", va="bottom")
    _arrow(ax, (0.0, 0.3), (0.0, -r), colour="#b2182b", width=1.4, head=8)
    ax.text(0.02, 0.27, "F", color="#b2182b", ha="left", va="center", fontsize=9, fontweight="bold")
    # pressure p: normal to the membrane, from the fluid side
    for x_p in (-0.9, -0.72, -0.55, -0.38, 0.38, 0.55, 0.72, 0.9):
        z_p = -float(models.waterbed_deflection_mm(abs(x_p), r, 1.0))
        slope_W = r * (6 * abs(x_p) - 4)  # dW/d|X|
        normal = np.array([np.sign(x_p) * slope_W, 1.0])
        normal /= np.hypot(*normal)
        start = np.array([x_p, z_p]) - 0.11 * normal
        _arrow(ax, tuple(start), (x_p, z_p), colour=MODEL_COLOURS["waterbed"], width=0.8, head=5)
    ax.text(
        -0.55,
        -float(models.waterbed_deflection_mm(0.55, r, 1.0)) - 0.14,
        "p",
        color=MODEL_COLOURS["waterbed"],
        ha="center",
        va="top",
        fontsize=9,
        fontstyle="italic",
    )
    # dimensions
    _dimension(ax, (0.0, 0.2), (1.0, 0.2), "L", text_offset=(0, 0.012), ha="center", va="bottom")
    ax.annotate(
        "",
        xy=(-0.035, -r),
        xytext=(-0.035, 0.0),
        arrowprops={
            "arrowstyle": "<|-|>,head_length=0.35,head_width=0.15",
            "color": "0.25",
            "linewidth": 0.6,
            "shrinkA": 0,
            "shrinkB": 0,
        },
    )
    ax.plot([-0.06, 0.0], [-r, -r], color="0.5", linewidth=0.5)
    ax.text(-0.05, -0.3 * r, "W₀", color="0.25", ha="right", va="center")
    ax.annotate(
        "membrane at rest",
        xy=(-0.8, 0.0),
        xytext=(-0.9, 0.12),
        ha="left",  # clear of the wall
        arrowprops={"arrowstyle": "-", "color": "0.4", "linewidth": 0.6},
    )
    ax.annotate(
        "deformed membrane",
        xy=(0.25, -float(models.waterbed_deflection_mm(0.25, r, 1))),
        xytext=(0.3, floor + 0.2),
        ha="left",
        arrowprops={"arrowstyle": "-", "color": "0.4", "linewidth": 0.6},
    )
    ax.text(
        -1.0,
        floor - wall - 0.02,
        f"deformed shape: eq. 19 drawn at W₀/L = {r:g}; resting membrane dashed",
        ha="left",
        va="top",
    )
    ax.set_aspect("equal")
    ax.set_xlim(-1.0 - wall - 0.12, 1.0 + wall + 0.12)
    ax.set_ylim(floor - wall - 0.12, top + 0.07)
    ax.set_xlabel("X / L")
    ax.set_ylabel("Z / L (height; W = −Z)")
    add_footer(fig, footer)
    return fig


# ---------------------------------------------------------------- Figure 4


def shift_exaggeration_for(depth_ratio, point_X_over_L, target_fraction=0.35):
    """Smallest 1-2-5 factor that makes the shift U visible at a point.

    Parameters
    ----------
    depth_ratio : float
        W0 / L.
    point_X_over_L : float
        Initial coordinate of the point, X / L.
    target_fraction : float
        The drawn shift should reach at least this fraction of X.

    Returns
    -------
    int
        1, 2, 5, 10, 20, 50, ... (1 when the shift is already visible).
    """
    shift = abs(float(models.waterbed_shift_mm(point_X_over_L, depth_ratio, 1.0)))
    wanted = target_fraction * point_X_over_L
    for exponent in range(7):
        for mantissa in (1, 2, 5):
            factor = mantissa * 10**exponent
            if factor * shift >= wanted:
                return factor
    return 10**7


@styled
def figure_material_point(schematic_depth_ratio, footer=""):
    """Figure 4: a material point at (X, 0) moves to (X + U, W) (eqs. 19 and 20).

    Parameters
    ----------
    schematic_depth_ratio : float
        W0 / L at which the membrane is drawn.
    footer : str
        Footer text; empty for none (the workflow writes that the figure is drawn
        from the equations: the data notice is not a schematic's).

    Returns
    -------
    matplotlib.figure.Figure
        Half the membrane (0 <= X <= L), axes in units of L.  The deformed
        curve (gid ``membrane-deformed``) is ``(X + k U(X), -W(X))`` with k
        the exaggeration of :func:`shift_exaggeration_for` at the point A,
        ``X = MATERIAL_POINT_X_OVER_L * L`` (gids ``point-initial`` and
        ``point-final``).
    """
    r = float(schematic_depth_ratio)
    X_A = MATERIAL_POINT_X_OVER_L
    # U is a few percent of X: drawn larger by a round factor, stated on the figure
    k = shift_exaggeration_for(r, X_A)
    X = np.linspace(0.0, 1.0, 401)
    W = models.waterbed_deflection_mm(X, r, 1.0)
    U = models.waterbed_shift_mm(X, r, 1.0)
    W_A = float(models.waterbed_deflection_mm(X_A, r, 1.0))
    U_A = float(models.waterbed_shift_mm(X_A, r, 1.0))
    x_A = X_A + k * U_A
    fig = new_figure(SCHEMATIC_MM, 62.0)
    ax = fig.add_subplot()
    ax.plot(
        [0.0, 1.0],
        [0.0, 0.0],
        color=REST_COLOUR,
        linestyle="--",
        linewidth=1.0,
        gid="membrane-rest",
    )
    ax.plot(X + k * U, -W, color=DATA_COLOUR, linewidth=1.5, gid="membrane-deformed")
    ax.plot([0, 0], [-r - 0.1, 0.16], color="0.35", linestyle="-.", linewidth=0.6)
    ax.text(-0.012, 0.005, "O", ha="right", va="bottom")
    ax.plot(
        [X_A],
        [0.0],
        marker="o",
        markersize=5,
        markerfacecolor="white",
        markeredgecolor=DATA_COLOUR,
        linestyle="none",
        gid="point-initial",
        zorder=4,
    )
    ax.plot(
        [x_A],
        [-W_A],
        marker="o",
        markersize=5,
        color=DATA_COLOUR,
        linestyle="none",
        gid="point-final",
        zorder=4,
    )
    ax.text(X_A + 0.015, 0.045, "A at (X, 0)", ha="left", va="bottom")
    ax.text(x_A + 0.015, -W_A - 0.012, "A after loading: (X + U, W)", ha="left", va="top")
    _arrow(ax, (X_A, 0.0), (x_A, -W_A), colour="#b2182b", width=0.9, head=5)
    # dimensions: X above the rest line, x below the deformed point
    _dimension(ax, (0.0, 0.1), (X_A, 0.1), "X", text_offset=(0, 0.01), ha="center", va="bottom")
    ax.plot([X_A, X_A], [0.0, 0.1], color="0.6", linewidth=0.5)
    y_x = -r - 0.06
    _dimension(
        ax, (0.0, y_x), (x_A, y_x), "x = X + U", text_offset=(0.0, -0.012), ha="left", va="top"
    )
    ax.plot([x_A, x_A], [-W_A, y_x], color="0.6", linewidth=0.5)
    _dimension(
        ax,
        (x_A - 0.03, 0.0),
        (x_A - 0.03, -W_A),
        "W",
        text_offset=(-0.01, 0),
        ha="right",
        va="center",
    )
    ax.plot([x_A - 0.04, x_A + 0.01], [0.0, 0.0], color="0.6", linewidth=0.5)
    largest = 8 * r**2 / 9
    ax.text(
        1.0,
        -r - 0.1,
        # (the magnification is in the legend) short lines, clear of the axis at X = 0
        f"drawn from eqs. 19 and 20 at W₀/L = {r:g}\ntrue shift at A: U = {U_A:.4f} L\n".replace(
            "-", "−"
        )
        + f"largest |U| = 8W₀²/(9L) = {largest:.4f} L, at X = L/3",
        ha="right",
        va="bottom",
    )
    ax.set_aspect("equal")
    ax.set_xlim(-0.06, 1.03)
    ax.set_ylim(-r - 0.13, 0.17)
    ax.set_xlabel("horizontal coordinate / L")
    ax.set_ylabel("Z / L (height; W = −Z)")
    handles = [
        Line2D([], [], color=REST_COLOUR, linestyle="--", label="membrane at rest"),
        Line2D([], [], color=DATA_COLOUR, label=f"deformed membrane (U drawn {k:g}×)"),
    ]
    fig.legend(handles=handles, loc="outside upper center", ncols=2)
    add_footer(fig, footer)
    return fig


# ---------------------------------------------------------------- Figure 5


@styled
def figure_free_body(schematic_depth_ratio, footer=""):
    """Figure 5: free-body diagrams at the load (A) and of a membrane element (B).

    (A) The load F is held by the two membrane forces N, each at the angle
    theta0 = arctan(4 W0 / L) of the small-slope solution, so F = 2 N sin theta0;
    the three vectors are drawn to scale.  (B) An element of membrane with the
    tension N at both ends and the fluid pressure p, curved with the radius
    R = L**2 / (6 W0) of the parabola (eq. 19), so N = p R.

    Parameters
    ----------
    schematic_depth_ratio : float
        W0 / L of the solution the angles and radius come from.
    footer : str
        Footer text; empty for none (the workflow writes that the figure is drawn
        from the equations: the data notice is not a schematic's).

    Returns
    -------
    matplotlib.figure.Figure
    """
    r = float(schematic_depth_ratio)
    theta0 = float(models.waterbed_load_angle_rad(r, 1.0))
    radius_L = 1.0 / (6.0 * r)  # 1 / W'' of eq. 19, in units of L
    fig = new_figure(SCHEMATIC_MM, 58.0)
    ax_a, ax_b = fig.subplots(1, 2, width_ratios=[1.0, 1.0])
    red, blue = "#b2182b", MODEL_COLOURS["waterbed"]
    # (A) at the load, N = 1 and F to scale
    f_len = 2.0 * np.sin(theta0)
    direction = np.array([np.cos(theta0), np.sin(theta0)])
    for side in (-1, 1):
        d = direction * [side, 1]
        ax_a.plot(
            [0, 1.35 * d[0]],
            [0, 1.35 * d[1]],
            color="0.82",
            linewidth=5.0,
            solid_capstyle="butt",
            zorder=1,
        )
        _arrow(ax_a, (0.0, 0.0), tuple(d), colour=blue, width=1.3, head=8)
        ax_a.text(
            *(d * 1.04 + [0, 0.06]),
            "N",
            color=blue,
            ha="center",
            va="bottom",
            fontsize=9,
            fontweight="bold",
        )
    _arrow(ax_a, (0.0, f_len), (0.0, 0.0), colour=red, width=1.3, head=8)
    ax_a.text(
        0.05, f_len * 0.6, "F", color=red, ha="left", va="center", fontsize=9, fontweight="bold"
    )
    ax_a.plot([0, 0.9], [0, 0], color="0.4", linestyle=":", linewidth=0.8)
    ax_a.add_patch(
        patches.Arc(
            (0, 0), 1.1, 1.1, theta1=0, theta2=np.degrees(theta0), color="0.2", linewidth=0.8
        )
    )
    mid = theta0 / 2
    ax_a.text(0.62 * np.cos(mid) + 0.02, 0.62 * np.sin(mid) - 0.03, "θ₀", ha="left", va="center")
    ax_a.plot([0], [0], marker="o", markersize=3.5, color="black")
    ax_a.text(
        0.0,
        -0.2,
        f"F = 2N sin θ₀\nθ₀ = arctan(4W₀/L) = {np.degrees(theta0):.1f}° at W₀/L = {r:g}\n"
        "(vectors to scale, N = 1)",
        ha="center",
        va="top",
    )
    ax_a.set_title("(A) at the load", loc="left")
    limits_a = ((-1.45, 1.45), (-0.62, max(f_len, 1.35 * np.sin(theta0)) + 0.25))
    # (B) membrane element, arc of radius R around the centre C
    half = np.radians(22.0)
    angles = np.linspace(np.pi / 2 - half, np.pi / 2 + half, 120)
    centre = np.array([0.0, -radius_L])
    ax_b.plot(
        centre[0] + radius_L * np.cos(angles),
        centre[1] + radius_L * np.sin(angles),
        color=DATA_COLOUR,
        linewidth=3.0,
        solid_capstyle="butt",
    )
    n_len = 0.45 * radius_L
    for end in (np.pi / 2 - half, np.pi / 2 + half):
        point = centre + radius_L * np.array([np.cos(end), np.sin(end)])
        outward = np.sign(np.cos(end))
        tangent = outward * np.array([np.sin(end), -np.cos(end)])
        _arrow(ax_b, tuple(point), tuple(point + n_len * tangent), colour=blue, width=1.3, head=8)
        tip = point + n_len * tangent
        ax_b.text(
            tip[0],
            tip[1] + 0.05 * radius_L,
            "N",
            color=blue,
            ha="center",
            va="bottom",
            fontsize=9,
            fontweight="bold",
        )
        ax_b.plot(
            [centre[0], point[0]], [centre[1], point[1]], color="0.5", linestyle="--", linewidth=0.6
        )
    for angle in np.linspace(np.pi / 2 - 0.8 * half, np.pi / 2 + 0.8 * half, 5):
        unit = np.array([np.cos(angle), np.sin(angle)])
        point = centre + radius_L * unit
        _arrow(
            ax_b, tuple(point - 0.16 * radius_L * unit), tuple(point), colour=red, width=0.8, head=5
        )
    ax_b.text(
        0.0,
        radius_L * 0.8 + centre[1],
        "p",
        color=red,
        ha="center",
        va="top",
        fontsize=9,
        fontstyle="italic",
    )
    ax_b.plot(*centre, marker="+", color="0.3", markersize=6)
    ax_b.text(centre[0] + 0.03 * radius_L, centre[1], "C", ha="left", va="center")
    end = np.pi / 2 + half
    ax_b.text(
        centre[0] + 0.55 * radius_L * np.cos(end) - 0.04 * radius_L,
        centre[1] + 0.55 * radius_L * np.sin(end),
        "R",
        ha="right",
        va="center",
    )
    ax_b.text(
        0.0,
        centre[1] - 0.1 * radius_L,
        f"N = pR\nR = L²/(6W₀) = {radius_L:.2f} L for eq. 19 at W₀/L = {r:g}\n"
        "(element's angular size enlarged for clarity)",
        ha="center",
        va="top",
    )
    ax_b.set_title("(B) an element of the membrane", loc="left")
    limits_b = ((-0.95 * radius_L, 0.95 * radius_L), (centre[1] - 0.5 * radius_L, 0.42 * radius_L))
    for ax, (x_lim, y_lim) in zip(
        (ax_a, ax_b), _same_box_aspect([limits_a, limits_b]), strict=True
    ):
        ax.set_xlim(*x_lim)
        ax.set_ylim(*y_lim)
        ax.set_aspect("equal")
        ax.set_axis_off()
    add_footer(fig, footer)
    return fig
