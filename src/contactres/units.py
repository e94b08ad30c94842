"""Ranges and magnitudes that decide whether a number is physical: every such rule lives here once.

The reader, the validator and the analysis all take their limits from this module, so that a rule
(for example the small-load limit of paper 2, Eq. 1) cannot disagree between two places.
"""

from __future__ import annotations

__all__ = [
    "ABSOLUTE_FREQUENCY_FRACTION",
    "JUNCTION_SIGMAS",
    "MAX_AMPLITUDE_M",
    "MIN_SWEEP_POINTS",
    "POISSON_OPEN_RANGE",
    "SMALL_LOAD_LIMIT",
    "poisson_in_range",
]

#: |Δf|/f above which the small-load approximation (paper 2, Eq. 1) is questioned.
SMALL_LOAD_LIMIT = 1e-3

#: Largest plausible QCM oscillation amplitude, m. Contact-resonance ramps reach tens of nm; 1 µm
#: would wreck the resonator, so a larger value means the column holds nanometres, not metres.
MAX_AMPLITUDE_M = 1e-6

#: A shift above this fraction of the fundamental is an absolute frequency, not a shift.
ABSOLUTE_FREQUENCY_FRACTION = 0.1

#: Open interval of the Poisson ratio of an isotropic solid (positive definite stiffness).
POISSON_OPEN_RANGE = (-1.0, 0.5)

#: Fewest points a sweep needs to take part in the analysis (a straight line with two
#: parameters per channel and an estimate of the noise needs at least four).
MIN_SWEEP_POINTS = 4

#: A Δf slope more than this many standard errors above zero means that Δf rises with the
#: amplitude (the junction grows), which no partial-slip loop does.
JUNCTION_SIGMAS = 2.0


def poisson_in_range(nu: float) -> bool:
    """True if ``nu`` lies strictly inside :data:`POISSON_OPEN_RANGE`."""
    lo, hi = POISSON_OPEN_RANGE
    return lo < nu < hi
