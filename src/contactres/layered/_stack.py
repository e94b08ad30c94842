"""A layered substrate: bonded layers of given thickness on an elastic half-space.

:class:`LayeredMaterial` describes the solid whose surface response :mod:`._recursion` computes:
layers j = 1..n (top first) of thickness h_j, welded to each other and to the substrate (the
displacement and the traction σ_i3 are continuous across every interface), on a half-space
that extends to z -> ∞ (only decaying or, for a lossless solid, outgoing waves in it: no wave
comes back from below). The top surface z = 0 carries the applied traction. Every material is
given in the common surface frame (z the inward normal), as a :class:`~contactres.Material`
or as a frequency-dependent material: any object with a method ``at(frequency_Hz)`` that
returns a :class:`~contactres.Material` (``at(0)``: the static, relaxed limit).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from .._summary import Summarised
from ..errors import ContactresInputError
from ..materials import Material
from ..viscoelastic import material_at  # the one definition; public here too

__all__ = [
    "MAX_THICKNESS_M",
    "FrequencyDependentMaterial",
    "LayeredMaterial",
    "checked_thickness",
    "material_at",
    "thickness_text",
]

#: The thickest layer any part of contactres takes, m: :class:`LayeredMaterial`, the command
#: line's ``--coating`` and the analysis's coating all check against this one limit
#: (:func:`checked_thickness`). A layer thicker than this is not a film (no contact, whose
#: radius is at most a few mm, sees through it: use its material as the substrate), and most
#: likely a thickness typed in nm or µm.
MAX_THICKNESS_M = 1.0


class FrequencyDependentMaterial(Protocol):
    """What a layer or substrate needs beyond a plain :class:`~contactres.Material`: its elastic
    constants at a frequency (Hz; 0 is the static, relaxed limit), e.g. a viscoelastic solid."""

    def at(self, frequency: float) -> Material:
        """The Material at ``frequency`` (Hz)."""
        ...


AnyMaterial = Material | FrequencyDependentMaterial


def _check_material(m, what: str):
    if isinstance(m, LayeredMaterial):
        raise ContactresInputError(f"{what} must be a Material, not a LayeredMaterial")
    if isinstance(m, Material) or callable(getattr(m, "at", None)):
        return m
    raise ContactresInputError(
        f"{what} must be a contactres.Material or a frequency-dependent material with "
        f"at(frequency_Hz), got {type(m).__name__}"
    )


def checked_thickness(value, where: str) -> float:
    """A layer's thickness in m, checked against the one rule of contactres: a finite number,
    > 0 and at most :data:`MAX_THICKNESS_M`.

    Parameters
    ----------
    value : float
        The thickness, m.
    where : str
        What the value is, naming where it came from (the start of the error line), e.g.
        ``"layer 2 thickness"`` or ``"coating thickness (--coating pmma:2)"``.

    Returns
    -------
    float
        The thickness, m.

    Raises
    ------
    ContactresInputError
        One line starting with ``where``: not a number, not finite or <= 0, or above
        :data:`MAX_THICKNESS_M`.

    Examples
    --------
    >>> checked_thickness(250e-9, "layer 1 thickness")
    2.5e-07
    """
    try:
        t = float(value)
    except (TypeError, ValueError):
        raise ContactresInputError(
            f"{where} must be a number in m, got {type(value).__name__}"
        ) from None
    if not (math.isfinite(t) and t > 0):
        raise ContactresInputError(
            f"{where} must be finite and > 0 m, got {value!r} m (a positive finite number of "
            "metres: 250 nm = 250e-9)"
        )
    if t > MAX_THICKNESS_M:
        raise ContactresInputError(
            f"{where} {t!r} m is above {MAX_THICKNESS_M:g} m, thicker than any meaningful film: "
            "a value in nm/µm? give metres (250 nm = 250e-9); or use that material as the "
            "substrate instead"
        )
    return t


def _check_thickness(h, j: int, n: int) -> float:
    where = f"layer {j}" + (" (top)" if j == 1 and n > 1 else "")
    return checked_thickness(h, f"{where} thickness")


def thickness_text(h: float) -> str:
    """A thickness (m) in the unit that reads best: ``"250 nm"``, ``"1.5 µm"``, ``"2 mm"``,
    ``"1 m"`` (four significant digits).

    Examples
    --------
    >>> thickness_text(250e-9), thickness_text(1e-6), thickness_text(1e-3), thickness_text(1.0)
    ('250 nm', '1 µm', '1 mm', '1 m')
    """
    for unit, scale in (("nm", 1e-9), ("µm", 1e-6), ("mm", 1e-3)):
        # The next unit once the digits printed reach 1000 (1e-6 m is 999.99... nm: "1 µm").
        text = f"{h / scale:.4g}"
        if float(text) < 1000:
            return f"{text} {unit}"
    return f"{h:.4g} m"


# repr=False: the summary (Summarised, _facts) replaces the materials' stiffness matrices.
@dataclass(frozen=True, eq=False, repr=False)
class LayeredMaterial(Summarised):
    """Bonded layers on a half-space substrate, top layer first.

    ``LayeredMaterial(substrate, layers=[(film, thickness_m), ...])``. Interfaces are welded
    (continuous displacement and traction σ_i3); the substrate fills the rest of z > 0 with no
    wave coming back from below (decaying, or outgoing for a lossless solid). Every material is
    a :class:`~contactres.Material` in the common surface frame (z the inward normal) or a
    frequency-dependent material (``at(frequency_Hz) -> Material``). No layers is allowed: the
    stack is then the substrate itself (same surface response).

    Parameters
    ----------
    substrate : Material or frequency-dependent material
        The half-space under the layers.
    layers : sequence of (material, thickness)
        Each layer's material and thickness in m (finite, > 0, at most 1 m), top first.

    Examples
    --------
    >>> from contactres import LayeredMaterial, Material
    >>> quartz = Material.isotropic(72e9, 0.17, density=2650.0, name="quartz")
    >>> pmma = Material.isotropic(5e9, 0.35, density=1190.0, name="PMMA")
    >>> LayeredMaterial(quartz, [(pmma, 250e-9)]).name
    'PMMA 250 nm on quartz'
    """

    substrate: AnyMaterial
    layers: Sequence[tuple[Any, float]] = ()

    def __post_init__(self) -> None:
        _check_material(self.substrate, "substrate")
        try:
            layers = tuple(self.layers)
        except TypeError:
            raise ContactresInputError(
                "layers must be a sequence of (material, thickness_m) pairs, got "
                f"{type(self.layers).__name__}"
            ) from None
        out = []
        for j, pair in enumerate(layers, start=1):
            if not (isinstance(pair, (tuple, list)) and len(pair) == 2):
                got = type(pair).__name__
                if isinstance(pair, (tuple, list)):
                    got += f" of {len(pair)} items"
                raise ContactresInputError(
                    f"layer {j} must be a (material, thickness_m) pair, got a {got}"
                )
            m = _check_material(pair[0], f"layer {j} material")
            out.append((m, _check_thickness(pair[1], j, len(layers))))
        object.__setattr__(self, "layers", tuple(out))

    # ----------------------------------------------------------------------------- views
    @property
    def materials(self) -> tuple:
        """The layers' materials, top first, then the substrate."""
        return (*(m for m, _ in self.layers), self.substrate)

    @property
    def thicknesses(self) -> np.ndarray:
        """The layers' thicknesses, m, top first (shape (n,); empty without layers)."""
        return np.array([h for _, h in self.layers], dtype=float)

    @property
    def top(self):
        """The material at the surface: the top layer, or the substrate without layers."""
        return self.materials[0]

    @property
    def density(self) -> float | None:
        """Density of the top material, kg/m^3 (None if it has none)."""
        return getattr(self.top, "density", None)

    @property
    def name(self) -> str:
        """E.g. ``"PMMA 250 nm on quartz"`` (layers top first, joined by "on")."""
        parts = [
            f"{getattr(m, 'name', None) or 'film'} {thickness_text(h)}" for m, h in self.layers
        ]
        return " on ".join([*parts, getattr(self.substrate, "name", None) or "substrate"])

    @property
    def is_lossy(self) -> bool:
        """True if any material is lossy; a frequency-dependent material without an
        ``is_lossy`` attribute counts as lossy (viscoelastic)."""
        return any(bool(getattr(m, "is_lossy", True)) for m in self.materials)

    @property
    def is_frequency_dependent(self) -> bool:
        """True if any material is not a plain :class:`~contactres.Material`."""
        return not all(isinstance(m, Material) for m in self.materials)

    def _facts(self) -> list[tuple[str, str]]:
        """The stack's name (layers and thicknesses), the number of layers, whether it is lossy
        or frequency-dependent (the materials themselves print with ``.materials``)."""
        facts = [("", repr(self.name)), ("layers", str(len(self.layers)))]
        if self.layers:
            facts.append(("total thickness", thickness_text(float(np.sum(self.thicknesses)))))
        facts.append(("lossy", "yes" if self.is_lossy else "no"))
        if self.is_frequency_dependent:
            facts.append(("frequency-dependent", "yes"))
        return facts

    # ----------------------------------------------------------------------------- operations
    def at(self, frequency: float) -> LayeredMaterial:
        """The stack with every material evaluated at ``frequency`` (Hz; 0: static limit)."""
        f = float(frequency)
        if not (math.isfinite(f) and f >= 0):
            raise ContactresInputError(f"frequency must be finite and >= 0 Hz, got {frequency!r}")
        return LayeredMaterial(
            material_at(self.substrate, f), tuple((material_at(m, f), h) for m, h in self.layers)
        )

    def rotated(self, normal=(0, 0, 1), inplane=None) -> LayeredMaterial:
        """The same stack with every material turned to the frame with z along ``normal`` and
        x along ``inplane`` (as :meth:`Material.rotated`; the layers stay parallel to the
        surface, so the rotation sets the crystal orientation of every layer alike)."""

        def turn(m):
            if not callable(getattr(m, "rotated", None)):
                raise ContactresInputError(f"{type(m).__name__} cannot be rotated")
            return m.rotated(normal, inplane)

        return LayeredMaterial(turn(self.substrate), tuple((turn(m), h) for m, h in self.layers))

    def with_loss(self, q_inv: float) -> LayeredMaterial:
        """The stack with every material given the loss C (1 + i Q^-1)
        (:meth:`Material.with_loss`)."""

        def lossy(m):
            if not callable(getattr(m, "with_loss", None)):
                raise ContactresInputError(f"{type(m).__name__} has no with_loss")
            return m.with_loss(q_inv)

        return LayeredMaterial(lossy(self.substrate), tuple((lossy(m), h) for m, h in self.layers))
