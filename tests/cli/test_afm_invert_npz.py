"""``afm invert`` with numpy archives (.npz) in and out (issue 31, point 5), and the CSV reader's
numbers read whole (no Python strip per cell) with the cells it cannot read still named."""

import numpy as np
import pandas as pd
import pytest
from click.testing import CliRunner

from contactres.cli import main
from contactres.errors import ContactresInputError
from contactres.fileio import write_npz
from contactres.measurements import read_resonance_table
from contactres.measurements.schema import AFM_TABLE
from contactres.normal import hertz
from contactres.resonators import Cantilever, contact_frequencies


def _run(*args):
    return CliRunner().invoke(main, list(args))


def _map(n=40):
    """n pixels of a lever (k_c = 40 N/m, r = 0.95, two modes) on a Hertz contact of
    M_sample = 50 GPa under a 165 GPa tip, R = 50 nm, loads from 2 to 20 nN (a/R <= 0.06);
    a label column."""
    lever = Cantilever((160e3, 1003e3), 40.0)
    load = np.geomspace(2e-9, 2e-8, n)
    e_star = 1 / (1 / 50e9 + 1 / 165e9)
    k_star = 2 * hertz(e_star, 50e-9, load).contact_radius * e_star  # dF/dδ = 2aE*
    f = contact_frequencies(lever, k_star / 40.0, 0.95, modes=(1, 2))
    frame = pd.DataFrame(
        {
            "pixel": np.arange(1, n + 1),
            "label": [f"p{i}, row" for i in range(n)],  # a comma: quoted in the CSV
            "f1_free_Hz": 160e3,
            "f2_free_Hz": 1003e3,
            "k_c_N_per_m": 40.0,
            "tip_position": 0.95,
            "fc1_Hz": f[:, 0],
            "fc2_Hz": f[:, 1],
            "tip_radius_m": 50e-9,
            "load_N": load,
            "M_tip_Pa": 165e9,
        }
    )
    return frame, k_star


def test_npz_in_and_out_give_the_csv_results_as_exact_doubles(tmp_path):
    frame, k_star = _map()
    frame.to_csv(tmp_path / "map.csv", index=False)
    write_npz(tmp_path / "map.npz", frame)
    for source, out in (("map.csv", "a.csv"), ("map.npz", "b.npz"), ("map.npz", "c.csv")):
        r = _run("afm", "invert", str(tmp_path / source), "--out", str(tmp_path / out))
        assert r.exit_code == 0, r.output
    text = pd.read_csv(tmp_path / "a.csv", keep_default_na=False)
    with np.load(tmp_path / "b.npz", allow_pickle=False) as archive:
        binary = {name: archive[name] for name in archive.files}
    assert list(binary) == list(text.columns)
    np.testing.assert_allclose(binary["k_star_N_per_m"], k_star, rtol=1e-8)
    np.testing.assert_allclose(binary["M_sample_Pa"], 50e9, rtol=1e-7)
    for name, values in binary.items():
        if values.dtype.kind == "f":  # the CSV's computed columns hold 10 digits of these
            got = pd.to_numeric(text[name]).to_numpy(dtype=float)
            np.testing.assert_allclose(values, got, rtol=1e-9, atol=0, equal_nan=True)
        else:
            assert values.astype(str).tolist() == text[name].astype(str).tolist(), name
    # The CSV written from the archive is the one written from the CSV, to the byte.
    assert (tmp_path / "c.csv").read_bytes() == (tmp_path / "a.csv").read_bytes()


def test_an_npz_table_is_checked_and_its_rows_named(tmp_path):
    frame, _ = _map(5)
    frame.loc[3, "fc1_Hz"] = np.inf
    write_npz(tmp_path / "bad.npz", frame)
    with pytest.raises(ContactresInputError, match=r"row 4, column 'fc1_Hz'.*not a finite"):
        read_resonance_table(tmp_path / "bad.npz", AFM_TABLE)
    frame, _ = _map(5)
    frame["tip_position"] = np.nan  # not given: solved from the two modes
    write_npz(tmp_path / "gap.npz", frame)
    checked = read_resonance_table(tmp_path / "gap.npz", AFM_TABLE)
    assert checked["tip_position"].isna().all() and checked["fc2_Hz"].notna().all()


