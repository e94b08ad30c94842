"""A field over the csv module's limit (128 kB) in a sweep table or a QCM-D export is a one-line
input error naming the file and its line, not an internal error (issue 27, point 15)."""

from __future__ import annotations

from importlib import resources

import pytest
from cli_checks import one_line_error, run

from contactres.errors import ContactresInputError
from contactres.measurements.readers.exports import read_export

BIG = 140_000  # characters: beyond the csv module's default field limit of 131072


def _example(name: str) -> list[str]:
    return resources.files("contactres.data").joinpath(name).read_text().splitlines()


def test_sweep_table_with_a_header_field_over_128_kB(tmp_path):
    lines = _example("example_sweeps.csv")
    path = tmp_path / "sweeps.csv"
    path.write_text("\n".join([lines[0] + "x" * BIG, *lines[1:]]) + "\n")
    r = run("qcm", "analyze", path, "--out", tmp_path / "out")
    one_line_error(r, "sweeps.csv", "line 1", "header")
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())


@pytest.mark.parametrize(("where", "line"), [("header", 1), ("cell", 2)])
def test_export_with_a_field_over_128_kB(tmp_path, where, line):
    lines = _example("example_qcmd.csv")
    head, first, rest = lines[0], lines[1], lines[2:]
    if where == "header":
        text = [f"{head},Note{'x' * BIG}", f"{first},", *(f"{x}," for x in rest)]
    else:
        text = [f"{head},Note", f'{first},"{"x" * BIG}"', *(f"{x}," for x in rest)]
    path = tmp_path / "export.csv"
    path.write_text("\n".join(text) + "\n")
    with pytest.raises(ContactresInputError, match=f"export.csv, line {line}: not a readable"):
        read_export(path)
    r = run("qcm", "stiffness", path, "--area", "2.5e-5", "--n-contacts", "3", "--out",
            tmp_path / "out")  # fmt: skip
    one_line_error(r, "export.csv", f"line {line}")
