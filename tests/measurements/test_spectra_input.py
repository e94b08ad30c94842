"""Reading admittance spectra (tidy table, folder of network-analyser files) and the amplitude.

Independent checks: the S11 -> Y conversion against the impedance of a known circuit written
here, the Touchstone formats (RI, MA, DB) against each other, and u0 = 4 d26 Q U/(nπ)² against
the exact steady state of a damped piezoelectric plate (1-D wave equation with the piezoelectric
boundary stress), not against the modal argument behind the formula.
"""

import cmath
import math

import numpy as np
import pandas as pd
import pytest

from contactres.measurements._shifts import D26_AT, E26_AT, shear_amplitude
from contactres.measurements._spectra_table import read_spectra

F = np.linspace(14.99e6, 15.01e6, 41)


def _circuit(f, r=200.0, fr=15.0e6, q=2e4, c0=5e-12):
    """Admittance of a series R-L-C in parallel with C0 (written here, independently)."""
    w = 2 * np.pi * f
    L = q * r / (2 * np.pi * fr)
    C = 1 / ((2 * np.pi * fr) ** 2 * L)
    return 1 / (r + 1j * w * L + 1 / (1j * w * C)) + 1j * w * c0


def _tidy(tmp_path, rows):
    path = tmp_path / "spectra.csv"
    pd.DataFrame(rows).to_csv(path, index=False)
    return path


def test_tidy_table_reads_and_sorts(tmp_path):
    y = _circuit(F)
    rows = []
    for sid, ref in (("ref", True), ("s1", False)):
        for f, v in zip(F[::-1], y[::-1], strict=True):  # written in falling frequency
            rows.append(
                {"spectrum": sid, "frequency_Hz": f, "G_S": v.real, "B_S": v.imag,
                 "reference": ref, "overtone": 3, "drive_voltage_V": 0.5,
                 "sweep": "" if ref else "A", "normal_force_N": "" if ref else 2e-3}
            )  # fmt: skip
    t = read_spectra(_tidy(tmp_path, rows))
    assert list(t.spectra["spectrum"]) == ["ref", "s1"]
    assert list(t.spectra["reference"]) == [True, False]
    assert np.all(np.diff(t.points[t.points.spectrum == "s1"]["frequency_Hz"]) > 0)
    assert t.spectra["n_points"].tolist() == [41, 41]


def _folder(tmp_path, files, index_rows):
    folder = tmp_path / "run"
    folder.mkdir()
    for name, text in files.items():
        (folder / name).write_text(text)
    pd.DataFrame(index_rows).to_csv(folder / "index.csv", index=False)
    return folder


@pytest.mark.parametrize("fmt", ["RI", "MA", "DB"])
def test_touchstone_s11_gives_the_circuit_admittance(tmp_path, fmt):
    z0 = 50.0
    y = _circuit(F)
    s = (1 - z0 * y) / (1 + z0 * y)  # S11 of an admittance y against z0
    lines = [f"! test\n# MHz S {fmt} R {z0:g}"]
    for f, v in zip(F, s, strict=True):
        if fmt == "RI":
            a, b = v.real, v.imag
        elif fmt == "MA":
            a, b = abs(v), math.degrees(cmath.phase(v))
        else:
            a, b = 20 * math.log10(abs(v)), math.degrees(cmath.phase(v))
        lines.append(f"{f / 1e6:.9f} {a:.15g} {b:.15g}")
    folder = _folder(
        tmp_path,
        {"a.s1p": "\n".join(lines)},
        [{"file": "a.s1p", "reference": "yes", "overtone": 3}],
    )
    t = read_spectra(folder)
    got = t.points["G_S"].to_numpy() + 1j * t.points["B_S"].to_numpy()
    assert np.allclose(got, y, rtol=1e-9, atol=1e-12 * np.max(abs(y)))
    assert t.spectra["spectrum"].tolist() == ["a"]


