"""The raw-data check as a job: what start-up reads, what a refusal leaves, when it reruns."""

import json
import re
import subprocess
import sys
import textwrap

import pytest

from conftest import REPO, run_snakemake, write_small_dataset

CHECK_LOG = ("logs", "check_raw_data.log")


def files_under(folder):
    return {
        p.relative_to(folder).as_posix(): p.read_bytes() for p in folder.rglob("*") if p.is_file()
    }


def set_cell(path, line, column, value):
    lines = path.read_text(encoding="utf-8").splitlines()
    header = lines[0].split(",")
    cells = lines[line - 1].split(",")
    cells[header.index(column)] = value
    lines[line - 1] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


@pytest.mark.e2e
def test_a_refused_folder_leaves_only_the_checks_log(tmp_path, snakemake_available):
    raw = write_small_dataset(tmp_path / "raw")
    set_cell(raw / "profiles" / "MK.csv", 3, "side", "middle")
    set_cell(raw / "profiles" / "HU.csv", 4, "deflection_image_mm", "abc")
    results = tmp_path / "out"
    process = run_snakemake(raw=str(raw), results=str(results))
    assert process.returncode != 0, process.stdout + process.stderr
    errors = [line for line in process.stderr.splitlines() if line.startswith("Error: ")]
    # both files' problems in one run, one line each, naming file, line and column
    assert errors == [
        f"Error: {raw}/profiles/MK.csv, line 3, column 'side': " + errors[0].split("'side': ")[1],
        f"Error: {raw}/profiles/HU.csv, line 4, column 'deflection_image_mm': "
        + errors[1].split("'deflection_image_mm': ")[1],
    ], process.stderr
    assert "Traceback" not in process.stdout + process.stderr
    # nothing under the results but the check's log, which says the same
    assert sorted(files_under(results)) == ["/".join(CHECK_LOG)]
    assert [e.removeprefix("Error: ") for e in errors] == [
        line.removeprefix("Error: ")
        for line in results.joinpath(*CHECK_LOG).read_text().splitlines()
        if line.startswith("Error: ")
    ]
    assert [p for p in results.rglob("*") if p.is_dir()] == [results / "logs"]


def folders_under(folder):
    return sorted(p.relative_to(folder).as_posix() for p in folder.rglob("*") if p.is_dir())


@pytest.mark.e2e
def test_a_refused_run_removes_no_folder_it_did_not_make(tmp_path, snakemake_available):
    """``results=.`` in a clone: the lab's empty folders (.git's among them) survive a refusal."""
    raw = write_small_dataset(tmp_path / "raw")
    set_cell(raw / "profiles" / "MK.csv", 3, "side", "middle")
    work = tmp_path / "clone"
    own = [".git/refs/tags", ".git/objects/info", ".git/branches", "notes/empty", "logs/old"]
    for folder in own:
        (work / folder).mkdir(parents=True)
    (work / "notes" / "todo.txt").write_text("mine\n")
    before = folders_under(work)
    process = run_snakemake("check", raw=str(raw), results=".", cwd=work)
    assert process.returncode != 0, process.stdout + process.stderr
    assert "Traceback" not in process.stdout + process.stderr
    after = folders_under(work)
    # every folder that was there is there; of the run's own only the log's folder is left
    # (and Snakemake's own working folder)
    assert set(before) <= set(after), sorted(set(before) - set(after))
    made = {f for f in set(after) - set(before) if not f.startswith(".snakemake")}
    assert made == set(), made
    assert (work / "logs" / "check_raw_data.log").is_file()
    assert (work / "notes" / "todo.txt").read_text() == "mine\n"


