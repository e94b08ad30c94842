"""Igor binary waves (``.ibw``) as Asylum Research instruments write them: the data, the layer
labels and the note.

An Asylum image (every DART, DART-PFM and ESM image among them) is one Igor wave of three
dimensions: points × lines × layers, each layer (channel) named by a dimension label
(``HeightRetrace``, ``Amplitude1Retrace``, ..., ``FrequencyRetrace``); a force record is a wave of
two dimensions, points × channels (``Raw``, ``Defl``, ``ZSnsr``). The wave's note holds the
instrument's settings as several hundred ``key: value`` lines separated by carriage returns
(``SpringConstant``, ``InvOLS``, ``DriveFrequency``, ``DARTIGain``, ``ScanSize``, ...).

:func:`read_ibw` reads the file with the ``igor2`` package (``igor2.binarywave.load``), which is
the optional extra ``afm`` (``pip install 'contactres[afm]'``), imported only when a file is
read. The file format is WaveMetrics' Technical Note PTN003 ("Igor Binary Wave Format"); the
version 5 header's section sizes are checked here before ``igor2`` parses the file, so a
truncated file is named as such instead of failing deep inside the parser.

Conventions
-----------
``data`` keeps Igor's order of the dimensions, layers last. In an Asylum image Igor's first
dimension ("rows") runs along the fast scan axis x (``ScanPoints`` points) and its second
("columns") along the slow axis y (``ScanLines`` lines): ``data[i, j, k]`` is the pixel at
(x, y) = (i·dx, j·dy) of layer k, so ``wave.layer("Height").T`` is the image with row index y.
"""

from __future__ import annotations

import io
import math
import os
import re
import struct
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._summary import Summarised, values
from ..errors import ContactresInputError, MissingExtraError

__all__ = ["IgorWave", "parse_note", "read_ibw"]

_EXTRA = "pip install 'contactres[afm]'"

# A number as Asylum writes one in a note ("4.499e-08", "-10", "NaN", "inf"); anything else
# ("16.11.212", "29.5625 °C", "$Lockin.0.r") stays text. Python's float() alone would also take
# "1_000" and " infinity ", which an instrument never writes for a number.
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|[+-]?(nan|inf)", re.IGNORECASE)

# Igor's text-encoding codes (Igor Pro 7 and later write them into the wave header; Igor 6 writes
# 0, "unknown"): the ones an instrument's note can carry.
_ENCODINGS = {1: "utf-8", 2: "mac_roman", 3: "cp1252", 4: "shift_jis"}

# The version 5 binary header (PTN003, BinHeader5): version, checksum, then the sizes in bytes of
# the sections that follow it: wfmSize (wave header + data), formula, note, extended data units,
# extended units of the 4 dimensions, dimension labels of the 4 dimensions, string indices, and
# two reserved option sizes.
_BIN_HEADER5 = "hhiiii4i4iiii"
_BIN_HEADER5_SIZE = struct.calcsize("<" + _BIN_HEADER5)  # 64 bytes
# The versions igor2 reads (Asylum instruments write version 5).
_VERSIONS = (1, 2, 3, 5)


def parse_note(text: str) -> dict[str, float | str]:
    """The ``key: value`` lines of an Igor wave note as a dict.

    Parameters
    ----------
    text : str
        The note, lines separated by carriage returns (Igor's line end; ``\\n`` and ``\\r\\n``
        are accepted too).

    Returns
    -------
    dict
        key -> value: a float where the value is a number (``"4.499e-08"``, ``"NaN"``,
        ``"inf"``), else the text with surrounding blanks removed (``"16.11.212"``,
        ``"29.5625 °C"``, ``""`` for a key with no value). A key that occurs on several lines
        (Asylum notes repeat ``SaveForce`` and ``SaveImage``, first as a number then as a
        folder) keeps its last value. Lines without a colon are skipped.

    Examples
    --------
    >>> parse_note("SpringConstant: 1.1841\\rInvOLS: 4.499e-08\\rMicroscopeModel:MFP3D")
    {'SpringConstant': 1.1841, 'InvOLS': 4.499e-08, 'MicroscopeModel': 'MFP3D'}
    """
    note: dict[str, float | str] = {}
    for line in text.splitlines():
        key, colon, value = line.partition(":")
        key, value = key.strip(), value.strip()
        if not colon or not key:
            continue
        note[key] = float(value) if _NUMBER.fullmatch(value) else value
    return note


