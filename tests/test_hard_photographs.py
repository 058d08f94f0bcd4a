"""The digitiser on photographs as a lab takes them (lineload.simulation.hard_photographs):
each rule that reads them can fail, shown on a small rendering made to need it."""

import json

import numpy as np
import pytest

from lineload.rawdata import photographs
from lineload.rawdata.photographs import ImageError, Scene, apex, digitise_photographs, edges
from lineload.rawdata.readings import reading_distances_mm
from lineload.simulation.hard_photographs import HardCase, render_pair, true_deflection_mm

#: Small renderings: 40 pixels a mm (25 um a pixel), 18.5 mm wide, half the corners'
#: light lost to vignetting, a 30 % gradient, gamma 2.2, a 2-pixel disc of defocus.
PPMM = 40.0
SETTINGS = {"reach_mm": 6.8, "first_mm": 0.05, "smoothing_px": 1.5, "window_mm": 0.02}
GRID = reading_distances_mm(SETTINGS["reach_mm"], SETTINGS["first_mm"])


def small_case(**fields):
    base = {
        "depth_mm": 1.0,
        "L_left_mm": 6.0,
        "L_right_mm": 6.5,
        "pixels_per_mm": PPMM,
        "width_px": 740,
        "height_px": 200,
        "tip_u_mm": 9.25,
        "skin_v_mm": 1.5,
        "radius_mm": 60.0,
        "blur": "disc",
        "blur_px": 2.0,
        "glare": 0.0,
        "bar": None,
        "rest_gap_mm": 0.4,
        "gamma": 2.2,
        "vignetting": 0.5,
        "gradient": 0.3,
    }
    return HardCase(**{**base, **fields})


def read(case, seed=1, tip_x_px=None):
    rest, loaded, tip_column = render_pair(case, np.random.default_rng(seed))
    trial = digitise_photographs(rest, loaded, PPMM, GRID, SETTINGS, tip_x_px=tip_x_px)
    return trial, tip_column, loaded


def errors_um(case, trial, within_mm=3.0):
    out = []
    for side, (distance, deflection) in trial.readings.items():
        near = distance <= within_mm
        out.append(1000 * (deflection[near] - true_deflection_mm(case, side, distance[near])))
    return np.concatenate(out)


def smoothed(image):
    scene = Scene(PPMM, 0.0, 0.0, image.shape[1], image.shape[0])
    return edges._smoothed(image, scene, SETTINGS["smoothing_px"], "loaded"), scene


@pytest.mark.parametrize("bar", ["top-left", "top-right"])
def test_a_scale_bar_the_darkest_column_rule_takes_for_the_wedge_is_ignored(bar):
    """Vignetting darkens the corner where the ruler is: the darkest column above the
    skin (the old rule) lies on the ruler; the wedge is sought around the notch."""
    case = small_case(bar=bar, bar_kind="ruler")
    trial, tip_column, loaded = read(case)
    smooth, scene = smoothed(loaded)
    z_mm, _, _ = edges._edges(smooth, scene, "loaded")
    above_skin = int(-np.nanmax(z_mm) * PPMM - 4 * SETTINGS["smoothing_px"])
    darkest = int(np.argmin(smooth[2:above_skin].mean(axis=0)))
    assert abs(darkest - tip_column) > 200  # the old rule's wedge: the ruler's corner
    assert trial.tip_x_mm * PPMM - 0.5 == pytest.approx(tip_column, abs=0.5)
    assert np.sqrt(np.mean(errors_um(case, trial) ** 2)) < 8.0


def test_a_bar_burned_into_the_finger_is_not_taken_for_its_edge():
    """A white bar and label over the finger: the deepest fall down those columns is
    the bar's lower edge; the skin is what reaches the bottom edge, with what it holds."""
    case = small_case(bar="bottom-left", bar_kind="bar", label=True)
    trial, _, loaded = read(case)
    x_mm = trial.outlines["x_mm"]
    under_bar = (x_mm > 25 / PPMM) & (x_mm < (25 + PPMM) / PPMM)
    smooth, _ = smoothed(loaded)
    fall = smooth[:-1] - smooth[1:]
    deepest_strong = [
        np.flatnonzero(fall[:, c] > 0.5 * fall[:, c].max()).max() for c in np.flatnonzero(under_bar)
    ]
    skin_row = -trial.outlines["loaded_mm"][under_bar] * PPMM
    assert np.median(deepest_strong) > np.nanmedian(skin_row) + 20  # the old rule's edge
    true_top = -(case.skin_v_mm + 60.0 - np.sqrt(60.0**2 - (x_mm[under_bar] - 9.25) ** 2))
    assert np.nanmax(np.abs(trial.outlines["rest_mm"][under_bar] - true_top)) < 3 / PPMM


def test_a_steep_notch_side_is_read_where_an_unsloped_contrast_rule_drops_it():
    """2 mm deep and steep (slope up to about 1.6): the edge's fall per pixel is below
    0.7 of the far edge's in many columns within 1 mm, yet each is read."""
    case = small_case(
        depth_mm=2.0, L_left_mm=5.0, L_right_mm=5.0, shape="blend", blend=0.7, log_k=15.0
    )
    case = HardCase(**{**case.__dict__, "height_px": 240})
    trial, _, loaded = read(case)
    smooth, scene = smoothed(loaded)
    _, fall, _ = edges._edges(smooth, scene, "loaded")
    away = np.abs(scene.column_x_mm - trial.tip_x_mm)
    reference = np.nanmedian(fall[(away > 1) & (away < 3)])
    near = (away < 1) & (away > 0.1)
    assert np.sum(fall[near] < 0.7 * reference) > 10  # the old rule would leave these
    for side in ("left", "right"):
        unread = [d for d, _ in trial.unread[side] if d > 0.1]
        assert not unread, (side, trial.unread[side])
    assert np.max(np.abs(errors_um(case, trial, 1.0))) < 2 / PPMM * 1000


