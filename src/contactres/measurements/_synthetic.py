"""Synthetic QCM amplitude sweeps from the package's forward model (paper 2).

The one generator of synthetic sweep tables for the example data, the tests and the benchmarks.
Every point follows the forward chain of paper 2::

    sphere + load -> JKR contact radius a (Eq. 9, with E* of Eq. 10)
    -> Mindlin stiffness κ = 2G*a (Eq. 7, G = E/(2(1 + ν)) of Eq. 8)
    -> tangential loop (Cattaneo-Mindlin, Eq. 6; Savkoor, Eqs. 13-14; a stick plateau; or a
       Voigt element) with a dashpot ωξ in parallel (Eq. 12)
    -> QCM shifts Δf(u0), ΔΓ(u0) (Eqs. 4-5; Eq. 1 for the Voigt element)
    -> Gaussian noise on both shifts.

A study is a frozen :class:`SweepStudy` (groups of configuration x medium, loads, experiments,
ramps, scatter, special cases); :func:`synthetic_sweeps` turns it and a seeded random generator
into a sweep table, one row per point. The random numbers are drawn in a fixed, documented order
(see :func:`synthetic_sweeps`), so a study and a seed give the same table on every run.
:mod:`contactres.measurements._studies` holds the recipes (the bundled example, the validation
study).

All quantities SI: forces N, lengths m, moduli Pa, γ J/m², stiffness N/m, shifts Hz.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from .._summary import Summarised, number, values
from ..errors import ContactresInputError
from ..normal import effective_modulus, jkr_contact_radius
from ..resonators import QCM, shifts_from_loop, shifts_from_stiffness
from ..tangential import (
    CattaneoMindlinLoop,
    DashpotLoop,
    MasingLoop,
    PlateauLoop,
    SavkoorLoop,
    VoigtLoop,
    kappa_jkr_mindlin,
    with_dashpot,
)
from ..validation import nonnegative, positive
from ._sweeps import VALIDATED_COLUMNS

__all__ = [
    "LOOP_MODELS",
    "SCATTERED",
    "Drift",
    "SweepGroup",
    "SweepStudy",
    "contact_loop",
    "sweep_shifts",
    "synthetic_sweeps",
]

#: Tangential contact models of a synthetic sweep (the names the sweep classifier reports).
LOOP_MODELS = ("cattaneo-mindlin", "plateau", "savkoor", "elastic")

#: Quantities that may scatter between experiments (or loads): E, γ and μ.
SCATTERED = ("E", "gamma", "mu")

# Columns of the table, in the order of a validated table; the constants follow when asked for.
_COLUMNS = (*VALIDATED_COLUMNS[: VALIDATED_COLUMNS.index("dgamma_Hz") + 1], "sphere_radius_m")


# repr=False: the summary (Summarised, _facts) replaces the list of every amplitude.
@dataclass(frozen=True, repr=False)
class SweepGroup(Summarised):
    """One sample configuration in one medium: the sphere, its material, ramp and noise.

    Parameters
    ----------
    configuration : name of the configuration (e.g. ``"SiO2_2.2mm"``)
    medium : name of the medium (e.g. ``"air"``)
    radius : sphere radius R, m
    E : Young's modulus of sphere and flat (E1 = E2 = E, paper 2, Eq. 10), Pa
    gamma : surface energy γ of paper 2, Eq. 9 (work of adhesion w = 2γ), J/m²
    amplitudes : the amplitude ramp upwards, u0, m (increasing, >= 0)
    omega_xi : ωξ of the dashpot in parallel with every contact (paper 2, Eq. 12), N/m; the
        low-amplitude half-bandwidth shift is ΔΓ0 = P ωξ (Eq. 1)
    noise : standard deviation of the Gaussian noise on Δf and on ΔΓ, Hz
    """

    configuration: str
    medium: str
    radius: float
    E: float
    gamma: float
    amplitudes: tuple[float, ...]
    omega_xi: float
    noise: float

    def __post_init__(self):
        u = nonnegative(f"{self.configuration}/{self.medium} amplitudes", self.amplitudes, "m")
        u = np.atleast_1d(u)
        if u.size < 1 or np.any(np.diff(u) <= 0):
            raise ContactresInputError(
                f"amplitudes must increase strictly, got {self.amplitudes!r}"
            )
        # A tuple keeps the dataclass hashable and its values exactly as given.
        object.__setattr__(self, "amplitudes", tuple(float(x) for x in u))
        positive("sphere radius", self.radius, "m")
        positive("E", self.E, "Pa")
        nonnegative("gamma", self.gamma, "J/m^2")
        nonnegative("omega_xi", self.omega_xi, "N/m")
        nonnegative("noise", self.noise, "Hz")

    def _facts(self) -> list[tuple[str, str]]:
        """Configuration and medium, R (mm), E (GPa), γ (mJ/m²), the ramp (nm), ωξ, noise."""
        return [
            ("", f"{self.configuration}/{self.medium}"),
            ("R", number(self.radius, "mm", 1e-3)),
            ("E", number(self.E, "GPa", 1e9)),
            ("γ", number(self.gamma, "mJ/m²", 1e-3)),
            ("amplitudes", values(np.array(self.amplitudes), "nm", 1e-9)),
            ("ωξ", number(self.omega_xi, "N/m")),
            ("noise", number(self.noise, "Hz")),
        ]


@dataclass(frozen=True)
class Drift:
    """A baseline drift of Δf in one load of one experiment: +``rate`` Hz per ramp after ramp 1.

    ``experiment`` counts from 1 and ``load`` is the index into the study's normal forces, as in
    the sweep ids ``{configuration}/{medium}/e{experiment}/F{load}/r{ramp}``.
    """

    configuration: str
    medium: str
    experiment: int
    load: int
    rate: float


# repr=False: the summary (Summarised, _facts) replaces the printout of every group.
@dataclass(frozen=True, repr=False)
class SweepStudy(Summarised):
    """Parameters of a synthetic study of QCM amplitude sweeps (paper 2's experiment).

    For every group, every experiment 1 ... ``n_experiments``, every normal force and every
    ramp, one amplitude sweep. Odd ramps run up the amplitudes, even ramps down (paper 2: up,
    down, up, down) unless ``alternate`` is False.

    Parameters
    ----------
    groups : configurations x media (:class:`SweepGroup`)
    normal_forces : normal force per contact F_N, N (tripod: F_N = m g / 3)
    n_experiments : repeated mountings of the sample per group
    ramps : ramp numbers within one load of one experiment (ramp 1 is the running-in ramp)
    alternate : even ramps run downwards
    qcm : the resonator (fundamental, overtone, effective area A_eff, Z_q)
    n_contacts : equal contacts on the resonator n_P (3 for a tripod; paper 2, Eq. 1)
    poisson : Poisson ratio ν of sphere and flat (paper 2 takes 0.17)
    mu : friction coefficient μ at the first normal force
    mu_exponent : μ(F_N) = ``mu`` (F_N / F_first)^``mu_exponent`` (0: load-independent)
    model : tangential model of every sweep, one of :data:`LOOP_MODELS`
    plateau_fraction : for ``model="plateau"``, the critical displacement d_c as a fraction of
        the largest amplitude
    savkoor_sliding : for Savkoor sweeps, the amplitude of full sliding 4a²τ0/κ (paper 2,
        Eq. 14) as a multiple of the largest amplitude; it sets τ0
    scatter : ``(quantity, sd)`` pairs, quantities from :data:`SCATTERED`: each is multiplied by
        a random factor, drawn in the listed order (also when sd = 0)
    scatter_law : ``"lognormal"`` (factor exp(sd·z)) or ``"normal"`` (factor 1 + sd·z)
    scatter_per : draw the factors once per ``"experiment"`` or once per ``"load"``
    running_in_kappa, running_in_mu : factors on κ and μ in ramp 1
    random_plateau : probability that a load of an experiment shows a stick plateau in its
        ramps other than ramp 1 (Cattaneo-Mindlin sweeps only); 0: never, and nothing drawn
    random_plateau_range : range of its critical displacement, fractions of the largest amplitude
    savkoor_experiments : ``(configuration, medium, experiment)`` whose sweeps follow Savkoor
    drifts : baseline drifts (:class:`Drift`)
    """

    groups: tuple[SweepGroup, ...]
    normal_forces: tuple[float, ...]
    n_experiments: int = 4
    ramps: tuple[int, ...] = (1, 2, 3, 4)
    alternate: bool = True
    qcm: QCM = field(default_factory=lambda: QCM(5e6, 3, 2.5e-5))
    n_contacts: int = 3
    poisson: float = 0.17
    mu: float = 1.0
    mu_exponent: float = 0.0
    model: str = "cattaneo-mindlin"
    plateau_fraction: float = 0.4
    savkoor_sliding: float = 2.0
    scatter: tuple[tuple[str, float], ...] = ()
    scatter_law: str = "lognormal"
    scatter_per: str = "experiment"
    running_in_kappa: float = 1.0
    running_in_mu: float = 1.0
    random_plateau: float = 0.0
    random_plateau_range: tuple[float, float] = (0.25, 0.4)
    savkoor_experiments: tuple[tuple[str, str, int], ...] = ()
    drifts: tuple[Drift, ...] = ()

    def _facts(self) -> list[tuple[str, str]]:
        """The groups by name, the loads (mN), experiments, ramps, the model and μ."""
        names = [f"{g.configuration}/{g.medium}" for g in self.groups]
        shown = ", ".join(names[:3]) + (", …" if len(names) > 3 else "")
        return [
            ("groups", f"{len(names)} ({shown})"),
            ("F_N", values(np.array(self.normal_forces), "mN", 1e-3)),
            ("experiments", str(self.n_experiments)),
            ("ramps", str(len(self.ramps))),
            ("model", self.model),
            ("μ", number(self.mu)),
        ]

    def __post_init__(self):
        object.__setattr__(self, "groups", tuple(self.groups))
        object.__setattr__(self, "normal_forces", tuple(float(f) for f in self.normal_forces))
        object.__setattr__(self, "ramps", tuple(int(r) for r in self.ramps))
        object.__setattr__(self, "scatter", tuple((str(q), float(s)) for q, s in self.scatter))
        if not self.groups:
            raise ContactresInputError("a study needs at least one group")
        if not self.normal_forces:
            raise ContactresInputError("a study needs at least one normal force")
        positive("normal_forces", self.normal_forces, "N")
        if self.n_experiments < 1 or not self.ramps or min(self.ramps) < 1:
            raise ContactresInputError(
                "n_experiments and ramp numbers must be >= 1, with at least one ramp"
            )
        positive("mu", self.mu)
        for name in ("plateau_fraction", "running_in_kappa", "running_in_mu", "savkoor_sliding"):
            positive(name, getattr(self, name))
        if self.model not in LOOP_MODELS:
            raise ContactresInputError(f"model must be one of {LOOP_MODELS}, got {self.model!r}")
        for q, sd in self.scatter:
            if q not in SCATTERED:
                raise ContactresInputError(
                    f"scatter quantity must be one of {SCATTERED}, got {q!r}"
                )
            nonnegative(f"scatter of {q}", sd)
        if self.scatter_law not in ("lognormal", "normal"):
            raise ContactresInputError(
                f"scatter_law: 'lognormal' or 'normal', not {self.scatter_law!r}"
            )
        if self.scatter_per not in ("experiment", "load"):
            raise ContactresInputError(
                f"scatter_per: 'experiment' or 'load', not {self.scatter_per!r}"
            )
        lo, hi = self.random_plateau_range
        if not (0.0 <= self.random_plateau <= 1.0 and 0.0 <= lo <= hi):
            raise ContactresInputError(
                "random_plateau must lie in [0, 1] and its range in order, >= 0"
            )


def contact_loop(
    model: str,
    kappa: float,
    mu: float,
    normal_force: float,
    omega_xi: float,
    omega: float,
    *,
    critical_displacement: float = 0.0,
    contact_radius: float = np.nan,
    sliding_amplitude: float = np.nan,
) -> DashpotLoop | VoigtLoop:
    """The tangential force-displacement loop of one contact, with its dashpot (paper 2).

    Parameters
    ----------
    model : one of :data:`LOOP_MODELS`:
        ``"cattaneo-mindlin"``: Coulomb partial slip (paper 2, Eq. 6), Masing loops;
        ``"plateau"``: the same behind a stick plateau up to ``critical_displacement``;
        ``"savkoor"``: constant sliding traction τ0 (paper 2, Eqs. 13-14), with τ0 set so that
        full sliding 4a²τ0/κ happens at ``sliding_amplitude``;
        ``"elastic"``: a Voigt element κ, ξ (no slip; paper 2, Eq. 1)
    kappa : tangential stiffness κ, N/m
    mu : friction coefficient μ (Cattaneo-Mindlin and plateau)
    normal_force : normal force per contact F_N, N
    omega_xi : ωξ of the dashpot in parallel (paper 2, Eq. 12), N/m
    omega : angular frequency of the resonator ω, rad/s
    critical_displacement : d_c of the plateau, m
    contact_radius : contact radius a (Savkoor), m
    sliding_amplitude : amplitude of full sliding (Savkoor), m

    Returns
    -------
    loop : DashpotLoop | VoigtLoop
        The slip loop with the dashpot in parallel, or the Voigt element for ``"elastic"``.
    """
    xi = omega_xi / omega
    if model == "elastic":
        return VoigtLoop(kappa, xi, omega)
    if model == "savkoor":
        tau = kappa * sliding_amplitude / (4.0 * contact_radius**2)
        loop: MasingLoop = SavkoorLoop(kappa, tau, contact_radius)
    elif model in ("cattaneo-mindlin", "plateau"):
        loop = CattaneoMindlinLoop(kappa, mu, normal_force)
        if model == "plateau":
            loop = PlateauLoop(loop, critical_displacement)
    else:
        raise ContactresInputError(f"model must be one of {LOOP_MODELS}, got {model!r}")
    return with_dashpot(loop, xi, omega)


def sweep_shifts(q: QCM, loop, amplitudes, n_contacts: int) -> tuple[np.ndarray, np.ndarray]:
    """Noise-free Δf(u0), ΔΓ(u0) of n_P equal contacts following ``loop``, Hz.

    Paper 2, Eqs. 4-5 (the first Fourier component of the loop force) for a slip loop; Eq. 1
    for a Voigt element, whose shifts P κ and P ωξ do not depend on the amplitude.

    Parameters
    ----------
    q : the resonator
    loop : a loop from :func:`contact_loop`
    amplitudes : oscillation amplitudes u0, m (1-d array)
    n_contacts : number of equal contacts n_P

    Returns
    -------
    df, dgamma : numpy.ndarray
        Δf and ΔΓ at every amplitude (the shape of ``amplitudes``), Hz
    """
    u = np.asarray(amplitudes, dtype=float)
    if isinstance(loop, VoigtLoop):
        df, dg = shifts_from_stiffness(q, loop.kappa, loop.xi, n_contacts)
        return np.full(u.shape, df), np.full(u.shape, dg)
    df, dg = shifts_from_loop(q, loop, u, n_contacts)
    return np.asarray(df), np.asarray(dg)


def _factors(study: SweepStudy, rng: np.random.Generator) -> dict[str, float]:
    """Scatter factors of E, γ, μ (1.0 where not scattered), drawn in the listed order."""
    out = dict.fromkeys(SCATTERED, 1.0)
    for q, sd in study.scatter:
        if study.scatter_law == "lognormal":
            out[q] = rng.lognormal(0.0, sd)
        else:
            out[q] = 1 + sd * rng.standard_normal()
    return out


def synthetic_sweeps(
    study: SweepStudy,
    rng: np.random.Generator | int,
    *,
    constants: bool = False,
    truth: bool = False,
) -> pd.DataFrame:
    """The sweep table of ``study``: one row per point, noise from ``rng``.

    For each sweep the contact follows paper 2's forward model: κ(F_N) from JKR (Eq. 9) and
    Mindlin (κ = 2G*a, Eq. 7) with the experiment's E and γ; μ(F_N) = μ (F_N/F_first)^exponent;
    ramp 1 scaled by the running-in factors; the loop of :func:`contact_loop` (with the group's
    dashpot ωξ, Eq. 12); the shifts of :func:`sweep_shifts` (Eqs. 4-5 or 1); Gaussian noise of
    the group's standard deviation added to Δf and to ΔΓ; a drift added to Δf where asked.

    Order of the random draws (fixed, so that a seed fixes the table): groups in order, then
    experiments, loads and ramps; per experiment the scatter factors (if drawn per experiment);
    per load the scatter factors (if drawn per load), then, if ``random_plateau`` > 0, a uniform
    number deciding the plateau and one for its critical displacement; per ramp the noise of Δf
    (one number per point, in the ramp's order), then that of ΔΓ. Noise is drawn also when its
    standard deviation is 0, so a noise-free study with the same seed has the same contacts.

    Parameters
    ----------
    study : the study
    rng : a numpy random generator (used and advanced) or a seed
    constants : append the constant columns ``fundamental_Hz``, ``overtone``, ``area_m2``,
        ``n_contacts``, ``poisson`` (the study's resonator), so the table stands on its own
    truth : append the true contact of every sweep, for validation studies:
        ``true_model`` (one of :data:`LOOP_MODELS`), ``true_kappa_N_per_m``, ``true_mu``,
        ``true_omega_xi_N_per_m``, ``true_critical_displacement_m`` (plateau, else NaN),
        ``true_sliding_force_N`` (Savkoor: πa²τ0, else NaN), ``true_drift`` (a drift is added);
        not columns of the sweep table, so drop them before analysing

    Returns
    -------
    table : pandas.DataFrame
        Columns ``sweep`` (``{configuration}/{medium}/e{experiment}/F{load index}/r{ramp}``),
        ``experiment`` (``e1``, ``e2``, ...), ``configuration``, ``medium``, ``ramp``,
        ``normal_force_N`` (N), ``amplitude_m`` (m), ``df_Hz``, ``dgamma_Hz`` (Hz),
        ``sphere_radius_m`` (m), then the constants if asked for.
    """
    rng = np.random.default_rng(rng)
    q, nu, n_p = study.qcm, study.poisson, study.n_contacts
    f_first = study.normal_forces[0]
    drifts = {(d.configuration, d.medium, d.experiment, d.load): d.rate for d in study.drifts}
    labels: list[tuple] = []  # (sweep, experiment, configuration, medium, ramp, F, R) per sweep
    truths: list[tuple] = []  # (model, κ, μ, ωξ, d_c, F_s, drift) per sweep
    parts: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # (u, df, dgamma) per sweep
    for g in study.groups:
        u_up = np.asarray(g.amplitudes, dtype=float)
        # Within a group, ramps that share a loop share its shifts (the loops are history-free):
        # computed once on the upward ramp, reversed for a downward one.
        shifts: dict = {}
        u_max = u_up[-1]
        factor = dict.fromkeys(SCATTERED, 1.0)
        for e in range(1, study.n_experiments + 1):
            if study.scatter_per == "experiment":
                factor = _factors(study, rng)
            savkoor = (g.configuration, g.medium, e) in study.savkoor_experiments
            for j, force in enumerate(study.normal_forces):
                if study.scatter_per == "load":
                    factor = _factors(study, rng)
                E = g.E * factor["E"]
                gamma = g.gamma * factor["gamma"]
                kappa0 = kappa_jkr_mindlin(force, E, gamma, g.radius, nu)
                mu0 = study.mu * (force / f_first) ** study.mu_exponent * factor["mu"]
                a = jkr_contact_radius(effective_modulus(E, nu), g.radius, force, gamma)
                # A random plateau belongs to a load of an experiment, not to one ramp.
                plateau, dc_random = False, 0.0
                if study.random_plateau > 0:
                    plateau = rng.random() < study.random_plateau
                    dc_random = rng.uniform(*study.random_plateau_range) * u_max
                for ramp in study.ramps:
                    first = ramp == 1
                    kappa = kappa0 * (study.running_in_kappa if first else 1.0)
                    mu = mu0 * (study.running_in_mu if first else 1.0)
                    model, dc = study.model, study.plateau_fraction * u_max
                    if savkoor:
                        model = "savkoor"
                    elif plateau and not first and model == "cattaneo-mindlin":
                        model, dc = "plateau", dc_random
                    loop = contact_loop(
                        model,
                        kappa,
                        mu,
                        force,
                        g.omega_xi,
                        q.omega,
                        critical_displacement=dc,
                        contact_radius=a,
                        sliding_amplitude=study.savkoor_sliding * u_max,
                    )
                    if loop not in shifts:
                        shifts[loop] = sweep_shifts(q, loop, u_up, n_p)
                    df, dg = shifts[loop]
                    u = u_up
                    if study.alternate and ramp % 2 == 0:
                        u, df, dg = u_up[::-1], df[::-1], dg[::-1]
                    df = df + rng.normal(0.0, g.noise, u.size)
                    dg = dg + rng.normal(0.0, g.noise, u.size)
                    rate = drifts.get((g.configuration, g.medium, e, j))
                    if rate is not None:
                        df = df + rate * (ramp - 1)
                    sweep = f"{g.configuration}/{g.medium}/e{e}/F{j}/r{ramp}"
                    truths.append(
                        (
                            model,
                            kappa,
                            mu if model in ("cattaneo-mindlin", "plateau") else np.nan,
                            g.omega_xi,
                            dc if model == "plateau" else np.nan,
                            # Savkoor: F_s = πa²τ0 with 4a²τ0/κ the sliding amplitude.
                            np.pi * kappa * study.savkoor_sliding * u_max / 4.0
                            if model == "savkoor"
                            else np.nan,
                            rate is not None and ramp > 1,
                        )
                    )
                    labels.append(
                        (sweep, f"e{e}", g.configuration, g.medium, ramp, force, g.radius)
                    )
                    parts.append((u, df, dg))
    # One table from whole columns: per-sweep labels repeated over the sweep's points.
    sizes = [u.size for u, _, _ in parts]
    names: tuple[str, ...] = ("sweep", "experiment", "configuration", "medium", "ramp")
    names = (*names, "normal_force_N")
    names = (*names, "sphere_radius_m")
    table = {
        name: np.repeat(np.asarray(values), sizes)
        for name, values in zip(names, zip(*labels, strict=True), strict=True)
    }
    for i, name in enumerate(("amplitude_m", "df_Hz", "dgamma_Hz")):
        table[name] = np.concatenate([part[i] for part in parts])
    out = pd.DataFrame(table, columns=list(_COLUMNS))
    if truth:
        names = ("true_model", "true_kappa_N_per_m", "true_mu", "true_omega_xi_N_per_m")
        names = (*names, "true_critical_displacement_m", "true_sliding_force_N", "true_drift")
        for name, values in zip(names, zip(*truths, strict=True), strict=True):
            out[name] = np.repeat(np.asarray(values), sizes)
    if constants:
        out = out.assign(
            fundamental_Hz=q.fundamental,
            overtone=q.overtone,
            area_m2=q.area,
            n_contacts=n_p,
            poisson=nu,
        )
    return out
