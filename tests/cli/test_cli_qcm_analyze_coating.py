"""``contactres qcm analyze --coating MATERIAL:THICKNESS``: E and γ on a coated plate.

A run on a small synthetic study prints Table 1 and the coating's lines and records the coating
in summary.json; every bad coating is one line with exit code 2, before any file is written.
"""

import json

import numpy as np
import pytest
from cli_checks import one_line_error, run

from contactres.measurements._synthetic import SweepGroup, SweepStudy, synthetic_sweeps
from contactres.resonators._qcm import QCM

OPTS = ["--area", "2.5e-5", "--overtone", "3", "--n-contacts", "3", "--bootstrap", "20"]


@pytest.fixture(scope="module")
def sweeps(tmp_path_factory):
    u = tuple(np.linspace(0.5e-9, 5e-9, 6))
    study = SweepStudy(
        groups=(SweepGroup("glass", "air", 1.1e-3, 70e9, 0.1, u, 2e4, 0.1),),
        normal_forces=(2e-3, 4e-3, 6e-3),
        n_experiments=3,
        alternate=False,
        qcm=QCM(5e6, 3, 2.5e-5),
    )
    path = tmp_path_factory.mktemp("coated") / "sweeps.csv"
    synthetic_sweeps(study, 7).to_csv(path, index=False)
    return path


def test_a_coated_run_prints_and_records_the_coating(sweeps, tmp_path):
    out = tmp_path / "out"
    plain = run("qcm", "analyze", sweeps, "--out", tmp_path / "plain", "--no-figures", *OPTS)
    assert plain.exit_code == 0, plain.output
    r = run(
        "qcm", "analyze", sweeps, "--out", out, "--no-figures", *OPTS, "--coating", "pmma:250e-9"
    )
    assert r.exit_code == 0, r.output
    assert "coated plate: PMMA 250 nm" in r.output
    assert "glass, air: uncoated E = " in r.output and "film share" in r.output
    summary = json.loads((out / "summary.json").read_text())
    assert summary["settings"]["coating"]["layers"] == [
        {"material": "PMMA", "thickness_m": 2.5e-07}
    ]
    assert "coating" in summary["conventions"]
    (g,) = summary["groups"]
    before = json.loads((tmp_path / "plain" / "summary.json").read_text())
    assert "coating" not in before["settings"] and "coating" not in before["conventions"]
    assert g["coating"]["uncoated"]["E_Pa"] == before["groups"][0]["E_Pa"]
    # A soft film: the substrate must be stiffer than the uncoated analysis says.
    assert g["E_Pa"] > before["groups"][0]["E_Pa"]
    assert [row["normal_force_N"] for row in g["coating"]["loads"]] == [2e-3, 4e-3, 6e-3]


@pytest.mark.parametrize(
    ("coating", "words"),
    [
        ("unobtainium:250e-9", ["unknown coating material", "pmma"]),
        ("pmma:0", ["thickness"]),
        ("pmma:-1e-9", ["thickness"]),
        ("pmma:2", ["--coating pmma:2", "thickness", "above 1 m"]),
        ("pmma250e-9", ["MATERIAL:THICKNESS"]),
    ],
)
def test_a_bad_coating_is_one_line(sweeps, tmp_path, coating, words):
    out = tmp_path / "out"
    r = run("qcm", "analyze", sweeps, "--out", out, *OPTS, "--coating", coating)
    one_line_error(r, *words)
    assert not out.exists()


def test_a_bad_plate_material_with_a_coating_is_one_line(sweeps, tmp_path):
    # The radiation on a coated plate runs (tests/analysis/test_radiation_coated.py); a bad
    # material is still refused before any work.
    r = run(
        "qcm",
        "analyze",
        sweeps,
        "--out",
        tmp_path / "out",
        *OPTS,
        "--coating",
        "pmma:250e-9",
        "--sphere-material",
        "glass",
        "--plate-material",
        "quartz-XY",
    )
    one_line_error(r, "--plate-material", "quartz-XY")


def test_the_film_share_line_leaves_out_a_load_without_a_share():
    # A load left out of the coated fit (κ <= 0) whose radius is outside the table has a NaN
    # share (analysis._coating._film_share); the line gives the others' range, whichever
    # row comes first (Python's min of a NaN first and numbers is the NaN).
    from types import SimpleNamespace

    from contactres.cli.qcm_analyze import coating_lines

    def group(shares):
        return {
            "configuration": "glass",
            "medium": "air",
            "coating": {
                "label": "film 2 µm",
                "uncoated": {"E_Pa": 70e9, "gamma_J_m2": 0.1},
                "loads": [{"film_share": s} for s in shares],
            },
        }

    for shares in ([float("nan"), 0.25, 0.5], [0.25, float("nan"), 0.5]):
        (_, line) = coating_lines(SimpleNamespace(groups=[group(shares)]))
        assert line.endswith("film share 25.0%-50.0%")
    (_, line) = coating_lines(SimpleNamespace(groups=[group([float("nan")])]))
    assert line.endswith("no film share")