@pytest.mark.parametrize("layout", ["G/B", "Y-RI", "S11-RI", "Y-MA"])
def test_delimited_layouts(tmp_path, layout):
    y = _circuit(F)
    s = (1 - 50 * y) / (1 + 50 * y)
    cols = {
        "G/B": {"G_S": y.real, "B_S": y.imag},
        "Y-RI": {"Y_re_S": y.real, "Y_im_S": y.imag},
        "S11-RI": {"S11_re": s.real, "S11_im": s.imag},
        "Y-MA": {"Y_mag_S": abs(y), "Y_phase_deg": np.degrees(np.angle(y))},
    }[layout]
    text = pd.DataFrame({"frequency_Hz": F, **cols}).to_csv(index=False, float_format="%.15g")
    folder = _folder(tmp_path, {"b.csv": text}, [{"file": "b.csv", "spectrum": "s7"}])
    t = read_spectra(folder)
    got = t.points["G_S"].to_numpy() + 1j * t.points["B_S"].to_numpy()
    assert np.allclose(got, y, rtol=1e-9, atol=1e-12 * np.max(abs(y)))
    assert t.spectra["spectrum"].tolist() == ["s7"]


@pytest.mark.parametrize(
    "change, words",
    [
        ({"frequency_Hz": "abc"}, ["line 3", "frequency_Hz", "'abc'"]),
        ({"G_S": "x1"}, ["line 3", "G_S", "'x1'"]),
        ({"frequency_Hz": "-1"}, ["line 3", "frequency_Hz", "> 0"]),
        ({"overtone": "2"}, ["overtone", "odd"]),
        ({"reference": "maybe"}, ["reference", "true/false"]),
        ({"drive_voltage_V": "0"}, ["drive_voltage_V", "> 0"]),
    ],
)
def test_bad_cells_name_line_column_value(tmp_path, change, words):
    rows = [
        {"spectrum": "s", "frequency_Hz": f, "G_S": 1e-3, "B_S": 0.0, "overtone": 3,
         "reference": "false", "drive_voltage_V": 1.0}
        for f in F[:5]
    ]  # fmt: skip
    rows[1].update(change)
    if "overtone" in change or "reference" in change or "drive_voltage_V" in change:
        for r in rows:
            r.update(change)
    path = _tidy(tmp_path, rows)
    with pytest.raises(ValueError) as info:
        read_spectra(path)
    msg = str(info.value)
    assert "\n" not in msg and str(path) in msg
    for w in words:
        assert w in msg, msg


def test_other_bad_inputs(tmp_path):
    path = _tidy(tmp_path, [{"spectrum": "s", "frequency_Hz": 1e6, "G_S": 1.0}] * 2)
    with pytest.raises(ValueError, match="appears twice"):
        read_spectra(path)
    with pytest.raises(ValueError, match="missing column"):
        read_spectra(_tidy(tmp_path, [{"spectrum": "s", "f": 1.0}]))
    folder = tmp_path / "empty"
    folder.mkdir()
    with pytest.raises(ValueError, match=r"index\.csv"):
        read_spectra(folder)
    with pytest.raises(FileNotFoundError):
        read_spectra(tmp_path / "nothing.csv")


# ------------------------------------------------------------------ the amplitude
def _plate_amplitude(f, n, q, voltage, d=None):
    """|u(0)| of an AT-cut plate (c66, ρ, e26) with loss c66 (1 + i/Q), driven by U at f: the
    exact solution of ρω²u + c̃ u'' = 0 with the traction-free faces c̃u' − e26 U/d = 0."""
    rho, c = 2648.0, 28.98e9
    if d is None:
        d = n * math.sqrt(c / rho) / (2 * 15e6)  # overtone n near 15 MHz
    ct = c * (1 + 1j / q)
    k = 2 * math.pi * f * np.sqrt(rho / ct)
    field = E26_AT * voltage / d
    b = field / (ct * k)
    a = b * (np.cos(k * d) - 1) / np.sin(k * d)
    return np.abs(a), d


@pytest.mark.parametrize("n", [1, 3, 5])
def test_amplitude_formula_matches_the_exact_plate(n):
    q, voltage = 5e4, 0.3
    f0 = 15e6 * n / n  # the plate is cut so that overtone n lies at 15 MHz
    f = f0 * (1 + np.linspace(-3, 3, 20001) / q)
    amp, _ = _plate_amplitude(f, n, q, voltage)
    exact = amp.max()
    # The plate's own d26 = e26/c66 (the package's default is the literature's 3.1 pm/V).
    assert exact == pytest.approx(shear_amplitude(voltage, n, q, E26_AT / 28.98e9), rel=1e-3)
    assert D26_AT / (E26_AT / 28.98e9) == pytest.approx(0.93, abs=0.01)


