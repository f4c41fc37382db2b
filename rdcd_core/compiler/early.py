"""Commands sent before their code can be there (W606): a target that drops them.

A ``startup`` runs when its fragment reaches a module; a command it sends (``Wheel.go(2)``) floods
the structure at once. On the default target a module holds a command until its code is installed
(vm.runtime_hold), so the command arrives whatever the order. The original firmware drops a
command whose code is not installed: there the command is lost on every module whose role gets the
command's code from a fragment injected after the sending one (or from the same fragment, which
reaches the other modules after the command does). The firmware injects fragments 8 s apart, so a
command installed by an earlier fragment is there.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from rdcd_core import diagnostics as diag
from rdcd_core.compiler import codes
from rdcd_core.compiler.ir import Ins, Item
from rdcd_core.compiler.program import RoleEntry
from rdcd_core.source import Span


@dataclass(slots=True)
class Traffic:
    """The commands a fragment's own code sends (not its stored bodies, which run later) and the
    commands it installs, with the roles of the modules that run it."""

    sends: list[tuple[int, int, Span | None]] = field(default_factory=list)  # (role, command, span)
    installs: set[tuple[int, int]] = field(default_factory=set)  # (role, command)
    roles: set[int] = field(default_factory=set)


def traffic_of(code: list[Item], roles: set[int]) -> Traffic:
    found = Traffic(roles=roles)
    for item in code:
        if type(item) is not Ins:
            continue
        if item.op in ("SEND_COMMAND", "SEND_COMMAND_STACK_ARG"):
            found.sends.append((item.args[0], item.args[1], item.span))
        elif item.op == "INSTALL_COMMAND":
            found.installs.add((item.args[0], item.args[1]))
    return found


def early_commands(traffic: list[Traffic], entries: list[RoleEntry], target: str) -> list[diag.Diagnostic]:
    """W606 for each command a fragment sends to roles whose code for it comes later."""
    found: list[diag.Diagnostic] = []
    names = {e.id: e.name for e in entries}
    for index, fragment in enumerate(traffic):
        for role, command, span in fragment.sends:
            late = []
            for entry in entries:
                if role not in entry.instance_of:
                    continue
                installs = [i for i, t in enumerate(traffic)
                            if any(r in entry.instance_of and c == command for r, c in t.installs)]
                if not installs or installs[0] < index:
                    continue
                if installs[0] == index and entry.id in fragment.roles:
                    continue  # the sender installs it for itself first, in the same run
                late.append(entry.name)
            if late and span is not None:
                found.append(diag.make(
                    codes.EARLY_COMMAND, span,
                    f"on the {target} target this command reaches {', '.join(late)} before the fragment "
                    f"that installs its code, and the firmware drops a command it has no code for: send "
                    f"it from code that runs later (a behaviour, a handler, a command), or deploy "
                    f"{names.get(role, 'the receiving role')} before the role that sends it"))
    return found
