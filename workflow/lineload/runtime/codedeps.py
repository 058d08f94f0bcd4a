"""Which modules of this package a workflow script runs, read from its real imports.

Snakemake reruns a ``script:`` job when the script changes, but not when a module
it imports does.  The workflow therefore declares the package modules each job
runs as inputs of its rule, computed here from the ``import`` statements of the
script and, transitively, of every module it reaches (absolute ``lineload``
imports and relative ones, at module level or inside functions, since either
runs when called).  Standard library only, so it is cheap at parse time.
"""

from __future__ import annotations

import ast
import os
import re
import textwrap
from functools import cache
from pathlib import Path

__all__ = ["PACKAGE", "PACKAGE_DIR", "module_files", "script_dependencies"]

PACKAGE = "lineload"
#: The folder of this package.
PACKAGE_DIR = Path(__file__).resolve().parents[1]


@cache
def _layout(package_dir):
    """The package's folders and ``.py`` files, relative (POSIX), listed once a process.

    One walk of the folder instead of a file-system look-up for every name an
    import statement might mean (Snakemake reads the rules on every start)."""
    folders, files = set(), set()
    for folder, subfolders, names in os.walk(package_dir):
        relative = os.path.relpath(folder, package_dir).replace(os.sep, "/")
        prefix = "" if relative == "." else f"{relative}/"
        subfolders[:] = [d for d in subfolders if d != "__pycache__"]
        folders.update(prefix + d for d in subfolders)
        files.update(prefix + n for n in names if n.endswith(".py"))
    return frozenset(folders), frozenset(files)


def module_files(module, package_dir=PACKAGE_DIR):
    """Source files that make up a dotted module name of this package.

    ``lineload.figures.style`` is ``figures/style.py``, and importing it runs
    ``lineload/__init__.py`` and ``figures/__init__.py`` too.

    Parameters
    ----------
    module : str
        Dotted name starting with ``lineload``.
    package_dir : pathlib.Path, optional
        Folder of the package (tests point it at a package of their own).  Its
        layout is read once a process (:func:`_layout`).

    Returns
    -------
    list of pathlib.Path
        Existing files, packages' ``__init__.py`` first; empty if the name is
        not a module of this package.
    """
    return [Path(name) for name in _module_files(module, str(package_dir))]


@cache
def _module_files(module, package_dir):
    """:func:`module_files` as paths (str), once a process per name (the layout is too)."""
    parts = module.split(".")
    if parts[0] != PACKAGE:
        return ()
    folders, sources = _layout(package_dir)
    found, prefix = [], ""
    for part in parts[1:]:
        if f"{prefix}__init__.py" in sources:
            found.append(f"{prefix}__init__.py")
        if f"{prefix}{part}" in folders:
            prefix = f"{prefix}{part}/"
        elif f"{prefix}{part}.py" in sources:
            found.append(f"{prefix}{part}.py")
            return _paths(found, package_dir)
        else:
            return ()
    if f"{prefix}__init__.py" in sources:
        found.append(f"{prefix}__init__.py")
    return _paths(found, package_dir)


def _paths(names, package_dir):
    """Paths (str) of files named relative (POSIX) to the package's folder."""
    return tuple(os.path.join(package_dir, *name.split("/")) for name in names)


def _module_name(path, package_dir):
    """Dotted name of a file of this package (``figures/__init__.py`` -> ``lineload.figures``)."""
    relative = os.path.splitext(os.path.relpath(path, package_dir))[0]
    parts = [PACKAGE, *relative.split(os.sep)]
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


#: Where an import statement may start: a line beginning ``import x`` or ``from x import``.
_IMPORT_START = re.compile(r"^[ \t]*(?:import[ \t]+\w|from[ \t]+[.\w]+[ \t]+import\b)", re.M)


def _import_statements(text):
    """The import statements of a source text, each parsed on its own.

    Parsing a whole module costs far more than its few import lines; each
    candidate statement (with its parenthesised or backslash continuation) is
    parsed alone.  A candidate that is not Python (a line of a docstring that
    looks like an import but is not one) does not parse and is skipped; one
    that does parse is counted, which can only add a dependency, never miss one.
    """
    for match in _IMPORT_START.finditer(text):
        end, depth = match.start(), 0
        while True:
            newline = text.find("\n", end)
            line = text[end : newline if newline >= 0 else len(text)]
            depth += line.count("(") - line.count(")")
            end = newline + 1 if newline >= 0 else len(text)
            if newline < 0 or (depth <= 0 and not line.rstrip().endswith("\\")):
                break
        try:
            yield from ast.parse(textwrap.dedent(text[match.start() : end])).body
        except SyntaxError:
            continue


def _imported_modules(path, package_dir):
    """Dotted names of this package's modules that a file imports (candidates, unchecked)."""
    with open(path, encoding="utf-8") as handle:
        statements = _import_statements(handle.read())
    resolved = os.path.realpath(path)
    inside = resolved.startswith(os.path.join(package_dir, ""))
    here = _module_name(resolved, package_dir) if inside else None
    is_package = os.path.basename(path) == "__init__.py"
    for node in statements:
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                if here is None:
                    continue
                base = here.split(".")
                base = base if is_package else base[:-1]
                base = base[: len(base) - (node.level - 1)]
                stem = ".".join(base + ([node.module] if node.module else []))
            else:
                stem = node.module or ""
            yield stem
            # `from lineload import fitting` imports the module lineload.fitting.batch
            for alias in node.names:
                yield f"{stem}.{alias.name}"


@cache
def _direct(path, stamp, package_dir):
    """This package's files a file imports directly (``stamp`` keys the cache to its version)."""
    files = {}
    for module in _imported_modules(path, package_dir):
        files.update(dict.fromkeys(_module_files(module, package_dir)))
    return tuple(files)


def _closure(path, package_dir):
    """Every file of this package reached from ``path`` by imports."""
    found, queue = {}, [path]
    while queue:
        current = queue.pop()
        status = os.stat(current)
        for file in _direct(current, (status.st_mtime_ns, status.st_size), package_dir):
            if file not in found:
                found[file] = None
                queue.append(file)
    return found


def script_dependencies(script, modules=(), package_dir=PACKAGE_DIR):
    """The package files a script runs: its imports, theirs, and so on.

    Parameters
    ----------
    script : str or os.PathLike
        A Python file (a workflow script or a module).
    modules : iterable of str, optional
        Dotted names the script imports by name at run time (``importlib``),
        which no ``import`` statement shows; their imports are followed too.
    package_dir : pathlib.Path, optional
        Folder of the package (tests point it at a package of their own).

    Returns
    -------
    list of str
        Paths of the package's source files, sorted, without the script itself.
    """
    package_dir = str(Path(package_dir).resolve())
    files = set(_closure(str(Path(script).resolve()), package_dir))
    for module in modules:
        for file in _module_files(module, package_dir):
            files.add(file)
            files.update(_closure(file, package_dir))
    return sorted(files)
