"""Behaviours that wait for values (END_WAIT) too large for a fragment: a chain whose parts go on
in the same run (CONTINUE_COMMAND, rdcd_core/compiler/chain.py); the last part waits, and the
behaviour runs again from its first part. Split and unsplit forms end alike in the lattice world."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rdcd_core.frontend import check_text
from tests.compiler.split_run import both, same_outcome

SPREAD = ("a := max(max(neighbours.a), self.x()); b := a + self.y(); c := b + a; d := c + b; "
          "a := min(a, 20); b := min(b, 30); c := min(c, 40); d := min(d, 50);")


def program(body: str = SPREAD) -> str:
    states = "".join(f"state {name} := 0;\n" for name in "abcd")
    return (f"{states}role W {{ self.center_position == EAST_WEST;\n  behavior spread() {{ {body} }} }}\n"
            "deployment { W }\n")


def test_a_large_reactive_behaviour_is_a_chain_that_waits():
    split, unsplit = both(program())
    assert max(f.size for f in unsplit.fragments) > 43 and not split.diagnostics
    assert all(f.size <= split.program_budget for f in split.fragments)
    code = b"".join(f.code for f in split.fragments)
    assert bytes([79]) in code and bytes([67]) in code  # CONTINUE_COMMAND, END_WAIT


@pytest.mark.parametrize("config,loss,seed", [("car7", 0.0, 5), ("car7", 0.1, 1), ("snake6", 0.1, 3)])
def test_the_chain_ends_as_the_unsplit_behaviour(config, loss, seed):
    after, before = same_outcome(program(), config=config, loss=loss, seed=seed, seconds=20.0)
    assert after == before
    assert any(dict(states)["d"] != 0 for _, states, *_ in after.values())  # values were computed


ASSIGN = st.tuples(st.sampled_from("abcd"), st.sampled_from("abcd"), st.sampled_from("+-*"),
                   st.integers(-3, 5))


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(ASSIGN, min_size=6, max_size=14))
def test_split_and_unsplit_reactive_behaviours_end_alike(assigns):
    body = "a := max(max(neighbours.a), self.x()); " + " ".join(
        f"{target} := min({source} {op} {k}, 40);" for target, source, op, k in assigns)
    text = program(body)
    split, unsplit = both(text)
    if max(f.size for f in unsplit.fragments) > 64 or unsplit.diagnostics:
        return  # no unsplit form in a program slot to compare with
    after, before = same_outcome(text, seconds=15.0)
    assert after == before


def test_a_huge_reactive_behaviour_is_reported_never_a_traceback():
    body = " ".join(f"a := min(a + {i % 7}, 40);" for i in range(300))
    result = check_text(program(body))
    assert not any(d.code.startswith("E9") for d in result.diagnostics)
    assert any(d.code in ("W601", "E601") for d in result.diagnostics)  # more parts than numbers
