"""Garbage bytecode and garbage packets: the verifier, the disassembler and a module's runtime
never raise. Bytes that do not verify are rejected with a message; bytes that do run within the
module's limits (no internal error, slots and queue bounded). And the whole chain: mutated example
programs that check without errors compile to fragments that all verify."""

from __future__ import annotations

import pytest
from hypothesis import event, given, settings
from hypothesis import strategies as st
from vm_fakes import FakeHal

from rdcd_core.compiler import compile_model
from rdcd_core.frontend import check_text
from tests.syntax.fuzz_inputs import mutated_sources, spaced_tokens
from vm import navigation as nav
from vm.isa.assembler import assemble
from vm.isa.disassembler import boundaries, disassemble, reachable, to_text
from vm.isa.verifier import verify
from vm.packets import PacketError, decode, seal
from vm.roles import RoleTable
from vm.runtime import ModuleRuntime
from vm.runtime_store import QUEUE, SLOTS

ROLES = RoleTable({1: "A", 2: "B", 3: "C"}, {2: frozenset({1})})
SOURCES = mutated_sources()


def _compiled(text: str) -> list[bytes]:
    result = check_text(text)
    return [] if result.has_errors else [f.code for f in compile_model(result.model).fragments]


FRAGMENTS = [code for text in SOURCES for code in _compiled(text)]

edit = st.tuples(st.sampled_from(["set", "flip", "insert", "delete", "truncate"]),
                 st.integers(0, 200), st.integers(0, 255))


def _mutate(code: bytes, edits: list[tuple[str, int, int]]) -> bytes:
    out = bytearray(code)
    for kind, position, value in edits:
        if kind == "insert":
            out.insert(position % (len(out) + 1), value)
        elif not out:
            continue
        elif kind == "set":
            out[position % len(out)] = value
        elif kind == "flip":
            out[position % len(out)] ^= 1 << (value % 8)
        elif kind == "delete":
            del out[position % len(out)]
        else:
            del out[position % len(out):]
    return bytes(out)


garbage = st.one_of(
    st.binary(max_size=80),
    st.builds(_mutate, st.sampled_from(FRAGMENTS), st.lists(edit, min_size=1, max_size=4)))


def _tools_never_raise(code: bytes) -> list[str]:
    problems = verify(code)
    assert all(isinstance(p, str) and p and "\n" not in p for p in problems)
    verify(code, strict=True)
    verify(code, max_size=8)
    decoded = disassemble(code)
    assert sum(d.size if d.info else 1 for d in decoded) == len(code)
    reachable(code)
    assert len(code) in boundaries(code)
    to_text(code, with_offsets=True)
    assert assemble(to_text(code)) == code  # the listing reads back to the same bytes
    return problems


def _module(**options: object) -> tuple[FakeHal, ModuleRuntime]:
    hal = FakeHal(connected={0, 2, 5}, sensors=set())
    return hal, ModuleRuntime(hal, ROLES, module_id=3, **options)  # type: ignore[arg-type]


def _run(hal: FakeHal, vm: ModuleRuntime, steps: int = 25) -> None:
    for k in range(steps):
        hal.t += 0.5
        hal.turns += 0.3
        hal.sensors = {0, 3} if k % 4 == 1 else set()  # handlers fire and re-arm
        vm.step()
    assert not any("internal error" in message for _, message in vm.errors), vm.errors
    assert len(vm.store.slots) <= SLOTS and len(vm.store.tasks) <= QUEUE


def test_the_examples_give_fragments_to_mutate() -> None:
    assert len(FRAGMENTS) >= 5 and all(verify(code) == [] for code in FRAGMENTS)


@settings(max_examples=300, deadline=None)
@given(garbage)
def test_verifier_and_disassembler_never_raise(code: bytes) -> None:
    _tools_never_raise(code)


@settings(max_examples=150, deadline=None)
@given(garbage)
def test_injected_garbage_is_rejected_or_runs_safely(code: bytes) -> None:
    problems = _tools_never_raise(code)
    hal, vm = _module()
    vm.inject(code)
    if problems:
        assert any("rejected" in message for _, message in vm.errors), vm.errors
        assert vm.store.slots == []
    _run(hal, vm)


packet = st.one_of(
    st.binary(max_size=60),
    st.builds(lambda t, ident, pos, vch, body: bytes(
        [t, ident, pos[0] & 0xFF, pos[1] & 0xFF, pos[2] & 0xFF,
         nav.axis_for_position(*pos) or 1, vch]) + body,
        st.sampled_from([1, 1, 1, 2, 3, 4, 9]), st.integers(0, 255),
        st.tuples(*[st.integers(-3, 3)] * 3), st.integers(0, 9),
        st.one_of(st.binary(max_size=70), st.sampled_from(FRAGMENTS),
                  st.builds(_mutate, st.sampled_from(FRAGMENTS), st.lists(edit, max_size=3)))))


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.integers(-2, 10), packet), max_size=12), st.booleans(), st.booleans())
def test_received_garbage_never_raises(packets: list[tuple[int, bytes]], checksum: bool,
                                       injected: bool) -> None:
    hal, vm = _module(checksum=checksum)
    if injected:
        vm.inject(FRAGMENTS[0])
    for k, (channel, raw) in enumerate(packets):
        assert not isinstance(decode(raw), Exception)
        vm.receive(channel, seal(raw) if checksum and k % 3 else raw)
        if k % 4 == 3:
            _run(hal, vm, steps=2)
    _run(hal, vm)


