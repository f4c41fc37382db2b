"""Rename of roles, constants and methods; refuses names that would clash or cannot be names."""

from __future__ import annotations

import re

from rdcd_core.diagnostics import TextEdit
from rdcd_core.ide.analysis import Analysis
from rdcd_core.ide.navigation import MEMBER_KINDS, member_chain, occurrences, split_target
from rdcd_core.module_api import SELF_PRIMITIVES
from rdcd_core.semantics.model import ROOT_ROLE
from rdcd_core.source import Span
from rdcd_core.syntax.keywords import KEYWORDS
from rdcd_core.types import PREDEFINED_VALUES

IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
RENAMABLE = ("role",) + MEMBER_KINDS


class RenameError(Exception):
    """The rename is refused; the message says why."""


def prepare_rename(analysis: Analysis, offset: int) -> Span | None:
    ref = analysis.reference_at(offset)
    if ref is None or ref.kind not in RENAMABLE or ref.target == ROOT_ROLE:
        return None
    return ref.name.span


def rename(analysis: Analysis, offset: int, new_name: str) -> list[TextEdit]:
    ref = analysis.reference_at(offset)
    model = analysis.model
    if model is None or ref is None or prepare_rename(analysis, offset) is None:
        raise RenameError("nothing to rename here: place the cursor on a role, constant or method")
    if not IDENTIFIER.match(new_name):
        raise RenameError(f"'{new_name}' is not a valid name")
    if new_name in KEYWORDS or new_name in PREDEFINED_VALUES or new_name == ROOT_ROLE:
        raise RenameError(f"'{new_name}' is reserved")
    if new_name == ref.name.text:
        return []
    found = occurrences(analysis, ref)
    if ref.kind == "role":
        if new_name in model.roles:
            raise RenameError(f"a role named '{new_name}' already exists")
    else:
        _check_member_clash(analysis, found, new_name, ref.kind == "constant")
    return [TextEdit(r.name.span, new_name) for r in found]


def _check_member_clash(analysis: Analysis, found: list, new_name: str, constant: bool) -> None:
    model = analysis.model
    assert model is not None
    owners = {split_target(r.target)[0] for r in found}
    affected: set[str] = set()
    for owner in owners:
        affected.update(member_chain(model, owner))
        affected.update(model.subroles(owner))
        affected.update(m for m in model.roles if model.roles[m].modifies in affected)
    for role in sorted(affected):
        symbol = model.roles.get(role)
        if symbol is None:
            continue
        if new_name in symbol.constants or new_name in symbol.methods:
            raise RenameError(f"role '{role}' already has a member named '{new_name}'")
    if not constant and new_name in SELF_PRIMITIVES:
        raise RenameError(f"'{new_name}' is a Module API primitive")
