"""The one list of the claims: what each says, where the paper says it, and how it is judged.

One :class:`Claim` per row of the claims table, in table order.  Everything else
that names claims reads it: the table (:func:`lineload.claims.table.compute_claims`
calls each entry's function), the article (which claims use which setting), the
generator's list of the verdicts it builds in (``data/built_in_verdicts.json``,
:func:`built_in_verdicts`) and the calibration (which claims have a boundary world;
its worlds' functions stay in :mod:`lineload.simulation.calibration`, and
``tests/test_claims_registry.py`` checks that the two agree).

The module imports only the standard library, :mod:`lineload.paper`'s numbers and
the verdict words: an entry names its function by module and name, as
:mod:`lineload.figures.registry` does, and :func:`claim_function` imports it when
asked, so the functions (whose rows take their text from here) and the registry do
not import each other.  Every function takes
``(fits, averaged, settings)`` and, if the entry needs ``forces``, the keyword
``forces``; it returns one row of :data:`lineload.claims.verdicts.CLAIM_COLUMNS`.

Adding a claim is one entry here, one function in a family module and one test
(``docs/adding-a-claim.md``).
"""

from __future__ import annotations

import importlib
import inspect
from dataclasses import dataclass

from lineload import paper
from lineload.claims.verdicts import (
    FAILS,
    HOLDS,
    IDENTITY,
    KINDS,
    LATER_WORK,
    METHOD_IDENTITY,
    METHOD_PROPERTY,
    MODEL_CHECK,
    PAPER_CLAIM,
    PAPER_SUGGESTION,
    UNTESTABLE,
    VERDICTS,
)

__all__ = [
    "CLAIMS",
    "CLAIM_IDS",
    "CLAIM_KINDS",
    "CLAIM_TEXT",
    "FAMILIES",
    "FORCE_CLAIMS",
    "HOW_BUILT_IN",
    "NEEDS",
    "SETTINGS",
    "TRUTH_NOT_COMPUTED",
    "BuiltIn",
    "Claim",
    "built_in_verdicts",
    "check_claims",
    "claim_function",
    "claim_named",
    "claims_needing",
    "claims_using",
]

#: The modules of :mod:`lineload.claims` that hold claim functions, one family each.
FAMILIES = {
    "shape": "the measured profile's own shape: extent, symmetry, circularity",
    "fit_quality": "how well the waterbed describes the readings",
    "halfwidth": "the fitted half-width L: its range, the shift neglected, the zero at L/3",
    "forces": "the forces on the wedge against the membrane's shapes",
    "bending": "the bending skin of the paper's closing suggestion",
    "elastic": "the layered elastic finger of later work against the homogeneous one",
}

#: What a claim's function may need besides its settings.
NEEDS = {
    "fits": "the fit table, one row per subject and depth (tables/fits.csv)",
    "averaged": "the averaged profiles with their sides (data/averaged/*.csv)",
    "noise": "the noise table, through ClaimSettings (tables/noise.csv)",
    "forces": "the optional force readings (forces.csv), passed as the keyword forces",
    "bending": "the bending skin's fits joined to the fit table (tables/bending.csv)",
    "elastic": "the elastic finger's fits joined to the fit table (tables/elastic_fits.csv)",
    "coordinates": "the fits in measured coordinates (shifted parabola, exact arc) beside the "
    "paper's: the claim is judged both ways",
}

#: The settings a rule may read (config keys under ``claims``, and ``mechanics:
#: force_sd_N``; :class:`lineload.claims.settings.ClaimSettings`).
SETTINGS = (
    "large_depth_mm",
    "significance",
    "extent_fraction",
    "symmetry_margin",
    "shift_margin",
    "circularity_margin",
    "slope_min_df",
    "elastic_margin",
    "force_sd_N",
)

#: How the generator builds a verdict into the shipped reconstruction.  ``tuned``: its
#: parameters were chosen so that the claim comes out this way (a test of the workflow,
#: not evidence); ``by construction``: not aimed at, but fixed by a choice of the
#: generator's (the near-field weight rising with depth; forces from a membrane under
#: tension at rest), so no more evidence than a tuned verdict; ``follows``: not aimed
#: at, a consequence of the paper's approximations or of the digitising errors;
#: ``identity``: true of any data.
HOW_BUILT_IN = ("tuned", "by construction", "follows", "identity")
#: The truth of a built-in verdict that the noise-free world was not analysed for: the
#: calibration's reconstructions make no elastic or bending fits (C12, C13).
TRUTH_NOT_COMPUTED = "not computed"


