"""Controllers handed to hardware: generated C99 with the passivity envelope built in.

What lives here: [`realization`][seapass.export.realization] (the deployed
controller as exact difference equations), [`envelope`][seapass.export.envelope]
(the sampled-data verdict and the certified interval of each tunable gain),
[`deployment`][seapass.export.deployment] (the two together with saturation and
the delay line: everything decided before a file is written), [`latency`][seapass.export.latency]
(the guard that the delay margin τ* covers the loop latency ``[control] delay_time``),
[`robust_envelope`][seapass.export.robust_envelope] (``robust=True``: the guards certified
at the sampled rate for every plant of a box),
[`c_code`][seapass.export.c_code] (``seapass_ctrl.h`` / ``seapass_ctrl.c`` from
Jinja2 templates shipped in ``export/templates``), [`ctext`][seapass.export.ctext]
(the one escaping of user text into C: comments, strings, identifiers) and
[`compiled`][seapass.export.compiled] (compile the generated C with the system
compiler and run it from Python, against the Python controller or the twin).

May import: everything in [`seapass.rig`][seapass.rig] and below.

Examples
--------
>>> import tempfile
>>> from seapass.model.design_file import parse_design
>>> d = parse_design({"name": "lp", "model": {"D1": "k1 + b1*s", "CL": "kd"},
...     "parameters": {"m": 1.0, "b": 10.0, "k1": 1000.0, "b1": 30.0, "kd": 500.0},
...     "control": {"rate": 500.0}})
>>> with tempfile.TemporaryDirectory() as out:
...     res = export_c(d, out, force_limit=100.0)
...     print(res.header.name, res.source.name, res.deployment.certified)
seapass_ctrl.h seapass_ctrl.c True
"""

from .c_code import ExportResult, c_literal, export_c, render_c
from .compiled import (
    CompiledController,
    VerifyResult,
    compile_c,
    equivalence_inputs,
    find_c_compiler,
    reference_commands,
    verify_c,
)
from .deployment import Deployment, plan_deployment
from .envelope import GainEnvelope, inward_interval
from .realization import FilterSpec

__all__ = [
    "CompiledController",
    "Deployment",
    "ExportResult",
    "FilterSpec",
    "GainEnvelope",
    "VerifyResult",
    "c_literal",
    "compile_c",
    "equivalence_inputs",
    "export_c",
    "find_c_compiler",
    "inward_interval",
    "plan_deployment",
    "reference_commands",
    "render_c",
    "verify_c",
]
