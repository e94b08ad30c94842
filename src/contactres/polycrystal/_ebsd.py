"""EBSD text exports as orientation maps, read and written: EDAX/TSL ``.ang``, Oxford HKL ``.ctf``.

Formats, as widely documented (OIM Analysis and Channel 5 exports; the readers of orix,
kikuchipy, MTEX and DREAM.3D read them this way); the authoritative vendor specifications were
*not* consulted, so the points marked "not confirmed" are assumptions:

``.ang`` (EDAX/TSL OIM): header lines beginning with ``#`` (``# GRID: SqrGrid`` or ``HexGrid``,
``# XSTEP:``, ``# YSTEP:`` in µm, ``# NCOLS_ODD:``, ``# NCOLS_EVEN:``, ``# NROWS:``), then one
whitespace-separated row per point with at least 8 columns: φ1, Φ, φ2 (Bunge, **radians**),
x, y (µm), image quality IQ, confidence index CI, phase id; further columns (detector signal,
fit, ...) are ignored. Unindexed points are commonly written with angles 4π (12.566) and
CI = -1 (not confirmed); they are kept as they are (angles up to 4π are valid rotations).

``.ctf`` (Oxford HKL Channel 5 / AZtec): a tab-separated header block (``Channel Text File``,
``JobMode Grid``, ``XCells``, ``YCells``, ``XStep``, ``YStep`` in µm, a line ``Euler angles
refer to Sample Coordinate system (CS0)!``, ``Phases n`` and n phase lines), ending with the
column line ``Phase X Y Bands Error Euler1 Euler2 Euler3 MAD BC BS`` (tab-separated); then one
tab-separated row per point. Euler1..3 are Bunge angles in **degrees**, X and Y in µm; Phase 0
is "not indexed"; MAD is the mean angular deviation (degrees, lower is better).

Not confirmed and not corrected here: the relation of the vendors' Euler reference frame to the
map's x/y axes (OIM and Channel 5 setups differ by rotations about the normal, and hexagonal
phases in .ctf by a 30° convention about c). The angles are taken as Bunge angles of the
map's sample frame x = map X, y = map Y, z = ND (:mod:`.orientations`), as written.

Exchange with orix (tests/polycrystal/test_ebsd_orix.py, orix 0.15 as the peer): the angles
are Bunge angles of the passive orientation g (sample to crystal coordinates), as orix's
``Rotation.from_euler`` (its default direction "lab2crystal") takes them; orix's
``Rotation.to_matrix()`` is g and contactres' surface matrix is R = gᵀ (:mod:`.orientations`),
equal to 1e-12. :func:`write_ang` and :func:`write_ctf` write the phase they are given
(:class:`~contactres.polycrystal.EbsdPhase`) and the 10 columns of an OIM ``.ang``, so that
``orix.io.load`` reads both files with the map's orientations (misorientation with the crystal
symmetry < 1e-6 rad); :func:`read_ang` reads the ``.ang`` orix writes (``orix.io.save``; orix
rounds the angles to 1e-5 rad). The confidence of each format keeps its own sense: CI (higher
is better) is never written as MAD (lower is better), nor MAD as CI (the writers' Notes).
Oxford's HDF5 maps (``.h5oina``) are read by :func:`~contactres.polycrystal.read_h5oina`.

Only regular square grids are read (every point on ``(x0 + j·XSTEP, y0 + i·YSTEP)``, each grid
position exactly once, in any order): a hexagonal ``.ang`` grid or a ``.ctf`` whose ``JobMode``
is not ``Grid`` raises ValueError. Bad input raises ValueError naming the file, the data row
(and line of the file), the column, the value and the rule broken.
"""

from __future__ import annotations

import itertools
import os
import re
from pathlib import Path

import numpy as np
import pandas as pd

from .._column_names import repeats_text
from ..errors import ContactresInputError
from ..fileio import write_text
from ..measurements.readers import Reader
from ._ebsd_phases import UNKNOWN_CUBIC, EbsdPhase
from ._h5oina import read_h5oina
from ._maps import OrientationMap, check_map_size

__all__ = ["EBSD_READERS", "read_ang", "read_ctf", "read_ebsd", "write_ang", "write_ctf"]

