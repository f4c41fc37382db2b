"""Random, mostly well-formed programs: the analysis never raises and its output is well-formed."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from rdcd_core.frontend import check_text
from rdcd_core.semantics import analyze
from rdcd_core.syntax.parser import parse

ROLES = ["A", "B", "C", "M", "Module", "Nope"]
NAMES = ["k", "d", "EAST", "UP", "EAST_WEST", "EVENT_PROXIMITY_1", "A", "M", "zz"]
QUERIES = ["self.y()", "self.x", "self.center_position", "self.total_connected()",
           "self.connected(UP)", "self.connected(d)", "sizeof(self.total_connected())",
           "connected_role(DOWN, A)", "connected_role(UP, M)", "sizeof(connected_role(d, B))",
           "self.sleep()", "A.c()", "size(1)"]


def _exprs() -> st.SearchStrategy[str]:
    leaves = st.one_of(st.integers(-130, 130).map(str), st.sampled_from(NAMES),
                       st.sampled_from(QUERIES))
    return st.recursive(leaves, lambda inner: st.one_of(
        st.tuples(inner, st.sampled_from(["==", "!=", "<", ">=", "+", "-", "&&", "||"]), inner)
        .map(lambda t: f"{t[0]} {t[1]} {t[2]}"),
        inner.map(lambda e: f"({e})"), inner.map(lambda e: f"!{e}"), inner.map(lambda e: f"-{e}")),
        max_leaves=6)


def _statements() -> st.SearchStrategy[str]:
    simple = st.one_of(
        st.sampled_from(["self.sleep();", "self.stopTurning();", "A.c();", "B.c();", "self.h();",
                         "self.g();", "self.c();", "self.nope();", ";"]),
        _exprs().map(lambda e: f"self.turnTowards({e});"),
        _exprs().map(lambda e: f"self.setLed({e}, 1);"),
        st.sampled_from(ROLES).map(lambda r: f"self.assumeRole({r}, {{ self.h(); }});"))
    return st.recursive(simple, lambda inner: st.one_of(
        st.tuples(_exprs(), inner, inner).map(lambda t: f"if ({t[0]}) {t[1]} else {t[2]}"),
        st.tuples(st.sampled_from(["EVENT_PROXIMITY_0", "k"]), inner)
        .map(lambda t: f"self.handleEvent({t[0]}, {{ {t[1]} }});"),
        st.tuples(st.sampled_from(["M", "A"]), inner)
        .map(lambda t: f"self.assumeRole({t[0]}, {{ {t[1]} }});")), max_leaves=5)


def _members() -> st.SearchStrategy[str]:
    return st.one_of(
        _exprs().map(lambda e: f"{e};"),
        st.tuples(st.sampled_from(["k", "d"]), _exprs()).map(lambda t: f"constant {t[0]} := {t[1]};"),
        st.sampled_from(["abstract constant k, d;", "abstract g();", "abstract command c();"]),
        st.tuples(st.sampled_from(["", "startup ", "behavior ", "command ", "abstract "]),
                  st.sampled_from(["c", "g", "h", "s"]), st.lists(_statements(), max_size=3))
        .map(lambda t: f"{t[0]}{t[1]}() {{ {' '.join(t[2])} }}"))


def _roles() -> st.SearchStrategy[str]:
    return st.tuples(st.sampled_from(["", "abstract "]), st.sampled_from(ROLES),
                     st.sampled_from(["", " extends A", " extends B", " modifies A", " modifies M",
                                      " extends Nope"]),
                     st.lists(_members(), max_size=4)) \
        .map(lambda t: f"{t[0]}role {t[1]}{t[2]} {{ {' '.join(t[3])} }}")


programs = st.tuples(st.lists(_roles(), min_size=1, max_size=5),
                     st.lists(st.sampled_from(ROLES), max_size=4)) \
    .map(lambda t: "\n".join(t[0]) + "\ndeployment { " + ", ".join(t[1]) + " }")


@given(programs)
def test_random_programs(text: str) -> None:
    model = analyze(parse(text).program)
    for diagnostic in model.diagnostics:
        assert 0 <= diagnostic.span.start <= diagnostic.span.end <= len(text)
        assert diagnostic.message and "\n" not in diagnostic.message
    for reference in model.references:
        assert text[reference.name.span.start:reference.name.span.end] == reference.name.text
    assert all(d.code != "E100" for d in check_text(text).diagnostics)
