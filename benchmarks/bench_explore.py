"""Latency of ``seapass explore``: slider release to every panel updated, in headless Chromium.

Starts the real command (``seapass explore --port 0 --no-browser``), opens the
page in Debian's chromium through Playwright and, for each of the paper's
designs (LP, APD, Ours: the presets from the example design files, with their
control period, delay and filter), clicks the ``kd`` slider track at seeded
random positions, as a person would.  The page itself times each change: from
the ``input`` event of the click (``event.timeStamp``) to the animation frame
after the last of the eight panels (continuous and sampled verdicts, passive
interval, 2-D region, frequency response, step response, destabilizing
environment, two-port absolute stability with η) has been drawn for the new value.  Every click lands at least a
fifth of the track away from the previous value, so no answer comes from the
cache of the dragged gain itself (the interval and the region legitimately do).

The designs are the example files (``examples/lp.toml``, ``apd.toml``,
``ours.toml``): tuned gains, 500 Hz control, and for Ours the bench's
one-sample delay and 50 Hz velocity filter.  The peer is the command line a
designer used before: one ``seapass check`` process for the same design
(start-up included, and it answers one of the eight panels), timed in the same run.

Usage::

    .venv/bin/python benchmarks/bench_explore.py                 # 20 clicks per design
    .venv/bin/python benchmarks/bench_explore.py --clicks 5 --screenshot docs/img/explore.png
"""

from __future__ import annotations

import argparse
import json
import os
import random
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]  # fmt: skip
LAUNCH = "import sys; from seapass.cli import main; sys.exit(main(sys.argv[1:]))"
#: The paper's designs as the example files give them: tuned gains, 500 Hz control (Ours
#: with the bench's one-sample delay and 50 Hz velocity filter).
DESIGNS = {"LP": "examples/lp.toml", "APD": "examples/apd.toml", "Ours": "examples/ours.toml"}
PANELS = ("verdict", "sampled", "interval", "region", "frequency", "step", "witness", "twoport")


def _idle(page: Any, before: str) -> None:
    sel = f"body[data-busy='0']:not([data-version='{before}'])"
    page.wait_for_selector(sel, state="attached", timeout=60_000)


def _click_kd(page: Any, frac: float) -> dict[str, Any]:
    before = page.get_attribute("body", "data-version")
    box = page.locator("#slider-kd").bounding_box()
    page.mouse.click(box["x"] + 8 + frac * (box["width"] - 16), box["y"] + box["height"] / 2)
    _idle(page, before)
    timing = page.evaluate("window.seapass.timings[window.seapass.timings.length - 1]")
    timing["kd"] = page.evaluate("window.seapass.state().values.kd")
    timing["passive"] = page.inner_text("#verdict-continuous .v") == "passive"
    return dict(timing)


def _drag_kd(page: Any, frac: float) -> dict[str, Any]:
    """Press on the thumb, drag to ``frac`` in ten moves, release; time from the release."""
    box = page.locator("#slider-kd").bounding_box()
    y = box["y"] + box["height"] / 2
    x0 = box["x"] + 8 + int(page.input_value("#slider-kd")) / 1000 * (box["width"] - 16)
    page.mouse.move(x0, y)
    page.mouse.down()
    page.mouse.move(box["x"] + 8 + frac * (box["width"] - 16), y, steps=10)
    page.mouse.up()
    v = page.evaluate("window.seapass.version()")
    page.wait_for_selector(
        f"body[data-busy='0'][data-version='{v}']", state="attached", timeout=60_000
    )
    release = page.evaluate("window.seapass.releases[window.seapass.releases.length - 1]")
    done = page.evaluate(f"window.seapass.timings.find((t) => t.version === {v})")
    return {
        "ms": max(0.0, done["at"] - release["t"]),
        "kinds": done["kinds"],
        "passive": page.inner_text("#verdict-continuous .v") == "passive",
    }


def _cli_peer(design: str, root: Path) -> float:
    """Seconds of one ``seapass check`` process on the same design (start-up included)."""
    values = {"LP": ["--D1", "k1", "--CL", "kd"], "APD": ["--D1", "k1", "--CA", "kd + bd*s"],
              "Ours": ["--D1", "k1 + b1*s", "--CA", "kd + bd*s"]}[design]  # fmt: skip
    sets = [
        "--set",
        "m=1",
        "--set",
        "b=10",
        "--set",
        "k1=1000",
        "--set",
        "kd=1000",
        "--set",
        "bd=100",
    ]
    if design == "Ours":
        sets += ["--set", "b1=300"]
    if design == "LP":
        sets = sets[:-2]
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", LAUNCH, "check", *values, *sets], check=True,
                   capture_output=True, cwd=root)  # fmt: skip
    return time.perf_counter() - t0


def _start(args: list[str], root: Path) -> tuple[subprocess.Popen[str], str]:
    server = subprocess.Popen(
        [sys.executable, "-c", LAUNCH, "explore", *args, "--port", "0", "--no-browser"],
        stdout=subprocess.PIPE,
        text=True,
        cwd=root,
    )
    assert server.stdout is not None
    line = server.stdout.readline()
    if "serving" not in line:
        server.kill()
        raise RuntimeError(f"seapass explore did not start: {line!r}")
    return server, line.split()[3]