#: The first 8 columns of an .ang row (more may follow and are ignored).
ANG_COLUMNS = ("phi1", "Phi", "phi2", "x", "y", "IQ", "CI", "phase")
#: The columns of a .ctf file that are read (by name from the column line).
CTF_COLUMNS = ("Phase", "X", "Y", "Euler1", "Euler2", "Euler3", "MAD")
_CTF_LINE = ("Phase", "X", "Y", "Bands", "Error", "Euler1", "Euler2", "Euler3", "MAD", "BC", "BS")
#: Largest ``|angle|`` accepted: two turns (as :func:`.surface_matrices_from_euler`).
_MAX_RAD = 4 * np.pi
#: A point is on the grid when within this fraction of a step of a grid position.
_GRID_TOL = 1e-3
_ENCODING = "latin-1"  # any byte decodes; the data are ASCII, headers may hold other text


def _line(path: Path, lineno: int) -> str:
    with open(path, encoding=_ENCODING) as f:
        return next(itertools.islice(f, lineno - 1, lineno), "").rstrip("\r\n")


def _bad(path: Path, row: int, lineno: int, column: str, value: str, rule: str) -> ValueError:
    return ContactresInputError(
        f"{path.name}: data row {row} (line {lineno}), column {column!r}: value {value!r}: {rule}"
    )


def _numeric(path: Path, frame: pd.DataFrame, names, positions, first_line: int, sep) -> dict:
    """Columns ``names`` (at field ``positions``) of ``frame`` as float arrays; ValueError at the
    first missing, non-numeric or non-finite value (the raw token is read back from the file)."""
    out = {}
    for name, pos, (_, col) in zip(names, positions, frame.items(), strict=True):
        values = pd.to_numeric(col, errors="coerce").to_numpy(dtype=float)
        bad = ~np.isfinite(values)
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            lineno = first_line + k
            fields = re.split(sep, _line(path, lineno).strip())
            token = fields[pos] if pos < len(fields) else "<missing>"
            rule = (
                f"missing (the row has {len(fields)} fields)"
                if pos >= len(fields) or token == ""
                else "must be a finite number"
            )
            raise _bad(path, k + 1, lineno, name, token, rule)
        out[name] = values
    return out


def _check_angles(path: Path, angles: np.ndarray, names, first_line: int, limit: float, unit: str):
    bad = np.abs(angles) > limit
    if bad.any():
        k, c = (int(v) for v in np.argwhere(bad)[0])
        raise _bad(
            path, k + 1, first_line + k, names[c], repr(float(angles[k, c])),
            f"Euler angle beyond two turns (|angle| <= {limit:g} {unit})",
        )  # fmt: skip


def _grid(path: Path, x: np.ndarray, y: np.ndarray, step_x: float, step_y: float, first_line):
    """Row and column index of every point of a square grid (µm in), checked."""
    fx, fy = (x - x.min()) / step_x, (y - y.min()) / step_y
    j, i = np.rint(fx).astype(np.int64), np.rint(fy).astype(np.int64)
    off = np.maximum(np.abs(fx - j), np.abs(fy - i)) > _GRID_TOL
    if off.any():
        k = int(np.flatnonzero(off)[0])
        col, value = ("x", x[k]) if abs(fx[k] - j[k]) > _GRID_TOL else ("y", y[k])
        raise _bad(path, k + 1, first_line + k, col, repr(float(value)),
                   f"not on the square grid of step ({step_x:g}, {step_y:g}) µm")  # fmt: skip
    H, W = int(i.max()) + 1, int(j.max()) + 1
    # Before the counts are allocated: two points far apart would span a grid of 10^10 pixels.
    check_map_size((H, W), f"{path.name}: the points span a grid of")
    flat = i * W + j
    counts = np.bincount(flat, minlength=H * W)
    if np.any(counts > 1):
        k = int(np.flatnonzero(counts[flat] > 1)[1 if counts[flat[0]] > 1 else 0])
        raise _bad(path, k + 1, first_line + k, "x, y", f"{x[k]:g}, {y[k]:g}",
                   "grid position given twice")  # fmt: skip
    if np.any(counts == 0):
        miss = int(np.flatnonzero(counts == 0)[0])
        raise ContactresInputError(
            f"{path.name}: grid position (row {miss // W}, column {miss % W}) of the "
            f"{H} x {W} grid has no data row (x = {x.min() + miss % W * step_x:g} µm, "
            f"y = {y.min() + miss // W * step_y:g} µm)"
        )
    return i, j, (H, W)


