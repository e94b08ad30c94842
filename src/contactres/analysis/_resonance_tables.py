"""Tables of measured resonances -> contact stiffness (and modulus), one row per point or pixel.

The orchestration behind ``contactres rum invert`` and ``contactres afm invert``: the checked
tables of :mod:`contactres.measurements` go through the oscillator models of
:mod:`contactres.resonators` and the modulus step of :mod:`contactres.analysis._inversion`;
the output keeps every input column and appends the results. A table is a
:class:`pandas.DataFrame` or, read from a numpy archive, a
:class:`~contactres.measurements.ArrayTable` (numpy columns: a map inverted without pandas,
issue 31); the output is of the input's kind. Rows that the physics rejects
(a contact resonance below the free one by more than
:data:`~contactres.resonators.FREE_TOLERANCE`) are errors naming the line; a CR-AFM resonance at
the free one is no contact (κ = 0, flag ``no-contact``); rows that only cannot be inverted (no
crossing of two modes, a mode without sensitivity) keep empty results and say why in ``flags``.
"""

from __future__ import annotations

import warnings
from collections.abc import Collection
from typing import TYPE_CHECKING

import numpy as np

from .._column_names import refuse_computed_names
from .._threads import one_blas_thread
from ..errors import ContactresInputError, ContactresWarning
from ..measurements import at_cell, where_rows
from ..resonators import (
    FREE_TOLERANCE,
    MODE_TOLERANCE,
    Cantilever,
    RUMOscillator,
    flag_names,
    invert_contact_resonance,
)
from ._inversion import ModulusFlag, modulus_from_contact_stiffness, surface_material

if TYPE_CHECKING:
    import pandas as pd

    from ..measurements import ArrayTable

__all__ = ["AFM_GROUP_COLUMNS", "invert_afm_table", "invert_rum_table"]

#: Columns that define one lever and one tip geometry: rows sharing them are inverted at once.
AFM_GROUP_COLUMNS = (
    "f1_free_Hz",
    "f2_free_Hz",
    "f3_free_Hz",
    "Q1_free",
    "Q2_free",
    "Q3_free",
    "lateral_ratio",
    "tip_height_over_L",
    "tilt_deg",
)
_MODES = (1, 2, 3)
#: The columns :func:`invert_rum_table` appends (the film columns of ``--coating`` are added by
#: the job, :func:`contactres.jobs.afm_invert.add_film_columns`, and checked here with these:
#: the ``appended`` of the inversions).
_RUM_COMPUTED = ("rum_model", "k_star_N_per_m")
#: The columns :func:`invert_afm_table` appends to every table, and with a ``sample`` (the
#: dynamic correction) also :data:`_AFM_DYNAMIC`, before ``flags`` and ``normalisation``.
_AFM_COMPUTED = (
    "kappa",
    "k_star_N_per_m",
    "tip_position_used",
    "sigma_N_s_per_m",
    "mode_spread",
    "tip_position_other",
    "kappa_other",
    "E_star_Pa",
    "M_sample_Pa",
    "contact_radius_m",
    "modulus_method",
    "flags",
    "normalisation",
)
_AFM_DYNAMIC = ("k_static_N_per_m", "k_a", "dcsf_real", "dcsf_imag")
#: The Hertz and reference inputs of the modulus step (floats; NaN where blank).
_MODULUS_INPUTS = ("tip_radius_m", "load_N", "M_tip_Pa", "hardness_Pa", "M_ref_Pa", "M_ref2_Pa")
#: The largest fc/f0 a RUM row may have. A contact spring at the tip raises the first mode of a
#: real oscillator at most to its pinned-tip (k* -> ∞) limit: 1.5 f0 for a rod free at the far
#: end, (3.9266/1.8751)² = 4.39 f0 for a cantilever (the stiffest raise of the resonators a RUM
#: or CR-AFM uses). The lumped model (f/f0)² = 1 + k*/K_eff has no limit of its own, so it takes
#: this one: a larger ratio is a unit slip between f0_Hz and fc_Hz (kHz against Hz), not a contact.
_MAX_RUM_RAISE = 4.39
#: Tip radius (m) above which a CR-AFM row is flagged ``large-tip``, with a warning: a CR-AFM tip
#: is 1 nm-1 µm, so 5e-2 is most likely nm or µm typed as m (M comes out 1e4 times too small).
#: Not an error: a sphere of mm size (a RUM-like contact, paper 1) is a valid input.
LARGE_TIP_M = 1e-3


