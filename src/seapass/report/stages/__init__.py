"""The stages of the two reports, grouped by topic.

What lives here: one module per topic; every ``stage_*`` returns a
:class:`~seapass.report.document.Section`.

Paper stages (``stage_*(quick)``, for :func:`seapass.report.reproduce.reproduce`):
:mod:`.tables`, :mod:`.regions`, :mod:`.simulation`, :mod:`.hardware`.
Design stages (``stage_*(design, quick)``, for :func:`seapass.report.analyze.analyze`):
:mod:`.design_passivity`, :mod:`.design_dynamics`, :mod:`.design_hardware`.
"""
