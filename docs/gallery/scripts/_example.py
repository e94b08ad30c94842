"""The paper 2 analysis of the bundled example, run once per documentation build.

Every plot directive runs its script on its own, but in one Python process: the scripts of
paper 2's Figs. 4, 5, 7, 8 and Table 1 import :func:`results` from here, and the module (with its
cached analysis, ~8 s) stays imported between them. Run alone, a script analyses once too.
"""

from functools import cache
from pathlib import Path

import contactres

#: The bundled example: the sweeps of ``contactres qcm analyze`` and ``contactres demo``.
EXAMPLE = Path(contactres.__file__).parent / "data" / "example_sweeps.csv"


@cache
def results():
    """:func:`contactres.analyze` of the example, without the bootstrap (faster, same values)."""
    table = contactres.read_sweeps(EXAMPLE)
    return contactres.analyze(table, settings=contactres.AnalysisSettings(bootstrap=0))
