"""What ``contactres qcm analyze`` prints: Table 1 with errors, withheld fits, friction per load,
and (with the materials) the radiation loss per group.

Plain text for a terminal: values with their standard errors (``59.7 ± 0.5``; ``t95`` is the
factor that turns an error from a few repeats into a 95 % interval), ``—`` where a value is
withheld or missing (never ``nan``), and one line per withheld group saying why and which input
to check. The files of the results folder hold every number at full precision.
"""

from __future__ import annotations

import math

import pandas as pd

from ..analysis import Results, radiation_summary

__all__ = ["friction_table", "plus_minus", "radiation_lines", "table1_text", "withheld_lines"]

DASH = "—"


def plus_minus(value: float, err: float, digits: int = 3) -> str:
    """``value ± err`` with the error to 2 significant digits and the value to match."""
    if not math.isfinite(value):
        return DASH
    if not math.isfinite(err) or err <= 0:
        return f"{value:.{digits}g}"
    decimals = max(0, 1 - math.floor(math.log10(err)))
    return f"{value:.{decimals}f} ± {err:.{decimals}f}"


def _t95(t: float) -> str:
    """The Student-t factor of the 95 % interval, as printed (``—`` where there is none)."""
    return f"{t:.2f}" if math.isfinite(t) else DASH


def table1_text(results: Results) -> pd.DataFrame:
    """Table 1 for the terminal: E (GPa) and γ (mJ/m²) with errors, counts, error method."""
    rows = []
    for g in results.groups:
        rows.append(
            {
                "configuration": g["configuration"],
                "medium": g["medium"],
                "E (GPa)": plus_minus(g["E_Pa"] / 1e9, g["E_err_Pa"] / 1e9),
                "γ (mJ/m²)": plus_minus(g["gamma_J_m2"] * 1e3, g["gamma_err_J_m2"] * 1e3),
                "experiments": g["n_experiments"],
                "sweeps": g["n_sweeps_used"],
                "t95": _t95(g.get("t95", math.nan)),
                "errors": g.get("error_method", "") or DASH,
            }
        )
    return pd.DataFrame(rows)


def withheld_lines(results: Results) -> list[str]:
    """One line per group whose E and γ are withheld, with the reason and the input to check,
    and per group whose fit left points out (κ <= 0, or no κ), saying so."""
    return [
        f"{g['configuration']}, {g['medium']}: E and γ withheld ({', '.join(g['checks'])}): "
        f"{g['note']}"
        if g.get("checks")
        else f"{g['configuration']}, {g['medium']}: {g['note']}"
        for g in results.groups
        if g.get("checks") or g.get("note")
    ]


def friction_table(results: Results) -> pd.DataFrame:
    """μ per load (exact-loop fit): median over experiments ± its error, and the counts."""
    loads = results.loads
    # A load of a group whose E and γ were withheld for an input μ scales with too says so
    # (loads.csv: flags mu-withheld), rather than a dash that reads as "no sliding".
    withheld = loads.get("flags", pd.Series("", index=loads.index)).astype(str) == "mu-withheld"
    return pd.DataFrame(
        {
            "configuration": loads["configuration"],
            "medium": loads["medium"],
            "F_N (mN)": [f"{f * 1e3:.4g}" for f in loads["normal_force_N"]],
            "μ (loop fit)": [
                "withheld (see E, γ)" if w else plus_minus(m, e, 2)
                for m, e, w in zip(
                    loads["mu_fit_median"], loads["mu_fit_median_err"], withheld, strict=True
                )
            ],
            "experiments": loads["n_experiments"],
            "sweeps": loads["n_sweeps"],
            "t95": [_t95(t) for t in loads.get("t95", [math.nan] * len(loads))],
        }
    )


def _two(value: float) -> str:
    """Two significant digits, never in exponent form for everyday sizes (130, not 1.3e+02)."""
    return f"{float(f'{value:.2g}'):g}"


def _span(values, scale: float = 1.0) -> str:
    """``lo–hi`` scaled, to two significant digits (one number where they agree)."""
    lo, hi = (_two(v * scale) for v in values)
    return lo if lo == hi else f"{lo}–{hi}"


def radiation_lines(results: Results) -> list[str]:
    """One line per group: the radiation loss tangent, the contact radius and the share of the
    measured loss tangent (ranges over the loads, median share), or why it is not given."""
    if results.radiation is None:
        return []
    lines = []
    for g in radiation_summary(results.radiation):
        head = f"{g['configuration']}, {g['medium']}: "
        if g["tan_delta_rad_range"] is None:
            lines.append(head + f"radiation loss not computed: {g['note'] or 'no loads'}")
            continue
        text = (
            f"radiation loss tangent {_span(g['tan_delta_rad_range'])} at a = "
            f"{_span(g['contact_radius_range_m'], 1e6)} µm"
        )
        if g["radiation_share_range"] is not None:
            text += (
                f", {_span(g['radiation_share_range'], 100)} % of the measured (median "
                f"{_two(g['radiation_share_median'] * 100)} %)"
            )
        change = g["E_relative_change"]
        if math.isfinite(change):
            sign = "+" if change >= 0 else "−"
            text += f"; E for a static κ {sign}{_two(abs(change) * 100)} %"
        share = g["radiation_share_range"]
        if share is not None and share[1] > 1:
            text += " — CHECK: above 100 % at some loads, the model does not hold there"
        lines.append(head + text)
    return lines
