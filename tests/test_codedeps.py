"""The package files a workflow script depends on, from its real imports."""

from pathlib import Path

import pytest

from lineload.runtime import codedeps


def write(folder, files):
    for name, text in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)


@pytest.fixture
def package(tmp_path):
    """A package named lineload with a known import graph."""
    root = tmp_path / "lineload"
    write(
        root,
        {
            "__init__.py": '"""Package."""\n',
            "models.py": "import math\nimport numpy as np\n",
            "fitting.py": "from .models import curve\n",
            "paper.py": "",
            "tables.py": "def f():\n    from . import paper\n",
            "figures/__init__.py": "",
            "figures/style.py": "from ..paper import SPECIES\n",
            "figures/schematics.py": "from .style import STYLE\nfrom .. import models\n",
            "figures/supplements.py": "from lineload.figures.style import STYLE\n"
            "from lineload import fitting\n",
            "figures/registry.py": "",
        },
    )
    return root


def names(files, package):
    return sorted(str(Path(f).relative_to(package)) for f in files)


def deps(tmp_path, package, text, modules=()):
    script = tmp_path / "script.py"
    script.write_text(text)
    return names(codedeps.script_dependencies(script, modules, package_dir=package), package)


def test_every_form_of_import_is_followed(tmp_path, package):
    assert deps(tmp_path, package, "import lineload.models as m\n") == [
        "__init__.py",
        "models.py",
    ]
    # `from lineload import fitting` imports the module, and fitting imports models
    assert deps(tmp_path, package, "from lineload import fitting\n") == [
        "__init__.py",
        "fitting.py",
        "models.py",
    ]
    assert deps(tmp_path, package, "from lineload.fitting import fit\n") == [
        "__init__.py",
        "fitting.py",
        "models.py",
    ]
    # an import inside a function runs when it is called, so it counts; relative imports
    # resolve from the module that makes them
    assert deps(tmp_path, package, "def f():\n    import lineload.tables\n") == [
        "__init__.py",
        "paper.py",
        "tables.py",
    ]
    # other packages and the standard library are not ours
    assert deps(tmp_path, package, "import numpy\nimport os.path\nimport lineloader\n") == []


def test_subpackages_and_their_parents(tmp_path, package):
    assert deps(tmp_path, package, "from lineload.figures import schematics\n") == [
        "__init__.py",
        "figures/__init__.py",
        "figures/schematics.py",
        "figures/style.py",
        "models.py",
        "paper.py",
    ]
    # a schematics job does not depend on the fit code, a supplements job does
    supplements = deps(tmp_path, package, "import lineload.figures.supplements\n")
    assert "fitting.py" in supplements and "models.py" in supplements


def test_modules_imported_by_name_at_run_time(tmp_path, package):
    script = "from lineload.figures import registry\n"
    assert "figures/schematics.py" not in deps(tmp_path, package, script)
    named = deps(tmp_path, package, script, modules=["lineload.figures.schematics"])
    assert {"figures/registry.py", "figures/schematics.py", "figures/style.py"} <= set(named)


def test_the_workflow_scripts_see_their_modules():
    # on the real package: the fit job runs the models, not the claims
    script = codedeps.PACKAGE_DIR.parents[0] / "scripts" / "fit_models.py"
    package = codedeps.PACKAGE_DIR
    files = {Path(f).relative_to(package).as_posix() for f in codedeps.script_dependencies(script)}
    assert {"fitting/batch.py", "fitting/__init__.py", "models.py"} <= files
    assert not any(f.startswith("claims/") for f in files)


def test_import_statements_over_several_lines_and_look_alikes(tmp_path, package):
    text = (
        '"""A docstring that mentions\n'
        "from lineload.tables import\n"  # not a statement: does not parse, skipped
        '"""\n'
        "from lineload.fitting import (\n"
        "    fit,\n"
        "    other,\n"
        ")\n"
        "from lineload.figures.style import \\\n"
        "    STYLE\n"
    )
    assert deps(tmp_path, package, text) == [
        "__init__.py",
        "figures/__init__.py",
        "figures/style.py",
        "fitting.py",
        "models.py",
        "paper.py",
    ]


LOADED = """
import ast, json, sys
sys.path.insert(0, {path_entry!r})
found = {{}}
for script in {scripts!r}:
    for name in [m for m in sys.modules if m == "lineload" or m.startswith("lineload.")]:
        del sys.modules[name]
    with open(script, encoding="utf-8") as handle:
        tree = ast.parse(handle.read())
    imports = [n for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom))]
    exec(compile(ast.Module(body=imports, type_ignores=[]), script, "exec"), {{}})
    found[script] = sorted(
        module.__file__
        for name, module in sys.modules.items()
        if (name == "lineload" or name.startswith("lineload.")) and module.__file__
    )
print(json.dumps(found))
"""


def unseen_dependencies(scripts, package_dir):
    """Per script, the package files its top-level imports really load (in a fresh
    interpreter) that :func:`codedeps.script_dependencies` does not list."""
    import json
    import subprocess
    import sys

    code = LOADED.format(path_entry=str(package_dir.parent), scripts=[str(s) for s in scripts])
    process = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    )
    loaded = json.loads(process.stdout.strip().splitlines()[-1])
    unseen = {}
    for script, files in loaded.items():
        listed = set(codedeps.script_dependencies(script, package_dir=package_dir))
        missing = sorted(
            str(Path(f).relative_to(package_dir))
            for f in files
            if f not in listed and Path(f) != package_dir / "__init__.py"
        )
        if missing:
            unseen[Path(script).name] = missing
    return unseen


def test_every_module_a_script_loads_is_one_of_its_dependencies():
    # a module that a job runs but its rule does not list would not rerun the job when
    # it changes: e.g. a package face that imports its modules on first use (PEP 562),
    # which no import statement shows
    scripts = sorted((Path(codedeps.PACKAGE_DIR).parent / "scripts").glob("*.py"))
    assert len(scripts) > 20
    assert unseen_dependencies(scripts, Path(codedeps.PACKAGE_DIR)) == {}


def test_a_module_loaded_out_of_sight_of_import_statements_is_found(tmp_path, package):
    # the check above can fail: a package face importing a module by name
    write(
        package,
        {
            "__init__.py": "import importlib\n"
            "def __getattr__(name):\n"
            "    return getattr(importlib.import_module('lineload.fitting'), name)\n"
            "curve = __getattr__('curve')\n",
            "models.py": "curve = 1\n",
        },
    )
    script = tmp_path / "script.py"
    script.write_text("from lineload import curve\n")
    assert unseen_dependencies([script], package) == {"script.py": ["fitting.py", "models.py"]}