def test_cleanup_removes_only_the_folders_the_run_made(tmp_path):
    from lineload.runtime import startup

    root = tmp_path / "results"
    (root / "logs" / "old").mkdir(parents=True)  # the user's, empty
    (root / "figures").mkdir()  # the user's, empty, and a folder the run would use
    patterns = [
        str(root / "figures" / "figure{n}.pdf"),
        str(root / "fits" / "{batch}.csv"),
        str(root / "specs" / "fit_models" / "{key}.json"),
        str(root / "logs" / "check_raw_data.log"),
        str(tmp_path / "elsewhere" / "x.csv"),  # outside the results: never planned
    ]
    planned = startup.planned_folders(patterns, root)
    assert planned == {
        root,
        root / "figures",
        root / "fits",
        root / "specs",
        root / "specs" / "fit_models",
        root / "logs",
    }
    new = startup.absent_folders(planned)
    assert new == sorted([root / "fits", root / "specs", root / "specs" / "fit_models"])
    # the run makes its folders and a spec, then is refused
    for folder in new:
        folder.mkdir(parents=True, exist_ok=True)
    spec = root / "specs" / "fit_models" / "M1.json"
    spec.write_text("{}")
    (root / "fits" / "kept.csv").write_text("a\n")  # something in a folder the run made
    startup.remove_written([spec], new)
    assert folders_under(root) == ["figures", "fits", "logs", "logs/old"]
    # and a root that did not exist before goes too, once empty
    fresh = tmp_path / "fresh"
    new = startup.absent_folders(startup.planned_folders([str(fresh / "a" / "b.csv")], fresh))
    (fresh / "a").mkdir(parents=True)
    startup.remove_written([], new)
    assert not fresh.exists()


@pytest.mark.e2e
def test_the_check_target_prints_twenty_problems_and_logs_every_one(tmp_path, snakemake_available):
    subjects = {f"S{k:02d}": ("monkey", [1.0], 5.0) for k in range(25)}
    raw = write_small_dataset(tmp_path / "raw", subjects=subjects)
    for subject in subjects:  # one broken cell in each of 25 files: 25 problems
        set_cell(raw / "profiles" / f"{subject}.csv", 3, "side", "middle")
    results = tmp_path / "out"
    process = run_snakemake("check", raw=str(raw), results=str(results))
    assert process.returncode != 0
    printed = [line for line in process.stderr.splitlines() if line.startswith("Error: ")]
    log = results.joinpath(*CHECK_LOG)
    assert len(printed) == 20
    assert f"... and 5 more errors not shown here, every one in {log}" in process.stderr
    logged = [line for line in log.read_text().splitlines() if line.startswith("Error: ")]
    assert len(logged) == 25 and logged[:20] == printed
    assert "Traceback" not in process.stdout + process.stderr


@pytest.mark.e2e
def test_a_file_put_back_with_its_old_time_is_named_with_what_to_do(tmp_path, snakemake_available):
    import os

    raw = write_small_dataset(tmp_path / "raw")
    results = tmp_path / "out"
    first = run_snakemake("fits", raw=str(raw), results=str(results))
    assert first.returncode == 0, first.stderr[-3000:]
    profile = raw / "profiles" / "MK.csv"
    old = profile.stat()
    # another version of the file, put back with a time before the build (as cp -p or a
    # backup would): Snakemake alone sees nothing to do
    text = profile.read_text().replace("\n2,left,", "\n2,left,", 1) + "2,left,199.000,0.000\n"
    profile.write_text(text)
    os.utime(profile, ns=(old.st_atime_ns, old.st_mtime_ns - 10**9))
    again = run_snakemake("fits", raw=str(raw), results=str(results))
    assert again.returncode == 0, again.stderr[-3000:]
    warnings = [line for line in again.stderr.splitlines() if line.startswith("Warning: ")]
    assert warnings == [
        f"Warning: {profile} differs from the file checked last time but is not newer than "
        "the results, so Snakemake would keep them (was it put back with its old time, by "
        f"cp -p, rsync or a backup?); run `touch {profile}` and build again to redo them"
    ], again.stderr
    assert "Nothing to be done" in again.stdout + again.stderr
    # doing what it says redoes the file's results, and the warning goes
    profile.touch()
    redone = run_snakemake("fits", raw=str(raw), results=str(results))
    assert redone.returncode == 0, redone.stderr[-3000:]
    assert "prepare_profiles" in redone.stderr and "Warning: " not in redone.stderr
    # an untouched folder gives no warning: the rule is not always on
    quiet = run_snakemake("fits", raw=str(raw), results=str(results))
    assert "Warning: " not in quiet.stderr


