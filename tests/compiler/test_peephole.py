"""The peephole optimiser on hand-built code."""

from __future__ import annotations

from rdcd_core.compiler.ir import Body, Ins, Label
from rdcd_core.compiler.layout import assemble
from rdcd_core.compiler.peephole import optimise


def ops(code):
    return [(i.op, i.args) if isinstance(i, Ins) else "label" for i in code]


def names(code):
    return [i.op for i in code if isinstance(i, Ins)]


def test_goto_to_migrate_becomes_migrate_and_goto_next_disappears():
    mig = Label()
    code = [Ins("COORD_X"), Ins("IF_FALSE_GOTO", (mig,)), Ins("SET_ROLE_NOTIFY", (1,)),
            Ins("GOTO", (mig,)), mig, Ins("MIGRATE_CONTINUE")]
    assert names(optimise(code)) == ["COORD_X", "IF_FALSE_GOTO", "SET_ROLE_NOTIFY", "MIGRATE_CONTINUE"]


def test_jump_threading_through_goto():
    a, b = Label(), Label()
    code = [Ins("COORD_X"), Ins("IF_FALSE_GOTO", (a,)), Ins("SLEEP"), Ins("END_TERMINATE"),
            a, Ins("GOTO", (b,)), Ins("SLEEP"), b, Ins("SET_LED", (1,)), Ins("END_TERMINATE")]
    result = optimise(code)
    branch = next(i for i in result if isinstance(i, Ins) and i.op == "IF_FALSE_GOTO")
    after = result[result.index(branch.args[0]) + 1]
    assert after.op == "SET_LED"
    assert names(result).count("SLEEP") == 1  # the SLEEP after the GOTO was dead
    assert "GOTO" not in names(result)


def test_dead_code_after_end():
    code = [Ins("SLEEP"), Ins("END_REPEAT"), Ins("SET_LED", (1,)), Ins("MIGRATE_CONTINUE")]
    assert names(optimise(code)) == ["SLEEP", "END_REPEAT"]


def test_fused_instructions():
    t = Label()
    code = [Ins("CONNECTED_DIR", (8,)), Ins("SIZEOF"), Ins("EQUALS_0"), Ins("IF_FALSE_GOTO", (t,)),
            Ins("COORD_Y"), Ins("PUSH", (0,)), Ins("GREATER"), Ins("IF_FALSE_GOTO", (t,)),
            Ins("PUSH", (2,)), Ins("COORD_X"), Ins("GREATER"), Ins("IF_FALSE_GOTO", (t,)),
            Ins("CONNECTED_ROLE", (9, 4)), Ins("IF_FALSE_GOTO", (t,)),
            Ins("PUSH", (3,)), Ins("EQUALS"), Ins("IF_FALSE_GOTO", (t,)), Ins("SLEEP"),
            t, Ins("MIGRATE_CONTINUE")]
    assert names(optimise(code)) == [
        "CONNECTED_DIR_SIZEOF", "IF_TRUE_GOTO", "PUSH", "COORD_Y_GREATER", "IF_FALSE_GOTO",
        "PUSH", "COORD_X_LESSER", "IF_FALSE_GOTO", "CONNECTED_DOWN_ROLE", "IF_FALSE_GOTO",
        "EQUALS_3", "IF_FALSE_GOTO", "SLEEP", "MIGRATE_CONTINUE"]


def test_conditional_jump_over_goto_is_inverted():
    a, b = Label(), Label()
    code = [Ins("COORD_X"), Ins("IF_FALSE_GOTO", (a,)), Ins("GOTO", (b,)), a, Ins("SLEEP"),
            b, Ins("END_TERMINATE")]
    assert names(optimise(code)) == ["COORD_X", "IF_TRUE_GOTO", "SLEEP", "END_TERMINATE"]


def test_shared_tails_are_merged():
    a = Label()
    tail = [Ins("EVAL_COMMAND", (5, 0)), Ins("SET_LED", (3,)), Ins("END_REPEAT")]
    code = [Ins("COORD_X"), Ins("IF_FALSE_GOTO", (a,)), Ins("SLEEP"), *tail, a,
            *[Ins(i.op, i.args) for i in tail]]
    before = len(assemble(code)[0])
    result = optimise(code)
    assert names(result).count("EVAL_COMMAND") == 1
    assert len(assemble(result)[0]) < before


def test_bodies_are_optimised_and_laid_out_after_the_code():
    end = Label()
    body = Body([Ins("SLEEP"), Ins("GOTO", (end,)), Ins("SET_LED", (1,)), end, Ins("END_TERMINATE")])
    code = [Ins("HANDLE_EVENT", (3, body)), Ins("MIGRATE_CONTINUE")]
    blob, _ = assemble(optimise(code))
    assert blob == bytes([30, 3, 5, 2, 18, 43, 13])


def test_identical_bodies_share_one_range():
    first = Body([Ins("SET_LED", (7,)), Ins("END_TERMINATE")])
    second = Body([Ins("SET_LED", (7,)), Ins("END_TERMINATE")])
    code = [Ins("INSTALL_COMMAND", (1, 128, first)), Ins("INSTALL_COMMAND", (2, 128, second)),
            Ins("MIGRATE_CONTINUE")]
    blob, _ = assemble(code)
    assert blob == bytes([42, 1, 128, 11, 3, 42, 2, 128, 11, 3, 18, 55, 7, 13])


def test_jumps_inside_a_body_are_relative_to_its_start():
    skip = Label()
    body = Body([Ins("COORD_X"), Ins("IF_FALSE_GOTO", (skip,)), Ins("SLEEP"), skip, Ins("END_REPEAT")])
    blob, _ = assemble([Ins("INSTALL_COMMAND", (1, 128, body)), Ins("MIGRATE_CONTINUE")])
    assert blob[6:] == bytes([19, 15, 4, 43, 14])
