"""The build as a Workflow Run RO-Crate, following the Provenance Run Crate profile.

The crate is written by the ``rocrate`` library from what the build already records:
every file with its size, SHA-256 and the rule that wrote it, the configuration as the
workflow's parameters with their values, the software and its versions, the commit,
and the licence and authors of ``CITATION.cff``.  It describes:

* the workflow (its ``Snakefile``, in the copy of the source the crate carries) as the
  main entity, a ``ComputationalWorkflow`` and ``HowTo`` whose steps are its rules;
* each rule as a tool (``SoftwareApplication``), run once by a ``CreateAction`` whose
  results are the files it wrote, and a ``ControlAction`` tying that run to its step;
* the whole run (a ``CreateAction`` of the workflow: the raw data and the parameter
  values in, every output out) and Snakemake's orchestration of it
  (an ``OrganizeAction``).

Nothing records a time or a random identifier: every ``@id`` is derived from a name,
``datePublished`` is the citation file's release date, and two builds of the same files
give the same bytes.
"""

from __future__ import annotations

import json
import os
from pathlib import Path, PurePosixPath

from lineload.io import write_text
from lineload.publishing.provenance import file_sha256

# rocrate (0.14 s to import) is imported where a crate is built, not here: Snakemake's
# start-up imports this module for source_files on every run

__all__ = [
    "CRATE_PROFILES",
    "MAIN_WORKFLOW",
    "METADATA",
    "RAW_FOLDER",
    "build_crate",
    "crate_json",
    "flat_parameters",
    "run_crate",
    "source_files",
    "write_crate",
]

#: The crate's metadata file, at its root.
METADATA = "ro-crate-metadata.json"
#: Where the crate keeps its copy of the raw inputs, and the workflow in its source copy.
RAW_FOLDER = "inputs"
MAIN_WORKFLOW = "source/workflow/Snakefile"

#: The profiles the crate follows: (permalink, name, version).
CRATE_PROFILES = (
    ("https://w3id.org/ro/wfrun/process/0.5", "Process Run Crate", "0.5"),
    ("https://w3id.org/ro/wfrun/workflow/0.5", "Workflow Run Crate", "0.5"),
    ("https://w3id.org/ro/wfrun/provenance/0.5", "Provenance Run Crate", "0.5"),
    ("https://w3id.org/workflowhub/workflow-ro-crate/1.0", "Workflow RO-Crate", "1.0"),
)

#: Media types by suffix, for ``encodingFormat``.
MEDIA_TYPES = {
    ".csv": "text/csv",
    ".md": "text/markdown",
    ".json": "application/json",
    ".pdf": "application/pdf",
    ".png": "image/png",
    ".html": "text/html",
    ".tex": "application/x-tex",
    ".yaml": "application/yaml",
    ".yml": "application/yaml",
    ".py": "text/x-python",
    ".typ": "text/plain",
    ".txt": "text/plain",
    ".log": "text/plain",
    ".tsv": "text/tab-separated-values",
    ".smk": "text/x-python",
    ".rst": "text/x-rst",
    ".cff": "application/yaml",
}
#: Files without a suffix that are plain text.
PLAIN_TEXT_NAMES = ("LICENSE", "Snakefile", "NOTICE")

#: bioschemas' own IRI for a computational workflow (see :func:`run_crate`).
BIOSCHEMAS_WORKFLOW = "https://bioschemas.org/ComputationalWorkflow"


def flat_parameters(config, prefix=""):
    """The configuration as ``{"section.key": value}``, in key order (nested sections
    flattened with dots; lists and empty values kept as they are)."""
    flat = {}
    for key in sorted(config):
        value = config[key]
        name = f"{prefix}{key}"
        if isinstance(value, dict) and value:
            flat.update(flat_parameters(value, f"{name}."))
        else:
            flat[name] = value
    return flat


#: The project's own files a run carries beside its workflow/ and config/ folders: the
#: pinned requirements, the raw data's contract and the documents.
SOURCE_DOCUMENTS = (
    "requirements.txt",
    "requirements-slurm.txt",
    "environment.yml",
    "pyproject.toml",
    "CITATION.cff",
    ".zenodo.json",
    "CHANGELOG.md",
    "LICENSE",
    "README.md",
    "data/README.md",
)


