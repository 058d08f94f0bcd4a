"""The commit a checkout is at, read from its .git files, against git's own answer."""

import subprocess

import pytest

from lineload.runtime.gitcommit import head_commit


def git(folder, *args):
    return subprocess.run(
        ["git", "-C", str(folder), *args], capture_output=True, text=True, check=True
    ).stdout.strip()


@pytest.fixture
def repository(tmp_path):
    folder = tmp_path / "repo"
    folder.mkdir()
    git(folder, "init", "-q", "-b", "main")
    for n in range(2):
        (folder / "a.txt").write_text(f"{n}\n")
        git(folder, "add", "a.txt")
        git(folder, "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qm", f"c{n}")
    return folder


def test_the_commit_is_gits_however_the_ref_is_kept(repository, tmp_path):
    head = git(repository, "rev-parse", "HEAD")
    assert head_commit(repository) == head  # a loose ref
    assert head_commit(repository / "sub" / "folder") == head  # looked for upwards
    git(repository, "pack-refs", "--all")
    assert not (repository / ".git" / "refs" / "heads" / "main").exists()
    assert head_commit(repository) == head  # a packed ref
    first = git(repository, "rev-parse", "HEAD~1")
    git(repository, "checkout", "-q", "--detach", first)
    assert head_commit(repository) == first  # a detached HEAD
    git(repository, "checkout", "-q", "main")
    git(repository, "worktree", "add", "-q", str(tmp_path / "wt"), "HEAD~1")
    assert head_commit(tmp_path / "wt") == first  # a worktree, through its commondir
    assert head_commit(repository) == head


def test_outside_a_checkout_there_is_none(tmp_path):
    assert head_commit(tmp_path) is None
