"""Citation metadata: ``CITATION.cff`` is the one source, Zenodo's ``.zenodo.json`` follows it.

The version and the release date the article prints come from the citation file too, so
a release changes them in one place.  ``python -m lineload.publishing.citation`` prints the
``.zenodo.json`` the citation file implies (the tests compare it with the committed one).
"""

from __future__ import annotations

import datetime
import json
import sys
from importlib import metadata
from pathlib import Path

import yaml

__all__ = [
    "citation_or_default",
    "read_citation",
    "software_name",
    "zenodo_json",
    "zenodo_metadata",
]


def read_citation(path):
    """The citation file as a dictionary, with its dates as ISO text.

    Parameters
    ----------
    path : str or os.PathLike
        A ``CITATION.cff`` (YAML, Citation File Format 1.2.0).

    Returns
    -------
    dict

    Raises
    ------
    ValueError
        If the file is not YAML, is not a mapping, or has no title or version; the
        message names the file.
    """
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except yaml.YAMLError as error:
        raise ValueError(f"{path}: not valid YAML ({error})") from None
    if not isinstance(data, dict):
        raise ValueError(
            f"{path}: expected the keys of a citation file, found {type(data).__name__}"
        )
    missing = [key for key in ("title", "version") if not data.get(key)]
    if missing:
        raise ValueError(
            f"{path}: no {' or '.join(missing)} (the article and the archive read them)"
        )
    return {k: v.isoformat() if isinstance(v, datetime.date) else v for k, v in data.items()}


def citation_or_default(paths):
    """The citation file if there is one, else what the installed package says.

    A workflow deployed without the repository's documents (only ``workflow/`` and
    ``config/``, as a module or a copy) has no ``CITATION.cff``: then the name and
    version are the ``lineload`` package's, and no date, licence or author is claimed.

    Parameters
    ----------
    paths : str, os.PathLike or a list of them
        The citation file, or a list holding it or nothing (a rule's optional input).

    Returns
    -------
    dict
        As :func:`read_citation` returns it.
    """
    if isinstance(paths, (str, Path)):
        paths = [paths]
    for path in paths:
        if Path(path).is_file():
            return read_citation(path)
    try:
        version = metadata.version("lineload")
    except metadata.PackageNotFoundError:
        version = "unknown"
    return {
        "title": "lineload",
        "version": version,
        "message": "No CITATION.cff came with this copy of the workflow.",
        "authors": [],
    }


def software_name(citation):
    """The short name of the software: its title up to the first colon (``lineload``)."""
    return str(citation["title"]).split(":", 1)[0].strip()


#: The name CITATION.cff carries until a release names its authors.
PLACEHOLDER_AUTHOR = "The lineload contributors"


def author_names(citation):
    """The authors as a byline writes them (``"Ada Lovelace and Alan Turing"``) and
    whether they are the placeholder a release replaces (or absent).

    Parameters
    ----------
    citation : dict
        As :func:`read_citation` returns it.

    Returns
    -------
    tuple of (str, bool)
    """
    names = []
    for author in citation.get("authors") or []:
        if "name" in author:
            names.append(str(author["name"]))
        else:
            given, family = author.get("given-names", ""), author.get("family-names", "")
            names.append(f"{given} {family}".strip())
    placeholder = not names or names == [PLACEHOLDER_AUTHOR]
    text = ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else "".join(names)
    return text, placeholder


def _creator(author):
    """A Zenodo creator from a CFF person or entity."""
    if "name" in author:  # an entity (or a placeholder)
        creator = {"name": str(author["name"])}
    else:
        given, family = author.get("given-names", ""), author.get("family-names", "")
        creator = {"name": f"{family}, {given}".strip(", ")}
    if author.get("affiliation"):
        creator["affiliation"] = str(author["affiliation"])
    if author.get("orcid"):
        creator["orcid"] = str(author["orcid"]).rsplit("/", 1)[-1]
    return creator


def zenodo_metadata(citation):
    """The ``.zenodo.json`` deposit metadata a citation file implies.

    Parameters
    ----------
    citation : dict
        As :func:`read_citation` returns it.

    Returns
    -------
    dict
        Title, version, publication date (``date-released``), licence, creators in the
        citation's order, the description (its ``abstract``, else its ``message``), and
        each reference with a DOI as a related identifier.
    """
    metadata = {
        "upload_type": "software",
        "title": str(citation["title"]),
        "version": str(citation["version"]),
        "creators": [_creator(author) for author in citation.get("authors", [])],
        "description": " ".join(
            str(citation.get("abstract") or citation.get("message", "")).split()
        ),
    }
    if citation.get("date-released"):
        metadata["publication_date"] = str(citation["date-released"])
    if citation.get("license"):
        metadata["license"] = str(citation["license"])
    if citation.get("keywords"):
        metadata["keywords"] = [str(k) for k in citation["keywords"]]
    related = [
        {"identifier": str(ref["doi"]), "relation": "references", "scheme": "doi"}
        for ref in citation.get("references", [])
        if ref.get("doi")
    ]
    if related:
        metadata["related_identifiers"] = related
    return metadata


def zenodo_json(citation):
    """:func:`zenodo_metadata` as the text of ``.zenodo.json`` (two-space indent, newline)."""
    return json.dumps(zenodo_metadata(citation), indent=2, ensure_ascii=False) + "\n"


def main(argv=None):
    """Print the ``.zenodo.json`` of a citation file (default: ``CITATION.cff``)."""
    argv = sys.argv[1:] if argv is None else argv
    path = argv[0] if argv else "CITATION.cff"
    try:
        sys.stdout.write(zenodo_json(read_citation(path)))
    except (OSError, ValueError) as error:
        print(f"error: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