def source_files(repository):
    """The workflow's source as a run carries it: paths relative to the repository.

    Every file under ``workflow/`` and ``config/`` (no caches: no ``__pycache__``,
    compiled files or an editable install's ``.egg-info``) and
    :data:`SOURCE_DOCUMENTS`, in name order; files that do not exist are left out.

    Parameters
    ----------
    repository : str or os.PathLike
        The folder holding ``workflow/`` (the checkout).

    Returns
    -------
    list of str
    """
    repository = Path(repository)
    candidates = [
        *(repository / "workflow").rglob("*"),
        *(repository / "config").rglob("*"),
        *(repository / name for name in SOURCE_DOCUMENTS),
    ]

    def cache(path):
        return path.suffix == ".pyc" or any(
            part == "__pycache__" or part.endswith(".egg-info") for part in path.parts
        )

    return sorted(
        path.relative_to(repository).as_posix()
        for path in candidates
        if path.is_file() and not cache(path.relative_to(repository))
    )


def _value_type(value):
    """The FormalParameter ``additionalType`` of a configured value."""
    if isinstance(value, bool):
        return "Boolean"
    if isinstance(value, int):
        return "Integer"
    if isinstance(value, float):
        return "Float"
    return "Text"


def _value_text(value):
    """A configured value as the crate states it (JSON for lists, maps and none)."""
    if isinstance(value, str):
        return value
    return json.dumps(value, sort_keys=True)


def _entity(crate, identifier, properties):
    from rocrate.model.contextentity import ContextEntity

    return crate.add(ContextEntity(crate, identifier, properties=properties))


def _ref(entity):
    return {"@id": entity.id}


