"""The config's keys as a Markdown table, written from the config schema.

Every setting's default and meaning is written once, in
``workflow/schemas/config.schema.yaml``; ``config/README.md`` shows them as tables
generated here, between two marker lines, so the page cannot drift from the
schema.  Rewrite it after editing the schema with::

    python -m lineload.publishing.configdoc config/README.md

and a test fails while the page is not current.  Standard library and PyYAML only.
"""

from __future__ import annotations

import re
import sys

from lineload.io import load_schema

__all__ = ["BEGIN", "END", "config_tables", "main", "updated_readme"]

#: The lines between which the generated tables stand in config/README.md.
BEGIN = "<!-- generated from workflow/schemas/config.schema.yaml: do not edit by hand -->"
END = "<!-- end of the generated tables -->"

_HEADER = "| key | type | default | meaning |\n|---|---|---|---|"
_BOUNDS = (
    ("exclusiveMinimum", ">"),
    ("minimum", ">="),
    ("exclusiveMaximum", "<"),
    ("maximum", "<="),
)
_NAMES = {"number": "number", "integer": "integer", "string": "text", "boolean": "true or false"}


def _value(value):
    """A value as it is typed in a config file (YAML's flow style)."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, list):
        return "[" + ", ".join(_value(item) for item in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k}: {_value(v)}" for k, v in value.items()) + "}"
    return str(value)


def _bounds(rules):
    parts = [f"{sign} {_value(rules[key])}" for key, sign in _BOUNDS if key in rules]
    return " and ".join(parts)


def _kind(rules):
    """What a key takes, in words: ``number > 0 and <= 50``, ``list of text``, ..."""
    if "oneOf" in rules:
        return " or ".join(_kind(option) for option in rules["oneOf"])
    if "const" in rules:
        return f"`{_value(rules['const'])}`"
    if "enum" in rules:
        return " or ".join(f"`{_value(option)}`" for option in rules["enum"])
    types = rules.get("type", [])
    types = [types] if isinstance(types, str) else list(types)
    nullable = "null" in types
    names = []
    for name in (t for t in types if t != "null"):
        if name == "array":
            items = rules.get("items", {})
            words = f"list of {_kind(items)}"
            if "maxItems" in rules:
                words += f", at most {rules['maxItems']}"
            if "minItems" in rules:
                words += f", at least {rules['minItems']}"
            names.append(words)
        else:
            bounds = _bounds(rules)
            names.append(_NAMES.get(name, name) + (f" {bounds}" if bounds else ""))
    if nullable:
        names.append("null")
    return " or ".join(names)


def _cell(text):
    """One line of a table cell: whitespace folded, the column sign escaped."""
    return re.sub(r"\s+", " ", str(text)).strip().replace("|", "\\|")


def _rows(properties):
    return [
        f"| `{key}` | {_cell(_kind(rules))} | `{_value(rules.get('default'))}` "
        f"| {_cell(rules.get('description', ''))} |"
        for key, rules in properties.items()
        if "properties" not in rules
    ]


def config_tables(schema):
    """The config's keys, section by section, as Markdown.

    Parameters
    ----------
    schema : dict
        The config schema (``load_schema("config")``).

    Returns
    -------
    str
        A table of the top-level settings, then a heading, the section's
        description and a table for each section (``figures``, ``claims``, ...):
        key, what it takes, its default and its meaning, all read from the schema.
    """
    properties = schema["properties"]
    blocks = ["### Top level", _HEADER + "\n" + "\n".join(_rows(properties))]
    for key, rules in properties.items():
        if "properties" in rules:
            blocks.append(f"### `{key}`")
            if rules.get("description"):
                blocks.append(re.sub(r"\s+", " ", rules["description"]).strip())
            blocks.append(_HEADER + "\n" + "\n".join(_rows(rules["properties"])))
    return "\n\n".join(blocks) + "\n"


def updated_readme(text, schema):
    """``text`` with the part between :data:`BEGIN` and :data:`END` generated anew.

    Parameters
    ----------
    text : str
        The page, holding both marker lines.
    schema : dict
        The config schema.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        If a marker line is missing or they are out of order.
    """
    start, stop = text.find(BEGIN), text.find(END)
    if start < 0 or stop < start:
        raise ValueError(f"the page needs the line {BEGIN!r} and, after it, {END!r}")
    head = text[: start + len(BEGIN)]
    return f"{head}\n\n{config_tables(schema)}\n{text[stop:]}"


def main(argv=None):
    """Rewrite the generated part of a page (default: ``config/README.md``)."""
    argv = sys.argv[1:] if argv is None else argv
    path = argv[0] if argv else "config/README.md"
    try:
        with open(path, encoding="utf-8") as handle:
            text = handle.read()
        new = updated_readme(text, load_schema("config"))
        with open(path, "w", encoding="utf-8") as handle:
            handle.write(new)
    except (OSError, ValueError) as error:
        print(f"error: {path}: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
