"""The ``--replay OUT.html`` option of ``rdcd simulate``: kept here so the command stays small."""

from __future__ import annotations

import argparse
import os
from typing import Any

ACCEPTED = ["html", "htm"]


def add_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--replay", metavar="OUT.html",
                        help="write an interactive 3D replay of the run to this self-contained HTML file "
                             "(.html added if it has no extension)")


def new_recording(args: argparse.Namespace, program: Any, structure: Any) -> Any:
    """A Recording for ``options.recording`` when --replay is given, else None."""
    if getattr(args, "replay", None) is None:
        return None
    from rdcd_core.inputs import InputError, read_source
    from sim.replay.recording import Recording
    from sim.replay.sources import SourceIndex

    try:
        text = read_source(args.file)
    except InputError:
        text = ""  # it was read a moment ago to compile; the page then shows no source text
    return Recording(structure, SourceIndex(program, text), args.duration)


def write(args: argparse.Namespace, recording: Any, program: Any, structure: Any,
          report: dict[str, Any]) -> str:
    """Writes the page (OSError if it cannot); returns the line to print."""
    from sim.replay.page import write_page

    size = write_page(args.replay, recording, program, structure, report, os.path.basename(args.file))
    notes = "".join(f"\n  note: {n}" for n in recording.finish_notes())
    return f"replay: {args.replay} ({size / 1e6:.2f} MB){notes}"
