"""The numbers docs/validation.md quotes for paper 2's self-contradictions (issue 27, point 13).

Each number the page prints ("Where paper 2 contradicts itself") is recomputed here from paper
2's values (Table 1's E and γ, the loads of its tripod, μ = 0.2 and 1, the 20 nm of its air
ramps) and looked up on the page in the form it is printed, so neither can drift from the other.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from contactres.tangential import kappa_jkr_mindlin

PAGE = Path(__file__).resolve().parents[2] / "docs" / "validation.md"
NU = 0.17
#: Paper 2's tripod: 0.5 g plus 0 ... 2.5 g, a third of the weight on each contact.
LOADS = (0.5e-3 * 9.81 / 3, 3.0e-3 * 9.81 / 3)
#: Table 1 of paper 2 as the page reads it: configuration -> (R, (E, γ) air, (E, γ) water).
TABLE1 = {
    "SiO2, 2.2 mm": (1.1e-3, (100e9, 0.19), (63e9, 0.05)),
    "SiO2, 1.2 mm": (0.6e-3, (61e9, 0.03), (47e9, 0.02)),
    "PMMA, 2.2 mm": (1.1e-3, (70e9, 0.01), (45e9, 0.0)),
}


@pytest.fixture(scope="module")
def section() -> str:
    text = PAGE.read_text(encoding="utf-8")
    start = text.index("## Where paper 2 contradicts itself")
    return text[start : text.index("\n## ", start + 1)]


def _kappa(config, medium):
    R, air, water = TABLE1[config]
    E, gamma = air if medium == "air" else water
    return kappa_jkr_mindlin(np.array(LOADS), E, gamma, R, NU)


def test_the_loads_are_the_papers():
    assert [f"{F * 1e3:.3f}" for F in LOADS] == ["1.635", "9.810"]


def test_kappa_by_hand_agrees_with_the_package():
    # Independent of the package: JKR with work of adhesion w = 2γ (paper 2's γ),
    # a³ = 3R/(4E*) [F + 3πwR + √(6πwRF + (3πwR)²)], E* = E/(2(1 - ν²)) for two equal bodies,
    # and Mindlin's κ = 8G*a with G* = G/(2(2 - ν)) (Johnson's, a quarter of paper 2's G*).
    R, (E, gamma), _ = TABLE1["SiO2, 2.2 mm"]
    F, w = LOADS[0], 2 * gamma
    E_star = E / (2 * (1 - NU**2))
    adhesion = 3 * np.pi * w * R
    a = (3 * R / (4 * E_star) * (F + adhesion + np.sqrt(2 * adhesion * F + adhesion**2))) ** (1 / 3)
    G = E / (2 * (1 + NU))
    assert 8 * G / (2 * (2 - NU)) * a == pytest.approx(_kappa("SiO2, 2.2 mm", "air")[0], rel=1e-9)


@pytest.mark.parametrize("config", list(TABLE1))
def test_table1_water_is_softer_as_the_page_prints(section, config):
    air, water = _kappa(config, "air"), _kappa(config, "water")
    ratio = water / air
    R = TABLE1[config][0]
    row = (
        f"| {config} ({R * 1e3:.1f} mm) | {air[0] / 1e6:.3f} / {air[1] / 1e6:.3f} MN/m | "
        f"{water[0] / 1e6:.3f} / {water[1] / 1e6:.3f} MN/m | {ratio[0]:.2f} / {ratio[1]:.2f} |"
    )
    assert row in section
    # Softer at every load, never the text's +10 %.
    assert np.all(ratio < 0.9)


def test_softening_range_as_the_page_prints(section):
    ratios = np.concatenate([_kappa(c, "water") / _kappa(c, "air") for c in TABLE1])
    lo, hi = 1 - ratios.max(), 1 - ratios.min()
    assert f"{lo * 100:.0f}-{hi * 100:.0f} % *softer*" in section


def test_full_sliding_amplitudes_as_the_page_prints(section):
    kappa = _kappa("SiO2, 2.2 mm", "air")
    F = np.array(LOADS)
    assert (
        f"({kappa[0] / 1e6:.3f} MN/m at 1.635 mN, {kappa[1] / 1e6:.3f} MN/m at 9.81 mN)" in section
    )
    # The page rounds to two significant figures below 10 nm and to 0.1 nm above.
    fmt = {0.2: (".2f", ".1f", ".2f", ".1f"), 1.0: (".1f", ".1f", ".1f", ".1f")}
    for mu, (f0, f1, f2, f3) in fmt.items():
        scale = mu * F / kappa * 1e9  # μF_N/κ, nm
        slide = 1.5 * scale  # Cattaneo-Mindlin slides fully at x = κu0/(μF_N) = 3/2
        row = (
            f"| {mu:g} | {scale[0]:{f0}} / {scale[1]:{f1}} nm | "
            f"{slide[0]:{f2}} / {slide[1]:{f3}} nm |"
        )
        assert row in section
    # μ that keeps 20 nm below full sliding, and x at 20 nm for μ = 1 at the lightest load.
    need = 2 * kappa * 20e-9 / (3 * F)
    assert f"{need[0]:.1f} at 1.635 mN and {need[1]:.2f} at 9.81 mN" in section
    assert f"x = {kappa[0] * 20e-9 / F[0]:.1f} at" in section
    # Full sliding below the 20 nm ramps for every μ <= 1 at the lightest load.
    assert 1.5 * F[0] / kappa[0] < 20e-9
