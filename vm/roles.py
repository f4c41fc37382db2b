"""The role table the compiler emits and every module receives (docs/vm.md).

Role ids are 1..14; 0 is "no role"; 255 is "any" (every role, including none, is an instance).
``instance_of[r]`` is the set of role ids that role r is an instance of; r itself is always
included, whether or not the table lists it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

NO_ROLE = 0
ANY_ROLE = 255


@dataclass(frozen=True)
class RoleTable:
    names: dict[int, str] = field(default_factory=dict)
    instance_of: dict[int, frozenset[int]] = field(default_factory=dict)

    def is_instance(self, role: int, of: int) -> bool:
        """Whether a module whose role is ``role`` plays role ``of``."""
        if of == ANY_ROLE or role == of:
            return True
        return of in self.instance_of.get(role, frozenset())

    def roles_instance_of(self, of: int) -> list[int]:
        """Every known role id that is an instance of ``of`` (used by INSTALL_COMMAND); for "any",
        "no role" too: a command installed for any role runs on a module that has none."""
        known = set(self.names) | set(self.instance_of)
        if of not in (NO_ROLE, ANY_ROLE):
            known.add(of)
        found = sorted(r for r in known if r not in (NO_ROLE, ANY_ROLE) and self.is_instance(r, of))
        return [NO_ROLE, *found] if of == ANY_ROLE else found

    def name(self, role: int) -> str:
        if role == NO_ROLE:
            return "none"
        if role == ANY_ROLE:
            return "any"
        return self.names.get(role, f"role{role}")

    def to_json(self) -> dict[str, object]:
        return {"names": {str(k): v for k, v in self.names.items()},
                "instance_of": {str(k): sorted(v) for k, v in self.instance_of.items()}}

    @classmethod
    def from_json(cls, data: dict[str, object]) -> RoleTable:
        names = data.get("names", {})
        inst = data.get("instance_of", {})
        assert isinstance(names, dict) and isinstance(inst, dict)
        return cls({int(k): str(v) for k, v in names.items()},
                   {int(k): frozenset(int(x) for x in v) for k, v in inst.items()})
