"""``seapass explore`` end to end: the real command, a real headless Chromium, a person's clicks.

Starts ``seapass explore --port 0 --no-browser`` as a child process, drives the
page with Playwright (Debian's chromium, no download), and stops the server
with Ctrl-C (SIGINT).  No wait has a time limit (a busy machine must not fail a
test): the server's work is bounded by a CPU-time limit instead (``cpu_budget``).  Skipped only when chromium or Playwright is missing
(``make test`` installs both).
"""

from __future__ import annotations

import json
import shutil
import signal
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from cpu_budget import limit_child_cpu

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
pytestmark = [
    pytest.mark.skipif(
        CHROMIUM is None,
        reason="chromium is not installed (apt-get install chromium; make test does it)",
    ),
]
sync_api = pytest.importorskip(
    "playwright.sync_api", reason="Playwright is not installed (pip install 'seapass[test]')"
)
pytest.importorskip(
    "uvicorn", reason="the explore extra is not installed (pip install 'seapass[explore]')"
)

#: CPU seconds the explorer process may compute (its panel workers have their own).
SERVER_CPU_S = 1800
LAUNCH = "import sys; from seapass.cli import main; sys.exit(main(sys.argv[1:]))"
IDLE = "body[data-busy='0']:not([data-version='0'])"


class Explorer:
    """The running command and its URL."""

    def __init__(self, tmp: Path) -> None:
        self.proc = subprocess.Popen(
            [
                sys.executable,
                "-c",
                LAUNCH,
                "explore",
                "--port",
                "0",
                "--no-browser",
                "--workers",
                "2",
                "--reports",
                str(tmp / "reports"),
            ],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            preexec_fn=limit_child_cpu(SERVER_CPU_S),
        )
        assert self.proc.stdout is not None
        line = self.proc.stdout.readline()
        assert "serving http://127.0.0.1:" in line, (
            line + self.proc.stderr.read() if self.proc.stderr else line
        )
        self.url = line.split()[3]

    def stop(self) -> tuple[int, str]:
        self.proc.send_signal(signal.SIGINT)
        _, err = self.proc.communicate()
        return self.proc.returncode, err


@pytest.fixture(scope="module")
def explorer(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Explorer]:
    ex = Explorer(tmp_path_factory.mktemp("explore"))
    yield ex
    if ex.proc.poll() is None:
        ex.proc.kill()
        ex.proc.wait()


@pytest.fixture(scope="module")
def browser() -> Iterator[object]:
    with sync_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield b
        b.close()


@pytest.fixture(scope="module")
def page(browser, explorer: Explorer) -> Iterator[object]:
    ctx = browser.new_context(viewport={"width": 1500, "height": 1300}, accept_downloads=True)
    ctx.set_default_timeout(0)  # waits end when the page is ready, not after some seconds
    pg = ctx.new_page()
    pg.problems = []  # console errors and page exceptions
    pg.on(
        "console", lambda m: pg.problems.append(m.text) if m.type in ("error", "warning") else None
    )
    pg.on("pageerror", lambda e: pg.problems.append(str(e)))
    pg.goto(explorer.url)
    pg.wait_for_selector(IDLE, state="attached")
    yield pg
    ctx.close()


def _settle(pg, before: str) -> None:
    """Wait until every panel shows a view newer than ``before``."""
    pg.wait_for_selector(f"body[data-busy='0']:not([data-version='{before}'])", state="attached")


def _version(pg) -> str:
    return pg.get_attribute("body", "data-version")


def _verdict(pg) -> str:
    return pg.inner_text("#verdict-continuous .v")


def _set_slider(pg, name: str, value: float) -> None:
    """Click the slider track where ``value`` sits, as a person would."""
    before = _version(pg)
    pos = pg.evaluate(
        """([name, v]) => { const s = window.seapass.state();
             const [lo, hi] = s.ranges[name];
             return Plots.toPos(v, lo, hi, s.scales[name]); }""",
        [name, value],
    )
    if abs(pos - int(pg.input_value(f"#slider-{name}"))) < 30:
        return  # already there: a click on the thumb does not move it
    frac = pos / 1000
    box = pg.locator(f"#slider-{name}").bounding_box()
    thumb = 16  # Chromium's default range thumb
    pg.mouse.click(
        box["x"] + thumb / 2 + frac * (box["width"] - thumb), box["y"] + box["height"] / 2
    )
    _settle(pg, before)


