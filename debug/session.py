"""The DAP requests (one handler each) over one ``debug.channel.Channel``, and what the world's
thread says (``debug.engine.Sink``) turned into events.

Modules are threads (thread id = module id + 1: ids stay the same for the whole session, names
follow the roles); frames, scopes and variables references are numbered afresh at every stop and
forgotten when the world moves on.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from typing import Any

from debug.channel import Channel
from debug.code import ADDRESS_STRIDE, CodeIndex
from debug.engine import EXCEPTION_FILTERS, RUNTIME, Breakpoint, Engine, Goal, Scan, Sink, Step, Stop
from debug.expr import ExprError, parse
from debug.inspect import Inspector, names, thread_name
from debug.launch import Launch, LaunchError, prepare
from vm.isa.disassembler import decode_at

MAX_VARIABLES = 10_000
MAX_INSTRUCTIONS = 10_000
MOMENT_EVENT = "rdcd/moment"  # a custom event (DAP allows them) after each stopped event


class RequestError(Exception):
    pass


class Session(Sink):
    def __init__(self, channel: Channel) -> None:
        self.channel = channel
        self.launch: Launch | None = None
        self.code: CodeIndex | None = None
        self.engine: Engine | None = None
        self.inspector: Inspector | None = None
        self.done = False
        self._next_bp = 0
        self._line_bps: dict[str, list[tuple[Breakpoint, list[tuple[int, int]]]]] = {}
        self._function_bps: list[tuple[Breakpoint, list[tuple[int, int]]]] = []
        self._frames: dict[int, tuple[int, bytes | None, int | None, Any]] = {}
        self._refs: dict[int, Any] = {}
        self._configured = False
        self._run: dict[str, Any] | None = None
        self._handlers: dict[str, Callable[[dict[str, Any]], dict[str, Any] | None]] = {
            name[3:]: getattr(self, name) for name in dir(self) if name.startswith("on_")}

    # ---- the loop --------------------------------------------------------------------------
    def serve(self) -> None:
        try:
            for message in self.channel.messages():
                if isinstance(message, str):
                    self.output(f"rdcd dap: ignored {message}\n", "stderr")
                    continue
                self.handle(message)
                if self.done:
                    break
        finally:
            if self.engine is not None:
                self.engine.terminate()

    def handle(self, message: dict[str, Any]) -> None:
        command = message.get("command")
        if message.get("type") != "request" or not isinstance(command, str) \
                or not isinstance(message.get("seq"), int):
            seq = message.get("seq")
            if isinstance(seq, int) and not isinstance(seq, bool) and seq >= 1 and isinstance(command, str):
                self.channel.fail(message, "not a request: a request has type \"request\"")
            else:  # nothing to answer to: said on the console
                self.output("rdcd dap: ignored a message that is not a request (a request has type "
                            "\"request\", an integer seq and a command)\n", "stderr")
            return
        args = message.get("arguments", {})
        if args is None:
            args = {}
        handler = self._handlers.get(command)
        if handler is None:
            self.channel.fail(message, f"'{command}' is not supported by rdcd dap")
            return
        if not isinstance(args, dict):
            self.channel.fail(message, f"{command}: the arguments must be an object")
            return
        try:
            body = handler(args)
        except RequestError as e:
            self.channel.fail(message, str(e))
            return
        except LaunchError as e:
            for d in e.diagnostics:
                self.channel.event("output", {"category": "stderr", "output": d["text"], "line": d["line"],
                                              "column": d["column"], "source": {
                                                  "name": os.path.basename(d["path"]), "path": d["path"]}})
            self.channel.fail(message, str(e))
            return
        except Exception as e:  # a bug: answered, not a dead adapter
            self.channel.fail(message, f"{command} failed: {type(e).__name__}: {e}")
            return
        self.channel.respond(message, body)
        after = getattr(self, f"after_{command}", None)
        if after is not None:
            after(args)

    # ---- Sink (the world's thread) ---------------------------------------------------------
    def stopped(self, stop: Stop) -> None:
        what = {"entry": "at the start", "step": "after a step", "pause": "paused",
                "exception": stop.text or "exception"}.get(stop.reason, stop.reason)
        body: dict[str, Any] = {"reason": stop.reason, "description": f"{what} at t = {stop.time:.3f} s",
                                "threadId": self._first_thread() if stop.module is None else stop.module + 1,
                                "allThreadsStopped": True, "preserveFocusHint": False}
        if stop.hit_ids:
            body["hitBreakpointIds"] = list(stop.hit_ids)
        if stop.text:
            body["text"] = stop.text
        self.channel.event("stopped", body)
        # for the editor's replay panel: the same moment in a replay of a run with the same options
        # (the simulation is deterministic), with the module the stop is on (None: no module)
        self.channel.event(MOMENT_EVENT, {"t": stop.time, "module": stop.module, "run": self._run_options()})

    def _run_options(self) -> dict[str, Any]:
        """The launch's run as a report names it, and the SHA-256 of the program text it runs."""
        if self._run is None:
            import hashlib

            from sim.report import run_options
            launch = self.launch
            assert launch is not None  # a stop comes only after a launch
            self._run = {**run_options(launch.program, launch.structure, launch.options),
                         "source_sha256": hashlib.sha256(launch.text.encode("utf-8")).hexdigest()}
        return self._run

    def output(self, text: str, category: str = "console", line: int = 0) -> None:
        self._console(text, category, line)

    def ended(self, run: Any) -> None:
        from sim.report import build_report, summary

        try:
            launch = self.launch
            report = build_report(launch.program, run.structure, run.roles,  # type: ignore[union-attr]
                                  launch.options, run.finish(), 0.0,  # type: ignore[union-attr]
                                  start=launch.structure)  # type: ignore[union-attr]
            self._console(summary(report) + "\n", "console")
        except Exception as e:  # the summary is a courtesy: the end is still said
            self._console(f"the run ended (no summary: {type(e).__name__}: {e})\n", "stderr")
        self.channel.event("exited", {"exitCode": 0})
        self.channel.event("terminated")

    def failed(self, message: str) -> None:
        self._console(message + "\n", "stderr")
        self.channel.event("exited", {"exitCode": 1})
        self.channel.event("terminated")

    def _console(self, text: str, category: str, line: int = 0, column: int = 0) -> None:
        body: dict[str, Any] = {"category": category, "output": text}
        if line and self.launch is not None:
            body.update({"source": self._source(), "line": line, "column": max(1, column)})
        self.channel.event("output", body)

    # ---- lifecycle -------------------------------------------------------------------------
    def on_initialize(self, args: dict[str, Any]) -> dict[str, Any]:
        return {
            "supportsConfigurationDoneRequest": True,
            "supportsFunctionBreakpoints": True,
            "supportsConditionalBreakpoints": True,
            "supportsHitConditionalBreakpoints": True,
            "supportsEvaluateForHovers": True,
            "exceptionBreakpointFilters": [{"filter": k, "label": v, "default": False}
                                           for k, v in EXCEPTION_FILTERS.items()],
            "supportsStepBack": True,
            "supportsSteppingGranularity": True,
            "supportsDisassembleRequest": True,
            "supportsLogPoints": True,
            "supportsTerminateRequest": True,
            "supportTerminateDebuggee": True,
            "supportsExceptionInfoRequest": True,
            "supportsSetVariable": False,
            "supportsRestartRequest": False,
            "supportsInstructionBreakpoints": False,
        }

    def on_launch(self, args: dict[str, Any]) -> None:
        if self.launch is not None:
            raise RequestError("launch: this session has already launched a program")
        launch = prepare(args)
        self.launch = launch
        self.code = CodeIndex(launch.program, launch.methods)
        self.inspector = Inspector(self.code)
        self.engine = Engine(launch.program, launch.structure, launch.options, self.code, self, names)
        return None

    def after_launch(self, args: dict[str, Any]) -> None:
        self.channel.event("initialized")

    def on_attach(self, args: dict[str, Any]) -> None:
        raise RequestError("attach: rdcd dap runs its own simulation; use launch")

    def on_configurationDone(self, args: dict[str, Any]) -> None:  # noqa: N802 - DAP's name
        if self.engine is None:
            raise RequestError("configurationDone: launch a program first")
        if self._configured:
            raise RequestError("configurationDone: already done")
        self._configured = True
        return None

    def after_configurationDone(self, args: dict[str, Any]) -> None:  # noqa: N802
        assert self.engine is not None and self.launch is not None
        self.engine.start(self.launch.stop_on_entry)

    def on_disconnect(self, args: dict[str, Any]) -> None:
        if self.engine is not None:
            self.engine.terminate()
        self.done = True

    def on_terminate(self, args: dict[str, Any]) -> None:
        if self.engine is not None:
            self.engine.terminate()
        return None

    def after_terminate(self, args: dict[str, Any]) -> None:
        self.channel.event("terminated")

    # ---- threads, frames, variables --------------------------------------------------------
    def _first_thread(self) -> int:
        return min(self.launch.structure.modules) + 1 if self.launch else 1

    def on_threads(self, args: dict[str, Any]) -> dict[str, Any]:
        if self.launch is None:
            return {"threads": []}
        run = self.engine.run if self.engine is not None else None
        threads = []
        for mid in sorted(self.launch.structure.modules):
            if run is not None and mid in run.runtimes:
                name = thread_name(run.runtimes[mid], self.launch.structure)
            else:
                position = self.launch.structure.modules[mid].position
                name = f"module {mid} ({', '.join(map(str, position))})"
            threads.append({"id": mid + 1, "name": name})
        return {"threads": threads}

    def _stopped(self, what: str) -> Stop:
        engine = self.engine
        if engine is None or engine.run is None:
            raise RequestError(f"{what}: nothing is running")
        stop = engine.stop
        if stop is None and engine.ended:
            raise RequestError(f"{what}: the run has ended")
        if stop is None:
            raise RequestError(f"{what}: the world is running; pause it first")
        return stop

    def _runtime(self, thread: Any, what: str) -> Any:
        self._stopped(what)
        if isinstance(thread, bool) or not isinstance(thread, int):
            raise RequestError(f"{what}: threadId must be an integer")
        runtimes = self.engine.run.runtimes  # type: ignore[union-attr]
        if thread - 1 not in runtimes:
            raise RequestError(f"{what}: there is no thread {thread} (threads are modules: "
                               f"{min(runtimes) + 1}..{max(runtimes) + 1})")
        return runtimes[thread - 1]

    def _module_frames(self, runtime: Any, stop: Stop) -> list[tuple[str, bytes | None, int | None, Any]]:
        frames: list[tuple[str, bytes | None, int | None, Any]] = []
        top = None
        if stop.module == runtime.module_id:
            if stop.frame is not None:
                top = stop.frame
                frames.append((self._frame_name(runtime, stop.frame.code, stop.frame.pc, stop.frame),
                               stop.frame.code, stop.frame.pc, stop.frame))
            elif stop.code is not None:
                frames.append((f"{self._method(stop.code, stop.pc or 0)} [error]", stop.code, stop.pc, None))
        for task in runtime.store.tasks:
            if task.frame is not None and task.frame is not top:
                name = self._frame_name(runtime, task.frame.code, task.frame.pc, task.frame) + " (waiting)"
                frames.append((name, task.frame.code, task.frame.pc, task.frame))
        if not frames:
            frames.append((f"module {runtime.module_id}: nothing running", None, None, None))
        return frames

    def _method(self, code: bytes, pc: int) -> str:
        assert self.code is not None
        line = self.code.line_of(code, pc)
        for m in self.code.methods:
            if m.lines[0] <= line <= m.lines[1]:
                return f"{m.role}.{m.name}"
        where = self.code.locate(code, pc)
        return self.code.fragments[where[0]].name if where else "code"

    def _frame_name(self, runtime: Any, code: bytes, pc: int, frame: Any) -> str:
        kind = "program"
        for task in runtime.store.tasks:
            if task.frame is frame and task.slot is not None:
                if task.slot.kind == "handler":
                    events = [k for k, v in enumerate(runtime.store.vectors)
                              if v is not None and v.slot is task.slot]
                    kind = f"handler of event {events[0]}" if events else "handler"
                elif task.slot.kind == "command":
                    kind = f"command {task.command}"
        return f"{self._method(code, pc)} [{kind}]"

    def on_stackTrace(self, args: dict[str, Any]) -> dict[str, Any]:  # noqa: N802
        stop = self._stopped("stackTrace")
        runtime = self._runtime(args.get("threadId"), "stackTrace")
        assert self.code is not None
        out = []
        for name, code, pc, frame in self._module_frames(runtime, stop):
            ident = len(self._frames) + 1
            self._frames[ident] = (runtime.module_id, code, pc, frame)
            item: dict[str, Any] = {"id": ident, "name": name, "line": 0, "column": 0}
            if code is not None and pc is not None:
                where = self.code.locate(code, pc)
                line = self.code.line(*where) if where else 0
                if line:
                    item.update({"source": self._source(), "line": line, "column": 1})
                if where:
                    item["instructionPointerReference"] = self.code.address(*where)
            else:
                item["presentationHint"] = "subtle"
            out.append(item)
        start = args.get("startFrame", 0)
        levels = args.get("levels", 0)
        start = start if isinstance(start, int) and start >= 0 else 0
        shown = out[start:start + levels] if isinstance(levels, int) and levels > 0 else out[start:]
        return {"stackFrames": shown, "totalFrames": len(out)}

    def _frame(self, ident: Any, what: str) -> tuple[int, bytes | None, int | None, Any]:
        self._stopped(what)
        if isinstance(ident, bool) or not isinstance(ident, int) or ident not in self._frames:
            raise RequestError(f"{what}: there is no frame {ident!r} (frames last until the world moves on)")
        return self._frames[ident]

    def on_scopes(self, args: dict[str, Any]) -> dict[str, Any]:
        mid, _, _, frame = self._frame(args.get("frameId"), "scopes")
        assert self.inspector is not None and self.engine is not None
        run = self.engine.run
        scopes = []
        for name, content, expensive in self.inspector.scopes(run.runtimes[mid], frame, run):  # type: ignore[union-attr]
            ref = self._ref(content)
            scope: dict[str, Any] = {"name": name, "variablesReference": ref, "expensive": expensive}
            if name == "Module":
                scope["presentationHint"] = "locals"
            if isinstance(content, dict):
                scope["namedVariables"] = len(content)
            scopes.append(scope)
        return {"scopes": scopes}

    def _ref(self, content: Any) -> int:
        if not isinstance(content, (dict, list)) or not content:
            return 0
        ident = len(self._refs) + 1
        self._refs[ident] = content
        return ident

    def on_variables(self, args: dict[str, Any]) -> dict[str, Any]:
        self._stopped("variables")
        ref = args.get("variablesReference")
        if isinstance(ref, bool) or not isinstance(ref, int) or ref not in self._refs:
            raise RequestError(f"variables: there is no variables reference {ref!r}")
        content = self._refs[ref]
        items = (list(content.items()) if isinstance(content, dict)
                 else [(f"[{i}]", v) for i, v in enumerate(content)])
        start, count = args.get("start", 0), args.get("count", 0)
        start = start if isinstance(start, int) and start >= 0 else 0
        items = items[start:start + count] if isinstance(count, int) and count > 0 else items[start:]
        return {"variables": [self._variable(str(k), v) for k, v in items[:MAX_VARIABLES]]}

    def _variable(self, name: str, value: Any) -> dict[str, Any]:
        ref = self._ref(value)
        item: dict[str, Any] = {"name": name, "value": _text(value), "variablesReference": ref}
        if isinstance(value, dict) and value:
            item["namedVariables"] = len(value)
        elif isinstance(value, list) and value:
            item["indexedVariables"] = len(value)
        return item

    def on_evaluate(self, args: dict[str, Any]) -> dict[str, Any]:
        stop = self._stopped("evaluate")
        expression = args.get("expression")
        if not isinstance(expression, str):
            raise RequestError("evaluate: 'expression' must be a string")
        frame_id = args.get("frameId")
        if frame_id is not None:
            mid, _, _, frame = self._frame(frame_id, "evaluate")
        elif stop.module is not None:
            mid, frame = stop.module, stop.frame
        else:
            raise RequestError("evaluate: select a module's frame first (no module is running now)")
        run = self.engine.run  # type: ignore[union-attr]
        try:
            value = parse(expression).evaluate(names(run.runtimes[mid], frame, run))  # type: ignore[union-attr]
        except ExprError as e:
            raise RequestError(f"{expression}: {e}") from None
        return {"result": _text(value), "variablesReference": self._ref(value)}

    def on_exceptionInfo(self, args: dict[str, Any]) -> dict[str, Any]:  # noqa: N802
        stop = self._stopped("exceptionInfo")
        self._runtime(args.get("threadId"), "exceptionInfo")
        if stop.reason != "exception":
            raise RequestError("exceptionInfo: the world did not stop on an exception")
        return {"exceptionId": "rdcd", "description": stop.text, "breakMode": "always"}

    # ---- running ---------------------------------------------------------------------------
    def _resume(self, step: Step | None = None) -> None:
        self._frames.clear()
        self._refs.clear()
        self.engine.resume(step=step)  # type: ignore[union-attr]

    def on_continue(self, args: dict[str, Any]) -> dict[str, Any]:
        self._stopped("continue")
        self._resume()
        return {"allThreadsContinued": True}

    def _step(self, args: dict[str, Any], kind: str) -> None:
        stop = self._stopped(kind)
        runtime = self._runtime(args.get("threadId"), kind)
        assert self.code is not None
        frame = stop.frame if stop.module == runtime.module_id else None
        line = self.code.line_of(frame.code, frame.pc) if frame is not None else 0
        instruction = args.get("granularity") == "instruction"
        self._resume(Step(runtime.module_id, kind, instruction, frame, line))

    def on_next(self, args: dict[str, Any]) -> None:
        self._step(args, "next")

    def on_stepIn(self, args: dict[str, Any]) -> None:  # noqa: N802
        self._step(args, "stepIn")

    def on_stepOut(self, args: dict[str, Any]) -> None:  # noqa: N802
        self._step(args, "stepOut")

    def on_pause(self, args: dict[str, Any]) -> None:
        if self.engine is None or self.engine.run is None:
            raise RequestError("pause: nothing is running")
        self.engine.pause()  # the engine knows whether a continue is still on its way

    def on_stepBack(self, args: dict[str, Any]) -> None:  # noqa: N802
        stop = self._stopped("stepBack")
        runtime = self._runtime(args.get("threadId"), "stepBack")
        mid, code = runtime.module_id, self.code
        assert code is not None
        instruction = args.get("granularity") == "instruction"
        target = self.engine.previous(mid, stop.count, statement=not instruction)  # type: ignore[union-attr]
        self._frames.clear()
        self._refs.clear()
        self.engine.go_back(None, Goal(target, "step" if target else "entry"))  # type: ignore[union-attr]

    def on_reverseContinue(self, args: dict[str, Any]) -> None:  # noqa: N802
        stop = self._stopped("reverseContinue")
        self._runtime(args.get("threadId"), "reverseContinue")
        engine = self.engine
        assert engine is not None and self.code is not None
        locations = self._locations()
        code = self.code

        def wanted(kind: str, rt: Any, frame: Any) -> bool:
            if kind == "error":
                return RUNTIME in engine.filters
            if kind != "instruction":
                return False
            for index, base in code.places(frame.code):
                for bp in locations.get((index, base + frame.pc), ()):
                    if bp.log is None and engine_condition(bp, rt, frame, engine):
                        return True
            return False
        self._back(Scan(stop.count, wanted), "breakpoint")

    def _back(self, scan: Scan, reason: str) -> None:
        self._frames.clear()
        self._refs.clear()
        self.engine.go_back(scan, Goal(0, reason))  # type: ignore[union-attr]

    # ---- breakpoints -----------------------------------------------------------------------
    def _source(self) -> dict[str, Any]:
        assert self.launch is not None
        return {"name": os.path.basename(self.launch.path), "path": self.launch.path}

    def _new_bp(self, spec: dict[str, Any], kind: str) -> Breakpoint:
        self._next_bp += 1
        bp = Breakpoint(self._next_bp, kind=kind)
        condition, hits, log = spec.get("condition"), spec.get("hitCondition"), spec.get("logMessage")
        if isinstance(condition, str) and condition.strip():
            bp.condition = parse(condition)
        if isinstance(hits, str) and hits.strip():
            bp.hit_condition = _hit_condition(hits)
        if isinstance(log, str) and log:
            bp.log = log
        return bp

    def on_setBreakpoints(self, args: dict[str, Any]) -> dict[str, Any]:  # noqa: N802
        source = args.get("source")
        specs = args.get("breakpoints")
        if specs is None:
            specs = [{"line": n} for n in args.get("lines", []) if isinstance(n, int)]
        if not isinstance(source, dict) or not isinstance(specs, list):
            raise RequestError("setBreakpoints: 'source' must be an object and 'breakpoints' a list")
        path = source.get("path")
        key = os.path.realpath(path) if isinstance(path, str) and path else str(source.get("name"))
        out, kept = [], []
        for spec in specs:
            if not isinstance(spec, dict) or isinstance(spec.get("line"), bool) \
                    or not isinstance(spec.get("line"), int):
                self._next_bp += 1
                out.append({"id": self._next_bp, "verified": False,
                            "message": "a breakpoint needs a line number"})
                continue
            line = spec["line"]
            try:
                bp = self._new_bp(spec, "breakpoint")
            except ExprError as e:
                self._next_bp += 1
                out.append({"id": self._next_bp, "verified": False, "line": line,
                            "message": f"condition: {e}"})
                continue
            answer: dict[str, Any] = {"id": bp.id, "verified": False, "line": line}
            if self.launch is None or self.code is None:
                answer["message"] = "no program is launched yet"
            elif key != os.path.realpath(self.launch.path):
                answer["message"] = f"not the launched program ({os.path.basename(self.launch.path)})"
            else:
                answer["source"] = self._source()
                locations = self.code.line_locations(line)
                if not locations:
                    moved = self.code.nearest_code_line(line)
                    if moved is None:
                        answer["message"] = "the program has no code"
                    else:
                        locations = self.code.line_locations(moved)
                        answer["line"] = moved
                        answer["message"] = f"moved from line {line}: no code there"
                if locations:
                    answer["verified"] = True
                    kept.append((bp, locations))
            out.append(answer)
        self._line_bps[key] = kept
        self._apply()
        return {"breakpoints": out}

    def on_setFunctionBreakpoints(self, args: dict[str, Any]) -> dict[str, Any]:  # noqa: N802
        specs = args.get("breakpoints")
        if not isinstance(specs, list):
            raise RequestError("setFunctionBreakpoints: 'breakpoints' must be a list")
        out, kept = [], []
        for spec in specs:
            name = spec.get("name") if isinstance(spec, dict) else None
            try:
                bp = self._new_bp(spec if isinstance(spec, dict) else {}, "function breakpoint")
            except ExprError as e:
                self._next_bp += 1
                out.append({"id": self._next_bp, "verified": False, "message": f"condition: {e}"})
                continue
            answer: dict[str, Any] = {"id": bp.id, "verified": False}
            method = self.code.method(name) if self.code is not None and isinstance(name, str) else None
            if self.code is None:
                answer["message"] = "no program is launched yet"
            elif method is None:
                known = sorted({f"{m.role}.{m.name}" for m in self.code.methods})
                answer["message"] = f"no method {name!r} (known: {', '.join(known) or 'none'})"
            else:
                locations = self.code.method_locations(method)
                role = next((r.id for r in self.launch.program.roles if r.name == method.role), None)  # type: ignore[union-attr]
                bp.role = role
                if locations:
                    answer.update({"verified": True, "line": self.code.line(*locations[0]),
                                   "source": self._source()})
                    kept.append((bp, locations))
                else:
                    answer["message"] = f"{name} has no code"
            out.append(answer)
        self._function_bps = kept
        self._apply()
        return {"breakpoints": out}

    def on_setExceptionBreakpoints(self, args: dict[str, Any]) -> dict[str, Any]:  # noqa: N802
        filters = args.get("filters", [])
        if not isinstance(filters, list) or not all(isinstance(f, str) for f in filters):
            raise RequestError("setExceptionBreakpoints: 'filters' must be a list of names")
        unknown = [f for f in filters if f not in EXCEPTION_FILTERS]
        if unknown:
            raise RequestError(f"setExceptionBreakpoints: unknown filter(s) {', '.join(unknown)} "
                               f"(known: {', '.join(EXCEPTION_FILTERS)})")
        if self.engine is None:
            raise RequestError("setExceptionBreakpoints: launch a program first")
        self.engine.filters = set(filters)
        self.engine._update_special()  # noqa: SLF001
        return {"breakpoints": [{"verified": True} for _ in filters]}

    def _locations(self) -> dict[tuple[int, int], list[Breakpoint]]:
        locations: dict[tuple[int, int], list[Breakpoint]] = {}
        for kept in [*self._line_bps.values(), self._function_bps]:
            for bp, places in kept:
                for place in places:
                    locations.setdefault(place, []).append(bp)
        return locations

    def _apply(self) -> None:
        if self.engine is not None and not (self.launch and self.launch.no_debug):
            self.engine.set_breakpoints(self._locations())

    # ---- disassembly -----------------------------------------------------------------------
    def on_disassemble(self, args: dict[str, Any]) -> dict[str, Any]:
        if self.code is None:
            raise RequestError("disassemble: launch a program first")
        where = self.code.parse_address(args.get("memoryReference"))
        count = args.get("instructionCount")
        if where is None or where[0] >= len(self.code.fragments):
            raise RequestError(f"disassemble: {args.get('memoryReference')!r} is not an address "
                               "of the program")
        if isinstance(count, bool) or not isinstance(count, int) or not 0 <= count <= MAX_INSTRUCTIONS:
            raise RequestError(f"disassemble: instructionCount must be 0..{MAX_INSTRUCTIONS}")
        index, offset = where
        extra = args.get("offset", 0)
        skip = args.get("instructionOffset", 0)
        offset += extra if isinstance(extra, int) and not isinstance(extra, bool) else 0
        skip = skip if isinstance(skip, int) and not isinstance(skip, bool) else 0
        fragment = self.code.fragments[index]
        listing = _decode(fragment.code)
        starts = [d.offset for d in listing]
        at = next((i for i, s in enumerate(starts) if s >= offset), len(starts))
        first = at + skip
        out = []
        for i in range(first, first + count):
            if 0 <= i < len(listing):
                d = listing[i]
                item: dict[str, Any] = {
                    "address": self.code.address(index, d.offset),
                    "instructionBytes": fragment.code[d.offset:d.offset + d.size].hex(" "),
                    "instruction": _instruction_text(d), "symbol": fragment.name}
                line = self.code.line(index, d.offset)
                if line:
                    item.update({"location": self._source(), "line": line})
                out.append(item)
            else:  # outside the fragment: VS Code asks for a window around the pc
                beyond = i if i < 0 else len(fragment.code) + i - len(listing)
                address = max(0, index * ADDRESS_STRIDE + beyond)
                out.append({"address": f"0x{address:x}", "instruction": "", "presentationHint": "invalid"})
        return {"instructions": out}


