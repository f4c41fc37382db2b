"""pygls's protocol with JSON-RPC and the LSP life cycle enforced, and no tracebacks in answers.

What pygls leaves out and this adds: malformed JSON gets -32700 (id null); a message that is not a
JSON-RPC message gets -32600; a request whose params cannot be read gets -32602 instead of silence;
requests before ``initialize`` get -32002 and notifications then are dropped (``exit`` aside);
requests after ``shutdown`` get -32600; ``exit`` ends the server with 0 after ``shutdown`` and 1
without. Error answers carry a one-line message and never a Python traceback; refusals a handler
means (``RequestFailed``, a cancelled request) are logged on one line, real failures with their
traceback in the log only.
"""

from __future__ import annotations

import json
import logging
import re
from concurrent.futures import Future
from typing import Any

import cattrs
from lsprotocol import types
from pygls.exceptions import (
    JsonRpcException,
    JsonRpcInternalError,
    JsonRpcInvalidParams,
    JsonRpcInvalidRequest,
    JsonRpcParseError,
    JsonRpcRequestCancelled,
    JsonRpcServerNotInitialized,
)
from pygls.protocol import LanguageServerProtocol
from pygls.protocol.json_rpc import JsonRPCNotification, JsonRPCRequestMessage, JsonRPCResponseMessage

from server.framing import Problem

log = logging.getLogger("rdcd.server")


