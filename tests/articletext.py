"""Reading an article back against the tables it was written from, and its template
against the facts: the checks of test_article_text.py, kept apart so that each can be
shown to fail on a planted contradiction.

:func:`contradictions` lists every sentence of a built article's text that its own
``claims.csv``, ``fits.csv`` or raw data contradict; :func:`typed_by_hand` lists every
number or model comparison written into the Typst template instead of read from
``facts.json``.
"""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd
from pypdf import PdfReader

VERDICT_WORDS = "holds|does not hold|cannot be checked on these data|identity"


def pdf_text(path):
    """The PDF's text as pypdf reads it, white space folded, hyphenation kept."""
    return " ".join(" ".join(page.extract_text() for page in PdfReader(path).pages).split())


#: A name from the code or the tables (``large_depth_mm``, ``left_source``,
#: ``lineload.claims.chord_curvature``): words joined by underscores, two of them
#: lower-case words of two letters or more, so that a symbol with a subscript written
#: out (``f_w``, ``SSE_waterbed``) is not one.
CODE_NAME = re.compile(r"[A-Za-z0-9]+(?:[._][A-Za-z0-9]+)+")


def is_code_name(word):
    """Whether a word matched by :data:`CODE_NAME` names something in the code."""
    parts = re.split(r"[._]", word)
    if word.startswith("lineload."):  # a module of the package: lineload.mechanics
        return True
    return "_" in word and sum(len(p) >= 2 and p.islower() for p in parts) >= 2


def names_in_prose(path):
    """Code names (:func:`is_code_name`) that a PDF sets in its body's serif font rather
    than as code, each once, in order."""
    runs = []

    def visit(text, cm, tm, font, size):
        serif = font is not None and "Libertinus" in str(font.get("/BaseFont", ""))
        runs.append(text if serif else " ")

    for page in PdfReader(path).pages:
        page.extract_text(visitor_text=visit)
    found = [w for w in CODE_NAME.findall("".join(runs)) if is_code_name(w)]
    return list(dict.fromkeys(found))


def dataset_contents(raw):
    """What a raw folder holds: its species, subjects, forces and photographs."""
    raw = Path(raw)
    subjects = pd.read_csv(raw / "subjects.csv", dtype={"subject": str})
    return {
        "species": set(subjects["species"]),
        "n_subjects": len(subjects),
        "forces": (raw / "forces.csv").is_file(),
        "photographs": (raw / "images").is_dir(),
    }


def _design(fits):
    return fits.groupby(["species", "depth_mm"]).size().to_dict()


def contradictions(text, claims, fits, contents, calibration_design=None):
    """Sentences of ``text`` that the tables or the data contradict.

    Parameters
    ----------
    text : str
        The article's text (:func:`pdf_text`).
    claims, fits : pandas.DataFrame
        The build's ``claims.csv`` and ``fits.csv``.
    contents : dict
        :func:`dataset_contents` of its raw folder.
    calibration_design : dict, optional
        ``{(species, depth_mm): trials}`` the committed calibration was computed for.

    Returns
    -------
    list of str
        One line per contradiction found; empty when none is.
    """
    found = []
    n_trials = len(fits)
    # each claim's verdict where the text gives it: "<claim>: <verdict>." and C3's quote
    for claim, verdict in zip(claims["claim"], claims["verdict"], strict=True):
        for said in re.findall(rf"\b{claim}: ({VERDICT_WORDS})\.", text):
            if said != verdict:
                found.append(f"{claim} said to be '{said}', claims.csv: '{verdict}'")
    for said in re.findall(r"its verdict is “([^”]+)”", text):
        c3 = claims.loc[claims["claim"] == "C3", "verdict"]
        if len(c3) and said != c3.iloc[0]:
            found.append(f"C3 said to be '{said}', claims.csv: '{c3.iloc[0]}'")
    # counts of trials: no part larger than the whole, no "all" of a wrong count
    for k, n in re.findall(r"\b(\d+) of (\d+) (?:trials|of the trials)\b", text):
        if int(k) > int(n) or int(n) > n_trials:
            found.append(f"'{k} of {n} trials' in a dataset of {n_trials} trials")
    for n in re.findall(r"\b[Aa]ll (\d+) trials\b", text):
        if int(n) > n_trials:
            found.append(f"'all {n} trials' in a dataset of {n_trials} trials")
    # grammar of counts and of small values
    for wrong in re.findall(
        r"\b(?:all [012]|1 degrees|1 trials|1 subjects)\b|(?<![\d.])0\.0 %", text
    ):
        found.append(f"'{wrong}': a count or a value the text cannot write so")
    # which model leaves the smaller residuals, by the fit table
    ratio = fits["boussinesq_rmse_mm"] / fits["waterbed_rmse_mm"]
    better, usable = int((ratio > 1).sum()), int(ratio.notna().sum())
    if better < usable and re.search(
        r"waterbed (?:follows the readings better|leaves smaller residuals than the half-space "
        r"form in (?:every|all|both|the one))",
        text,
    ):
        found.append(f"the waterbed said better throughout; it is in {better} of {usable}")
    if better > 0 and re.search(
        r"half-space form leaves smaller residuals than the waterbed", text
    ):
        found.append(f"the half-space form said better throughout; the waterbed is in {better}")
    # data the dataset lacks
    if "human" not in contents["species"]:
        for said in ("Humans: the same", "the human subjects", "No human subjects"):
            if said in text:
                found.append(f"'{said}' in a dataset without humans")
    if "monkey" not in contents["species"]:
        for said in ("Monkeys: averaged profiles", "No monkey subjects"):
            if said in text:
                found.append(f"'{said}' in a dataset without monkeys")
    if not contents["forces"] and "fitted membrane with tension at rest" in text:
        found.append("a fitted membrane described in a dataset without forces")
    if contents["photographs"] and "were divided by the magnification" in text:
        found.append("readings said divided by a magnification; they were read from photographs")
    # the committed calibration is another design's unless the fit table has its design
    if calibration_design is not None and _design(fits) != calibration_design:
        for said in ("Wrong, % (95 % CI)", "replicated trials per model", "Calibration: "):
            if said in text:
                found.append(f"'{said}': another design's calibration shown as this one's")
    return found


