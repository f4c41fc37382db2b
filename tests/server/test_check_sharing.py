"""A request that joins the check of its document's text gets that check's analysis even when the
check has just finished and its done callback has not run yet (the race behind a rare empty
answer: semantic tokens of a freshly opened document came back empty once in CI)."""

from __future__ import annotations

import asyncio

from rdcd_core.ide.analysis import analyze
from server.app import create_server
from server.documents import Document

TEXT = "role Wheel { self.center_position == EAST_WEST; }\ndeployment { Wheel }\n"


def _joined(document: Document, checked_text: str, edit: str | None = None) -> object:
    """What ``analysis_of`` answers for ``document`` (edited to ``edit`` as version 2 first, if
    given) while the document's check is a finished check of version 1 with ``checked_text``'s
    analysis whose done callbacks are queued on the loop, not run."""
    server = create_server()

    async def scenario() -> object:
        finished = asyncio.get_running_loop().create_future()
        finished.add_done_callback(lambda future: None)
        finished.set_result(analyze(checked_text))  # callbacks are scheduled, not run
        if edit is not None:
            document.update(edit, 2)
        document.checking, document.checking_key, document.checking_text = finished, (1, "default"), TEXT
        return await server.analysis_of(document)

    try:
        return asyncio.run(scenario())
    finally:
        server.checker.shutdown(wait=False)


def test_a_request_joining_a_check_done_before_its_callback_ran_gets_its_analysis() -> None:
    document = Document("file:///share/a.rdcd", 1, TEXT)
    found = _joined(document, TEXT)  # no await yields before the answer
    assert found is not None and found is document.analysis


def test_a_check_of_an_older_version_is_not_taken_for_the_current_text() -> None:
    document = Document("file:///share/b.rdcd", 1, TEXT)
    found = _joined(document, "role Old { }\ndeployment { Old }\n", edit=TEXT + "\n")  # checks v2
    assert found is not None and found is document.analysis and "Old" not in found.model.roles