class RdcdProtocol(LanguageServerProtocol):
    def __init__(self, server: Any, converter: Any) -> None:
        super().__init__(server, converter)
        self.initialize_received = False
        self.exit_code: int | None = None

    @property
    def shut_down(self) -> bool:
        return self._shutdown

    # -- from bytes to a message ----------------------------------------------------------------
    def refuse_frame(self, problem: Problem) -> None:
        log.warning("bad input from the client: %s", problem.message)
        if problem.reply:
            kind = "Parse error" if problem.code == JsonRpcParseError.CODE else "Invalid request"
            self.refuse(None, problem.code, f"{kind}: {problem.message}")

    def receive_body(self, body: bytes) -> None:
        try:
            data = json.loads(body, parse_constant=_reject_constant)
        except (ValueError, RecursionError) as error:  # UnicodeDecodeError is a ValueError
            log.warning("malformed JSON from the client: %s", _one_line(error))
            self.refuse(None, JsonRpcParseError.CODE, f"Parse error: {_one_line(error)}")
            return
        self.receive(data)

    def receive(self, data: Any) -> None:
        """One JSON value from the client: checked, then handed to pygls (or answered here)."""
        if not isinstance(data, dict):
            self.refuse(None, JsonRpcInvalidRequest.CODE, "Invalid request: a message is a JSON object")
            return
        has_id, msg_id, method = "id" in data, data.get("id"), data.get("method")
        if not _is_id(msg_id):
            has_id, msg_id = has_id and msg_id is not None, None
            if has_id:
                self.refuse(None, JsonRpcInvalidRequest.CODE, "Invalid request: an id is a number or string")
                return
        if data.get("jsonrpc") != "2.0":
            self.refuse(msg_id, JsonRpcInvalidRequest.CODE, 'Invalid request: "jsonrpc" must be "2.0"')
            return
        if method is None:
            self._receive_response(data, has_id)
        elif not isinstance(method, str):
            self.refuse(msg_id, JsonRpcInvalidRequest.CODE, "Invalid request: the method is a string")
        elif self._admitted(method, msg_id if has_id else None, has_id):
            self._dispatch(data, method, msg_id if has_id else None, has_id)

    def _admitted(self, method: str, msg_id: Any, is_request: bool) -> bool:
        """The LSP life cycle: initialize first, nothing but exit after shutdown."""
        if method == types.EXIT:
            self.exit_code = 0 if self._shutdown else 1
            return False
        if self._shutdown:
            reason = (JsonRpcInvalidRequest.CODE, f"Invalid request: {method} after shutdown")
        elif not self.initialize_received and method != types.INITIALIZE:
            reason = (JsonRpcServerNotInitialized.CODE, f"the server is not initialized yet ({method})")
        elif self.initialize_received and method == types.INITIALIZE:
            reason = (JsonRpcInvalidRequest.CODE, "Invalid request: the server is already initialized")
        else:
            return True
        if is_request:
            self.refuse(msg_id, *reason)
        else:
            log.info("notification dropped: %s", reason[1])
        return False

    def _dispatch(self, data: dict, method: str, msg_id: Any, is_request: bool) -> None:
        message_type = self.get_message_type(method)
        if message_type is None:
            message_type = JsonRPCRequestMessage if is_request else JsonRPCNotification
        elif is_request != ("id" in {a.name for a in message_type.__attrs_attrs__}):
            kind = "a request" if not is_request else "a notification"
            if is_request:
                self.refuse(msg_id, JsonRpcInvalidRequest.CODE, f"Invalid request: {method} is {kind}")
            return
        try:
            message = self._converter.structure(data, message_type)
        except Exception as error:
            reason = f"invalid params for {method}: {_describe(error)}"
            log.info("%s", reason)
            if is_request:
                self.refuse(msg_id, JsonRpcInvalidParams.CODE, reason)
            return
        if method == types.INITIALIZE:
            self.initialize_received = True
        try:
            self.handle_message(message)
        except Exception:
            log.exception("handling %s failed", method)
            if is_request:
                self.refuse(msg_id, JsonRpcInternalError.CODE, f"internal error in {method}")

    def _receive_response(self, data: dict, has_id: bool) -> None:
        """An answer to one of our requests (progress tokens, refreshes)."""
        if not has_id:
            log.info("a message with neither method nor id dropped")
            return
        try:
            if "error" in data:
                message = self._converter.structure(data, types.ResponseErrorMessage)
            else:
                result_type = self._result_types.pop(data["id"], None) or JsonRPCResponseMessage
                message = self._converter.structure(data, result_type)
            self.handle_message(message)
        except Exception as error:
            log.info("unreadable answer from the client: %s", _describe(error))

    # -- answers --------------------------------------------------------------------------------
    def refuse(self, msg_id: Any, code: int, message: str) -> None:
        """An error answer; ``msg_id`` None gives ``"id": null`` as JSON-RPC wants when it is unknown."""
        self._send_data({"jsonrpc": "2.0", "id": msg_id, "error": {"code": code, "message": message}})

    def _send_response(self, msg_id: Any, result: Any = None, error: Any = None) -> None:
        if error is not None and error.data is not None:  # pygls puts tracebacks there
            error = types.ResponseError(code=error.code, message=error.message)
        super()._send_response(msg_id, result, error)

    def _send_handler_result(self, future: Future[Any], *, msg_id: Any) -> None:
        self._request_futures.pop(msg_id, None)
        if future.cancelled():
            log.info("request %s cancelled", msg_id)
            self.refuse(msg_id, JsonRpcRequestCancelled.CODE, "the request was cancelled")
            return
        error = future.exception()
        if error is None:
            self._send_response(msg_id, result=future.result())
        elif isinstance(error, JsonRpcException):  # a refusal the handler meant
            log.info("request %s refused: %s", msg_id, error.message)
            self.refuse(msg_id, error.code, error.message)
        else:
            log.error("request %s failed", msg_id, exc_info=error)
            self.refuse(msg_id, JsonRpcInternalError.CODE, f"internal error: {_one_line(error)}")

    def _check_handler_result(self, future: Future[Any]) -> None:
        if future.cancelled() or (error := future.exception()) is None:
            return
        if isinstance(error, JsonRpcException):
            log.info("notification refused: %s", error.message)
        else:
            log.error("a notification handler failed", exc_info=error)


def _is_id(value: Any) -> bool:
    return isinstance(value, str) or (isinstance(value, int) and not isinstance(value, bool))


def _reject_constant(name: str) -> Any:
    raise ValueError(f"{name} is not JSON")


def _one_line(error: BaseException) -> str:
    return _clip(" ".join(str(error).split()) or type(error).__name__)


def _clip(text: str, limit: int = 200) -> str:
    return text if len(text) <= limit else text[:limit] + "…"


def _describe(error: Exception) -> str:
    """cattrs's validation errors as ``required field missing @ $.params.textDocument``."""
    try:
        messages = cattrs.transform_error(error)
    except Exception:
        messages = [_one_line(error)]
    camel = [re.sub(r"_([a-z])", lambda m: m.group(1).upper(), m) for m in messages[:3]]
    return _clip(" ".join("; ".join(camel).split()))
