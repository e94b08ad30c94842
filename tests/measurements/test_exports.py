"""Reader plug-ins for QCM-D instrument exports (contactres.measurements.readers.exports).

Every layout is written here from known shifts (Δf_n, ΔΓ_n per overtone), read back with its
conventions applied (Δf/n -> Δf, D -> Γ = D f_n / 2 with the D scale, time unit, baseline),
and compared with the known values. Detection must pick each layout's reader and no other, and
none for the package's tidy sweep table; a convention the file does not tell gives one line.
"""

from __future__ import annotations

import json
from importlib import resources

import numpy as np
import pytest

from contactres.measurements.readers.exports import (
    EXPORT_READERS,
    ExportTable,
    ExportWarning,
    export_reader,
    pick_export_reader,
    read_export,
)

F_F = 4.95e6  # fundamental, Hz
T = np.arange(6) * 2.0  # s
OVERTONES = (3, 5, 7)
MULTI = (1, 3, 5, 7, 9)  # the five overtones of an openQCM Next multiscan log


def true_df(n):
    """Δf_n (Hz, not divided by n), zero at t = 0."""
    return -n * (0.4 * T + 0.01 * T**2)


def true_dg(n):
    """ΔΓ_n (Hz, half-bandwidth), zero at t = 0."""
    return n * (0.05 * T + 0.002 * T**2)


def gamma0(n):
    """Γ_n of the unloaded crystal (Hz): D ~ 1e-5 at the fundamental."""
    return 25.0 + 3.0 * n


def dD(n):
    """The D shift that gives ΔΓ_n (first order): ΔD = 2 ΔΓ / (n f_F)."""
    return 2 * true_dg(n) / (n * F_F)


def write(path, header, rows, sep=",", comma=False):
    def cell(v):
        text = v if isinstance(v, str) else repr(float(v))
        return text.replace(".", ",") if comma and not isinstance(v, str) else text

    lines = [sep.join(header)] + [sep.join(cell(v) for v in row) for row in rows]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def qsense_a(tmp_path, name="qsense_a.txt"):
    """QSense text export, layout A: two sensors, Δf/n, D in ppm, time in minutes, decimal comma."""
    header = ["Time_1"] + [f"{c}_1:{n}" for n in OVERTONES for c in "FD"]
    header += ["Time_2", "F_2:3", "D_2:3", "Meas. Temp. Time", "Tact"]
    rows = []
    for i, t in enumerate(T):
        row = [t / 60]
        for n in OVERTONES:
            row += [true_df(n)[i] / n, dD(n)[i] * 1e6]
        rows.append([*row, t / 60, 1.0, 0.5, t, 22.0])
    return write(tmp_path / name, header, rows, sep=";", comma=True)


def qsense_b(tmp_path):
    """QSense export, layout B: absolute f_n in Hz, absolute D in ppm, time in s (tab)."""
    pairs = (("f", "Hz"), ("D", "ppm"))
    header = ["Time_1 [s]"] + [f"{c}{n}_1 [{u}]" for n in OVERTONES for c, u in pairs]
    rows = []
    for i, t in enumerate(T):
        row = [t]
        for n in OVERTONES:
            f = n * F_F + true_df(n)[i]
            row += [f, 2 * (gamma0(n) + true_dg(n)[i]) / f * 1e6]
        rows.append(row)
    return write(tmp_path / "qsense_b.txt", header, rows, sep="\t")


def awsensors(tmp_path):
    """AWSensors: Time_(s), Delta_F/n_n=N_(Hz), Delta_D_n=N_() with D in ppm (comma)."""
    pairs = (("F/n", "Hz"), ("D", ""))
    header = ["Time_(s)"] + [f"Delta_{q}_n={n}_({u})" for n in OVERTONES for q, u in pairs]
    rows = [[t] + [v for n in OVERTONES for v in (true_df(n)[i] / n, dD(n)[i] * 1e6)]
            for i, t in enumerate(T)]  # fmt: skip
    return write(tmp_path / "aws.csv", header, rows)


