"""Commands held until their code is there (default target; docs/vm.md, "Commands before their code").

A command packet can reach a module before the fragment that installs the command's code, or
before the module has taken its role: a ``startup`` of the entry module that sends ``Wheel.go(2)``
runs as soon as its fragment arrives, while the wheels' fragments are still diffusing. The
firmware drops such a command; this project's VM holds it, at most ``MAX_HELD`` commands for at
most ``HOLD_S`` seconds each, and runs it as soon as the module plays a role the command is for
and the command's code is installed. A held command for a role the module then does not take is
forgotten silently (it was not for this module); one for its role whose code does not come in
time, or one more than ``MAX_HELD``, is a runtime error of the module (reported, never silent).
"""

from __future__ import annotations

from dataclasses import dataclass

MAX_HELD = 8  # commands a module holds at once
HOLD_S = 30.0  # seconds a command waits for its code (as long as a command id is remembered)


@dataclass(slots=True)
class Held:
    until: float  # simulated time at which it is given up
    role: int  # the role the command was sent to (a module playing an instance of it runs it)
    command: int
    arg: int


class HeldCommands:
    def __init__(self) -> None:
        self.items: list[Held] = []
        self.released = 0  # held commands that ran once their code was there (for reports)

    def __bool__(self) -> bool:
        return bool(self.items)

    def hold(self, now: float, role: int, command: int, arg: int) -> bool:
        """False when ``MAX_HELD`` commands wait already (the caller reports it)."""
        if len(self.items) >= MAX_HELD:
            return False
        self.items.append(Held(now + HOLD_S, role, command, arg))
        return True

    def take(self, ready) -> list[Held]:  # noqa: ANN001 - Callable[[Held], bool | None]
        """Removes and returns the commands ``ready`` says may run now (True); those it answers
        None for are forgotten (not for this module); the rest keep waiting."""
        run: list[Held] = []
        keep: list[Held] = []
        for held in self.items:
            answer = ready(held)
            if answer:
                run.append(held)
            elif answer is not None:
                keep.append(held)
        self.items = keep
        self.released += len(run)
        return run

    def expire(self, now: float) -> list[Held]:
        """Removes and returns the commands whose time is up."""
        gone = [h for h in self.items if now >= h.until]
        if gone:
            self.items = [h for h in self.items if now < h.until]
        return gone