#: One subject per job, so that what an edit of one subject's file reruns can be seen
ONE_PER_JOB = ["subjects_per_job=1"]


@pytest.mark.e2e
def test_the_check_reruns_only_when_a_raw_file_changes(tmp_path, snakemake_available):
    """Snakemake's timestamps remember a passed check; an edit reruns it and only the
    jobs of the edited file; a later corruption is still caught, leaving the rest alone."""
    raw = write_small_dataset(tmp_path / "raw")
    results = tmp_path / "out"
    first = run_snakemake("fits", raw=str(raw), results=str(results), config=ONE_PER_JOB)
    assert first.returncode == 0, first.stderr[-3000:]
    summary = json.loads((results / "data" / "raw_check.json").read_text())
    assert summary == {
        "raw_data": "raw",
        "depths_mm": {"MK": [1.0, 2.0], "HU": [1.0]},
        "outlines_mm": {},
        "warnings": [],
    }

    again = run_snakemake(
        "fits", "--dry-run", raw=str(raw), results=str(results), config=ONE_PER_JOB
    )
    assert "Nothing to be done" in again.stdout + again.stderr, again.stdout

    profile = raw / "profiles" / "MK.csv"
    lines = profile.read_text().splitlines()
    cells = lines[5].split(",")
    cells[3] = f"{float(cells[3]) + 0.001:.3f}"  # a valid edit of one reading
    lines[5] = ",".join(cells)
    profile.write_text("\n".join(lines) + "\n")
    edited = run_snakemake("fits", raw=str(raw), results=str(results), config=ONE_PER_JOB)
    assert edited.returncode == 0, edited.stderr[-3000:]
    ran = re.findall(r"^local(?:rule|checkpoint) (\w+):", edited.stderr, re.M)
    # the noise is measured from every trial, so every batch's fits take the new noise
    expected = [
        "check_profiles",  # MK's batch only: HU's files are as they were
        "check_raw_data",
        "prepare_profiles",
        "noise",
        "fit_models",
        "fit_models",
    ]
    assert ran == [*expected, "fits_table", "fits"], ran
    # the batches are one subject each here: of the two, only MK's profiles were redone
    prepared = re.findall(
        r"^localrule prepare_profiles:\n(?:\s+\S.*\n)*?\s+wildcards: batch=(\S+)$",
        edited.stderr,
        re.M,
    )
    assert prepared == ["MK"], edited.stderr[-3000:]

    (raw / "profiles" / "notes.txt").write_text("a stray file\n")  # the check warns, alone
    stray = run_snakemake("fits", raw=str(raw), results=str(results), config=ONE_PER_JOB)
    ran = re.findall(r"^local(?:rule|checkpoint) (\w+):", stray.stderr, re.M)
    assert ran == ["check_raw_data"], stray.stderr[-3000:]
    assert "Warning: " in stray.stderr and "notes.txt" in stray.stderr

    set_cell(profile, 3, "depth_mm", "deep")
    before = files_under(results)
    broken = run_snakemake("fits", raw=str(raw), results=str(results), config=ONE_PER_JOB)
    assert broken.returncode != 0
    errors = [line for line in broken.stderr.splitlines() if line.startswith("Error: ")]
    assert len(errors) == 1 and f"{raw}/profiles/MK.csv, line 3" in errors[0], broken.stderr
    after = files_under(results)
    # the failed check's output is removed (the next run checks again); nothing else changed
    # but the record of MK's batch check, which holds the problem it found
    changed = {k for k in before.keys() | after.keys() if before.get(k) != after.get(k)}
    batch_check = {
        "data/checked/MK.json",
        "logs/check_profiles/MK.log",
        "benchmarks/check_profiles/MK.tsv",
    }
    assert changed == {"data/raw_check.json", "/".join(CHECK_LOG)} | batch_check, changed
    assert (
        "line 3" in json.loads((results / "data" / "checked" / "MK.json").read_text())["errors"][0]
    )