def _given_columns(table):
    """The columns of the table as the file gave them (not the schema's absent ones): copied
    from a DataFrame, the same arrays from an ArrayTable (its columns are not written to)."""
    from ..measurements import ArrayTable

    given = table[table.attrs.get("given", [c for c in table.columns if c != "line"])]
    return given.copy(deep=not isinstance(given, ArrayTable))


def _floats(table, name: str) -> np.ndarray:
    """A column of a DataFrame or an ArrayTable as float64 numbers."""
    return np.asarray(table[name], dtype=float)


def _matrix(table, names) -> np.ndarray:
    """The columns ``names`` as a (rows, columns) float64 array."""
    return np.column_stack([_floats(table, c) for c in names])


def _uniform(column: np.ndarray) -> bool:
    """True if every value of a float column equals the first (NaN: every value NaN)."""
    first = column[0]
    return bool(np.isnan(column).all() if np.isnan(first) else (column == first).all())


def _row_groups(keys: list[np.ndarray]) -> list[np.ndarray]:
    """The row numbers of each distinct row of the float columns ``keys``, groups in the order
    of their first row, rows ascending: pandas' ``groupby(sort=False, dropna=False).indices``
    (NaN equal to NaN, -0.0 to 0.0), by a sort of numbers."""
    if all(_uniform(column) for column in keys):  # one lever and one geometry: a map
        return [np.arange(len(keys[0]))]
    table = np.column_stack(keys)
    table = np.where(np.isnan(table), np.nan, table + 0.0)  # one NaN and one zero, bit for bit
    rows = np.ascontiguousarray(table).view(np.dtype((np.void, table.itemsize * table.shape[1])))
    _, first, inverse = np.unique(rows.ravel(), return_index=True, return_inverse=True)
    label = np.argsort(np.argsort(first))[inverse.reshape(-1)]  # groups by their first row
    order = np.argsort(label, kind="stable")
    return np.split(order, np.cumsum(np.bincount(label))[:-1])


def _flag_text(codes: np.ndarray, names) -> np.ndarray:
    """Bit masks as ';'-joined hyphenated names (``names(code)`` -> list), one per distinct
    mask rather than per row."""
    uniq, inverse = np.unique(np.asarray(codes, dtype=int), return_inverse=True)
    text = np.array([";".join(n.replace("_", "-") for n in names(c)) for c in uniq], dtype=object)
    return text[inverse.reshape(-1)]


