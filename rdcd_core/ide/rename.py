"""Rename of roles, constants, methods, states and parameters; refuses names that would clash or
cannot be names (a rename never changes what another name means)."""

from __future__ import annotations

import re

from rdcd_core.diagnostics import TextEdit
from rdcd_core.ide.analysis import Analysis
from rdcd_core.ide.navigation import MEMBER_KINDS, member_chain, occurrences, split_target
from rdcd_core.ide.states import parameter_info, state_symbol
from rdcd_core.module_api import FUNCTIONS, SELF_PRIMITIVES
from rdcd_core.semantics.model import ROOT_ROLE, Model
from rdcd_core.source import Span
from rdcd_core.syntax.keywords import KEYWORDS
from rdcd_core.types import PREDEFINED_VALUES

IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
RENAMABLE = ("role",) + MEMBER_KINDS + ("state", "parameter")


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
        raise RenameError("nothing to rename here: place the cursor on a role, constant, method, state "
                          "or parameter")
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
        if new_name in model.states or any(new_name in r.states for r in model.roles.values()):
            raise RenameError(f"a state named '{new_name}' exists: a role name would clash with it")
    elif ref.kind == "state":
        _check_state_clash(model, ref.target, new_name)
    elif ref.kind == "parameter":
        _check_parameter_clash(model, ref.target, new_name)
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
        if new_name in symbol.constants or new_name in symbol.methods or new_name in symbol.states:
            raise RenameError(f"role '{role}' already has a member named '{new_name}'")
        if constant:
            _check_parameters(model, [role], new_name)
    if constant and new_name in model.states:
        raise RenameError(f"a module state named '{new_name}' exists: the constant would hide it")
    if not constant and new_name in SELF_PRIMITIVES:
        raise RenameError(f"'{new_name}' is a Module API primitive")


def _family(model: Model, role: str) -> list[str]:
    """The roles whose code sees the members of ``role``: its chain, sub-roles and their mixins."""
    affected = set(member_chain(model, role)) | set(model.subroles(role))
    affected.update(m for m in model.roles if model.roles[m].modifies in affected)
    return sorted(affected)


def _check_parameters(model: Model, roles: list[str], new_name: str) -> None:
    """A parameter named ``new_name`` in these roles' methods would hide the renamed name."""
    for role in roles:
        symbol = model.roles.get(role)
        if symbol is None or symbol.decl is None:
            continue
        for member in symbol.decl.members:
            params = getattr(member, "params", ())
            if any(p.text == new_name for p in params):
                raise RenameError(f"'{member.name.text}' in role '{role}' has a parameter named "
                                  f"'{new_name}', which would hide it")


def _check_common(model: Model, new_name: str) -> None:
    if new_name in model.roles:
        raise RenameError(f"'{new_name}' is a role")
    if new_name in FUNCTIONS or new_name in SELF_PRIMITIVES:
        raise RenameError(f"'{new_name}' is a Module API function")


def _check_state_clash(model: Model, target: str, new_name: str) -> None:
    """Module state is seen by every role; role state by its role's family. Another constant,
    state or method of that name there, or a parameter, would change what a name means."""
    state = state_symbol(model, target)
    if state is None:
        raise RenameError("this state is not declared")
    _check_common(model, new_name)
    if new_name in model.states:
        raise RenameError(f"a module state named '{new_name}' already exists")
    roles = list(model.roles) if state.owner is None else _family(model, state.owner)
    for role in roles:
        symbol = model.roles.get(role)
        if symbol is None:
            continue
        if new_name in symbol.constants or new_name in symbol.methods or new_name in symbol.states:
            raise RenameError(f"role '{role}' already has a member named '{new_name}'")
    _check_parameters(model, roles, new_name)


def _check_parameter_clash(model: Model, target: str, new_name: str) -> None:
    info = parameter_info(model, target)
    if info is None:
        raise RenameError("this parameter is not declared")
    _check_common(model, new_name)
    if any(p.text == new_name for p in info.method.params):
        raise RenameError(f"'{info.method.name.text}' already has a parameter named '{new_name}'")
    hides = "module state" if new_name in model.states else None
    for role in member_chain(model, info.role):
        symbol = model.roles.get(role)
        if hides is None and symbol is not None and new_name in symbol.states:
            hides = "role state"
        if hides is None and symbol is not None and new_name in symbol.constants:
            hides = "constant"
    if hides is not None:
        raise RenameError(f"the parameter would hide the {hides} '{new_name}' in "
                          f"'{info.method.name.text}'")
