"""How per-subject work is split into jobs (lineload.runtime.batches)."""

import pytest

from lineload.runtime import batches


def ids(n):
    return [f"S{i}" for i in range(1, n + 1)]


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 7, 8, 31, 32, 33, 64, 65, 1000, 10007])
def test_auto_gives_each_job_enough_subjects_and_each_rule_few_jobs(n):
    split = batches.batches(ids(n))
    sizes = [len(members) for members in split.values()]
    # every subject once, in the sheet's order
    assert [s for members in split.values() for s in members] == ids(n)
    assert len(split) <= batches.MAX_JOBS_PER_RULE
    # every batch but the last has the same size, at least the minimum (or all subjects)
    assert len(set(sizes[:-1])) <= 1 and sizes[-1] <= sizes[0]
    assert sizes[0] >= min(n, batches.MIN_SUBJECTS_PER_JOB)
    # and no larger than it needs to be: one subject fewer per job would exceed a bound
    if sizes[0] > batches.MIN_SUBJECTS_PER_JOB:
        assert -(-n // (sizes[0] - 1)) > batches.MAX_JOBS_PER_RULE


def test_a_number_is_used_as_given_and_names_say_first_and_how_many_follow():
    split = batches.batches(ids(7), 3)
    assert split == {"S1+2": ["S1", "S2", "S3"], "S4+2": ["S4", "S5", "S6"], "S7": ["S7"]}
    assert list(batches.batches(ids(3), 1)) == ["S1", "S2", "S3"]


def test_the_split_does_not_depend_on_the_machine(monkeypatch):
    # the split reads nothing but its arguments: the same on any number of cores
    before = batches.batches(ids(50))
    monkeypatch.setattr("os.cpu_count", lambda: 64)
    assert batches.batches(ids(50)) == before