def _header_float(path: Path, header: dict, key: str) -> float:
    if key not in header:
        raise ContactresInputError(
            f"{path.name}: header entry {key!r} is missing (the grid step, µm)"
        )
    try:
        v = float(header[key])
    except ValueError:
        raise ContactresInputError(
            f"{path.name}: header entry {key!r} = {header[key]!r} is not a number"
        ) from None
    if not (np.isfinite(v) and v > 0):
        raise ContactresInputError(
            f"{path.name}: header entry {key!r} = {v!r} must be a positive step"
        )
    return v


def _read_block(path: Path, skip: int, sep: str, header) -> pd.DataFrame:
    """The data rows: all-float in one fast pass, else as text (the checks find the culprit)."""
    kwargs = dict(sep=sep, header=header, skiprows=skip, encoding=_ENCODING)
    try:
        try:
            return pd.read_csv(path, dtype=float, **kwargs)
        except ValueError as exc:
            if isinstance(exc, pd.errors.ParserError):
                raise
            return pd.read_csv(path, dtype=str, keep_default_na=False, **kwargs)
    except pd.errors.EmptyDataError:
        raise ContactresInputError(f"{path.name}: no data rows after the header") from None
    except pd.errors.ParserError as exc:
        raise ContactresInputError(f"{path.name}: malformed data rows: {exc}") from None


def _assemble(
    path, euler, x, y, phase, conf, conf_name, steps: tuple[float, float], first_line
) -> OrientationMap:
    i, j, shape = _grid(path, x, y, *steps, first_line)
    grid = np.empty((*shape, 3))
    grid[i, j] = euler
    ph = np.empty(shape, dtype=np.int64)
    ph[i, j] = phase
    cf = np.empty(shape)
    cf[i, j] = conf
    return OrientationMap(
        euler=grid, step_x=steps[0] * 1e-6, step_y=steps[1] * 1e-6, phase=ph, confidence=cf,
        confidence_name=conf_name, source=path.name,
    )  # fmt: skip


def read_ang(path: str | os.PathLike) -> OrientationMap:
    """Read an EDAX/TSL ``.ang`` file (square grid) as an :class:`OrientationMap`.

    Returns Euler angles in radians as written (φ1, Φ, φ2 columns), steps in m (header XSTEP,
    YSTEP in µm), ``phase`` = the phase id column, ``confidence`` = CI. See the module
    docstring for the assumptions on the format.

    Raises
    ------
    ValueError
        For a hexagonal grid, a missing step, a row with fewer than 8 columns, a non-numeric or
        non-finite value, an angle beyond 4π, or points not filling a square grid (the message
        names the file, row, line, column, value and rule).
    """
    path = Path(path)
    header: dict[str, str] = {}
    n_head = 0
    with open(path, encoding=_ENCODING) as f:
        for line in f:
            s = line.strip()
            if s and not s.startswith("#"):
                break
            n_head += 1
            m = re.match(r"#\s*([A-Za-z_][\w-]*)\s*:?\s*(.*)$", s)
            if m and m.group(1).upper() in ("GRID", "XSTEP", "YSTEP", "NCOLS_ODD", "NCOLS_EVEN"):
                header[m.group(1).upper()] = m.group(2).strip()
    grid = header.get("GRID", "SqrGrid")
    if grid.lower() != "sqrgrid":
        raise ContactresInputError(
            f"{path.name}: '# GRID: {grid}' is not supported: only square grids (SqrGrid) are "
            "read; resample a hexagonal scan onto a square grid first"
        )
    steps = (_header_float(path, header, "XSTEP"), _header_float(path, header, "YSTEP"))
    frame = _read_block(path, n_head, r"\s+", None)
    first_line = n_head + 1
    if frame.shape[1] < len(ANG_COLUMNS):
        raise _bad(path, 1, first_line, ANG_COLUMNS[frame.shape[1]], "<missing>",
                   f"an .ang row needs {len(ANG_COLUMNS)} columns {ANG_COLUMNS}, "
                   f"found {frame.shape[1]}")  # fmt: skip
    cols = _numeric(path, frame.iloc[:, :8], ANG_COLUMNS, range(8), first_line, r"\s+")
    euler = np.stack([cols["phi1"], cols["Phi"], cols["phi2"]], axis=-1)
    _check_angles(path, euler, ANG_COLUMNS[:3], first_line, _MAX_RAD, "rad")
    phase = cols["phase"]
    if np.any(phase != np.rint(phase)):
        k = int(np.flatnonzero(phase != np.rint(phase))[0])
        raise _bad(path, k + 1, first_line + k, "phase", repr(float(phase[k])),
                   "the phase id must be an integer")  # fmt: skip
    return _assemble(path, euler, cols["x"], cols["y"], phase, cols["CI"], "CI", steps, first_line)