def _joined_flags(codes, modulus_codes) -> np.ndarray:
    """The flags of the lever (``flag_names``) and of the modulus of every row as one
    ';'-joined text, joined once per distinct pair of masks rather than per row (a 512² map
    has a few pairs in 262,144 rows: the join per row was ~0.15 s of its inversion)."""
    a = np.asarray(codes, dtype=np.int64).reshape(-1)
    b = np.asarray(modulus_codes, dtype=np.int64).reshape(-1)
    width = int(b.max(initial=0)) + 1  # one integer per pair of masks (>= 0): a sort of ints,
    uniq, inverse = np.unique(a * width + b, return_inverse=True)  # not of rows (~10x slower)
    lever = _flag_text(uniq // width, flag_names)
    modulus = _flag_text(uniq % width, _modulus_names)
    text = [";".join(t for t in pair if t) for pair in zip(lever, modulus, strict=True)]
    joined = np.array(text, dtype=object)
    return joined[inverse.reshape(-1)]


def _modulus_names(code: int) -> list[str]:
    return [f.name.lower() for f in ModulusFlag if f.name and int(code) & f]


def _lumped_rows(table: pd.DataFrame, source: str) -> np.ndarray:
    """Which rows are lumped (K_eff_N_per_m given) rather than rods (mass_kg given)."""
    lumped = table["K_eff_N_per_m"].notna().to_numpy()
    rod = table["mass_kg"].notna().to_numpy()
    both = lumped & rod
    if both.any():
        raise ContactresInputError(
            f"{at_cell(table, source, both, 'mass_kg')}: give K_eff_N_per_m (lumped model) or "
            "mass_kg (rod model) in a row, not both"
        )
    neither = ~(lumped | rod)
    if neither.any():
        raise ContactresInputError(
            f"{at_cell(table, source, neither, 'K_eff_N_per_m')}: each row needs "
            "K_eff_N_per_m (lumped model) or mass_kg (rod model)"
        )
    return lumped


@one_blas_thread()
def invert_rum_table(
    table: pd.DataFrame, source: str = "table", *, appended: Collection[str] = ()
) -> pd.DataFrame:
    """k* of every row of a checked RUM table (:data:`~contactres.measurements.schema.RUM_TABLE`):
    ``k_star_N_per_m`` and ``rum_model`` appended.

    Lumped rows: (f/f0)² = 1 + k*/K_eff; rod rows (mass m): k* = (EA/L)(kL) tan(kL) of a rod
    free at one end with the contact spring at the other, EA/L = 4 m f0² (mode 1; see
    :class:`~contactres.resonators.RUMOscillator`). Raises ValueError naming the line for a
    contact resonance below f0 (a spring cannot lower it), above 4.39 f0 (the pinned limit of a
    cantilever, the largest raise of a real oscillator's first mode: a unit slip) or at/above the
    rod's clamped limit.
    The rows are grouped by their calibration (one oscillator per group; a file rarely holds
    more than a few), each group converted at once.

    ``appended``: the names of the columns the caller adds to the result after these (a
    coating's film columns, ``rum invert --coating``), refused with the run's own in one line
    where the table gives one (as :func:`invert_afm_table`).
    """
    import pandas as pd

    refuse_computed_names(table, (*_RUM_COMPUTED, *appended), source)
    lumped = _lumped_rows(table, source)
    f0 = table["f0_Hz"].to_numpy(float)
    fc = table["fc_Hz"].to_numpy(float)
    below = fc < f0
    if below.any():
        raise ContactresInputError(
            f"{at_cell(table, source, below, 'fc_Hz')}: the contact resonance is below the free "
            "resonance f0_Hz of its row; a contact spring can only raise it (check the columns)"
        )
    far = fc > _MAX_RUM_RAISE * f0
    if far.any():
        raise ContactresInputError(
            f"{at_cell(table, source, far, 'fc_Hz')}: more than {_MAX_RUM_RAISE:g} times the free "
            "resonance f0_Hz of its row, the most a contact spring can raise the first mode of a "
            "rod (1.5x) or cantilever (4.39x); check that f0_Hz and fc_Hz are both in Hz"
        )
    calib = np.where(lumped, table["K_eff_N_per_m"], table["mass_kg"]).astype(float)
    k_star = np.full(len(table), np.nan)
    groups = pd.DataFrame({"lumped": lumped, "f0": f0, "calib": calib}).groupby(
        ["lumped", "f0", "calib"], sort=False
    )
    for rows in groups.indices.values():  # one oscillator per calibration, not per row
        i = rows[0]
        if lumped[i]:
            osc = RUMOscillator.lumped(f0[i], calib[i])
        else:
            osc = RUMOscillator.rod(f0[i], calib[i])
            over = fc[rows] >= osc.clamped_frequency
            if over.any():
                mask = np.zeros(len(table), bool)
                mask[rows[over]] = True
                raise ContactresInputError(
                    f"{at_cell(table, source, mask, 'fc_Hz')}: at or above the clamped limit "
                    f"1.5 f0 = {osc.clamped_frequency:.6g} Hz of the rod model, which no finite "
                    "contact stiffness reaches (check f0_Hz and fc_Hz)"
                )
        k_star[rows] = osc.contact_stiffness(fc[rows])
    out = _given_columns(table)
    out["rum_model"] = np.where(lumped, "lumped", "rod")
    out["k_star_N_per_m"] = k_star
    return out


def _leading(values: np.ndarray) -> tuple[float, ...] | None:
    """The leading given (non-NaN) values of a lever's constants (f1, f2, ...), or None."""
    n = int(np.argmin(np.append(~np.isnan(values), False)))
    return tuple(float(v) for v in values[:n]) or None


def _dynamic(col, k_modes, fc, rows, sample, loss) -> dict:
    """Paper 1's correction of the Hertz rows ``rows``: every averaged mode n corrected at its
    own frequency, K_n = k*_n/Re DCSF(k_l(f_n) a_n) (each with its own fixed point for a), and
    K_static the mean of the K_n; k_a and the DCSF reported are those of the row's first
    averaged mode. ``k_modes``: (rows, modes) k* per mode, NaN where not averaged."""
    n = len(rows)
    out = {k: np.full(n, np.nan) for k in ("k_static", "k_a", "dcsf_real", "dcsf_imag")}
    i, j = np.nonzero(rows[:, None] & np.isfinite(k_modes) & (k_modes > 0))
    if i.size == 0:
        return out
    from ..dynamic import prepare  # here: a static inversion never loads scipy.special

    surface = surface_material(sample, "sample")
    res = modulus_from_contact_stiffness(
        k_modes[i, j],
        tip_radius=col["tip_radius_m"][i],
        load=col["load_N"][i],
        frequency=fc[i, j],
        sample=surface,
        dynamic=True,
        loss=loss,
        prepared=prepare(surface, loss),  # one kernel table for every row and mode
    )
    count = np.bincount(i, minlength=n)
    with np.errstate(invalid="ignore"):
        out["k_static"] = np.bincount(i, weights=res.k_static, minlength=n) / count
    first = np.unique(i, return_index=True)[1]  # (i, j) come row by row, modes ascending
    out["k_a"][i[first]] = res.k_a[first]
    out["dcsf_real"][i[first]] = res.dcsf.real[first]
    out["dcsf_imag"][i[first]] = res.dcsf.imag[first]
    return out


def _modulus(col: dict, k_star: np.ndarray, have_kc: np.ndarray, ref, ref2) -> dict:
    """E*, M_sample, a and the modulus flags of every row: Hertz where tip_radius_m, load_N and
    k_c are given, else the reference sample(s) where fc1_ref_Hz and M_ref_Pa are; NaN
    elsewhere. A blank M_tip_Pa is a rigid tip; a blank hardness_Pa is no plasticity check."""
    n = len(k_star)
    out = {k: np.full(n, np.nan) for k in ("E_star_Pa", "M_sample_Pa", "contact_radius_m")}
    out["modulus_method"] = np.full(n, "", dtype=object)
    out["modulus_flags"] = np.zeros(n, dtype=int)
    load = col["load_N"]
    hertz = ~np.isnan(col["tip_radius_m"]) & ~np.isnan(load) & have_kc
    refd = ~hertz & ~np.isnan(ref) & ~np.isnan(col["M_ref_Pa"])
    two = refd & ~np.isnan(ref2) & ~np.isnan(col["M_ref2_Pa"])
    one_ref = dict(reference_k_star=ref, reference_modulus=col["M_ref_Pa"])
    methods = (
        (hertz, dict(tip_radius=col["tip_radius_m"])),
        (refd & ~two, one_ref),
        (two, dict(one_ref, reference2_k_star=ref2, reference2_modulus=col["M_ref2_Pa"])),
    )
    tip, hardness = col["M_tip_Pa"], col["hardness_Pa"]
    positive, no_tip, no_load = np.isfinite(k_star) & (k_star > 0), np.isnan(tip), np.isnan(load)
    for rows, kwargs in methods:
        if not (rows := rows & positive).any():
            continue
        for rigid in (True, False):
            for loaded in (True, False):  # a reference method uses the load where given
                ok = rows & (no_tip == rigid) & (no_load != loaded)
                if not ok.any():
                    continue
                H = hardness[ok] if loaded and not np.isnan(hardness[ok]).all() else None
                res = modulus_from_contact_stiffness(
                    k_star[ok],
                    load=load[ok] if loaded else None,
                    tip_modulus=None if rigid else tip[ok],
                    hardness=H,
                    **{k: v[ok] for k, v in kwargs.items()},
                )
                out["E_star_Pa"][ok] = res.E_star
                out["M_sample_Pa"][ok] = res.M_sample
                out["contact_radius_m"][ok] = res.contact_radius
                out["modulus_method"][ok] = res.method
                out["modulus_flags"][ok] = res.flags
    return out


def _check_free_q(table, source: str) -> None:
    """A free Q for every free frequency given, or none (the lever's damping is per mode)."""
    given = {n: ~np.isnan(_floats(table, f"Q{n}_free")) for n in _MODES}
    other = given[1] | given[2] | given[3]  # a column at a time: not a reduction across a row
    for n in _MODES:
        f = ~np.isnan(_floats(table, f"f{n}_free_Hz"))
        bad = f & ~given[n] & other
        if bad.any():
            raise ContactresInputError(
                f"{where_rows(table, source, bad, f'Q{n}_free')}: is empty while another free "
                "Q is given; give the Q of every free mode or of none"
            )


@one_blas_thread()
def invert_afm_table(
    table: pd.DataFrame | ArrayTable,
    source: str = "table",
    normalisation: str = "global",
    *,
    sample=None,
    loss: float = 0.0,
    mode_tolerance: float = MODE_TOLERANCE,
    appended: Collection[str] = (),
) -> pd.DataFrame | ArrayTable:
    """κ, k*, r, σ and (where the inputs allow) E* and M_sample of every row of a checked CR-AFM
    table (:data:`~contactres.measurements.schema.AFM_TABLE`).

    Rows are grouped by their lever and tip geometry (:data:`AFM_GROUP_COLUMNS`) and by whether
    the tip position is given; each group is inverted at once by
    :func:`~contactres.resonators.invert_contact_resonance` (the modes
    used are the contact-resonance columns given in the row; r blank: solved from two modes; a
    blank Q: no damping for that cell). The modulus step
    (:func:`~contactres.analysis.modulus_from_contact_stiffness`) runs where
    tip_radius_m, load_N and k_c_N_per_m (Hertz) or fc1_ref_Hz and M_ref_Pa (reference samples,
    inverted with the same lever and tip position; k_c not needed) are given. ``flags`` names
    why a value is missing; ``normalisation`` is recorded in every row. ``mode_spread`` is the
    largest relative disagreement of κ between the modes that check it (three modes with r
    solved, two or more with r given; flag ``inconsistent-modes`` beyond ``mode_tolerance``).

    ``sample`` (a :class:`~contactres.materials.Material` in its surface frame, with density,
    or a ``(material, (h, k, l))`` pair) applies paper 1's dynamic correction to the Hertz
    rows: each mode averaged into κ is corrected at its own frequency, K_n = k*_n/Re
    DCSF(k_l(f_n) a) (Q⁻¹ = ``loss``), and the modulus follows from the mean K_static
    (``k_static_N_per_m``); ``k_a``, ``dcsf_real``, ``dcsf_imag`` are those of the row's first
    averaged mode. With r solved from two modes the crossing itself is found on the measured
    (dynamic) κ; the correction then changes each mode's κ by its own factor. The reference
    rows are not corrected: sample and reference are measured at nearly the same frequency and
    contact size, so their corrections cancel to second order in k_l a.

    A tip radius above :data:`LARGE_TIP_M` (1 mm) is kept but flagged ``large-tip`` with a
    :class:`~contactres.errors.ContactresWarning` naming the first such cell: a CR-AFM tip is
    1 nm-1 µm, a larger value is most often a unit slip, while a mm sphere is a valid contact.

    ``appended``: the names of the columns the caller adds to the result after these (a
    coating's film columns, ``afm invert --coating``). A given column named as one the run
    writes, computed here or appended, is refused, all of them in one line.
    """
    # Only the names this run writes: a column the run does not compute (k_a without a
    # sample) is the user's and stays as given. The caller's names are checked with them:
    # checked apart, a table holding both would be refused twice, one fix at a time.
    refuse_computed_names(
        table,
        (*_AFM_COMPUTED, *(_AFM_DYNAMIC if sample is not None else ()), *appended),
        source,
    )
    fc = _matrix(table, [f"fc{n}_Hz" for n in _MODES])
    none = np.isnan(fc[:, 0]) & np.isnan(fc[:, 1]) & np.isnan(fc[:, 2])
    if none.any():
        raise ContactresInputError(
            f"{where_rows(table, source, none, 'fc1_Hz')}: no contact resonance in this row "
            "(fc1_Hz, fc2_Hz and fc3_Hz are all empty)"
        )
    for n in _MODES:  # a contact spring only raises a mode: below the free lever is impossible
        # (at the free frequency or a hair below it, FREE_TOLERANCE: no contact, κ = 0)
        free_n = _floats(table, f"f{n}_free_Hz")
        below = fc[:, n - 1] < free_n * (1.0 - FREE_TOLERANCE)
        if below.any():
            raise ContactresInputError(
                f"{at_cell(table, source, below, f'fc{n}_Hz')}: below the free resonance "
                f"f{n}_free_Hz of its row; a contact can only raise it (check the columns)"
            )
    _check_free_q(table, source)
    if normalisation == "modewise":  # each mode measured needs its own free frequency
        for n in _MODES:
            lacking = ~np.isnan(fc[:, n - 1]) & np.isnan(_floats(table, f"f{n}_free_Hz"))
            if lacking.any():
                raise ContactresInputError(
                    f"{where_rows(table, source, lacking, f'f{n}_free_Hz')}: is empty while "
                    f"fc{n}_Hz is given; modewise normalisation needs the free frequency of "
                    "every mode used (or use --normalisation global)"
                )
    q = _matrix(table, [f"Q{n}" for n in _MODES])
    f_ref = _matrix(table, ["fc1_ref_Hz", "fc1_ref2_Hz"])
    r_in = _floats(table, "tip_position")
    k_c = _floats(table, "k_c_N_per_m")
    have_kc = ~np.isnan(k_c)
    n = len(table)
    res = {
        c: np.full(n, np.nan)
        for c in (
            "kappa",
            "tip_position_used",
            "sigma_N_s_per_m",
            "mode_spread",
            "tip_position_other",
            "kappa_other",
        )
    }
    flags = np.zeros(n, dtype=int)
    k_modes = np.full((n, len(_MODES)), np.nan)  # κ of each mode averaged into κ (else NaN)
    refs = np.full((n, 2), np.nan)  # κ on the reference samples (k* = κ k_c; ratios need κ)
    # AFM_GROUP_COLUMNS (free f1-f3, free Q1-Q3, lateral ratio, tip height, tilt), r given
    keys = [*(_floats(table, c) for c in AFM_GROUP_COLUMNS), (~np.isnan(r_in)).astype(float)]
    for rows in _row_groups(keys):
        first = np.array([column[rows[0]] for column in keys])
        free = _leading(first[0:3])
        assert free is not None  # f1_free_Hz is a required column: never empty
        lever = Cantilever(
            free,
            1.0,  # κ = k*/k_c is what the frequencies give; k* = κ k_c below, where k_c is known
            normalisation=normalisation,
            free_q_factors=_leading(first[3:6]),
        )
        geometry = dict(
            lateral_ratio=np.nan_to_num(first[6]),
            tip_height=np.nan_to_num(first[7]),
            tilt=np.nan_to_num(first[8]),
        )
        # The results of a group of every row (a map) go in by a slice, not row by row.
        at = slice(None) if len(rows) == n else rows
        r = r_in[rows] if first[9] else None
        # The modes up to the last one given in the group: a map of two modes is not inverted
        # a third time on a column of NaN (a third of its inversion; issue 31, point 5).
        f_group = fc[rows]
        given = [j for j in range(len(_MODES)) if not np.isnan(f_group[:, j]).all()]
        used = given[-1] + 1 if given else len(_MODES)
        qs = q[rows, :used] if np.isfinite(q[rows, :used]).any() else None
        inv = invert_contact_resonance(
            lever,
            f_group[:, :used].copy(),  # contiguous, as before (numpy's loops by layout)
            tip_position=r,
            q_factors=qs,
            mode_tolerance=mode_tolerance,
            **geometry,
        )
        res["kappa"][at] = inv.kappa
        res["tip_position_used"][at] = inv.tip_position
        res["sigma_N_s_per_m"][at] = inv.sigma * np.where(have_kc[at], k_c[at], np.nan)
        res["mode_spread"][at] = inv.mode_spread
        res["tip_position_other"][at] = inv.tip_position_other
        res["kappa_other"][at] = inv.kappa_other
        k_modes[at, :used] = np.where(inv.averaged_modes, inv.kappa_modes, np.nan)
        flags[at] = inv.flags
        solved = np.isfinite(inv.tip_position)  # two modes without a crossing: no reference
        for j in (0, 1):
            take = solved & ~np.isnan(f_ref[rows, j])
            if take.any():
                freqs = np.full((int(take.sum()), 3), np.nan)
                freqs[:, 0] = f_ref[rows[take], j]
                back = invert_contact_resonance(
                    lever, freqs, tip_position=inv.tip_position[take], **geometry
                )
                # a reference at its free frequency (κ = 0, no contact) calibrates nothing
                refs[rows[take], j] = np.where(back.kappa > 0, back.kappa, np.nan)
    k_star = res["kappa"] * k_c
    # Without k_c, k* is unknown, but the reference method needs only ratios of k*: it runs on κ.
    col = {c: _floats(table, c) for c in _MODULUS_INPUTS}
    scale = np.where(have_kc, k_c, 1.0)
    k_used = np.where(have_kc, k_star, res["kappa"])
    if sample is not None:
        hertz = have_kc & ~np.isnan(col["tip_radius_m"]) & ~np.isnan(col["load_N"])
        dyn = _dynamic(col, k_modes * k_c[:, None], fc, hertz & np.isfinite(k_star), sample, loss)
        k_used = np.where(np.isfinite(dyn["k_static"]), dyn["k_static"], k_used)
    mod = _modulus(col, k_used, have_kc, *(refs * scale[:, None]).T)
    # Without k_c a row has no k*: said in its flags, not left as bare empty cells (issue 27).
    mod["modulus_flags"] = np.where(
        have_kc, mod["modulus_flags"], mod["modulus_flags"] | ModulusFlag.NO_SPRING_CONSTANT
    )
    out = _given_columns(table)
    out["kappa"] = res["kappa"]
    out["k_star_N_per_m"] = k_star
    out["tip_position_used"] = res["tip_position_used"]
    out["sigma_N_s_per_m"] = res["sigma_N_s_per_m"]
    out["mode_spread"] = res["mode_spread"]
    out["tip_position_other"] = res["tip_position_other"]
    out["kappa_other"] = res["kappa_other"]
    if sample is not None:
        method = mod["modulus_method"]
        corrected = np.isfinite(dyn["k_static"]) & (method != "")
        method[corrected] = method[corrected] + " + dynamic"
    names = ["E_star_Pa", "M_sample_Pa", "contact_radius_m", "modulus_method"]
    for name in names:
        out[name] = mod[name]
    if sample is not None:
        parts = ("k_static", "k_a", "dcsf_real", "dcsf_imag")
        for name, key in zip(_AFM_DYNAMIC, parts, strict=True):
            out[name] = dyn[key]
    flags_text = _joined_flags(flags, mod["modulus_flags"])
    large = np.nan_to_num(col["tip_radius_m"]) > LARGE_TIP_M  # issue 27: no silent unit slip
    if large.any():
        flags_text[large] = [f"{t};large-tip" if t else "large-tip" for t in flags_text[large]]
        warnings.warn(
            f"{at_cell(table, source, large, 'tip_radius_m')} m: above 1 mm in "
            f"{int(large.sum())} row(s), flagged large-tip; check the unit (a CR-AFM tip is "
            "1 nm-1 µm; a sphere of mm size is accepted)",
            ContactresWarning,
            stacklevel=2,
        )
    out["flags"] = flags_text
    out["normalisation"] = normalisation
    return out
