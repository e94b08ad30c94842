"""Tables of measured resonances -> contact stiffness (and modulus), one row per point or pixel.

The orchestration behind ``contactres rum invert`` and ``contactres afm invert``: the checked
tables of :mod:`contactres.measurements.resonances` go through the oscillator models of
:mod:`contactres.resonators` and the modulus step of :mod:`contactres.analysis.inversion`;
the output keeps every input column and appends the results. Rows that the physics rejects
(a contact resonance below the free one) are errors naming the line; rows that only cannot be
inverted (no crossing of two modes, a mode without sensitivity) keep empty results and say why
in ``flags``.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..measurements.messages import at_cell, where_rows
from ..resonators.cantilever import Cantilever
from ..resonators.cantilever_inversion import flag_names, invert_contact_resonance
from ..resonators.rum import RUMOscillator
from .inversion import ModulusFlag, modulus_from_contact_stiffness

__all__ = ["AFM_GROUP_COLUMNS", "M_RANGE_PA", "invert_afm_table", "invert_rum_table"]

#: Columns that define one lever and one tip geometry: rows sharing them are inverted at once.
AFM_GROUP_COLUMNS = (
    "f1_free_Hz",
    "f2_free_Hz",
    "f3_free_Hz",
    "Q1_free",
    "Q2_free",
    "Q3_free",
    "k_c_N_per_m",
    "lateral_ratio",
    "tip_height_over_L",
    "tilt_deg",
)
_MODES = (1, 2, 3)
#: Plausible indentation moduli of a sample, Pa: soft gels (~1e5) to beyond diamond (1.2e12).
M_RANGE_PA = (1e5, 1.5e12)


def _calibrations(table: pd.DataFrame, source: str) -> tuple[str, np.ndarray]:
    """The RUM model of every row (lumped from K_eff_N_per_m, rod from mass_kg), one per file."""
    lumped = table["K_eff_N_per_m"].notna().to_numpy()
    rod = table["mass_kg"].notna().to_numpy()
    both = lumped & rod
    if both.any():
        raise ValueError(
            f"{at_cell(table, source, both, 'mass_kg')}: give K_eff_N_per_m (lumped model) or "
            "mass_kg (rod model) in a row, not both"
        )
    neither = ~(lumped | rod)
    if neither.any():
        raise ValueError(
            f"{at_cell(table, source, neither, 'K_eff_N_per_m')}: each row needs "
            "K_eff_N_per_m (lumped model) or mass_kg (rod model)"
        )
    return "lumped" if lumped.all() else ("rod" if rod.all() else "mixed"), lumped


def invert_rum_table(table: pd.DataFrame, source: str = "table") -> pd.DataFrame:
    """k* of every row of a checked RUM table (:data:`~contactres.measurements.resonances
    .RUM_TABLE`): ``k_star_N_per_m`` and ``rum_model`` appended.

    Lumped rows: (f/f0)² = 1 + k*/K_eff; rod rows (mass m): k* = (EA/L)(kL) tan(kL) of a rod
    free at one end with the contact spring at the other, EA/L = 4 m f0² (mode 1; see
    :class:`~contactres.resonators.rum.RUMOscillator`). Raises ValueError naming the line for a
    contact resonance below f0 (a spring cannot lower it) or at/above the rod's clamped limit.
    The rows are grouped by their calibration (one oscillator per group; a file rarely holds
    more than a few), each group converted at once.
    """
    _, lumped = _calibrations(table, source)
    f0 = table["f0_Hz"].to_numpy(float)
    fc = table["fc_Hz"].to_numpy(float)
    below = fc < f0
    if below.any():
        raise ValueError(
            f"{at_cell(table, source, below, 'fc_Hz')}: the contact resonance is below the free "
            "resonance f0_Hz of its row; a contact spring can only raise it (check the columns)"
        )
    calib = np.where(lumped, table["K_eff_N_per_m"], table["mass_kg"]).astype(float)
    codes = pd.factorize(pd.MultiIndex.from_arrays([lumped, f0, calib]))[0]
    k_star = np.full(len(table), np.nan)
    for code in range(codes.max() + 1):  # one oscillator per calibration, not per row
        rows = np.flatnonzero(codes == code)
        i = rows[0]
        if lumped[i]:
            osc = RUMOscillator.lumped(f0[i], calib[i])
        else:
            osc = RUMOscillator.rod(f0[i], calib[i])
            over = fc[rows] >= osc.clamped_frequency
            if over.any():
                mask = np.zeros(len(table), bool)
                mask[rows[over]] = True
                raise ValueError(
                    f"{at_cell(table, source, mask, 'fc_Hz')}: at or above the clamped limit "
                    f"1.5 f0 = {osc.clamped_frequency:.6g} Hz of the rod model, which no finite "
                    "contact stiffness reaches (check f0_Hz and fc_Hz)"
                )
        k_star[rows] = osc.contact_stiffness(fc[rows])
    out = table[table.attrs.get("given", [c for c in table.columns if c != "line"])].copy()
    out["rum_model"] = np.where(lumped, "lumped", "rod")
    out["k_star_N_per_m"] = k_star
    return out


def _given(values: np.ndarray) -> tuple[float, ...] | None:
    """The leading given (non-NaN) values of one row of a lever's constants, or None."""
    out = []
    for v in values:
        if np.isnan(v):
            break
        out.append(float(v))
    return tuple(out) or None


