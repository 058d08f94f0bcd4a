"""Measure the workflow's speed targets on this machine and write a Markdown table.

    python benchmarks/run.py                  # everything, 3 repeats (about 15 minutes)
    python benchmarks/run.py --repeats 3 --output benchmarks/results.md
    python benchmarks/run.py --against /path/to/old/checkout     # side by side, alternating

Measured (medians of the repeats, wall-clock seconds, `--cores 2`):

- the import baseline: `python -c "import numpy, pandas, scipy.optimize, matplotlib.pyplot"`;
- a clean build of the default target on the shipped data;
- a rerun with nothing changed;
- a rerun after editing one subject's profile (and which jobs ran);
- the `fits` target on scale datasets of 1,000 and 10,000 subjects x 4 depths made by the
  generator in a temporary folder, with the peak memory of the whole process tree, and a
  rerun of it with nothing changed;
- the elastic finger's fits by interpolation in the kept library (both fingers), milliseconds
  per trial on profiles made from the library with noise (issue 36: at most 5 ms);
- with `--elastic-library`: the `elastic_library` target (the finite-element solves of the
  library's grid), with its factorisations per second from the jobs' logs;
- with `--calibration 1 2 ...`: the boundary calibration (one job per world and block of
  datasets) at each core count, and its speed-up over the first;
- with `--photographs PAIRS`, instead of all the above: rule digitise on that many
  photograph pairs (the example's, hard-linked over and over) at each of
  `--photograph-cores` (default 1 and 2), wall-clock and the jobs' CPU seconds;
- what no workflow can go below: Snakemake's own start-up (`snakemake --version`), a rerun of
  a one-rule workflow with one param (which makes Snakemake import pandas to compare it),
  plain and with its Snakefile freezing the start-up's objects (`gc.freeze()`) as this
  workflow's does, and the time the jobs of the last clean build took (from their
  benchmark files).

With ``--against CHECKOUT`` (another checkout of the project, e.g. an older commit in a
temporary ``git worktree``) only the clean build (with the import baseline before each),
the rerun with nothing changed and the ``fits`` target at each scale are measured,
for both checkouts in turn (this one, that one, this one, ...),
with the one-rule floors (plain, and freezing the start-up's objects as this workflow's
Snakefile does) before each rerun, so that a change in the machine's load falls
on all alike; each runs its own code
(``PYTHONPATH`` is set to its ``workflow/``).  ``--python`` runs Snakemake with another
interpreter (e.g. a venv of ``requirements.txt`` alone, as a user has it).

Nothing here is a test: timings depend on the machine and what else it is doing.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

#: What every job imports at least: the clean build is measured in multiples of it.
BASELINE_IMPORTS = "import numpy, pandas, scipy.optimize, matplotlib.pyplot"
#: The targets the issues set (issue 34: clean build; issue 33: rerun and scale fits).
#: The clean build, in multiples of the import baseline of the same session.
CLEAN_BUILD_TARGET = 12
#: The rerun with nothing changed, in seconds over a one-rule workflow's rerun.
RERUN_OVER_FLOOR_S = 0.2
#: The `fits` target on the scale datasets, seconds by number of subjects.
FITS_TARGET_S = {1000: 7, 10000: 35}
#: The elastic finger's fit of one trial by interpolation in its library (issue 36), ms.
ELASTIC_FIT_TARGET_MS = 5.0
#: Trials timed for it.
ELASTIC_FIT_TRIALS = 200

REPO = Path(__file__).resolve().parents[1]
PAGE_KB = os.sysconf("SC_PAGE_SIZE") / 1024


def tree_rss_kb(root_pid):
    """Resident memory (kB) of a process and all its descendants, from /proc."""
    parents, rss = {}, {}
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            with open(f"/proc/{entry}/stat") as handle:
                fields = handle.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        parents[int(entry)] = int(fields[1])
        rss[int(entry)] = int(fields[21]) * PAGE_KB
    total, stack = 0.0, [root_pid]
    while stack:
        pid = stack.pop()
        total += rss.get(pid, 0.0)
        stack.extend(child for child, parent in parents.items() if parent == pid)
    return total


def run(command, cwd=REPO):
    """Run a command; return (seconds, peak tree RSS in MB, stdout+stderr, CPU seconds).

    The CPU seconds (user + system, of the command and every process it waited for)
    move far less than the wall-clock ones when other work shares the machine: for a
    rerun with nothing to do, one process that waits for nothing, they are what the
    wall clock shows on an idle machine.
    """
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    process = subprocess.Popen(
        command, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    peak = [0.0]

    def sample():
        while process.poll() is None:
            peak[0] = max(peak[0], tree_rss_kb(process.pid))
            time.sleep(0.1)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    output, _ = process.communicate()
    seconds = time.perf_counter() - start
    sampler.join()
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    if process.returncode != 0:
        raise RuntimeError(f"{' '.join(map(str, command))} failed:\n{output[-3000:]}")
    return seconds, peak[0] / 1024, output, cpu


def snakemake(*args, raw, results, cores=2, config=(), python=sys.executable):
    return [
        python, "-m", "snakemake", "--cores", str(cores), *args,
        "--config", f"raw_data={raw}", f"results={results}", *config,
    ]  # fmt: skip


def run_in(checkout, command):
    """:func:`run` in a checkout, with that checkout's package first on the path."""
    previous = os.environ.get("PYTHONPATH")
    os.environ["PYTHONPATH"] = str(Path(checkout) / "workflow")
    try:
        return run(command, cwd=checkout)
    finally:
        if previous is None:
            del os.environ["PYTHONPATH"]
        else:
            os.environ["PYTHONPATH"] = previous