def test_page_loads_offline_without_errors(page) -> None:
    assert page.title() == "seapass explore"
    assert _verdict(page) in ("passive", "not passive")
    for plot in ("interval", "region", "magnitude", "phase", "rez", "step", "force", "eta"):
        assert page.locator(f"#plot-{plot} *").count() > 3, plot
    assert page.problems == []


def test_pick_lp_and_move_kd_across_k1(page) -> None:
    before = _version(page)
    page.select_option("#preset", "LP")
    _settle(page, before)
    state = page.evaluate("window.seapass.state()")
    assert state["model"]["CL"] == "kd" and state["values"]["k1"] == 1000
    _set_slider(page, "kd", 500.0)
    assert _verdict(page) == "passive"
    rez, step = (
        page.get_attribute("#plot-rez path[data-series]", "d"),
        page.inner_text("#step-text"),
    )
    marker = page.get_attribute("#interval-marker", "d")

    _set_slider(page, "kd", 2000.0)
    kd = page.evaluate("window.seapass.state().values.kd")
    assert 1000 < kd < 5000
    assert _verdict(page) == "not passive"
    assert "Re Z(jw) < 0" in page.inner_text("#verdict-continuous .why")
    assert page.get_attribute("#plot-rez path[data-series]", "d") != rez
    assert page.inner_text("#step-text") != step
    assert page.get_attribute("#interval-marker", "d") != marker
    assert page.locator("#plot-rez rect.band").count() >= 1  # the failing band is shaded
    assert "m_e =" in page.inner_text("#witness-text")
    assert "outside" in page.inner_text("#interval-text")
    assert f"p.kd={kd:g}" in page.url or f"p.kd={kd}" in page.url

    _set_slider(page, "kd", 300.0)
    assert _verdict(page) == "passive"
    assert page.problems == []


def _absolute(pg) -> str:
    return pg.inner_text("#verdict-absolute .v")


def test_twoport_panel_follows_the_design(page) -> None:
    """Absolute stability and η live: the same verdict as seapass.ports on the page's view."""
    from seapass.model.sea import SEA
    from seapass.ports.stability import absolute_stability

    def library() -> tuple[str, float]:
        st = page.evaluate("window.seapass.state()")
        r = absolute_stability(SEA(**st["model"], values=st["values"]), witness=False)
        return (
            "absolutely stable" if r.absolutely_stable else "not absolutely stable"
        ), r.eta.value

    before = _version(page)
    page.select_option("#preset", "Ours")
    _settle(page, before)
    assert _absolute(page) == "absolutely stable" == library()[0]
    assert page.locator("#plot-eta path[data-series]").count() == 1
    assert float(page.inner_text("#verdict-eta .v")) == pytest.approx(library()[1], rel=1e-4)
    # a load-side gain that renders the environment too stiffly: not absolutely stable
    before = _version(page)
    page.fill("#model-CL", "kl")
    page.press("#model-CL", "Enter")
    _settle(page, before)
    before = _version(page)
    page.fill("#box-kl", "50000")
    page.press("#box-kl", "Enter")
    _settle(page, before)
    assert _absolute(page) == "not absolutely stable" == library()[0]
    assert "llewellyn" in page.inner_text("#verdict-absolute .why")
    assert page.locator("#plot-eta rect.band").count() >= 1  # the failing band is shaded
    assert "seapass twoport check" in page.inner_text("#twoport-text")
    before = _version(page)
    page.select_option("#preset", "LP")
    _settle(page, before)
    assert page.problems == []


def test_a_bad_expression_is_marked_next_to_its_box(page) -> None:
    page.fill("#model-CL", "kd +* s")
    page.press("#model-CL", "Enter")
    page.wait_for_selector("[data-err='model.CL']:not(:empty)")
    assert "cannot parse" in page.inner_text("[data-err='model.CL']")
    assert "invalid" in page.get_attribute("#model-CL", "class")
    before = _version(page)
    page.fill("#model-CL", "kd")
    page.press("#model-CL", "Enter")
    _settle(page, before)
    assert page.inner_text("[data-err='model.CL']") == ""
    page.fill("#box-kd", "lots")
    page.press("#box-kd", "Enter")
    page.wait_for_selector("[data-err='values.kd']:not(:empty)")
    assert "not a number" in page.inner_text("[data-err='values.kd']")
    before = _version(page)
    page.fill("#box-kd", "2500")
    page.press("#box-kd", "Enter")
    _settle(page, before)
    assert _verdict(page) == "not passive"