def engine_condition(bp: Breakpoint, runtime: Any, frame: Any, engine: Engine) -> bool:
    if bp.role is not None and not runtime.roles.is_instance(runtime.role, bp.role):
        return False
    if bp.condition is None:
        return True
    try:
        return bool(bp.condition.evaluate(names(runtime, frame, engine.run)))
    except ExprError:
        return False


def _decode(code: bytes) -> list[Any]:
    out, offset = [], 0
    while offset < len(code):
        d = decode_at(code, offset)
        out.append(d)
        offset += 1 if d.raw or d.name == "PUSH" else d.size
    return out


def _instruction_text(d: Any) -> str:
    if d.name == "PUSH":
        return f"PUSH {d.operands[0]}"
    return f"{d.name} {', '.join(map(str, d.operands))}".strip()


def _hit_condition(text: str) -> tuple[str, int]:
    text = text.strip()
    for op in (">=", "<=", "==", ">", "<", "%"):
        if text.startswith(op):
            number = text[len(op):].strip()
            break
    else:
        op, number = ">=", text
    if not number.isdigit():
        raise ExprError(f"hit count {text!r}: write N, >= N, == N, > N, < N, <= N or % N")
    return op, int(number)


def _text(value: Any) -> str:
    if value is None:
        return "none"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, dict):
        return "{…}" if value else "{}"
    if isinstance(value, list):
        return f"[{len(value)}]"
    if isinstance(value, str):
        return value
    return str(value)