def read_ctf(path: str | os.PathLike) -> OrientationMap:
    """Read an Oxford HKL ``.ctf`` file (``JobMode Grid``) as an :class:`OrientationMap`.

    Returns Euler angles converted from degrees to radians, steps in m (header XStep, YStep in
    µm), ``phase`` = the Phase column (0 = not indexed), ``confidence`` = MAD (degrees). See the
    module docstring for the assumptions on the format.

    Raises
    ------
    ValueError
        For a JobMode other than Grid, a missing step or column line, a missing column among
        :data:`CTF_COLUMNS`, a non-numeric or non-finite value, an angle beyond 720°, or points
        not filling a square grid (the message names the file, row, line, column, value and
        rule).
    """
    path = Path(path)
    header: dict[str, str] = {}
    n_head = None
    with open(path, encoding=_ENCODING) as f:
        for n, line in enumerate(f):
            fields = line.rstrip("\r\n").split("\t")
            if fields[0].strip() == "Phase" and "Euler1" in (s.strip() for s in fields):
                n_head = n
                break
            if len(fields) >= 2:
                header.setdefault(fields[0].strip(), fields[1].strip())
    if n_head is None:
        raise ContactresInputError(
            f"{path.name}: no column line (tab-separated {' '.join(_CTF_LINE)}) found: not a "
            ".ctf file"
        )
    # A name twice on the column line: pandas would read the first and rename the other
    # (Euler1.1) without a word. (Empty fields, a trailing tab's, are no names.)
    names = [s.strip() for s in fields]
    repeats = repeats_text(names, named_only=True)
    if repeats is not None:
        raise ContactresInputError(
            f"{path.name}, line {n_head + 1}: duplicate column name(s) {repeats}; every column "
            "needs its own name"
        )
    mode = header.get("JobMode", "Grid")
    if mode != "Grid":
        raise ContactresInputError(
            f"{path.name}: JobMode {mode!r} is not supported: only 'Grid' maps"
        )
    steps = (_header_float(path, header, "XStep"), _header_float(path, header, "YStep"))
    frame = _read_block(path, n_head, "\t", 0)
    frame.columns = [str(c).strip() for c in frame.columns]
    missing = [c for c in CTF_COLUMNS if c not in frame.columns]
    if missing:
        raise ContactresInputError(
            f"{path.name}: column line (line {n_head + 1}) lacks the columns {missing}; a .ctf "
            f"file needs {list(CTF_COLUMNS)}"
        )
    positions = [list(frame.columns).index(c) for c in CTF_COLUMNS]
    first_line = n_head + 2
    cols = _numeric(path, frame[list(CTF_COLUMNS)], CTF_COLUMNS, positions, first_line, "\t")
    euler = np.stack([cols["Euler1"], cols["Euler2"], cols["Euler3"]], axis=-1)
    _check_angles(path, euler, CTF_COLUMNS[3:6], first_line, 720.0, "degrees")
    phase = cols["Phase"]
    if np.any(phase != np.rint(phase)):
        k = int(np.flatnonzero(phase != np.rint(phase))[0])
        raise _bad(path, k + 1, first_line + k, "Phase", repr(float(phase[k])),
                   "the phase must be an integer")  # fmt: skip
    return _assemble(
        path, np.radians(euler), cols["X"], cols["Y"], phase, cols["MAD"], "MAD (degrees)",
        steps, first_line,
    )  # fmt: skip


def _looks_like_ang(path: Path, head: str) -> bool:
    """An ``.ang`` header: ``#`` lines with the grid step."""
    return any(line.startswith("# XSTEP:") for line in head.splitlines())


def _looks_like_ctf(path: Path, head: str) -> bool:
    """A ``.ctf`` header: its first line."""
    return head.lstrip().startswith("Channel Text File")


def _looks_like_h5oina(path: Path, head: str) -> bool:
    """An HDF5 file (its 8-byte signature) named ``.h5oina`` (other HDF5 files are other
    formats: BGlib's ``.h5``, NetCDF)."""
    if path.suffix.lower() != ".h5oina" or not path.is_file():
        return False
    with path.open("rb") as fh:
        return fh.read(8) == b"\x89HDF\r\n\x1a\n"


