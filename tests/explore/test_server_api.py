"""The explorer's HTTP API: answers, errors as data, and a bounded fuzz of every endpoint.

Runs the real app with one real worker process (``PanelPool(1)``) through
Starlette's in-process test client: no socket, nothing leaves the process.
"""

from __future__ import annotations

import json
import os
import warnings

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

pytest.importorskip(
    "starlette", reason="the explore extra is not installed (pip install 'seapass[explore]')"
)
with warnings.catch_warnings():  # starlette >= 1.10 prefers httpx2 for its test client
    warnings.simplefilter("ignore")
    from starlette.testclient import TestClient

from seapass.explore.panels import KINDS
from seapass.explore.pool import PanelPool
from seapass.explore.server import MAX_BODY, create_app

LP = {
    "name": "LP",
    "model": {"D1": "k1", "CL": "kd"},
    "values": {"m": 1, "b": 10, "k1": 1000, "kd": 500},
    "period": 0.002,
}
WORKERS = int(os.environ.get("SEAPASS_EXPLORE_TEST_WORKERS", "1"))


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory):
    app = create_app(
        LP, pool=PanelPool(WORKERS, timeout=None), report_dir=tmp_path_factory.mktemp("reports")
    )
    with TestClient(app, base_url="http://127.0.0.1") as c:
        yield c


def _post(client: TestClient, url: str, body: object):
    return client.post(url, content=json.dumps(body), headers={"Content-Type": "application/json"})


def test_page_and_assets_are_served(client: TestClient) -> None:
    page = client.get("/")
    assert page.status_code == 200 and "seapass explore" in page.text
    for asset in ("app.js", "plots.js", "style.css", "icon.svg"):
        r = client.get(f"/static/{asset}")
        assert r.status_code == 200 and r.content, asset
    # offline: nothing is loaded from another origin
    for text in (
        page.text,
        client.get("/static/app.js").text,
        client.get("/static/style.css").text,
    ):
        assert (
            "http://" not in text.replace("http://www.w3.org/2000/svg", "")
            and "https://" not in text
        )


def test_initial_view_and_presets(client: TestClient) -> None:
    d = client.get("/api/initial").json()
    assert d["state"]["name"] == "LP" and d["kinds"] == list(KINDS)
    ids = {p["id"] for p in d["presets"]}
    assert {"LP", "APD", "Ours", "ctrl/load-P", "mech/pure-spring", "proposed"} <= ids
    for p in d["presets"]:  # every preset is a valid view
        assert _post(client, "/api/state", p["state"]).json()["ok"], p["id"]


def test_state_errors_are_per_field(client: TestClient) -> None:
    d = _post(
        client, "/api/state", {**LP, "model": {"D1": "k1 +", "CL": "kd"}, "period": "x"}
    ).json()
    assert not d["ok"] and set(d["errors"]) == {"model.D1", "period"}


def test_every_panel(client: TestClient) -> None:
    for kind in KINDS:
        r = _post(client, f"/api/panel/{kind}", {"state": LP})
        assert r.status_code == 200 and r.json()["ok"], (kind, r.text)
    bad = _post(client, "/api/panel/verdict", {"state": {**LP, "values": {"m": -1}}}).json()
    assert not bad["ok"] and "values.m" in bad["error"]


def test_panels_stream_one_line_per_kind(client: TestClient) -> None:
    r = _post(client, "/api/panels", {"state": {**LP, "values": {**LP["values"], "kd": 2000}}})
    assert r.status_code == 200 and r.headers["content-type"].startswith("application/x-ndjson")
    lines = [json.loads(x) for x in r.text.splitlines()]
    assert sorted(x["kind"] for x in lines) == sorted(KINDS)
    by = {x["kind"]: x for x in lines}
    assert by["verdict"]["data"]["passive"] is False and by["witness"]["data"]["found"]


def test_export_design(client: TestClient) -> None:
    d = _post(client, "/api/export/design", LP).json()
    assert (
        d["ok"]
        and d["filename"] == "LP.toml"
        and 'CL = "kd"' in d["text"]
        and "rate = 500.0" in d["text"]
    )
    boxed = {**LP, "uncertainty": {"m": [0.9, 1.1]}, "delay_time": 0.001}
    d = _post(client, "/api/export/design", boxed).json()
    assert (
        d["ok"]
        and "[uncertainty]\nm = [0.9, 1.1]" in d["text"]
        and "delay_time = 0.001" in d["text"]
    )
    outside = {**boxed, "values": {**LP["values"], "m": 2.0}}  # the m slider left the box
    for url, body in [("/api/export/design", outside), ("/api/export/report", {"state": outside})]:
        d = _post(client, url, body).json()
        assert not d["ok"] and list(d["errors"]) == ["uncertainty.m"], d