def _show_lp_not_passive(pg) -> None:
    """LP with kd above k1: the view the export tests start from, whatever ran before."""
    before = _version(pg)
    pg.select_option("#preset", "LP")
    _settle(pg, before)
    before = _version(pg)
    pg.fill("#box-kd", "2500")
    pg.press("#box-kd", "Enter")
    _settle(pg, before)


def test_exported_design_gives_the_same_verdict_in_analyze(page, tmp_path: Path) -> None:
    from seapass.cli import main

    _show_lp_not_passive(page)  # tests may run in any order (pytest-xdist)
    assert _verdict(page) == "not passive"
    sampled = page.inner_text("#verdict-sampled .v")
    with page.expect_download() as info:
        page.click("#export-design")
    design = tmp_path / info.value.suggested_filename
    info.value.save_as(design)
    out = tmp_path / "report"
    assert main(
        [
            "analyze",
            str(design),
            "--out",
            str(out),
            "--stages",
            "passivity,sampled",
            "--quick",
            "--no-progress",
        ]
    ) in (0, 1)
    cont = json.loads((out / "data" / "passivity.json").read_text())
    assert cont["passive"] is False
    samp = json.loads((out / "data" / "sampled.json").read_text())
    assert json.dumps(samp).count('"passive": true') == 0 and sampled == "not passive"


def test_the_url_reproduces_the_view(page, browser) -> None:
    other = browser.new_page(viewport={"width": 1500, "height": 1300})
    other.set_default_timeout(0)
    other.goto(page.url)
    other.wait_for_selector(IDLE, state="attached")
    a, b = page.evaluate("window.seapass.state()"), other.evaluate("window.seapass.state()")
    assert a == b
    assert _verdict(other) == _verdict(page)
    assert other.inner_text("#interval-text") == page.inner_text("#interval-text")
    other.close()


def test_export_report_runs_analyze(page) -> None:
    page.check("#report-quick")
    page.click("#export-report")
    page.wait_for_selector("#report-status[data-status]")
    assert page.get_attribute("#report-status", "data-status") == "done", page.inner_text(
        "#report-status"
    )
    href = page.get_attribute("#report-link", "href")
    r = page.request.get(page.url.split("#")[0].rstrip("/") + href)
    assert r.status == 200 and "<html" in r.text().lower()


def test_a_box_and_a_latency_in_the_url_reach_the_exported_file(page, browser, tmp_path) -> None:
    """Issue 26: the view's [uncertainty] and delay_time survive the URL and "Export design"."""
    from seapass.model.design_file import load_design

    _show_lp_not_passive(page)  # LP, m = 1, kd = 2500: a controller to delay
    hash_ = page.evaluate(
        """() => window.seapass.encode(Object.assign({}, window.seapass.state(),
             { uncertainty: {m: [0.9, 1.1]}, delay_time: 0.001 }))"""
    )
    other = browser.new_context(accept_downloads=True).new_page()
    other.set_default_timeout(0)
    other.goto(page.url.split("#")[0] + "#" + hash_)
    other.wait_for_selector(IDLE, state="attached")
    st = other.evaluate("window.seapass.state()")
    assert st["delay_time"] == 0.001 and st["uncertainty"] == {"m": [0.9, 1.1]}
    assert "latency 0.001 s" in other.inner_text("#verdict-delay")
    with other.expect_download() as info:
        other.click("#export-design")
    path = tmp_path / info.value.suggested_filename
    info.value.save_as(path)
    design = load_design(path)
    assert design.delay_time == 0.001 and dict(design.uncertainty) == {"m": (0.9, 1.1)}
    assert design.values["kd"] == 2500 and design.CL == "kd"
    other.context.close()


def test_ctrl_c_stops_cleanly(explorer: Explorer, page) -> None:
    code, err = explorer.stop()
    assert code == 0, err
    assert "stopped" in err and "Traceback" not in err
