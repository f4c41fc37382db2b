"""State-dependent discovery too large for one fragment (rdcd_core/compiler/watched.py): each role
keeps in the discovery program the entry items that fit, the rest is a chain of commands installed
first; the split program ends as its unsplit form does in the lattice world (IR limit lifted for
the unsplit form), without loss and at 10 % loss."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rdcd_core.frontend import check_text
from tests.compiler.split_run import both, same_outcome
from tests.replay.test_browser_state import ROLE_STATE

# as in benchmarks/fragment_fit.py
THREE = ("state step := 0;\nrole Mover { step == 3; self.center_position == EAST_WEST;\n"
         "  startup go() { self.setLed(3); self.turnTowards(90); }\n"
         "  behavior b() { self.sleep(); step := step + 1; } }\n"
         "role Waiter { step < 3;\n  behavior w() { self.sleep(); self.setLed(step); step := step + 1; } }\n"
         "role Done { step > 3; startup s() { self.setLed(0); self.turnTowards(0); } }\n"
         "deployment { Mover, Waiter, Done }\n")
SIX = ("state step := 0;\n" + "".join(
    f"role R{k} {{ step == {k};\n  behavior b() {{ self.sleep(); self.setLed({k}); step := step + 1; }} }}\n"
    for k in range(6)) + "deployment { " + ", ".join(f"R{k}" for k in range(6)) + " }\n")


def program(visits: int = 3, limit: int = 9, leds: int = 0, extra: int = 0) -> str:
    """The replay's state program (64 bytes unsplit), with a startup of ``leds`` LED statements
    on Bottom and ``extra`` more statements in its counting behaviour."""
    startup = " ".join(f"self.setLed({n});" for n in range(leds))
    more = " ".join(f"visits := visits + {n + 1};" for n in range(extra))
    return f"""state lowest := 127;
abstract role Node {{
  behavior spread() {{ lowest := min(min(neighbours.lowest), self.z()); }}
}}
role Bottom extends Node {{
  state visits := {visits};
  self.z() == lowest;
  {f"startup s() {{ {startup} }}" if leds else ""}
  behavior count() {{ if (visits < {limit}) {{ visits := visits + 1; {more} }} }}
}}
role Upper extends Node {{ }}
deployment {{ Bottom, Upper }}
"""


def over(result) -> list:
    return [d for d in result.diagnostics if d.code in ("W601", "E601")]


def test_the_replays_state_program_fits_in_two_fragments():
    split, unsplit = both(ROLE_STATE)
    assert [f.size for f in unsplit.fragments] == [64]
    assert all(f.size <= split.program_budget for f in split.fragments)
    assert not over(check_text(ROLE_STATE))
    assert split.injection[-1].startswith("discover_")  # the installs arrive first on every link
    assert [f.kind for f in split.fragments] == ["entry", "discovery"]
    assert split.fragments[0].code[:3] == unsplit.fragments[0].code[:3]  # the state's initial value first


@pytest.mark.parametrize("loss,seed", [(0.0, 5), (0.1, 1), (0.1, 2)])
def test_the_split_program_ends_as_the_unsplit_one(loss, seed):
    after, before = same_outcome(ROLE_STATE, loss=loss, seed=seed, seconds=20.0)
    assert after == before
    assert {role for role, *_ in after.values()} == {"Bottom", "Upper"}  # every module got its role


def test_every_module_gets_its_role_on_a_snake():
    after, before = same_outcome(ROLE_STATE, config="snake6", seconds=20.0)
    assert after == before and all(role for role, *_ in after.values())


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(visits=st.integers(0, 5), limit=st.integers(4, 12), leds=st.integers(0, 6), extra=st.integers(0, 2))
def test_split_and_unsplit_forms_end_alike(visits, limit, leds, extra):
    text = program(visits, limit, leds, extra)
    split, unsplit = both(text)
    if max(f.size for f in unsplit.fragments) > 64:
        return  # the unsplit form does not fit a program slot: nothing to compare with
    after, before = same_outcome(text, seconds=20.0)
    assert after == before


def test_a_large_startup_is_spread_over_several_commands():
    text = program(leds=20)
    result = check_text(text)
    assert not result.has_errors and not over(result)
    split = result.compiled
    assert len(split.fragments) >= 3 and all(f.size <= split.program_budget for f in split.fragments)
    after, _ = same_outcome(text, seconds=20.0)
    assert all(not errors for *_, errors in after.values())


def test_a_huge_behaviour_is_named_not_a_traceback():
    text = program(extra=40)  # one behaviour of 40 statements: over a program slot alone
    result = check_text(text)
    assert [d.code for d in over(result)] and not any(d.code.startswith("E9") for d in result.diagnostics)


def test_deep_nesting_in_a_startup_is_reported_not_a_traceback():
    nested = "if (visits > 0) " * 40 + "self.setLed(1);"
    text = program().replace("behavior count()", f"startup deep() {{ {nested} }}\n  behavior count()")
    result = check_text(text)
    assert all(not d.code.startswith("E9") for d in result.diagnostics)


def test_without_a_spare_command_number_discovery_stays_whole(monkeypatch):
    import sys

    monkeypatch.setattr(sys.modules["rdcd_core.compiler.plan"], "watched_numbers", lambda commands: [])
    result = check_text(ROLE_STATE)
    assert [d.code for d in over(result)] == ["W601"]
    assert [f.size for f in result.compiled.fragments] == [64]


def test_programs_whose_discovery_fits_keep_their_bytes():
    from tests.conftest import EXAMPLES

    sizes = {}
    for name in ("gradient", "lowest", "count", "hops"):
        compiled = check_text((EXAMPLES / f"{name}.rdcd").read_text(encoding="utf-8")).compiled
        sizes[name] = [f.size for f in compiled.fragments]
    assert sizes == {"gradient": [34], "lowest": [41], "count": [22], "hops": [20]}


def test_roles_on_step_invariants_fit_and_follow_the_step():
    """`role R { step == 3; }`-style invariants (as reconfiguration sequences make): three roles
    whose tests do not fit one fragment go on in a command that tests the later roles."""
    from tests.compiler.split_run import outcome, run

    text = THREE
    result = check_text(text)
    assert not over(result) and all(f.size <= 43 for f in result.compiled.fragments)
    world = run(result.compiled, seconds=15.0, loss=0.1, seed=2)
    found = outcome(result.compiled, world)
    for mid, (role, states, *_rest, errors) in found.items():
        history = [world.runtimes[mid].roles.name(r) for _, r in world.runtimes[mid].role_history]
        assert not errors
        if history[-1] == "Done":  # an east-west module: Waiter until step 3, Mover, then Done
            assert history == ["Waiter", "Mover", "Done"] and dict(states)["step"] == 4
        else:  # north-south: Waiter until step 3, then no role holds
            assert history == ["Waiter", "none"] and role is None and dict(states)["step"] == 3


def test_too_many_stored_commands_are_a_warning():
    result = check_text(SIX)
    assert [d.code for d in result.diagnostics] == ["W602"]
    assert "which every module stores" in result.diagnostics[0].message
