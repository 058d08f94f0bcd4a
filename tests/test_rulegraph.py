"""Parsing and laying out the rule graph."""

import pytest

from lineload import rulegraph

DOT = """digraph snakemake_dag {
    graph[bgcolor=white, margin=0];
	0[label = "all", color = "0.00 0.6 0.85", style="rounded"];
	1[label = "table", color = "0.46 0.6 0.85", style="rounded"];
	2[label = "fit", color = "0.33 0.6 0.85", style="rounded"];
	3[label = "prepare", color = "0.54 0.6 0.85", style="rounded"];
	1 -> 0
	2 -> 1
	3 -> 2
	3 -> 0
}"""


def test_parse():
    rules, edges = rulegraph.parse_rulegraph(DOT)
    assert rules == ["all", "table", "fit", "prepare"]
    assert edges == {("table", "all"), ("fit", "table"), ("prepare", "fit"), ("prepare", "all")}


def test_transitive_reduction_drops_implied_edges_only():
    _, edges = rulegraph.parse_rulegraph(DOT)
    reduced = rulegraph.transitive_reduction(edges)
    assert reduced == edges - {("prepare", "all")}


def test_layers_follow_the_longest_upstream_chain():
    rules, edges = rulegraph.parse_rulegraph(DOT)
    layout = rulegraph.layered_layout(rules, edges)
    assert {rule: layer for rule, (layer, _) in layout.items()} == {
        "prepare": 0,
        "fit": 1,
        "table": 2,
        "all": 3,
    }


def test_cycle_is_refused():
    with pytest.raises(ValueError, match="cycle"):
        rulegraph.layered_layout(["a", "b"], {("a", "b"), ("b", "a")})


def test_drawing_has_a_box_per_rule_and_an_arrow_per_direct_edge():
    rules, edges = rulegraph.parse_rulegraph(DOT)
    figure = rulegraph.draw_rulegraph(rules, edges)
    (ax,) = figure.axes
    labels = sorted(text.get_text() for text in ax.texts)
    assert labels == sorted(rules)
    arrows = [p for p in ax.patches if type(p).__name__ == "FancyArrowPatch"]
    assert len(arrows) == len(rulegraph.transitive_reduction(edges))


def test_layout_does_not_depend_on_node_order():
    rules, edges = rulegraph.parse_rulegraph(DOT)
    assert rulegraph.layered_layout(rules, edges) == rulegraph.layered_layout(rules[::-1], edges)
