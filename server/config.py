"""Server settings: from the command line, the environment, the initialization options and workspace
configuration.

Accepted shapes: ``{"rdcd": {"inlayHints": {"fragmentSizes": false}}}``,
``{"inlayHints": {"fragmentSizes": false}}`` and the flat ``{"rdcd.inlayHints.fragmentSizes": false}``;
the same for ``diagnostics.debounceMs`` and ``target`` (``"default"`` or ``"original"``: what
programs are checked and compiled for, ``rdcd check --target``). A value that cannot be used is
reported and the setting keeps its value: an infinite or NaN debounce would mean a server that
never publishes.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

log = logging.getLogger("rdcd.server")

DEFAULT_DEBOUNCE_MS = 50.0
MAX_DEBOUNCE_MS = 10_000.0
DEBOUNCE_ENV = "RDCD_LSP_DEBOUNCE_MS"


class SettingError(ValueError):
    """A setting's value that cannot be used; the message is one line for the user."""


def parse_debounce(value: Any, source: str) -> float:
    """Milliseconds in [0, MAX_DEBOUNCE_MS] from a number or a numeric string."""
    number: Any = value
    if isinstance(value, str):
        try:
            number = float(value.strip())
        except ValueError:
            raise SettingError(f"{source}: {_show(value)} is not a number of milliseconds") from None
    if isinstance(number, bool) or not isinstance(number, (int, float)):
        raise SettingError(f"{source}: {_show(value)} is not a number of milliseconds")
    if isinstance(number, float) and not math.isfinite(number) or not 0 <= number <= MAX_DEBOUNCE_MS:
        raise SettingError(f"{source} must be between 0 and {MAX_DEBOUNCE_MS:g} milliseconds, "
                           f"not {_show(value)}")
    return float(number)


@dataclass
class Settings:
    debounce_ms: float = DEFAULT_DEBOUNCE_MS
    fragment_size_hints: bool = True
    target: str = "default"

    @classmethod
    def from_environment(cls, environ: Mapping[str, str]) -> tuple[Settings, list[str]]:
        """The settings and one line per unusable variable (its default is kept)."""
        settings, problems = cls(), []
        if DEBOUNCE_ENV in environ:
            try:
                settings.debounce_ms = parse_debounce(environ[DEBOUNCE_ENV], DEBOUNCE_ENV)
            except SettingError as error:
                problems.append(f"{error}; using {DEFAULT_DEBOUNCE_MS:g}")
        return settings, problems

    def update(self, options: Any) -> list[str]:
        """Takes what it can use from ``options``; logs and returns what it could not."""
        if not isinstance(options, dict):
            return []
        problems = []
        value = _lookup(options, "inlayHints.fragmentSizes")
        if isinstance(value, bool):
            self.fragment_size_hints = value
        elif value is not None:
            problems.append(f"rdcd.inlayHints.fragmentSizes must be true or false, not {_show(value)}")
        value = _lookup(options, "target")
        if value is not None:
            from rdcd_core.compiler import TARGETS  # the server reaches the VM only through rdcd_core

            if isinstance(value, str) and value in TARGETS:
                self.target = value
            else:
                problems.append(f"rdcd.target must be one of {', '.join(TARGETS)}, not {_show(value)}")
        value = _lookup(options, "diagnostics.debounceMs")
        if value is not None:
            try:
                self.debounce_ms = parse_debounce(value, "rdcd.diagnostics.debounceMs")
            except SettingError as error:
                problems.append(str(error))
        for problem in problems:
            log.warning("setting ignored: %s", problem)
        return problems


def _show(value: Any, limit: int = 40) -> str:
    try:
        text = repr(value)
    except ValueError:  # an integer of more than 4,300 digits
        text = "a huge number"
    return text if len(text) <= limit else text[:limit] + "…"


def _lookup(options: dict, dotted: str) -> Any:
    for root in (options, options.get("rdcd")):
        if not isinstance(root, dict):
            continue
        if "rdcd." + dotted in root:
            return root["rdcd." + dotted]
        if dotted in root:
            return root[dotted]
        node: Any = root
        for part in dotted.split("."):
            node = node.get(part) if isinstance(node, dict) else None
        if node is not None:
            return node
    return None
