"""Tests of the command line: help, version, exit codes and one-line errors."""

import json
import re
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from cli_checks import STAND_IN, figures_not_drawn, one_line_error, run

from contactres import __version__
from contactres.cli._common import parse_range


def test_help_lists_subcommands():
    r = run("--help")
    assert r.exit_code == 0
    for cmd in ("crystals", "demo", "qcm", "figures"):
        assert cmd in r.output


def test_version():
    r = run("--version")
    assert r.exit_code == 0 and __version__ in r.output


def test_python_dash_m_runs():
    p = subprocess.run(
        [sys.executable, "-m", "contactres", "--version"],
        capture_output=True,
        text=True,
        check=False,
    )
    assert p.returncode == 0 and __version__ in p.stdout


@pytest.mark.parametrize(
    "args", [["no-such-command"], ["crystals", "--format", "xml"], ["crystals", "--bogus"]]
)
def test_bad_arguments_give_one_line_and_exit_2(args):
    r = run(*args)
    assert r.exit_code == 2
    lines = r.output.strip().splitlines()
    assert len(lines) == 1 and "error" in lines[0]
    assert "Traceback" not in r.output


def test_crystals_formats():
    r = run("crystals", "--format", "json")
    assert r.exit_code == 0
    rows = json.loads(r.output)
    cu = next(row for row in rows if row["name"] == "Cu")
    assert cu["zener"] == pytest.approx(3.21, abs=0.005)
    r = run("crystals", "--format", "csv")
    assert r.output.splitlines()[0].startswith("name,c11_GPa")
    assert "RbI" in run("crystals").output


@pytest.fixture(scope="module")
def demo_results():
    """The demo job's Result installed without the ``maps`` extra, then with it: computed once
    for the demo's tests here (the demo is one of the suite's costliest runs).

    Without the extra, :func:`contactres.jobs.demo.run` runs in full with ``import xarray``
    failing. With it, ``run`` runs again, its two map steps for real; the parts the first run
    computed and that do not use the extra (the analyses, paper 1's curves, the coated
    contact) are handed back to it, as recomputing them gives the same numbers.
    """
    from contactres.jobs import demo, paper1

    with pytest.MonkeyPatch.context() as mp:
        mp.setitem(sys.modules, "xarray", None)  # import xarray -> ImportError
        bare = demo.run()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(demo, "_sweeps", lambda: bare.sweeps_analysis)
        spectra = (bare.spectra_rows, bare.spectra_fits, bare.spectra_analysis)
        mp.setattr(demo, "_spectra", lambda: spectra)
        mp.setattr(paper1, "crystal_curves", lambda model: bare.crystal_dcsf)
        mp.setattr(demo, "_coated_contact", lambda: bare.coated_contact)
        full = demo.run()
    return bare, full


def _demo_returns(monkeypatch, result):
    """``contactres demo`` (in this process) computes ``result`` and writes it. The stand-in
    takes the command's arguments as the real ``run`` does (a changed signature fails here)
    and reports the real run's steps through the command's progress callback."""
    import inspect

    from contactres.jobs import demo
    from contactres.jobs.contract import say

    real = inspect.signature(demo.run)

    def stand_in(*args, **kwargs):
        bound = real.bind(*args, **kwargs)
        for step in demo.STEPS:
            say(bound.arguments.get("progress"), step)
        return result

    monkeypatch.setattr(demo, "run", stand_in)


