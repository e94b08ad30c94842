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

import pytest

SCRIPT = """
import json, sys, tempfile, warnings
from importlib.resources import files
import contactres
from contactres.report import write_report

warnings.simplefilter("ignore")
table = contactres.read_sweeps(files("contactres") / "data" / "example_sweeps.csv")
materials = json.loads(sys.argv[1])
results = contactres.analyze(table, settings=contactres.AnalysisSettings(bootstrap=0, **materials))
with tempfile.TemporaryDirectory() as folder:
    write_report(results, folder + "/out", formats=("csv", "json"))
print(json.dumps({
    "dynamic": sorted(m for m in sys.modules if m.startswith("contactres.dynamic")),
    "radiation": results.radiation is not None,
}))
"""


def _loaded(materials: dict) -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([*sys.path])  # this checkout's contactres, as here
    run = subprocess.run(
        [sys.executable, "-c", SCRIPT, json.dumps(materials)],
        capture_output=True,
        text=True,
        env=env,
        timeout=600,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout.splitlines()[-1])


@pytest.mark.parametrize(
    ("materials", "radiation"),
    [({}, False), ({"sphere_material": "glass", "plate_material": "quartz-AT"}, True)],
    ids=["no-materials", "radiation-control"],
)
def test_the_dynamic_solver_is_loaded_only_for_the_radiation_loss(materials, radiation):
    loaded = _loaded(materials)
    assert loaded["radiation"] is radiation
    if radiation:
        assert "contactres.dynamic.tangential_stiffness" in loaded["dynamic"]
    else:
        assert loaded["dynamic"] == []
