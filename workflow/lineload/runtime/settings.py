"""Settings given on the command line, typed as they would be in a config file.

Snakemake 9 reads ``--config KEY=VALUE`` before the workflow is loaded, and two
of its choices get in the way of nested settings:

* a key must be a plain identifier: ``figures.example_depth_mm=1.25`` (or
  ``figures:example_depth_mm``) stops Snakemake with a traceback before this
  workflow can say anything (snakemake/snakemake issues 1975 and 3907);
* a value that is a YAML mapping or list is read with YAML's *base* loader,
  which keeps every leaf as text: ``figures='{example_depth_mm: 1.25}'``
  arrives as ``{'example_depth_mm': '1.25'}``, and the schema then refuses
  1.25 as "not a number".  ``null`` arrives as the text ``'null'``.

:func:`apply_command_line` repairs both from the raw ``KEY=VALUE`` words,
before the config is validated: a value that is a YAML mapping or list is read
again with YAML's safe loader (numbers stay numbers, ``null`` is None), a bare
``null`` becomes None, and a key with ``__`` names a nested setting
(``figures__example_depth_mm=1.25``).  Other values keep Snakemake's reading
when it is a number or ``True``/``False``, and are otherwise the text as typed.

Standard library and PyYAML only: Snakemake calls this while it parses the
workflow.
"""

from __future__ import annotations

__all__ = ["NESTED_SEPARATOR", "apply_command_line", "typed_value"]

#: Joins the levels of a nested key on the command line: ``figures__example_depth_mm``.
NESTED_SEPARATOR = "__"

_NULL = ("null", "Null", "NULL", "~")


def typed_value(text, as_read):
    """A command-line value as a config file would give it.

    Parameters
    ----------
    text : str
        The VALUE of ``KEY=VALUE`` as typed.
    as_read : object
        What Snakemake made of it.

    Returns
    -------
    object
        A mapping or list read again by YAML's safe loader (so ``1.25`` is a
        number and ``null`` is None); None for a bare ``null``; a number or
        ``True``/``False`` as Snakemake read it; else the text as typed (YAML's
        base loader would cut ``Sample #3`` at the ``#`` and turn ``Note: x``
        into a mapping).
    """
    import yaml

    stripped = text.strip()
    if stripped in _NULL:
        return None
    if stripped[:1] in ("{", "["):
        try:
            value = yaml.safe_load(stripped)
        except yaml.YAMLError:
            return as_read
        if isinstance(value, (dict, list)):
            return value
    if isinstance(as_read, (bool, int, float)):
        return as_read
    return text


def _merge(target, overrides):
    """Update a nested dict in place, level by level (as Snakemake merges configs)."""
    for key, value in overrides.items():
        if isinstance(value, dict) and isinstance(target.get(key), dict):
            _merge(target[key], value)
        else:
            target[key] = value


def apply_command_line(config, entries):
    """Retype ``--config`` values and move ``a__b=value`` keys into place, in ``config``.

    Parameters
    ----------
    config : dict
        The config as Snakemake merged it (config files, then ``--config``);
        changed in place.
    entries : sequence of str or None
        The ``KEY=VALUE`` words given to ``--config`` (Snakemake's
        ``workflow.config_settings.config_args``), in order.

    Returns
    -------
    dict
        ``config``.
    """
    for entry in entries or ():
        if not isinstance(entry, str) or "=" not in entry:
            continue
        key, text = entry.split("=", 1)
        key = key.strip()
        if key not in config:
            continue
        value = typed_value(text, config[key])
        path = key.split(NESTED_SEPARATOR)
        if len(path) > 1 and all(path):
            del config[key]
        else:
            path = [key]
        target = config
        for part in path[:-1]:
            if not isinstance(target.get(part), dict):
                target[part] = {}
            target = target[part]
        _merge(target, {path[-1]: value})
    return config