def qcmi(tmp_path):
    """QCM-I: tab-separated, absolute f_n and D (plain), FWHM and Variation columns, repeated
    flow and temperature columns (as in the sample export of pyQCM-BraTaDio)."""
    header = ["Channel A QCM Time [sec]"]
    for n in (1, *OVERTONES):
        label = "Fundamental" if n == 1 else f"{n}."
        freq = "Fundamental Frequency" if n == 1 else f"{n}. Overtone"
        header += [f"Channel A {label} Dissipation  [ ]", "Channel A Flow [ul/min]",
                   f"Channel A {freq} [Hz]", f"Channel A {label} FWHM [Hz]",
                   "Channel A Temp [Celsius]", f"Channel A {freq} Variation [Hz]"]  # fmt: skip
    rows = []
    for i, t in enumerate(T):
        row = [t]
        for n in (1, *OVERTONES):
            df = true_df(n)[i]
            f, g = n * F_F + df, gamma0(n) + true_dg(n)[i]
            row += [2 * g / f, 0, f, 2 * g, 25.0, df]
        rows.append(row)
    return write(tmp_path / "qcmi.txt", header, rows, sep="\t")


def openqcm_multi(tmp_path):
    """openQCM Next multiscan log: Frequency_i (n = 2i + 1, i = 0-4), D in ppm."""
    header = ["Date", "Time", "Relative_time", "Temperature"]
    for i in range(5):
        header += [f"Frequency_{i}", f"Dissipation_{i}"]
    rows = []
    for j, t in enumerate(T):
        row = ["2026-01-01", f"12:00:{j:02d}", t, 24.8]
        for n in MULTI:
            f = n * F_F + true_df(n)[j]
            row += [f, 2 * (gamma0(n) + true_dg(n)[j]) / f * 1e6]
        rows.append(row)
    return write(tmp_path / "multi.csv", header, rows)


def openqcm_single(tmp_path):
    """openQCM Q-1 log: one overtone (5), D as a plain number."""
    header = ["Date", "Time", "Relative_time", "Temperature", "Resonance_Frequency", "Dissipation"]
    rows = []
    for j, t in enumerate(T):
        f = 5 * F_F + true_df(5)[j]
        rows.append(
            ["2026-01-01", f"12:00:{j:02d}", t, 24.8, f, 2 * (gamma0(5) + true_dg(5)[j]) / f]
        )
    return write(tmp_path / "F0.csv", header, rows)


# (maker, reader, conventions, overtones, ΔΓ exact?)  ΔΓ from a D shift is first order in Δf/f.
CASES = {
    "qsense-A": (qsense_a, "qsense", dict(time_unit="min", df_divided_by_n=True,
                 dissipation_scale=1e-6, fundamental=F_F, channel="1"), OVERTONES),
    "qsense-B": (qsense_b, "qsense", dict(baseline="first"), OVERTONES),
    "awsensors": (awsensors, "awsensors", dict(dissipation_scale=1e-6, fundamental=F_F),
                  OVERTONES),
    "qcmi": (qcmi, "qcmi", dict(baseline="first"), (1, *OVERTONES)),
    "openqcm-multi": (openqcm_multi, "openqcm", dict(dissipation_scale=1e-6, baseline="first"),
                      MULTI),
    "openqcm-single": (openqcm_single, "openqcm", dict(dissipation_scale=1, baseline="first",
                       overtone=5), (5,)),
}  # fmt: skip


