"""The scope in which code is checked: a concrete role, the mixins assumed around the code."""

from __future__ import annotations

from dataclasses import dataclass, replace

from rdcd_core.fastinit import fast_init
from rdcd_core.semantics.context import Context
from rdcd_core.semantics.model import ConstantSymbol, MethodSymbol, RoleSymbol
from rdcd_core.syntax import ast


@fast_init
@dataclass(frozen=True, slots=True)
class Env:
    ctx: Context
    role: RoleSymbol  # the role the module plays: a concrete owner of the code, or its declarer
    home: RoleSymbol  # the role (or mixin) that declares the code: references resolve here
    mixins: tuple[RoleSymbol, ...] = ()  # assumed around the code, innermost last
    constant: str | None = None  # folding this constant's definition: no run-time calls
    method: ast.MethodDecl | None = None  # the enclosing method
    in_assume: bool = False
    in_handler: bool = False  # a handleEvent block: runs later, without the method's parameters

    def lookup_constant(self, name: str) -> tuple[ConstantSymbol | None, int]:
        """The constant and how many of the mixins hold it (-1: the base role; mixins shadow)."""
        for index in range(len(self.mixins) - 1, -1, -1):
            found = self.mixins[index].constants.get(name)
            if found is not None:
                return found, index
        return self.role.constants.get(name), -1

    def holder(self, depth: int, name: str) -> Env:
        """The scope in which the definition of constant ``name`` found at ``depth`` is folded."""
        return replace(self, mixins=self.mixins[:depth + 1], constant=name)

    def lookup_method(self, name: str) -> MethodSymbol | None:
        for mixin in reversed(self.mixins):
            found = mixin.methods.get(name)
            if found is not None:
                return found
        return self.role.methods.get(name)

    def home_target(self, name: str, table: str) -> str:
        """``Role.name`` of the declaration seen from the code's declaring role."""
        for scope in (*reversed(self.mixins), self.home, self.role):
            symbols = scope.constants if table == "constant" else scope.methods
            found = symbols.get(name)
            if found is not None:
                return f"{found.owner}.{name}"
        return f"{self.home.name}.{name}"

    def constant_names(self) -> list[str]:
        names = set(self.role.constants)
        for mixin in self.mixins:
            names.update(mixin.constants)
        return sorted(names)

    def method_names(self) -> list[str]:
        names = set(self.role.methods)
        for mixin in self.mixins:
            names.update(mixin.methods)
        return sorted(names)
