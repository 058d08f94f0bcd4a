"""From photographs to readings: known outlines rendered as camera images (blur, noise,
uneven light, texture, glare), digitised, and compared with the truth they came from."""

import json
import os
import time

import numpy as np
import pandas as pd
import pytest

from conftest import REPO, batch_of, refused_run, run_snakemake
from lineload.fitting.batch import fit_waterbed
from lineload.rawdata.photographs import (
    ImageError,
    Scene,
    digitise_pair,
    skin_outline_mm,
)
from lineload.simulation.photograph_render import Camera, render_photograph
from lineload.simulation.synthetic import reading_distances_mm, true_deflection_mm

#: The field of view of the test photographs: 80 pixels per tissue mm (12.5 um a pixel),
#: 17 mm wide, enough to see 2.5 mm of untouched skin beyond the deformed region.
SCENE = Scene(pixels_per_mm=80.0, x0_mm=-8.5, z0_mm=0.8, width_px=1360, height_px=440)
#: The digitising noise the paper's hand readings imply (8 um a reading, data/README.md);
#: the digitiser must do better than half of it over the fit window.
HAND_READING_SD_MM = 0.008
FIT_WINDOW_MM = 3.0


def finger(radius_mm, depth_mm, extent_mm, exponent, shift_mm=(0.0, 0.0)):
    """Resting and loaded outlines of a finger (a circle lowered by the true deflection),
    the loaded view moved by ``shift_mm`` as a camera or finger moves between shots."""
    dx, dz = shift_mm

    def rest(x):
        return -(radius_mm - np.sqrt(radius_mm**2 - np.asarray(x) ** 2))

    def loaded(x):
        xs = np.asarray(x) - dx
        return rest(xs) - true_deflection_mm(xs, depth_mm, extent_mm, exponent) + dz

    return rest, loaded, (dx, float(loaded(dx)))


def photograph_pair(rng, camera, depth_mm=1.0, extent_mm=5.5, exponent=2.2, shift_mm=(0.0, 0.0)):
    rest, loaded, tip = finger(10.0, depth_mm, extent_mm, exponent, shift_mm)
    rest_image = render_photograph(rest, SCENE, camera, rng)
    loaded_image = render_photograph(loaded, SCENE, camera, rng, wedge_tip_mm=tip)
    return rest_image, loaded_image, tip


def harder_camera(rng):
    """Camera settings the digitiser was not tuned on, each harder than Camera()'s."""
    return Camera(
        blur_px=rng.uniform(1.5, 2.5),
        noise_sd=rng.uniform(0.02, 0.04),
        lighting_gradient=rng.uniform(0.2, 0.4),
        texture_sd=rng.uniform(0.03, 0.05),
        texture_px=rng.uniform(2.0, 5.0),
        glare=rng.uniform(0.2, 0.35),
        glare_mm=rng.uniform(0.2, 0.4),
        bits=int(rng.choice([8, 16])),
    )


def test_a_clean_photograph_gives_the_outline_to_a_fraction_of_a_pixel():
    rng = np.random.default_rng(5)
    camera = Camera(noise_sd=0.0, texture_sd=0.0, glare=0.0, lighting_gradient=0.0, bits=16)
    rest, _, _ = finger(10.0, 1.0, 5.5, 2.2)
    z, contrast = skin_outline_mm(render_photograph(rest, SCENE, camera, rng), SCENE)
    error = z - rest(SCENE.column_x_mm)
    flat = np.abs(SCENE.column_x_mm) < 4  # where the outline slopes less than 0.4
    pixel_mm = 1 / SCENE.pixels_per_mm
    assert np.nanmax(np.abs(error[flat])) < 0.05 * pixel_mm
    assert np.nanmedian(contrast) > 0.1