@pytest.mark.parametrize("case", CASES)
def test_each_layout_reads_back_the_known_shifts(tmp_path, case):
    maker, name, conventions, overtones = CASES[case]
    path = maker(tmp_path)
    table = read_export(path, **conventions)
    assert isinstance(table, ExportTable)
    assert list(table.data.columns) == ["time_s", "overtone", "df_Hz", "dgamma_Hz"]
    assert table.conventions["reader"] == name
    assert table.conventions["source_file"] == str(path)
    assert table.conventions["overtones"] == list(overtones)
    for n in overtones:
        part = table.data[table.data.overtone == n]
        np.testing.assert_allclose(part.time_s, T, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(part.df_Hz, true_df(n), rtol=1e-9, atol=1e-6)
        np.testing.assert_allclose(part.dgamma_Hz, true_dg(n), rtol=1e-9, atol=1e-6)
    json.dumps(dict(table.conventions))  # every convention is recorded in JSON-ready form


def test_conventions_record_what_was_read_and_done(tmp_path):
    a = read_export(qsense_a(tmp_path), **CASES["qsense-A"][2]).conventions
    assert a["df_as_read"] == "divided by n (Δf_n/n)"
    assert a["dissipation_as_read"] == "D" and a["dissipation_scale"] == 1e-6
    assert a["time_unit_as_read"] == "min" and a["channel"] == "1"
    assert a["baseline"].startswith("as exported") and a["fundamental_source"] == "given"
    assert a["given_by_user"] == sorted(CASES["qsense-A"][2])
    b = read_export(qsense_b(tmp_path), baseline="first").conventions
    assert b["frequency_as_read"] == "absolute f_n" and b["dissipation_scale"] == 1e-6
    assert b["baseline"] == "the first point of each overtone"
    assert b["reference_frequency_Hz"]["3"] == pytest.approx(3 * F_F)
    assert b["reference_gamma_Hz"]["5"] == pytest.approx(gamma0(5))
    assert b["fundamental_Hz"] == pytest.approx(F_F) and "from the file" in b["fundamental_source"]


def test_gamma_is_d_times_f_over_two_by_hand(tmp_path):
    """One value by hand: Γ = D f / 2 with the D scale, against the file's own FWHM (QCM-I)."""
    # the first two rows of the QCM-I sample export in pyQCM-BraTaDio (offset_data/...STA.txt)
    path = write(
        tmp_path / "sample.txt",
        ["Channel A QCM Time [sec]", "Channel A Fundamental Dissipation [ ]",
         "Channel A Fundamental Frequency [Hz]", "Channel A Fundamental FWHM [Hz]"],
        [[5.0501468, 1.31161656206037e-05, 4961272.01729206, 65.0728654676696],
         [5.045002, 1.33234290197324e-05, 4961264.47245154, 66.1010550468283]],
        sep="\t",
    )  # fmt: skip
    with pytest.warns(ExportWarning, match=r"out of time order .* line 3 \(t = 5.045 s\)"):
        t = read_export(path, baseline="first").data
    # The sample's second row is 5 ms earlier than its first: the reference (baseline "first")
    # is the point of the earliest time, the second row (issue 27, point 3); the differences
    # between the rows do not depend on it.
    assert t.df_Hz.iloc[1] == 0 and t.dgamma_Hz.iloc[1] == 0
    assert t.df_Hz.iloc[0] == pytest.approx(4961272.01729206 - 4961264.47245154, rel=1e-12)
    assert t.dgamma_Hz.iloc[0] == pytest.approx((65.0728654676696 - 66.1010550468283) / 2, rel=1e-5)


def test_real_qsense_rows_decimal_comma(tmp_path):
    """The first rows of a real QSense export (safyre8/QCM-D_data_processing, S1_...slb.txt)."""
    path = tmp_path / "S1.txt"
    path.write_text(
        "Time_1;F_1:5;D_1:5;F_1:7;D_1:7;Meas. Temp. Time;Tact\n"
        "0,0955409351736307;4,60659066447988E-10;0;-4,07453626394272E-10;0;"
        "-0,0367393270134926;22,0311783160223\n"
        "2,27098176069558;-0,328020308450959;-0,0392417522828907;-0,300130797691509;"
        "0,190391210680261;0,822157015092671;22,0288766386672\n",
        encoding="utf-8",
    )
    t = read_export(path, time_unit="s", df_divided_by_n=True, dissipation_scale=1e-6,
                    fundamental=4.95e6).data  # fmt: skip
    row = t[(t.overtone == 7)].iloc[1]
    assert row.time_s == pytest.approx(2.27098176069558)
    assert row.df_Hz == pytest.approx(7 * -0.300130797691509, rel=1e-12)
    assert row.dgamma_Hz == pytest.approx(0.190391210680261e-6 * 7 * 4.95e6 / 2, rel=1e-12)


# ------------------------------------------------------------------ detection
MAKERS = {
    "qsense": (qsense_a, qsense_b),
    "awsensors": (awsensors,),
    "qcmi": (qcmi,),
    "openqcm": (openqcm_multi, openqcm_single),
}


def test_detection_does_not_confuse_the_formats(tmp_path):
    files = {name: [m(tmp_path) for m in makers] for name, makers in MAKERS.items()}
    for name, paths in files.items():
        for path in paths:
            head = path.read_text(encoding="utf-8")[:4096]
            hits = [r.name for r in EXPORT_READERS if r.detect(path, head)]
            assert hits == [name], (path.name, hits)
            assert pick_export_reader(path).name == name


def test_the_tidy_sweep_table_is_no_export():
    sweeps = resources.files("contactres") / "data" / "example_sweeps.csv"
    with resources.as_file(sweeps) as path:
        head = path.read_text(encoding="utf-8")[:4096]
        assert not [r.name for r in EXPORT_READERS if r.detect(path, head)]
        with pytest.raises(ValueError, match="no export reader recognises") as info:
            pick_export_reader(path)
    assert len(str(info.value).splitlines()) == 1


def test_every_reader_declares_itself():
    assert [r.name for r in EXPORT_READERS] == ["qsense", "awsensors", "qcmi", "openqcm"]
    for r in EXPORT_READERS:
        assert r.suffixes and all(s.startswith(".") for s in r.suffixes)
        assert {"time", "frequency", "dissipation", "overtones", "channels"} <= set(r.conventions)
        assert "github.com" in r.source
        assert export_reader(r.name.upper()) is r
    with pytest.raises(ValueError, match="known: qsense, awsensors, qcmi, openqcm"):
        export_reader("biolin")


def test_binary_and_empty_files_are_refused(tmp_path):
    for name, text in (("run.xlsx", "PK"), ("empty.txt", "  \n")):
        (tmp_path / name).write_text(text)
        with pytest.raises(ValueError, match=name):
            read_export(tmp_path / name)


# ------------------------------------------------------------------ missing and wrong choices
def one_line(exc_info, *words):
    text = str(exc_info.value)
    assert len(text.splitlines()) == 1, text
    for w in words:
        assert w in text, text
    return text


@pytest.mark.parametrize(
    "maker, given, missing",
    [
        (qsense_a, dict(channel="1"),
         ["time_unit", "df_divided_by_n", "dissipation_scale", "fundamental"]),
        (qsense_a, dict(time_unit="s", df_divided_by_n=True, dissipation_scale=1e-6,
                        fundamental=F_F), ["channel", "1, 2"]),
        (qsense_b, {}, ["baseline", "--baseline"]),
        (awsensors, dict(fundamental=F_F), ["dissipation_scale", "--dissipation-scale"]),
        (awsensors, dict(dissipation_scale=1e-6), ["fundamental", "--fundamental"]),
        (qcmi, {}, ["baseline"]),
        (openqcm_multi, dict(baseline="first"), ["dissipation_scale"]),
        (openqcm_single, dict(baseline="first", dissipation_scale=1), ["overtone", "--overtone"]),
    ],
)  # fmt: skip
def test_a_convention_the_file_does_not_tell_is_asked_for(tmp_path, maker, given, missing):
    path = maker(tmp_path)
    with pytest.raises(ValueError) as info:
        read_export(path, **given)
    one_line(info, str(path), *missing)


@pytest.mark.parametrize(
    "maker, given, words",
    [
        (awsensors, dict(dissipation_scale=1e-6, fundamental=F_F, df_divided_by_n=False),
         ["df_divided_by_n=False", "--df-per-overtone", "contradicts"]),
        (qsense_b, dict(baseline="first", dissipation_scale=1), ["dissipation_scale=1",
                                                                   "contradicts", "1e-06"]),
        (qsense_b, dict(baseline="first", df_divided_by_n=True), ["does not apply"]),
        (qsense_b, dict(baseline="as-exported"),
         ["as-exported", "--baseline", "needs a file of shifts"]),
        (qsense_b, dict(baseline="window:100:200"), ["no point of overtone 3", "100 <= t"]),
        (qsense_b, dict(baseline="window:5:1"), ["T0 < T1"]),
        (qsense_b, dict(baseline="first", fundamental=10e6), ["fundamental=1e+07", "disagrees"]),
        (qsense_b, dict(baseline="first", overtone=9),
         ["overtone 9", "--overtone", "is not in the file"]),
        (qsense_b, dict(baseline="first", channel="4"),
         ["channel '4'", "--channel", "is not in the file"]),
        (qsense_b, dict(baseline="first", time_unit="min"),
         ["time_unit='min'", "--time-unit", "contradicts"]),
        (openqcm_single, dict(baseline="first", dissipation_scale=1e-6, overtone=5, channel="A"),
         ["channel", "--channel", "does not apply"]),
        (openqcm_single, dict(baseline="first", dissipation_scale=1e-6, overtone=4),
         ["odd"]),
        (openqcm_multi, dict(baseline="first", dissipation_scale=1), ["no dissipation factor",
                                                                        "1e-6 for ppm"]),
        (openqcm_multi, dict(baseline="first", dissipation_scale=1e-6, sensor=1),
         ["unknown convention", "'sensor'"]),
    ],
)  # fmt: skip
def test_a_wrong_choice_is_one_line(tmp_path, maker, given, words):
    with pytest.raises(ValueError) as info:
        read_export(maker(tmp_path), **given)
    one_line(info, *words)


def test_a_bad_cell_names_file_line_column_value_and_rule(tmp_path):
    path = qsense_a(tmp_path)
    lines = path.read_text().splitlines()
    cells = lines[3].split(";")
    cells[3] = "n/a"
    lines[3] = ";".join(cells)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError) as info:
        read_export(path, **CASES["qsense-A"][2])
    one_line(info, str(path), "line 4", "'F_1:5'", "'n/a'", "is not a finite number")