@dataclass(frozen=True)
class BuiltIn:
    """What the generator puts into the shipped reconstruction for one claim.

    Attributes
    ----------
    verdict : str
        The verdict the claims table should reach on the shipped data.
    how : str
        One of :data:`HOW_BUILT_IN`.
    why : str
        How it comes about, in one clause.
    truth : str or None
        The verdict of the noise-free world (what the rules conclude from the true
        profiles on the same reading grids,
        :func:`lineload.simulation.calibration.reconstruction_claims` without
        errors); None: the same as ``verdict``; :data:`TRUTH_NOT_COMPUTED` where that
        analysis makes no fits the claim needs.
    """

    verdict: str
    how: str
    why: str
    truth: str | None = None


@dataclass(frozen=True)
class Claim:
    """One claim of the claims table.

    Attributes
    ----------
    id : str
        ``C1``, ``C2``, ...: the claim's name everywhere (table, article, tests).
    kind : str
        One of :data:`lineload.claims.verdicts.KINDS`; only ``paper claim`` counts
        as evidence about fingers.
    statement : str
        The claim in our words (never the paper's sentence).
    location : str
        Where the paper (or its source) makes it.
    paper_value : str
        What the paper gives for it.
    rule : str
        How the verdict is reached, in one sentence (the table's ``rule`` column
        states it in full, with its thresholds).
    family : str
        The module of :mod:`lineload.claims` that holds the function, a key of
        :data:`FAMILIES`.
    function : str
        Name of the claim's function in that module.
    needs : tuple of str
        Keys of :data:`NEEDS`: what the function reads.
    settings : tuple of str
        Entries of :data:`SETTINGS` the function's rule reads itself.
    boundary_world : str or None
        The calibration's world either side of the claim's boundary (a key of
        :data:`lineload.simulation.calibration.BOUNDARY_WORLDS`); None without one.
    built_in : BuiltIn or None
        What the generator builds into the shipped data; None: not in its list.
    """

    id: str
    kind: str
    statement: str
    location: str
    paper_value: str
    rule: str
    family: str
    function: str
    needs: tuple = ("fits", "averaged", "noise")
    settings: tuple = ("significance",)
    boundary_world: str | None = None
    built_in: BuiltIn | None = None

    @property
    def import_path(self):
        """Dotted name of the module that holds the function."""
        return f"lineload.claims.{self.family}"


