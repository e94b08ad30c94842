"""Test configuration: a fast, deterministic hypothesis profile for `make test`."""

from dataclasses import replace

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile(
    "default",
    max_examples=40,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile("default")


def pytest_configure(config):
    """pandas' warnings of a change to come (a call that the next major version refuses, a
    result that will differ) are errors in the tests, as contactres' own warnings are (in
    pyproject.toml): there they would be a crash or a silent change for users on an upgrade.
    Added here, not in pyproject.toml: their classes exist from pandas 3 on, and pytest refuses
    a filter whose class it cannot import (pandas>=2.0 is supported)."""
    import pandas.errors

    for name in ("PandasDeprecationWarning", "PandasFutureWarning"):
        if hasattr(pandas.errors, name):
            config.addinivalue_line("filterwarnings", f"error::pandas.errors.{name}")


def kelvin_voigt_resonance(lever, k_star, tan_delta, tip_position):
    """Mode 1's contact resonance (f in Hz, Q) of ``lever`` on a Kelvin-Voigt contact: a spring
    k* (N/m) and a dashpot σ = tan δ k*/ω in parallel, at the tip position r.

    The contact enters the lever's characteristic equation at its complex eigenfrequency
    ω_c = 2π(f′ + i f″) as κ_c = (k* + iω_c σ)/k_c, and ω_c depends on κ_c: the fixed point is
    found by substitution (each step shrinks the change by about tan δ/(2Q)), with the forward
    model contact_frequencies (tested against an independent beam in tests/resonators).
    """
    import numpy as np

    from contactres import contact_frequencies

    k_star = np.asarray(k_star, dtype=float)
    kappa = k_star / lever.spring_constant + 0j
    for _ in range(60):
        fc = contact_frequencies(lever, kappa, tip_position, modes=(1,))[..., 0]
        sigma = tan_delta * k_star / (2 * np.pi * fc.real)
        new = (k_star + 2j * np.pi * fc * sigma) / lever.spring_constant
        done = np.max(np.abs(new / kappa - 1)) < 1e-15
        kappa = new
        if done:
            break
    fc = contact_frequencies(lever, kappa, tip_position, modes=(1,))[..., 0]
    return fc.real, fc.real / (2 * fc.imag)


@pytest.fixture
def kelvin_voigt():
    """:func:`kelvin_voigt_resonance`, for the tests of contact-resonance maps."""
    return kelvin_voigt_resonance


def water_study_analysis(seed: int, plateau: float = 0.3):
    """Paper 2's water configurations (validation_study) with a share ``plateau`` of loads with
    a stick plateau, no drift and no Savkoor experiment: the analysis, and its sweeps with the
    truth."""
    from contactres.analysis import AnalysisSettings, analyze
    from contactres.measurements import synthetic_sweeps, validate_sweeps, validation_study

    base = validation_study(4)
    study = replace(
        base,
        groups=tuple(g for g in base.groups if g.medium == "water"),
        random_plateau=plateau,
        drifts=(),
        savkoor_experiments=(),
    )
    raw = synthetic_sweeps(study, seed, truth=True)
    truth_cols = [c for c in raw.columns if c.startswith("true_")]
    table = validate_sweeps(
        raw.drop(columns=truth_cols), constants=dict(overtone=3, area_m2=2.5e-5, n_contacts=3)
    )
    res = analyze(table, settings=AnalysisSettings(bootstrap=0))
    truth = raw.drop_duplicates("sweep")[["sweep", *truth_cols]]
    return res, res.sweeps.merge(truth, on="sweep", validate="one_to_one")


@pytest.fixture(scope="session")
def water_study():
    """``water_study(seed, plateau=0.3) -> (results, sweeps with the truth)``: paper 2's water
    configurations with a share ``plateau`` of plateau loads (issue 27, point 11)."""
    return water_study_analysis


@pytest.fixture(scope="session")
def shared_water_study(water_study):
    """``shared_water_study(seed, plateau=0.3) -> (results, sweeps with the truth)``: as
    ``water_study``, each (seed, plateau) analysed once per test process.

    The classification tests of the μ prior, the plateau prior and the plateau's evidence read
    the same seeds (0, 1 and 2 at 30 % plateau loads; ~1 s of CPU each). Each call returns a
    deep copy, so a test that changes what it was given changes no other test's. Only for
    tests that analyse with the library as it is: one that patches the analysis (a spy, a
    constant set aside) calls ``water_study`` itself, or it would read another's results.
    (Here, not in a tests/analysis/conftest.py: the doctest collection of this file then
    met another module named ``conftest`` and failed with an import file mismatch.)"""
    import copy

    done = {}

    def study(seed: int, plateau: float = 0.3):
        if (seed, plateau) not in done:
            done[seed, plateau] = water_study(seed, plateau)
        return copy.deepcopy(done[seed, plateau])

    return study


@pytest.fixture(scope="session")
def example_analysis():
    """``example_analysis(**settings) -> Results``: the analysis of the bundled
    example_sweeps.csv without bootstrap (``AnalysisSettings(bootstrap=0, **settings)``).

    Several test files read the same analysis (~1.5 s of CPU each); it is computed once per
    test process and settings. Each call returns a deep copy, so a test that changes the
    Results it was given changes no other test's."""
    import copy

    from contactres import AnalysisSettings, analyze, example_path, read_sweeps

    done = {}

    def results(**settings):
        chosen = AnalysisSettings(bootstrap=0, **settings)
        if chosen not in done:
            done[chosen] = analyze(read_sweeps(example_path("example_sweeps.csv")), settings=chosen)
        return copy.deepcopy(done[chosen])

    return results


def pytest_sessionfinish(session, exitstatus):
    """A run in which no test ran fails. Test workers that crash while collecting (a native
    library's segmentation fault on import) left a fresh CI run with "no tests ran" and, as CI
    read it, nothing failed; pytest-xdist restarts them and may end with status 0."""
    if hasattr(session.config, "workerinput") or session.config.option.collectonly:
        return  # a worker's own session, or a collection-only run
    reporter = session.config.pluginmanager.get_plugin("terminalreporter")
    if reporter is None or exitstatus != 0:
        return
    outcomes = ("passed", "failed", "error", "skipped", "xfailed", "xpassed")
    if not any(reporter.stats.get(k) for k in outcomes):
        session.exitstatus = pytest.ExitCode.INTERNAL_ERROR
