"""``gc_paused()``: the front end runs without the cyclic garbage collector.

Parsing and analysis allocate many small objects that live as long as the result and make no
garbage cycles: the collector would only scan them again and again (up to a third of the time on
large files). Reference counting still frees everything; cycles, if any, wait for the next full
collection after the pause.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def gc_paused() -> Iterator[None]:
    """Disables the cyclic collector inside the block (nested pauses are fine)."""
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if was_enabled:
            # What the block made mostly lives on (a tree, a model, a program): move it straight to
            # the oldest generation (freeze, then unfreeze: documented to do exactly that), or the
            # first young collection after the pause would scan each of its objects (a tenth of a
            # second after a 15,000-line check), and the next one again.
            gc.freeze()
            gc.unfreeze()
            gc.enable()
