"""The interactive design explorer behind ``seapass explore``: a local web app.

What lives here: [`state`][seapass.explore.state] (the view the browser sends, validated
field by field), [`sliders`][seapass.explore.sliders] (which parameters are gains, their
default ranges and scales), [`panels`][seapass.explore.panels] (one pure function per panel, cached;
the delay margin's in [`delay_panel`][seapass.explore.delay_panel]),
[`pool`][seapass.explore.pool] (killable worker processes that compute the panels),
[`presets`][seapass.explore.presets] (the catalog's designs as views),
[`robustview`][seapass.explore.robustview] (the box verdict of ``[uncertainty]``),
[`reports`][seapass.explore.reports] ("Export report": ``seapass analyze`` in a child
process) and [`server`][seapass.explore.server] (the Starlette app on 127.0.0.1, needs the
``explore`` extra), with the page, its script and style sheet in ``static/``.

May import: [`seapass.errors`][seapass.errors], [`seapass.files`][seapass.files], [`seapass.exact`][seapass.exact],
[`seapass.model`][seapass.model], [`seapass.analysis`][seapass.analysis],
[`seapass.ports`][seapass.ports], [`seapass.delay`][seapass.delay], [`seapass.sim`][seapass.sim], [`seapass.batch`][seapass.batch],
[`seapass.sampled`][seapass.sampled], [`seapass.robust`][seapass.robust] (the box verdict);
starlette and uvicorn in `server` only.
"""

from .panels import KINDS, compute
from .pool import PanelPool
from .presets import presets
from .state import ExploreState
from .validation import StateCheck, check_state

__all__ = ["KINDS", "ExploreState", "PanelPool", "StateCheck", "check_state", "compute", "presets"]