#: The EBSD reader recipes (kind ``ebsd``), in the polycrystal layer that owns the formats; the
#: full registry of every kind is composed above it (``contactres.jobs.readers``).
EBSD_READERS: tuple[Reader, ...] = (
    Reader("ang", (".ang",), _looks_like_ang, read_ang, "ebsd"),
    Reader("ctf", (".ctf",), _looks_like_ctf, read_ctf, "ebsd"),
    Reader("h5oina", (".h5oina",), _looks_like_h5oina, read_h5oina, "ebsd"),
)


def read_ebsd(path: str | os.PathLike) -> OrientationMap:
    """Read an EBSD export by its suffix: ``.ang`` (:func:`read_ang`), ``.ctf``
    (:func:`read_ctf`) or ``.h5oina`` (:func:`~contactres.polycrystal.read_h5oina`), the
    recipes of :data:`EBSD_READERS`."""
    suffix = Path(path).suffix.lower()
    for reader in EBSD_READERS:
        if suffix in reader.suffixes:
            return reader.load(path)
    known = " or ".join(s for r in EBSD_READERS for s in r.suffixes)
    raise ContactresInputError(
        f"{Path(path).name}: unknown EBSD export {suffix!r} (expected {known})"
    )


def _points(m: OrientationMap):
    """Points in file order (x fastest): x, y (µm), euler (N, 3) rad, phase, confidence, zeros."""
    H, W = m.shape
    yy, xx = np.meshgrid(np.arange(H) * m.step_y * 1e6, np.arange(W) * m.step_x * 1e6,
                         indexing="ij")  # fmt: skip
    zeros = np.zeros(H * W, dtype=np.int64)
    return (
        xx.ravel(),
        yy.ravel(),
        m.euler.reshape(-1, 3),
        m.phase.ravel(),
        m.confidence.ravel(),
        zeros,
    )


def _not_indexed(m: OrientationMap) -> np.ndarray:
    """The pixels the map itself marks as not indexed (flat, file order): CI < 0 of an .ang,
    phase 0 of a .ctf or .h5oina (MAD maps); none for a map of another confidence."""
    if m.confidence_name == "CI":
        return m.confidence.ravel() < 0
    if m.confidence_name.startswith("MAD"):
        return m.phase.ravel() == 0
    return np.zeros(m.phase.size, dtype=bool)


def _the_phase(
    m: OrientationMap, off: np.ndarray, phase: EbsdPhase | None
) -> tuple[int, EbsdPhase]:
    """The map's one phase id among its indexed pixels (1 if none), and the phase to write."""
    if phase is not None and not isinstance(phase, EbsdPhase):
        raise ContactresInputError(
            f"phase must be an EbsdPhase (e.g. ebsd_phase('Ni')), got {type(phase).__name__}"
        )
    ids = np.unique(m.phase.ravel()[~off])
    if ids.size > 1:
        raise ContactresInputError(
            f"{m.source or 'the map'} holds phases {', '.join(str(int(i)) for i in ids)}: the "
            "writers describe one phase; write each phase's pixels as a map of its own"
        )
    return (int(ids[0]) if ids.size else 1), (UNKNOWN_CUBIC if phase is None else phase)