# Run Snakemake in this process with an audit hook: which raw files does start-up open?
START_UP = textwrap.dedent(
    """
    import json, sys
    opened = []
    def hook(event, args):
        if event == "open" and isinstance(args[0], str) and {raw!r} in args[0]:
            opened.append(args[0])
    sys.addaudithook(hook)
    from snakemake.cli import main
    sys.argv = ["snakemake", "-s", {snakefile!r}, "-n", "--cores", "1", "fits",
                "--config", "raw_data={raw}", "results={results}"]
    try:
        main()
    except SystemExit as end:
        status = end.code
    print(json.dumps({{"status": status, "opened": sorted(set(opened))}}))
    """
)


@pytest.mark.e2e
def test_start_up_reads_the_sheet_and_no_profile(tmp_path, snakemake_available):
    raw = write_small_dataset(tmp_path / "raw")
    (raw / "outlines").mkdir()
    (raw / "outlines" / "MK.csv").write_text("depth_mm,state,x_image_mm,z_image_mm\n")
    code = START_UP.format(
        raw=str(raw),
        snakefile=str(REPO / "workflow" / "Snakefile"),
        results=str(tmp_path / "out"),
    )
    process = subprocess.run(
        [sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, timeout=300
    )
    report = json.loads(process.stdout.strip().splitlines()[-1])
    assert report["status"] == 0, process.stderr[-3000:]
    assert report["opened"] == [f"{raw}/subjects.csv"]


def test_what_start_up_imports_leaves_pandas_out(tmp_path):
    """Every top-level lineload import of the Snakefile and rules, and the start-up reading,
    in a fresh interpreter: pandas stays unimported (Snakemake's plugins may import it)."""
    sources = [
        REPO / "workflow" / "Snakefile",
        *sorted((REPO / "workflow" / "rules").glob("*.smk")),
    ]
    imports = sorted(
        {
            line.strip()
            for path in sources
            for line in path.read_text().splitlines()
            # at the top level: an import inside a function runs only when it is called
            if re.match(r"(from lineload\b|import lineload\b)", line)
        }
    )
    assert any("startup" in line for line in imports), imports
    raw = write_small_dataset(tmp_path / "raw")
    code = "\n".join(
        [
            *imports,
            "import sys",
            "from lineload.io import load_schema",
            f"startup.list_raw_files({str(raw)!r})",
            f"startup.read_subject_sheet({str(raw)!r}, load_schema('subjects'))",
            "print('pandas' in sys.modules)",
        ]
    )
    process = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert process.stdout.strip() == "False", process.stderr


def test_a_link_loop_or_a_notice_not_in_utf8_stops_start_up_with_one_sentence(tmp_path, capsys):
    from lineload.runtime import startup

    raw = write_small_dataset(tmp_path / "raw")
    (raw / "outlines").mkdir()
    (raw / "outlines" / "a.csv").symlink_to("b.csv")
    (raw / "outlines" / "b.csv").symlink_to("a.csv")
    with pytest.raises(SystemExit) as stopped:
        startup.list_raw_files(str(raw))
    assert stopped.value.code == 1
    said = capsys.readouterr().err
    assert said.count("\n") == 1 and said.startswith(f"Error: {raw}/outlines/a.csv: cannot be")
    # without the loop the folder lists
    for name in ("a.csv", "b.csv"):
        (raw / "outlines" / name).unlink()
    assert startup.list_raw_files(str(raw))["outlines"] == {}
    # a notice written in Latin-1: one sentence naming the file and the byte
    notice = raw / "NOTICE.txt"
    notice.write_bytes("Données synthétiques\n".encode("latin-1"))
    with pytest.raises(SystemExit):
        startup.notice_text(None, str(notice))
    said = capsys.readouterr().err
    assert said.count("\n") == 1 and "byte 5 is not UTF-8" in said and "NOTICE.txt" in said
    notice.write_text("Données synthétiques\n", encoding="utf-8")
    assert startup.notice_text(None, str(notice)) == "Données synthétiques"


def test_the_report_command_is_read_as_snakemake_reads_it(tmp_path, capsys):
    from lineload.runtime import startup

    assert startup.report_argument(["snakemake", "--report", "out/r.html"]) == "out/r.html"
    assert startup.report_argument(["snakemake", "--report=r.html", "-c1"]) == "r.html"
    assert startup.report_argument(["snakemake", "--report", "--cores", "2"]) == "report.html"
    assert startup.report_argument(["snakemake", "--cores", "2"]) is None
    # the line is said only for a report this run wrote, not for one left from before
    import time

    (tmp_path / "old.html").write_text("<html></html>")
    startup.say_where_the_report_is(str(tmp_path / "old.html"), time.time_ns() + 10**9)
    assert capsys.readouterr().err == ""
    startup.say_where_the_report_is(str(tmp_path / "missing.html"))
    assert capsys.readouterr().err == ""
    (tmp_path / "r.html").write_text("<html></html>")
    startup.say_where_the_report_is(str(tmp_path / "r.html"))
    assert (
        capsys.readouterr().err == f"The report: {tmp_path / 'r.html'} (open it in a web browser)\n"
    )


# ------------------------------------------------------ config values that are numbers


@pytest.mark.parametrize(
    ("setting", "key"),
    [
        ("fit_window_mm=nan", "fit_window_mm"),
        ("input_checks__deflection_factor=nan", "input_checks/deflection_factor"),
        ("claims__significance=nan", "claims/significance"),
        ("digitise__reach_mm=nan", "digitise/reach_mm"),
    ],
)
def test_nan_and_infinities_in_the_config_are_refused_with_one_line(tmp_path, setting, key):
    process = run_snakemake(
        "-n", raw=write_small_dataset(tmp_path / "raw"), results=tmp_path / "out", config=[setting]
    )
    output = process.stdout + process.stderr
    errors = [line for line in output.splitlines() if line.startswith("Error: ")]
    assert process.returncode != 0 and "Traceback" not in output, output
    assert len(errors) == 1 and errors[0].startswith(f"Error: config, key '{key}': nan is not a"), (
        output
    )
    assert not (tmp_path / "out").exists()


def test_config_problem_sees_what_the_schema_cannot():
    from lineload.runtime.startup import config_problem

    assert config_problem({"raw_data": "data/raw", "results": "results", "a": [1.0, 2]}) is None
    assert "key 'a/1'" in config_problem({"a": [1.0, float("nan")]})
    # an infinity where the schema sets no upper bound
    assert "key 'b/c': inf is not a finite" in config_problem({"b": {"c": float("inf")}})
    long_name = config_problem({"raw_data": "data/" + "x" * 256, "results": "results"})
    assert long_name.startswith("config, key 'raw_data': the name") and "256 bytes" in long_name
    deep = config_problem({"results": "/".join(["y" * 200] * 25)})
    assert deep.startswith("config, key 'results': the path is") and "\n" not in deep


def test_an_over_long_results_path_is_one_line(tmp_path):
    process = run_snakemake(
        "-n", raw=write_small_dataset(tmp_path / "raw"), results=tmp_path / ("z" * 256)
    )
    output = process.stdout + process.stderr
    assert process.returncode != 0 and "Traceback" not in output, output
    assert "Error: config, key 'results': the name" in output, output


# ------------------------------------------------------ nothing read from outside


@pytest.mark.parametrize("entry", ["subjects.csv", "profiles/MK.csv"])
def test_start_up_refuses_a_link_out_of_the_dataset_before_reading_it(tmp_path, entry):
    raw = write_small_dataset(tmp_path / "raw")
    (raw / entry).unlink()
    (raw / entry).symlink_to("/etc/passwd")
    process = run_snakemake("-n", raw=raw, results=tmp_path / "out")
    output = process.stdout + process.stderr
    errors = [line for line in output.splitlines() if line.startswith("Error: ")]
    assert process.returncode != 0 and "Traceback" not in output, output
    assert errors == [
        f"Error: {raw}/{entry} leads to /etc/passwd, outside the raw-data folder {raw}; "
        "expected every input inside it (copy the file in, or link the whole folder), "
        "nothing is read from elsewhere"
    ], output
    assert not (tmp_path / "out").exists()


# ------------------------------------------------------ one build per results folder

HOLD = """
import sys, time
from lineload.runtime import buildlock
fd, held = buildlock.acquire(sys.argv[1], buildlock.this_build(["check"]))
print("held" if fd is not None else held, flush=True)
time.sleep(120)
"""


def holder(results, cwd):
    """A process holding the results folder's lock (as a running build's main process does)."""
    import os

    process = subprocess.Popen(
        [sys.executable, "-c", HOLD, str(results)],
        cwd=cwd,
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(REPO / "workflow")},
    )
    assert process.stdout.readline().strip() == "held"
    return process


