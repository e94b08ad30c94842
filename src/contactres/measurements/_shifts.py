"""From fitted admittance spectra to the sweep table: shifts and oscillation amplitudes.

Each spectrum of an amplitude sweep (:class:`~contactres.measurements._spectra_table.SpectraTable`)
has been fitted for its resonance frequency f_r and half-bandwidth Γ
(:func:`contactres.measurements.fit_resonances`). Against the no-contact reference
spectra of the same overtone (and of the same configuration, medium and experiment where the
reference names them) the shifts are

    Δf = f_r − f_ref,   ΔΓ = Γ − Γ_ref   (Hz; Δf not divided by n, Γ the half-bandwidth),

with f_ref, Γ_ref the mean of the matching references and standard errors
σ_Δ² = σ² + σ_ref² (σ_ref: the larger of the fit errors' combination √(Σσ_i²)/N and, for
N >= 2 references, their scatter sd/√N).

Oscillation amplitude. A thickness-shear plate of thickness d driven by a voltage U (amplitude)
across its electrodes is loaded by the piezoelectric stress e26 U/d at both faces; projected on
the mode cos(nπz/d) of the odd overtone n this is a modal force 2 e26 U/d (per area) against the
modal stiffness c66 (nπ/d)² d/2, and at resonance the response is Q times the static one. The
surface amplitude is therefore

    u0 = 4 d26 Q U/(nπ)²,   d26 = e26/c66,   Q = f_r/(2Γ)

(e.g. D. Johannsmann, *The Quartz Crystal Microbalance in Soft Matter Research*, Springer 2015;
checked in the tests against the exact solution of the damped piezoelectric plate). Q is that of
the spectrum itself (the contact's damping lowers it). d26 = 3.1 pm/V, the AT-cut value of the
QCM literature (D. Johannsmann et al., "Quartz crystal microbalance with dissipation
monitoring…", Sensors 21, 3490 (2021), with e26 = 9.65e-2 C/m²); e26/c66 with c66 = 28.98 GPa of
:func:`contactres.materials.at_cut_quartz` gives 3.33 pm/V, 7 % more — the amplitude is no
better known than that: pass ``d26`` or a calibration factor u0/U in m/V measured on your
instrument for better.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pandas as pd

from ..errors import ContactresInputError
from ._spectra_table import CONSTANT_COLUMNS, SpectraTable

__all__ = [
    "D26_AT",
    "E26_AT",
    "FUNDAMENTAL_TOLERANCE",
    "MAX_SHIFT_HALF_WIDTHS",
    "QCM_FUNDAMENTAL_HZ",
    "shear_amplitude",
    "sweeps_from_spectra",
]

#: Piezoelectric stress constant e26 of AT-cut quartz, C/m² (the QCM literature's value).
E26_AT = 9.65e-2
#: Piezoelectric strain constant d26 of AT-cut quartz, m/V (Johannsmann et al. 2021).
D26_AT = 3.1e-12
#: Labels that select the references of a spectrum (besides the overtone) when a reference
#: names them.
_MATCH = ("configuration", "medium", "experiment")
#: Fundamentals f_F of QCM crystals, Hz: 1 MHz (the lowest made) to 500 MHz (inverted-mesa
#: high-frequency crystals reach ~150 MHz). A spectrum whose frequencies over its overtone lie
#: outside is in another unit (a frequency column in MHz, a Touchstone option line's unit).
QCM_FUNDAMENTAL_HZ = (1e6, 5e8)
#: Relative tolerance of the spectra's f/n against a fundamental_Hz column.
FUNDAMENTAL_TOLERANCE = 0.05
#: Half-widths Γ_ref of the reference a measured resonance may lie from it: a contact moves the
#: resonance by a fraction of Γ (paper 2: Δf/Γ_ref below 0.3 in the example), and a spectrum
#: scanned a few Γ around it cannot hold one further away; 10 leaves room for stiff contacts.
MAX_SHIFT_HALF_WIDTHS = 10.0


def shear_amplitude(drive_voltage, overtone, quality, d26: float = D26_AT):
    """Surface amplitude u0 = 4 d26 Q U/(nπ)² of a thickness-shear resonator at resonance, m.

    Parameters
    ----------
    drive_voltage : float or array
        Amplitude (peak) U of the voltage across the crystal, V.
    overtone : int or array
        Odd overtone order n.
    quality : float or array
        Quality factor Q = f_r/(2Γ) of the resonance (Γ: half-bandwidth).
    d26 : float
        Piezoelectric strain constant, m/V (default :data:`D26_AT`).

    Returns
    -------
    float or ndarray
        u0 in m (module docstring for the derivation and sources).
    """
    n = np.asarray(overtone, dtype=float)
    return 4 * d26 * np.asarray(quality) * np.asarray(drive_voltage) / (n * math.pi) ** 2


def _references(spectra: pd.DataFrame, measured: pd.Series) -> np.ndarray:
    """Mask of the usable references of one measured spectrum (module docstring)."""
    ref = spectra["reference"].to_numpy(bool) & np.isfinite(spectra["f_r_Hz"].to_numpy(float))
    ref &= spectra["overtone"].to_numpy(float) == float(measured["overtone"])
    for col in _MATCH:
        mine = spectra[col].astype(str).to_numpy()
        # Only an empty label is a wildcard: a reference that names a label (also "1" or a
        # default) serves only the spectra with that label.
        ref &= (mine == "") | (mine == str(measured[col]))
    return ref


def _reference_value(values: np.ndarray, errors: np.ndarray) -> tuple[float, float]:
    n = values.size
    err = math.sqrt(float(np.sum(errors**2))) / n
    if n >= 2:
        err = max(err, float(np.std(values, ddof=1)) / math.sqrt(n))
    return float(np.mean(values)), err


def _where(table: SpectraTable, row) -> str:
    """The file (a folder's spectrum file) or the table's line of one spectrum."""
    file = str(row.get("file", "") or "")
    if file and file != "nan":
        return f"{table.source}/{file}: spectrum {row['spectrum']}"
    return f"{table.source}, line {row['line']}: spectrum {row['spectrum']}"


def _scanned(table: SpectraTable) -> pd.DataFrame:
    """Lowest and highest frequency of every spectrum, Hz (columns f_lo, f_hi)."""
    f = table.points.groupby("spectrum", sort=False)["frequency_Hz"]
    return pd.DataFrame({"f_lo": f.min(), "f_hi": f.max()})


def _check_overtones(table: SpectraTable, spectra: pd.DataFrame) -> None:
    """Every spectrum's frequencies where its overtone n of a QCM lies: f/n a QCM fundamental
    (:data:`QCM_FUNDAMENTAL_HZ`), and within :data:`FUNDAMENTAL_TOLERANCE` of the
    ``fundamental_Hz`` it carries. One line naming the file, the overtone, the expected and the
    found range (issue 27: a frequency column in MHz gave Δf = ΔΓ = 0, a Touchstone unit that
    did not match the data shifts of 1e7 Hz and more)."""
    lo, hi = QCM_FUNDAMENTAL_HZ
    for row in spectra.to_dict("records"):
        n = float(row["overtone"])
        if not np.isfinite(n):
            continue
        f_lo, f_hi = row["f_lo"], row["f_hi"]
        expected, why = (n * lo, n * hi), f"a QCM's overtone {n:g} (fundamental 1-500 MHz)"
        f_f = float(row.get("fundamental_Hz", np.nan))
        if np.isfinite(f_f):
            tol = FUNDAMENTAL_TOLERANCE
            expected = (n * f_f * (1 - tol), n * f_f * (1 + tol))
            why = f"overtone {n:g} of the fundamental {f_f:.6g} Hz (± {tol:.0%})"
        if not (expected[0] <= 0.5 * (f_lo + f_hi) <= expected[1]):
            raise ContactresInputError(
                f"{_where(table, row)} runs from {f_lo:.6g} to {f_hi:.6g} Hz, where {why} "
                f"lies at {expected[0]:.6g} to {expected[1]:.6g} Hz: check the frequency "
                "unit (a column in MHz, a Touchstone option line) and the overtone"
            )


def _check_near_references(table, measured: pd.DataFrame, f_ref, g_ref) -> None:
    """Every measured resonance within :data:`MAX_SHIFT_HALF_WIDTHS` half-widths of its
    references' (one line naming the file, the overtone, the expected and found range)."""
    far = np.abs(measured["f_r_Hz"].to_numpy(float) - f_ref) > MAX_SHIFT_HALF_WIDTHS * g_ref
    if far.any():
        i = int(np.flatnonzero(far)[0])
        row = measured.iloc[i]
        k = MAX_SHIFT_HALF_WIDTHS
        raise ContactresInputError(
            f"{_where(table, row)} (overtone {row['overtone']:g}) resonates at "
            f"{row['f_r_Hz']:.9g} Hz (scanned {row['f_lo']:.9g} to {row['f_hi']:.9g} Hz), where "
            f"its references put the overtone at {f_ref[i] - k * g_ref[i]:.9g} to "
            f"{f_ref[i] + k * g_ref[i]:.9g} Hz (f_ref ± {k:g} Γ_ref): another unit, overtone, "
            "crystal or medium than its references (label the references' medium)"
        )


def sweeps_from_spectra(
    table: SpectraTable,
    fits: pd.DataFrame,
    *,
    reference=None,
    d26: float = D26_AT,
    calibration_m_per_V: float | None = None,
) -> tuple[pd.DataFrame, list[str]]:
    """The sweep table (Δf, ΔΓ, u0 per spectrum) of fitted spectra, and what was left out.

    Parameters
    ----------
    table : SpectraTable
        The spectra and their labels.
    fits : DataFrame
        :func:`~contactres.measurements.fit_resonances` of ``table.points`` (columns
        spectrum, f_r_Hz, f_r_err_Hz, gamma_Hz, gamma_err_Hz, flags).
    reference : iterable of str, optional
        Ids of the reference spectra; default: the ``reference`` column of the table.
    d26 : float
        Piezoelectric strain constant, m/V, for the amplitude (default :data:`D26_AT`).
    calibration_m_per_V : float, optional
        u0/U measured on the instrument, m/V: then u0 = this × U instead of the Q formula.

    Returns
    -------
    (DataFrame, list of str)
        One row per measured (non-reference) spectrum with a valid fit, in the columns of the
        sweep table (``sweep``, ``amplitude_m``, ``df_Hz``, ``dgamma_Hz``, ``df_err_Hz``,
        ``dgamma_err_Hz``, ``normal_force_N``, ``experiment``, ``configuration``, ``medium``,
        ``ramp``, ``overtone``, ``time_s``) plus ``spectrum``, ``f_r_Hz``, ``gamma_Hz``,
        ``quality``, ``drive_voltage_V``; and one line per spectrum left out (its fit flags).

    Raises
    ------
    ValueError
        No reference, a measured spectrum without a matching reference, without drive voltage
        (and no calibration), overtone, sweep or normal force; unknown reference ids.
    """
    if calibration_m_per_V is not None and not (
        math.isfinite(calibration_m_per_V) and calibration_m_per_V > 0
    ):
        raise ContactresInputError(
            f"the calibration u0/U must be > 0 m/V, got {calibration_m_per_V!r}"
        )
    if not (math.isfinite(d26) and d26 > 0):
        raise ContactresInputError(f"d26 must be > 0 m/V, got {d26!r}")
    spectra = table.spectra.merge(
        fits.drop(columns=["n_points"], errors="ignore"), on="spectrum", how="left"
    )
    spectra = spectra.join(_scanned(table), on="spectrum")
    _check_overtones(table, spectra)
    if reference is not None:
        ids = [str(x).strip() for x in reference]
        unknown = sorted(set(ids) - set(spectra["spectrum"]))
        if unknown:
            raise ContactresInputError(
                f"{table.source}: no spectrum with id(s) {unknown} (--reference)"
            )
        spectra["reference"] = spectra["spectrum"].isin(ids)
    refs = spectra["reference"].to_numpy(bool)
    if not refs.any():
        raise ContactresInputError(
            f"{table.source}: no reference spectrum (no contact): mark them in the column "
            "'reference' or name them (--reference ID,...)"
        )
    # A flagged fit is no result, also where it has values (e.g. too few points at the peak).
    flags = spectra["flags"].fillna("").astype(str).str.strip()
    ok = (
        np.isfinite(spectra["f_r_Hz"].to_numpy(float))
        & np.isfinite(spectra["gamma_Hz"].to_numpy(float))
        & (flags == "").to_numpy()
    )
    left_out = [
        f"spectrum {row.spectrum} (line {row.line}): not used, fit flags {row.flags or 'none'}"
        for row in spectra[~ok].itertuples()
    ]
    measured = spectra[~refs & ok]
    if not (~refs).any():
        raise ContactresInputError(
            f"{table.source}: every spectrum is a reference (no contact); the shifts need "
            "measured spectra too (reference = no, or not in --reference)"
        )
    if measured.empty:
        more = " ..." if len(left_out) > 3 else ""
        raise ContactresInputError(
            f"{table.source}: no measured spectrum has a usable resonance fit "
            f"({len(left_out)} left out: {'; '.join(left_out[:3])}{more})"
        )
    for col, what in (("overtone", "overtone"), ("normal_force_N", "normal force")):
        bad = ~np.isfinite(measured[col].to_numpy(float))
        if bad.any():
            row = measured[bad].iloc[0]
            raise ContactresInputError(
                f"{table.source}, line {row['line']}: spectrum {row['spectrum']} has no {what} "
                f"(column {col!r}); every measured spectrum needs one"
            )
    zero = measured["normal_force_N"].to_numpy(float) == 0
    if zero.any():  # 0 N (no contact) is the label of a reference only
        row = measured[zero].iloc[0]
        raise ContactresInputError(
            f"{table.source}, line {row['line']}: spectrum {row['spectrum']} is no reference "
            "and has normal force 0 N (column 'normal_force_N'); 0 N is no contact: mark it a "
            "reference, or give the force of its contact"
        )
    no_sweep = (
        np.ones(len(measured), bool)
        if "sweep" not in measured.columns
        else (measured["sweep"].astype(str).str.strip() == "").to_numpy()
    )
    if no_sweep.any():
        row = measured[no_sweep].iloc[0]
        raise ContactresInputError(
            f"{table.source}, line {row['line']}: spectrum {row['spectrum']} is not a reference "
            "and has no sweep id (column 'sweep')"
        )
    if calibration_m_per_V is None:
        bad = ~np.isfinite(measured["drive_voltage_V"].to_numpy(float))
        if bad.any():
            row = measured[bad].iloc[0]
            raise ContactresInputError(
                f"{table.source}, line {row['line']}: spectrum {row['spectrum']} has no drive "
                "voltage (column 'drive_voltage_V'); give it, or a calibration u0/U"
            )
    # One pass per distinct reference set (a handful), not per point.
    keys = measured[["overtone", *_MATCH]].astype(str).agg("|".join, axis=1)
    f_ref = np.empty(len(measured))
    g_ref = np.empty(len(measured))
    f_ref_err = np.empty(len(measured))
    g_ref_err = np.empty(len(measured))
    for key in keys.unique():
        mine = (keys == key).to_numpy()
        first = measured[mine].iloc[0]
        use = _references(spectra, first)
        if not use.any():
            raise ContactresInputError(
                f"{table.source}, line {first['line']}: spectrum {first['spectrum']} (overtone "
                f"{first['overtone']:g}, {', '.join(f'{c} {first[c]}' for c in _MATCH)}) has no "
                "usable reference spectrum of the same overtone"
            )
        r = spectra[use]
        f_ref[mine], f_ref_err[mine] = _reference_value(
            r["f_r_Hz"].to_numpy(float), r["f_r_err_Hz"].to_numpy(float)
        )
        g_ref[mine], g_ref_err[mine] = _reference_value(
            r["gamma_Hz"].to_numpy(float), r["gamma_err_Hz"].to_numpy(float)
        )
    _check_near_references(table, measured, f_ref, g_ref)
    f_r = measured["f_r_Hz"].to_numpy(float)
    gamma = measured["gamma_Hz"].to_numpy(float)
    quality = f_r / (2 * gamma)
    u = measured["drive_voltage_V"].to_numpy(float)
    n = measured["overtone"].to_numpy(float)
    if calibration_m_per_V is None:
        amplitude = shear_amplitude(u, n, quality, d26)
    else:
        amplitude = calibration_m_per_V * u
    out = pd.DataFrame(
        {
            "sweep": measured["sweep"].astype(str).to_numpy(),
            "amplitude_m": amplitude,
            "df_Hz": f_r - f_ref,
            "dgamma_Hz": gamma - g_ref,
            "df_err_Hz": np.hypot(measured["f_r_err_Hz"].to_numpy(float), f_ref_err),
            "dgamma_err_Hz": np.hypot(measured["gamma_err_Hz"].to_numpy(float), g_ref_err),
            "normal_force_N": measured["normal_force_N"].to_numpy(float),
            "experiment": measured["experiment"].astype(str).to_numpy(),
            "configuration": measured["configuration"].astype(str).to_numpy(),
            "medium": measured["medium"].astype(str).to_numpy(),
            "ramp": measured["ramp"].to_numpy(float),
            "overtone": n,
            "time_s": measured["time_s"].to_numpy(float),
            "spectrum": measured["spectrum"].to_numpy(),
            "f_r_Hz": f_r,
            "gamma_Hz": gamma,
            "quality": quality,
            "drive_voltage_V": u,
        }
    )
    for col in CONSTANT_COLUMNS:  # constants the spectra carried, passed on
        if col in measured.columns and np.isfinite(measured[col].to_numpy(float)).any():
            out[col] = measured[col].to_numpy(float)
    # Columns that no spectrum gave are left out (the sweep table treats them as absent).
    for col in ("ramp", "time_s"):
        if not np.isfinite(out[col]).any():
            out = out.drop(columns=col)
    if "ramp" in out.columns:
        out["ramp"] = out["ramp"].astype("Int64")
    out["overtone"] = out["overtone"].astype(int)
    out.attrs["conventions"] = {
        "df": "Δf = f_r − f_ref in Hz (not divided by n)",
        "dgamma": "ΔΓ: shift of the half-bandwidth at half height of G, Hz (not D)",
        "amplitude": (
            f"u0 = {calibration_m_per_V:g} m/V × U"
            if calibration_m_per_V is not None
            else f"u0 = 4 d26 Q U/(nπ)², d26 = {d26:.4g} m/V, Q = f_r/(2Γ)"
        ),
        "reference": "mean of the reference spectra of the same overtone (and labels)",
    }
    return out, left_out


def is_spectra_input(path) -> bool:
    """True if ``path`` is a folder (of spectrum files) or a table (a text file, or a sheet of
    an ``.xlsx`` workbook) whose header has the spectra columns ``frequency_Hz`` and ``G_S``
    (rather than a sweep table)."""
    from pathlib import Path

    p = Path(path)
    if p.is_dir():
        return True
    if p.suffix.lower() == ".xlsx" and p.is_file():
        # A workbook: the header of the sheet the spectra reader would read.
        from .readers import BUILT_IN

        try:
            names = set(BUILT_IN.pick(p, "spectra").load(p).columns)
        except ContactresInputError:
            return False  # the sweep reader then names what is wrong with the file
        return {"frequency_Hz", "G_S"} <= names
    try:
        with p.open(encoding="utf-8-sig", errors="replace") as fh:
            for text in fh:
                if text.strip() and not text.lstrip().startswith("#"):
                    names = {x.strip().strip('"') for x in text.replace(";", ",").split(",")}
                    names |= {x.strip() for x in text.split("\t")}
                    return {"frequency_Hz", "G_S"} <= names
    except OSError:
        return False
    return False


def read_spectra_sweeps(
    path,
    *,
    reference=None,
    layout: str | None = None,
    reference_impedance: float = 50.0,
    voltage: str = "amplitude",
    d26: float = D26_AT,
    calibration_m_per_V: float | None = None,
    validate: bool = True,
    progress=None,
    two_port: str | None = None,
    **constants,
):
    """Spectra -> resonance fits -> the validated sweep table, in one call.

    Parameters
    ----------
    path : str or path-like
        Tidy spectra table or folder (:func:`~contactres.measurements._spectra_table.read_spectra`).
    reference, d26, calibration_m_per_V
        As in :func:`sweeps_from_spectra`.
    layout, reference_impedance, voltage, two_port
        As in :func:`~contactres.measurements._spectra_table.read_spectra`.
    validate : bool
        Validate the sweep table (needs its constants: from columns of the spectra table or
        ``constants``); False returns None in its place (``qcm spectra`` writes the rows, and
        the constants may come later, with the analysis).
    progress : callable, optional
        Called with a short text at each stage (the fits, the shifts): the CLI's progress lines.
    **constants
        The sweep table's constants (``area_m2``, ``fundamental_Hz``, ...), as in
        :func:`~contactres.measurements.read_sweeps`.

    Returns
    -------
    (SweepTable, DataFrame, DataFrame, list of str)
        The validated sweep table, the sweep rows with their errors and spectrum columns
        (:func:`sweeps_from_spectra`), the resonance fits (one row per spectrum) and one line
        per spectrum left out.
    """
    from ._checksum import file_sha256
    from ._spectra import fit_resonances
    from ._spectra_table import read_spectra
    from ._sweeps import validate_sweeps

    digest = file_sha256(path)  # of the file as read (None for a folder of spectra)
    table = read_spectra(
        path,
        layout=layout,
        reference_impedance=reference_impedance,
        voltage=voltage,
        two_port=two_port,
    )
    p = table.points
    if progress is not None:
        progress(f"fitting the resonances of {p['spectrum'].nunique()} spectra")
    fits = fit_resonances(
        p["spectrum"].to_numpy(),
        p["frequency_Hz"].to_numpy(),
        p["G_S"].to_numpy(),
        None if p["B_S"].isna().all() else p["B_S"].to_numpy(),
    )
    if progress is not None:
        progress("shifts against the references and amplitudes")
    rows, left_out = sweeps_from_spectra(
        table, fits, reference=reference, d26=d26, calibration_m_per_V=calibration_m_per_V
    )
    if rows.empty:
        raise ContactresInputError(
            f"{table.source}: no measured spectrum has a usable resonance fit"
        )
    if not validate:
        return None, rows, fits, left_out
    given = {k: v for k, v in constants.items() if v is not None}
    raw = rows.drop(columns=["spectrum", "f_r_Hz", "gamma_Hz", "quality", "drive_voltage_V"])
    line = table.spectra.set_index("spectrum")["line"]
    raw["line"] = line.reindex(rows["spectrum"]).to_numpy()
    sweeps = validate_sweeps(raw, source=table.source, constants=given)
    sweeps = replace(sweeps, source_sha256=digest)
    return sweeps, rows, fits, left_out