#: Every claim, in table order.  Claims without a boundary world: C4 (no shape of the
#: generator's family bulges above the resting surface), C7 (an identity), C11 (the
#: generator's forces come from a membrane under tension at rest, which the force part
#: of the rule rejects as stress-free whatever the shapes), C12 and C13 (the calibration's
#: reconstructions make no elastic or bending fits; C12's error rates come from its own
#: study, docs/calibration/elastic_layer_margin.md).
CLAIMS = (
    Claim(
        id="C1",
        kind=PAPER_CLAIM,
        statement="At the same indentation depth the skin is deformed over a wider region "
        "in humans than in monkeys.",
        location="Results, first paragraph; Fig. 7 caption",
        paper_value="humans 6-12 mm vs monkeys 3-7 mm from the wedge",
        rule="At every depth measured in both species, every human trial's deformed extent "
        "exceeds every monkey trial's beyond their standard errors.",
        family="shape",
        function="claim_c1",
        settings=("extent_fraction", "significance"),
        boundary_world="humans-narrower",
        built_in=BuiltIn(HOLDS, "tuned", "the species' edges were drawn from the paper's ranges"),
    ),
    Claim(
        id="C2",
        kind=PAPER_CLAIM,
        statement="The deflection profile is close to symmetric about the wedge (left side "
        "vs right side).",
        location="Results, first paragraph (last sentence); Fig. 1 caption",
        paper_value="generally symmetrical (no number given)",
        rule="In every trial the true RMS difference between the sides, the noise removed, "
        "lies below a margin of the depth (an equivalence test).",
        family="shape",
        function="claim_c2",
        settings=("significance", "symmetry_margin"),
        boundary_world="sides-unequal",
        built_in=BuiltIn(HOLDS, "tuned", "the sides' edges differ by a few percent of the depth"),
    ),
    Claim(
        id="C3",
        kind=PAPER_CLAIM,
        statement="Close to the load (within about 3 mm) the waterbed profile fits the data "
        "better than the modified Boussinesq profile.",
        location="Abstract; Fig. 2 caption; Results, 'Comparison of theoretical and "
        "experimental results', end of paragraph; Discussion, second paragraph",
        paper_value="waterbed much better than Boussinesq up to about 3 mm (no number given)",
        rule="In every trial with both fits the waterbed leaves a smaller sum of squares than "
        "the Boussinesq form on the same points, beyond the noise.",
        family="fit_quality",
        function="claim_c3",
        boundary_world="boussinesq-nearer",
        built_in=BuiltIn(
            UNTESTABLE,
            "follows",
            "the true profile's shape was tuned until the waterbed fits better; M4 at 2 mm, "
            "read from 0.1 mm on, is the exception: there the logarithm's steep start fits "
            "better, by less than the digitising errors let the rule resolve",
            truth=FAILS,
        ),
    ),
    Claim(
        id="C4",
        kind=PAPER_CLAIM,
        statement="Beyond about 3 mm from the load the waterbed is wrong: it predicts an "
        "upward bulge (W < 0) between L/3 and L which the measured skin does not show.",
        location="Discussion, second paragraph",
        paper_value="bulge W < 0 on L/3 < X < L predicted, not observed",
        rule="No trial's readings rise above the resting surface where the fitted waterbed "
        "predicts its bulge, and every trial whose noise could show the bulge refutes it.",
        family="fit_quality",
        function="claim_c4",
        built_in=BuiltIn(HOLDS, "tuned", "the true profile never goes below the resting surface"),
    ),
    Claim(
        id="C5",
        kind=PAPER_CLAIM,
        statement="The fitted membrane half-width L lies between 10 and 15 mm.",
        location="Results, 'Comparison of theoretical and experimental results' (Figs 6 and 7)",
        paper_value="10-15 mm",
        rule="Every trial's interval on the L of the paper's procedure lies inside the "
        "paper's range.",
        family="halfwidth",
        function="claim_c5",
        needs=("fits", "coordinates"),
        boundary_world="h3-wider",
        built_in=BuiltIn(
            UNTESTABLE,
            "follows",
            "L was tuned into 10-15 mm (10.2-14.4 mm); at 0.5 mm the intervals of the trials "
            "near 10 mm reach past that end",
            truth=HOLDS,
        ),
    ),
    Claim(
        id="C6",
        # a property of the paper's method at the data's W0/L, not evidence about fingers:
        # both fits are one-parameter curves of the same membrane, so the gap between the
        # paper's L and the exact arc's is fixed by W0/L (the arc and the parabola differ by
        # about 1 % of W0 at W0/L = 0.1 and 4 % at 0.2) up to a standard error of hundredths
        # of a percent; the fingers enter only through L, which C5 tests
        kind=METHOD_PROPERTY,
        statement="The horizontal shift U of the membrane is negligible: at X = L/3, where it "
        "is largest (8W₀²/(9L)), it is a small fraction of X.",
        location="Results, 'Comparison of theoretical and experimental results'",
        paper_value="< 8 % of X",
        rule="In every trial the L of the paper's procedure lies within a margin of the exact "
        "arc's, interval included (an equivalence test).",
        family="halfwidth",
        function="claim_c6",
        needs=("fits", "averaged", "noise", "coordinates"),
        settings=("shift_margin", "significance"),
        boundary_world="deeper-for-width",
        built_in=BuiltIn(
            HOLDS,
            "follows",
            "the paper's procedure and the exact arc differ by W0/L effects: a property of the "
            "paper's method at the reconstruction's W0/L, reported apart from the paper's claims",
        ),
    ),
    Claim(
        id="C7",
        # an identity of eq. 19
        kind=METHOD_IDENTITY,
        statement="Each fitted waterbed curve crosses the zero line at X = L/3, where U is "
        "largest.",
        location="Results, 'Comparison of theoretical and experimental results' (from eqs 19-20)",
        paper_value="X = L/3",
        rule="Every fitted waterbed curve's numerical zero equals L/3 to floating-point "
        "accuracy, which checks the code, not the data.",
        family="halfwidth",
        function="claim_c7",
        needs=("fits",),
        settings=(),
        built_in=BuiltIn(IDENTITY, "identity", "eq. 19 crosses zero at L/3 for any L"),
    ),
    Claim(
        id="C8",
        kind=PAPER_CLAIM,
        statement="The waterbed describes the data less well the deeper the indentation.",
        location="Discussion, third (last) paragraph",
        paper_value="accuracy falls as depth increases (no number given)",
        rule="Across subjects, the slope against depth of the waterbed's misfit beyond the "
        "noise, relative to W₀², is above zero (one-sided t-test).",
        family="fit_quality",
        function="claim_c8",
        settings=("significance", "slope_min_df"),
        boundary_world="one-shape-at-every-depth",
        built_in=BuiltIn(
            HOLDS,
            "by construction",
            "the generator's near-field weight rises with depth, so the profile's shape "
            "departs further from the waterbed's the deeper the indentation",
        ),
    ),
    Claim(
        id="C9",
        kind=PAPER_CLAIM,
        statement="At the larger depths the measured deflection within about 3 mm of the load "
        "is smaller than the waterbed predicts, i.e. the fingertip is stiffer than the model.",
        location="Discussion, third (last) paragraph (last sentence); Figs 6 and 7",
        paper_value="data within 3 mm deflected less than the model curve at the higher "
        "depths, in all cases shown",
        rule="In every trial at the larger depths the readings' mean residual over the fit "
        "window lies below each of the three fitted waterbed curves beyond the noise.",
        family="fit_quality",
        function="claim_c9",
        needs=("fits", "averaged", "noise", "coordinates"),
        settings=("large_depth_mm", "significance"),
        boundary_world="readings-on-the-curve",
        built_in=BuiltIn(HOLDS, "tuned", "the near-field term puts the readings under the curve"),
    ),
    Claim(
        id="C10",
        kind=PAPER_CLAIM,
        statement="Skin that does not touch the indenter takes a circular (constant-curvature) "
        "shape.",
        location="Discussion, third (last) paragraph (eqs 4-5); Fig. 1 caption",
        paper_value="approximately circular on either side of the load (no number given)",
        rule="Pooled over the trials, the curvatures of the inner and outer halves of the fit "
        "window agree within a margin of the whole window's (an equivalence test).",
        family="shape",
        function="claim_c10",
        settings=("circularity_margin", "significance"),
        boundary_world="nearly-circles",
        built_in=BuiltIn(
            FAILS,
            "by construction",
            "the generator's near-field term bends the skin next to the wedge more than "
            "further out",
        ),
    ),
    Claim(
        id="C11",
        # a claim the paper never makes: whether the fitted shapes and the forces go with
        # the stress-free membrane, a check of the model's consistency
        kind=MODEL_CHECK,
        statement="(Implicit) The forces measured on the wedge fit the proposed membrane, "
        "which carries no tension at rest (N = Eε): through F = 2N sin θ₀, the fitted shapes "
        "fix how fast the force must grow with depth.",
        location="Methods, 'Experimental procedure' (force range); eqs 3 and 7",
        paper_value=f"{paper.FORCE_RANGE_N[0]:g}-{paper.FORCE_RANGE_N[1]:g} N over depths of "
        f"{min(paper.DEPTHS_MM):g}-{max(paper.DEPTHS_MM):g} mm: at most "
        f"{paper.FORCE_RANGE_N[1] / paper.FORCE_RANGE_N[0]:.2f} times more force at one depth "
        "than at another",
        rule="The force ratio a stress-free membrane needs between a subject's smallest and "
        "largest depth, from the fitted exact arcs, stays within what the paper's force range "
        "allows, and measured forces do not reject that membrane.",
        family="forces",
        function="claim_c11",
        needs=("fits", "forces"),
        settings=("force_sd_N", "significance"),
        built_in=BuiltIn(
            FAILS,
            "by construction",
            "the generator's forces come from a membrane under tension at rest, and L changes "
            "little with depth, so a stress-free membrane needs far more force at depth; a "
            "model-consistency check reported apart from the paper's claims",
        ),
    ),
    Claim(
        id="C12",
        # not the paper's: the finding of its lab's later finite-element work, tested on
        # these data with the elastic finger's fits (docs/elastic-finger.md)
        kind=LATER_WORK,
        statement="(Later work) A layered elastic fingertip, a stiffer outer layer over soft "
        "pulp, describes the surface profiles better than a homogeneous one, beyond the noise.",
        location="later work, not the 1989 paper: Dandekar, Raju and Srinivasan 2003, J. "
        "Biomech. Eng. 125:682-691 (three-dimensional finite-element fingertips)",
        paper_value="a multi-layered model was needed to match the line-load surface "
        "deflections, a homogeneous one was not (no number compared here)",
        rule="Per species, more than half the trials have a layered fit whose improvement over "
        "the homogeneous one is beyond the noise (a likelihood ratio, two degrees of freedom) "
        "and beyond a geometry margin measured on homogeneous fingers whose sections the "
        "library does not hold.",
        family="elastic",
        function="claim_c12",
        needs=("fits", "averaged", "noise", "elastic"),
        settings=("significance", "elastic_margin"),
        built_in=BuiltIn(
            HOLDS,
            "by construction",
            "the generator has no elastic finger, layered or not: its profiles are a "
            "membrane's with a near-field term, and the layered finger's two extra parameters "
            "follow that shape better than the homogeneous finger, so the verdict describes "
            "the generator's shapes, not a layer",
            truth=TRUTH_NOT_COMPUTED,
        ),
    ),
    Claim(
        id="C13",
        kind=PAPER_SUGGESTION,
        statement="(The paper's closing suggestion) The skin's bending stiffness accounts for "
        "the waterbed's worsening with depth: a skin that bends describes the profiles better "
        "than the membrane by more, relative to the deformation, the deeper the wedge.",
        location="Discussion, last paragraph",
        paper_value="a suggestion, no number: for more accuracy the skin's thickness and "
        "bending rigidity may have to be modelled",
        rule="Across subjects, the slope against depth of the bending skin's advantage over "
        "the waterbed, relative to W₀², is above zero (one-sided t-test).",
        family="bending",
        function="claim_c13",
        needs=("fits", "averaged", "noise", "bending"),
        settings=("significance", "slope_min_df"),
        built_in=BuiltIn(
            UNTESTABLE,
            "by construction",
            "the generator has no bending skin: its near-field term is not a bending "
            "skin's shape, and the bending fit's advantage over the waterbed does not grow "
            "with depth beyond the noise, so the verdict describes the generator's shapes, "
            "not a skin",
            truth=TRUTH_NOT_COMPUTED,
        ),
    ),
)