def test_demo_writes_folder(tmp_path, monkeypatch, demo_results):
    _demo_returns(monkeypatch, demo_results[1])  # the rerun below writes the same Result again
    out = tmp_path / "demo"
    r = run("demo", "--out", str(out))
    assert r.exit_code == 0, r.output
    # Issue 27: every folder the demo writes holds its manifest, which lists each of its files;
    # a rerun into the folder replaces them (the manifests vouch for them) and nothing else.
    files = sorted(p.relative_to(out) for p in out.rglob("*") if p.is_file())
    for folder in {f.parent for f in files}:
        listed = json.loads((out / folder / "manifest.json").read_text())["files"]
        written = [f.name for f in files if f.parent == folder and f.name != "manifest.json"]
        assert sorted(listed) == sorted(written), folder
    # The rerun is about which files are written (each of the first run's, replaced under its
    # manifest, and no other), not their pixels: the first run drew every figure, so the rerun
    # writes a stand-in into each figure's file (drawing them again was a fifth of the test).
    # That each figure's file now holds the stand-in shows the rerun replaced it.
    figures_not_drawn(monkeypatch)  # the figure files and the report pages' images
    assert run("demo", "--out", str(out)).exit_code == 0
    assert sorted(p.relative_to(out) for p in out.rglob("*") if p.is_file()) == files
    figures = [f for f in files if f.suffix == ".png"]
    assert figures and all((out / f).read_bytes() == STAND_IN for f in figures)
    assert (out / "crystals.csv").is_file()
    _check_demo_ends_with_the_numbers(r.output, out)
    cr_map = {"afm_map.json", "afm_map.nc", "afm_maps.png", "afm_histograms.png"}
    assert cr_map <= {p.name for p in (out / "cr-map").iterdir()}
    # The coated substrate: paper 2's sphere on 250 nm of PMMA on fused silica. Its contact is
    # between Hertz on bare silica and Hertz on bulk PMMA (1 Hz storage constants).
    from contactres import Material, indentation_modulus, pmma
    from contactres.jobs.demo import COATED_CONTACT
    from contactres.normal import hertz

    coated = pd.read_csv(out / "coated-contact" / "contact.csv")
    assert list(coated["force_N"]) == list(COATED_CONTACT["forces"])
    assert (coated["coating"] == "PMMA 250 nm").all()
    assert coated["film_share"].between(0, 1).all()
    silica = indentation_modulus(Material.crystal("fused-silica"))
    film = indentation_modulus(Material(C=np.real(pmma().at(1.0).C)))
    a = coated["contact_radius_m"]
    assert (a > hertz(silica, 1.1e-3, coated["force_N"]).contact_radius).all()
    assert (a < hertz(film, 1.1e-3, coated["force_N"]).contact_radius).all()


def _check_demo_ends_with_the_numbers(output, out):
    """The demo's screen (issue 30): the files in one line, then Table 1, μ per load and the
    modulus map's statistics, last."""
    lines = output.splitlines()
    wrote = [line for line in lines if line.startswith("wrote ")]
    assert len(wrote) == 1 and re.fullmatch(
        rf"wrote \d+ files into {re.escape(str(out))}/", wrote[0]
    )
    assert not any(line.strip().startswith(str(out)) for line in lines)  # no file list
    assert lines.index(wrote[0]) < lines.index(next(x for x in lines if x.startswith("Table 1")))
    # μ per load: every load of loads.csv, in its order, with its median μ.
    loads = pd.read_csv(out / "qcm-analysis" / "loads.csv")
    start = lines.index("friction coefficient per load (exact-loop fit, median over experiments)")
    rows = lines[start + 2 : start + 2 + len(loads)]
    for row, mu in zip(rows, loads["mu_fit_median"], strict=True):
        assert float(row.split()[3]) == pytest.approx(mu, abs=0.006)  # rounded to the error
    # The spectra's chain: its E as the analysis in qcm-spectra/analysis wrote it.
    import json

    start = lines.index("the same chain from the bundled admittance spectra (qcm-spectra/)")
    e_line = re.search(r"E = (\S+) ±", lines[start + 2])
    assert e_line, lines[start : start + 3]
    summary = json.loads((out / "qcm-spectra" / "analysis" / "summary.json").read_text())
    (group,) = summary["groups"]
    assert float(e_line[1]) == pytest.approx(group["E_Pa"] / 1e9, rel=1e-2)
    # Then the maps: M, which for a cubic crystal lies between the (001) and (111) faces', what
    # the k* map determines, and the CR-AFM map's medians (as its afm_map.json holds them).
    from contactres import Material, indentation_modulus

    poly = next(x for x in lines if x.startswith("polycrystal map:"))
    m = re.fullmatch(
        r"polycrystal map: 4096 pixels, M from (\S+) to (\S+) GPa, median (\S+) GPa", poly
    )
    assert m, poly
    fit = next(x for x in lines if x.startswith("constants fitted back"))
    assert "strong combination" in fit and "M(111)/M(001)" in fit
    cr_line = lines[-1]
    k_med = re.search(r"median k\* (\S+) N/m", cr_line)
    assert cr_line.startswith("CR-AFM map (cr-map/)") and k_med, cr_line
    afm = json.loads((out / "cr-map" / "afm_map.json").read_text())
    assert float(k_med[1]) == pytest.approx(_find(afm, "median_k_star_N_per_m"), rel=1e-3)
    lo, hi, median = (float(x) * 1e9 for x in m.groups())
    cu = Material.crystal("Cu")
    m001 = indentation_modulus(cu)
    m111 = indentation_modulus(cu.rotated((1, 1, 1)))
    assert m001 * (1 - 1e-3) <= lo <= median <= hi <= m111 * (1 + 1e-3)


