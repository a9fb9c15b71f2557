"""The stages of the two reports, grouped by topic.

What lives here: one module per topic; every ``stage_*`` returns a
[`Section`][seapass.report.document.Section].

Paper stages (``stage_*(quick)``, for [`seapass.report.reproduce.reproduce`][seapass.report.reproduce.reproduce]):
`.tables`, `.regions`, `.simulation`, `.hardware`.
Design stages (``stage_*(design, quick)``, for [`seapass.report.analyze.analyze`][seapass.report.analyze.analyze]):
`.design_passivity`, `.design_frequency`, `.design_twoport`, `.design_dynamics`,
`.design_hardware`.
"""