def run_crate(
    files,
    rules,
    parameters,
    citation,
    software,
    commit,
    main_workflow,
    raw_folder,
):
    """The run as an RO-Crate (``rocrate.ROCrate``; write it with :func:`crate_json`).

    Parameters
    ----------
    files : list of dict
        Every file of the crate, in the order to list them: ``name`` (its path in the
        crate, POSIX, relative), ``path`` (where to read it), ``rule`` (the rule that
        wrote it, or None for an input or a source file) and ``kind``: ``output``,
        ``log``, ``input`` (a raw file, under ``raw_folder``) or ``source``.
    rules : dict
        Rule name -> ``{"description": str, "source": name of its .smk in the crate}``,
        in the order the steps run.
    parameters : dict
        ``{"section.key": value}`` (:func:`flat_parameters` of the config in force).
    citation : dict
        ``CITATION.cff`` as :func:`lineload.publishing.citation.read_citation` reads it.
    software : dict
        ``python`` (version) and ``packages`` (name -> version; ``snakemake`` among them).
    commit : str or None
        The git commit built (None outside a git checkout).
    main_workflow : str
        The crate name of the workflow's ``Snakefile`` (a ``source`` file).
    raw_folder : str
        The crate folder that holds the raw inputs.

    Returns
    -------
    rocrate.rocrate.ROCrate
    """
    from rocrate.rocrate import ROCrate

    crate = ROCrate()
    root = crate.root_dataset
    root["name"] = str(citation["title"])
    root["description"] = " ".join(
        str(citation.get("abstract") or citation.get("message", "")).split()
    )
    root["version"] = str(citation["version"])
    root["datePublished"] = str(citation.get("date-released") or "")
    licence = str(citation.get("license", ""))
    if licence:
        root["license"] = _entity(
            crate,
            f"https://spdx.org/licenses/{licence}",
            {"@type": "CreativeWork", "name": f"{licence} License", "identifier": licence},
        )
    authors = []
    for number, author in enumerate(citation.get("authors", []), start=1):
        if "name" in author:
            properties = {"@type": "Organization", "name": str(author["name"])}
        else:
            given, family = author.get("given-names", ""), author.get("family-names", "")
            properties = {"@type": "Person", "name": f"{given} {family}".strip()}
        identifier = str(author.get("orcid") or f"#author-{number}")
        authors.append(_entity(crate, identifier, properties))
    root["author"] = authors[0] if len(authors) == 1 else authors
    root["conformsTo"] = [
        _entity(crate, uri, {"@type": ["CreativeWork", "Profile"], "name": name, "version": v})
        for uri, name, v in CRATE_PROFILES
    ]

    packages = dict(software["packages"])
    engine_version = str(packages.get("snakemake") or "")

    # the files: sizes, hashes and formats
    entities = {}
    for item in files:
        name = item["name"]
        properties = {
            "name": PurePosixPath(name).name,
            "contentSize": str(os.path.getsize(item["path"])),
            "sha256": file_sha256(item["path"]),
        }
        path = PurePosixPath(name)
        media = MEDIA_TYPES.get(path.suffix) or (
            "text/plain" if path.name in PLAIN_TEXT_NAMES else None
        )
        if media:
            properties["encodingFormat"] = media
        if name == main_workflow:
            workflow = crate.add_workflow(
                item["path"], name, main=True, lang="snakemake", lang_version=engine_version
            )
            for key, value in properties.items():
                workflow[key] = value
            entities[name] = workflow
        else:
            entities[name] = crate.add_file(item["path"], name, properties=properties)
    workflow = entities[main_workflow]
    language = workflow["programmingLanguage"]
    language["version"] = engine_version
    if not language.get("url"):
        language["url"] = "https://snakemake.readthedocs.io"
    # a HowTo: its steps are the rules (the Provenance Run Crate profile); and bioschemas'
    # own IRI for a workflow beside the context's term, which RO-Crate 1.3 maps to
    # bioschemas.org/terms/: the Workflow RO-Crate profile (and its validator) look for the
    # IRI that RO-Crate 1.1's context gave it
    workflow.type.extend(["HowTo", BIOSCHEMAS_WORKFLOW])
    workflow["name"] = f"{root['name']} (Snakefile)"
    workflow["version"] = str(commit or citation["version"])
    workflow["author"] = root["author"]

    # software the rules run, and the engine that ran them
    requirements = [
        _entity(
            crate,
            f"https://pypi.org/project/{name}/{version}/",
            {
                "@type": "SoftwareApplication",
                "name": name,
                "version": str(version),
                "url": f"https://pypi.org/project/{name}/",
            },
        )
        for name, version in sorted(packages.items())
        if version
    ]
    requirements.append(
        _entity(
            crate,
            "https://www.python.org/downloads/release/python-"
            + software["python"].replace(".", "")
            + "/",
            {
                "@type": "SoftwareApplication",
                "name": "Python",
                "version": str(software["python"]),
                "url": "https://www.python.org",
            },
        )
    )
    workflow["softwareRequirements"] = requirements
    engine = _entity(
        crate,
        "#snakemake",
        {
            "@type": "SoftwareApplication",
            "name": "Snakemake",
            "version": engine_version,
            "url": "https://snakemake.readthedocs.io",
        },
    )

    # the workflow's parameters: the configuration, and the raw data folder
    inputs, values = [], []
    for key, value in parameters.items():
        value_entity = _entity(
            crate,
            f"#value/{key}",
            {"@type": "PropertyValue", "name": key, "value": _value_text(value)},
        )
        parameter = crate.add_formal_parameter(
            key,
            _value_type(value),
            identifier=f"#parameter/{key}",
            description=f"Configuration key {key} (config/config.yaml)",
            properties={"workExample": _ref(value_entity)},
        )
        value_entity["exampleOfWork"] = parameter
        inputs.append(parameter)
        values.append(value_entity)
    raw_files = [entities[f["name"]] for f in files if f["kind"] == "input"]
    raw_data = crate.add_dataset(
        None,
        f"{raw_folder.rstrip('/')}/",
        properties={
            "name": "raw data",
            "description": "The raw files the run read (data/README.md gives their contract)",
            "hasPart": [_ref(e) for e in raw_files],
        },
    )
    raw_parameter = crate.add_formal_parameter(
        "raw_data",
        "Dataset",
        identifier="#parameter/raw_data",
        description="The raw-data folder (config key raw_data)",
        properties={"workExample": _ref(raw_data)},
    )
    raw_data["exampleOfWork"] = raw_parameter
    inputs.insert(0, raw_parameter)
    workflow["input"] = inputs

    # the workflow's outputs: one parameter per file it writes (logs are not outputs)
    outputs, results = [], []
    for item in files:
        if item["kind"] != "output":
            continue
        entity = entities[item["name"]]
        parameter = crate.add_formal_parameter(
            item["name"],
            "File",
            identifier=f"#output/{item['name']}",
            properties={"workExample": _ref(entity)},
        )
        entity["exampleOfWork"] = parameter
        outputs.append(parameter)
        results.append(entity)
    workflow["output"] = outputs

    # each rule: a tool, a step, a run of it, and the control of that run
    tools, steps, controls = [], [], []
    for position, (rule, about) in enumerate(rules.items()):
        tool = _entity(
            crate,
            f"#rule/{rule}",
            {
                "@type": "SoftwareApplication",
                "name": rule,
                "description": about["description"],
                "url": about["source"],
                "version": str(commit or citation["version"]),
            },
        )
        step = _entity(
            crate,
            f"#step/{rule}",
            {"@type": "HowToStep", "name": rule, "position": str(position), "workExample": tool},
        )
        written = [entities[f["name"]] for f in files if f.get("rule") == rule]
        run = crate.add_action(
            tool,
            identifier=f"#run/{rule}",
            result=written,
            properties={
                "@type": "CreateAction",
                "name": f"Run of rule {rule}",
                "description": f"The files rule {rule} wrote in this run",
            },
        )
        controls.append(
            _entity(
                crate,
                f"#control/{rule}",
                {
                    "@type": "ControlAction",
                    "name": f"Step {rule}",
                    "instrument": step,
                    "object": run,
                },
            )
        )
        tools.append(tool)
        steps.append(step)
    workflow["hasPart"] = tools
    workflow["step"] = steps

    run = crate.add_action(
        workflow,
        identifier="#run",
        object=[raw_data, *values],
        result=results,
        properties={
            "@type": "CreateAction",
            "name": f"Run of {root['name']} {root['version']} at commit {commit or 'unknown'}",
            "description": "The raw data and the configuration in; every output of the build out",
        },
    )
    # the actions from the root, as the Process Run Crate profile recommends
    root["mentions"] = [run, *(crate.get(f"#run/{rule}") for rule in rules)]
    _entity(
        crate,
        "#orchestration",
        {
            "@type": "OrganizeAction",
            "name": "Snakemake's orchestration of the run",
            "instrument": engine,
            "result": run,
            "object": controls,
        },
    )
    return crate


