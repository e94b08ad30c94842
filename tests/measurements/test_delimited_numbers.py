"""The measured columns of a sweep table read as numbers by pandas' parser (issue 31): the same
doubles as the validator reads from their text, bit for bit, and the text path wherever the two
could differ."""

import io
import warnings

import numpy as np
import pandas as pd
import pytest

from contactres.measurements import read_sweeps, validate_sweeps
from contactres.measurements.readers import BUILT_IN

CONST = dict(overtone=3, area_m2=2.5e-5, n_contacts=3, sphere_radius_m=1.1e-3)


def _forms(rng: np.random.Generator, n: int, lo: int, hi: int, digits: bool = True) -> list[str]:
    """``n`` texts of numbers of many forms: digit strings of 1-21 digits with or without a
    point and exponent (not if ``digits`` is False), %g/%E/%f of random magnitudes
    10^lo..10^hi, reprs; minus signs, leading zeros, blanks around."""
    # Every draw at once (a draw per cell in a loop took ~5 s for 10^5 cells), then the texts.
    length = rng.integers(1, 22, n).tolist()
    pool = (rng.integers(0, 10, (n, 21)) + ord("0")).astype(np.uint8).view("S21").ravel()
    cut = rng.integers(0, np.add(length, 1)).tolist()
    x = (rng.uniform(1, 10, n) * 10.0 ** rng.integers(lo, hi, n).astype(float)).tolist()
    form = rng.integers(0 if digits else 3, 7, n).tolist()
    exponent = rng.integers(-30, 30, n).tolist()
    precision = {3: rng.integers(1, 18, n), 4: rng.integers(0, 17, n), 5: rng.integers(0, 12, n)}
    minus, before, after = (rng.random((3, n)) < 0.3 * np.array([[1], [1 / 6], [1 / 6]])).tolist()
    out = []
    for i in range(n):
        digits_, c = pool[i][: length[i]].decode(), cut[i]
        if form[i] == 0:
            s = digits_
        elif form[i] == 1:
            s = f"{digits_[:c] or '0'}.{digits_[c:]}"
        elif form[i] == 2:
            s = f"{digits_[:c] or '0'}.{digits_[c:]}e{exponent[i]}"
        elif form[i] == 6:
            s = repr(x[i])
        else:
            s = f"{x[i]:.{precision[form[i]][i]}{'xgEf'[form[i] - 2]}}"
        s = ("-" if minus[i] else "") + s
        out.append((" " if before[i] else "") + s + (" " if after[i] else ""))
    return out


def _text_numbers(cells: pd.Series) -> np.ndarray:
    """The validator's text path, written out: pandas.to_numeric of each cell, of the stripped
    cell where that gave none."""
    values = pd.to_numeric(cells, errors="coerce").to_numpy(dtype=float, copy=True)
    again = np.isnan(values)
    values[again] = pd.to_numeric(cells[again].str.strip(), errors="coerce").to_numpy(float)
    return values


