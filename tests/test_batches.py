"""How per-subject work is split into jobs (lineload.runtime.batches)."""

import pytest

from lineload.runtime import batches


def ids(n):
    return [f"S{i}" for i in range(1, n + 1)]


@pytest.mark.parametrize("photographs", [False, True])
@pytest.mark.parametrize(
    "n", [1, 2, 3, 4, 5, 7, 8, 31, 32, 33, 64, 65, 249, 250, 251, 1000, 1999, 2001, 10007]
)
def test_auto_gives_each_job_enough_subjects_and_each_rule_few_jobs(n, photographs):
    split = batches.batches(ids(n), photographs=photographs)
    sizes = [len(members) for members in split.values()]
    fewest = batches.MIN_PHOTOGRAPHED_PER_JOB if photographs else batches.MIN_SUBJECTS_PER_JOB
    # every subject once, in the sheet's order
    assert [s for members in split.values() for s in members] == ids(n)
    assert len(split) <= batches.MAX_JOBS_PER_RULE
    # every batch but the last has the same size, at least the minimum (or all subjects)
    assert len(set(sizes[:-1])) <= 1 and sizes[-1] <= sizes[0]
    assert sizes[0] >= min(n, fewest)
    # and no larger than it needs to be: one subject fewer per job would exceed a bound
    if sizes[0] > fewest:
        assert -(-n // (sizes[0] - 1)) > batches.MAX_JOBS_PER_RULE


def test_photographs_spread_over_jobs_sooner_than_digitised_profiles():
    # 40 subjects: one job for digitised profiles (start-up would outweigh the work of
    # more), eight for photographs (each subject's digitising outweighs a start-up)
    assert len(batches.batches(ids(40))) == 1
    assert len(batches.batches(ids(40), photographs=True)) == 8
    # 1,000 digitised subjects: a few jobs of many subjects, never one per core asked for
    assert [len(m) for m in batches.batches(ids(1000)).values()] == [250] * 4


def test_a_number_is_used_as_given_and_names_say_first_and_how_many_follow():
    split = batches.batches(ids(7), 3)
    assert split == {"S1+2": ["S1", "S2", "S3"], "S4+2": ["S4", "S5", "S6"], "S7": ["S7"]}
    assert list(batches.batches(ids(3), 1)) == ["S1", "S2", "S3"]


def test_the_split_does_not_depend_on_the_machine(monkeypatch):
    # the split reads nothing but its arguments: the same on any number of cores
    before = batches.batches(ids(50))
    monkeypatch.setattr("os.cpu_count", lambda: 64)
    assert batches.batches(ids(50)) == before