def test_the_lock_is_taken_once_and_taken_over_from_a_killed_holder(tmp_path):
    import signal

    from lineload.runtime.buildlock import LOCK_NAME, acquire, release

    results = tmp_path / "results"
    other = holder(results, tmp_path)
    try:
        fd, held = acquire(str(results))
        assert fd is None and f"process {other.pid} on " in held and str(tmp_path) in held
        assert "\n" not in held
    finally:
        other.send_signal(signal.SIGKILL)
        other.wait()
    assert (results / LOCK_NAME).is_file()  # left behind by the killed build...
    fd, held = acquire(str(results))  # ...and taken over: its process is gone
    assert fd is not None and held is None
    assert json.loads((results / LOCK_NAME).read_text())["pid"] != other.pid
    again, held = acquire(str(results))  # the same process's second try is refused too
    assert again is None and held
    release(fd, str(results))
    assert not (results / LOCK_NAME).exists()


def test_a_second_build_on_one_results_folder_is_refused_naming_the_first(tmp_path):
    """Snakemake's lock is the working folder's: a build from another working folder
    onto the same results folder is refused by this one, and the first's files stay."""
    raw = write_small_dataset(tmp_path / "raw")
    results = tmp_path / "results"
    (results / "mine").mkdir(parents=True)  # the lab's own, which must stay
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    first = holder(results, elsewhere)
    try:
        process = run_snakemake("check", raw=raw, results=results)
    finally:
        first.kill()
        first.wait()
    output = process.stdout + process.stderr
    errors = [line for line in output.splitlines() if line.startswith("Error: ")]
    assert process.returncode != 0 and "Traceback" not in output, output
    assert len(errors) == 1 and f"process {first.pid} on" in errors[0], output
    assert f"in {elsewhere})" in errors[0], output
    assert (results / "mine").is_dir()
    # the first build gone, the next one runs, and lets go of the lock when done
    dry = run_snakemake("-n", raw=raw, results=tmp_path / "dry")
    assert dry.returncode == 0, dry.stderr  # a dry run takes no lock
    assert not (tmp_path / "dry" / ".lineload-build.lock").exists()
    done = run_snakemake("check", raw=raw, results=results)
    assert done.returncode == 0, done.stderr[-2000:]
    assert not (results / ".lineload-build.lock").exists()


def test_where_to_look_names_first_what_the_target_built(tmp_path):
    from lineload.runtime import startup

    zipped, article = tmp_path / "b.zip", tmp_path / "a.pdf"
    article.write_text("%PDF")
    targets = {"bundle": [("the bundle", str(zipped))]}
    built = startup.named_targets(frozenset({"bundle", "results/fits.csv"}), targets)
    assert built == [("the bundle", str(zipped))]
    assert startup.named_targets(frozenset(), targets) == []
    documents = [("the article", str(article)), ("the claims table", str(tmp_path / "no.md"))]
    # a bundle not written (the run failed before it) is not named
    lines = startup.where_to_look(documents, "r.html", built).splitlines()
    assert lines[2] == f"  the article: {article}" and len(lines) == 4
    zipped.write_bytes(b"PK")
    lines = startup.where_to_look(documents, "r.html", built).splitlines()
    assert lines[2] == f"  this run built the bundle: {zipped}"
    assert lines[-1] == "  the HTML report: snakemake --report r.html"