def _modulus(part: pd.DataFrame, k_star: np.ndarray, ref: np.ndarray, ref2: np.ndarray) -> dict:
    """E* and M_sample of the rows ``part``: by Hertz where tip_radius_m and load_N are given,
    by the reference sample(s) where fc1_ref_Hz and M_ref_Pa are; NaN elsewhere."""
    n = len(part)
    out = {k: np.full(n, np.nan) for k in ("E_star_Pa", "M_sample_Pa", "contact_radius_m")}
    out["modulus_method"] = np.full(n, "", dtype=object)
    out["modulus_flags"] = np.full(n, "", dtype=object)
    col = {c: part[c].to_numpy(float) for c in part.columns if c.endswith(("_m", "_N", "_Pa"))}
    tip = col["M_tip_Pa"]  # blank: a rigid tip
    hertz = ~np.isnan(col["tip_radius_m"]) & ~np.isnan(col["load_N"])
    refd = ~hertz & ~np.isnan(ref) & ~np.isnan(col["M_ref_Pa"])
    two = refd & ~np.isnan(ref2) & ~np.isnan(col["M_ref2_Pa"])
    for rows, kwargs in (
        (hertz, dict(tip_radius=col["tip_radius_m"], load=col["load_N"])),
        (refd & ~two, dict(reference_k_star=ref, reference_modulus=col["M_ref_Pa"])),
        (
            two,
            dict(
                reference_k_star=ref,
                reference_modulus=col["M_ref_Pa"],
                reference2_k_star=ref2,
                reference2_modulus=col["M_ref2_Pa"],
            ),
        ),
    ):
        for rigid in (True, False):
            ok = rows & np.isfinite(k_star) & (k_star > 0) & (np.isnan(tip) == rigid)
            if ok.any():
                _modulus_rows(out, ok, k_star, tip, col["hardness_Pa"], kwargs, rigid)
    return out


def _modulus_rows(out, ok, k_star, tip, hardness, kwargs, rigid: bool) -> None:
    """The modulus step for the rows ``ok`` (one method; a rigid tip or M_tip given)."""
    args = {k: v[ok] for k, v in kwargs.items()}
    res = modulus_from_contact_stiffness(
        k_star[ok],
        tip_modulus=None if rigid else tip[ok],
        hardness=None if np.isnan(hardness[ok]).all() else hardness[ok],
        **args,
    )
    out["E_star_Pa"][ok] = res.E_star
    out["M_sample_Pa"][ok] = res.M_sample
    out["contact_radius_m"][ok] = res.contact_radius
    out["modulus_method"][ok] = res.method
    out["modulus_flags"][ok] = [
        ";".join(f.name.lower().replace("_", "-") for f in ModulusFlag if int(v) & f)
        for v in np.atleast_1d(res.flags)
    ]


