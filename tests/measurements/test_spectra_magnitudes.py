"""Spectra whose magnitudes are not what their labels say are refused, in one line (issue 27,
points 5 and 14): frequencies in another unit than Hz, Touchstone option lines the
specification does not define, a spectrum far from its references, files outside the folder of
the index; and a reference at 0 N (no contact) is accepted.

The spectra are written here from a series R-L-C in parallel with C0 (the motional branch of a
quartz and its static capacitance), independent of the fit.
"""

import warnings

import numpy as np
import pandas as pd
import pytest

from contactres.measurements import read_spectra_sweeps
from contactres.measurements._spectra_table import read_spectra

F_R, Q, N = 15.0e6, 2.0e4, 3  # resonance (Hz), quality factor, overtone: Γ = 375 Hz
F = F_R + np.linspace(-2000.0, 2000.0, 81)


def _circuit(f, fr=F_R, r=200.0, q=Q, c0=5e-12):
    w = 2 * np.pi * f
    inductance = q * r / (2 * np.pi * fr)
    capacitance = 1 / ((2 * np.pi * fr) ** 2 * inductance)
    return 1 / (r + 1j * w * inductance + 1 / (1j * w * capacitance)) + 1j * w * c0


def _s11(f, fr=F_R, z0=50.0):
    y = _circuit(f, fr)
    return (1 - z0 * y) / (1 + z0 * y)


def _touchstone(option, f=F, fr=F_R, scale=1.0):
    lines = [] if option is None else [option]
    lines += [
        f"{x / scale:.12g} {s.real:.15g} {s.imag:.15g}" for x, s in zip(f, _s11(f, fr), strict=True)
    ]
    return "\n".join(lines) + "\n"


def _folder(tmp_path, files, rows):
    folder = tmp_path / "run"
    folder.mkdir()
    for name, text in files.items():
        (folder / name).write_text(text)
    pd.DataFrame(rows).to_csv(folder / "index.csv", index=False)
    return folder


def _index(measured="m.s1p", reference="ref.s1p", **labels):
    common = {"overtone": N, "drive_voltage_V": 0.1, **labels}
    return [
        {"file": reference, "reference": "yes", "sweep": "", "normal_force_N": "", **common},
        {"file": measured, "reference": "no", "sweep": "A", "normal_force_N": 1e-3, **common},
    ]


def _one_line(info, *words):
    text = str(info.value)
    assert len(text.splitlines()) == 1, text
    for w in words:
        assert w in text, text


def test_a_frequency_column_in_mhz_is_refused(tmp_path):
    rows = []
    for sid, ref, fr in (("ref", True, F_R), ("s1", False, F_R + 40.0)):
        y = _circuit(F, fr)
        rows += [{"spectrum": sid, "frequency_Hz": f / 1e6, "G_S": v.real, "B_S": v.imag,
                  "reference": ref, "overtone": N, "drive_voltage_V": 0.1,
                  "sweep": "" if ref else "A", "normal_force_N": "" if ref else 1e-3}
                 for f, v in zip(F, y, strict=True)]  # fmt: skip
    path = tmp_path / "mhz.csv"
    pd.DataFrame(rows).to_csv(path, index=False, float_format="%.12g")
    with pytest.raises(ValueError) as info:
        read_spectra_sweeps(path, validate=False)
    _one_line(info, "mhz.csv", "spectrum ref", "overtone 3", "14.998 to 15.002 Hz",
              "3e+06 to 1.5e+09 Hz")  # fmt: skip


@pytest.mark.parametrize(
    "option, scale, words",
    [
        ("# MHz S RI R 50", 1.0, ["m.s1p", "1.4998e+13 to 1.5002e+13 Hz", "overtone 3"]),
        (None, 1.0, ["m.s1p, line 1", "data before the option line"]),
        ("# Hertz S RI R 50", 1.0, ["m.s1p, line 1", "unknown word 'Hertz'"]),
        ("# Hz S XX R 50", 1.0, ["m.s1p, line 1", "unknown word 'XX'", "RI, MA or DB"]),
        ("# Hz S RI R abc", 1.0, ["m.s1p, line 1", "R 'abc'", "reference impedance"]),
        ("# Hz S RI R 50\n# kHz S RI R 50", 1.0, ["m.s1p, line 2", "second option line"]),
        ("# Hz S RI MA R 50", 1.0, ["m.s1p, line 1", "format is given twice"]),
        ("# Hz H RI R 50", 1.0, ["m.s1p, line 1", "two-port hybrid"]),
    ],
)
def test_touchstone_option_lines_are_checked(tmp_path, option, scale, words):
    files = {"ref.s1p": _touchstone("# Hz S RI R 50"),
             "m.s1p": _touchstone(option, fr=F_R + 40.0, scale=scale)}  # fmt: skip
    folder = _folder(tmp_path, files, _index())
    with pytest.raises(ValueError) as info:
        read_spectra_sweeps(folder, validate=False)
    _one_line(info, *words)


def test_good_option_lines_in_any_case_and_unit(tmp_path):
    files = {"ref.s1p": _touchstone("# hz s ri r 50"),
             "m.s1p": _touchstone("# kHz S RI R 50", fr=F_R + 40.0, scale=1e3)}  # fmt: skip
    _, rows, _fits, left_out = read_spectra_sweeps(_folder(tmp_path, files, _index()),
                                                  validate=False)  # fmt: skip
    assert not left_out
    assert rows["df_Hz"].iloc[0] == pytest.approx(40.0, abs=0.5)


