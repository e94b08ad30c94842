"""The docstring examples (run as doctests by ``make test``) cannot pass vacuously.

``np.isclose``/``np.allclose`` default to ``atol=1e-8``, which accepts any two values of a contact
radius in m, a compliance in 1/Pa or a depth: an example that compares such values must say
``atol`` itself (``atol=0`` for a relative comparison).
"""

import re
from pathlib import Path

import contactres

SRC = Path(contactres.__file__).parent
CALL = re.compile(r"np\.(?:isclose|allclose)\(")


def _calls(text: str):
    """Each np.isclose/np.allclose call of a doctest, with its continuation lines."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if ">>>" in line and CALL.search(line):
            call = line
            for more in lines[i + 1 :]:
                if not more.strip().startswith("..."):
                    break
                call += more
            yield i + 1, call


def test_every_doctest_closeness_check_states_its_atol():
    loose = [
        f"{path.relative_to(SRC)}:{n}"
        for path in sorted(SRC.rglob("*.py"))
        for n, call in _calls(path.read_text(encoding="utf-8"))
        if "atol=" not in call
    ]
    assert loose == []


def test_the_guard_sees_a_loose_check():
    text = (
        "    >>> bool(np.isclose(a, b))\n    True\n    >>> np.allclose(a,\n    ...     b, atol=0)\n"
    )
    assert [("atol=" in call) for _, call in _calls(text)] == [False, True]