# repr=False: the summary (Summarised, _facts) replaces the numpy repr of the data.
@dataclass(frozen=True, eq=False, repr=False)
class IgorWave(Summarised):
    """An Igor binary wave: its data, the names of its layers and its note.

    Attributes
    ----------
    data : ndarray (read-only)
        The wave's values, float64 (complex128 for a complex wave), in Igor's order of the
        dimensions with the layers last: (points, lines, layers) for an Asylum image,
        (points, channels) for a force record (see the module's conventions: the first index
        of an image runs along x).
    labels : tuple of str
        The names of the layers in order, from the dimension labels of the last dimension
        (``""`` for a layer without a label; empty if the wave has no labels there).
    note : dict
        The note's ``key: value`` lines (:func:`parse_note`): numbers as floats, in the
        instrument's units (Asylum: SI, ``SpringConstant`` N/m, ``InvOLS`` m/V,
        ``DriveFrequency`` Hz, ``ScanSize`` m); text otherwise; a repeated key keeps its last
        value. A plain dict (it goes into JSON as it is), made afresh by every read.
    name : str
        The wave's name.
    scale : tuple of float or None
        (dx, dy), the pixel size in m along Igor's first two dimensions: the wave's own scaling
        where both are in metres, else the note's ``FastScanSize``/``ScanPoints`` and
        ``SlowScanSize``/``ScanLines`` (``ScanSize`` for a missing fast or slow size); None when
        neither gives it (a force record).
    source : str
        The file read.
    """

    data: np.ndarray
    labels: tuple[str, ...]
    note: dict[str, float | str] = field(repr=False)
    name: str
    scale: tuple[float, float] | None
    source: str

    def _facts(self) -> list[tuple[str, str]]:
        """Name, data shape and range, the layers' labels, the pixel size and the file."""
        labels = ", ".join(self.labels[:6]) + (", …" if len(self.labels) > 6 else "")
        facts = [("", repr(self.name)), ("data", values(self.data))]
        facts.append(("layers", labels or "no labels"))
        if self.scale is not None:
            facts.append(("pixel", f"{self.scale[0] * 1e9:.4g} x {self.scale[1] * 1e9:.4g} nm"))
        facts.append(("source", self.source))
        return facts

    def layer_index(self, name: str) -> int:
        """The position of the layer called ``name`` in :attr:`labels`.

        ``name`` is a full label (``"FrequencyRetrace"``) or a channel without its scan
        direction (``"Frequency"``: the ``Retrace`` layer, else the ``Trace`` one); case is
        ignored. A one-line ContactresInputError names the file and the labels present when
        no layer matches.
        """
        wanted = str(name).strip().lower()
        lower = [label.lower() for label in self.labels]
        for candidate in (wanted, wanted + "retrace", wanted + "trace"):
            if candidate in lower:
                return lower.index(candidate)
        present = ", ".join(label or "(unlabelled)" for label in self.labels) or "none"
        raise ContactresInputError(
            f"{self.source}: no layer {name!r} in the wave {self.name!r}; layers present: {present}"
        )

    def layer(self, name: str) -> np.ndarray:
        """The layer called ``name`` (see :meth:`layer_index`): ``data[..., k]``, read-only."""
        return self.data[..., self.layer_index(name)]


def _igor2():
    """The ``igor2.binarywave`` module, or the one-line MissingExtraError naming the extra."""
    try:
        import igor2.binarywave as binarywave
    except ImportError as exc:
        raise MissingExtraError(f"reading .ibw files needs igor2: {_EXTRA}") from exc
    return binarywave


def _check_sizes(raw: bytes, source: str) -> None:
    """Refuse a file too short for the sections its own header declares (version 5), or whose
    first two bytes are no Igor version: a one-line ContactresInputError.

    igor2 reports such files with struct errors (and logs the bytes it got); the sizes are
    checked here first so that the message names the rule.
    """
    bad = f"{source}: truncated or not an Igor binary wave"
    if len(raw) < 2:
        raise ContactresInputError(f"{bad} ({len(raw)} bytes)")
    # The version is a 2-byte integer in the file's byte order (PTN003): read it both ways.
    order = next((o for o in "<>" if struct.unpack(o + "h", raw[:2])[0] in _VERSIONS), None)
    if order is None:
        raise ContactresInputError(f"{bad} (its first bytes are no Igor wave version)")
    if struct.unpack(order + "h", raw[:2])[0] != 5:
        return  # versions 1-3 (before Igor 3): no Asylum instrument writes them; igor2 checks
    if len(raw) < _BIN_HEADER5_SIZE:
        raise ContactresInputError(f"{bad} ({len(raw)} bytes, shorter than its header)")
    sizes = struct.unpack(order + _BIN_HEADER5, raw[:_BIN_HEADER5_SIZE])
    # wfmSize, formula, note, extended data units, 4 extended dimension units, 4 dimension
    # labels, string indices (the two reserved option sizes are not in the file).
    declared = _BIN_HEADER5_SIZE + sum(sizes[2:17])
    if min(sizes[2:17]) < 0 or len(raw) < declared:
        raise ContactresInputError(f"{bad} ({len(raw)} bytes where its header declares {declared})")


