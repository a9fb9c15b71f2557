"""The report as a person sees it: headless Chromium loads report.html offline.

Every embedded image must decode, every formula (MathML) must be laid out, no
console message (script error, CSP violation from an attempted network
access) may appear.  Skipped only when
Debian's ``chromium`` is not installed (``make test`` installs it).
"""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from cpu_budget import limit_child_cpu
from seapass.cli import main

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")

pytestmark = pytest.mark.skipif(
    CHROMIUM is None,
    reason="chromium is not installed (apt-get install chromium; make test does it)",
)


def _render(page: Path, tmp: Path) -> tuple[str, str, Path]:
    assert CHROMIUM is not None
    profile = tmp / "profile"
    shot = tmp / "shot.png"
    base = [
        CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
        "--no-first-run", "--disable-background-networking", "--disable-component-update",
        "--disable-sync", f"--user-data-dir={profile}", "--enable-logging=stderr", "--v=0",
        "--virtual-time-budget=10000", "--window-size=1200,3000",
    ]  # fmt: skip
    # chromium's work is bounded by CPU time per process, not by a wall-clock timeout
    limit = limit_child_cpu(300)
    dom = subprocess.run(
        [*base, "--dump-dom", page.as_uri()], capture_output=True, text=True, preexec_fn=limit
    )
    subprocess.run([*base, f"--screenshot={shot}", page.as_uri()], capture_output=True,
                   preexec_fn=limit)  # fmt: skip
    return dom.stdout, dom.stderr, shot


@pytest.fixture(scope="module")
def rendered(tmp_path_factory: pytest.TempPathFactory) -> tuple[str, str, Path, Path]:
    tmp = tmp_path_factory.mktemp("browser")
    out = tmp / "report"
    rc = main(["reproduce", "--out", str(out), "--quick", "--stages", "stiffness,regions",
               "--no-progress"])  # fmt: skip
    assert rc == 0
    dom, log, shot = _render(out / "report.html", tmp)
    return dom, log, shot, out


def test_every_image_loads(rendered: tuple[str, str, Path, Path]) -> None:
    dom, _log, _shot, out = rendered
    body = re.search(r"<body[^>]*>", dom)
    assert body is not None, "chromium produced no DOM"
    total = re.search(r'data-images-total="(\d+)"', body.group(0))
    loaded = re.search(r'data-images-loaded="(\d+)"', body.group(0))
    assert total and loaded, f"the on-load check did not run: {body.group(0)}"
    n_figures = len(list((out / "figures").glob("*.png")))
    assert int(total.group(1)) == n_figures >= 4
    assert loaded.group(1) == total.group(1)
    assert "data-script-errors" not in body.group(0)


def test_formulas_are_laid_out_as_math(rendered: tuple[str, str, Path, Path]) -> None:
    dom, _log, _shot, _out = rendered
    body = re.search(r"<body[^>]*>", dom)
    assert body is not None
    total = re.search(r'data-math-total="(\d+)"', body.group(0))
    laid = re.search(r'data-math-laid-out="(\d+)"', body.group(0))
    assert total and laid, f"the on-load check did not run: {body.group(0)}"
    # MathML, rendered by the browser itself: every formula has a box
    assert int(total.group(1)) >= 5
    assert laid.group(1) == total.group(1)


def test_no_console_messages(rendered: tuple[str, str, Path, Path]) -> None:
    _dom, log, _shot, _out = rendered
    console = [line for line in log.splitlines() if ":CONSOLE" in line]
    assert console == []


def test_screenshot_is_not_blank(rendered: tuple[str, str, Path, Path]) -> None:
    _dom, _log, shot, _out = rendered
    import matplotlib.image as mpimg

    img = mpimg.imread(shot)
    assert img.shape[0] >= 2000 and img.shape[1] >= 1000
    # text, tables and figures: far from a uniform page
    assert float(img[..., :3].std()) > 0.05


def test_page_needs_no_network(rendered: tuple[str, str, Path, Path]) -> None:
    _dom, _log, _shot, out = rendered
    page = (out / "report.html").read_text(encoding="utf-8")
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:|//)""", page)
    assert "<link" not in page
    assert "Content-Security-Policy" in page
