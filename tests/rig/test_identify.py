"""`rig fit --rig-out`: the template's comments kept, the log named relative to the output."""

from __future__ import annotations

import contextlib
import io
import json
import tomllib
from pathlib import Path

import pytest

from seapass.cli import main
from seapass.rig.log import chirp_command, twin_log
from seapass.rig.packaged import rig_template
from seapass.rig.rigfile import paper_rig, parse_rig


@pytest.fixture(scope="module")
def chirp_csv(tmp_path_factory: pytest.TempPathFactory) -> Path:
    rig = paper_rig()
    log = twin_log(rig, chirp_command(rig.control.rate, duration=4.0), load_mass=0.1, seed=3)
    path = tmp_path_factory.mktemp("bench") / "chirp.csv"
    path.write_text(log.to_csv())
    return path


def test_rig_out_keeps_comments_and_names_the_log_relatively(
    tmp_path: Path, chirp_csv: Path
) -> None:
    template = rig_template()
    rig = tmp_path / "myrig.toml"
    rig.write_text(template)
    out = tmp_path / "fitted" / "fitted.toml"
    out.parent.mkdir()
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf), contextlib.redirect_stderr(io.StringIO()):
        code = main(["rig", "fit", str(chirp_csv.resolve()), "--rig", str(rig),
                     "--rig-out", str(out), "--json"])  # fmt: skip
    assert code == 0
    fit = json.loads(buf.getvalue())["parameters"]
    text = out.read_text()
    # every comment of the template is still there, in order
    comments = [ln[ln.index("#") :] for ln in template.splitlines() if "#" in ln]
    comments.append("# written by seapass rig fit; read by --robust")  # the fit's [intervals]
    assert [ln[ln.index("#") :] for ln in text.splitlines() if "#" in ln] == comments
    fitted = parse_rig(tomllib.loads(text))
    assert fitted.damper.b1 == fit["b1"]["value"]
    assert fitted.transmission.viscous == fit["b"]["value"]
    # the description names the log relative to the fitted file, never by an absolute path
    assert str(tmp_path) not in text and "/" + chirp_csv.parent.name not in fitted.description[:1]
    rel = fitted.description.split("fitted from ")[1].rstrip(")")
    assert not Path(rel).is_absolute()
    assert (out.parent / rel).resolve() == chirp_csv.resolve()
