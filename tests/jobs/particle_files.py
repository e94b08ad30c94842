"""Helpers of the ``qcm particles`` tests: the tidy table and the four instrument layouts written
from known shifts, and a stand-in of the particle library for the plumbing tests.

The layouts are those of tests/measurements/test_exports.py (QSense layout A: Δf/n, D in ppm,
time in minutes, decimal comma, two sensors; AWSensors: Δf/n and D in ppm; QCM-I: absolute f_n,
plain D and FWHM; openQCM Next multiscan: absolute f_n of n = 1-9, D in ppm), each written here
from a tidy table of shifts (Δf_n not divided by n, ΔΓ_n the half bandwidth) with the conventions
the reader needs to read them back. Absolute frequencies are read against their first point
(``baseline="first"``): the first time step of the tables written here has zero shifts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np

from contactres.errors import ContactresInputError

F_F = 5e6  # fundamental, Hz


def gamma0(n):
    """Γ_n of the bare crystal (Hz), D ~ 1e-5 at the fundamental."""
    return 25.0 + 3.0 * n


def _write(path, header, rows, sep=",", comma=False):
    def cell(v):
        text = v if isinstance(v, str) else repr(float(v))
        return text.replace(".", ",") if comma and not isinstance(v, str) else text

    lines = [sep.join(header)] + [sep.join(cell(v) for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _wide(shifts):
    """times (T,), overtones (N,), Δf and ΔΓ (T, N) of a tidy table."""
    times = np.sort(shifts["time_s"].unique())
    overtones = np.sort(shifts["overtone"].unique())
    df = shifts.pivot(index="time_s", columns="overtone", values="df_Hz").loc[times, overtones]
    dg = shifts.pivot(index="time_s", columns="overtone", values="dgamma_Hz").loc[times, overtones]
    return times, [int(n) for n in overtones], df.to_numpy(), dg.to_numpy()


def tidy(path, shifts):
    """The tidy table itself (reader ``tidy``; needs the fundamental)."""
    shifts.to_csv(path / "shifts.csv", index=False, float_format="%.17g")
    return path / "shifts.csv", dict(fundamental=F_F)


def qsense(path, shifts):
    """QSense layout A: sensor 1 of two, Δf/n, D in ppm, time in min, ';' and decimal comma."""
    t, ns, df, dg = _wide(shifts)
    header = ["Time_1"] + [f"{c}_1:{n}" for n in ns for c in "FD"] + ["Time_2", "F_2:3", "D_2:3"]
    rows = []
    for i, ti in enumerate(t):
        row = [ti / 60]
        for j, n in enumerate(ns):
            row += [df[i, j] / n, 2 * dg[i, j] / (n * F_F) * 1e6]
        rows.append([*row, ti / 60, 1.0, 0.5])
    conventions = dict(
        time_unit="min", df_divided_by_n=True, dissipation_scale=1e-6, fundamental=F_F
    )
    conventions["channel"] = "1"
    return _write(path / "qsense.txt", header, rows, sep=";", comma=True), conventions


def awsensors(path, shifts):
    """AWSensors: Time_(s), Delta_F/n_n=N_(Hz), Delta_D_n=N_(ppm)."""
    t, ns, df, dg = _wide(shifts)
    header = ["Time_(s)"]
    header += [f"Delta_{q}_n={n}_({u})" for n in ns for q, u in (("F/n", "Hz"), ("D", "ppm"))]
    rows = [
        [ti, *(v for j, n in enumerate(ns) for v in (df[i, j] / n, 2 * dg[i, j] / (n * F_F) * 1e6))]
        for i, ti in enumerate(t)
    ]
    return _write(path / "aws.csv", header, rows), dict(fundamental=F_F)


def qcmi(path, shifts):
    """QCM-I: tab-separated, absolute f_n, plain D and FWHM per overtone."""
    t, ns, df, dg = _wide(shifts)
    header = ["Channel A QCM Time [sec]"]
    for n in ns:
        label = "Fundamental" if n == 1 else f"{n}."
        freq = "Fundamental Frequency" if n == 1 else f"{n}. Overtone"
        header += [
            f"Channel A {label} Dissipation  [ ]",
            f"Channel A {freq} [Hz]",
            f"Channel A {label} FWHM [Hz]",
        ]
    rows = []
    for i, ti in enumerate(t):
        row = [ti]
        for j, n in enumerate(ns):
            f, g = n * F_F + df[i, j], gamma0(n) + dg[i, j]
            row += [2 * g / f, f, 2 * g]
        rows.append(row)
    return _write(path / "qcmi.txt", header, rows, sep="\t"), dict(baseline="first")


def openqcm(path, shifts):
    """openQCM Next multiscan: Frequency_i and Dissipation_i (ppm) of n = 2i + 1, i = 0-4."""
    t, ns, df, dg = _wide(shifts)
    if ns != [1, 3, 5, 7, 9]:
        raise ValueError(f"the openQCM Next log holds n = 1-9, not {ns}")
    header = ["Date", "Time", "Relative_time", "Temperature"]
    for i in range(5):
        header += [f"Frequency_{i}", f"Dissipation_{i}"]
    rows = []
    for k, tk in enumerate(t):
        row = ["2026-01-01", f"12:{k // 60:02d}:{k % 60:02d}", tk, 24.8]
        for j, n in enumerate(ns):
            f = n * F_F + df[k, j]
            row += [f, 2 * (gamma0(n) + dg[k, j]) / f * 1e6]
        rows.append(row)
    conventions = dict(baseline="first", dissipation_scale=1e-6)
    return _write(path / "openqcm.csv", header, rows), conventions


#: layout -> (writer, the overtones it holds of n = 1-13: None for all)
LAYOUTS = {
    "tidy": (tidy, None),
    "qsense": (qsense, None),
    "awsensors": (awsensors, None),
    "qcmi": (qcmi, None),
    "openqcm": (openqcm, (1, 3, 5, 7, 9)),
}


# --- a stand-in of the particle library (issue 28's contract), for the plumbing only ---------


@dataclass(frozen=True)
class Particle:
    mass: float
    moment_of_inertia: float
    radius: float

    @classmethod
    def sphere(cls, radius, density):
        if not density > 0:
            raise ContactresInputError(f"density {density!r} must be > 0")
        mass = 4.0 / 3.0 * math.pi * radius**3 * density
        return cls(mass, 0.4 * mass * radius**2, radius)


@dataclass(frozen=True)
class Medium:
    name: str
    density: float
    viscosity: float


MEDIA = {"air": Medium("air", 1.18, 1.85e-5), "water": Medium("water", 997.0, 8.9e-4)}


def medium_named(name):
    try:
        return MEDIA[str(name).strip().lower()]
    except KeyError:
        raise ContactresInputError(f"no medium called {name!r}; known: air, water") from None


def penetration_depth(medium, frequency):
    return np.sqrt(2 * medium.viscosity / (medium.density * 2 * np.pi * np.asarray(frequency)))


def particle_model_validity(particle, frequency, medium=None):
    """R < δ in a medium denser than 100 kg/m³ (a liquid), else None."""
    if medium is None or medium.density < 100:
        return None
    depth = float(penetration_depth(medium, frequency))
    return f"R < δ = {depth:.3g} m" if particle.radius < depth else None


def particle_shifts(fundamental, overtones, particle, kappa, xi, coverage, *, rocking="free",
                    medium=None, zq=8.8e6):  # fmt: skip
    """A particle translating on its contact (rotation locked, no medium): the load
    K_L = −mω²K/(K − mω²), K = κ + iωξ, in Δf + iΔΓ = (N/A) K_L/(2nπ² Z_q)."""
    n = np.asarray(overtones, float)
    omega = 2 * np.pi * fundamental * n
    k = np.asarray(kappa, float) + 1j * omega * np.asarray(xi, float)
    inertia = -particle.mass * omega**2
    load = k * inertia / (k + inertia)
    z = np.asarray(coverage, float) * load / (2 * n * np.pi**2 * zq)
    return z.real, z.imag


def fake_fit(truth, flagged):
    """A stand-in of fit_particles returning ``truth`` (the study's κ, ξ, coverage per step)
    with 1 % errors and the stand-in's shifts at the truth as the model; the steps of
    ``flagged`` (bool mask) are reported as identifying the mass only: κ, ξ and f_coupled NaN
    and a flag."""

    def fit(fundamental, overtones, df, dgamma, particle, *, rocking, medium, sigma_df,
            sigma_dgamma, zq):  # fmt: skip
        assert df.shape == dgamma.shape == (len(truth), len(overtones))
        model = particle_shifts(
            fundamental,
            np.asarray(overtones)[None, :],
            particle,
            *(truth[c].to_numpy(float)[:, None] for c in ("kappa_N_per_m", "xi_kg_per_s",
                                                           "coverage_per_m2")),
        )  # fmt: skip
        kappa = truth["kappa_N_per_m"].to_numpy(float).copy()
        xi = truth["xi_kg_per_s"].to_numpy(float).copy()
        coverage = truth["coverage_per_m2"].to_numpy(float).copy()
        f_c = np.sqrt(kappa / particle.mass) / (2 * np.pi)
        kappa[flagged], xi[flagged], f_c[flagged] = np.nan, np.nan, np.nan
        flags = ["sauerbrey-like" if f else "" for f in flagged]
        return SimpleNamespace(
            kappa=kappa,
            kappa_err=0.01 * np.nan_to_num(kappa, nan=1.0),
            xi=xi,
            xi_err=0.01 * np.nan_to_num(xi, nan=1.0),
            coverage=coverage,
            coverage_err=0.01 * coverage,
            f_coupled=f_c,
            f_coupled_err=0.01 * f_c,
            df_model=model[0],
            dgamma_model=model[1],
            flags=flags,
        )

    return fit


def install_standin(monkeypatch, fit):
    """Put the stand-in's names where the job imports them from. The library's fit is loaded
    first: its module binds the resonators' names when imported, and must bind the real ones
    (a stand-in bound there would outlive this test)."""
    import contactres.analysis
    import contactres.resonators

    assert contactres.analysis.PARTICLE_FLAGS  # loads contactres.analysis._particles

    for name, value in (
        ("Particle", Particle),
        ("medium_named", medium_named),
        ("penetration_depth", penetration_depth),
        ("particle_model_validity", particle_model_validity),
        ("particle_shifts", particle_shifts),
    ):
        monkeypatch.setattr(contactres.resonators, name, value, raising=False)
    monkeypatch.setattr(contactres.analysis, "fit_particles", fit, raising=False)