def test_empty_cells_are_skipped_and_counted(tmp_path):
    path = openqcm_multi(tmp_path)
    lines = path.read_text().splitlines()
    lines[2] = ",".join(lines[2].split(",")[:-2])  # a short row: no 9th overtone there
    path.write_text("\n".join(lines) + "\n")
    with pytest.warns(ExportWarning, match=r"overtone 9: 1 row\(s\) .* \(line\(s\) 3\)"):
        table = read_export(path, baseline="first", dissipation_scale=1e-6)
    assert table.conventions["empty_cells_skipped"] == 1
    assert (table.data.overtone == 9).sum() == len(T) - 1


def test_frequencies_divided_by_n_are_caught(tmp_path):
    """Absolute f_n/n in a log (all overtones near f_F) are not n f_F: one line, column named."""
    path = openqcm_multi(tmp_path)
    text = path.read_text()
    for n in MULTI[1:]:
        text = text.replace(repr(n * F_F + 0.0), repr(F_F))
    path.write_text(text)
    with pytest.raises(ValueError) as info:
        read_export(path, baseline="first", dissipation_scale=1e-6)
    one_line(info, "not n f_F", "Frequency_")


@pytest.mark.parametrize(("unit", "factor"), [("MHz", 1e6), ("kHz", 1e3)])
@pytest.mark.parametrize(
    "given", [{}, dict(df_divided_by_n=False, fundamental=F_F, baseline="as-exported")]
)
def test_resonance_frequencies_in_mhz_are_no_shifts(tmp_path, unit, factor, given):
    """f_n typed in MHz (14.85 for n f_F = 3 x 4.95 MHz) sit below the absolute threshold and
    passed for shifts of a few Hz (issue 27: κ of 5e4 N/m from a QSense export): refused, in
    one line, whatever the options say about shifts."""
    path = qsense_b(tmp_path)
    lines = path.read_text().splitlines()
    rows = []
    for line in lines[1:]:
        cells = line.split("\t")
        for j in range(1, len(cells), 2):  # the f columns, after the time
            cells[j] = repr(float(cells[j]) / factor)
        rows.append("\t".join(cells))
    path.write_text("\n".join([lines[0], *rows]) + "\n")
    with pytest.raises(ValueError) as info:
        read_export(path, **given)
    f0 = f"3 x {F_F / factor:g} {unit}"  # n f_F in the file's unit
    one_line(info, "'f3_1 [Hz]'", f"absolute resonance frequency in {unit}", f0, "in Hz")


