"""Fuzzing the raw-data check on the photograph path: seeded mutations of the photograph
example (data/photographs), each refused in one line or read right.

As tests/test_fuzz.py does for profile files: the kinds of mistake a lab makes to a
folder of photographs - cells of images.csv (numbers, units, names, states), the
sheet's saving (a BOM, semicolons, UTF-16, a header in capitals, rows lost or doubled,
empty columns), the images' bytes (cut short, damaged, another mode or bit depth,
copied, swapped, blank) and links (out of the folder, to /dev/zero) - go through
``lineload.rawdata.validation.check_dataset`` in process.  A mutation it refuses must be refused
with ``Error:`` lines of one line each, naming the folder, and no traceback; one it
accepts is digitised as the job reads it, and its readings must lie within 20 um of the
true deflections (images/truth.csv of the clean example) over the fit window.
"""

from __future__ import annotations

import math
import os
import shutil

import numpy as np
import pytest

from conftest import REPO
from lineload.io import load_schema
from lineload.rawdata.photographs import digitise_photographs, read_photograph
from lineload.rawdata.validation import (
    InputError,
    check_dataset,
    image_scale_px_per_mm,
    read_table,
    report_lines,
)
from lineload.simulation.synthetic import reading_distances_mm

#: Mutated folders per run; each is one seeded draw, so a failure names its number.
N_MUTATIONS = 60
SEED = 30
EXAMPLE = REPO / "data" / "photographs"
SCHEMAS = {n: load_schema(n) for n in ("subjects", "profiles", "outlines", "forces", "images")}
TOP = load_schema("config")["properties"]
LIMITS = {k: v["default"] for k, v in TOP["input_checks"]["properties"].items()}
#: The example's digitise settings (config/photographs.yaml: reach_mm 6.5).
DIGITISE = {"reach_mm": 6.5, "first_mm": 0.05, "smoothing_px": 1.5, "window_mm": 0.02}
FIT_WINDOW_MM = TOP["fit_window_mm"]["default"]
#: How far an accepted read may lie from the truth (RMS over the fit window): the
#: example's pairs are read to 1-3 um; a wrong scale, tip or pairing is off by far more.
READ_TOLERANCE_MM = 0.020

#: Cells people and programs write into images.csv.
ODD_CELLS = (
    "", "abc", "nan", "inf", "-1", "0", "1000", "15", "61.8", "1e400", "M9", "rest",
    "loaded", "M1_2mm_rest.png", "M1_1mm_rest.PNG", "../subjects.csv", "\u00a060", "1,5",
)  # fmt: skip
PHOTOS = [p.name for p in sorted(EXAMPLE.glob("images/*.png"))]