def _find(doc, key):
    """The first value of ``key`` anywhere in a nested JSON document."""
    if isinstance(doc, dict):
        if key in doc:
            return doc[key]
        found = (_find(v, key) for v in doc.values())
    elif isinstance(doc, list):
        found = (_find(v, key) for v in doc)
    else:
        return None
    return next((v for v in found if v is not None), None)


@pytest.mark.parametrize(
    "name",
    [
        "crystals.csv",
        "coated-contact/contact.csv",
        "paper2-forward/paper2_fig2_loops.png",
        "qcm-spectra/analysis/loads.csv",
        "cr-map/afm_map.json",
    ],
)
def test_demo_never_overwrites_a_file_of_the_users(tmp_path, monkeypatch, name):
    """Issue 27: the demo overwrote a file of the user's under one of its names. Refused in one
    line naming it, before the work; the file is unchanged and nothing else is written."""
    from contactres.jobs import demo

    def never(*args, **kwargs):
        raise AssertionError("the work started before the folder was checked")

    monkeypatch.setattr(demo, "run", never)
    out = tmp_path / "demo"
    mine = out / name
    mine.parent.mkdir(parents=True)
    mine.write_bytes(b"my own file\n")
    one_line_error(run("demo", "--out", str(out)), f"({mine.name})", "did not write")
    assert [p for p in tmp_path.rglob("*") if p.is_file()] == [mine]
    assert mine.read_bytes() == b"my own file\n"


def test_demo_onto_a_file_is_an_error(tmp_path):
    f = tmp_path / "file"
    f.write_text("keep me")
    r = run("demo", "--out", str(f))
    assert r.exit_code == 2
    assert f.read_text() == "keep me"


def test_parse_range():
    assert list(parse_range("0:2:5")) == [0, 0.5, 1, 1.5, 2]
    assert list(parse_range("1,2.5")) == [1, 2.5]
    for bad in ("0:2", "a:b:3", "0:1:0", "", "nan"):
        with pytest.raises(ValueError, match="range"):
            parse_range(bad)


def test_bare_command_shows_help():
    r = run()
    assert r.exit_code == 0 and "Commands:" in r.output


def test_json_output_keeps_small_values_exactly():
    # pandas' to_json rounds to 15 decimals: 1.234567890123e-12 m became 1e-12 or 0.
    import io

    import pandas as pd

    from contactres.cli._common import emit

    table = pd.DataFrame({"u0_m": [1.234567890123e-12, float("nan")], "x": [float("inf"), 2.0]})
    out = io.StringIO()
    emit(table, "json", out)
    rows = json.loads(out.getvalue())
    assert rows[0]["u0_m"] == 1.234567890123e-12
    assert rows[1]["u0_m"] is None and rows[0]["x"] is None  # no JSON form: null


def test_csv_output_has_no_float_noise_and_keeps_15_digits():
    import io

    import pandas as pd

    from contactres.cli._common import emit

    value = 1.234567890123456e-12
    out = io.StringIO()
    emit(pd.DataFrame({"x": [0.1 + 0.2, value]}), "csv", out)
    lines = out.getvalue().split()
    assert lines[1] == "0.3"  # not 0.30000000000000004
    assert abs(float(lines[2]) - value) <= 5e-15 * value  # half a unit in the 15th digit


def test_demo_without_the_maps_extra_leaves_the_map_out_in_one_line(
    tmp_path, monkeypatch, demo_results
):
    """Installed without the ``maps`` extra (xarray cannot be imported), the demo writes every
    other part and says in one line which step it left out and what to install."""
    bare, _ = demo_results
    assert bare.map_dataset is None and bare.map_triangle is None and bare.cr_map is None
    monkeypatch.setitem(sys.modules, "xarray", None)  # the writers too run without it
    _demo_returns(monkeypatch, bare)
    # which files and lines, not pixels: every figure is drawn by test_demo_writes_folder
    figures_not_drawn(monkeypatch)
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


def test_the_demo_carries_the_legend_of_its_map(demo_results):
    """The legend of the demo's map figure: Cu's M over the standard triangle, as M computed at
    the triangle's normals here."""
    from contactres import Material
    from contactres.polycrystal import indentation_moduli, surface_matrices_from_normals

    triangle = demo_results[1].map_triangle
    ok = triangle.cells
    exact = indentation_moduli(
        Material.crystal("Cu"), surface_matrices_from_normals(triangle.normals)
    )
    np.testing.assert_allclose(triangle.moduli[ok], exact, rtol=1e-12)
    assert triangle.moduli.shape == (81, 81) and triangle.triangle.lattice == "cubic"
