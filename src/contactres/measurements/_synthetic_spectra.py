"""Synthetic admittance spectra of a quartz resonator: the Butterworth–van Dyke circuit.

The forward side of the resonance-curve fit (:mod:`contactres.measurements._spectra`): the data
that the tests and the benchmark fit come from the *circuit* (R, L, C in series, C0 in parallel),
evaluated through its impedance, never through the fit's own resonance curve.

Butterworth–van Dyke (BVD) equivalent circuit of a quartz crystal near one overtone
(Johannsmann, *The Quartz Crystal Microbalance in Soft Matter Research*, Springer 2015, ch. 4;
paper 2 of this package, Vlachová, König, Johannsmann, Beilstein J. Nanotechnol. 6, 845 (2015),
measures f_r and Γ this way)::

    Y(ω) = iωC0 + 1 / (R + iωL + 1/(iωC)),      ω = 2πf.

The motional branch in the resonance parameters used throughout the package:

    f_r = 1 / (2π √(LC))      series resonance: the maximum of G = Re Y, Hz
    Γ   = R / (4π L)          half width at half height of G (exact for this circuit), Hz
    G_max = 1 / R             peak conductance, S

so that 1/(R + iωL + 1/(iωC)) = G_max / (1 + i (f² − f_r²)/(2 f Γ)) exactly, and the quality
factor is Q = f_r / (2Γ). :func:`bvd_circuit` and :func:`bvd_parameters` convert between the two
forms.

All quantities SI: frequencies Hz, admittances S, capacitances F, R in Ω, L in H.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ..validation import nonnegative, positive

__all__ = ["bvd_admittance", "bvd_circuit", "bvd_parameters", "synthetic_spectra"]


def bvd_circuit(f_r, gamma, g_max) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The BVD motional branch (R, L, C) of a resonance (f_r, Γ, G_max).

    Parameters
    ----------
    f_r : series resonance frequency, Hz (> 0)
    gamma : half width at half height Γ of the conductance, Hz (> 0)
    g_max : peak conductance, S (> 0)

    Returns
    -------
    R, L, C : Ω, H, F; ``R = 1/G_max``, ``L = R/(4πΓ)``, ``C = 1/((2π f_r)² L)``.
    """
    f_r = np.asarray(positive("f_r", f_r, "Hz"), dtype=float)
    gamma = np.asarray(positive("gamma", gamma, "Hz"), dtype=float)
    g_max = np.asarray(positive("g_max", g_max, "S"), dtype=float)
    R = 1.0 / g_max
    L = R / (4.0 * np.pi * gamma)
    C = 1.0 / ((2.0 * np.pi * f_r) ** 2 * L)
    return R, L, C