def _sheet_mutation(images, rng):
    sheet = images / "images.csv"
    lines = sheet.read_text().splitlines()
    kind = rng.choice(
        ["cell", "BOM", "semicolons", "tabs", "UTF-16", "File", "drop row", "double row",
         "trailing columns", "extra column", "reorder rows", "swap states", "CRLF"]
    )  # fmt: skip
    if kind == "cell":
        row = int(rng.integers(1, len(lines)))
        cells = lines[row].split(",")
        column = int(rng.integers(len(cells)))
        value = str(rng.choice(ODD_CELLS))
        kind = f"line {row + 1} column {column + 1} -> {value!r}"
        cells[column] = value
        lines[row] = ",".join(cells)
    elif kind == "BOM":
        lines[0] = "\ufeff" + lines[0]
    elif kind == "semicolons":
        lines = [line.replace(",", ";") for line in lines]
    elif kind == "tabs":
        lines = [line.replace(",", "\t") for line in lines]
    elif kind == "UTF-16":
        sheet.write_bytes("\n".join(lines).encode("utf-16"))
        return kind
    elif kind == "File":
        lines[0] = lines[0].replace("file", "File")
    elif kind == "drop row":
        del lines[int(rng.integers(1, len(lines)))]
    elif kind == "double row":
        row = int(rng.integers(1, len(lines)))
        lines.insert(row, lines[row])
    elif kind == "trailing columns":
        lines = [line + ",," for line in lines]
    elif kind == "extra column":
        lines = [line + (",note" if i == 0 else ",seen") for i, line in enumerate(lines)]
    elif kind == "reorder rows":
        body = lines[1:]
        lines = [lines[0], *(body[i] for i in rng.permutation(len(body)))]
    elif kind == "swap states":
        row = 1 + 2 * int(rng.integers((len(lines) - 1) // 2))
        lines[row], lines[row + 1] = (
            lines[row].replace(",rest,", ",loaded,"),
            lines[row + 1].replace(",loaded,", ",rest,"),
        )
    elif kind == "CRLF":
        sheet.write_bytes(("\r\n".join(lines) + "\r\n").encode())
        return kind
    sheet.write_text("\n".join(lines) + "\n")
    return f"sheet: {kind}"


def _image_mutation(images, rng, outside):
    import imageio.v3 as iio
    from PIL import Image

    name = str(rng.choice(PHOTOS))
    path = images / name
    kind = rng.choice(
        ["truncate", "damage", "text", "LA", "1-bit", "12-bit", "blank", "copy over",
         "swap files", "link /dev/zero", "link /etc/passwd", "link outside", "link inside",
         "empty", "noise"]
    )  # fmt: skip
    data = path.read_bytes()
    if kind == "truncate":
        path.write_bytes(data[: int(rng.integers(8, len(data)))])
    elif kind == "damage":
        start = int(rng.integers(100, len(data) - 64))
        path.write_bytes(data[:start] + bytes(64) + data[start + 64 :])
    elif kind == "text":
        path.write_text("subject,depth_mm\n")
    elif kind in ("LA", "1-bit"):
        Image.open(path).convert("LA" if kind == "LA" else "1").save(path)
    elif kind == "12-bit":
        picture = iio.imread(path).astype(np.uint16) * 16  # 8-bit levels as 12-bit ones
        iio.imwrite(path, picture)
    elif kind == "blank":
        iio.imwrite(path, np.full_like(iio.imread(path), 200))
    elif kind == "noise":
        picture = iio.imread(path)
        iio.imwrite(path, rng.integers(0, 256, picture.shape).astype(picture.dtype))
    elif kind == "copy over":
        shutil.copy(images / str(rng.choice(PHOTOS)), path)
    elif kind == "swap files":
        other = images / str(rng.choice(PHOTOS))
        path.rename(images / "tmp.bin")
        other.rename(path)
        (images / "tmp.bin").rename(other)
    elif kind == "empty":
        path.write_bytes(b"")
    elif kind.startswith("link"):
        path.unlink()
        if kind == "link outside":
            target = outside / name
            target.write_bytes(data)
        elif kind == "link inside":
            target = images / "kept" / name
            target.parent.mkdir(exist_ok=True)
            target.write_bytes(data)
        else:
            target = kind.split()[1]
        path.symlink_to(target)
    return f"{name}: {kind}"


def _mutate(raw, rng, outside):
    images = raw / "images"
    if rng.random() < 0.5:
        return _sheet_mutation(images, rng)
    return _image_mutation(images, rng, outside)


def _truth():
    table = read_table(EXAMPLE / "images" / "truth.csv", load_schema("truth"))
    return {
        key: (rows["distance_mm"].to_numpy(float), rows["deflection_mm"].to_numpy(float))
        for key, rows in table.groupby(["subject", "depth_mm", "side"])
    }


TRUTH = _truth()


def _read_errors_mm(raw):
    """Each accepted pair digitised as its job reads it: the RMS error of its readings
    against the true deflection within the fit window, per (subject, depth, side)."""
    sheet = raw / "images" / "images.csv"
    images = read_table(sheet, load_schema("images"))
    scale = image_scale_px_per_mm(images)
    grid = reading_distances_mm(DIGITISE["reach_mm"], DIGITISE["first_mm"])
    errors = {}
    for (subject, depth), pair in images.groupby(["subject", "depth_mm"]):
        rest, loaded = (pair[pair["state"] == s].iloc[0] for s in ("rest", "loaded"))
        paths = [str(raw / "images" / str(r["file"])) for r in (rest, loaded)]
        trial = digitise_photographs(
            *(read_photograph(p, p) for p in paths),
            float(scale.loc[loaded.name]),
            grid,
            DIGITISE,
            tip_x_px=loaded.get("tip_x_px"),
            names=paths,
        )
        for side in ("left", "right"):
            distance, deflection = trial.readings[side]
            true_x, true_w = TRUTH[(str(subject), float(depth), side)]
            inside = distance <= FIT_WINDOW_MM
            truth = np.interp(distance[inside], true_x, true_w)
            errors[(subject, float(depth), side)] = float(
                np.sqrt(np.mean((deflection[inside] - truth) ** 2)) if inside.any() else math.inf
            )
    return errors


def fuzz(work, check=check_dataset, n=N_MUTATIONS):
    """Run ``n`` seeded mutations of the example through ``check`` (and the reader when
    it accepts).  Returns ``(refused, accepted, problems)``."""
    rng = np.random.default_rng(SEED)
    outside = work / "outside"
    outside.mkdir(exist_ok=True)
    refused, accepted, problems = 0, 0, []
    for k in range(n):
        raw = work / f"raw{k}"
        shutil.copytree(EXAMPLE, raw)
        mutation = _mutate(raw, rng, outside)
        what = f"mutation {k} ({mutation})"
        try:
            check(str(raw), SCHEMAS, plausibility=LIMITS, digitise=DIGITISE)
        except InputError as error:
            refused += 1
            lines = report_lines(error)
            errors = [line for line in lines if line.startswith("Error: ")]
            one_line = all("\n" not in e and e.startswith(f"Error: {raw}") for e in errors)
            if not 1 <= len(errors) <= 8 or not one_line:
                problems.append(f"{what}: {lines}")
            continue
        except Exception as error:  # a traceback where a sentence belongs
            problems.append(f"{what}: {type(error).__name__}: {error}")
            continue
        accepted += 1
        try:
            errors = _read_errors_mm(raw)
        except Exception as error:  # accepted, then the reader broke
            problems.append(f"{what}: accepted, then {type(error).__name__}: {error}")
            continue
        wrong = {k: v for k, v in errors.items() if not v <= READ_TOLERANCE_MM}
        if len(errors) != len(TRUTH) or wrong:
            problems.append(f"{what}: accepted, read wrong: {wrong or sorted(errors)}")
    return refused, accepted, problems


def test_every_photograph_mutation_is_refused_in_one_line_or_read_right(tmp_path):
    refused, accepted, problems = fuzz(tmp_path)
    assert not problems, "\n".join(problems)
    # both outcomes occur (a check that refused everything, or nothing, would fail here)
    assert refused > N_MUTATIONS // 3 and accepted > N_MUTATIONS // 10, (refused, accepted)


def test_the_photograph_fuzz_test_catches_a_check_that_lets_everything_through(
    tmp_path, monkeypatch
):
    from lineload.rawdata import validation

    # the check's photograph part accepts every pair and every file as it is
    monkeypatch.setattr(validation, "links_outside", lambda *a, **k: [])
    monkeypatch.setattr(validation, "check_images", lambda *a, **k: {"M1": [1.0, 2.0]})
    _, accepted, problems = fuzz(tmp_path, check=validation.check_dataset, n=30)
    assert accepted >= 25
    assert len(problems) >= 8, problems


@pytest.mark.parametrize("k", [0])
def test_the_example_itself_reads_right(k, tmp_path):
    raw = tmp_path / "raw"
    shutil.copytree(EXAMPLE, raw)
    check_dataset(str(raw), SCHEMAS, plausibility=LIMITS, digitise=DIGITISE)
    errors = _read_errors_mm(raw)
    assert len(errors) == len(TRUTH) and max(errors.values()) < READ_TOLERANCE_MM / 4, errors
    assert os.path.isdir(raw)
