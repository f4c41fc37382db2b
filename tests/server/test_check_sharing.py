"""A request that joins the check of its document's text gets that check's analysis even when the
check has just finished and its done callback has not run yet (the race behind a rare empty
answer: semantic tokens of a freshly opened document came back empty once in CI)."""

from __future__ import annotations

import asyncio

from rdcd_core.ide.analysis import analyze
from server.app import create_server
from server.documents import Document

TEXT = "role Wheel { self.center_position == EAST_WEST; }\ndeployment { Wheel }\n"


def test_a_request_joining_a_check_done_before_its_callback_ran_gets_its_analysis() -> None:
    server = create_server()
    document = Document("file:///share/a.rdcd", 1, TEXT)

    async def scenario() -> object:
        loop = asyncio.get_running_loop()
        # a check of this version, finished, whose done callback is still queued on the loop
        finished = loop.create_future()
        finished.add_done_callback(lambda future: None)
        finished.set_result(analyze(TEXT))  # callbacks are scheduled, not run
        document.checking, document.checking_key, document.checking_text = finished, (1, "default"), TEXT
        return await server.analysis_of(document)  # no await yields before the answer

    found = asyncio.run(scenario())
    assert found is not None and found is document.analysis
    server.checker.shutdown(wait=False)


def test_a_check_of_an_older_version_is_not_taken_for_the_current_text() -> None:
    server = create_server()
    document = Document("file:///share/b.rdcd", 1, TEXT)

    async def scenario() -> object:
        loop = asyncio.get_running_loop()
        old = loop.create_future()
        old.set_result(analyze("role Old { }\ndeployment { Old }\n"))
        document.update(TEXT + "\n", 2)
        document.checking, document.checking_key, document.checking_text = old, (1, "default"), TEXT
        return await server.analysis_of(document)  # starts a check of version 2 instead

    found = asyncio.run(scenario())
    assert found is not None and found is document.analysis and "Old" not in found.model.roles
    server.checker.shutdown(wait=False)