def _bits(values: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(values, dtype=np.float64).view(np.int64)


def test_the_parser_reads_numbers_as_the_text_path_does(tmp_path):
    """10^5 cells of many forms and magnitudes (10^-320 to 2**53; larger numbers and -0.0 are
    left to the text path, next test): pandas' parser gives every one the double the text path
    gives it."""
    rng = np.random.default_rng(31)
    cells = pd.Series(_forms(rng, 120_000, -320, 16))
    values = _text_numbers(cells)
    kept = (np.abs(values) < 2.0**53) & ~(np.signbit(values) & (values == 0))
    cells = cells[kept].tolist()
    assert len(cells) > 100_000
    path = tmp_path / "t.csv"
    path.write_text("sweep,df_Hz\n" + "\n".join(f"s,{c}" for c in cells) + "\n")
    raw = BUILT_IN.pick(path, "sweeps").load(path)
    assert raw.attrs["number_columns"] == ("df_Hz",)  # the parser's numbers, not text
    assert raw["df_Hz"].dtype == np.float64
    text = pd.read_csv(path, dtype=str, keep_default_na=False)["df_Hz"]
    assert np.array_equal(_bits(raw["df_Hz"].to_numpy()), _bits(_text_numbers(text)))


@pytest.mark.parametrize(
    "cell",
    [
        "+5.4E+32",  # to_numeric rounds a leading + differently (5.3999999999999995e+32)
        "-0",  # in a column of whole numbers: the integer 0, +0.0
        "9007199254740993",  # 2**53 + 1: from a 64-bit integer
        "nan",
        "inf",
        "0x10",
        "1.5\u00a0",  # a no-break space after the number: the validator strips it
        "",
    ],
)
def test_cells_the_parser_may_read_otherwise_are_read_as_text(tmp_path, cell):
    """Where the parser's number could differ from the text's (or there is none), the column
    comes as text, for the validator to read and name as before."""
    path = tmp_path / "t.csv"
    path.write_text(f"sweep,df_Hz,note\ns,1,a\ns,{cell},b\ns,2,c\n")
    raw = BUILT_IN.pick(path, "sweeps").load(path)
    assert "number_columns" not in raw.attrs
    assert raw["df_Hz"].tolist() == ["1", cell, "2"]


def test_a_whole_number_column_with_minus_zero_matches_the_text_path(tmp_path):
    """The text path makes "-0" in a column of whole numbers +0.0: so does reading."""
    frame = _table(np.random.default_rng(4))
    frame["dgamma_Hz"] = [str(k % 7 + 1) for k in range(len(frame))]
    frame.loc[3, "dgamma_Hz"] = "-0"
    _same_as_text(tmp_path, frame)


def _table(rng: np.random.Generator) -> pd.DataFrame:
    """A sweep table of 40 sweeps of 8 points, its measured numbers written in many forms."""
    n = 320
    u, k = rng.uniform(1e-10, 1e-8, n), rng.integers(1, 17, n)
    amplitude = [f"{a:.{b}g}" for a, b in zip(u, k, strict=True)]
    amplitude[::5] = [f"{u:.6E}" for u in rng.uniform(1e-10, 1e-8, len(amplitude[::5]))]
    return pd.DataFrame(
        {
            "sweep": [f" s{k // 8} " for k in range(n)],
            "configuration": "SiO2",
            "medium": "air",
            "experiment": [f"e{k // 80}" for k in range(n)],
            "ramp": [str(k // 8 % 2 + 1) for k in range(n)],
            "normal_force_N": [f"{2e-3 * (1 + k // 16 % 5):.4g}" for k in range(n)],
            "amplitude_m": amplitude,
            "df_Hz": _forms(rng, n, 0, 3, digits=False),
            "dgamma_Hz": [c.replace("-", "") for c in _forms(rng, n, -1, 2, digits=False)],
            "time_s": [str(k) for k in range(n)],
        }
    )


def _same_as_text(tmp_path, frame: pd.DataFrame) -> None:
    """read_sweeps of ``frame`` written as CSV equals validate_sweeps of its text cells."""
    path = tmp_path / "sweeps.csv"
    frame.to_csv(path, index=False)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        read = read_sweeps(path, **CONST).data
        cells = pd.read_csv(io.BytesIO(path.read_bytes()), dtype=str, keep_default_na=False)
        text = validate_sweeps(cells, source=str(path), constants=CONST).data
    assert list(read.columns) == list(text.columns)
    for col in read.columns:
        a, b = read[col].to_numpy(), text[col].to_numpy()
        if a.dtype.kind == "f":
            assert np.array_equal(_bits(a), _bits(b)), col
        else:
            assert a.tolist() == b.tolist(), col


def test_read_sweeps_gives_the_text_paths_table(tmp_path):
    """A sweep table whose measured numbers come in many forms: read_sweeps (the parser's
    numbers) gives, bit for bit, what validating its text cells gives."""
    frame = _table(np.random.default_rng(5))
    path = tmp_path / "sweeps.csv"
    frame.to_csv(path, index=False)
    raw = BUILT_IN.pick(path, "sweeps").load(path)
    assert set(raw.attrs["number_columns"]) == {
        "amplitude_m",
        "df_Hz",
        "dgamma_Hz",
        "normal_force_N",
        "time_s",
    }
    _same_as_text(tmp_path, frame)