def test_glare_is_still_left_unread_and_says_so():
    """Glare at the tip: the nearest readings are unread with a glare reason (and only
    with glare: without it the same view reads from 0.1 mm); what is read stays within
    about a pixel of the truth."""
    plain, _, _ = read(small_case(depth_mm=1.5))
    glaring, _, _ = read(small_case(depth_mm=1.5, glare=0.7))
    for side in ("left", "right"):
        assert not [d for d, _ in plain.unread[side] if d > 0.06]
        reasons = dict(glaring.unread[side])
        assert {0.1, 0.15, 0.2} <= set(reasons)
        assert all("glare" in reasons[d] for d in (0.1, 0.15, 0.2))
    assert np.max(np.abs(errors_um(small_case(depth_mm=1.5, glare=0.7), glaring))) < 1.2 * 25
    record = photographs.quality_record(1.5, glaring)
    assert json.loads(json.dumps(record))["unread"]["left"][0]["reason"].startswith("glare")


def test_a_pair_without_skin_is_refused_with_the_measured_contrast():
    case = small_case(radius_mm=60.0, skin_v_mm=50.0, rest_gap_mm=None)  # skin below the view
    rest, loaded, _ = render_pair(case, np.random.default_rng(3))
    with pytest.raises(ImageError) as refused:
        digitise_photographs(rest, loaded, PPMM, GRID, SETTINGS, names=("rest.png", "loaded.png"))
    message = str(refused.value)
    assert message.startswith("rest.png: no edge between skin and background")
    assert "times the image's own noise" in message and "expected at least 8 times" in message
    assert "in focus" in message and "\n" not in message


def test_a_failing_value_never_prints_as_its_threshold():
    assert edges._shown(7.9996, 8.0) != "8"
    assert float(edges._shown(7.9996, 8.0)) < 8.0
    assert edges._shown(3.21, 8.0) == "3.21"


def test_the_sheets_tip_is_checked_against_the_apex_and_the_apex_error_is_measured():
    """The apex is found with a stated error; a tip 6 pixels off shows in the check."""
    case = small_case(bar="beside-wedge", bar_kind="bar")
    trial, tip_column, _ = read(case)
    assert 0 < trial.tip_sd_mm * PPMM < 0.5
    assert abs(trial.tip_x_mm * PPMM - 0.5 - tip_column) < 4 * trial.tip_sd_mm * PPMM + 0.05
    off, _, _ = read(case, tip_x_px=tip_column + 6)
    problem = photographs.trial_problem(off, case.depth_mm, 3.0)
    assert problem is not None and "left of its apex" not in problem and "right of" in problem


def test_a_declared_region_over_the_skins_edge_is_left_unread_and_says_so():
    """A black label burned in across the skin's edge 0.5-0.8 mm right of the tip, over
    both outlines: undeclared, its edge leaves the traced outline and everything from it
    in to the tip is left unread; declared (digitise: exclude_px), only its columns are,
    with that reason, and the readings between it and the tip are read right."""
    case = small_case()
    rest, loaded, tip_column = render_pair(case, np.random.default_rng(1))
    rest_row = case.skin_v_mm * PPMM
    box = [
        int(tip_column + 0.5 * PPMM),
        int(rest_row - 10),
        int(tip_column + 0.8 * PPMM),
        int(rest_row + 1.0 * PPMM),
    ]
    left, top, right, bottom = box
    for image in (rest, loaded):
        image[top : bottom + 1, left : right + 1] = 0
    inside, between = [0.5, 0.75], [0.2, 0.25, 0.3]  # the box grows by 7 pixels

    def read_with(boxes):
        settings = {**SETTINGS, "exclude_px": boxes}
        return digitise_photographs(rest, loaded, PPMM, GRID, settings)

    plain = dict(read_with([]).unread["right"])
    assert all("overlay" in plain.get(d, "") for d in between + inside), plain
    declared = read_with([box])
    reasons = dict(declared.unread["right"])
    assert all(reasons.get(d) == "an excluded region" for d in inside), reasons
    assert not set(between) & set(reasons), reasons
    assert np.max(np.abs(errors_um(case, declared))) < 1.5 * 25


def test_a_ruler_crossing_the_wedges_face_is_not_taken_for_its_middle():
    """At 2 mm the ruler beside the wedge crosses its face: that column, wedge above and
    ruler below, is darker than the wedge's middle. Sought within 1 mm of the notch, the
    middle lands on it and the apex 34 pixels off; within 0.3 mm, the apex is right."""
    case = small_case(depth_mm=2.0, bar="beside-wedge", bar_kind="ruler", height_px=240)
    trial, tip_column, loaded = read(case)
    assert trial.tip_x_mm * PPMM - 0.5 == pytest.approx(tip_column, abs=0.5)
    smooth, scene = smoothed(loaded)
    z_mm, _, _ = edges._edges(smooth, scene, "loaded")
    wide = apex._wedge_apex_mm(smooth, scene, z_mm, 1.5, trial.tip_x_mm, centre_mm=1.0)
    assert abs(wide[0] * PPMM - 0.5 - tip_column) > 10
