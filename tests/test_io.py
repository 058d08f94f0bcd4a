"""Output files: atomic, byte-stable, readable by others like any file the user writes."""

import os

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
