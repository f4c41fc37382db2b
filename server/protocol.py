"""pygls's protocol, answering requests whose params cannot be read with InvalidParams.

pygls itself only logs such a message, and the client would wait for an answer forever.
"""

from __future__ import annotations

import logging
from typing import Any

from pygls.exceptions import JsonRpcException, JsonRpcInvalidParams
from pygls.protocol import LanguageServerProtocol

log = logging.getLogger("rdcd.server")


class RdcdProtocol(LanguageServerProtocol):
    def structure_message(self, data: dict[str, Any]):  # type: ignore[no-untyped-def]
        try:
            return super().structure_message(data)
        except JsonRpcException as error:
            if isinstance(data, dict) and "id" in data and "method" in data:
                answer = JsonRpcInvalidParams(f"invalid params for {data.get('method')}")
                if not isinstance(error, JsonRpcInvalidParams):
                    answer = error
                try:
                    self._send_response(data["id"], None, answer.to_response_error())
                except Exception:
                    log.exception("cannot answer a malformed request")
            raise
