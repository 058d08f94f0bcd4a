"""What the bending skin's small-slope step costs at the paper's depths.

For each depth, half-width and bending length below, the same skin is solved without
the small-slope step (:func:`lineload.bending_exact.bending_finite_profile`), read at the
paper's reading grid inside a 3 mm fit window (the deformed positions a photograph
sees), and the small-slope model is fitted to it with W0 at the depth, as the workflow
fits readings (:func:`lineload.bending_exact.small_slope_error`).  The table gives the
largest difference between the two profiles at the readings, and what the fit makes
of the finite-slope profile: its L, its bending length and its RMSE.

Run: ``python docs/calibration/scripts/bending_small_slope.py``
(writes ``docs/calibration/bending_small_slope.md``).
"""

from __future__ import annotations

from pathlib import Path

from lineload.bending_exact import small_slope_error
from lineload.rawdata.readings import reading_distances_mm

DEPTHS_MM = (0.5, 1.0, 2.0)
HALF_WIDTHS_MM = (8.0, 12.0, 16.0)
BENDING_LENGTHS_MM = (0.05, 0.2)
WINDOW_MM = 3.0


def main():
    distance_mm = reading_distances_mm(WINDOW_MM)
    lines = [
        "# The bending skin's small-slope step, measured",
        "",
        "Made by `docs/calibration/scripts/bending_small_slope.py` (its docstring says how).",
        "The finite-slope skin read at the paper's reading grid within "
        f"{WINDOW_MM:g} mm, against the small-slope profile of the same skin, and the "
        "small-slope model fitted to it (W0 at the depth, clamped wall).",
        "",
        "| W0 (mm) | L (mm) | l_b (mm) | largest difference (um) | fitted L (mm) "
        "| fitted l_b (mm) | fit RMSE (um) |",
        "|--:|--:|--:|--:|--:|--:|--:|",
    ]
    for depth_mm in DEPTHS_MM:
        for L_mm in HALF_WIDTHS_MM:
            for lb_mm in BENDING_LENGTHS_MM:
                row = small_slope_error(depth_mm, L_mm, lb_mm, distance_mm)
                lines.append(
                    f"| {depth_mm:g} | {L_mm:g} | {lb_mm:g} | "
                    f"{1000 * row['max_error_in_window_mm']:.1f} | {row['fitted_L_mm']:.2f} | "
                    f"{row['fitted_bending_length_mm']:.3g} | {1000 * row['fit_rmse_mm']:.1f} |"
                )
    out = Path(__file__).resolve().parents[1] / "bending_small_slope.md"
    out.write_text("\n".join(lines) + "\n")
    print(out.read_text())


if __name__ == "__main__":
    main()
