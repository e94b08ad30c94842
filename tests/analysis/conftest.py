"""Fixtures shared by the analysis tests."""

import pytest


@pytest.fixture(scope="session")
def shared_water_study(water_study):
    """``shared_water_study(seed, plateau=0.3) -> (results, sweeps with the truth)``: as
    ``water_study``, each (seed, plateau) analysed once per test process.

    The classification tests of the μ prior, the plateau prior and the plateau's evidence read
    the same seeds (0, 1 and 2 at 30 % plateau loads; ~1 s of CPU each). Each call returns a
    deep copy, so a test that changes what it was given changes no other test's. Only for
    tests that analyse with the library as it is: one that patches the analysis (a spy, a
    constant set aside) calls ``water_study`` itself, or it would read another's results."""
    import copy

    done = {}

    def study(seed: int, plateau: float = 0.3):
        if (seed, plateau) not in done:
            done[seed, plateau] = water_study(seed, plateau)
        return copy.deepcopy(done[seed, plateau])

    return study
