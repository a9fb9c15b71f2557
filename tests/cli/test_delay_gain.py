"""``bound`` / ``region`` at a fixed delay, ``delay-margin --range`` and ``plot`` with a delay:
end to end through ``main``, the data behind each figure, and bad input (one ``error:``
line, exit 2)."""

from __future__ import annotations

import contextlib
import io
import json

import pytest

from seapass.cli import main
from seapass.delay.margin import delay_margin
from seapass.delay.passivity import delayed_passivity
from seapass.model.sea import SEA
from seapass.outcome import Outcome

WALL = ["--D1", "k1", "--CA", "kd*exp(-tau*s)", "--set", "m=1", "--set", "b=10",
        "--set", "k1=1000"]  # fmt: skip
OURS = ["--D1", "k1 + b1*s", "--CA", "(kd + bd*s)*exp(-tau*s)", "--set", "m=1", "--set", "b=10",
        "--set", "k1=1000", "--set", "b1=20", "--set", "bd=25"]  # fmt: skip


def run(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = int(exc.code or 0)
    e = err.getvalue()
    assert "Traceback" not in e
    return code, out.getvalue(), e


def test_bound_with_a_delay_json_and_text():
    code, out, err = run(["bound", "kd", *WALL, "--set", "tau=0.002", "--range", "kd=0:8000",
                          "--points", "5", "--json"])  # fmt: skip
    assert code == 0 and err == ""
    d = json.loads(out)
    assert d["param"] == "kd" and d["range"] == [0, 8000] and d["outcome"] == "passive"
    ((a, b),) = d["intervals"]
    assert a == 0 and b <= 5000 <= d["edges"][0][1][1]  # kd <= b/tau, end enclosed
    assert d["delay"] == {"name": "tau", "tau": 0.002} and d["undecided"] == []
    code, out, _ = run(["bound", "kd", *WALL, "--set", "tau=0.002", "--range", "kd=0:8000",
                        "--points", "5"])  # fmt: skip
    assert code == 0 and out.startswith("passive for 0 <= kd <= ")
    printed = float(out.split("<= kd <= ")[1].split()[0])
    sea = SEA(D1="k1", CA="kd*exp(-tau*s)", values=dict(m=1, b=10, k1=1000, kd=printed, tau=0.002))
    assert delayed_passivity(sea).outcome is Outcome.PASSIVE  # the printed end is passive


def test_region_with_a_delay_follows_b_over_tau(tmp_path):
    fig = tmp_path / "map.png"
    code, out, err = run(["region", "b", "kd", *WALL[:4], "--set", "m=1", "--set", "k1=1000",
                          "--set", "tau=0.002", "--range", "b=5:10", "--range", "kd=0:8000",
                          "--points", "2", "--json", "--plot", str(fig)])  # fmt: skip
    assert code == 0, err
    d = json.loads(out)
    assert d["x"] == [5.0, 10.0] and d["outcome"] == "passive"
    for b, ivs, edges in zip(d["x"], d["intervals"], d["edges"], strict=True):
        ((lo, hi),) = ivs
        assert lo == 0 and hi <= b / 0.002 <= edges[0][1][1]
    assert fig.stat().st_size > 0


def test_delay_margin_over_a_gain_matches_delay_margin_per_gain(tmp_path):
    fig = tmp_path / "region.png"
    code, out, err = run(["delay-margin", "tau", *OURS[:2], "--CA", "(kd + bd*s)*exp(-tau*s)",
                          *OURS[4:], "--range", "kd=100:3000", "--points", "3", "--json",
                          "--plot", str(fig)])  # fmt: skip
    assert code == 0, err
    d = json.loads(out)
    assert d["gains"] == [100.0, 1550.0, 3000.0] and fig.stat().st_size > 0
    sea = SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
              values=dict(m=1, b=10, k1=1000, b1=20, kd=None, bd=25, tau=None))  # fmt: skip
    for k, r in zip(d["gains"], d["results"], strict=True):
        ref = delay_margin(sea.with_values(kd=k), "tau", rtol=1e-6)
        assert r["tau_star"] == list(ref.tau_star)
    stars = [r["tau_star"][0] for r in d["results"]]
    assert stars == sorted(stars, reverse=True)  # a stiffer virtual spring tolerates less
    # consistent with the bound at a fixed delay: tau*(3000) > 0.01 > tau*(3500)
    code, out, _ = run(["bound", "kd", *OURS, "--set", "tau=0.01", "--range", "kd=0:1e4", "--json"])
    ((_, end),) = json.loads(out)["intervals"]
    assert d["results"][2]["tau_star"][0] > 0.01 and 3000 < end


def test_plot_real_with_a_delay_shows_certified_bands(tmp_path):
    fig = tmp_path / "real.png"
    code, out, err = run(["plot", "real", *OURS, "--set", "kd=3500", "--set", "tau=0.01",
                          "--json", "--plot", str(fig)])  # fmt: skip
    assert code == 0, err
    d = json.loads(out)
    assert d["delay"] == {"name": "tau", "tau": 0.01} and d["negative_bands"]
    w = delayed_passivity(SEA(D1="k1 + b1*s", CA="(kd + bd*s)*exp(-tau*s)",
                              values=dict(m=1, b=10, k1=1000, b1=20, kd=3500, bd=25, tau=0.01))).omega  # fmt: skip
    assert any(a <= w <= b for a, b in d["negative_bands"])  # the witness lies in a band
    for a, b in d["negative_bands"]:  # the sampled curve agrees inside the proven bands
        inside = [r for x, r in zip(d["omega"], d["real"], strict=True) if a < x < b]
        assert all(r < 0 for r in inside)
    assert fig.stat().st_size > 0


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["bound", "kp", *WALL, "--set", "tau=0.002"], "kp"),
        (["bound", "kd", *WALL, "--set", "tau=-0.002"], ">= 0"),
        (["bound", "kd", *WALL], "tau"),
        (["bound", "kd", "--D1", "k1", "--CA", "kd", "--set", "m=1", "--set", "b=10",
          "--set", "k1=1000", "--points", "5"], "--points"),
        (["region", "b", "kd", *WALL[:4], "--set", "m=1", "--set", "k1=1000",
          "--set", "tau=-1"], ">= 0"),
        (["delay-margin", "tau", *OURS, "--range", "zz=1:2"], "--range zz"),
        (["delay-margin", "tau", *OURS, "--set", "kd=1", "--range", "kd=1:2"], "--range gain"),
        (["delay-margin", "tau", *OURS, "--set", "kd=1", "--points", "3"], "--range"),
        (["plot", "bode", *OURS, "--set", "kd=1", "--set", "tau=0.01"], "real or nyquist"),
    ],
)  # fmt: skip
def test_bad_input_is_one_error_line(argv, words):
    code, _out, err = run(argv)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and lines[0].startswith("error:"), err
    assert words in lines[0], lines[0]