@pytest.mark.parametrize(
    "maker, column, sep, given",
    [
        (qsense_b, "f5_1 [Hz]", "\t", dict(baseline="first")),
        (openqcm_multi, "Frequency_1", ",", dict(baseline="first", dissipation_scale=1e-6)),
    ],
)
@pytest.mark.parametrize("factor", [1e293, 10.0, 0.1], ids=["1e300", "extra-digit", "lost-digit"])
def test_a_resonance_frequency_far_from_its_overtone_is_refused(tmp_path, maker, column, sep,
                                                                given, factor):  # fmt: skip
    """One absolute f_n cell far from n f_F (a corrupted cell, an extra or a lost digit) became
    a shift of its own size without a word (issue 27's closing campaign: Δf = 1e300 Hz); it
    is refused, naming line and column. Line 4 is the third row, not the baseline's."""
    path = maker(tmp_path)
    lines = path.read_text().splitlines()
    j = lines[0].split(sep).index(column)
    cells = lines[3].split(sep)
    cells[j] = repr(float(cells[j]) * factor)
    lines[3] = sep.join(cells)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError) as info:
        read_export(path, **given)
    one_line(info, "line 4", repr(column), "no resonance frequency of overtone")


def test_small_positive_shifts_are_still_shifts(tmp_path):
    """Shifts of one sign that start at 0 are shifts, however near n x a few they end."""
    path = awsensors(tmp_path)
    text = path.read_text().replace(",-", ",")  # Δf/n > 0: a film that left the crystal
    path.write_text(text)
    table = read_export(path, dissipation_scale=1e-6, fundamental=F_F)
    assert table.conventions["frequency_as_read"] == "shift"