def test_a_layout_needs_both_of_its_columns(tmp_path):
    y = _circuit(F)
    text = pd.DataFrame({"frequency_Hz": F, "Y_re_S": y.real}).to_csv(index=False)
    folder = _folder(tmp_path, {"c.csv": text}, [{"file": "c.csv"}])
    with pytest.raises(ValueError, match="needs both columns"):
        read_spectra(folder)


def test_touchstone_y_is_normalised_to_r(tmp_path):
    """Touchstone 1 stores y = Y R: a .y1p with R 50 gives back Y."""
    y = _circuit(F)
    lines = ["# MHz Y RI R 50"] + [
        f"{f / 1e6:.9f} {v.real * 50:.15g} {v.imag * 50:.15g}" for f, v in zip(F, y, strict=True)
    ]
    folder = _folder(tmp_path, {"d.y1p": "\n".join(lines)}, [{"file": "d.y1p"}])
    t = read_spectra(folder)
    got = t.points["G_S"].to_numpy() + 1j * t.points["B_S"].to_numpy()
    assert np.allclose(got, y, rtol=1e-9, atol=1e-12 * np.max(abs(y)))


def _skrf_two_port(tmp_path, y_params, name):
    """A two-port .s2p of the Y parameters ``y_params`` (F, 2, 2), converted to S and written
    by scikit-rf (a peer: its y2s and Touchstone writer, not contactres's formulas)."""
    skrf = pytest.importorskip("skrf", reason="scikit-rf (the peers extra) is not installed")
    net = skrf.Network(
        frequency=skrf.Frequency.from_f(F, unit="Hz"), s=skrf.network.y2s(y_params, z0=50.0)
    )
    net.write_touchstone(str(tmp_path / name), form="ri")
    return tmp_path / f"{name}.s2p"


@pytest.mark.parametrize("parameter", ["S11", "S22", "S21"])
def test_two_port_touchstone_written_by_scikit_rf_gives_the_crystal(tmp_path, parameter):
    """The crystal as a shunt on port 1 or port 2 (reflection), or in series between the ports
    (transmission): Y parameters [[y, 0], [0, 0]], [[0, 0], [0, y]] or [[y, −y], [−y, y]]
    (Pozar, Table 4.2), converted to S and written by scikit-rf; read back, the admittance is
    the circuit's."""
    y = _circuit(F)
    params = np.zeros((F.size, 2, 2), dtype=complex)
    if parameter == "S11":
        params[:, 0, 0] = y
    elif parameter == "S22":
        params[:, 1, 1] = y
    else:
        params[:] = y[:, None, None] * np.array([[1, -1], [-1, 1]])
    path = _skrf_two_port(tmp_path, params, "crystal")
    folder = tmp_path / "run"
    folder.mkdir()
    path.rename(folder / path.name)
    pd.DataFrame([{"file": path.name, "overtone": 3}]).to_csv(folder / "index.csv", index=False)
    t = read_spectra(folder, two_port=parameter)
    got = t.points["G_S"].to_numpy() + 1j * t.points["B_S"].to_numpy()
    assert np.allclose(got, y, rtol=1e-8, atol=1e-10 * np.max(abs(y)))


def test_two_port_file_needs_its_parameter_and_skips_noise_data(tmp_path):
    y = _circuit(F[:3])
    s11 = (1 - 50 * y) / (1 + 50 * y)
    lines = ["# Hz S RI R 50"] + [
        f"{f:.6f} {v.real:.15g} {v.imag:.15g} 0 0 0 0 0 0" for f, v in zip(F[:3], s11, strict=True)
    ]
    noise = ["! noise parameters", f"{F[0]:.6f} 1.5 0.3 20 0.2"]
    folder = _folder(tmp_path, {"a.s2p": "\n".join(lines + noise)}, [{"file": "a.s2p"}])
    with pytest.raises(
        ValueError, match=r"a\.s2p: a two-port Touchstone file: give the crystal's S parameter"
    ):
        read_spectra(folder)
    t = read_spectra(folder, two_port="S11")
    assert t.points["frequency_Hz"].to_numpy() == pytest.approx(F[:3], rel=1e-12)
    with pytest.raises(ValueError, match="two-port parameter must be one of S11, S22, S21"):
        read_spectra(folder, two_port="S12")
    (folder / "a.s2p").write_text("\n".join(["# Hz Y RI R 50", *lines[1:]]))
    with pytest.raises(ValueError, match="two-port files of S parameters"):
        read_spectra(folder, two_port="S11")
