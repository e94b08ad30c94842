"""Helpers shared by the command-line tests: run a command, check a one-line error."""

from click.testing import CliRunner

from contactres.cli import main


def run(*args):
    """Invoke ``contactres ARGS`` in-process (arguments converted to text)."""
    return CliRunner().invoke(main, [str(a) for a in args])


#: What a figure's PNG holds in a test that does not draw it (:func:`figures_not_drawn`).
STAND_IN = b"not drawn\n"


def figures_not_drawn(monkeypatch):
    """Build every figure but draw none: each PNG a command writes (a file, or an image of its
    report page) holds :data:`STAND_IN`. For tests about which files a command writes and the
    numbers in them, not about pixels: drawing is most of a report's time (issue 31), and the
    figures are drawn by the tests that look at them (tests/test_png.py, tests/report, the
    demo's and each command's own report test)."""
    from contextlib import nullcontext
    from pathlib import Path

    from contactres import _png

    def stand_in(fig, target, dpi, *, tight=False):
        with open(target, "wb") if isinstance(target, (str, Path)) else nullcontext(target) as f:
            f.write(STAND_IN)

    monkeypatch.setattr(_png, "print_png", stand_in)


def one_line_error(r, *words):
    """Assert a user error: exit 2, one line of output in all, naming every one of ``words``,
    with no traceback and no numpy repr; return that line."""
    assert r.exit_code == 2, r.output
    lines = r.output.strip().splitlines()
    assert len(lines) == 1, r.output
    assert ": error: " in lines[0] and "internal error" not in lines[0]
    assert "Traceback" not in r.output and "np.float64" not in r.output
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]


def invoke(command, base, option, value):
    """Run ``command`` (a list of words) with the options ``base`` and ``option`` = ``value``."""
    options = {**base, option: value}
    return run(*command, *[x for kv in options.items() for x in kv])


def option_names(command) -> set[str]:
    """The options of a click command, but --help."""
    return {p.opts[0] for p in command.params if p.opts[0] != "--help"}


#: The example files whose listed command (``contactres examples``) test_cli_examples.py runs
#: from a folder of the copies without the optional extras; test_cli_help.py does not run a
#: help's example that is one of these command lines again.
LISTED_COMMANDS_RUN = (
    "example_rum.csv",
    "example_afm.csv",
    "example_qcmd.csv",
    "example_cu_kstar.csv",
)
