"""Reports: the document model, its renderings, the stage pipeline, ``reproduce`` and ``analyze``.

What lives here: [`document`][seapass.report.document] (sections, tables, figures,
findings and their kinds), [`render`][seapass.report.render] (``report.html`` and
``report.md`` from the jinja2 templates in ``templates/``), [`formula`][seapass.report.formula]
(formulas in plain text shown as MathML, decimal transfer functions),
[`output`][seapass.report.output] (writing the report directory),
[`pipeline`][seapass.report.pipeline] (the stage runner shared by both reports),
[`reproduce`][seapass.report.reproduce] (the paper), [`analyze`][seapass.report.analyze]
(a user's design) and [`seapass.report.stages`][seapass.report.stages] (the stages, by topic).

May import: everything in [`seapass.plot`][seapass.plot] and below.
"""

from .analyze import analyze
from .document import Report, Section
from .output import write_report
from .reproduce import reproduce

__all__ = ["Report", "Section", "analyze", "reproduce", "write_report"]