def test_readings_recover_known_profiles_under_harder_camera_settings():
    """20 seeded pairs, each with its own camera, finger and shift between the shots."""
    rms_um, squares, covered, seconds = [], [], 0, []
    for seed in range(20):
        rng = np.random.default_rng([2026, seed])
        depth = rng.uniform(0.5, 2.0)
        extent = rng.uniform(4.5, 6.0)
        exponent = rng.uniform(1.8, 2.6)
        shift = (rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05))
        rest_image, loaded_image, tip = photograph_pair(
            rng, harder_camera(rng), depth, extent, exponent, shift
        )
        grid = reading_distances_mm(extent, 0.05)
        start = time.perf_counter()
        trial = digitise_pair(rest_image, loaded_image, SCENE, grid, reach_mm=extent + 0.3)
        seconds.append(time.perf_counter() - start)
        # the wedge's apex, from its faces, to half a pixel
        assert trial.tip_x_mm == pytest.approx(tip[0], abs=0.5 / SCENE.pixels_per_mm)
        errors, means = [], {}
        for side, (distance, deflection) in trial.readings.items():
            truth = true_deflection_mm(distance, depth, extent, exponent)
            window = distance <= FIT_WINDOW_MM
            errors.append(deflection[window] - truth[window])
            means[side] = dict(zip(distance.round(4), deflection, strict=True))
        squares.extend(np.concatenate(errors) ** 2)
        rms_um.append(1000 * np.sqrt(np.mean(np.concatenate(errors) ** 2)))
        # L of the left/right mean, against L of the truth on the same distances
        common = sorted(set(means["left"]) & set(means["right"]))
        distance = np.array([d for d in common if d <= FIT_WINDOW_MM])
        mean = np.array([(means["left"][d] + means["right"][d]) / 2 for d in distance])
        covariance = np.eye(distance.size) * trial.reading_sd_mm**2 / 2
        fitted = fit_waterbed(distance, mean, depth, covariance).params
        target = fit_waterbed(
            distance, true_deflection_mm(distance, depth, extent, exponent), depth
        )
        covered += fitted["L_ci_low_mm"] <= target.params["L_mm"] <= fitted["L_ci_high_mm"]
    # over the fit window: better than half the hand readings' noise over all pairs and
    # in the median pair, and no pair as bad as the hand readings themselves (the worst
    # are those with the strongest glare, whose first readable points it moves out)
    hand_um = 1000 * HAND_READING_SD_MM
    assert np.sqrt(np.mean(squares)) * 1000 < hand_um / 2, np.round(rms_um, 2)
    assert np.median(rms_um) < hand_um / 2 and max(rms_um) < hand_um, np.round(rms_um, 2)
    # L within its interval: at least 17 of 20 (the 2.5 % binomial quantile at 95 %)
    assert covered >= 17, covered
    assert np.median(seconds) < 1.0


def test_the_readings_move_with_the_truth():
    """A deeper indentation reads deeper: the digitiser does not return a fixed shape."""
    rng = np.random.default_rng(11)
    grid = reading_distances_mm(5.5, 0.05)
    found = []
    for depth in (0.5, 1.5):
        rest_image, loaded_image, _ = photograph_pair(rng, Camera(), depth)
        trial = digitise_pair(rest_image, loaded_image, SCENE, grid, reach_mm=5.8)
        distance, deflection = trial.readings["left"]
        found.append(deflection[np.isclose(distance, 1.0)][0])
    assert found[0] == pytest.approx(true_deflection_mm(1.0, 0.5, 5.5, 2.2), abs=0.005)
    assert found[1] == pytest.approx(true_deflection_mm(1.0, 1.5, 5.5, 2.2), abs=0.005)


def test_registration_takes_out_a_camera_shift_and_a_wrong_tip_shows():
    rng = np.random.default_rng(3)
    shift = (0.04, -0.03)
    rest_image, loaded_image, tip = photograph_pair(rng, Camera(), shift_mm=shift)
    grid = reading_distances_mm(5.5, 0.05)
    trial = digitise_pair(rest_image, loaded_image, SCENE, grid, reach_mm=5.8)
    assert trial.shift_mm == pytest.approx(shift, abs=0.003)
    distance, deflection = trial.readings["right"]
    good = deflection - true_deflection_mm(distance, 1.0, 5.5, 2.2)
    # the tip placed 0.1 mm off (a wrong sheet): the readings near the wedge are off too
    wrong = digitise_pair(
        rest_image, loaded_image, SCENE, grid, reach_mm=5.8, tip_x_mm=tip[0] + 0.1
    )
    distance, deflection = wrong.readings["right"]
    bad = deflection - true_deflection_mm(distance, 1.0, 5.5, 2.2)
    assert np.abs(bad[:5]).min() > 5 * np.abs(good[:5]).max()


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ("size", "expected 440 x 1360 pixels"),
        ("blank", "no edge between skin and background"),
        ("no wedge", "wedge was not found"),
        ("dims", "expected a greyscale or colour image"),
        ("float", "expected 8- or 16-bit levels"),
    ],
)
def test_bad_images_are_refused_with_one_line_naming_them(change, message):
    rng = np.random.default_rng(1)
    rest_image, loaded_image, _ = photograph_pair(rng, Camera())
    if change == "size":
        loaded_image = loaded_image[:-10]
    elif change == "blank":
        loaded_image = np.full_like(loaded_image, 200)
    elif change == "no wedge":
        loaded_image = rest_image.copy()
    elif change == "dims":
        loaded_image = loaded_image[None, :, :, None]
    elif change == "float":
        loaded_image = np.full(loaded_image.shape, np.nan)
    with pytest.raises(ImageError) as refused:
        digitise_pair(
            rest_image,
            loaded_image,
            SCENE,
            [0.5, 1.0],
            reach_mm=5.8,
            names=("M1_1mm_rest.png", "M1_1mm_loaded.png"),
        )
    text = str(refused.value)
    assert message in text and text.startswith("M1_1mm_loaded.png: ") and "\n" not in text


def test_colour_photographs_are_read_as_grey():
    rng = np.random.default_rng(2)
    _, loaded_image, _ = photograph_pair(rng, Camera())
    colour = np.repeat(loaded_image[:, :, None], 3, axis=2)
    z_grey, _ = skin_outline_mm(loaded_image, SCENE)
    z_colour, _ = skin_outline_mm(colour, SCENE)
    np.testing.assert_allclose(z_colour, z_grey, atol=0.02 / SCENE.pixels_per_mm)


