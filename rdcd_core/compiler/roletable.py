"""The role table of docs/vm.md: ids 1..14 and the instance-of relation.

Order of ids: deployed concrete roles (deployment order); roles observed at run time that are
not deployed (``connected_role`` targets, command targets); mixins that are observed; one id per
application of a mixin named in ``assumeRole`` to a deployed concrete role it can modify.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rdcd_core.compiler.program import RoleEntry
from rdcd_core.semantics.model import Model, RoleKind
from rdcd_core.semantics.walk import code_nodes
from rdcd_core.syntax import ast


def application_name(mixin: str, role: str) -> str:
    return f"{mixin}@{role}"


@dataclass(slots=True)
class RoleTable:
    entries: list[RoleEntry] = field(default_factory=list)
    ids: dict[str, int] = field(default_factory=dict)

    def id_of(self, name: str) -> int | None:
        return self.ids.get(name)

    def add(self, name: str, kind: str) -> None:
        if name not in self.ids:
            self.ids[name] = len(self.ids) + 1
            self.entries.append(RoleEntry(self.ids[name], name, kind, []))


def _method_bodies(model: Model) -> list[ast.Node]:
    """Every invariant and method body once (after copy-down, inherited ones repeat per role)."""
    nodes: dict[int, ast.Node] = {}
    for symbol in model.roles.values():
        for inv in symbol.invariants:
            nodes.setdefault(id(inv.decl.expr), inv.decl.expr)
        for method in symbol.methods.values():
            if method.decl.body is not None:
                nodes.setdefault(id(method.decl.body), method.decl.body)
    return list(nodes.values())


def scan_roles(model: Model) -> tuple[list[str], list[str]]:
    """Roles observed at run time, and mixins named in ``assumeRole``, in source order."""
    observed: list[str] = []
    assumed: list[str] = []
    for root in _method_bodies(model):
        for node in code_nodes(root):
            if isinstance(node, ast.GlobalCall):
                observed.append(node.role.text)
            elif isinstance(node, ast.FunctionCall) and node.name.text == "connected_role":
                if len(node.args) == 2 and isinstance(ast.unparen(node.args[1]), ast.NameRef):
                    observed.append(ast.unparen(node.args[1]).name.text)
            elif isinstance(node, ast.SelfCall) and node.name.text == "assumeRole" and node.args:
                first = ast.unparen(node.args[0])
                if isinstance(first, ast.NameRef):
                    assumed.append(first.name.text)
    known = model.roles
    return ([r for r in dict.fromkeys(observed) if r in known],
            [r for r in dict.fromkeys(assumed) if r in known and known[r].is_mixin])


def build_role_table(model: Model) -> RoleTable:
    table = RoleTable()
    for name in model.deployment:
        table.add(name, "concrete")
    observed, assumed = scan_roles(model)
    for name in observed:
        if not model.roles[name].is_mixin:
            table.add(name, model.roles[name].kind.value)
    for name in observed:  # a mixin needs an id of its own only if it is observed
        if model.roles[name].is_mixin:
            table.add(name, RoleKind.MIXIN.value)
    for mixin in assumed:
        for role in model.deployment:
            if mixin in model.mixins_of(role):
                table.add(application_name(mixin, role), "application")
    _fill_instance_of(model, table)
    return table


def _fill_instance_of(model: Model, table: RoleTable) -> None:
    for entry in table.entries:
        if entry.kind == "application":
            mixin, role = entry.name.split("@", 1)
            names = [entry.name, mixin, *model.ancestors(role)]
        elif entry.kind == RoleKind.MIXIN.value:
            names = [entry.name]
        else:
            names = model.ancestors(entry.name)
        entry.instance_of.extend(table.ids[n] for n in names if n in table.ids)