def test_a_spectrum_far_from_its_references_is_refused(tmp_path):
    """Overtone 5 (25 MHz) labelled 3: f/n is a QCM fundamental, but 10 MHz from the
    references of overtone 3."""
    f5 = 25e6 + np.linspace(-2000.0, 2000.0, 81)
    files = {"ref.s1p": _touchstone("# Hz S RI R 50"),
             "m.s1p": _touchstone("# Hz S RI R 50", f=f5, fr=25e6)}  # fmt: skip
    with pytest.raises(ValueError) as info:
        read_spectra_sweeps(_folder(tmp_path, files, _index()), validate=False)
    _one_line(info, "m.s1p", "overtone 3", "resonates at 2500", "f_ref ± 10 Γ_ref")


def test_a_fundamental_column_checks_the_overtone(tmp_path):
    files = {"ref.s1p": _touchstone("# Hz S RI R 50"),
             "m.s1p": _touchstone("# Hz S RI R 50", fr=F_R + 40.0)}  # fmt: skip
    folder = _folder(tmp_path, files, _index(fundamental_Hz=9e6))
    with pytest.raises(ValueError) as info:
        read_spectra_sweeps(folder, validate=False)
    _one_line(info, "ref.s1p", "overtone 3 of the fundamental 9e+06 Hz", "2.565e+07 to 2.835e+07")


def test_a_reference_at_zero_newtons_is_accepted(tmp_path):
    rows = _index()
    rows[0]["normal_force_N"] = 0
    files = {"ref.s1p": _touchstone("# Hz S RI R 50"),
             "m.s1p": _touchstone("# Hz S RI R 50", fr=F_R + 40.0)}  # fmt: skip
    _, out, _, _ = read_spectra_sweeps(_folder(tmp_path, files, rows), validate=False)
    assert out["normal_force_N"].tolist() == [1e-3]
    # A measured spectrum at 0 N is no contact: refused, naming the spectrum.
    rows[1]["normal_force_N"] = 0
    (tmp_path / "b").mkdir()
    folder = _folder(tmp_path / "b", files, rows)
    with pytest.raises(ValueError) as info:
        read_spectra_sweeps(folder, validate=False)
    _one_line(info, "spectrum m", "0 N", "reference")


def test_a_short_circuit_point_is_flagged_without_a_numpy_warning(tmp_path):
    text = _touchstone("# Hz S RI R 50", fr=F_R + 40.0).splitlines()
    text[5] = f"{F[4]:.12g} -1 0"  # S11 = -1: Y infinite
    files = {"ref.s1p": _touchstone("# Hz S RI R 50"), "m.s1p": "\n".join(text) + "\n",
             "m2.s1p": _touchstone("# Hz S RI R 50", fr=F_R + 40.0)}  # fmt: skip
    rows = [*_index(), {**_index(measured="m2.s1p")[1]}]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _, out, _fits, left_out = read_spectra_sweeps(_folder(tmp_path, files, rows),
                                                     validate=False)  # fmt: skip
    assert len(left_out) == 1 and "spectrum m " in left_out[0] and "bad-values" in left_out[0]
    assert out["spectrum"].tolist() == ["m2"]


@pytest.mark.parametrize("name", ["../secret.s1p", "ABSOLUTE", "link.s1p"])
def test_the_index_names_files_of_its_own_folder_only(tmp_path, name):
    secret = tmp_path / "secret.s1p"
    secret.write_text("# Hz S RI R 50\nprivate words here\n")
    rows = _index()
    rows[1]["file"] = str(secret) if name == "ABSOLUTE" else name
    files = {"ref.s1p": _touchstone("# Hz S RI R 50")}
    folder = _folder(tmp_path, files, rows)
    if name == "link.s1p":
        (folder / name).symlink_to(secret)
    with pytest.raises(ValueError) as info:
        read_spectra(folder)
    _one_line(info, "index.csv, line 3", "outside the folder")
    assert "private" not in str(info.value)


def test_an_admittance_beyond_any_measurement_is_flagged_not_an_internal_error(tmp_path):
    """G of 1e300 S made the fit's residuals overflow: scipy's ValueError reached the user."""
    rows = []
    for sid, ref, fr, scale in (("ref", True, F_R, 1.0), ("s1", False, F_R + 40.0, 1.0),
                                ("s2", False, F_R + 40.0, 1e300)):  # fmt: skip
        y = _circuit(F, fr) * scale
        rows += [{"spectrum": sid, "frequency_Hz": f, "G_S": v.real, "B_S": v.imag,
                  "reference": ref, "overtone": N, "drive_voltage_V": 0.1,
                  "sweep": "" if ref else "A", "normal_force_N": "" if ref else 1e-3}
                 for f, v in zip(F, y, strict=True)]  # fmt: skip
    path = tmp_path / "huge.csv"
    pd.DataFrame(rows).to_csv(path, index=False, float_format="%.15g")
    _, out, _fits, left_out = read_spectra_sweeps(path, validate=False)
    assert out["spectrum"].tolist() == ["s1"]
    assert len(left_out) == 1 and "spectrum s2" in left_out[0] and "bad-values" in left_out[0]