def check_claims(claims, functions=True):
    """Refuse a registry that is not complete and consistent.

    Parameters
    ----------
    claims : sequence of Claim
        A registry (:data:`CLAIMS`, or one a test builds).
    functions : bool, optional
        Also import every entry's function and check that it exists and takes the
        keyword ``forces`` exactly when the entry needs forces.

    Raises
    ------
    ValueError
        Naming every entry at fault and what is wrong with it.
    """
    problems = []
    seen, worlds = set(), set()
    for claim in claims:
        where = f"claim {claim.id or '(no id)'}"
        if not claim.id or claim.id in seen:
            problems.append(f"{where}: id empty or given twice")
        seen.add(claim.id)
        if claim.kind not in KINDS:
            problems.append(f"{where}: kind {claim.kind!r} is not one of {KINDS}")
        for field in ("statement", "location", "paper_value", "rule", "function"):
            if not str(getattr(claim, field)).strip():
                problems.append(f"{where}: no {field}")
        if claim.family not in FAMILIES:
            problems.append(f"{where}: family {claim.family!r} is not one of {tuple(FAMILIES)}")
        unknown = [n for n in claim.needs if n not in NEEDS]
        if unknown:
            problems.append(f"{where}: needs {unknown}, not among {tuple(NEEDS)}")
        unknown = [s for s in claim.settings if s not in SETTINGS]
        if unknown:
            problems.append(f"{where}: settings {unknown} are not among {SETTINGS}")
        if claim.boundary_world is not None:
            if claim.boundary_world in worlds:
                problems.append(f"{where}: boundary world {claim.boundary_world!r} given twice")
            worlds.add(claim.boundary_world)
        built = claim.built_in
        if built is not None and (
            built.verdict not in VERDICTS
            or (built.truth or built.verdict) not in (*VERDICTS, TRUTH_NOT_COMPUTED)
            or built.how not in HOW_BUILT_IN
            or not built.why.strip()
        ):
            problems.append(f"{where}: built-in verdict {built} is not a verdict, way and reason")
    if functions and not problems:
        for claim in claims:
            try:
                function = claim_function(claim)
            except (ImportError, AttributeError) as error:
                problems.append(f"claim {claim.id}: no function {claim.function!r} ({error})")
                continue
            takes_forces = "forces" in inspect.signature(function).parameters
            if takes_forces != ("forces" in claim.needs):
                problems.append(
                    f"claim {claim.id}: {claim.function} "
                    f"{'takes' if takes_forces else 'does not take'} the keyword forces, but "
                    f"the entry {'does not need' if takes_forces else 'needs'} forces"
                )
    if problems:
        raise ValueError("the claims registry is inconsistent: " + "; ".join(problems))