def _decode(text: bytes, code: int) -> str:
    """Igor text in the encoding the header names (``code``, :data:`_ENCODINGS`); for an unknown
    code (Igor 6 writes 0), UTF-8 if the bytes are valid UTF-8, else Windows-1252 (Asylum's
    instruments run Windows: "°C" is the byte 0xB0 there)."""
    if code in _ENCODINGS:
        return text.decode(_ENCODINGS[code], errors="replace")
    try:
        return text.decode("utf-8")
    except UnicodeDecodeError:
        return text.decode("cp1252", errors="replace")


def _header_byte(values, index: int) -> int:
    """One byte of a header field igor2 returns as an array of 1-byte strings (``b''`` for 0)."""
    try:
        value = values[index]
    except (IndexError, TypeError):
        return 0
    return value[0] if isinstance(value, bytes) and value else 0


def _labels(wave: dict, ndim: int, encoding: int) -> tuple[str, ...]:
    """The layer names: the element labels of the last dimension (igor2 gives, per dimension,
    the dimension's own label first, then one per element)."""
    per_dim = wave.get("labels") or []
    if ndim < 1 or len(per_dim) < ndim or not per_dim[ndim - 1]:
        return ()
    return tuple(_decode(b, encoding).strip("\x00").strip() for b in per_dim[ndim - 1][1:])


def _positive(value) -> bool:
    return isinstance(value, float) and math.isfinite(value) and value > 0


def _scale(header: dict, note, encoding: int) -> tuple[float, float] | None:
    """(dx, dy) in m: the wave's scaling where its first two dimensions are in metres, else the
    note's scan size over its points and lines; None if neither gives it."""
    n = [int(v) for v in header["nDim"]]
    units = [_decode(bytes(u).strip(b"\x00"), encoding) for u in header["dimUnits"][:2]]
    steps = [float(abs(a)) for a in header["sfA"][:2]]
    if n[1] > 0 and units == ["m", "m"] and all(s > 0 for s in steps):
        return steps[0], steps[1]
    size = note.get("ScanSize")
    fast, slow = note.get("FastScanSize", size), note.get("SlowScanSize", size)
    points, lines = note.get("ScanPoints"), note.get("ScanLines")
    if all(_positive(v) for v in (fast, slow, points, lines)):
        return fast / points, slow / lines
    return None


def read_ibw(path: str | os.PathLike) -> IgorWave:
    """Read an Igor binary wave (``.ibw``), such as an Asylum Research image or force record.

    Parameters
    ----------
    path : str or path-like
        The ``.ibw`` file.

    Returns
    -------
    IgorWave
        ``.data`` (layers last), ``.labels`` (layer names in order), ``.note`` (the note's
        ``key: value`` lines, numbers as floats: ``note["SpringConstant"]`` in N/m,
        ``note["InvOLS"]`` in m/V, ``note["DriveFrequency"]`` in Hz on an Asylum file),
        ``.name``, ``.scale`` (pixel size in m, or None) and ``.source``; a layer is found by
        its label with :meth:`IgorWave.layer`.

    Raises
    ------
    ContactresInputError
        One line naming the file: missing, truncated or not an Igor binary wave, or a text
        wave (no numbers).
    MissingExtraError
        igor2 is not installed (the optional extra ``afm``).

    Notes
    -----
    A note without a key (no ``SpringConstant`` in it, say) is read as it is: the caller that
    needs the value says what to give instead. The file format: WaveMetrics, Igor Pro
    Technical Note PTN003, "Igor Binary Wave Format".
    """
    source = str(path)
    p = Path(path)
    if not p.is_file():
        raise ContactresInputError(f"{source}: no such file")
    raw = p.read_bytes()
    _check_sizes(raw, source)
    binarywave = _igor2()
    try:
        wave = binarywave.load(io.BytesIO(raw))["wave"]
        header = wave["wave_header"]
        values = np.asarray(wave["wData"])
    except (ValueError, TypeError, KeyError, IndexError, struct.error) as exc:
        raise ContactresInputError(
            f"{source}: truncated or not an Igor binary wave ({type(exc).__name__} in igor2)"
        ) from None
    if values.dtype.kind not in "iufc":
        raise ContactresInputError(f"{source}: a text wave ({values.dtype}), not a wave of numbers")
    values = values.astype(complex if values.dtype.kind == "c" else float)
    values.flags.writeable = False
    # whpad1 holds, after 3 reserved bytes, the encodings of the name, the units and the note.
    encoding = _header_byte(header.get("whpad1"), 5)
    note = parse_note(_decode(bytes(wave.get("note") or b""), encoding))
    name_code = _header_byte(header.get("whpad1"), 3)
    name = _decode(bytes(header.get("bname") or b""), name_code).strip("\x00")
    return IgorWave(
        data=values,
        # Labels are names (ASCII in practice): decoded as the note is.
        labels=_labels(wave, values.ndim, encoding),
        note=note,
        name=name,
        scale=_scale(header, note, encoding),
        source=source,
    )