def _open(browser: Any, url: str) -> Any:
    page = browser.new_page(viewport={"width": 1500, "height": 1300})
    page.goto(url)
    page.wait_for_selector(
        "body[data-busy='0']:not([data-version='0'])", state="attached", timeout=120_000
    )
    return page


def _summary(samples: list[dict[str, Any]]) -> dict[str, Any]:
    ms = sorted(s["ms"] for s in samples)
    out: dict[str, Any] = {
        "median_ms": statistics.median(ms),
        "p90_ms": ms[min(len(ms) - 1, int(0.9 * len(ms)))],
        "max_ms": ms[-1],
        "clicks": len(ms),
        "panel_median_ms": {k: statistics.median(s["kinds"][k] for s in samples) for k in PANELS},
    }
    bad = [s["ms"] for s in samples if not s["passive"]]
    out["not_passive"] = len(bad)
    out["not_passive_median_ms"] = statistics.median(bad) if bad else None
    return out


def run(clicks: int = 20, *, screenshot: Path | None = None, seed: int = 1) -> dict[str, Any]:
    """Measure; return ``{"designs": {name: {...}}, "cpus", "load_*"}`` (times in ms)."""
    from playwright.sync_api import sync_playwright

    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        raise RuntimeError("chromium is not installed (apt-get install chromium)")
    root = Path(__file__).resolve().parent.parent
    out: dict[str, Any] = {"designs": {}, "cpus": os.cpu_count(), "load_before": os.getloadavg()}
    rng = random.Random(seed)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=CHROMIUM_ARGS)
        for design, path in DESIGNS.items():
            server, url = _start([path], root)
            try:
                page = _open(browser, url)
                samples: list[dict[str, Any]] = []
                for i in range(clicks + 3):  # the first three warm the compiled kernels
                    cur = int(page.input_value("#slider-kd")) / 1000
                    frac = cur
                    while abs(frac - cur) < 0.2:
                        frac = rng.uniform(0.03, 0.97)
                    t = _click_kd(page, frac)
                    if i >= 3:
                        samples.append(t)
                drags = []
                for _ in range(max(3, clicks // 2)):
                    cur = int(page.input_value("#slider-kd")) / 1000
                    frac = cur
                    while abs(frac - cur) < 0.2:
                        frac = rng.uniform(0.03, 0.97)
                    drags.append(_drag_kd(page, frac))
                out["designs"][design] = {
                    **_summary(samples),
                    "drag": _summary(drags),
                    "cli_check_s": _cli_peer(design, root),
                }
                page.close()
            finally:
                server.terminate()
                server.wait(timeout=30)
        if screenshot is not None:
            take_screenshot(browser, screenshot, root)
        browser.close()
    out["load_after"] = os.getloadavg()
    return out


def take_screenshot(browser: Any, path: Path, root: Path) -> None:
    """The docs' picture: LP with kd = 2000 > k1, every panel showing why it is not passive."""
    server, url = _start(["LP"], root)
    try:
        page = _open(browser, url)
        before = page.get_attribute("body", "data-version")
        page.fill("#box-kd", "2000")
        page.press("#box-kd", "Enter")
        _idle(page, before)
        page.wait_for_timeout(2500)  # let the 2-D region refine
        path.parent.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(path), full_page=True)
        page.close()
    finally:
        server.terminate()
        server.wait(timeout=30)


def markdown(result: dict[str, Any]) -> str:
    """A table for ``docs/benchmarks.md``."""
    lines = [
        "| design | median | p90 | max | clicks | median when not passive | slowest panel (median) "
        "| one `seapass check` | ratio |",
        "|---|---:|---:|---:|---:|---:|---|---:|---:|",
    ]
    for name, d in result["designs"].items():
        slow = max(d["panel_median_ms"], key=d["panel_median_ms"].get)
        bad = d["not_passive_median_ms"]
        bad_txt = "—" if bad is None else f"{bad:.0f} ms ({d['not_passive']} clicks)"
        lines.append(
            f"| {name} | {d['median_ms']:.0f} ms | {d['p90_ms']:.0f} ms | {d['max_ms']:.0f} ms | "
            f"{d['clicks']} | {bad_txt} | "
            f"{slow} {d['panel_median_ms'][slow]:.0f} ms | "
            f"{d['cli_check_s']:.2f} s | {1000 * d['cli_check_s'] / d['median_ms']:.0f}x |"
        )
    lines += [
        "",
        "Drag and release (press on the thumb, ten moves, release; timed from the release, "
        "the panels updating live during the drag):",
        "",
        "| design | median | p90 | max | drags |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, d in result["designs"].items():
        g = d["drag"]
        lines.append(
            f"| {name} | {g['median_ms']:.0f} ms | {g['p90_ms']:.0f} ms | {g['max_ms']:.0f} ms "
            f"| {g['clicks']} |"
        )
    lb, la = result["load_before"], result["load_after"]
    lines.append("")
    lines.append(
        f"{result['cpus']} CPUs; load average {lb[0]:.1f} before, {la[0]:.1f} after the run."
    )
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--clicks", type=int, default=20)
    ap.add_argument("--screenshot", type=Path)
    ap.add_argument("--json", type=Path, help="also write the raw numbers here")
    args = ap.parse_args()
    result = run(args.clicks, screenshot=args.screenshot)
    print(markdown(result))
    if args.json:
        args.json.write_text(json.dumps(result, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
