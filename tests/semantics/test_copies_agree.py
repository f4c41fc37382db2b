"""Tables the front end keeps beside their sources (rdcd_core may import only ``vm.isa`` from the
VM) agree with those sources."""

from __future__ import annotations

from rdcd_core.semantics.statespace import FACING
from rdcd_core.syntax.messages import TEXT
from rdcd_core.syntax.tables import tables
from vm import navigation


def test_facing_channels_equal_the_vms_navigation_table() -> None:
    assert len(FACING) == len(navigation.AXES) * 6
    for (axis, direction), channels in FACING.items():
        assert channels == navigation.channels_facing(axis, direction), (axis, direction)


def test_punctuation_shown_in_messages_is_the_grammars() -> None:
    assert TEXT == {name: text for text, name in tables().lexer.literals.items()}
