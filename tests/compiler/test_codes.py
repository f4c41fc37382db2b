"""Every compiler code's documented example triggers it (the backstops excepted)."""

from __future__ import annotations

from rdcd_core.compiler import codes, compile_model
from rdcd_core.diagnostics import code_info
from rdcd_core.frontend import check_text

BACKSTOPS = {"E604", "E606", "E607"}  # the checker reports these programs first


def test_examples_trigger_their_code():
    for code in ("E601", "E603", "W601", "W602", "W603"):
        found = [d.code for d in check_text(code_info(code).example).diagnostics]
        assert code in found, (code, found)


def test_strict_isa_example():
    result = check_text(code_info(codes.EXT_REFUSED).example)
    assert not result.has_errors
    assert {d.code for d in compile_model(result.model, strict_isa=True).diagnostics} == {"E605"}
    assert {d.code for d in compile_model(result.model, target="original").diagnostics} == {"E605"}
    assert compile_model(result.model).diagnostics == []  # the default target has ADD


def test_target_examples_trigger_their_code():
    for code, target in (("E605", "original"), ("E608", "default"), ("W604", "original"),
                         ("W605", "original")):
        found = [d.code for d in check_text(code_info(code).example, target=target).diagnostics]
        assert code in found, (code, found)
    for code in ("W604", "W605"):
        assert code not in [d.code for d in check_text(code_info(code).example).diagnostics]


def test_backstop_examples_are_rejected_by_the_checker_first():
    for code in BACKSTOPS - {"E607"}:
        assert check_text(code_info(code).example).has_errors, code