def test_shifts_and_resonance_frequencies_mixed(tmp_path):
    path = awsensors(tmp_path)
    lines = path.read_text().splitlines()
    cells = lines[2].split(",")
    cells[1] = "4950000.5"
    lines[2] = ",".join(cells)
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError) as info:
        read_export(path, dissipation_scale=1e-6, fundamental=F_F)
    one_line(info, "line 3", "'Delta_F/n_n=3_(Hz)'", "4950000.5", "is no shift")


def test_window_baseline_and_re_zeroed_shifts(tmp_path):
    """A window baseline on a file of shifts removes the mean over the window (recorded)."""
    table = read_export(awsensors(tmp_path), dissipation_scale=1e-6, fundamental=F_F,
                        baseline="window:0:2.5")  # fmt: skip
    part = table.data[table.data.overtone == 3]
    ref = true_df(3)[:2].mean()
    np.testing.assert_allclose(part.df_Hz, true_df(3) - ref, atol=1e-9)
    assert table.conventions["shift_offsets_removed_Hz"]["df"]["3"] == pytest.approx(ref)


def test_read_with_a_named_reader_and_overtone_filter(tmp_path):
    table = read_export(qcmi(tmp_path), "qcmi", baseline="first", overtone=5)
    assert set(table.data.overtone) == {5}
    with pytest.raises(ValueError) as info:
        read_export(qcmi(tmp_path), "awsensors", dissipation_scale=1e-6, fundamental=F_F)
    one_line(info, "no AWSensors columns")


# ------------------------------------------------------------------ nothing dropped silently
# (issue 27, point 3: a repeated header name or an overtone without one of its columns lost
# that overtone without a word; rows out of time order moved the "first" baseline)
def _rename(path, old, new):
    lines = path.read_text().splitlines()
    lines[0] = lines[0].replace(old, new)
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize(
    "maker, old, new, given, words",
    [
        (qsense_a, "F_1:5", "F_1:3", CASES["qsense-A"][2], ["'F_1:3'", "columns 2 and 4"]),
        (qcmi, "Channel A 5. Overtone [Hz]", "Channel A 3. Overtone [Hz]", dict(baseline="first"),
         ["'Channel A 3. Overtone [Hz]'", "columns 10 and 16"]),
        (openqcm_multi, "Dissipation_2", "Dissipation_1",
         dict(baseline="first", dissipation_scale=1e-6), ["'Dissipation_1'", "columns"]),
        (awsensors, "Delta_D_n=5_()", "Delta_D_n=3_()", dict(dissipation_scale=1e-6,
         fundamental=F_F), ["'Delta_D_n=3_()'", "columns 3 and 5"]),
    ],
)  # fmt: skip
def test_a_repeated_header_name_is_an_error_naming_both_columns(tmp_path, maker, old, new,
                                                                given, words):  # fmt: skip
    path = _rename(maker(tmp_path), old, new)
    with pytest.raises(ValueError) as info:
        read_export(path, **given)
    one_line(info, str(path), "twice", *words)


@pytest.mark.parametrize(
    "maker, old, new, given, n, column",
    [
        (qsense_a, "F_1:5", "F_1:5 (old)", CASES["qsense-A"][2], 5, "'D_1:5'"),
        (qsense_a, "D_1:7", "Dx_1:7", CASES["qsense-A"][2], 7, "'F_1:7'"),
        (qcmi, "Channel A 5. Dissipation  [ ]", "Channel A 5. Q [ ]", dict(baseline="first"), 5,
         "'Channel A 5. Overtone [Hz]'"),
        (openqcm_multi, "Frequency_2", "Freq_2", dict(baseline="first", dissipation_scale=1e-6),
         5, "'Dissipation_2'"),
        (awsensors, "Delta_F/n_n=7_(Hz)", "Delta_f7", dict(dissipation_scale=1e-6,
         fundamental=F_F), 7, "'Delta_D_n=7_()'"),
    ],
)  # fmt: skip
def test_an_overtone_without_one_of_its_columns_is_named(tmp_path, maker, old, new, given, n,
                                                         column):  # fmt: skip
    path = _rename(maker(tmp_path), old, new)
    with pytest.warns(ExportWarning) as caught:
        table = read_export(path, **given)
    text = " | ".join(str(w.message) for w in caught)
    assert f"overtone {n} not read" in text and column in text, text
    assert n not in set(table.data.overtone)
    assert any(f"overtone {n} not read" in line for line in table.conventions["left_out"])


