"""Fixtures shared by the report tests."""

from pathlib import Path

import pytest
from click.testing import CliRunner

import contactres
from contactres.cli import main

EXAMPLE = Path(contactres.__file__).parent / "data" / "example_sweeps.csv"


@pytest.fixture(scope="session")
def example_set(tmp_path_factory) -> Path:
    """The results folder ``qcm analyze --report html`` writes for the bundled example (no
    bootstrap, no figures): analysed once for every test that reads it."""
    out = tmp_path_factory.mktemp("example") / "results"
    args = ["qcm", "analyze", str(EXAMPLE), "--out", str(out), "--report", "html"]
    result = CliRunner().invoke(main, [*args, "--bootstrap", "0", "--no-figures"])
    assert result.exit_code == 0, result.output
    return out
