#!/usr/bin/env bash
# Redraw the rule graph shown in the README from Snakemake's own --rulegraph output,
# drawn by graphviz-pure (a packaged port of Graphviz's dot).  The graph is that of the
# rules that make the tables and figures; the bookkeeping rules (all, provenance), which
# depend on everything, are left out so that each arrow shows a real flow of data.
#   bash docs/rulegraph.sh [folder]      (default: docs/)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs}
mkdir -p "$out"
PYTHONHASHSEED=0 snakemake claims_table fit_tables figure_outlines figure_schematics figure_fits \
    figure_supplements figure_families figure_calibration --rulegraph >"$out/rulegraph.dot"
graphviz-pure -Tpng -o "$out/rulegraph.png" "$out/rulegraph.dot" 2>/dev/null
