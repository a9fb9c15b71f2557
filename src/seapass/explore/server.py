"""The explorer's web server: a small Starlette app on 127.0.0.1, served by uvicorn.

Routes (every API answer is JSON; errors are data, never a crash):

``GET /``                      the page (``static/index.html``)
``GET /static/...``            its script, style sheet and icon (shipped in the package)
``GET /api/initial``           the initial view and the presets
``POST /api/state``            validate a view: ``{"ok", "state", "errors"}``
``POST /api/panel/{kind}``     one panel of a view: ``{"ok", "data" | "error"}``
``POST /api/panels``           several panels, one JSON line each as soon as it is ready
``POST /api/export/design``    the view as a design file: ``{"ok", "filename", "text"}``
``POST /api/export/report``    start ``seapass analyze`` on the view: ``{"ok", "report"}``
``GET /api/report/{id}``       status of a report run
``GET /reports/{id}/{path}``   the files of a finished report

Requests must come from the page itself: POST bodies must be JSON (a
cross-site form cannot send that without a pre-flight this server never
grants) and the ``Host`` header must name the loopback address.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import logging
import os
import socket
import sys
import tempfile
import threading
import webbrowser
from collections.abc import AsyncIterator, Callable
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import ClientDisconnect, Request
from starlette.responses import FileResponse, JSONResponse, Response, StreamingResponse
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from .panels import KINDS, REGION_CHUNK, REGION_RESOLUTIONS, check_rows
from .pool import PanelPool
from .presets import presets
from .reports import ReportJobs
from .state import design_export
from .validation import check_state

__all__ = ["MAX_BODY", "STATIC", "bind", "create_app", "graphical_session", "serve"]

STATIC = Path(__file__).parent / "static"
#: Largest request body accepted (a view is a few kB).
MAX_BODY = 256 * 1024
_log = logging.getLogger("seapass.explore")


class _BadRequest(Exception):
    pass


async def _json_body(request: Request) -> Any:
    if request.headers.get("content-type", "").split(";")[0].strip() != "application/json":
        raise _BadRequest("send the body as application/json")
    length = request.headers.get("content-length")
    if length is not None and (not length.isdigit() or int(length) > MAX_BODY):
        raise _BadRequest(f"request body larger than {MAX_BODY} bytes")
    body = b""
    async for chunk in request.stream():
        body += chunk
        if len(body) > MAX_BODY:
            raise _BadRequest(f"request body larger than {MAX_BODY} bytes")
    try:
        return json.loads(body.decode("utf-8"))
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise _BadRequest(f"the body is not valid JSON ({type(exc).__name__})") from None


def _error(message: str, status: int = 400) -> JSONResponse:
    return JSONResponse({"ok": False, "error": message}, status_code=status)


def _guarded(handler: Callable[[Request], Any]) -> Callable[[Request], Any]:
    """Every failure becomes a JSON error; the server keeps serving.

    A client that goes away in the middle of its request (a closed tab, a
    superseded panel request) is normal, not an error: nothing is logged.
    """

    async def wrapped(request: Request) -> Response:
        try:
            return await handler(request)
        except _BadRequest as exc:
            return _error(str(exc))
        except ClientDisconnect:
            _log.debug("client went away during %s", request.url.path)
            return Response(status_code=499)  # nobody reads it
        except Exception:  # the server never crashes on a request
            _log.exception("internal error on %s", request.url.path)
            return _error("internal error; the server log has the details", 500)

    return wrapped


def create_app(
    initial: dict[str, Any],
    *,
    pool: PanelPool | None = None,
    report_dir: Path | None = None,
) -> Starlette:
    """The explorer app.

    Parameters
    ----------
    initial : dict
        The view shown first (a state as sent by the browser).
    pool : PanelPool, optional
        Where panels are computed; default `PanelPool` with its default workers.
    report_dir : path, optional
        Where "Export report" writes; default a new temporary directory.
    """
    panels = pool if pool is not None else PanelPool()
    reports = ReportJobs(
        Path(report_dir) if report_dir else Path(tempfile.mkdtemp(prefix="seapass-explore-"))
    )
    threads = ThreadPoolExecutor(max_workers=32, thread_name_prefix="explore-panel")
    preset_list = presets()

    async def index(request: Request) -> Response:
        return FileResponse(STATIC / "index.html", headers={"Cache-Control": "no-store"})

    async def initial_view(request: Request) -> Response:
        check = check_state(initial)
        return JSONResponse(
            {
                "state": check.to_json()["state"],
                "errors": dict(check.errors),
                "presets": preset_list,
                "kinds": list(KINDS),
                "resolutions": list(REGION_RESOLUTIONS),
                "chunk": REGION_CHUNK,
            }
        )

    async def state(request: Request) -> Response:
        return JSONResponse(check_state(await _json_body(request)).to_json())

    async def panel(request: Request) -> Response:
        kind = request.path_params["kind"]
        if kind not in KINDS:
            return _error(f"unknown panel {kind!r}; panels: {', '.join(KINDS)}", 404)
        body = await _json_body(request)
        if not isinstance(body, dict):
            raise _BadRequest("expected a JSON object with the view")
        options: dict[str, Any] = {}
        if kind == "region":
            options = {
                "resolution": body.get("resolution", REGION_RESOLUTIONS[0]),
                "rows": body.get("rows"),
            }
            try:
                check_rows(options["resolution"], options["rows"])
            except ValueError as exc:
                raise _BadRequest(str(exc)) from None
        loop = asyncio.get_running_loop()
        reply = await loop.run_in_executor(threads, panels.call, kind, body.get("state"), options)
        return JSONResponse(reply)

    async def panel_stream(request: Request) -> Response:
        body = await _json_body(request)
        if not isinstance(body, dict):
            raise _BadRequest("expected a JSON object with the view and the panel kinds")
        kinds = body.get("kinds", list(KINDS))
        if not isinstance(kinds, list) or not kinds or any(k not in KINDS for k in kinds):
            raise _BadRequest(f"kinds must be a non-empty list of {', '.join(KINDS)}")
        kinds = list(dict.fromkeys(kinds))
        view = body.get("state")
        loop = asyncio.get_running_loop()

        async def job(kind: str) -> tuple[str, dict[str, Any]]:
            reply = await loop.run_in_executor(threads, panels.call, kind, view)
            return kind, reply

        tasks = [asyncio.ensure_future(job(k)) for k in kinds]

        async def lines() -> AsyncIterator[bytes]:
            try:
                for done in asyncio.as_completed(tasks):
                    kind, reply = await done
                    yield (json.dumps({"kind": kind, **reply}) + "\n").encode()
            finally:  # the client went away: the answers nobody reads are not awaited
                for t in tasks:
                    t.cancel()

        return StreamingResponse(
            lines(),
            media_type="application/x-ndjson",
            headers={"Cache-Control": "no-store", "X-Content-Type-Options": "nosniff"},
        )

    async def export_design(request: Request) -> Response:
        check = check_state(await _json_body(request))
        if check.state is None:
            return JSONResponse(
                {"ok": False, "errors": dict(check.errors), "error": "fix the marked fields"}
            )
        return JSONResponse(design_export(check.state))

    async def export_report(request: Request) -> Response:
        body = await _json_body(request)
        if not isinstance(body, dict):
            raise _BadRequest("expected a JSON object")
        check = check_state(body.get("state"))
        if check.state is None:
            return JSONResponse(
                {"ok": False, "errors": dict(check.errors), "error": "fix the marked fields"}
            )
        exported = design_export(check.state)
        if not exported["ok"]:
            return JSONResponse(exported)
        try:
            job = reports.start(check.state.name, exported["text"], quick=bool(body.get("quick")))
        except RuntimeError as exc:
            return _error(str(exc), 409)
        return JSONResponse({"ok": True, "report": job.to_json()})

    async def report_status(request: Request) -> Response:
        job = reports.get(request.path_params["id"])
        if job is None:
            return _error("no such report", 404)
        return JSONResponse({"ok": True, "report": job.to_json()})

    async def report_file(request: Request) -> Response:
        path = reports.file(request.path_params["id"], request.path_params["path"])
        if path is None:
            return _error("no such file", 404)
        return FileResponse(path)

    @contextlib.asynccontextmanager
    async def lifespan(app: Starlette) -> AsyncIterator[None]:
        yield
        reports.close()
        panels.close()
        threads.shutdown(wait=False, cancel_futures=True)

    routes = [
        Route("/", index),
        Route("/api/initial", _guarded(initial_view)),
        Route("/api/state", _guarded(state), methods=["POST"]),
        Route("/api/panel/{kind}", _guarded(panel), methods=["POST"]),
        Route("/api/panels", _guarded(panel_stream), methods=["POST"]),
        Route("/api/export/design", _guarded(export_design), methods=["POST"]),
        Route("/api/export/report", _guarded(export_report), methods=["POST"]),
        Route("/api/report/{id:int}", _guarded(report_status)),
        Route("/reports/{id:int}/{path:path}", _guarded(report_file)),
        Mount("/static", app=StaticFiles(directory=STATIC), name="static"),
    ]
    middleware = [
        Middleware(_QuietDisconnects),
        Middleware(TrustedHostMiddleware, allowed_hosts=["127.0.0.1", "localhost"]),
    ]
    app = Starlette(routes=routes, middleware=middleware, lifespan=lifespan)
    app.state.pool = panels
    app.state.reports = reports
    return app


class _QuietDisconnects:
    """ASGI middleware: a client that disconnects while its answer is sent ends the answer.

    A failed write of the server (an `OSError`, which Starlette turns into
    `ClientDisconnect` for a streamed answer) comes after the handler has
    returned; without this it would reach the server, which logs a traceback
    for a normal event.  Other errors pass on.
    """

    def __init__(self, app: Any) -> None:
        self.app = app

    async def __call__(self, scope: Any, receive: Any, send: Any) -> None:
        gone = False

        async def watched_send(message: Any) -> None:
            nonlocal gone
            try:
                await send(message)
            except OSError:  # the server could not write: the connection is closed
                gone = True
                raise

        try:
            await self.app(scope, receive, watched_send)
        except ClientDisconnect:
            _log.debug("client went away during %s", scope.get("path"))
        except OSError:
            if not gone:
                raise
            _log.debug("client went away during %s", scope.get("path"))


def bind(port: int) -> socket.socket:
    """A listening socket on 127.0.0.1 (``port=0``: a free port)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    # small JSON answers must not wait for delayed ACKs (Nagle): ~40 ms per request otherwise
    sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    try:
        sock.bind(("127.0.0.1", port))
    except OSError as exc:
        sock.close()
        raise OSError(
            f"port: cannot listen on 127.0.0.1:{port} ({exc.strerror}); "
            "choose another port, or port=0 for a free one"
        ) from None
    sock.listen(64)
    return sock