@pytest.mark.parametrize("dtype", [np.uint8, np.uint16])
def test_a_grey_photograph_saved_in_colour_keeps_every_level(dtype):
    from lineload.rawdata.photographs.files import _as_float

    # every level, saved as RGB and as RGBA (alpha ignored): the grey read back is each
    # level over full scale, to the rounding of the weights' sum (1 to within 2e-16).
    # Cutting the weighted sum back to whole levels before scaling, as a hand-written
    # conversion did, loses a level (57 of 255 reads as 56, and 1,405 of 65,536 levels)
    top = np.iinfo(dtype).max
    grey = np.arange(top + 1, dtype=np.uint32).astype(dtype).reshape(16, -1)
    alpha = np.zeros_like(grey)
    for channels in ([grey] * 3, [grey] * 3 + [alpha]):
        read = _as_float(np.stack(channels, axis=-1), "colour.png")
        assert read.shape == grey.shape
        np.testing.assert_allclose(read, grey / top, rtol=0, atol=4 * np.finfo(float).eps)
    np.testing.assert_allclose(
        _as_float(grey, "grey.png"), grey / top, rtol=0, atol=np.finfo(float).eps
    )


def test_the_rendering_is_seeded():
    one = photograph_pair(np.random.default_rng(9), Camera())[1]
    two = photograph_pair(np.random.default_rng(9), Camera())[1]
    three = photograph_pair(np.random.default_rng(10), Camera())[1]
    assert np.array_equal(one, two) and not np.array_equal(one, three)


# ---------------------------------------------------------------- photographs in the workflow


def photograph_folder(folder):
    """The photograph example's raw folder, written from the generator into ``folder``."""
    from lineload.simulation.synthetic import photograph_dataset

    for relative, content in photograph_dataset().items():
        path = folder / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(content, bytes):
            path.write_bytes(content)
        else:
            path.write_text(content)
    return folder


def test_the_shipped_photograph_example_is_the_generators():
    """data/photographs/ is what the seeded generator writes, byte for byte."""
    from lineload.simulation.synthetic import photograph_dataset

    shipped = REPO / "data" / "photographs"
    files = photograph_dataset()
    assert sorted(
        p.relative_to(shipped).as_posix() for p in shipped.rglob("*") if p.is_file()
    ) == sorted(files)
    for relative, content in files.items():
        expected = content if isinstance(content, bytes) else content.encode()
        assert (shipped / relative).read_bytes() == expected, relative


@pytest.mark.e2e
def test_the_photograph_example_builds_from_images_to_article(photograph_build):
    from lineload.simulation.synthetic import (
        PHOTOGRAPH_DEPTHS_MM,
        PHOTOGRAPH_SUBJECTS,
        shipped_subjects,
        trial_parameters,
    )

    _, results = photograph_build  # the whole build, shared with test_article_text.py
    assert (results / "article" / "reproduction.pdf").stat().st_size > 0
    fits = pd.read_csv(results / "tables" / "fits.csv")
    assert sorted(fits["subject"].unique()) == sorted(PHOTOGRAPH_SUBJECTS)
    # the digitised readings are the true profiles, to a few micrometres
    subjects = {s.subject: s for s in shipped_subjects()}
    for name in PHOTOGRAPH_SUBJECTS:
        batch = batch_of(name, PHOTOGRAPH_SUBJECTS, photographs=True)  # the digitising job's
        readings = pd.read_csv(results / "digitised" / f"{batch}.csv")
        readings = readings[readings["subject"] == name]
        for depth in PHOTOGRAPH_DEPTHS_MM:
            trial = trial_parameters(subjects[name], depth)
            errors = []
            for side, extent in (("left", trial.extent_left_mm), ("right", trial.extent_right_mm)):
                rows = readings[(readings["depth_mm"] == depth) & (readings["side"] == side)]
                near = rows["distance_image_mm"] <= FIT_WINDOW_MM
                truth = true_deflection_mm(
                    rows["distance_image_mm"],
                    depth,
                    extent,
                    trial.exponent,
                    trial.near_fraction,
                    trial.near_exponent,
                )
                errors.extend((rows["deflection_image_mm"] - truth)[near])
            # over the fit window, both sides: better than half a hand reading's noise
            assert np.sqrt(np.mean(np.square(errors))) < HAND_READING_SD_MM / 2, (name, depth)
        record = json.loads((results / "digitised" / f"{batch}.json").read_text())
        members = [r["subject"] for r in record["subjects"]]
        assert name in members and record["batch"] == batch
        quality = record["subjects"][members.index(name)]
        assert [t["depth_mm"] for t in quality["trials"]] == list(PHOTOGRAPH_DEPTHS_MM)
        # the photographs are named as in the raw folder, never by an absolute path
        for trial in quality["trials"]:
            assert trial["loaded"] == f"images/{name}_{trial['depth_mm']:g}mm_loaded.png"
            assert trial["rest"] == f"images/{name}_{trial['depth_mm']:g}mm_rest.png"
        # the job's own comparison with images/truth.csv agrees: within half a reading
        assert all(t["error_rms_um"] < 1000 * HAND_READING_SD_MM / 2 for t in quality["trials"])
        assert (results / "digitised" / f"{batch}.png").is_file()
        # each trial's registration error is its shared offset in the noise table
        noise = pd.read_csv(results / "tables" / "noise.csv")
        for trial in quality["trials"]:
            own = noise[noise["scope"] == f"{name} at {trial['depth_mm']:g} mm"]
            own = dict(zip(own["parameter"], own["value"], strict=True))
            assert list(own) == ["shared_offset_sd_mm", "reading_sd_mm"]
            assert own["shared_offset_sd_mm"] == pytest.approx(trial["registration_sd_um"] / 1000)
            assert own["reading_sd_mm"] == pytest.approx(trial["own_reading_sd_um"] / 1000)
    # the photographs are raw inputs: in the provenance record and in the crate
    record = json.loads((results / "provenance.json").read_text())
    assert "images/images.csv" in record["raw_data"]["sha256"]
    assert (results / "inputs" / "images" / "M1_1mm_loaded.png").is_file()