NON_BYTES: list[object] = [10**12, -1, None, "text", [300], [1, 2], 3.5, object(), b"",
                           bytearray(b"\x0d")]


def test_non_bytes_never_raise() -> None:
    """What a buggy world might hand over: never an exception, never 10**12 zero bytes."""
    hal, vm = _module()
    for thing in NON_BYTES:
        assert isinstance(verify(thing), list)  # type: ignore[arg-type]
        assert isinstance(decode(thing), PacketError)  # type: ignore[arg-type]
        vm.receive(0, thing)  # type: ignore[arg-type]
        vm.receive(thing, b"\x03\x01\x00\x00\x00\x01\x00\x01")  # type: ignore[arg-type]
        vm.inject(thing)  # type: ignore[arg-type]
    vm.receive(float("inf"), b"\x03")  # type: ignore[arg-type]
    vm.receive(float("nan"), b"\x03")  # type: ignore[arg-type]
    _run(hal, vm)


# ------------------------------------------------------------------ the whole chain

TOKENS = [spaced_tokens(text) for text in SOURCES]
WORDS = sorted({t for tokens in TOKENS for t in tokens if not t.isspace()} | {
    "-129", "-128", "-1", "0", "1", "7", "8", "9", "63", "64", "127", "128", "255", "==", "!=",
    "<=", ">=", "&&", "||", "!", "+", "-", "{", "}", "(", ")", ";", ",", "self", "assumeRole",
    "handleEvent", "sleep", "setLed", "turnTowards", "turnDegrees", "sleepWhileTurning", "x", "y",
    "z", "sizeof", "connected_role", "connected", "total_connected", "EVENT_PROXIMITY_5", "UP"})
token_edit = st.tuples(st.sampled_from(["replace", "delete", "insert", "copy", "number", "number"]),
                       st.integers(0, 10_000), st.integers(1, 30), st.sampled_from(WORDS))


def _mutate_program(tokens: list[str], edits: list[tuple[str, int, int, str]]) -> str:
    tokens = list(tokens)
    for kind, position, length, word in edits:
        if not tokens:
            break
        i = position % len(tokens)
        if kind == "replace":
            tokens[i] = word
        elif kind == "number":  # most programs stay valid: the compiler gets to work
            numbers = [k for k, token in enumerate(tokens) if token.isdigit()]
            if numbers:
                tokens[numbers[position % len(numbers)]] = str(length * 5 - 10)
        elif kind == "delete":
            del tokens[i:i + length % 6 + 1]
        elif kind == "insert":
            tokens.insert(i, f" {word} ")
        else:  # copy a run of tokens elsewhere: duplicated members, statements, roles
            j = (position * 7 + length) % len(tokens)
            tokens[i:i] = tokens[j:j + length]
    return "".join(tokens)


@settings(max_examples=100, deadline=None)
@given(st.integers(0, len(SOURCES) - 1), st.lists(token_edit, min_size=1, max_size=3),
       st.sampled_from([8, 20, 50, 71, 100]), st.booleans())
def test_mutated_programs_compile_to_fragments_that_verify(which: int, edits: list, budget: int,
                                                           strict: bool) -> None:
    text = _mutate_program(TOKENS[which], edits)
    result = check_text(text, packet_budget=budget)
    codes = {d.code for d in result.diagnostics}
    assert "E100" not in codes and "E607" not in codes, result.diagnostics
    event("checked without errors" if not result.has_errors else "errors")
    if result.has_errors:
        return
    program = compile_model(result.model, packet_budget=budget, strict_isa=strict, text=text)
    assert "E607" not in {d.code for d in program.diagnostics}, program.diagnostics
    for fragment in program.fragments:
        if not any(d.severity.label == "error" for d in program.diagnostics):
            assert verify(fragment.code, strict=strict) == [], (fragment.name, text)
        _tools_never_raise(fragment.code)


@pytest.mark.parametrize("budget", [71, 72, 100, 10**6])
def test_packets_larger_than_a_slot_still_give_fragments_that_fit_it(budget: int) -> None:
    """A packet budget beyond 71 bytes used to plan fragments over the 64-byte slot (E607)."""
    for text in SOURCES[:2]:
        result = check_text(text, packet_budget=budget)
        assert not result.has_errors, result.diagnostics
        program = compile_model(result.model, packet_budget=budget)
        assert program.diagnostics == [] or all(d.code != "E607" for d in program.diagnostics)
        assert all(verify(f.code) == [] and len(f.code) <= 64 for f in program.fragments)