@pytest.mark.parametrize(
    ("method", "url", "body", "headers", "status"),
    [
        ("post", "/api/state", b"{not json", {"Content-Type": "application/json"}, 400),
        ("post", "/api/state", b'{"model": {}}', {"Content-Type": "text/plain"}, 400),
        ("post", "/api/panel/verdict", b"[1, 2]", {"Content-Type": "application/json"}, 400),
        ("post", "/api/panel/eval", b"{}", {"Content-Type": "application/json"}, 404),
        (
            "post",
            "/api/panels",
            b'{"kinds": ["verdict", "rm -rf"]}',
            {"Content-Type": "application/json"},
            400,
        ),
        (
            "post",
            "/api/panel/region",
            b'{"resolution": 100000}',
            {"Content-Type": "application/json"},
            400,
        ),
        (
            "post",
            "/api/panel/region",
            b'{"resolution": 96, "rows": [0, 90]}',
            {"Content-Type": "application/json"},
            400,
        ),
        (
            "post",
            "/api/state",
            b"[" * 100000 + b"]" * 100000,
            {"Content-Type": "application/json"},
            400,
        ),
        ("post", "/api/state", b" " * (MAX_BODY + 1), {"Content-Type": "application/json"}, 400),
        ("get", "/api/report/999", None, {}, 404),
        ("get", "/reports/1/../../../etc/passwd", None, {}, 404),
        ("get", "/api/initial", None, {"Host": "evil.example"}, 400),
    ],
)
def test_bad_requests_get_a_clear_answer(client, method, url, body, headers, status) -> None:
    r = client.request(method.upper(), url, content=body, headers=headers)
    assert r.status_code == status, r.text
    if r.headers.get("content-type", "").startswith("application/json"):
        assert r.json()["error"]


def test_a_panel_over_its_time_budget_is_stopped_and_the_pool_recovers() -> None:
    if WORKERS == 0:
        pytest.skip("needs a worker process")
    # a budget of 0 s: over it before any panel can answer, however fast or busy the machine
    pool = PanelPool(1, timeout=0.0)
    try:
        slow = {
            "model": {"D1": "k1 + b1*s", "CA": "kd + bd*s"},
            "values": {"b1": 300, "kd": 1708, "bd": 300},
            "period": 0.002,
            "delay": 1,
            "velocity_filter": 50,
        }
        r = pool.call("sampled", slow)
        assert not r["ok"] and "longer than" in r["error"]
        pool.timeout = None
        assert pool.call("verdict", LP)["ok"]  # a fresh worker took over
    finally:
        pool.close()


_json = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats() | st.text(max_size=20),
    lambda inner: (
        st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=6), inner, max_size=3)
    ),
    max_leaves=12,
)
_bodies = st.one_of(
    _json,
    st.builds(
        lambda m, v, x: {"state": {"model": m, "values": v, **x}},
        st.dictionaries(
            st.sampled_from(["D1", "CA", "CL"]),
            st.sampled_from(["k1", "kd + bd*s", "1/s", "s^2", "kd/(s-1)", "k1 +", ""]),
        ),
        st.dictionaries(
            st.sampled_from(["m", "b", "k1", "kd", "bd"]),
            st.floats(-1e3, 1e5) | st.text(max_size=5),
        ),
        st.dictionaries(
            st.sampled_from(["period", "delay", "velocity_filter", "load_mass", "resolution"]),
            _json,
        ),
    ),
)


@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    url=st.sampled_from(
        [
            "/api/state",
            "/api/panel/verdict",
            "/api/panel/frequency",
            "/api/panel/step",
            "/api/panels",
            "/api/export/design",
            "/api/panel/interval",
        ]
    ),
    body=_bodies,
)
def test_fuzz_endpoints_never_crash(client: TestClient, url: str, body: object) -> None:
    r = _post(client, url, body)
    assert r.status_code in (200, 400), r.text
    if url == "/api/panels" and r.status_code == 200:
        for line in r.text.splitlines():
            assert "internal error" not in json.loads(line).get("error", "")
    else:
        assert "internal error" not in r.text
    assert client.get("/api/initial").status_code == 200  # still serving


@pytest.mark.parametrize(
    ("argv", "says"),
    [
        (["explore", "--port", "70000", "--no-browser"], "--port 70000"),
        (["explore", "no/such/design.toml", "--no-browser"], "no/such/design.toml"),
        (["explore", "--workers", "99", "--no-browser"], "--workers 99"),
    ],
)
def test_cli_bad_input_is_one_line(argv: list[str], says: str, capsys) -> None:
    from seapass.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and says in err and err.count("\n") == 1


def test_cli_without_the_web_extra(monkeypatch, capsys) -> None:
    import sys

    from seapass.cli import main

    monkeypatch.setitem(sys.modules, "uvicorn", None)  # import uvicorn now raises ImportError
    assert main(["explore", "--no-browser"]) == 2
    assert "pip install 'seapass[explore]'" in capsys.readouterr().err


def test_cli_port_in_use(capsys) -> None:
    import socket

    from seapass.cli import main

    with socket.socket() as busy:
        busy.bind(("127.0.0.1", 0))
        busy.listen(1)
        port = busy.getsockname()[1]
        assert main(["explore", "--port", str(port), "--no-browser", "--workers", "0"]) == 2
    assert f"127.0.0.1:{port}" in capsys.readouterr().err
