"""Reports: the document model, its renderings, the stage pipeline, ``reproduce`` and ``analyze``.

What lives here: :mod:`~seapass.report.document` (sections, tables, figures,
findings), :mod:`~seapass.report.render` (``report.html`` and ``report.md``),
:mod:`~seapass.report.output` (writing the report directory),
:mod:`~seapass.report.pipeline` (the stage runner shared by both reports),
:mod:`~seapass.report.reproduce` (the paper), :mod:`~seapass.report.analyze`
(a user's design) and :mod:`seapass.report.stages` (the stages, by topic).

May import: everything in :mod:`seapass.plot` and below.
"""

from .analyze import analyze
from .document import Report, Section
from .output import write_report
from .reproduce import reproduce

__all__ = ["Report", "Section", "analyze", "reproduce", "write_report"]
