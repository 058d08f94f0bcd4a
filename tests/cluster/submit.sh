#!/usr/bin/env bash
# Stand-in for sbatch in the cluster test: start the job script Snakemake wrote, in the
# background and detached (as a scheduler would on another node), and print a job id.
# The script has only itself to go on, so a passing test shows job scripts are
# self-contained. Completion is signalled by the marker files the script touches.
set -euo pipefail
jobscript="$1"
nohup bash "$jobscript" > "$jobscript.out" 2>&1 < /dev/null &
echo "$!"