def test_rows_and_comment_lines_left_out_are_named(tmp_path):
    path = openqcm_multi(tmp_path)
    lines = path.read_text().splitlines()
    lines[2] = ",".join(lines[2].split(",")[:-2])  # line 3: no 9th overtone
    lines[4] = "# " + lines[4]  # line 5 commented out
    path.write_text("\n".join(lines) + "\n")
    with pytest.warns(ExportWarning) as caught:
        table = read_export(path, baseline="first", dissipation_scale=1e-6)
    text = " | ".join(str(w.message) for w in caught)
    assert "overtone 9: 1 row(s)" in text and "line(s) 3)" in text, text
    assert "1 comment line(s)" in text and "line(s) 5" in text, text
    assert len(table.conventions["left_out"]) == 2


def test_every_over_long_row_is_named(tmp_path):
    path = awsensors(tmp_path)
    lines = path.read_text().splitlines()
    for i in (2, 4, 6):
        lines[i] += ",1.5,2.5"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ValueError) as info:
        read_export(path, dissipation_scale=1e-6, fundamental=F_F)
    one_line(info, "line(s) 3 (9 fields), 5 (9 fields), 7 (9 fields)", "header (line 1, 7 fields)")


def test_qcmi_rows_out_of_time_order_take_the_earliest_as_baseline(tmp_path):
    path = qcmi(tmp_path)
    lines = path.read_text().splitlines()
    body = lines[1:]
    order = [3, 0, 5, 1, 4, 2]  # the t = 0 row is the second row of the file
    path.write_text("\n".join([lines[0], *(body[i] for i in order)]) + "\n")
    with pytest.warns(ExportWarning, match="earliest point, line 3"):
        table = read_export(path, baseline="first")
    for n in (1, *OVERTONES):
        part = table.data[table.data.overtone == n]
        np.testing.assert_allclose(part.time_s, T[order], rtol=1e-12)
        np.testing.assert_allclose(part.df_Hz, true_df(n)[order], rtol=1e-9, atol=1e-6)
        np.testing.assert_allclose(part.dgamma_Hz, true_dg(n)[order], rtol=1e-9, atol=1e-6)
    assert table.conventions["reference_frequency_Hz"]["3"] == pytest.approx(3 * F_F)


# ------------------------------------------------------------------ issue 27, point 12
_ORD = {1: "fundamental", 3: "3rd", 5: "5th", 7: "7th"}


def pyqcm_table(tmp_path, calibrated: bool):
    """A QSense export as pyQCM-BraTaDio's format_file.py rewrites it (Time, fundamental_freq,
    3rd_freq, ..., fundamental_dis, 3rd_dis, ..., Temp_Time, Temp; comma separated). Without
    calibration offsets the values stay QSense's (Δf/n, D in ppm); with them pyQCM writes
    n x F plus the offset (f_n) and D x 1e-6 plus the offset (absolute D, plain)."""
    ns = (1, *OVERTONES)
    columns = {"Time": T}
    for n in ns:
        if calibrated:
            f = n * F_F + true_df(n)
            columns[f"{_ORD[n]}_freq"] = f
        else:
            columns[f"{_ORD[n]}_freq"] = true_df(n) / n
    for n in ns:
        if calibrated:
            f = n * F_F + true_df(n)
            columns[f"{_ORD[n]}_dis"] = 2 * (gamma0(n) + true_dg(n)) / f
        else:
            columns[f"{_ORD[n]}_dis"] = dD(n) * 1e6
    columns["Temp_Time"], columns["Temp"] = T, 22.0
    import pandas as pd

    path = tmp_path / f"Formatted-run{int(calibrated)}.csv"
    pd.DataFrame(columns).to_csv(path, index=False, float_format="%.17g")
    return path


