"""Entry point of rule rulegraph: draw the DOT rule graph as PNG and PDF."""

import argparse

import _bootstrap  # noqa: F401  (puts the lineload package on the path)
from lineload.figures.style import save_figure
from lineload.rulegraph import draw_rulegraph, parse_rulegraph


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--dot", required=True)
    parser.add_argument("--png", required=True)
    parser.add_argument("--pdf", required=True)
    args = parser.parse_args()

    with open(args.dot, encoding="utf-8") as handle:
        rules, edges = parse_rulegraph(handle.read())
    save_figure(draw_rulegraph(rules, edges), args.pdf, args.png, dpi=200)
    print(f"{len(rules)} rules, {len(edges)} dependencies")


if __name__ == "__main__":
    main()
