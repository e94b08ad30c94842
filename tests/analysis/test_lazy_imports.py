"""The QCM analysis loads the dynamic contact solver only when it computes the radiation loss.

Run in a fresh interpreter each (this process has imported everything already): without
materials, no ``contactres.dynamic`` module may be loaded by reading, analysing and writing the
bundled example; with them (the control) the solver must be loaded, or the test would pass for a
check that cannot fail.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

SCRIPT = """
import json, sys, tempfile, warnings
import contactres
from contactres.report import write_report

warnings.simplefilter("ignore")
table = contactres.read_sweeps(sys.argv[2])
materials = json.loads(sys.argv[1])
results = contactres.analyze(table, settings=contactres.AnalysisSettings(bootstrap=0, **materials))
with tempfile.TemporaryDirectory() as folder:
    write_report(results, folder + "/out", formats=("csv", "json"))
print(json.dumps({
    "dynamic": sorted(m for m in sys.modules if m.startswith("contactres.dynamic")),
    "halfspace": sorted(m for m in sys.modules if m.startswith("contactres.halfspace")),
    "radiation": results.radiation is not None,
    "radiation_rows": 0 if results.radiation is None else len(results.radiation),
}))
"""


def _loaded(materials: dict, sweeps: str) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([*sys.path])  # this checkout's contactres, as here
    run = subprocess.run(
        [sys.executable, "-c", SCRIPT, json.dumps(materials), sweeps],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout.splitlines()[-1])


def test_the_dynamic_solver_is_loaded_for_the_radiation_loss(tmp_path):
    # The control: with both materials the solver is loaded (and seen loaded from the fresh
    # interpreter). Without them none is: test_the_command_loads_no_solver_without_materials
    # below, whose command reads, analyses and writes the whole example through the same
    # read_sweeps, analyze and write_report (and the bootstrap and the page besides). The
    # control needs one radiation loss computed, not the example's 24: one group of it (the
    # 2.2 mm spheres in air) at three of its loads, enough for its JKR fit and so its radii.
    import pandas as pd

    from contactres import example_path

    rows = pd.read_csv(example_path("example_sweeps.csv"))
    rows = rows[(rows["configuration"] == "SiO2_2.2mm") & (rows["medium"] == "air")]
    forces = np.unique(rows["normal_force_N"])
    part = tmp_path / "sweeps.csv"
    rows[rows["normal_force_N"].isin(forces[[0, 2, 5]])].to_csv(part, index=False)
    loaded = _loaded({"sphere_material": "glass", "plate_material": "quartz-AT"}, str(part))
    assert loaded["radiation"] is True and loaded["radiation_rows"] == 3
    assert "contactres.dynamic._tangential_stiffness" in loaded["dynamic"]
    assert "contactres.halfspace._compliance" in loaded["halfspace"]


def test_the_command_loads_no_solver_without_materials(tmp_path):
    """``contactres qcm analyze`` itself (its command tree and job): no contactres.dynamic or
    contactres.halfspace module without --sphere-material/--plate-material."""
    code = (
        "import sys, json\n"
        "from contactres.cli import main\n"
        "try:\n"
        "    main(sys.argv[1:])\n"
        "except SystemExit:\n"
        "    pass\n"
        "print(json.dumps(sorted(m for m in sys.modules\n"
        "    if m.startswith(('contactres.dynamic', 'contactres.halfspace')))))\n"
    )
    from importlib.resources import files

    example = str(files("contactres") / "data" / "example_sweeps.csv")
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([*sys.path])
    args = ["qcm", "analyze", example, "--out", str(tmp_path / "out"), "--no-figures"]
    run = subprocess.run(
        [sys.executable, "-c", code, *args],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    assert (tmp_path / "out" / "summary.json").exists()
    assert json.loads(run.stdout.splitlines()[-1]) == []


def test_the_first_use_of_analyze_imports_neither_scipy_stats_nor_optimize():
    """``import contactres; contactres.analyze`` (the first real use, issue 31) leaves out
    scipy.stats (~0.5 s) and scipy.optimize (~0.15 s): the analysis imports them where used."""
    code = (
        "import sys, json, contactres\n"
        "contactres.analyze\n"
        "print(json.dumps(sorted(m for m in sys.modules\n"
        "    if m.startswith(('scipy.stats', 'scipy.optimize')))))\n"
    )
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([*sys.path])
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, timeout=600
    )
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout.splitlines()[-1]) == []


def test_the_student_factor_is_scipy_stats_quantile():
    """t95_factor (contactres.analysis._distributions, numpy alone since issue 31: it was
    scipy.special.stdtrit, bit for bit) against scipy.stats' Student t quantile, to the stated
    accuracy of the quantile (2e-12 up to 1e4 degrees of freedom, 2e-16 dof beyond); NaN below
    one degree of freedom."""
    import numpy as np
    from scipy import stats

    from contactres.analysis._jkr import t95_factor

    dof = np.array([0.0, 0.5, 1.0, 2.0, 3.0, 7.5, 30.0, 1e6, np.nan])
    expected = stats.t.ppf(0.975, np.where(dof >= 1, dof, np.nan))
    got = t95_factor(dof)
    np.testing.assert_array_equal(np.isnan(got), np.isnan(expected))
    shown = ~np.isnan(expected)
    tol = np.maximum(2e-12, 2e-16 * dof[shown])
    assert np.all(np.abs(got[shown] / expected[shown] - 1) < tol)
    assert float(t95_factor(3.0)) == pytest.approx(3.182446305284263, rel=1e-12)