@pytest.mark.parametrize(
    "calibrated, given",
    [
        (False, dict(time_unit="s", df_divided_by_n=True, dissipation_scale=1e-6,
                     fundamental=F_F)),
        (True, dict(time_unit="s", dissipation_scale=1, baseline="first")),
    ],
)  # fmt: skip
def test_the_pyqcm_table_is_read(tmp_path, calibrated, given):
    path = pyqcm_table(tmp_path, calibrated)
    head = path.read_text()[:4096]
    assert [r.name for r in EXPORT_READERS if r.detect(path, head)] == ["qsense"]
    table = read_export(path, **given)
    assert "pyQCM" in table.conventions["layout"]
    assert table.conventions["overtones"] == [1, *OVERTONES]
    for n in (1, *OVERTONES):
        part = table.data[table.data.overtone == n]
        np.testing.assert_allclose(part.df_Hz, true_df(n), rtol=1e-9, atol=1e-6)
        np.testing.assert_allclose(part.dgamma_Hz, true_dg(n), rtol=1e-6, atol=1e-6)


def test_the_pyqcm_table_asks_for_the_units_it_does_not_state(tmp_path):
    path = pyqcm_table(tmp_path, False)
    with pytest.raises(ValueError) as info:
        read_export(path)
    one_line(info, "time_unit", "df_divided_by_n", "dissipation_scale", "fundamental")


def test_awsensors_dimensionless_d_needs_no_scale(tmp_path):
    """``Delta_D_n=3_()`` states a dimensionless D: plain values are read without a scale; ppm
    values under it are caught (a plain ΔD of 1e-3 is no contact's)."""
    pairs = (("F/n", "Hz"), ("D", ""))
    header = ["Time_(s)"] + [f"Delta_{q}_n={n}_({u})" for n in OVERTONES for q, u in pairs]
    rows = [[t] + [v for n in OVERTONES for v in (true_df(n)[i] / n, dD(n)[i])]
            for i, t in enumerate(T)]  # fmt: skip
    table = read_export(write(tmp_path / "plain.csv", header, rows), fundamental=F_F)
    assert table.conventions["dissipation_scale"] == 1
    assert "'()'" in table.conventions["dissipation_scale_source"]
    for n in OVERTONES:
        part = table.data[table.data.overtone == n]
        np.testing.assert_allclose(part.dgamma_Hz, true_dg(n), rtol=1e-9, atol=1e-9)
    with pytest.raises(ValueError) as info:
        read_export(awsensors(tmp_path), fundamental=F_F)  # its D is in ppm
    one_line(info, "line 3", "'Delta_D_n=3_()'", "dissipation_scale=1e-6")


def test_a_line_break_inside_a_quoted_cell_is_one_line(tmp_path):
    """Issue 27, point 15: a CR inside a quoted cell made the rows and their lines disagree (an
    internal error of the export reader)."""
    path = awsensors(tmp_path)
    lines = path.read_text().splitlines()
    lines[0] += ",Note"
    lines[2] += ',"a\rb"'
    path.write_bytes(("\n".join(lines) + "\n").encode())
    with pytest.raises(ValueError) as info:
        read_export(path, dissipation_scale=1e-6, fundamental=F_F)
    one_line(info, str(path), "line 3", "quoted cell runs over a line break")


def test_an_overtone_without_any_bandwidth_is_left_out_by_name_and_the_rest_is_read(tmp_path):
    # A real QCM-I export (pyQCM-BraTaDio's raw_data/qcmi_sample.txt) logs the 13th overtone's
    # frequency but leaves its dissipation and FWHM empty; it used to stop the whole file with
    # "no point ... in the baseline window nan <= t <= nan".
    path = qcmi(tmp_path)
    lines = [line.split("\t") for line in path.read_text().splitlines()]
    empty = [i for i, name in enumerate(lines[0]) if name.startswith("Channel A 7. ")]
    empty = [i for i in empty if "Overtone" not in lines[0][i]]  # keep its frequency
    for row in lines[1:]:
        for i in empty:
            row[i] = ""
    path.write_text("\n".join("\t".join(row) for row in lines) + "\n")
    with pytest.warns(ExportWarning, match=r"overtone 7 left out: no row holds its time"):
        table = read_export(path, baseline="first")
    assert sorted(set(table.data.overtone)) == [1, 3, 5]
    assert table.conventions["overtones"] == [1, 3, 5]
    for n in (1, 3, 5):
        part = table.data[table.data.overtone == n]
        np.testing.assert_allclose(part.df_Hz, true_df(n), rtol=1e-9, atol=1e-6)
