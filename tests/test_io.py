"""Output files: atomic, byte-stable, readable by others like any file the user writes."""

import errno
import os
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from lineload import io


def test_written_files_get_the_usual_permissions(tmp_path):
    path = tmp_path / "sub" / "table.txt"
    io.write_text("a\n", path)
    umask = os.umask(0)
    os.umask(umask)
    assert path.stat().st_mode & 0o777 == 0o666 & ~umask
    assert not [p for p in path.parent.iterdir() if p.name.endswith(".tmp")]


def test_csv_text_is_fixed(tmp_path):
    frame = pd.DataFrame({"a_mm": [0.1 + 0.2, 1 / 3], "name": ["x", "y"]})
    io.write_csv(frame, tmp_path / "t.csv")
    assert (tmp_path / "t.csv").read_bytes() == b"a_mm,name\n0.3,x\n0.3333333333,y\n"


def test_failed_write_leaves_nothing(tmp_path):
    with pytest.raises(TypeError):
        io.write_text(None, tmp_path / "x.txt")
    assert list(tmp_path.iterdir()) == []


def test_row_writer_matches_the_pandas_writer_byte_for_byte(tmp_path):
    """The pandas-free writer of the fit jobs and write_csv give the same file."""
    import numpy as np

    rows = [
        {"subject": "01", "n": 3, "x_mm": 0.1 + 0.2, "flag": True, "note": 'a, "b"'},
        {"subject": "M-2", "n": 12, "x_mm": float("nan"), "flag": False, "note": "plain"},
        {"subject": "H3", "n": np.int64(7), "x_mm": np.float64(1e-12), "flag": np.True_},
        {"subject": "Z", "n": 0, "x_mm": float("inf"), "flag": False, "note": None},
        {"subject": "Y", "n": 5, "x_mm": 123456789.123, "flag": False, "note": ""},
    ]
    columns = ["subject", "n", "x_mm", "flag", "note"]
    io.write_rows(rows, columns, tmp_path / "rows.csv")
    io.write_csv(pd.DataFrame(rows, columns=columns), tmp_path / "frame.csv")
    assert (tmp_path / "rows.csv").read_bytes() == (tmp_path / "frame.csv").read_bytes()


def test_read_trials_groups_as_pandas_does(tmp_path):
    """Trials come back per subject and depth, in file order, as a pandas groupby gives them."""
    path = tmp_path / "averaged.csv"
    path.write_text(
        "subject,depth_mm,distance_mm,left_mm,deflection_mm\n"
        "01,2,0.1,0.9,0.95\n"
        "01,1,0.1,0.4,0.45\n"
        "01,2,0.3,0.5,\n"
        "M2,1,0.2,0.3,0.25\n"
        "01,1,0.2,0.3,0.35\n",
        encoding="utf-8",
    )
    trials = io.read_trials(path)
    frame = io.read_results_csv(path)
    expected = {}
    for subject, rows in frame.groupby("subject", sort=False):
        expected[subject] = {
            depth: (list(group["distance_mm"]), list(group["deflection_mm"]))
            for depth, group in rows.groupby("depth_mm", sort=True)
        }
    assert list(trials) == list(expected) == ["01", "M2"]
    assert {s: list(d) for s, d in trials.items()} == {"01": [1.0, 2.0], "M2": [1.0]}
    for subject, depths in expected.items():
        assert list(trials[subject]) == list(depths)
        for depth, (x, y) in depths.items():
            # the same text through numpy's reader and pandas' default one, which may
            # round the last bit differently; NaN where the cell is empty
            for ours, theirs in ((trials[subject][depth][0], x), (trials[subject][depth][1], y)):
                np.testing.assert_allclose(ours, theirs, rtol=2 * np.finfo(float).eps)


def test_read_trials_names_a_missing_column(tmp_path):
    path = tmp_path / "averaged.csv"
    path.write_text("subject,depth_mm,distance_mm\nA,1,0.1\n", encoding="utf-8")
    with pytest.raises(ValueError, match="deflection_mm"):
        io.read_trials(path)


def test_a_job_killed_while_writing_leaves_no_temporary_file(tmp_path):
    # a job (as the rules run them, inside output_to) killed with SIGTERM in the middle of
    # replaced_atomically: the temporary file goes, the destination never appears
    import subprocess
    import sys
    import time

    target = tmp_path / "figure.png"
    code = (
        "import time\n"
        "from lineload.io import output_to, replaced_atomically\n"
        f"with output_to({str(tmp_path / 'job.log')!r}):\n"
        f"    with replaced_atomically({str(target)!r}) as temporary:\n"
        "        open(temporary, 'w').write('half')\n"
        "        print('writing', flush=True)\n"
        "        time.sleep(30)\n"
    )
    job = subprocess.Popen([sys.executable, "-c", code])
    deadline = time.monotonic() + 20
    while not list(tmp_path.glob(".figure.png.*.tmp")) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert list(tmp_path.glob(".figure.png.*.tmp")), "the job never started writing"
    job.terminate()
    assert job.wait(timeout=10) == 128 + 15
    assert not list(tmp_path.glob(".*.tmp")) and not target.exists()


@pytest.mark.parametrize(
    "names, cells",
    [
        (["a", "b"], [["1", "2.5"], ["x", ""]]),  # plain: joined
        (["a", "b"], [["1", ""], ['say "hi"', "x,y"]]),  # quotes needed
        (["a", "b"], [[], []]),  # header only
        (["only"], [["", "x"]]),  # an empty cell alone on its line is quoted
        (["a", "b", "c"], [["", ""], ["", ""], ["line\nbreak", "z"]]),
    ],
)
def test_csv_text_writes_the_bytes_of_the_csv_module(names, cells):
    import csv
    import io as stdio

    buffer = stdio.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(names)
    writer.writerows(zip(*cells, strict=True))
    assert io.csv_text(names, cells) == buffer.getvalue()


