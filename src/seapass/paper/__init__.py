"""What is specific to the paper: Tables I and II compared, and the simulation study.

What lives here: [`tables`][seapass.paper.tables] (the printed rows next to what
seapass derives, each bound classified), [`tablefmt`][seapass.paper.tablefmt] (text,
Markdown and LaTeX renderings of them) and [`simstudy`][seapass.paper.simstudy]
(Sec. V: LP, APD and Ours tuned at one load mass, tested at three).

May import: [`seapass.errors`][seapass.errors], [`seapass.progress`][seapass.progress], [`seapass.files`][seapass.files], [`seapass.model`][seapass.model],
[`seapass.analysis`][seapass.analysis], [`seapass.sim`][seapass.sim], [`seapass.tuning`][seapass.tuning].
"""

from .simstudy import SimulationStudy, run_simulation_study
from .tables import PAPER_ROWS, PaperRow, TableRow, build_tables

__all__ = [
    "PAPER_ROWS",
    "PaperRow",
    "SimulationStudy",
    "TableRow",
    "build_tables",
    "run_simulation_study",
]
