"""Which functions hold one BLAS thread (:func:`contactres._threads.one_blas_thread`), pinned.

The decorator sits on the entry of each batched small-matrix computation (issue 31, point 1).
A helper inserted between the decorator and its function once moved the decorator onto the
helper, silently: the tangential table then ran on OpenBLAS's default threads. The list below
is the intended one; the second test checks the context is open inside the table's own work.
"""

from __future__ import annotations

import re
from pathlib import Path

import contactres
from contactres import Material, _threads
from contactres.dynamic import _tangential_table, prepare_tangential

DECORATED = {
    ("analysis/_coating.py", "apply_coating"),
    ("dynamic/_normal_stiffness.py", "evaluate_models"),
    ("dynamic/_normal_stiffness.py", "contact_displacement"),
    ("dynamic/_normal_stiffness.py", "contact_pressure"),
    ("dynamic/_dcsf.py", "dcsf_models"),
    ("dynamic/_tangential_galerkin.py", "tangential_per_a"),
    ("dynamic/_table.py", "kernel_table"),
    ("dynamic/_layered_punch.py", "layered_punch_stiffness"),
    ("dynamic/_tangential_table.py", "prepare_tangential"),
}
_DECORATED_DEF = re.compile(r"^@one_blas_thread\(\)[^\n]*\n(?:@[^\n]*\n)*def (\w+)", re.M)


def test_the_decorator_sits_on_the_intended_functions():
    root = Path(contactres.__file__).parent
    found = {
        (path.relative_to(root).as_posix(), name)
        for path in root.rglob("*.py")
        for name in _DECORATED_DEF.findall(path.read_text(encoding="utf-8"))
    }
    assert found == DECORATED


def test_the_tangential_table_is_prepared_inside_the_context(monkeypatch):
    depths = []
    tail = _tangential_table.kernel_tail

    def spy(m):
        depths.append(_threads._OPEN.depth)
        return tail(m)

    monkeypatch.setattr(_tangential_table, "kernel_tail", spy)
    prepare_tangential(Material.isotropic(70e9, 0.3, 2700.0), rtol=1e-3)
    assert depths and all(d >= 1 for d in depths)
