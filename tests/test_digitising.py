"""Digitising photographs batch by batch: the same readings as subject by subject, records
that name the photographs relative to the raw folder, and a figure of bounded size."""

import os

import numpy as np
import pytest

from conftest import REPO
from lineload.io import config_defaults, load_schema
from lineload.rawdata import digitising
from lineload.rawdata.digitising import digitise_batch, profile_text, subject_profile
from lineload.rawdata.sheets import read_columns
from lineload.rawdata.validation import read_table

RAW = REPO / "data" / "photographs"
SETTINGS = {**config_defaults("digitise"), "reach_mm": 6.5}  # config/photographs.yaml
SUBJECTS = {
    "M1": {"label": "Monkey 1", "magnification": 1.0},
    "M2": {"label": "Monkey 2", "magnification": 1.0},
}


def run(subjects, raw=RAW):
    images = read_table(raw / "images" / "images.csv", load_schema("images"))
    truth = read_table(raw / "images" / "truth.csv", load_schema("truth"))
    return digitise_batch(str(raw), images, subjects, SETTINGS, 3.0, truth, log=lambda _: None)


@pytest.fixture(scope="module")
def together():
    return run(SUBJECTS)


def test_a_batch_reads_what_its_subjects_read_one_by_one(together):
    alone = [run({s: about}) for s, about in SUBJECTS.items()]
    assert together.rows == [row for one in alone for row in one.rows]
    assert together.records == [record for one in alone for record in one.records]
    assert profile_text(together.rows) == "".join(
        [
            profile_text(alone[0].rows),
            *(profile_text(one.rows).split("\n", 1)[1] for one in alone[1:]),
        ]
    )


def test_the_records_name_photographs_relative_to_the_raw_folder(together, tmp_path):
    """No absolute path: the record reads the same wherever the raw folder is."""
    for record in together.records:
        for trial in record["trials"]:
            for state in ("rest", "loaded"):
                name = trial[state]
                assert not os.path.isabs(name) and "\\" not in name, name
                assert (RAW / name).is_file()
    # the same folder elsewhere (an absolute path given): the same records
    import shutil

    moved = tmp_path / "elsewhere" / "raw"
    shutil.copytree(RAW, moved)
    assert run({"M1": SUBJECTS["M1"]}, moved.resolve()).records == together.records[:1]


def test_a_batch_figure_draws_at_most_its_share_of_trials(together, monkeypatch):
    assert [(d["label"], d["depth_mm"]) for d in together.drawn] == [
        ("Monkey 1", 1.0),
        ("Monkey 1", 2.0),
        ("Monkey 2", 1.0),
        ("Monkey 2", 2.0),
    ]
    # a larger batch draws the trials it read least surely, in batch order
    monkeypatch.setattr(digitising, "FIGURE_TRIALS", 2)
    few = run(SUBJECTS)
    assert few.rows == together.rows
    own = {
        (r["subject"], t["depth_mm"]): t["own_reading_sd_um"]
        for r in together.records
        for t in r["trials"]
    }
    labels = {"Monkey 1": "M1", "Monkey 2": "M2"}
    drawn = [(labels[d["label"]], d["depth_mm"]) for d in few.drawn]
    assert sorted(drawn, key=list(own).index) == drawn
    assert sorted(own.values())[-2:] == sorted(own[key] for key in drawn)


def test_one_subjects_rows_of_a_batch_file(together, tmp_path):
    path = tmp_path / "batch.csv"
    path.write_text(profile_text(together.rows))
    profile = read_columns(path, load_schema("profiles"))
    columns, lines = subject_profile(profile, "M2")
    assert set(columns["subject"]) == {"M2"}
    expected = [row for row in together.rows if row[0] == "M2"]
    assert len(lines) == len(expected)
    np.testing.assert_allclose(
        columns["deflection_image_mm"], [row[4] for row in expected], atol=5e-6
    )
    # a raw profile file (one subject, no subject column) comes back as it is
    raw = read_columns(REPO / "data" / "raw" / "profiles" / "M3.csv", load_schema("profiles"))
    assert subject_profile(raw, "M3") is raw


def test_a_pair_the_job_refuses_is_drawn_where_its_refusal_says(tmp_path):
    """A pair the digitise job cannot read (the resting photograph replaced by the
    loaded one after the check) stops the batch with a message naming the diagnostic
    PNG, which is there and draws the same bytes twice; without a path, nothing is drawn
    and the message is the digitiser's own."""
    import shutil

    import imageio.v3 as iio

    from lineload.rawdata.photographs import ImageError

    raw = tmp_path / "raw"
    shutil.copytree(RAW, raw)
    images = raw / "images"
    shutil.copy(images / "M1_1mm_loaded.png", images / "M1_1mm_rest.png")
    sheet = read_table(images / "images.csv", load_schema("images"))
    picture = tmp_path / "logs" / "M1.png"
    drawn = []
    for _ in range(2):
        with pytest.raises(ImageError) as refused:
            digitise_batch(
                str(raw),
                sheet,
                SUBJECTS,
                SETTINGS,
                3.0,
                log=lambda _: None,
                diagnostic=str(picture),
            )
        assert "M1_1mm_loaded.png: the wedge was not found" in str(refused.value)
        assert str(refused.value).endswith(f"drawn in {picture} (panel 1)")
        drawn.append(picture.read_bytes())
        assert iio.imread(picture).shape[2] in (3, 4)
        picture.unlink()
    assert drawn[0] == drawn[1]
    with pytest.raises(ImageError) as plain:
        digitise_batch(str(raw), sheet, SUBJECTS, SETTINGS, 3.0, log=lambda _: None)
    assert "drawn in" not in str(plain.value)
    assert not picture.exists()
