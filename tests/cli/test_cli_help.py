"""Every command but ``figures``: defaults shown one way, units stated, an example that runs,
progress on a terminal, CSV without floating-point noise."""

import re
import shlex

import click
import pytest
from cli_checks import LISTED_COMMANDS_RUN, figures_not_drawn, run

from contactres.cli import main

# A unit after the quantity ("..., Hz", "(m^2)", "N/m") or "dimensionless".
UNIT = re.compile(r"(dimensionless|degrees|\b(m|N|Pa|Hz|s|kg/s|N/m|m/V|m\^2|Ω|kg m\^-2 s\^-1)\b)")
NUMERIC = ("FLOAT", "INTEGER", "START:STOP:NUM", "integer range")


def _commands(group=main, path=()):
    """(words, command) of every command, the figures group left out (its own polish)."""
    for name, command in sorted(group.commands.items()):
        if name == "figures":
            continue
        if isinstance(command, click.Group):
            yield from _commands(command, (*path, name))
        else:
            yield (*path, name), command


COMMANDS = list(_commands())
IDS = [" ".join(words) for words, _ in COMMANDS]


def _options(command):
    return [p for p in command.params if isinstance(p, click.Option) and p.opts[0] != "--help"]


@pytest.mark.parametrize("words, command", COMMANDS, ids=IDS)
def test_defaults_shown_one_way_and_units_stated(words, command):
    for p in _options(command):
        if p.is_flag:
            continue
        if isinstance(p.default, (str, int, float)) and not isinstance(p.default, bool):
            assert p.show_default is True, (words, p.opts)
        # A default the option has no value for is shown the same way: show_default="...".
        assert "default:" not in p.help.lower() and "(default" not in p.help.lower(), p.opts
        if p.type.name in NUMERIC:
            assert UNIT.search(p.help), (words, p.opts, p.help)
    # A value is shown as a value, [default: 5e6], whether click or a later file applies it;
    # parentheses are kept for a described default, [default: (all in the file)].
    for described in re.findall(
        r"\[default: \(([^)]*)\)\]", " ".join(run(*words, "--help").output.split())
    ):
        assert not re.fullmatch(r"[-+0-9.eE]+", described), (words, described)


def _example(words):
    """The command line of the 'Example:' paragraph of ``words --help`` (wrapped lines
    joined)."""
    text = run(*words, "--help").output
    match = re.search(r"^\s*Example: (contactres .*?)(?:\n\s*\n|\Z)", text, re.M | re.S)
    assert match, f"no 'Example:' line in 'contactres {' '.join(words)} --help'"
    # Printed as written (click's \b): one line, or lines joined by a shell's " \" as a user
    # pastes them; a line click had wrapped (e.g. "--tip-" / "radius") would not survive.
    lines = match.group(1).splitlines()
    assert all(line.rstrip().endswith(" \\") for line in lines[:-1]), lines
    return shlex.split(" ".join(line.rstrip().removesuffix("\\") for line in lines))


@pytest.mark.parametrize("words", [w for w, _ in COMMANDS], ids=IDS)
def test_every_help_has_an_example(words):
    example = _example(words)
    assert example[: 1 + len(words)] == ["contactres", *words]


# The demo runs ~10 s and writes the figures: its example is run by 'make demo', not here.
SLOW = {("demo",): "about 10 s (paper figures); 'make demo' runs it"}


