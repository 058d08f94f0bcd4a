"""Figures 1 and 2 show what was measured: subjects and depths chosen from the data."""

import pytest

from conftest import job_params, run_snakemake, write_small_dataset
from lineload.figures.choices import ChoiceError, example_choice, nearest_depth, outline_choice

PAPER = {
    "M1": ("monkey", [0.5, 1.0, 1.5, 2.0]),
    "M2": ("monkey", [0.5, 1.0, 1.5, 2.0]),
    "H1": ("human", [0.5, 1.0, 1.5, 2.0]),
    "H3": ("human", [1.0, 2.0]),
}
LAB = {f"S-0{i}": ("monkey" if i <= 2 else "human", [0.75, 1.25, 1.75]) for i in range(1, 6)}


def split(spec):
    return {s: species for s, (species, _) in spec.items()}, {s: d for s, (_, d) in spec.items()}


def test_the_paper_like_dataset_gives_the_papers_figure():
    choice = example_choice(*split(PAPER))
    assert choice.subjects == ["M1", "H1"] and choice.depth_mm == 1.0
    assert choice.note == ""  # nothing to say: it is the paper's depth
    assert "nearest the paper's 1 mm" in choice.log and "M1, H1" in choice.log


def test_a_lab_without_1_mm_gets_the_nearest_measured_depth_and_is_told():
    choice = example_choice(*split(LAB))
    # 0.75 and 1.25 are equally near 1 mm: the deeper one
    assert choice.depth_mm == 1.25
    assert choice.subjects == ["S-01", "S-03"]
    assert "1.25 mm" in choice.note and "paper's 1 mm" in choice.note
    assert "measured: 0.75, 1.25, 1.75" in choice.log


def test_a_depth_that_every_species_has_wins_over_a_nearer_one():
    spec = {"A": ("monkey", [1.0, 2.0]), "B": ("human", [0.5, 2.0]), "C": ("human", [0.5])}
    choice = example_choice(*split(spec))
    assert choice.depth_mm == 2.0 and choice.subjects == ["A", "B"]
    # with one species only, the nearest depth
    choice = example_choice(*split({"A": ("human", [0.6, 1.5, 3.0])}))
    assert choice.depth_mm == 0.6 and choice.subjects == ["A"]


def test_humans_first_in_the_sheet_still_give_monkey_then_human_panels():
    spec = {"H": ("human", [1.0]), "M": ("monkey", [1.0])}
    assert example_choice(*split(spec)).subjects == ["M", "H"]


def test_named_subjects_get_their_nearest_shared_depth():
    choice = example_choice(*split(LAB), subjects=["S-05", "S-02"])
    assert choice.subjects == ["S-05", "S-02"] and choice.depth_mm == 1.25
    assert "as set in the config" in choice.log


def test_a_set_depth_is_kept_and_said_when_it_is_not_the_papers():
    choice = example_choice(*split(PAPER), depth_mm=2.0)
    assert choice.subjects == ["M1", "H1"] and choice.depth_mm == 2.0
    assert "as set in the config" in choice.note
    empty = example_choice(*split(PAPER), depth_mm=3.0)
    assert empty.subjects == [] and empty.depth_mm == 3.0


@pytest.mark.parametrize(
    ("subjects", "depth", "words"),
    [
        (["M9"], None, ("'M9'", "not in subjects.csv")),
        (["H3"], 0.5, ("'H3'", "no profile at 0.5 mm", "1, 2")),
        (["M1", "H3"], 1.5, ("'H3'", "1.5 mm")),
    ],
)
def test_a_choice_the_data_cannot_satisfy_names_the_key(subjects, depth, words):
    with pytest.raises(ChoiceError) as caught:
        example_choice(*split(PAPER), subjects=subjects, depth_mm=depth)
    message = str(caught.value)
    assert message.startswith("config, key 'figures/example_subjects': ")
    for word in words:
        assert word in message


def test_named_subjects_without_a_shared_depth_are_refused():
    spec = {"A": ("monkey", [1.0]), "B": ("human", [2.0])}
    with pytest.raises(ChoiceError, match="share no depth"):
        example_choice(*split(spec), subjects=["A", "B"])


def test_nearest_depth_breaks_ties_towards_the_deeper():
    assert nearest_depth([0.75, 1.25]) == 1.25
    assert nearest_depth([0.9, 1.2]) == 0.9
    assert nearest_depth([3.0], 1.0) == 3.0
    assert nearest_depth([]) is None


def test_outline_choice_defaults_and_refusals():
    species = {"M1": "monkey", "M2": "monkey", "H1": "human"}
    outlines = {"M2": [2.0, 1.0], "H1": [1.0, 2.0]}
    choice = outline_choice(species, outlines)
    assert choice.subjects == ["M2", "H1"] and choice.depth_mm == 1.0
    assert outline_choice(species, outlines, depth_mm=2.0).depth_mm == 2.0
    assert outline_choice(species, {}).subjects == []
    with pytest.raises(ChoiceError, match=r"outline_subjects.*'M1'"):
        outline_choice(species, outlines, subjects=["M1"])
    with pytest.raises(ChoiceError, match=r"outline_depth_mm.*got 1\.5"):
        outline_choice(species, outlines, depth_mm=1.5)


@pytest.mark.e2e
def test_a_labs_figure2_follows_its_depths_and_says_so(tmp_path, snakemake_available):
    """Five subjects at 0.75, 1.25 and 1.75 mm: Figure 2 at 1.25 mm, logged and noted."""
    raw = write_small_dataset(
        tmp_path / "raw",
        subjects={
            s: (species, depths, 5.0 if species == "monkey" else 9.0)
            for s, (species, depths) in LAB.items()
        },
    )
    out = tmp_path / "out"
    process = run_snakemake("figure_fits", raw=raw, results=out)
    assert process.returncode == 0, process.stderr[-3000:]
    log = (out / "logs" / "figure_fits.log").read_text()
    assert "figure2: S-01, S-03 (the first monkey and the first human of subjects.csv" in log
    assert "at 1.25 mm: the measured depth nearest the paper's 1 mm" in log
    assert "note: Shown at 1.25 mm" in log
    # the job was given the config's values (unset); it made the choice from the data
    spec = job_params(out / "logs" / "figure_fits.log")
    assert spec["settings"]["example_depth_mm"] is None
    assert spec["settings"]["example_subjects"] == []