def refuse(tmp_path, change):
    raw = photograph_folder(tmp_path / "raw")
    change(raw)
    return refused_run(raw, tmp_path / "results", config=["digitise__reach_mm=6.5"])


def edit_sheet(old, new):
    def change(raw):
        sheet = raw / "images" / "images.csv"
        sheet.write_text(sheet.read_text().replace(old, new, 1))

    return change


@pytest.mark.e2e
@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (edit_sheet("M1_1mm_rest.png", "M1_1mm_rst.png"), "line 2, column 'file': no file"),
        (edit_sheet(",pixels_per_mm", ",dpi"), "no scale: expected a column pixels_per_mm"),
        (edit_sheet("M1,1,loaded", "M1,1,rest"), "a second rest photograph of M1 at 1 mm"),
        (edit_sheet("M2,2,rest", "M9,2,rest"), "subject 'M9' is not in subjects.csv"),
    ],
)
def test_a_bad_photograph_sheet_is_refused_with_one_line_naming_it(tmp_path, change, expected):
    _, output, errors = refuse(tmp_path, change)
    assert any(expected in line and "images/images.csv" in line for line in errors), output


@pytest.mark.e2e
def test_a_photograph_of_another_size_or_not_an_image_is_refused(tmp_path):
    def shrink(raw):
        import imageio.v3 as iio

        path = raw / "images" / "M1_2mm_loaded.png"
        iio.imwrite(path, iio.imread(path)[:-5])
        (raw / "images" / "M2_1mm_rest.png").write_text("not a picture\n")

    _, output, errors = refuse(tmp_path, shrink)
    assert any("M1 at 2 mm is 235 x 960 pixels, the rest one 240 x 960" in e for e in errors), (
        output
    )
    assert any("M2_1mm_rest.png cannot be read as an image" in e for e in errors), output


@pytest.mark.e2e
def test_a_subject_with_both_a_profile_file_and_photographs_is_refused(tmp_path):
    def both(raw):
        (raw / "profiles").mkdir()
        (raw / "profiles" / "M1.csv").write_text(
            "depth_mm,side,distance_image_mm,deflection_image_mm\n1,left,0.5,0.8\n"
        )

    _, output, errors = refuse(tmp_path, both)
    assert any("has both a profile file" in e and "subjects.csv" in e for e in errors), output


@pytest.mark.e2e
def test_a_photograph_without_an_edge_is_refused_before_any_job_runs(tmp_path):
    """The check reads every pair as its job would: nothing is built from a folder
    where one photograph shows no finger."""

    def blank(raw):
        import imageio.v3 as iio

        path = raw / "images" / "M2_1mm_loaded.png"
        iio.imwrite(path, np.full_like(iio.imread(path), 200))

    _, output, errors = refuse(tmp_path, blank)
    assert any(
        "images/images.csv, line 7, column 'file'" in e
        and "M2_1mm_loaded.png: no edge between skin and background" in e
        for e in errors
    ), output


@pytest.mark.e2e
def test_one_dataset_mixes_readings_and_photographs(tmp_path):
    """A lab's folder may hold subjects of both kinds: M3 as hand readings beside the
    photographed M1 and M2."""
    raw = photograph_folder(tmp_path / "raw")
    (raw / "profiles").mkdir()
    shipped = REPO / "data" / "raw"
    (raw / "profiles" / "M3.csv").write_bytes((shipped / "profiles" / "M3.csv").read_bytes())
    with open(raw / "subjects.csv", "a") as sheet:
        sheet.write("M3,monkey,20,Monkey 3\n")
    made = run_snakemake(
        "fits", raw=raw, results=tmp_path / "results", config=["digitise__reach_mm=6.5"]
    )
    assert made.returncode == 0, made.stderr[-3000:]
    fits = pd.read_csv(tmp_path / "results" / "tables" / "fits.csv")
    assert sorted(fits["subject"].unique()) == ["M1", "M2", "M3"]
    assert len(fits[fits["subject"] == "M3"]) == 4  # its four depths, from its readings
    assert not (tmp_path / "results" / "digitised" / "M3.csv").exists()


# ------------------------------------------------------------ the check, file by file
# (check_dataset called directly: the same lines the raw-data check prints, in a second)

