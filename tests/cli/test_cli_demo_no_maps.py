"""``contactres demo`` installed without the ``maps`` extra.

In a file of its own, apart from tests/cli/test_cli.py's full demo run: each is one of the suite's
longest tests (~8 and ~17 s of CPU), and ``make test`` (``--dist loadfile``) runs one file on one
worker, so in one file they ran one after the other.
"""

from cli_checks import run


def test_demo_without_the_maps_extra_leaves_the_map_out_in_one_line(tmp_path, monkeypatch):
    """Installed without the ``maps`` extra (xarray cannot be imported), the demo writes every
    other part and says in one line which step it left out and what to install."""
    import sys

    monkeypatch.setitem(sys.modules, "xarray", None)  # import xarray -> ImportError
    out = tmp_path / "demo"
    r = run("demo", "--out", str(out))
    assert r.exit_code == 0, r.output
    notes = [line for line in r.stderr.splitlines() if "left out" in line]
    # One line for each map: the polycrystal map and the contact-resonance map.
    assert len(notes) == 2 and all("contactres[maps]" in line for line in notes)
    assert all(len(line) <= 130 for line in notes), notes  # issue 30: was 221 characters
    assert "polycrystal map" in notes[0] and "contact-resonance AFM map" in notes[1]
    assert not (out / "polycrystal").exists() and not (out / "cr-map").exists()
    assert (out / "crystals.csv").is_file() and (out / "coated-contact" / "contact.csv").is_file()