def invert_afm_table(
    table: pd.DataFrame, source: str = "table", normalisation: str = "global"
) -> pd.DataFrame:
    """κ, k*, r, σ and (where the inputs allow) E* and M_sample of every row of a checked CR-AFM
    table (:data:`~contactres.measurements.resonances.AFM_TABLE`).

    Rows are grouped by their lever and tip geometry (:data:`AFM_GROUP_COLUMNS`) and by whether
    the tip position is given; each group is inverted at once by
    :func:`~contactres.resonators.cantilever_inversion.invert_contact_resonance` (the modes
    used are the contact-resonance columns given in the row; r blank: solved from two modes).
    The modulus step (:func:`~contactres.analysis.inversion.modulus_from_contact_stiffness`)
    runs where tip_radius_m and load_N (Hertz) or fc1_ref_Hz and M_ref_Pa (reference samples,
    inverted with the same lever and tip position) are given. ``flags`` names why a value is
    missing; ``normalisation`` is recorded in every row.
    """
    fc = table[[f"fc{n}_Hz" for n in _MODES]].to_numpy(float)
    none = np.isnan(fc).all(axis=1)
    if none.any():
        raise ValueError(
            f"{where_rows(table, source, none, 'fc1_Hz')}: no contact resonance in this row "
            "(fc1_Hz, fc2_Hz and fc3_Hz are all empty)"
        )
    for n in _MODES:  # a contact spring only raises a mode: below the free lever is impossible
        below = fc[:, n - 1] < table[f"f{n}_free_Hz"].to_numpy(float)
        if below.any():
            raise ValueError(
                f"{at_cell(table, source, below, f'fc{n}_Hz')}: below the free resonance "
                f"f{n}_free_Hz of its row; a contact can only raise it (check the columns)"
            )
    q = table[[f"Q{n}" for n in _MODES]].to_numpy(float)
    r_given = table["tip_position"].notna().to_numpy()
    key = table[list(AFM_GROUP_COLUMNS)].fillna(-1.0).assign(r_given=r_given)
    codes = pd.factorize(pd.MultiIndex.from_frame(key))[0]
    n = len(table)
    res = {
        c: np.full(n, np.nan)
        for c in ("kappa", "k_star_N_per_m", "tip_position_used", "sigma_N_s_per_m")
    }
    res["flags"] = np.full(n, "", dtype=object)
    ref, ref2 = np.full(n, np.nan), np.full(n, np.nan)
    for code in range(codes.max() + 1):  # one lever and tip geometry per group, not per row
        rows = np.flatnonzero(codes == code)
        first = table.iloc[rows[0]]
        lever = Cantilever(
            _given(first[["f1_free_Hz", "f2_free_Hz", "f3_free_Hz"]].to_numpy(float)),
            first["k_c_N_per_m"] if np.isfinite(first["k_c_N_per_m"]) else 1.0,
            normalisation=normalisation,
            free_q_factors=_given(first[["Q1_free", "Q2_free", "Q3_free"]].to_numpy(float)),
        )
        geometry = dict(
            lateral_ratio=np.nan_to_num(first["lateral_ratio"]),
            tip_height=np.nan_to_num(first["tip_height_over_L"]),
            tilt=np.nan_to_num(first["tilt_deg"]),
        )
        r = table["tip_position"].to_numpy(float)[rows] if r_given[rows[0]] else None
        qs = q[rows] if np.isfinite(q[rows]).any() else None
        out = invert_contact_resonance(lever, fc[rows], tip_position=r, q_factors=qs, **geometry)
        res["kappa"][rows] = out.kappa
        res["k_star_N_per_m"][rows] = out.k_star if np.isfinite(first["k_c_N_per_m"]) else np.nan
        res["tip_position_used"][rows] = out.tip_position
        res["sigma_N_s_per_m"][rows] = out.sigma
        res["flags"][rows] = [";".join(flag_names(f)) for f in np.atleast_1d(out.flags)]
        for col, target in (("fc1_ref_Hz", ref), ("fc1_ref2_Hz", ref2)):
            f_ref = table[col].to_numpy(float)[rows]
            if np.isfinite(f_ref).any():
                freqs = np.full((len(rows), 3), np.nan)
                freqs[:, 0] = f_ref
                back = invert_contact_resonance(
                    lever, freqs, tip_position=out.tip_position, **geometry
                )
                target[rows] = back.k_star
    no_kc = table["k_c_N_per_m"].isna().to_numpy()
    # Without k_c, k* is unknown but the reference method needs only ratios of k*.
    k_star = np.where(no_kc, res["kappa"], res["k_star_N_per_m"])
    mod = _modulus(table, k_star, ref, ref2)
    out = table[table.attrs.get("given", [c for c in table.columns if c != "line"])].copy()
    for name, values in res.items():
        out[name] = values
    for name in ("E_star_Pa", "M_sample_Pa", "contact_radius_m", "modulus_method"):
        out[name] = mod[name]
    # A modulus beyond diamond's (M ~ 1.2 TPa) or below a soft gel's is a wrong input (k_c, R,
    # P in the wrong unit), not a result: withheld and flagged.
    absurd = ~((mod["M_sample_Pa"] >= M_RANGE_PA[0]) & (mod["M_sample_Pa"] <= M_RANGE_PA[1]))
    absurd &= np.isfinite(mod["M_sample_Pa"])
    out.loc[absurd, ["E_star_Pa", "M_sample_Pa"]] = np.nan
    mod["modulus_flags"][absurd] = "modulus-out-of-range"
    both = [
        ";".join(x for x in pair if x)
        for pair in zip(res["flags"], mod["modulus_flags"], strict=True)
    ]
    out["flags"] = both
    out["normalisation"] = normalisation
    return out