def test_csv_text_checks_only_the_columns_it_is_told_may_need_quotes():
    cells = [["1", "2"], ["a,b", "c"]]
    assert io.csv_text(["n", "t"], cells, may_quote=[cells[1]]) == 'n,t\n1,"a,b"\n2,c\n'
    # a column left out of the check is trusted to need no quotes (numbers)
    assert io.csv_text(["n", "t"], cells, may_quote=[cells[0]]) == "n,t\n1,a,b\n2,c\n"


def test_row_writer_without_quoted_cells_matches_the_pandas_writer(tmp_path):
    rows = [{"subject": "M1", "x_mm": 0.25, "n": 3}, {"subject": "H1", "x_mm": float("nan")}]
    columns = ["subject", "x_mm", "n"]
    io.write_rows(rows, columns, tmp_path / "rows.csv")
    io.write_csv(pd.DataFrame(rows, columns=columns).astype({"n": "Int64"}), tmp_path / "f.csv")
    assert (tmp_path / "rows.csv").read_bytes() == (tmp_path / "f.csv").read_bytes()
    assert (tmp_path / "rows.csv").read_bytes() == b"subject,x_mm,n\nM1,0.25,3\nH1,,\n"


def test_a_full_disk_names_the_output_that_could_not_be_written(tmp_path, capfd):
    # a real failed write: /dev/full refuses every byte, and the error names no file
    log = tmp_path / "job.log"
    destination = tmp_path / "tables" / "fits.csv"
    with pytest.raises(SystemExit) as stopped, io.output_to(log):
        with io.replaced_atomically(destination), open("/dev/full", "w") as full:
            full.write("x")
            full.flush()
    assert stopped.value.code == 1
    said = capfd.readouterr().err
    assert said == (
        f"Error: could not write {destination}: {os.strerror(errno.ENOSPC)}; the disk is "
        "full: free some space and run the same command again\n"
    )
    assert "Traceback" in log.read_text()  # the details stay in the job's log
    assert not list((tmp_path / "tables").iterdir())  # and no temporary is left


@pytest.mark.parametrize(
    ("code", "words"),
    [(errno.EROFS, "read-only disk"), (errno.EACCES, "choose a results folder")],
)
def test_an_output_on_a_read_only_disk_or_without_permission_says_so(tmp_path, capfd, code, words):
    destination = tmp_path / "fits.csv"
    with pytest.raises(SystemExit), io.output_to(tmp_path / "job.log"):
        with io.replaced_atomically(destination):
            raise OSError(code, os.strerror(code))
    said = capfd.readouterr().err
    assert said.startswith(f"Error: could not write {destination}: {os.strerror(code)}; ")
    assert words in said and said.count("\n") == 1


def test_a_file_that_cannot_be_read_is_not_blamed_on_the_results_folder(tmp_path, capfd):
    # a raw file without read permission: no advice to move the results
    with pytest.raises(SystemExit), io.output_to(tmp_path / "job.log"):
        raise PermissionError(errno.EACCES, "Permission denied", "/data/raw/profiles/M1.csv")
    said = capfd.readouterr().err
    assert said == (
        "Error: could not open /data/raw/profiles/M1.csv: Permission denied; no permission: "
        "check the permissions of the file and its folders\n"
    )


def test_a_figure_path_that_is_a_folder_is_one_sentence(tmp_path, capfd):
    (tmp_path / "figure.pdf").mkdir()
    with pytest.raises(SystemExit), io.output_to(tmp_path / "job.log"):
        io.write_text("x", tmp_path / "figure.pdf")
    said = capfd.readouterr().err
    assert said.startswith(f"Error: could not write {tmp_path / 'figure.pdf'}")
    assert "a folder stands where the file belongs" in said


def test_other_errors_keep_their_traceback(tmp_path):
    # an error the job cannot explain is a bug: it stays an exception, with its traceback
    with pytest.raises(FileNotFoundError), io.output_to(tmp_path / "job.log"):
        open(tmp_path / "missing.csv")


def test_a_temporary_file_is_named_by_the_file_it_stands_for(tmp_path):
    # a full disk fails while the temporary is written: the message names the output
    with io.replaced_atomically(tmp_path / "fits.csv") as temporary:
        assert io._destination(temporary) == str(tmp_path / "fits.csv")
        Path(temporary).write_text("x")
    assert io._destination(tmp_path / "notes.txt") == str(tmp_path / "notes.txt")


def test_a_table_without_rows_has_no_trials(tmp_path):
    path = tmp_path / "averaged.csv"
    path.write_text("subject,depth_mm,distance_mm,deflection_mm\n", encoding="utf-8")
    assert io.read_trials(path) == {}


@pytest.mark.parametrize("name", ["config", "subjects", "profiles", "outlines", "forces", "images"])
def test_a_schema_reads_as_pyyaml_reads_it_and_a_changed_copy_stays_a_copy(name):
    import yaml

    from lineload.io import SCHEMA_DIR, load_schema

    text = (SCHEMA_DIR / f"{name}.schema.yaml").read_text(encoding="utf-8")
    first = load_schema(name)
    assert first == yaml.safe_load(text)  # the libyaml parse gives the same dict
    first["properties"] = "changed by a caller"
    assert load_schema(name) == yaml.safe_load(text)  # the cached one is untouched
