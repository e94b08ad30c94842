"""A synthetic contact-resonance AFM map of polycrystalline copper (the README's walkthrough).

One row per pixel in the schema of :data:`~contactres.measurements._resonances.AFM_TABLE`, so the
table goes straight into ``contactres afm invert`` / :func:`contactres.invert_afm_table`; the
pixel coordinates ``x_m``, ``y_m`` are extra columns, carried through to the output. The forward
chain, per grain::

    surface normal of the grain -> M_sample = indentation modulus of Cu on that face
    (paper 1, Eq. 4; :func:`~contactres.normal.indentation_modulus`)
    -> 1/E* = 1/M_tip + 1/M_sample (Si tip along [001])
    -> Hertz: a = (3PR/(4E*))^(1/3), k* = 2aE* (K. L. Johnson, Contact Mechanics, Cambridge
       University Press 1985, Eqs. 4.22-4.23)
    -> κ = k*/k_c -> contact resonances of modes 1 and 2 of an Euler-Bernoulli lever with the tip
       at r = L1/L (U. Rabe, K. Janser, W. Arnold, Rev. Sci. Instrum. 67, 3281 (1996);
       :func:`~contactres.resonators.contact_frequencies`)
    -> optional Gaussian noise on every frequency, Hz.

The inversion runs the other way through different code (the closed form of κ(β) in
:mod:`~contactres.resonators`, E* = √(k*³/(6RP)) in
:mod:`~contactres.analysis`), so a noise-free map must come back to the
M_sample of the truth: tests/measurements/test_afm_example.py checks 1e-6.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ..materials import Material
from ..normal import indentation_modulus
from ..resonators import FREE_ROOTS, Cantilever, contact_frequencies
from ..validation import nonnegative, positive

__all__ = ["NAMED_SURFACES", "ExampleLever", "example_afm_map"]

#: The surfaces of the first three grains (the rest are random): softest to stiffest for Cu.
NAMED_SURFACES = ((0, 0, 1), (0, 1, 1), (1, 1, 1))


@dataclass(frozen=True)
class ExampleLever:
    """Lever, tip and load of the example map (a stiff CR-AFM lever, a sharp Si tip).

    Parameters
    ----------
    f1_free : first free flexural resonance, Hz (f2 follows for an ideal beam, 6.267 f1)
    spring_constant : k_c = 3EI/L³, static spring constant at the free end, N/m
    tip_position : r = L1/L of the tip, dimensionless in (0, 1]
    tip_radius : Hertz radius R of the tip, m
    load : normal load P, N
    tip_crystal, tip_surface : the tip's crystal and the face it presents (Miller indices);
        M_tip is its indentation modulus (Si[001]: 164.8 GPa)
    sample_crystal : the crystal of the grains (a name of :func:`contactres.crystal_names`)
    """

    f1_free: float = 160e3
    spring_constant: float = 40.0
    tip_position: float = 0.95
    tip_radius: float = 50e-9
    load: float = 1e-6
    tip_crystal: str = "Si"
    tip_surface: tuple[int, int, int] = (0, 0, 1)
    sample_crystal: str = "Cu"

    def cantilever(self) -> Cantilever:
        """The free lever: f1 and the ideal-beam f2 = f1 (β₂⁰/β₁⁰)², global normalisation."""
        f2 = self.f1_free * (FREE_ROOTS[1] / FREE_ROOTS[0]) ** 2
        return Cantilever((self.f1_free, f2), self.spring_constant)

    def tip_modulus(self) -> float:
        """M_tip, Pa: the indentation modulus of the tip crystal on ``tip_surface``."""
        tip = Material.crystal(self.tip_crystal).rotated(self.tip_surface)
        return float(np.real(indentation_modulus(tip)))


def _grains(shape, n_grains, rng):
    """Voronoi grains: the index of the nearest of ``n_grains`` uniform seeds, per pixel."""
    seeds = rng.random((n_grains, 2)) * np.array(shape)
    iy, ix = np.indices(shape)
    d2 = (iy[..., None] + 0.5 - seeds[:, 0]) ** 2 + (ix[..., None] + 0.5 - seeds[:, 1]) ** 2
    return np.argmin(d2, axis=-1)


def _surface_label(normal) -> str:
    n = np.asarray(normal, dtype=float)
    if np.allclose(n, np.round(n)):
        return "(" + "".join(str(int(v)) for v in np.round(n).astype(int)) + ")"
    return "random"


def example_afm_map(
    shape: tuple[int, int] = (64, 64),
    *,
    pixel_size: float = 100e-9,
    n_grains: int = 8,
    noise: float = 0.0,
    seed: int = 0,
    lever: ExampleLever = ExampleLever(),  # frozen: one shared default is safe
    truth: bool = False,
) -> pd.DataFrame | tuple[pd.DataFrame, pd.DataFrame]:
    """A CR-AFM map of polycrystalline Cu, one row per pixel, in the AFM table's schema.

    Grains are the Voronoi cells of ``n_grains`` seeds; the first three show the (001), (011)
    and (111) faces (:data:`NAMED_SURFACES`), the others random faces. Every pixel of a grain has
    the grain's contact resonances (module notes: Hertz contact, Rabe et al. 1996 lever), plus
    Gaussian noise of ``noise`` Hz on each frequency.

    Parameters
    ----------
    shape : (ny, nx) pixels
    pixel_size : pixel pitch, m (100 nm: a 6.4 µm square for 64 x 64)
    n_grains : number of grains, >= 3
    noise : standard deviation of the Gaussian noise on fc1_Hz and fc2_Hz, Hz (default 0: exact
        frequencies; ~10 Hz is a good tracking loop at these ~0.7 and ~2.4 MHz resonances)
    seed : seed of :func:`numpy.random.default_rng`. Draws, in order: the grain seeds
        (n_grains x 2), the random surface normals ((n_grains − 3) x 3, normal distribution),
        then, only if ``noise > 0``, the noise (pixels x 2), so the grains do not depend on
        ``noise``
    lever : the lever, tip and load (:class:`ExampleLever`; frozen)
    truth : also return the truth per pixel

    Returns
    -------
    table : DataFrame with x_m, y_m (m; row-major, y slow), f1_free_Hz, f2_free_Hz,
        k_c_N_per_m, tip_position, fc1_Hz, fc2_Hz, tip_radius_m, load_N, M_tip_Pa. Drop
        ``tip_position`` to have the inversion solve r from the two modes.
    truth : (only with ``truth=True``) DataFrame in the same row order with x_m, y_m, grain,
        surface ("(001)", "(011)", "(111)" or "random"), M_sample_Pa, E_star_Pa,
        k_star_N_per_m, kappa and the noise-free fc1_Hz, fc2_Hz.
    """
    if np.ndim(shape) != 1 or len(shape) != 2:
        raise ContactresInputError(f"shape must be (ny, nx) pixels, got {shape!r}")
    ny, nx = (int(v) for v in shape)
    positive("shape", np.array([ny, nx]), "pixels")
    positive("pixel_size", pixel_size, "m")
    nonnegative("noise", noise, "Hz")
    if int(n_grains) < len(NAMED_SURFACES):
        raise ContactresInputError(f"n_grains must be >= {len(NAMED_SURFACES)}, got {n_grains!r}")
    rng = np.random.default_rng(seed)
    grain = _grains((ny, nx), int(n_grains), rng).ravel()
    normals = [*NAMED_SURFACES, *rng.standard_normal((int(n_grains) - 3, 3))]

    # Forward per grain (a handful of anisotropic M), then spread over the pixels.
    cu = Material.crystal(lever.sample_crystal)
    m_grain = np.array([float(np.real(indentation_modulus(cu.rotated(n)))) for n in normals])
    m_tip = lever.tip_modulus()
    e_star = 1.0 / (1.0 / m_tip + 1.0 / m_grain)
    a = (3.0 * lever.load * lever.tip_radius / (4.0 * e_star)) ** (1.0 / 3.0)
    k_star = 2.0 * a * e_star
    kappa = k_star / lever.spring_constant
    cant = lever.cantilever()
    f_grain = contact_frequencies(cant, kappa, lever.tip_position, modes=(1, 2))
    f_true = f_grain[grain]
    f_meas = f_true + (noise * rng.standard_normal(f_true.shape) if noise > 0 else 0.0)

    iy, ix = np.divmod(np.arange(ny * nx), nx)
    xy = {"x_m": ix * pixel_size, "y_m": iy * pixel_size}
    n = ny * nx
    table = pd.DataFrame(
        {
            **xy,
            "f1_free_Hz": np.full(n, cant.free_frequencies[0]),
            "f2_free_Hz": np.full(n, cant.free_frequencies[1]),
            "k_c_N_per_m": np.full(n, lever.spring_constant),
            "tip_position": np.full(n, lever.tip_position),
            "fc1_Hz": f_meas[:, 0],
            "fc2_Hz": f_meas[:, 1],
            "tip_radius_m": np.full(n, lever.tip_radius),
            "load_N": np.full(n, lever.load),
            "M_tip_Pa": np.full(n, m_tip),
        }
    )
    if not truth:
        return table
    labels = np.array([_surface_label(v) for v in normals], dtype=object)
    true = pd.DataFrame(
        {
            **xy,
            "grain": grain,
            "surface": labels[grain],
            "M_sample_Pa": m_grain[grain],
            "E_star_Pa": e_star[grain],
            "k_star_N_per_m": k_star[grain],
            "kappa": kappa[grain],
            "fc1_Hz": f_true[:, 0],
            "fc2_Hz": f_true[:, 1],
        }
    )
    return table, true
