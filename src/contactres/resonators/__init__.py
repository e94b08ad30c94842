"""Resonators that see a contact through a shift of their resonance.

The QCM (paper 2): :class:`QCM` and the conversions between the contact's complex stiffness and
the shifts Δf + iΔΓ (:func:`shifts_from_stiffness`, :func:`stiffness_from_shifts`,
:func:`loop_stiffness`, :func:`shifts_from_loop`, the small-amplitude expansions). The AFM
cantilever of contact-resonance AFM (:class:`Cantilever`, :func:`contact_frequencies`, and its
inversion :func:`invert_contact_resonance`) and the RUM oscillator (:class:`RUMOscillator`).

The public names are loaded on first use (PEP 562 module ``__getattr__``); the modules that
implement them are private (``_qcm``, ``_particles``, ``_cantilever``, ``_cantilever_inversion``,
``_rum``).
"""

from __future__ import annotations

from types import MappingProxyType

from .._lazy import attach

# Read as True by mypy and pyright (the real objects below), False at run time: no import.
TYPE_CHECKING = False

# Public name -> the (private) module that defines it.
_EXPORTS = MappingProxyType(
    {
        "FREE_ROOTS": "._cantilever",
        "contact_frequencies": "._cantilever",
        "Cantilever": "._cantilever",
        "MODE_TOLERANCE": "._cantilever_inversion",
        "flag_names": "._cantilever_inversion",
        "invert_contact_resonance": "._cantilever_inversion",
        "ContactResonanceResult": "._cantilever_inversion",
        "DEFAULT_NODES": "._qcm",
        "QCM": "._qcm",
        "cattaneo_mindlin_expansion": "._qcm",
        "friction_from_slopes": "._qcm",
        "loop_stiffness": "._qcm",
        "masing_stiffness": "._qcm",
        "mu_from_slopes": "._qcm",
        "savkoor_expansion": "._qcm",
        "shifts_from_loop": "._qcm",
        "shifts_from_stiffness": "._qcm",
        "stiffness_from_shifts": "._qcm",
        "AIR": "._particles",
        "Medium": "._particles",
        "Particle": "._particles",
        "VALIDITY_RADIUS_RATIO": "._particles",
        "WATER": "._particles",
        "coupled_resonance": "._particles",
        "kanazawa_gordon": "._particles",
        "medium_named": "._particles",
        "particle_compliance": "._particles",
        "particle_model_validity": "._particles",
        "particle_shifts": "._particles",
        "particle_stiffness": "._particles",
        "penetration_depth": "._particles",
        "sphere_drag": "._particles",
        "RUMOscillator": "._rum",
    }
)

__all__ = sorted(_EXPORTS)

# What type checkers see: the real objects behind the public names (never run, so the imports
# stay lazy; tests/test_public_api.py keeps these imports and ``_EXPORTS`` the same). ``X as X``
# marks an explicit re-export; isort would split each onto its own import, hence off here.
if TYPE_CHECKING:
    # isort: off
    from ._cantilever import (
        Cantilever as Cantilever,
        FREE_ROOTS as FREE_ROOTS,
        contact_frequencies as contact_frequencies,
    )
    from ._cantilever_inversion import (
        ContactResonanceResult as ContactResonanceResult,
        MODE_TOLERANCE as MODE_TOLERANCE,
        flag_names as flag_names,
        invert_contact_resonance as invert_contact_resonance,
    )
    from ._qcm import (
        DEFAULT_NODES as DEFAULT_NODES,
        QCM as QCM,
        cattaneo_mindlin_expansion as cattaneo_mindlin_expansion,
        friction_from_slopes as friction_from_slopes,
        loop_stiffness as loop_stiffness,
        masing_stiffness as masing_stiffness,
        mu_from_slopes as mu_from_slopes,
        savkoor_expansion as savkoor_expansion,
        shifts_from_loop as shifts_from_loop,
        shifts_from_stiffness as shifts_from_stiffness,
        stiffness_from_shifts as stiffness_from_shifts,
    )
    from ._particles import (
        AIR as AIR,
        Medium as Medium,
        Particle as Particle,
        VALIDITY_RADIUS_RATIO as VALIDITY_RADIUS_RATIO,
        WATER as WATER,
        coupled_resonance as coupled_resonance,
        kanazawa_gordon as kanazawa_gordon,
        medium_named as medium_named,
        particle_compliance as particle_compliance,
        particle_model_validity as particle_model_validity,
        particle_shifts as particle_shifts,
        particle_stiffness as particle_stiffness,
        penetration_depth as penetration_depth,
        sphere_drag as sphere_drag,
    )
    from ._rum import (
        RUMOscillator as RUMOscillator,
    )

    # isort: on

__getattr__, __dir__ = attach(__name__, _EXPORTS)
