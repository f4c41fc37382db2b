"""The planner's shortcuts are exact: the size bound it settles trials with is never below the
optimised size, the size it measures without source entries equals the laid-out size, and shared
tails are found as the pairwise search found them (issue 10: these replaced quadratic steps)."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from rdcd_core.compiler import compile_model
from rdcd_core.compiler.context import Context
from rdcd_core.compiler.entry import assign_command_numbers, entry_items
from rdcd_core.compiler.ir import Ins, Label
from rdcd_core.compiler.layout import assemble, laid_out_size, size_bound
from rdcd_core.compiler.peephole import optimise
from rdcd_core.compiler.roletable import build_role_table
from rdcd_core.compiler.tails import GOTO_SIZE, merge_tails
from rdcd_core.frontend import check_text
from tests.compiler.test_statements_property import body, program


@settings(max_examples=40, deadline=None)
@given(body, body, body)
def test_bound_and_measured_size_are_exact(startup: str, behaviour: str, command: str) -> None:
    result = check_text(program(startup, behaviour, command))
    if result.has_errors:
        return
    model = result.model
    table, commands = build_role_table(model), assign_command_numbers(model)
    for role in model.deployment:
        ctx = Context(model, table, role, command_numbers=commands)
        for item in entry_items(ctx, needs_role_check=True):
            bound = size_bound(item.code)
            optimised = optimise(item.code)
            assert laid_out_size(optimised) == len(assemble(optimised)[0])
            assert laid_out_size(optimised) <= bound
    compile_model(model)  # and the whole program still compiles


def _pairwise(code: list) -> list:
    """merge_tails as it was: every pair of ends compared (the reference)."""
    ends = [i for i, item in enumerate(code) if isinstance(item, Ins) and item.ends_flow]
    for later in reversed(ends):
        for earlier in ends:
            if earlier >= later:
                break
            length = 0
            while earlier - length >= 0 and later - length > earlier:
                x, y = code[earlier - length], code[later - length]
                if not (isinstance(x, Ins) and isinstance(y, Ins)) or x.key() != y.key():
                    break
                length += 1
            if length and sum(code[later - k].size for k in range(length)) > GOTO_SIZE:
                start = earlier - length + 1
                label = Label("tail")
                result = code[:start] + [label] + code[start:later - length + 1]
                result.append(Ins("GOTO", (label,), code[later].span))
                return result + code[later + 1:]
    return code


OPS = st.sampled_from([("SLEEP", ()), ("SET_LED", (1,)), ("SET_LED", (2,)), ("PUSH", (200,)),
                       ("END_TERMINATE", ()), ("END_REPEAT", ()), ("MIGRATE_CONTINUE", ()), ("label", ())])


@settings(max_examples=300, deadline=None)
@given(st.lists(OPS, max_size=40))
def test_shared_tails_match_the_pairwise_search(ops: list) -> None:
    code = [Label() if op == "label" else Ins(op, args) for op, args in ops]
    assert _shape(merge_tails(list(code))) == _shape(_pairwise(list(code)))


def _shape(code: list) -> list:
    """The code with each label named by where it first stands (new labels differ by identity)."""
    places = {}
    for index, item in enumerate(code):
        if isinstance(item, Label):
            places.setdefault(id(item), index)
    return [(item.op, tuple(places.get(id(a), a) if isinstance(a, Label) else a for a in item.args))
            if isinstance(item, Ins) else ("label", places[id(item)]) for item in code]
