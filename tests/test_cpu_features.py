"""The fits agree across numpy's CPU kernels to the tolerance rounding allows.

numpy chooses SIMD kernels at run time (AVX-512, AVX2, SSE); a sum or a sine can
round differently from one to the other.  Results are promised byte-identical
for two builds on the same machine, and equal to the derived tolerance of
:mod:`numerics` across machines.  ``NPY_DISABLE_CPU_FEATURES`` switches the
newer kernels off for one process, so both sides are compared here on one
machine (on a CPU without them, both runs take the same kernels and agree).
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import REPO
from lineload.fitting import batch as fitting
from lineload.simulation.coverage import TRUE_NOISE
from numerics import assert_rows_agree
from test_batch import averaged_trials, edge_trials

SCRIPT = """
import json, sys
sys.path[:0] = [{tests!r}]
from test_batch import averaged_trials, edge_trials
from conftest import REPO
from lineload.fitting import batch as fitting
from lineload.simulation.coverage import TRUE_NOISE
trials = [(t[2], t[3], t[1]) for t in averaged_trials(REPO / "data" / "raw")] + edge_trials()
x, y, depth = zip(*trials)
json.dump(
    {{
        "plain": fitting.fit_trials(x, y, depth, 3.0),
        "noise": fitting.fit_trials(x, y, depth, 3.0, noise=TRUE_NOISE),
    }},
    sys.stdout,
)
"""


def shipped_and_edge_trials():
    trials = [(t[2], t[3], t[1]) for t in averaged_trials(REPO / "data" / "raw")]
    return trials + edge_trials()


def as_rows(rows):
    """Rows read back from JSON (which writes NaN and infinities as numpy reads them)."""
    rows = [{k: (v if isinstance(v, str) else float(v)) for k, v in row.items()} for row in rows]
    for row in rows:
        row["n_points"] = int(row["n_points"])
    return rows


@pytest.mark.parametrize("disabled", ["X86_V4", "X86_V4 X86_V3"])
def test_fits_agree_with_newer_vector_kernels_switched_off(disabled):
    env = {**os.environ, "NPY_DISABLE_CPU_FEATURES": disabled}
    code = SCRIPT.format(tests=str(REPO / "tests"))
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, check=False
    )
    assert done.returncode == 0, done.stderr[-2000:]
    other = json.loads(done.stdout)
    x, y, depth = zip(*shipped_and_edge_trials(), strict=True)
    # as in the tests of batches, and as the workflow's fit tables are (with the noise)
    here = fitting.fit_trials(x, y, depth, 3.0)
    assert_rows_agree(as_rows(other["plain"]), here, x, y)
    assert np.isfinite([row["arc_L_mm"] for row in here[:20]]).all()
    with_noise = fitting.fit_trials(x, y, depth, 3.0, noise=TRUE_NOISE)
    assert_rows_agree(as_rows(other["noise"]), with_noise, x, y, sandwich=True)
    assert np.isfinite([row["arc_L_ci_low_mm"] for row in with_noise[:20]]).all()
