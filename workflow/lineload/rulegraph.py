"""Draw Snakemake's rule graph (``snakemake --rulegraph``) with matplotlib.

Graphviz is not a Python package, so the workflow lays the graph out itself:
each rule sits in the layer of its longest chain of upstream rules, and rules
in a layer are ordered by the mean position of the rules they depend on.
"""

from __future__ import annotations

import re

__all__ = ["draw_rulegraph", "layered_layout", "parse_rulegraph", "transitive_reduction"]

_NODE = re.compile(r'^\s*(\d+)\s*\[\s*label\s*=\s*"([^"]+)"', re.M)
_EDGE = re.compile(r"^\s*(\d+)\s*->\s*(\d+)", re.M)


def parse_rulegraph(dot_text):
    """Rule names and dependencies from the DOT text of ``snakemake --rulegraph``.

    Parameters
    ----------
    dot_text : str

    Returns
    -------
    tuple
        ``(rules, edges)``: the rule names in order of appearance, and the set
        of ``(upstream, downstream)`` name pairs.
    """
    names = {number: name for number, name in _NODE.findall(dot_text)}
    edges = {(names[a], names[b]) for a, b in _EDGE.findall(dot_text)}
    return list(names.values()), edges


def transitive_reduction(edges):
    """Drop each edge that another path between the same two rules already implies.

    Parameters
    ----------
    edges : set of tuple
        ``(upstream, downstream)`` pairs of an acyclic graph.

    Returns
    -------
    set of tuple
        The smallest subset with the same reachability.
    """
    downstream = {}
    for a, b in edges:
        downstream.setdefault(a, set()).add(b)

    def reachable(start, skip_edge):
        seen, stack = set(), [start]
        while stack:
            node = stack.pop()
            for nxt in downstream.get(node, ()):
                if (node, nxt) == skip_edge or nxt in seen:
                    continue
                seen.add(nxt)
                stack.append(nxt)
        return seen

    return {(a, b) for a, b in edges if b not in reachable(a, (a, b))}


def layered_layout(rules, edges):
    """Layer and position of each rule, sources first.

    Parameters
    ----------
    rules : list of str
    edges : set of tuple
        ``(upstream, downstream)`` pairs; the graph must have no cycle.

    Returns
    -------
    dict
        Rule name to ``(layer, position)``; positions within a layer are
        0, 1, 2, ... ordered to keep edges short.
    """
    upstream = {rule: sorted(a for a, b in edges if b == rule) for rule in rules}
    layer = {}

    def depth(rule, seen=()):
        if rule in seen:
            raise ValueError(f"the rule graph has a cycle through {rule!r}")
        if rule not in layer:
            layer[rule] = 1 + max((depth(u, (*seen, rule)) for u in upstream[rule]), default=-1)
        return layer[rule]

    rules = sorted(rules)
    for rule in rules:
        depth(rule)
    position = {}
    for level in range(max(layer.values(), default=-1) + 1):
        members = [r for r in rules if layer[r] == level]

        def barycentre(rule):
            # ties broken by name, so the picture does not depend on Snakemake's node order
            parents = [position[u] for u in upstream[rule]]
            return (sum(parents) / len(parents) if parents else 0.0, rule)

        for index, rule in enumerate(sorted(members, key=barycentre)):
            position[rule] = index
    return {rule: (layer[rule], position[rule]) for rule in rules}


def draw_rulegraph(rules, edges, notes=None):
    """A figure of the rule graph: one box per rule, arrows along the data flow.

    Edges implied by longer paths are left out (transitive reduction), so an
    arrow means "feeds directly and not only through another rule".

    Parameters
    ----------
    rules : list of str
    edges : set of tuple
        ``(upstream, downstream)`` pairs.
    notes : dict, optional
        Rule name to a short line shown under its name.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure
    from matplotlib.patches import FancyArrowPatch, FancyBboxPatch

    notes = notes or {}
    edges = transitive_reduction(edges)
    places = layered_layout(rules, edges)
    n_layers = 1 + max(layer for layer, _ in places.values())
    widest = max(sum(1 for lay, _ in places.values() if lay == k) for k in range(n_layers))
    box_w, box_h, gap_x, gap_y = 2.6, 0.7, 0.4, 0.9
    fig = Figure(figsize=(max(4.0, widest * 1.3), n_layers * 0.75 + 0.3))
    ax = fig.add_axes((0, 0, 1, 1))
    centre = {}
    for rule, (layer, pos) in places.items():
        in_layer = sum(1 for lay, _ in places.values() if lay == layer)
        x = (pos - (in_layer - 1) / 2) * (box_w + gap_x)
        y = -layer * (box_h + gap_y)
        centre[rule] = (x, y)
        ax.add_patch(
            FancyBboxPatch(
                (x - box_w / 2, y - box_h / 2),
                box_w,
                box_h,
                boxstyle="round,pad=0.02,rounding_size=0.15",
                facecolor="#eef3f8",
                edgecolor="#4a6b8a",
                linewidth=1.0,
            )
        )
        label = rule if rule not in notes else f"{rule}\n{notes[rule]}"
        ax.text(x, y, label, ha="center", va="center", fontsize=7, family="DejaVu Sans")
    for a, b in sorted(edges):
        (xa, ya), (xb, yb) = centre[a], centre[b]
        ax.add_patch(
            FancyArrowPatch(
                (xa, ya - box_h / 2),
                (xb, yb + box_h / 2),
                arrowstyle="-|>",
                mutation_scale=8,
                color="0.45",
                linewidth=0.8,
                shrinkA=1,
                shrinkB=1,
            )
        )
    xs = [x for x, _ in centre.values()]
    ys = [y for _, y in centre.values()]
    ax.set_xlim(min(xs) - box_w / 2 - 0.2, max(xs) + box_w / 2 + 0.2)
    ax.set_ylim(min(ys) - box_h / 2 - 0.2, max(ys) + box_h / 2 + 0.2)
    ax.set_axis_off()
    return fig