def claim_named(claim_id, claims=CLAIMS):
    """The entry of a claim id (KeyError naming the known ids otherwise)."""
    for claim in claims:
        if claim.id == claim_id:
            return claim
    raise KeyError(f"no claim {claim_id!r}; the registry has {', '.join(c.id for c in claims)}")


def claim_function(claim):
    """The function of an entry (imports its family module).

    The families are named in an import statement too: the workflow finds the modules
    a job runs from import statements (:mod:`lineload.runtime.codedeps`), and without
    it a change to a claim's rule would not rebuild the claims table.
    """
    from lineload.claims import (  # noqa: F401
        bending,
        elastic,
        fit_quality,
        forces,
        halfwidth,
        shape,
    )

    return getattr(importlib.import_module(claim.import_path), claim.function)


def claims_using(setting, claims=CLAIMS):
    """Ids of the claims whose rule reads a setting (an entry of :data:`SETTINGS`), in
    table order."""
    return [claim.id for claim in claims if setting in claim.settings]


def claims_needing(need, claims=CLAIMS):
    """Ids of the claims that need an input (a key of :data:`NEEDS`), in table order."""
    return [claim.id for claim in claims if need in claim.needs]


def built_in_verdicts(claims=CLAIMS):
    """The verdicts the generator builds into the shipped reconstruction, as a list of
    dicts (``data/built_in_verdicts.json``).

    Returns
    -------
    list of dict
        ``claim``, ``verdict`` (on the shipped data), ``truth`` (in the noise-free
        world), ``how`` (one of :data:`HOW_BUILT_IN`) and ``why``, in table order.
    """
    return [
        {
            "claim": claim.id,
            "verdict": claim.built_in.verdict,
            "truth": claim.built_in.truth or claim.built_in.verdict,
            "how": claim.built_in.how,
            "why": claim.built_in.why,
        }
        for claim in claims
        if claim.built_in is not None
    ]


check_claims(CLAIMS, functions=False)

#: Claim ids in table order.
CLAIM_IDS = [claim.id for claim in CLAIMS]
#: Claim id -> (statement, where in the paper, the paper's value).
CLAIM_TEXT = {claim.id: (claim.statement, claim.location, claim.paper_value) for claim in CLAIMS}
#: Claim id -> its kind (:data:`lineload.claims.verdicts.KINDS`).
CLAIM_KINDS = {claim.id: claim.kind for claim in CLAIMS}
#: Claims that also take the force readings (keyword ``forces``).
FORCE_CLAIMS = tuple(claim.id for claim in CLAIMS if "forces" in claim.needs)