def bvd_parameters(R, L, C) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The resonance (f_r, Γ, G_max) of a BVD motional branch (R, L, C): the inverse of
    :func:`bvd_circuit`. ``f_r = 1/(2π√(LC))`` Hz, ``Γ = R/(4πL)`` Hz, ``G_max = 1/R`` S."""
    R = np.asarray(positive("R", R, "ohm"), dtype=float)
    L = np.asarray(positive("L", L, "H"), dtype=float)
    C = np.asarray(positive("C", C, "F"), dtype=float)
    return 1.0 / (2.0 * np.pi * np.sqrt(L * C)), R / (4.0 * np.pi * L), 1.0 / R


def bvd_admittance(frequency, f_r, gamma, g_max, c0=0.0) -> np.ndarray:
    """Admittance Y = G + iB of the BVD circuit, evaluated through its impedance.

    ``Y = iωC0 + 1/(R + iωL + 1/(iωC))`` with (R, L, C) from :func:`bvd_circuit`; arguments
    broadcast against each other.

    Parameters
    ----------
    frequency : f, Hz
    f_r, gamma, g_max : the resonance (Hz, Hz, S), see :func:`bvd_circuit`
    c0 : parallel (static) capacitance C0, F (>= 0)

    Returns
    -------
    complex ndarray, S. Near f_r the reactances ωL and 1/(ωC) (each ≈ Q/G_max) cancel, so about
    log10(Q) digits are lost: ~1e-10 relative at Q = 1e6, far below any measured noise.
    """
    R, L, C = bvd_circuit(f_r, gamma, g_max)
    c0 = np.asarray(nonnegative("c0", c0, "F"), dtype=float)
    omega = 2.0 * np.pi * np.asarray(frequency, dtype=float)
    z = R + 1j * omega * L + 1.0 / (1j * omega * C)
    return 1j * omega * c0 + 1.0 / z


def synthetic_spectra(
    f_r,
    gamma,
    g_max,
    *,
    n_points: int = 200,
    span=10.0,
    centre=0.0,
    noise=1e-3,
    c0=0.0,
    c0_drift=0.0,
    offset=0.0,
    baseline_slope=0.0,
    phase=0.0,
    seed=None,
) -> pd.DataFrame:
    """Admittance spectra of BVD resonators with noise, drift and an instrumental baseline.

    One spectrum per element of the broadcast per-spectrum arguments (``f_r``, ``gamma``,
    ``g_max`` and every keyword except ``n_points`` and ``seed``), vectorised. Spectrum k is
    measured at ``n_points`` equally spaced frequencies

        f = f_r + Γ (centre + span (t − 1/2)),   t = 0 … 1 (the sweep runs upwards),

    and reads

        Y = e^{iφ} [Y_m(f) + i 2πf C0(t)] + Y_off + s (f − f_r) + noise,

    Y_m the BVD motional branch (:func:`bvd_admittance`, through R, L, C),
    C0(t) = c0 + c0_drift·t a parallel capacitance drifting linearly in time during the sweep,
    φ = ``phase`` an instrumental phase rotation, Y_off = ``offset`` and s = ``baseline_slope``
    a complex offset and slope of the baseline.

    Parameters
    ----------
    f_r : series resonance frequency, Hz
    gamma : half width at half height Γ of the conductance, Hz
    g_max : peak conductance of the motional branch, S
    n_points : frequency points per spectrum (>= 1)
    span : the frequency span in units of Γ (full width, > 0); 10 covers f_r ± 5Γ
    centre : the centre of the span relative to f_r in units of Γ (5 with span 10: the peak at
        the lower edge)
    noise : standard deviation of the Gaussian noise, as a fraction of ``g_max``: independent
        normal noise of sd ``noise · g_max`` (S) on G and on B. ``1/noise`` is the peak
        signal-to-noise ratio (SNR): 1e-3 is SNR 1000. 0: noiseless
    c0 : parallel capacitance C0 at the start of the sweep, F (>= 0)
    c0_drift : change of C0 during the sweep (from its first to its last point), F
    offset : complex baseline offset G_off + iB_off, S
    baseline_slope : complex baseline slope, S/Hz, times (f − f_r)
    phase : phase rotation φ of the instrument, rad
    seed : seed of :func:`numpy.random.default_rng` (or a Generator); the noise is drawn as one
        array of shape (n_spectra, n_points, 2), [..., 0] on G and [..., 1] on B

    Returns
    -------
    pandas.DataFrame
        One row per frequency point, spectra in order: ``spectrum`` (text id ``s0``, ``s1``, …,
        zero-padded to equal width), ``frequency_Hz``, ``G_S``, ``B_S``. The caller adds the
        labels of the tidy spectra table.
    """
    n_points = int(n_points)
    if n_points < 1:
        raise ContactresInputError(f"n_points must be >= 1, got {n_points}")
    given = (f_r, gamma, g_max, span, centre, noise, c0, c0_drift, offset, baseline_slope, phase)
    names = "f_r gamma g_max span centre noise c0 c0_drift offset baseline_slope phase".split()
    arg = {k: np.ravel(v) for k, v in zip(names, np.broadcast_arrays(*given), strict=True)}
    for k, unit in (("f_r", "Hz"), ("gamma", "Hz"), ("g_max", "S"), ("span", None)):
        arg[k] = positive(k, arg[k], unit)
    for k, unit in (("noise", None), ("c0", "F")):
        arg[k] = nonnegative(k, arg[k], unit)
    for k in ("centre", "c0_drift", "phase", "offset", "baseline_slope"):
        arg[k] = np.asarray(arg[k], dtype=complex if k in ("offset", "baseline_slope") else float)
        if not np.all(np.isfinite(arg[k])):
            raise ContactresInputError(
                f"{k} must be finite, got {arg[k][~np.isfinite(arg[k])][0]!r}"
            )
    arg = {k: np.reshape(v, (-1, 1)) for k, v in arg.items()}  # one row per spectrum
    f_r, gamma, g_max = arg["f_r"], arg["gamma"], arg["g_max"]
    n = f_r.shape[0]
    t = np.linspace(0.0, 1.0, n_points) if n_points > 1 else np.full(1, 0.5)
    f = f_r + gamma * (arg["centre"] + arg["span"] * (t - 0.5))
    if np.any(f <= 0):
        raise ContactresInputError(
            "the frequencies f_r + Γ (centre + span (t − 1/2)) must be > 0 (Hz)"
        )
    y = bvd_admittance(f, f_r, gamma, g_max) + 2j * np.pi * f * (arg["c0"] + arg["c0_drift"] * t)
    y = np.exp(1j * arg["phase"]) * y + arg["offset"] + arg["baseline_slope"] * (f - f_r)
    rng = np.random.default_rng(seed)
    z = rng.standard_normal((n, n_points, 2)) * (arg["noise"] * g_max)[:, :, None]
    width = len(str(max(n - 1, 0)))
    ids = np.array([f"s{k:0{width}d}" for k in range(n)], dtype=object)
    return pd.DataFrame(
        {
            "spectrum": np.repeat(ids, n_points),
            "frequency_Hz": f.ravel(),
            "G_S": (y.real + z[..., 0]).ravel(),
            "B_S": (y.imag + z[..., 1]).ravel(),
        }
    )


def spectra_from_sweeps(
    sweeps: pd.DataFrame,
    *,
    gamma_ref: float = 300.0,
    g_max_ref: float = 5e-3,
    n_points: int = 60,
    span: float = 10.0,
    noise: float = 1e-3,
    c0: float = 4e-12,
    n_references: int = 2,
    d26: float | None = None,
    seed=None,
) -> pd.DataFrame:
    """The admittance spectra behind a sweep table: the tidy spectra table of a study.

    Every point of ``sweeps`` (columns of the sweep table: sweep, amplitude_m, df_Hz,
    dgamma_Hz, normal_force_N, overtone, fundamental_Hz and the labels) becomes one spectrum of
    the BVD resonator with f_r = f_ref + Δf and Γ = Γ_ref + ΔΓ (f_ref = n × fundamental_Hz);
    its peak conductance falls as 1/Γ (G_max = 1/R, R ∝ Γ) and its drive voltage is the one
    that gives the point's amplitude, U = u0 (nπ)²/(4 d26 Q), Q = f_r/(2Γ)
    (:func:`contactres.measurements._shifts.shear_amplitude`). ``n_references`` no-contact
    reference spectra (f_ref, Γ_ref) are added per (overtone, configuration, medium,
    experiment). Noise, C0 and span as in :func:`synthetic_spectra`; seeded.

    Returns
    -------
    pandas.DataFrame
        The tidy spectra table (columns of
        :data:`contactres.measurements._spectra_table.SPECTRA_TABLE`), references first.
    """
    from ._shifts import D26_AT

    d26 = D26_AT if d26 is None else float(d26)
    n = sweeps["overtone"].to_numpy(float)
    f_ref = n * sweeps["fundamental_Hz"].to_numpy(float)
    f_r = f_ref + sweeps["df_Hz"].to_numpy(float)
    gamma = gamma_ref + sweeps["dgamma_Hz"].to_numpy(float)
    quality = f_r / (2 * gamma)
    voltage = sweeps["amplitude_m"].to_numpy(float) * (n * np.pi) ** 2 / (4 * d26 * quality)
    keys = ["overtone", "fundamental_Hz", "configuration", "medium", "experiment"]
    refs = sweeps[keys].drop_duplicates().reset_index(drop=True)
    refs = refs.loc[refs.index.repeat(n_references)].reset_index(drop=True)
    ref_f = refs["overtone"].to_numpy(float) * refs["fundamental_Hz"].to_numpy(float)
    all_f = np.concatenate([ref_f, f_r])
    all_gamma = np.concatenate([np.full(ref_f.size, gamma_ref), gamma])
    spectra = synthetic_spectra(
        all_f,
        all_gamma,
        g_max_ref * gamma_ref / all_gamma,
        n_points=n_points,
        span=span,
        noise=noise * gamma_ref / all_gamma,  # the same absolute noise on every spectrum
        c0=c0,
        seed=seed,
    )
    n_ref = ref_f.size
    labels = pd.DataFrame(
        {
            "reference": np.r_[np.ones(n_ref, bool), np.zeros(len(sweeps), bool)],
            "overtone": np.r_[refs["overtone"].to_numpy(int), n.astype(int)],
            "drive_voltage_V": np.r_[np.full(n_ref, 0.1), voltage],
            "sweep": np.r_[np.full(n_ref, ""), sweeps["sweep"].astype(str).to_numpy()],
            "normal_force_N": np.r_[
                np.full(n_ref, np.nan), sweeps["normal_force_N"].to_numpy(float)
            ],
            **{
                col: np.r_[refs[col].astype(str).to_numpy(), sweeps[col].astype(str).to_numpy()]
                for col in ("configuration", "medium", "experiment")
            },
        }
    )
    if "ramp" in sweeps.columns:
        labels["ramp"] = np.r_[np.full(n_ref, np.nan), sweeps["ramp"].to_numpy(float)]
    for col in ("area_m2", "n_contacts", "sphere_radius_m", "poisson", "fundamental_Hz"):
        if col in sweeps.columns:  # the sweep table's constants, carried along
            labels[col] = np.r_[np.full(n_ref, np.nan), sweeps[col].to_numpy(float)]
    ids = spectra["spectrum"].drop_duplicates().to_numpy()
    labels.insert(0, "spectrum", ids)
    out = spectra.merge(labels, on="spectrum", how="left", validate="many_to_one")
    if "ramp" in out.columns:
        out["ramp"] = out["ramp"].astype("Int64")
    return out
