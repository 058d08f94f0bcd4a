# Loads and validates the config and every raw input before any job is planned.
# A broken input stops the run here with one message naming file, line and
# column: no job starts, so nothing partial is written.
import sys
from pathlib import Path

from snakemake.exceptions import WorkflowError
from snakemake.utils import min_version, validate

min_version("9.0")

WORKFLOW_DIR = Path(workflow.basedir) / "workflow"
sys.path.insert(0, str(WORKFLOW_DIR))

from lineload.io import load_schema  # noqa: E402
from lineload.validation import InputError, check_dataset  # noqa: E402


def abort(message):
    """Print one line for the user and stop with a non-zero exit, no traceback."""
    sys.stderr.write(f"Error: {message}\n")
    raise SystemExit(1)


def schema_message(error, what):
    """One line from a snakemake.utils.validate failure (a jsonschema error inside)."""
    inner = error.__context__
    if not hasattr(inner, "absolute_path"):
        return f"{what}: {error}"
    where = "/".join(str(p) for p in inner.absolute_path)
    return f"{what}, key '{where}': {inner.message}" if where else f"{what}: {inner.message}"


try:
    validate(config, "../schemas/config.schema.yaml")
except WorkflowError as error:
    abort(schema_message(error, "config"))

RAW = config["raw_data"]
RES = config["results"]
PYTHON = f'"{sys.executable}"'
SCRIPTS = WORKFLOW_DIR / "scripts"

try:
    DATASET = check_dataset(
        RAW, {name: load_schema(name) for name in ("subjects", "profiles", "outlines")}
    )
    validate(DATASET["subjects"], "../schemas/subjects.schema.yaml")
except InputError as error:
    abort(str(error))
except WorkflowError as error:
    abort(schema_message(error, f"{RAW}/subjects.csv"))

SUBJECTS = DATASET["subjects"].set_index("subject", drop=False)
SUBJECT_IDS = list(SUBJECTS["subject"])


wildcard_constraints:
    subject="[A-Za-z0-9_-]+",


def result(*parts):
    """Path of an output under the results folder."""
    return str(Path(RES, *parts))