@pytest.mark.parametrize(
    "arrays, message",
    [
        ({"fc1_Hz": np.ones(3), "k_c_N_per_m": np.ones(4)}, "one length"),
        ({"fc1_Hz": np.ones((3, 2))}, "one-dimensional"),
        ({"fc1_Hz": np.array([1.0, None], dtype=object)}, "numpy archive"),  # a pickle
        ({"fc1_Hz": np.ones(3, dtype=complex)}, "numbers or text"),
        ({}, "no arrays"),
    ],
)
def test_a_bad_archive_is_refused_in_one_line(tmp_path, arrays, message):
    path = tmp_path / "t.npz"
    np.savez(path, **arrays)  # (allow_pickle: numpy's default, to write the object array)
    with pytest.raises(ContactresInputError, match=message) as info:
        read_resonance_table(path, AFM_TABLE)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_numbers_with_white_space_read_as_written_and_text_is_named(tmp_path):
    """The reader parses each column whole and strips only the cells pandas' parser leaves
    (other white space than ASCII, blanks of spaces); the values are those of the same table
    written without the white space."""
    frame, _ = _map(4)
    clean = tmp_path / "clean.csv"
    frame.to_csv(clean, index=False)
    padded = frame.astype(object)
    padded["fc1_Hz"] = [f" {v!r} " for v in frame["fc1_Hz"]]
    padded["fc2_Hz"] = [f"\u00a0{v!r}\t" for v in frame["fc2_Hz"]]  # no-break space: Python's
    padded["tip_position"] = ["0.95", "   ", "", "\u00a00.95"]  # blanks: not given
    padded.to_csv(tmp_path / "padded.csv", index=False)
    want = read_resonance_table(clean, AFM_TABLE)
    got = read_resonance_table(tmp_path / "padded.csv", AFM_TABLE)
    for name in ("fc1_Hz", "fc2_Hz"):
        np.testing.assert_array_equal(got[name].to_numpy(), want[name].to_numpy())
    np.testing.assert_array_equal(got["tip_position"].to_numpy(), [0.95, np.nan, np.nan, 0.95])
    for cell in ("1_000", "12 kHz", "nan"):
        bad = frame.astype(object)
        bad.loc[2, "fc2_Hz"] = cell
        bad.to_csv(tmp_path / "bad.csv", index=False)
        with pytest.raises(ContactresInputError, match=r"line 4, column 'fc2_Hz'") as info:
            read_resonance_table(tmp_path / "bad.csv", AFM_TABLE)
        assert cell in str(info.value)


def test_the_flags_of_the_lever_and_of_the_modulus_are_joined_per_row(tmp_path):
    """The flags column joins the lever's flags and the modulus' flags of each row with ';'
    (joined once per distinct pair of masks): a row with both, rows with either, a clean row."""
    frame, _ = _map(4)
    frame.loc[[1, 3], "fc2_Hz"] *= 1.03  # the modes disagree on κ: inconsistent-modes
    frame.loc[[2, 3], "load_N"] = 1e-12  # E* = √(k*³/6RP) beyond the 165 GPa tip: tip-limit
    frame.to_csv(tmp_path / "map.csv", index=False)
    r = _run("afm", "invert", str(tmp_path / "map.csv"), "--out", str(tmp_path / "o.csv"))
    assert r.exit_code == 0, r.output
    flags = pd.read_csv(tmp_path / "o.csv", keep_default_na=False)["flags"].tolist()
    assert flags == [
        "",
        "inconsistent-modes",
        "tip-limit",
        "inconsistent-modes;tip-limit",
    ]