def graphical_session() -> bool:
    """Whether a browser window can open here (never a text-mode browser in the terminal)."""
    if sys.platform in ("darwin", "win32"):
        return True
    return any(os.environ.get(v) for v in ("DISPLAY", "WAYLAND_DISPLAY", "BROWSER"))


def serve(
    initial: dict[str, Any],
    *,
    port: int = 8765,
    open_browser: bool = True,
    workers: int | None = None,
    report_dir: Path | None = None,
    ready: Callable[[str], None] | None = None,
) -> None:
    """Serve the explorer on 127.0.0.1 until Ctrl-C (or SIGTERM); blocking.

    ``ready(url)`` is called once the server accepts connections.
    """
    import uvicorn

    sock = bind(port)
    url = f"http://127.0.0.1:{sock.getsockname()[1]}/"
    pool = PanelPool() if workers is None else PanelPool(workers)
    warm = threading.Thread(target=pool.warm_up, args=(initial,), daemon=True)
    warm.start()
    app = create_app(initial, pool=pool, report_dir=report_dir)
    config = uvicorn.Config(app, log_level="warning", access_log=False, lifespan="on")
    server = uvicorn.Server(config)

    def announce() -> None:
        while not server.started:
            if server.should_exit:
                return
            threading.Event().wait(0.02)
        if ready is not None:
            ready(url)
        if open_browser and graphical_session():
            webbrowser.open(url)

    threading.Thread(target=announce, daemon=True).start()
    try:
        server.run(sockets=[sock])
    finally:
        pool.close()
        sock.close()