def write_ang(path: str | os.PathLike, m: OrientationMap, phase: EbsdPhase | None = None) -> Path:
    """Write a square-grid ``.ang`` file of ``m`` in the EDAX/TSL layout (atomically).

    Parameters
    ----------
    path : str or PathLike
        The file to write.
    m : OrientationMap
        The map; its indexed pixels must be of one phase id.
    phase : EbsdPhase, optional
        The phase the header names (``# MaterialName``, ``# Symmetry``, ``# LatticeConstants``),
        e.g. :func:`~contactres.polycrystal.ebsd_phase` ``("Ni")``; default: a cubic phase named
        "unknown" with a = 1 Å (a placeholder, not a claim).

    Notes
    -----
    Header: the phase block under ``# Phase <id>`` (the map's phase id), ``# GRID: SqrGrid``,
    steps in µm and the grid size. Rows: the 10 columns of OIM's export, φ1 Φ φ2 (rad, Bunge,
    the map's sample frame as :mod:`._maps` states it), x y (µm), IQ (0), CI, phase id, detector
    signal (0), fit (0), with 17 significant digits so that :func:`read_ang` gives the angles
    back bit for bit. CI is the map's own when it has one (an .ang map); a map without (a .ctf
    map, whose MAD is a different, lower-is-better quantity, or a synthetic map) is written
    with CI = −1 on the pixels it marks as not indexed and CI = 1 on the others: no CI is
    derived from MAD, every indexed pixel passes the default rule of
    :func:`~contactres.polycrystal.indexed_pixels`. orix (``orix.io.load``) reads these files
    with the same orientations (tests/polycrystal/test_ebsd_orix.py).

    Raises
    ------
    ContactresInputError
        ``phase`` not an :class:`EbsdPhase`; indexed pixels of several phase ids.
    """
    H, W = m.shape
    off = _not_indexed(m)
    pid, ph = _the_phase(m, off, phase)
    consts = " ".join(f"{v:.4f}" for v in (*ph.lengths, *ph.angles))
    head = [
        f"# Phase {pid}", f"# MaterialName {ph.name}", f"# Formula {ph.name}", "# Info",
        f"# Symmetry {ph.ang_symmetry}", f"# LatticeConstants {consts}", "# NumberFamilies 0",
        "#", "# GRID: SqrGrid", f"# XSTEP: {m.step_x * 1e6!r}", f"# YSTEP: {m.step_y * 1e6!r}",
        f"# NCOLS_ODD: {W}", f"# NCOLS_EVEN: {W}", f"# NROWS: {H}", "#",
    ]  # fmt: skip
    x, y, e, ids, conf, zeros = _points(m)
    ci = conf if m.confidence_name == "CI" else np.where(off, -1.0, 1.0)
    table = pd.DataFrame({
        "phi1": e[:, 0], "Phi": e[:, 1], "phi2": e[:, 2], "x": x, "y": y, "IQ": zeros,
        "CI": ci, "phase": ids, "signal": zeros, "fit": zeros,
    })  # fmt: skip
    rows = table.to_csv(sep=" ", header=False, index=False, float_format="%.17g")
    return write_text(path, "\n".join(head) + "\n" + rows)


def write_ctf(path: str | os.PathLike, m: OrientationMap, phase: EbsdPhase | None = None) -> Path:
    """Write a ``.ctf`` file of ``m`` in the Oxford Channel 5 layout (atomically).

    Parameters
    ----------
    path, m, phase
        As :func:`write_ang`; ``phase`` fills the header's phase line (``a;b;c`` in Å,
        ``α;β;γ`` in degrees, the name, the Laue group index, the space group number).

    Notes
    -----
    Rows: Phase (1; 0 on the pixels the map marks as not indexed), X, Y (µm), Bands (0), Error
    (0; 3, "no solution", where not indexed), Euler1..3 (Bunge, degrees, 17 significant
    digits), MAD, BC (0), BS (0). MAD is the map's own when it has one (a .ctf or .h5oina map,
    degrees); a map without (an .ang map, whose CI is a different, higher-is-better quantity,
    or a synthetic map) is written with MAD = 0, i.e. "no deviation recorded": no MAD is
    derived from CI, and the CI rule is carried by the phase 0 of its not-indexed pixels.
    orix (``orix.io.load``) reads these files with the same orientations.

    Raises
    ------
    ContactresInputError
        ``phase`` not an :class:`EbsdPhase`; indexed pixels of several phase ids.
    """
    H, W = m.shape
    off = _not_indexed(m)
    _, ph = _the_phase(m, off, phase)
    head = [
        "Channel Text File", "Prj\tcontactres", "JobMode\tGrid", f"XCells\t{W}",
        f"YCells\t{H}", f"XStep\t{m.step_x * 1e6!r}", f"YStep\t{m.step_y * 1e6!r}",
        "Euler angles refer to Sample Coordinate system (CS0)!\tMag\t0", "Phases\t1",
        f"{';'.join(f'{v:.4f}' for v in ph.lengths)}\t{';'.join(f'{v:.4f}' for v in ph.angles)}"
        f"\t{ph.name}\t{ph.laue_index}\t{int(ph.space_group)}",
        "\t".join(_CTF_LINE),
    ]  # fmt: skip
    x, y, e, _, conf, zeros = _points(m)
    d = np.degrees(e)
    mad = conf if m.confidence_name.startswith("MAD") else np.zeros(conf.shape)
    table = pd.DataFrame({
        "Phase": np.where(off, 0, 1), "X": x, "Y": y, "Bands": zeros,
        "Error": np.where(off, 3, 0), "Euler1": d[:, 0], "Euler2": d[:, 1], "Euler3": d[:, 2],
        "MAD": mad, "BC": zeros, "BS": zeros,
    })  # fmt: skip
    rows = table.to_csv(sep="\t", header=False, index=False, float_format="%.17g")
    return write_text(path, "\n".join(head) + "\n" + rows)
