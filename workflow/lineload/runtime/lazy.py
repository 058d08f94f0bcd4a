"""A module imported when first used, so that what Snakemake reads at start-up stays light.

Snakemake parses the rule files (a run, a dry run, ``snakemake --lint``) with the
standard library and PyYAML only where the workflow catalog lints it: the package's
start-up path (the config, the subject sheet, the raw folder's listing) must not import
numpy.  A module that needs numpy for its other functions binds it with
:func:`lazy_import`; the import happens at the first attribute looked up.
"""

from __future__ import annotations

import importlib

__all__ = ["lazy_import"]


class _LazyModule:
    """Stands for a module until an attribute of it is first needed."""

    def __init__(self, name):
        self._name = name

    def __getattr__(self, attribute):
        # called only for a name not yet looked up: each is then kept on the
        # stand-in, so that a loop calling np.<function> pays for a plain lookup
        # (an import_module call per access cost 3 us, 0.3 s of a raw-data check)
        value = getattr(importlib.import_module(self._name), attribute)
        setattr(self, attribute, value)
        return value

    def __repr__(self):
        return f"<module {self._name!r}, imported when first used>"


def lazy_import(name):
    """Return a stand-in for module ``name`` that imports it at its first use.

    Parameters
    ----------
    name : str
        The module's full name, e.g. ``"numpy"``.

    Returns
    -------
    object
        Attribute access (``np.asarray``) imports the module (once: Python keeps it
        in ``sys.modules``) and returns the module's attribute, kept for the next
        access.
    """
    return _LazyModule(name)