DIGITISE = {"reach_mm": 6.5, "first_mm": 0.05, "smoothing_px": 1.5, "window_mm": 0.02}


def example_copy(folder):
    """A copy of the shipped photograph example (data/photographs) in ``folder``."""
    import shutil

    shutil.copytree(REPO / "data" / "photographs", folder)
    return folder


def problems_of(raw, digitise=None, **settings):
    """The raw-data check's lines for a folder (empty when it passes)."""
    from lineload.io import load_schema
    from lineload.rawdata.validation import InputError, check_dataset

    schemas = {n: load_schema(n) for n in ("subjects", "profiles", "outlines", "forces", "images")}
    try:
        check_dataset(
            str(raw),
            schemas,
            plausibility=settings.get("plausibility"),
            digitise={**DIGITISE, **(digitise or {})},
        )
    except InputError as error:
        return error.problems
    return []


def one_line_each(problems):
    assert problems, "expected a refusal"
    for line in problems:
        assert "\n" not in line and "Traceback" not in line, line
    return problems


def png_claiming(path, width, height):
    """Rewrite a PNG's header to claim another size (the pixels stay as they are)."""
    import struct
    import zlib

    data = bytearray(path.read_bytes())
    data[16:24] = struct.pack(">II", width, height)  # IHDR's width and height
    data[29:33] = struct.pack(">I", zlib.crc32(bytes(data[12:29])))
    path.write_bytes(bytes(data))


def test_the_example_passes_the_check(tmp_path):
    assert problems_of(example_copy(tmp_path / "raw")) == []


def test_each_photograph_is_read_by_its_batch_and_not_by_the_gathering_check(tmp_path):
    """The raw-data check reads a photograph in the job of its subject's batch
    (check_images with ``read``); the job that gathers the batches reads the sheet only."""
    from lineload.io import load_schema
    from lineload.rawdata.validation import Problems, check_dataset, check_images

    raw = example_copy(tmp_path / "raw")
    damaged = raw / "images" / "M2_2mm_rest.png"
    damaged.write_bytes(damaged.read_bytes()[:5000])
    schema, ids = load_schema("images"), ["M1", "M2"]

    def batch(subjects):
        found = Problems()
        depths = check_images(str(raw), schema, ids, None, found, DIGITISE, None, read=subjects)
        return depths, found.errors

    # M2's batch reads the damaged file and refuses it, M1's does not open it
    depths, errors = batch({"M2"})
    assert depths == {"M2": [1.0]} and len(errors) == 1, errors
    assert "M2_2mm_rest.png" in errors[0] and "truncated" in errors[0]
    assert batch({"M1"}) == ({"M1": [1.0, 2.0]}, [])
    assert batch(()) == ({}, [])  # the sheet alone: no photograph read
    # the gathering check takes the batches' findings, and opens no photograph itself
    passed = {"M1": [1.0, 2.0], "M2": [1.0, 2.0]}
    checked = {"depths_mm": {}, "outlines": {}, "refused": [], "errors": [], "warnings": []}
    schemas = {n: load_schema(n) for n in ("subjects", "profiles", "outlines", "forces", "images")}
    found = check_dataset(
        str(raw), schemas, digitise=DIGITISE, checked={**checked, "photographs": passed}
    )
    assert found["depths_mm"] == passed
    assert any("truncated" in p for p in problems_of(raw))  # read when not checked in batches


def test_both_photographs_of_a_pair_refused_each_have_their_line(tmp_path):
    """Both files of a pair failing (missing, a name in the wrong case) gave StopIteration."""
    raw = example_copy(tmp_path / "raw")
    (raw / "images" / "M1_1mm_rest.png").unlink()
    sheet = raw / "images" / "images.csv"
    sheet.write_text(sheet.read_text().replace("M1_1mm_loaded.png", "M1_1mm_loaded.PNG"))
    problems = one_line_each(problems_of(raw))
    assert any("line 2, column 'file': no file" in p and "M1_1mm_rest.png" in p for p in problems)
    assert any(
        "line 3, column 'file'" in p and "'M1_1mm_loaded.png': names differ in case" in p
        for p in problems
    ), problems