def make_scale_data(folder, n):
    """The generator's dataset of ``n`` subjects (half monkeys, half humans), 4 depths."""
    subprocess.run(
        [
            sys.executable,
            str(REPO / "workflow/scripts/make_synthetic_data.py"),
            "--out",
            str(folder),
            "--monkeys",
            str(n // 2),
            "--humans",
            str(n - n // 2),
            "--clean",
        ],
        check=True,
        capture_output=True,
    )


def make_photograph_scale_data(folder, pairs):
    """A raw folder of ``pairs`` photograph pairs (``pairs / 2`` subjects at two depths):
    the example's four pairs (data/photographs) over and over, each file a hard link to
    the example's (the digitiser reads every one; nothing is cached)."""
    example = REPO / "data" / "photographs"
    (folder / "images").mkdir(parents=True)
    shutil.copy(example / "NOTICE.txt", folder / "NOTICE.txt")
    subjects, images = (
        ["subject,species,magnification,label"],
        ["subject,depth_mm,state,file,pixels_per_mm"],
    )
    for i in range(pairs // 2):
        name, source = f"P{i:05d}", ("M1", "M2")[i % 2]
        subjects.append(f"{name},monkey,1,Photographed {i}")
        for depth in (1, 2):
            for state in ("rest", "loaded"):
                file = f"{name}_{depth}mm_{state}.png"
                os.link(
                    example / "images" / f"{source}_{depth}mm_{state}.png", folder / "images" / file
                )
                images.append(f"{name},{depth},{state},{file},60")
    (folder / "subjects.csv").write_text("\n".join(subjects) + "\n")
    (folder / "images" / "images.csv").write_text("\n".join(images) + "\n")


def job_seconds(results, rule):
    """Wall seconds, CPU seconds and peak memory (MB) of every job of ``rule``, from its
    benchmark files."""
    rows = []
    for path in sorted((results / "benchmarks" / rule).glob("*.tsv")):
        header, values = path.read_text().splitlines()[:2]
        row = dict(zip(header.split("\t"), values.split("\t"), strict=True))
        rows.append((float(row["s"]), float(row["cpu_time"]), float(row["max_rss"])))
    return rows


def photograph_scale(pairs, cores, python, work):
    """Digitising ``pairs`` pairs (rule digitise, batches as configured) at each core
    count: lines of a Markdown table.  The raw-data check, which reads every pair too,
    runs first, once, and is not counted; then for each core count the digitised files
    are removed and made again."""
    raw, results = work / "photographs-raw", work / "photographs-results"
    make_photograph_scale_data(raw, pairs)
    config = ("digitise__reach_mm=6.5",)
    run(
        snakemake("check", raw=raw, results=results, cores=max(cores), config=config, python=python)
    )
    lines = [
        f"Digitising {pairs} photograph pairs ({pairs // 2} subjects, batches of "
        "`subjects_per_job: auto`), after the raw-data check:",
        "",
        "| cores | wall s | CPU s (all) | jobs' wall s, summed | CPU s (jobs) "
        "| CPU ms a pair (jobs) | jobs | largest job MB | load average |",
        "|--:|--:|--:|--:|--:|--:|--:|--:|---|",
    ]
    for n in cores:
        shutil.rmtree(results / "digitised", ignore_errors=True)
        shutil.rmtree(results / "benchmarks" / "digitise", ignore_errors=True)
        command = snakemake(
            "--forcerun", "digitise", "--until", "digitise",
            raw=raw, results=results, cores=n, config=config, python=python,
        )  # fmt: skip
        seconds, _, _, everything = run(command)
        jobs = job_seconds(results, "digitise")
        cpu = sum(c for _, c, _ in jobs)
        memory = max(m for _, _, m in jobs)
        load = os.getloadavg()
        lines.append(
            f"| {n} | {seconds:.1f} | {everything:.1f} | {sum(w for w, _, _ in jobs):.1f} "
            f"| {cpu:.1f} | {1000 * cpu / pairs:.1f} "
            f"| {len(jobs)} | "
            f"{memory:.0f} | {load[0]:.1f} / {load[1]:.1f} / {load[2]:.1f} |"
        )
    return lines


def make_one_rule_workflow(folder, python=sys.executable, freeze=False):
    """A workflow of one rule with one param (which makes Snakemake import pandas to
    compare it), built once: its rerun is what no workflow goes below.

    With ``freeze``, its Snakefile first freezes the objects of Snakemake's start-up
    (``gc.freeze()``), as this workflow's Snakefile does: the floor to hold a rerun of
    this workflow against, since the freeze saves a one-rule workflow as much."""
    folder.mkdir()
    (folder / "Snakefile").write_text(
        ("import gc\ngc.freeze()\n\n" if freeze else "") + 'rule all:\n    input: "a.txt"\n\n'
        'rule a:\n    output: "a.txt"\n    params: n=1\n'
        '    shell: "echo {params.n} > {output}"\n'
    )
    run([python, "-m", "snakemake", "--cores", "2"], cwd=folder)
    return folder


def side_by_side(against, repeats, scales, python, work):
    """Rows (what, this checkout's median, the other's, both runs) measured alternately."""
    checkouts = {"this": REPO, "other": Path(against).resolve()}
    rows = []

    def alternate(what, prepare, command_for, n, cpu=False):
        times = {name: [] for name in checkouts}
        cpus = {name: [] for name in checkouts}
        for _ in range(n):
            for name, checkout in checkouts.items():
                prepare(name)
                measured = run_in(checkout, command_for(name))
                times[name].append(measured[0])
                cpus[name].append(measured[3])
        rows.append((what, *(statistics.median(times[k]) for k in checkouts), times))
        if cpu:
            rows.append(
                (f"{what}, CPU seconds", *(statistics.median(cpus[k]) for k in checkouts), cpus)
            )

    raw = work / "raw"
    shutil.copytree(REPO / "data" / "raw", raw)
    baseline = []
    alternate(
        "clean build, default target (shipped data)",
        # the import baseline before each build, so that their ratio sees one load
        lambda name: (
            shutil.rmtree(work / f"results-{name}", ignore_errors=True),
            baseline.append(run([python, "-c", BASELINE_IMPORTS])),
        ),
        lambda name: snakemake(raw=raw, results=work / f"results-{name}", python=python),
        repeats,
        cpu=True,
    )
    clean_row = rows[-2]
    base = statistics.median(measured[0] for measured in baseline)
    rows.append(
        (
            f"import baseline (`{BASELINE_IMPORTS}`)",
            base,
            float("nan"),
            {"baseline": [m[0] for m in baseline]},
        )
    )
    rows.append(
        (
            f"clean build / import baseline (target <= {CLEAN_BUILD_TARGET:g})",
            clean_row[1] / base,
            clean_row[2] / base,
            {},
        )
    )
    one_rule = make_one_rule_workflow(work / "one-rule", python)
    frozen = make_one_rule_workflow(work / "one-rule-frozen", python, freeze=True)
    floors = {"": [], ", its Snakefile freezing the start-up's objects": []}

    def measure_floors(name):
        for folder, values in zip((one_rule, frozen), floors.values(), strict=True):
            values.append(run([python, "-m", "snakemake", "--cores", "2"], cwd=folder))

    alternate(
        "rerun, nothing changed (shipped data)",
        # the floors between the two, so that they see the same load
        measure_floors,
        lambda name: snakemake(raw=raw, results=work / f"results-{name}", python=python),
        max(repeats, 5),
        cpu=True,
    )
    for kind, floor in floors.items():
        for what, index in (("", 0), (", CPU seconds", 3)):
            values = [measured[index] for measured in floor]
            rows.append(
                (
                    f"floor: rerun of a one-rule workflow with one param{kind}, "
                    f"nothing changed{what}",
                    statistics.median(values),
                    float("nan"),
                    {"floor": values},
                )
            )
    for n in scales:
        scale_raw = work / f"raw{n}"
        make_scale_data(scale_raw, n)

        def clean(name, n=n):
            shutil.rmtree(work / f"results{n}-{name}", ignore_errors=True)

        alternate(
            f"`fits` target, {n} subjects x 4 depths",
            clean,
            lambda name, n=n, scale_raw=scale_raw: snakemake(
                "fits", raw=scale_raw, results=work / f"results{n}-{name}", python=python
            ),
            repeats,
        )
        for name in checkouts:
            shutil.rmtree(work / f"results{n}-{name}", ignore_errors=True)
    return rows


def elastic_fit_ms():
    """Milliseconds per trial of the elastic fits, on noisy profiles made from the library.

    Each trial is a profile of the kept library (a species, depth, section, thickness and
    ratio taken in turn) on the shipped reading grid inside 3 mm, with 0.005 mm of noise;
    the library's blocks are read once beforehand, as the fit job reads them.
    """
    import numpy as np
    import pandas as pd

    sys.path.insert(0, str(REPO / "workflow"))
    from lineload.fitting.elastic import fit_elastic, library_blocks
    from lineload.rawdata.readings import reading_distances_mm

    blocks = list(library_blocks(pd.read_csv(REPO / "data" / "elastic" / "library.csv")).values())
    x = reading_distances_mm(3.0)
    x = x[(x > 0) & (x <= 3.0)]
    rng = np.random.default_rng(0)
    trials = []
    for k in range(ELASTIC_FIT_TRIALS):
        block = blocks[k % len(blocks)]
        g, t, r = (k % n for n in block.deflection_mm.shape[:3])
        trials.append((x, block.curves_at(x)[g, t, r] + rng.normal(0, 0.005, x.size), block))
    start = time.perf_counter()
    for distance_mm, deflection_mm, block in trials:
        fit_elastic(distance_mm, deflection_mm, block)
    return 1000 * (time.perf_counter() - start) / len(trials)


def jobs_run(output):
    """Rules that ran, with counts, from the jobs Snakemake announced.

    Not from its job table: that is printed when the run starts, and the jobs after
    the raw-data check (a checkpoint) are decided only once it has passed.
    """
    counts = {}
    for rule in re.findall(r"^(?:local)?(?:rule|checkpoint) (\w+):$", output, re.M):
        counts[rule] = counts.get(rule, 0) + 1
    return ", ".join(f"{rule} x{n}" for rule, n in counts.items()) or "none"


def median_of(repeats, measure):
    values = [measure() for _ in range(repeats)]
    return statistics.median(v[0] for v in values), values


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument(
        "--scale",
        type=int,
        nargs="*",
        default=[1000, 10000],
        help="subject counts of the scale runs (half monkeys, half humans)",
    )
    parser.add_argument("--output", type=Path, help="write the Markdown table here too")
    parser.add_argument(
        "--calibration",
        type=int,
        nargs="*",
        metavar="CORES",
        help="also time the boundary calibration (one job per world and block of datasets) "
        "at these core counts, e.g. --calibration 1 2 4, and give the speed-up over the first",
    )
    parser.add_argument(
        "--calibration-datasets",
        type=int,
        default=4,
        help="verdict_datasets of the timed calibration (blocks of half as many)",
    )
    parser.add_argument(
        "--elastic-library",
        action="store_true",
        help="also time the elastic_library target (the finite-element library, minutes)",
    )
    parser.add_argument(
        "--photographs",
        type=int,
        metavar="PAIRS",
        help="only time digitising this many photograph pairs at each of --photograph-cores",
    )
    parser.add_argument("--photograph-cores", type=int, nargs="*", default=[1, 2])
    parser.add_argument("--against", type=Path, help="another checkout, measured alternately")
    parser.add_argument("--python", default=sys.executable, help="the Python that runs Snakemake")
    args = parser.parse_args()
    work = Path(tempfile.mkdtemp(prefix="lineload-bench-"))
    if args.photographs:
        try:
            lines = photograph_scale(args.photographs, args.photograph_cores, args.python, work)
        finally:
            shutil.rmtree(work, ignore_errors=True)
        table = "\n".join(lines) + "\n"
        print(table)
        if args.output:
            args.output.write_text(table)
        return
    if args.against:
        try:
            rows = side_by_side(args.against, args.repeats, args.scale, args.python, work)
        finally:
            shutil.rmtree(work, ignore_errors=True)
        load = os.getloadavg()
        lines = [
            f"This checkout ({REPO}) against {args.against}, alternating; medians of "
            f"{args.repeats} runs (at least 5 for the rerun), wall-clock seconds, "
            f"{os.cpu_count()} cores, Snakemake run by {args.python}; load average at the "
            f"end {load[0]:.2f} / {load[1]:.2f} / {load[2]:.2f} (1 / 5 / 15 min).",
            "",
            "| what | this | other | every run (this; other) |",
            "|---|--:|--:|---|",
            *[
                f"| {what} | {this:.2f} | {'' if other != other else f'{other:.2f}'} | "
                + "; ".join(" ".join(f"{t:.2f}" for t in ts) for ts in times.values())
                + " |"
                for what, this, other, times in rows
            ],
        ]
        table = "\n".join(lines) + "\n"
        print(table)
        if args.output:
            args.output.write_text(table)
        return
    rows = []
    try:
        baseline, _ = median_of(
            args.repeats,
            lambda: run([sys.executable, "-c", BASELINE_IMPORTS]),
        )
        rows.append(
            ("import numpy, pandas, scipy.optimize, matplotlib.pyplot", baseline, "", "baseline")
        )

        per_trial_ms = statistics.median(elastic_fit_ms() for _ in range(args.repeats))
        rows.append(
            (
                f"elastic fits by interpolation, {ELASTIC_FIT_TRIALS} trials",
                per_trial_ms * ELASTIC_FIT_TRIALS / 1000,
                "",
                f"{per_trial_ms:.2f} ms per trial; target <= {ELASTIC_FIT_TARGET_MS:g} ms",
            )
        )

        raw = work / "raw"
        shutil.copytree(REPO / "data" / "raw", raw)
        results = work / "results"

        def clean_build():
            shutil.rmtree(results, ignore_errors=True)  # the raw-data check's output too
            return run(snakemake(raw=raw, results=results))

        clean, runs = median_of(args.repeats, clean_build)
        rows.append(
            (
                "clean build, default target (shipped data)",
                clean,
                f"{max(r[1] for r in runs):.0f} MB",
                f"target <= {CLEAN_BUILD_TARGET:g} x baseline = "
                f"{CLEAN_BUILD_TARGET * baseline:.1f} s ({clean / baseline:.1f} x)",
            )
        )

        def job_seconds(pattern):
            return sum(
                float(path.read_text().splitlines()[1].split("\t")[0])
                for path in (results / "benchmarks").glob(pattern)
            )

        figure_seconds = job_seconds("figure_*.tsv")
        article_seconds = job_seconds("article.tsv")
        all_job_seconds = job_seconds("**/*.tsv")

        noop, _ = median_of(max(args.repeats, 5), lambda: run(snakemake(raw=raw, results=results)))
        rows.append(
            ("rerun, nothing changed", noop, "", f"target <= floor + {RERUN_OVER_FLOOR_S:g} s")
        )

        # What no workflow goes below on this machine.
        version, _ = median_of(
            max(args.repeats, 5), lambda: run([sys.executable, "-m", "snakemake", "--version"])
        )
        rows.append(("floor: `snakemake --version`", version, "", "Snakemake's start-up"))
        for freeze, note in (
            (False, "with one param, so Snakemake imports pandas to compare it"),
            (True, "the same, its Snakefile freezing the start-up's objects as ours does"),
        ):
            one_rule = make_one_rule_workflow(work / f"one-rule-{freeze}", freeze=freeze)
            trivial, _ = median_of(
                max(args.repeats, 5),
                lambda one_rule=one_rule: run(
                    [sys.executable, "-m", "snakemake", "--cores", "2"], cwd=one_rule
                ),
            )
            rows.append(("floor: rerun of a one-rule workflow, nothing changed", trivial, "", note))
        rows.append(
            (
                "figure jobs of the last clean build, summed",
                figure_seconds,
                "",
                f"a clean build on 2 cores takes at least {version:.2f} + "
                f"{figure_seconds:.2f} / 2 = {version + figure_seconds / 2:.1f} s",
            )
        )
        rows.append(
            (
                "article job of the last clean build (Typst)",
                article_seconds,
                "",
                "facts from the tables, then the PDF",
            )
        )
        rows.append(
            (
                "every job of the last clean build, summed",
                all_job_seconds,
                "",
                f"on 2 cores at least {version:.2f} + {all_job_seconds:.2f} / 2 = "
                f"{version + all_job_seconds / 2:.1f} s",
            )
        )

        def edit_one():
            profile = raw / "profiles" / "M2.csv"
            text = profile.read_text()
            # change one reading's last digit and back on alternate calls
            lines = text.splitlines()
            last = lines[5]
            lines[5] = last[:-1] + ("1" if last[-1] != "1" else "2")
            profile.write_text("\n".join(lines) + "\n")
            # the workflow profile's quiet console names no job: print the rules (not the
            # progress) so that the jobs that ran can be counted
            return run(snakemake("--quiet", "progress", "host", raw=raw, results=results))

        edited, runs = median_of(args.repeats, edit_one)
        rows.append(
            ("rerun after editing profiles/M2.csv", edited, "", "jobs: " + jobs_run(runs[-1][2]))
        )

        previous = None
        for n in args.scale:
            scale_raw, scale_results = work / f"raw{n}", work / f"results{n}"
            subprocess.run(
                [
                    sys.executable,
                    str(REPO / "workflow/scripts/make_synthetic_data.py"),
                    "--out",
                    str(scale_raw),
                    "--monkeys",
                    str(n // 2),
                    "--humans",
                    str(n - n // 2),
                    "--clean",
                ],
                check=True,
                capture_output=True,
            )

            def scale_build(scale_raw=scale_raw, scale_results=scale_results):
                shutil.rmtree(scale_results, ignore_errors=True)
                return run(snakemake("fits", raw=scale_raw, results=scale_results))

            seconds, runs = median_of(args.repeats, scale_build)
            peak = max(r[1] for r in runs)
            targets = {n: f"target <= {t:g} s" for n, t in FITS_TARGET_S.items()}
            note = f"{targets.get(n, '')}, peak <= 2 GB".lstrip(", ")
            if previous:
                note += f"; {seconds / previous[1]:.2f} x the {previous[0]}-subject time"
            rows.append(
                (f"`fits` target, {n} subjects x 4 depths", seconds, f"{peak:.0f} MB", note)
            )
            again, _ = median_of(
                max(args.repeats, 5),
                lambda scale_raw=scale_raw, scale_results=scale_results: run(
                    snakemake("fits", raw=scale_raw, results=scale_results)
                ),
            )
            rows.append(
                (
                    f"rerun of `fits`, {n} subjects, nothing changed",
                    again,
                    "",
                    "the raw-data check is up to date, not repeated",
                )
            )
            previous = (n, seconds)

        if args.elastic_library:
            library_results = work / "elastic"
            seconds, runs = median_of(
                1,
                lambda: run(snakemake("elastic_library", raw=raw, results=library_results)),
            )
            rates = [
                line.split("(")[-1].split(" factorisations per second")[0]
                for log in sorted((library_results / "logs" / "elastic_library").glob("*.log"))
                for line in log.read_text().splitlines()
                if "factorisations per second" in line
            ]
            rows.append(
                (
                    "`elastic_library` target (finite-element solves), --cores 2",
                    seconds,
                    f"{max(r[1] for r in runs):.0f} MB",
                    "factorisations per second per job: " + ", ".join(rates),
                )
            )

        first = None
        for cores in args.calibration or ():
            n = args.calibration_datasets
            settings = f"calibration={{verdict_datasets: {n}, block_datasets: {max(n // 2, 1)}}}"

            def calibrate(cores=cores, settings=settings):
                shutil.rmtree(work / "calibration", ignore_errors=True)
                return run(
                    snakemake(
                        "boundary_calibration",
                        raw=raw,
                        results=work / "calibration",
                        cores=cores,
                        config=(settings,),
                    )
                )

            seconds, _ = median_of(1, calibrate)
            first = first or (cores, seconds)
            rows.append(
                (
                    f"boundary calibration, {n} datasets per world and side, --cores {cores}",
                    seconds,
                    "",
                    f"speed-up {first[1] / seconds:.2f} over --cores {first[0]}",
                )
            )
    finally:
        shutil.rmtree(work, ignore_errors=True)

    lines = [
        f"Measured on {os.cpu_count()} cores, median of {args.repeats} runs "
        "(at least 5 for the reruns and floors); peak memory of the whole process tree.",
        "",
        "| what | seconds | peak memory | note |",
        "|---|--:|--:|---|",
        *[
            f"| {what} | {seconds:.2f} | {memory} | {note} |"
            for what, seconds, memory, note in rows
        ],
    ]
    table = "\n".join(lines) + "\n"
    print(table)
    if args.output:
        args.output.write_text(table)


if __name__ == "__main__":
    main()