@pytest.mark.parametrize("words", [w for w, _ in COMMANDS], ids=IDS)
def test_every_example_runs(words, tmp_path, monkeypatch):
    """Run verbatim as an installed user would: from a folder holding the example files (the
    help says 'contactres examples --copy .' puts them there), not from the repository."""
    if words in SLOW:
        pytest.skip(SLOW[words])
    from contactres.examples import EXAMPLES, copy_examples

    example = _example(words)
    args = example[1:]
    assert not any("src/contactres" in a for a in args), "an example names the source tree"
    listed = [shlex.split(EXAMPLES[name].command) for name in LISTED_COMMANDS_RUN]
    if example in listed:  # the same command line runs in test_cli_examples.py, without extras
        return
    copy_examples(tmp_path / "work")
    monkeypatch.chdir(tmp_path / "work")
    if "--out" in args:  # write into the test's folder, not the repository
        i = args.index("--out") + 1
        args[i] = str(tmp_path / args[i])
    for option in ("--fits", "--copy"):
        if option in args:
            i = args.index(option) + 1
            args[i] = str(tmp_path / args[i])
    if words == ("qcm", "analyze"):
        args += ["--no-figures", "--bootstrap", "0"]  # the example, faster (~2 s)
    if words == ("afm", "map"):
        # The demo maps this file with these constants (jobs.demo.CR_MAP) and
        # tests/cli/test_cli.py::test_demo_writes_folder draws its figures: not again here.
        figures_not_drawn(monkeypatch)
    r = run(*args)
    assert r.exit_code == 0, r.output


def test_crystals_plain_fits_100_columns_and_csv_keeps_every_column():
    r = run("crystals")
    assert r.exit_code == 0, r.output
    assert max(len(line) for line in r.stdout.splitlines()) <= 100
    assert "Cu" in r.stdout and "Simmons" in r.stdout and "M111_GPa" in r.stdout
    header = run("crystals", "--format", "csv").stdout.splitlines()[0].split(",")
    assert header[0] == "name" and header[-1] == "source" and "M001_GPa" in header


def test_progress_steps_on_a_terminal_only(monkeypatch):
    from contactres.cli import _common

    args = ("dcsf", "--crystal", "Cu", "--ka", "0.5", "--format", "csv")
    assert "step" not in run(*args).stderr  # piped: the CSV alone
    monkeypatch.setattr(_common, "_interactive", lambda: True)
    r = run(*args)
    assert r.exit_code == 0, r.output
    assert "contactres dcsf: step" in r.stderr and "step" not in r.stdout


NOISE = re.compile(r"\d\.\d{15,}")


def test_no_floating_point_noise_in_csv(tmp_path):
    data = "src/contactres/data"
    # Written files only: the CSV printed on stdout keeps full precision (tests and scripts read
    # it back at 1e-12), its noise is left open.
    r = run("qcm", "analyze", f"{data}/example_sweeps.csv", "--out", tmp_path / "a",
            "--no-figures", "--bootstrap", "0")  # fmt: skip
    assert r.exit_code == 0, r.output
    r = run("qcm", "spectra", f"{data}/example_spectra.csv", "--out", tmp_path / "s.csv",
            "--fits", tmp_path / "f.csv")  # fmt: skip
    assert r.exit_code == 0, r.output
    r = run("rum", "invert", f"{data}/example_rum.csv", "--out", tmp_path / "rum.csv")
    assert r.exit_code == 0, r.output
    written = [*(tmp_path / "a").glob("*.csv"), *tmp_path.glob("*.csv")]
    assert len(written) >= 5
    for path in written:
        match = NOISE.search(path.read_text(encoding="utf-8"))
        assert not match, (path.name, match)


def _every_command(group=main, path=()):
    """(words, command) of every command and group, figures included."""
    for name, command in sorted(group.commands.items()):
        yield (*path, name), command
        if isinstance(command, click.Group):
            yield from _every_command(command, (*path, name))


def test_command_listings_are_not_cut_at_an_abbreviation():
    # click's short help stops at the first ". ": "Paper 2: the loops of Fig." (issue 30, 6).
    cut = re.compile(r"\b(Figs?|Eqs?|e\.g|i\.e|cf)\.$")
    for words, command in _every_command():
        short = command.get_short_help_str(limit=1000)
        assert not cut.search(short), (" ".join(words), short)


def test_figures_group_names_the_figure_formats():
    r = run("figures", "--help")
    assert r.exit_code == 0 and "PNG + CSV" not in r.output and "--figure-format" in r.output
