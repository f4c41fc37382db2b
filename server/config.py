"""Server settings: from the command line, the initialization options and workspace configuration.

Accepted shapes: ``{"rdcd": {"inlayHints": {"fragmentSizes": false}}}``,
``{"inlayHints": {"fragmentSizes": false}}`` and the flat ``{"rdcd.inlayHints.fragmentSizes": false}``;
the same for ``diagnostics.debounceMs`` and ``target`` (``"default"`` or ``"original"``: what
programs are checked and compiled for, ``rdcd check --target``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

DEFAULT_DEBOUNCE_MS = 50


@dataclass
class Settings:
    debounce_ms: float = float(os.environ.get("RDCD_LSP_DEBOUNCE_MS", DEFAULT_DEBOUNCE_MS))
    fragment_size_hints: bool = True
    target: str = "default"

    def update(self, options: Any) -> None:
        if not isinstance(options, dict):
            return
        value = _lookup(options, "inlayHints.fragmentSizes")
        if isinstance(value, bool):
            self.fragment_size_hints = value
        value = _lookup(options, "target")
        if isinstance(value, str):
            from rdcd_core.compiler import TARGETS  # the server reaches the VM only through rdcd_core

            if value in TARGETS:
                self.target = value
        value = _lookup(options, "diagnostics.debounceMs")
        if isinstance(value, (int, float)) and not isinstance(value, bool) and value >= 0:
            self.debounce_ms = float(value)


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