# ------------------------------------------------------------------ the template

#: What the template may spell in digits of its own, each for a stated reason.
ALLOWED_NUMBERS = [
    r"//[^\n]*",  # comments
    r"^#(?:set|show|let) [^\n]*",  # layout and definitions
    r"#if [^\[]*\[|else if [^\[]*\[",  # conditions in code, never printed
    r"\.(?:at|slice)\([^)]*\)|calc\.\w+\([^,]*,",  # indexing into the facts
    r"\$[^$]*\$",  # equations: their constants are the model's, not the data's
    r"\(\s*(?:auto|\d+(?:\.\d+)?fr|\d+(?:\.\d+)?%)(?:\s*,\s*(?:auto|\d+(?:\.\d+)?fr|"
    r"\d+(?:\.\d+)?%))*\s*\)",  # column widths
    r"\b(?:size|inset|radius|width|margin|above|below|gap|leading|spacing|stroke|x|y|"
    r"ppi|columns)\s*:\s*[^,)\]\n]*",  # layout arguments
    r"\bC\d+\b",  # claim ids
    r"\b(?:the paper's |the workflow's )?Figures? \d+\b",  # the paper's figure numbers
    r"\beqs?\.? \d+(?: and \d+)?\b",  # the paper's equation numbers
    r"\b95 %|± 1\.96",  # the nominal interval level, a convention of the whole workflow
    r"22\(4\):343--349",  # the paper's citation
    r"SHA-256",  # the name of a hash
    r'"[^"\n]*"',  # strings in code: labels, file names, keys
    r"\bD1\b",  # the numbering pattern of the digitised figures
    r"continued\(\d+\)",  # the column count of a table's "continued" row
    r"counter\(heading\)\.update\(0\)",  # the appendices' letters start again
    r"\b\d+(?:\.\d+)?(?:pt|em|cm|mm)\b(?=[,)\s])",  # lengths in code
]

#: A comparison of the models or of a count typed as a fact, without a fact beside it.
COMPARATIVE = re.compile(
    r"(?:waterbed|half-space|Boussinesq)[^.#]{0,80}\b(?:follows[^.#]*better|is better|"
    r"fits better|better than|worse than|smaller than|larger than|exceeds?|beats?|wins?)\b",
    re.IGNORECASE,
)


def typed_by_hand(template):
    """Numbers and model comparisons the template states on its own.

    Parameters
    ----------
    template : str
        The Typst source of the article.

    Returns
    -------
    list of str
        Each offending line (numbered) with what was found; empty when none is.
    """
    found = []
    for number, line in enumerate(template.splitlines(), start=1):
        stripped = line
        for pattern in ALLOWED_NUMBERS:
            stripped = re.sub(pattern, " ", stripped, flags=re.MULTILINE)
        for digits in re.findall(r"(?<![\w#.])\d+(?:\.\d+)?(?![\w])", stripped):
            found.append(f"line {number}: the number {digits} typed by hand")
        for sentence in COMPARATIVE.findall(stripped):
            found.append(f"line {number}: a comparison typed by hand: {sentence[:80]}")
    return found
