"""Handlers never take the server down: an exception is logged and the request gets an empty result."""

from __future__ import annotations

import functools
import inspect
import logging
from collections.abc import Callable
from typing import Any

from pygls.exceptions import JsonRpcException

log = logging.getLogger("rdcd.server")


class RequestFailed(JsonRpcException):
    """LSP's RequestFailed: the request was valid but cannot be carried out (e.g. a refused rename)."""

    CODE = -32803


def guarded(default: Any = None) -> Callable:
    def decorate(handler: Callable) -> Callable:
        if inspect.iscoroutinefunction(handler):  # a handler that awaits the document's check
            @functools.wraps(handler)
            async def waiting(ls: Any, params: Any) -> Any:
                try:
                    return await handler(ls, params)
                except JsonRpcException:
                    raise
                except Exception:
                    log.exception("%s failed", handler.__name__)
                    return default() if callable(default) else default

            return waiting

        @functools.wraps(handler)
        def wrapper(ls: Any, params: Any) -> Any:
            try:
                return handler(ls, params)
            except JsonRpcException:
                raise
            except Exception:
                log.exception("%s failed", handler.__name__)
                return default() if callable(default) else default

        return wrapper

    return decorate