@pytest.mark.parametrize(
    ("kind", "words"),
    [
        ("LA", "greyscale with an alpha channel (LA)"),
        ("1-bit", "1-bit black and white"),
        ("float", "32-bit floating point"),
        ("palette", "palette colours"),
        ("truncated", "is the file truncated or damaged?"),
        ("bomb", "claims 1,600,000,000 pixels; expected at most 40,000,000"),
        ("large", "is 10000 x 5000 pixels (50,000,000); expected at most 40,000,000"),
        ("12-bit", "levels reach only"),
        ("text", "cannot be read as an image"),
    ],
)
def test_each_kind_of_bad_photograph_is_named(tmp_path, kind, words):
    import imageio.v3 as iio
    from PIL import Image

    raw = example_copy(tmp_path / "raw")
    path = raw / "images" / "M2_1mm_loaded.png"
    picture = iio.imread(path)
    grey = picture if picture.ndim == 2 else picture[..., 0]
    if kind == "LA":
        Image.fromarray(grey.astype(np.uint8)).convert("LA").save(path)
    elif kind == "1-bit":
        Image.fromarray(grey.astype(np.uint8)).convert("1").save(path)
    elif kind == "float":
        path.unlink()
        path = path.with_suffix(".tif")
        iio.imwrite(path, grey.astype(np.float32))
        sheet = raw / "images" / "images.csv"
        sheet.write_text(sheet.read_text().replace("M2_1mm_loaded.png", "M2_1mm_loaded.tif"))
    elif kind == "palette":
        Image.fromarray(grey.astype(np.uint8)).convert("P").save(path)
    elif kind == "truncated":
        data = path.read_bytes()
        path.write_bytes(data[: len(data) // 2])
    elif kind == "bomb":
        png_claiming(path, 40000, 40000)
    elif kind == "large":
        png_claiming(path, 10000, 5000)
    elif kind == "12-bit":
        levels = grey.astype(np.float64) / (255.0 if grey.dtype == np.uint8 else 65535.0)
        iio.imwrite(path, np.rint(levels * 4095).astype(np.uint16))
    elif kind == "text":
        path.write_text("not a picture\n")
    started = time.perf_counter()
    problems = one_line_each(problems_of(raw))
    assert time.perf_counter() - started < 30  # a bomb is refused from its header
    assert any(
        words in p and "M2_1mm_loaded." in p and "images.csv, line 7, column 'file'" in p
        for p in problems
    ), problems


def test_a_256_character_file_name_is_one_line(tmp_path):
    raw = example_copy(tmp_path / "raw")
    sheet = raw / "images" / "images.csv"
    sheet.write_text(sheet.read_text().replace("M1_1mm_rest.png", "x" * 256 + ".png"))
    problems = one_line_each(problems_of(raw))
    assert any("line 2, column 'file'" in p and "260 bytes long" in p for p in problems), problems


# ------------------------------------------------------ nothing read from outside


@pytest.mark.parametrize(
    ("entry", "target"),
    [
        ("images/M1_1mm_rest.png", "/dev/zero"),
        ("images/M1_1mm_rest.png", "/etc/passwd"),
        ("images/images.csv", "/etc/passwd"),
        ("subjects.csv", "/etc/passwd"),
        ("images/M2_2mm_loaded.png", "elsewhere"),  # a real photograph, outside the folder
    ],
)
def test_a_link_out_of_the_dataset_is_refused_before_it_is_opened(
    tmp_path, monkeypatch, entry, target
):
    import builtins

    raw = example_copy(tmp_path / "raw")
    if target == "elsewhere":
        target = tmp_path / "elsewhere.png"
        (raw / entry).rename(target)
    else:
        (raw / entry).unlink()
    (raw / entry).symlink_to(target)
    opened = []
    real_open = builtins.open

    def watched(file, *args, **kwargs):
        opened.append(os.path.realpath(file) if isinstance(file, str | os.PathLike) else file)
        return real_open(file, *args, **kwargs)

    monkeypatch.setattr(builtins, "open", watched)
    problems = one_line_each(problems_of(raw))
    assert any(
        p.startswith(f"{raw}/{entry} leads to {os.path.realpath(target)}, outside the raw-data")
        for p in problems
    ), problems
    assert os.path.realpath(target) not in opened


def test_a_dataset_that_is_itself_a_link_is_read(tmp_path):
    """Labs and clusters link data folders: the folder is resolved once, and its own
    files are inside it."""
    example_copy(tmp_path / "store" / "raw")
    (tmp_path / "raw").symlink_to(tmp_path / "store" / "raw")
    assert problems_of(tmp_path / "raw") == []


def test_a_sheet_naming_a_file_outside_is_refused(tmp_path):
    raw = example_copy(tmp_path / "raw")
    sheet = raw / "images" / "images.csv"
    sheet.write_text(sheet.read_text().replace("M1_1mm_rest.png", "../../../../etc/passwd"))
    from lineload.rawdata.validation import photograph_files

    assert all("passwd" not in f for f in photograph_files(str(raw))["M1"])
    problems = one_line_each(problems_of(raw))
    assert any("line 2, column 'file'" in p and "'../../../../etc/passwd'" in p for p in problems)


# --------------------------------------------------------- sheets as labs save them


def sheet_saved(raw, how):
    sheet = raw / "images" / "images.csv"
    text = sheet.read_text()
    if how == "BOM":
        sheet.write_bytes(b"\xef\xbb\xbf" + text.encode())
    elif how == "semicolons":
        sheet.write_text(text.replace(",", ";"))
    elif how == "tabs":
        sheet.write_text(text.replace(",", "\t"))
    elif how == "UTF-16":
        sheet.write_bytes(text.encode("utf-16"))
    elif how == "File":
        sheet.write_text(text.replace(",file,", ",File,", 1))
    elif how == "trailing":
        sheet.write_text("".join(line + ",,\n" for line in text.splitlines()))
    elif how == "nameless":
        lines = text.splitlines()
        sheet.write_text(
            "".join(f"{line},,{'x' if i == 3 else ''}\n" for i, line in enumerate(lines))
        )
    elif how == "Images":
        (raw / "images").rename(raw / "Images")


@pytest.mark.parametrize(
    ("how", "words"),
    [
        ("BOM", None),
        ("trailing", None),
        ("semicolons", "found semicolons (';') between the column names"),
        ("tabs", "found tabs between the column names"),
        ("UTF-16", "is UTF-16 text"),
        ("File", "column 'file': missing from the header; found 'File', expected 'file'"),
        ("nameless", "line 1: column 7 has no name in the header but holds values"),
        ("Images", "Images: expected the name 'images'"),
    ],
)
def test_a_sheet_as_a_lab_saves_it_is_read_or_named(tmp_path, how, words):
    raw = example_copy(tmp_path / "raw")
    sheet_saved(raw, how)
    problems = problems_of(raw)
    if words is None:
        assert problems == []
        return
    one_line_each(problems)
    assert any(words in p for p in problems), problems
    # never the misleading line: a photographed subject has no profile file to miss
    if how != "Images":
        assert not any("no profile file" in p for p in problems), problems


# ------------------------------------- photographs held to the profiles' plausibility


def photograph_mistake(raw, mistake):
    """Make one of a lab's mistakes in the example; returns the config's digitise changes."""
    import shutil

    import imageio.v3 as iio
    from skimage.transform import rescale

    images = raw / "images"
    sheet = images / "images.csv"
    text = sheet.read_text()
    if mistake == "rest copied over":
        shutil.copy(images / "M1_1mm_loaded.png", images / "M1_1mm_rest.png")
    elif mistake == "loaded copied over":
        shutil.copy(images / "M1_1mm_rest.png", images / "M1_1mm_loaded.png")
    elif mistake == "loaded copied over, tip given":
        shutil.copy(images / "M1_1mm_rest.png", images / "M1_1mm_loaded.png")
        sheet.write_text(
            "".join(
                line + (",tip_x_px\n" if i == 0 else ",480\n")
                for i, line in enumerate(text.splitlines())
            )
        )
    elif mistake.startswith("tip at"):  # "tip at 470": the sheet's tip for M1 at 1 mm
        sheet.write_text(
            "".join(
                line + (",tip_x_px\n" if i == 0 else f",{mistake.split()[-1] if i == 2 else 480}\n")
                for i, line in enumerate(text.splitlines())
            )
        )
    elif mistake == "swapped":
        sheet.write_text(
            text.replace("M1,1,rest", "M1,1,tmp")
            .replace("M1,1,loaded", "M1,1,rest")
            .replace("M1,1,tmp", "M1,1,loaded")
        )
    elif mistake == "micrometres":
        sheet.write_text(text.replace("M2,1,", "M2,1000,").replace("M2,2,", "M2,2000,"))
    elif mistake == "scale on the 1 mm rows":
        sheet.write_text(
            text.replace("mm_rest.png,60", "mm_rest.png,15", 1).replace(
                "M1_1mm_loaded.png,60", "M1_1mm_loaded.png,15"
            )
        )
    elif mistake in ("resting zoomed", "resting zoomed, its scale given"):
        path = images / "M2_2mm_rest.png"
        picture = iio.imread(path)
        zoomed = rescale(picture.astype(float), 1.03, preserve_range=True)
        iio.imwrite(
            path, np.rint(zoomed[: picture.shape[0], : picture.shape[1]]).astype(picture.dtype)
        )
        if mistake.endswith("given"):
            sheet.write_text(text.replace("M2_2mm_rest.png,60", "M2_2mm_rest.png,61.8"))
    elif mistake == "reach too short":
        return {"reach_mm": 2.0}
    return {}


@pytest.mark.parametrize(
    ("mistake", "line", "words"),
    [
        ("rest copied over", 3, "M1_1mm_loaded.png: the wedge was not found"),
        ("loaded copied over", 3, "is the loaded photograph the resting one (copied over it)?"),
        ("loaded copied over, tip given", 3, "copied over the other?"),
        ("swapped", 2, "the resting photograph shows it: are rest and loaded swapped?"),
        ("micrometres", 6, "column 'depth_mm'"),
        ("scale on the 1 mm rows", 3, "the two photographs at different scales"),
        ("resting zoomed", 9, "the two photographs at different scales (zoom"),
        ("resting zoomed, its scale given", 8, "at 61.8 pixels per mm, the loaded one"),
        ("reach too short", 3, "reach_mm too short"),
        ("tip at 470", 3, "puts the wedge's tip 10.1 pixels left of its apex"),
    ],
)
def test_a_photograph_mistake_is_refused_with_its_likely_cause(tmp_path, mistake, line, words):
    raw = example_copy(tmp_path / "raw")
    digitise = photograph_mistake(raw, mistake)
    problems = one_line_each(problems_of(raw, digitise))
    assert any(f"images.csv, line {line}," in p and words in p for p in problems), problems


def test_readings_past_the_deflection_bound_are_refused_as_a_profile_file_is():
    """The bounds of trial_problem, on readings made to break each one."""
    from lineload.rawdata.photographs import DigitisedTrial, trial_problem

    def trial(near, far, residual_mm=0.002):
        distances = np.array([0.05, 1.0])
        readings = {side: (distances, np.array([near, far])) for side in ("left", "right")}
        return DigitisedTrial(readings, 8.0, (0.0, 0.0), residual_mm, 0.001, 0.001)

    assert trial_problem(trial(0.97, 0.5), 1.0, 3.0) is None
    assert "more than 3 times it" in trial_problem(trial(3.5, 0.5), 1.0, 3.0)
    assert "more than 3 times it" in trial_problem(trial(0.97, 3.2), 1.0, 3.0)
    assert "less than 1/3 of it" in trial_problem(trial(0.2, 0.1), 1.0, 3.0)
    assert "no deflection" in trial_problem(trial(0.0, 0.0), 1.0, 3.0)
    assert "swapped" in trial_problem(trial(-0.9, -0.5), 1.0, 3.0)
    assert "times the outlines' own roughness" in trial_problem(trial(0.97, 0.5, 0.011), 1.0, 3.0)
    assert trial_problem(trial(0.97, 0.5, 0.009), 1.0, 3.0) is None


def test_a_tip_given_where_the_image_shows_it_is_read():
    """The sheet's tip, where the photograph shows it (the example's tip is pixel 480),
    passes; the check of the tip against the apex can fail only on a wrong one."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as folder:
        raw = example_copy(Path(folder) / "raw")
        photograph_mistake(raw, "tip at 480")
        assert problems_of(raw) == []


@pytest.mark.e2e
@pytest.mark.parametrize(
    ("mistake", "words"),
    [
        ("rest copied over", "M1_1mm_loaded.png: the wedge was not found"),
        ("micrometres", "line 6, column 'depth_mm'"),
        ("truncated", "is the file truncated or damaged?"),
    ],
)
def test_a_photograph_mistake_stops_the_build_with_one_line_and_nothing_written(
    tmp_path, mistake, words
):
    def change(raw):
        if mistake == "truncated":
            path = raw / "images" / "M2_2mm_rest.png"
            path.write_bytes(path.read_bytes()[:5000])
        else:
            photograph_mistake(raw, mistake)

    _, output, errors = refuse(tmp_path, change)  # no traceback, nothing but the log
    assert any(words in e and "images/images.csv, line" in e for e in errors), output


@pytest.mark.e2e
def test_a_refused_pair_is_drawn_into_the_checks_log_and_nothing_else_is_left(tmp_path):
    """The raw-data check refuses a pair whose resting photograph is the loaded one: its
    line names a PNG beside the batch check's log that draws the pair as the digitiser
    saw it; no output is left (refused_run), the PNG is the one file beside the log."""
    import imageio.v3 as iio

    _, output, errors = refuse(tmp_path, lambda raw: photograph_mistake(raw, "rest copied over"))
    named = [e for e in errors if "M1_1mm_loaded.png: the wedge was not found" in e]
    assert len(named) == 1, output
    where = named[0].rsplit(" drawn in ", 1)[1].removesuffix(" (panel 1)")
    picture = tmp_path / "results" / "logs" / "check_profiles" / os.path.basename(where)
    assert where == str(picture) and picture.is_file(), named
    assert iio.imread(picture).ndim == 3
    left = sorted(p.name for p in (tmp_path / "results").rglob("*") if p.is_file())
    assert left == sorted(["check_raw_data.log", picture.name]), left


@pytest.mark.e2e
def test_an_accepted_build_writes_no_diagnostic_image(photograph_build):
    _, results = photograph_build
    assert (results / "logs" / "check_profiles").is_dir()
    assert sorted((results / "logs").rglob("*.png")) == []


@pytest.mark.e2e
def test_a_pair_the_digitise_job_refuses_leaves_its_drawing_and_no_output(tmp_path):
    """The digitise job meets a pair it cannot read (its resting photograph replaced by
    the loaded one after the check, given an old time, so the check is not redone): the
    job fails with one line naming its diagnostic PNG, a log Snakemake keeps, and its
    outputs are not left."""
    import shutil

    raw, results = photograph_folder(tmp_path / "raw"), tmp_path / "results"
    config = ["digitise__reach_mm=6.5"]
    assert run_snakemake("check", raw=raw, results=results, config=config).returncode == 0
    images = raw / "images"
    shutil.copy(images / "M1_1mm_loaded.png", images / "M1_1mm_rest.png")
    os.utime(images / "M1_1mm_rest.png", (1e9, 1e9))  # older than the check
    batch = batch_of("M1", ["M1", "M2"], photographs=True)
    target = results / "digitised" / f"{batch}.csv"
    done = run_snakemake(str(target), raw=raw, results=results, config=config)
    output = done.stdout + done.stderr
    assert done.returncode != 0, output
    picture = results / "logs" / "digitise" / f"{batch}.png"
    errors = [line for line in output.splitlines() if line.startswith("Error: ")]
    assert any(
        "M1_1mm_loaded.png: the wedge was not found" in e
        and e.endswith(f"drawn in {picture} (panel 1)")
        for e in errors
    ), output
    assert picture.is_file()
    assert not (results / "digitised").exists() or not any((results / "digitised").iterdir())
