"""The explorer with a client that disconnects, and a region over a model without k1
(issue 20, item 5).

The app is driven at the ASGI level, as uvicorn drives it, with a client that
goes away: in the middle of its request body, and in the middle of a streamed
answer (the server's write fails with an ``OSError``, as an ASGI 2.4 server's
does).  Nothing may be logged above DEBUG and nothing may escape the app.
"""

from __future__ import annotations

import asyncio
import json
import logging
from typing import Any

import pytest

pytest.importorskip("starlette", reason="the explore extra is not installed")

from seapass.explore.panels import compute
from seapass.explore.pool import PanelPool, run_panel
from seapass.explore.server import create_app
from seapass.explore.validation import check_state

LP = {"name": "LP", "model": {"D1": "k1", "CL": "kd"}, "values": {"m": 1, "b": 10, "kd": 500}}


def scope(path: str, spec: str) -> dict[str, Any]:
    return {
        "type": "http",
        "asgi": {"version": "3.0", "spec_version": spec},
        "http_version": "1.1",
        "method": "POST",
        "scheme": "http",
        "path": path,
        "raw_path": path.encode(),
        "query_string": b"",
        "root_path": "",
        "server": ("127.0.0.1", 8765),
        "client": ("127.0.0.1", 5555),
        "headers": [(b"host", b"127.0.0.1"), (b"content-type", b"application/json")],
    }


async def run(app: Any, path: str, parts: list[bytes], *, spec: str, fail_after: int | None):
    """Send ``parts`` of the body, then a disconnect; the client's socket fails after
    ``fail_after`` messages of the answer (None: never)."""
    inbox: list[dict[str, Any]] = [
        {"type": "http.request", "body": p, "more_body": True} for p in parts
    ]
    if fail_after is None:  # gone in the middle of the body
        inbox.append({"type": "http.disconnect"})
    else:  # the body was complete: the disconnect comes while the answer is sent
        inbox[-1]["more_body"] = False
    sent: list[dict[str, Any]] = []
    gone = asyncio.Event()

    async def receive() -> dict[str, Any]:
        if inbox:
            return inbox.pop(0)
        await gone.wait()
        return {"type": "http.disconnect"}

    async def send(message: dict[str, Any]) -> None:
        if fail_after is not None and len(sent) >= fail_after:
            gone.set()
            raise OSError("the client closed the connection")
        sent.append(message)

    await app(scope(path, spec), receive, send)
    return sent


@pytest.fixture(scope="module")
def app():
    app = create_app(LP, pool=PanelPool(1, timeout=None))
    yield app
    app.state.pool.close()


@pytest.mark.parametrize("path", ["/api/panel/verdict", "/api/panels", "/api/state"])
def test_a_client_gone_during_its_request_is_not_an_error(
    app: Any, path: str, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.DEBUG)
    body = json.dumps({"state": LP}).encode()
    sent = asyncio.run(run(app, path, [body[:7]], spec="2.4", fail_after=None))
    assert [r for r in caplog.records if r.levelno > logging.DEBUG] == []
    assert any("client went away" in r.getMessage() for r in caplog.records)
    starts = [m for m in sent if m["type"] == "http.response.start"]
    assert [m["status"] for m in starts] == [499]


@pytest.mark.parametrize("spec", ["2.4", "2.3"])
def test_a_client_gone_while_its_answer_streams_is_not_an_error(
    app: Any, spec: str, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.DEBUG)
    body = json.dumps({"state": LP, "kinds": ["verdict", "frequency", "interval"]}).encode()
    asyncio.run(run(app, "/api/panels", [body[:9], body[9:]], spec=spec, fail_after=2))
    assert [r for r in caplog.records if r.levelno > logging.DEBUG] == []


def test_other_errors_still_reach_the_log(app: Any, caplog: pytest.LogCaptureFixture) -> None:
    """The quiet path is for a closed connection only: an OSError of the app itself is not."""
    caplog.set_level(logging.DEBUG)
    from seapass.explore import server

    async def broken(request: Any) -> Any:
        raise OSError("disk full")

    guarded = server._guarded(broken)  # the wrapper under test

    class R:
        url = type("U", (), {"path": "/x"})()

    response = asyncio.run(guarded(R()))
    assert response.status_code == 500
    assert any(r.levelno >= logging.ERROR for r in caplog.records)


# ------------------------------------------------------------------ the region panel


@pytest.mark.parametrize(
    "model",
    [
        {"D1": "ks", "CL": "kd"},  # a spring not named k1, one gain
        {"D1": "k", "CA": "kp"},
        {"D1": "k2 + c*s", "CA": "kp"},
    ],
)
def test_region_of_a_model_without_k1_is_computed(model: dict[str, str]) -> None:
    check = check_state({"model": model})
    assert check.state is not None
    x, y = check.state.region
    assert x in check.state.values and y in check.state.values and x != y
    reply = run_panel("region", {"model": model})
    assert reply["ok"], reply
    assert "internal error" not in json.dumps(reply)
    assert compute("region", check.state)["x"] == x


def test_a_state_naming_a_missing_parameter_cannot_be_built() -> None:
    check = check_state({"model": {"D1": "ks", "CL": "kd"}})
    assert check.state is not None
    import dataclasses

    with pytest.raises(ValueError, match="must be two different parameters"):
        dataclasses.replace(check.state, region=("kd", "k1"))