def build_crate(files, rules, record, citation, root, logs=True):
    """The crate of a build whose results, raw-input copies and source copy are under
    ``root``.

    Parameters
    ----------
    files : list of dict
        ``name`` (in the crate, relative to ``root``), ``kind`` (``output``, ``log``,
        ``input`` or ``source``) and ``rule`` (for outputs and logs), as the workflow
        lists them; every file is read at ``root / name``.
    rules : dict
        As for :func:`run_crate`.
    record : dict
        The provenance record (``config``, ``python``, ``packages``, ``git``).
    citation : dict
        ``CITATION.cff`` as :func:`lineload.publishing.citation.read_citation` reads it.
    root : str or os.PathLike
        The crate's root (the results folder).
    logs : bool, optional
        List the rules' logs (those that exist); the bundle leaves them out.

    Returns
    -------
    tuple of (rocrate.rocrate.ROCrate, dict)
        The crate, and its files: name in the crate -> path.
    """
    present = [
        {**item, "path": str(Path(root, item["name"]))}
        for item in files
        if item["kind"] != "log" or (logs and Path(root, item["name"]).exists())
    ]
    crate = run_crate(
        present,
        rules,
        flat_parameters(record["config"]),
        citation,
        {"python": record["python"], "packages": record["packages"]},
        record["git"]["commit"],
        main_workflow=MAIN_WORKFLOW,
        raw_folder=RAW_FOLDER,
    )
    return crate, {item["name"]: item["path"] for item in present}


def crate_json(crate):
    """The crate's ``ro-crate-metadata.json`` text, as ``rocrate`` generates it."""
    return json.dumps(crate.metadata.generate(), indent=2, ensure_ascii=False) + "\n"


def write_crate(crate, folder):
    """Write ``ro-crate-metadata.json`` into ``folder`` (the crate's root)."""
    write_text(crate_json(crate), Path(folder) / METADATA)
