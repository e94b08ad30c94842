"""Job ``afm_map``: a contact-resonance map from the instrument's file -> maps of k*, σ, tan δ,
E* and M (:func:`contactres.invert_cr_map`).

Inputs: the path of one map file, or a :class:`MapInput` already in memory:

* an Asylum Research DART image (``.ibw``, :func:`contactres.read_ibw`): the layers
  ``Amplitude1``, ``Amplitude2``, ``Phase1``, ``Phase2`` (degrees) and ``Frequency`` (the
  tracked centre, :func:`contactres.measurements.dart_frequency_Hz`), found by label; the two
  drives at f_c ∓ Δf/2, Δf the note's ``DFRTFrequencyWidth`` (or ``Settings.frequency_width``),
  and per pixel f0 and Q by :func:`contactres.analysis.dart_reconstruction`;
* a band-excitation SHO fit (``.h5``, BGlib's layout, :func:`contactres.measurements.read_be_sho`):
  frequency and Q per pixel;
* a grid of frequency and Q (``.nc`` or ``.zarr``,
  :func:`contactres.measurements.read_resonance_grid`).

The lever: k_c, the free frequency f_free and the free Q from the settings where given, else
from the note (``SpringConstant``, ``ThermalFrequency``, ``ThermalQ`` of an Asylum note); the
option wins and the note's value is reported beside it (``conventions["lever"]``). A missing
constant is one line naming the option to give.

Phases. The reconstruction takes the lag of the response (rising through the resonance). An
instrument may store the opposite sign; ``Settings.phase_sign`` says which ("lag", "lead"), and
"auto" takes the sign under which the phase rises from f1 to f2 on most pixels (the only one
a damped oscillator allows), recorded in the conventions. A constant offset cancels.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .._threads import one_blas_thread
from ..errors import ContactresInputError, MissingExtraError
from .contract import JobResult, Progress, say

if TYPE_CHECKING:
    import os

    from ..analysis import ModulusModel
    from ..measurements.readers import Readers

__all__ = [
    "DART_LAYERS",
    "PHASE_SIGNS",
    "MapInput",
    "Result",
    "Settings",
    "read_input",
    "run",
    "series",
]

#: The layers of a DART image the map needs (found by label; ``Retrace`` first).
DART_LAYERS = ("Amplitude1", "Amplitude2", "Phase1", "Phase2", "Frequency")
#: How the file's phases relate to the oscillator's lag (module notes).
PHASE_SIGNS = ("auto", "lag", "lead")


@dataclass(frozen=True, eq=False)
class MapInput:
    """One map as read (all maps (y, x)).

    Attributes
    ----------
    frequency : the resonance frequency (BE, grid) or the DART drives' centre f_c, Hz
    q_factor : Q per pixel, or None (DART: reconstructed)
    dart : (A1, A2, phase1, phase2) of a DART image (amplitudes in one unit, phases in degrees
        as stored), or None
    amplitude_unit : the unit of the amplitudes A1, A2 (and so of the reconstructed drive
        amplitude): "m" for an Asylum image (its amplitude layers are deflections in m,
        InvOLS applied by the instrument); "1" when not known
    note : the instrument's settings (an Asylum note), or {}
    pixel_size : (dx, dy) or one square pitch, m; or None
    source : the file read (or a name)
    """

    frequency: np.ndarray
    q_factor: np.ndarray | None = None
    dart: tuple | None = None
    note: dict = field(default_factory=dict)
    pixel_size: float | tuple[float, float] | None = None
    source: str = "map"
    amplitude_unit: str = "1"


@dataclass(frozen=True)
class Settings:
    """How to turn the map into physics.

    Parameters
    ----------
    spring_constant, free_frequency, free_q : float or None
        k_c (N/m), the free lever's mode-1 frequency (Hz) and Q; None: from the note.
    tip_position, lateral_ratio, tip_height, tilt : float
        r = L1/L, α = k_lat/k*, η = h/L, tilt (degrees)
        (:func:`contactres.invert_contact_resonance`).
    modulus : ModulusModel or None
        Hertz, flat punch or a reference region (:class:`contactres.analysis.ModulusModel`);
        None: k*, σ and tan δ only.
    frequency_width : float or None
        The DART drive separation Δf, Hz; None: the note's ``DFRTFrequencyWidth``.
    phase_sign : str
        "auto", "lag" or "lead" (module notes).
    min_sin : float
        Smallest ``|sin(φ2 − φ1)|`` the reconstruction solves.
    """

    spring_constant: float | None = None
    free_frequency: float | None = None
    free_q: float | None = None
    tip_position: float = 1.0
    lateral_ratio: float = 0.0
    tip_height: float = 0.0
    tilt: float = 0.0
    modulus: ModulusModel | None = None
    frequency_width: float | None = None
    phase_sign: str = "auto"
    min_sin: float = 1e-3


@dataclass(frozen=True)
class Result(JobResult):
    """``dataset``: the maps (an :mod:`xarray` Dataset, :func:`contactres.invert_cr_map`, plus
    the DART flags and drive amplitude of a DART image); ``source``: the file; ``conventions``:
    units, the sign of the phases, the equations, the lever's constants (option and note);
    ``summary``: pixel counts and medians."""

    NOT_VALUES = ("dataset", "warnings")
    NAME = "afm_map"

    dataset: object
    source: str
    conventions: dict
    summary: dict
    warnings: tuple[str, ...] = ()

    def input_files(self) -> tuple[str, ...]:
        return (self.source,) if Path(self.source).exists() else ()


def read_input(path: str | os.PathLike, readers: Readers | None = None) -> MapInput:
    """The map of the file ``path``, read by the ``afm_map`` recipe that recognises it
    (:func:`contactres.jobs.readers.read_afm_map_file`: its suffix first, then its first
    bytes)."""
    from ..measurements import IgorWave, check_frequency_map, dart_frequency_Hz
    from .readers import ALL_READERS, read_afm_map_file

    read = read_afm_map_file(path, ALL_READERS if readers is None else readers)
    if not isinstance(read, IgorWave):  # frequency and Q per pixel (ResonanceMaps)
        return MapInput(
            frequency=check_frequency_map(read.frequency_Hz, str(read.source)),
            q_factor=np.asarray(read.q_factor, dtype=float),
            pixel_size=None if read.pixel_size is None else tuple(read.pixel_size),
            source=str(read.source),
        )
    layers = [np.asarray(read.layer(name), dtype=float) for name in DART_LAYERS[:4]]
    centre = dart_frequency_Hz(read)
    if any(layer.T.shape != centre.shape for layer in layers):
        raise ContactresInputError(f"{path}: the DART layers are not images of one shape")
    return MapInput(
        frequency=np.asarray(centre, dtype=float),
        dart=tuple(layer.T for layer in layers),  # Igor's first index runs along x
        note=dict(read.note),
        pixel_size=read.scale,  # (dx, dy) or None
        source=str(path),
        amplitude_unit="m",  # Asylum stores its amplitude layers in m
    )


def _note_number(note, key):
    value = note.get(key)
    return float(value) if isinstance(value, float) and np.isfinite(value) else None


def _lever(data: MapInput, s: Settings):
    """(Cantilever, record of each constant: option, note, used)."""
    from ..resonators import Cantilever

    keys = {
        "spring_constant_N_per_m": ("spring_constant", "SpringConstant", "--spring-constant N/m"),
        "free_frequency_Hz": ("free_frequency", "ThermalFrequency", "--free-frequency HZ"),
        "free_q": ("free_q", "ThermalQ", "--free-q"),
    }
    record, used = {}, {}
    for name, (attr, key, option) in keys.items():
        option_value, note_value = getattr(s, attr), _note_number(data.note, key)
        value = option_value if option_value is not None else note_value
        record[name] = {"option": option_value, "note": note_value, "note_key": key, "used": value}
        if value is None and name != "free_q":  # without a free Q: no lever damping removed
            where = f"the note of {data.source}" if data.note else f"{data.source} (no note)"
            raise ContactresInputError(f"no {key} in {where}: give {option}")
        used[name] = value
    q = used["free_q"]
    lever = Cantilever(
        (used["free_frequency_Hz"],),
        used["spring_constant_N_per_m"],
        free_q_factors=None if q is None else (q,),
    )
    return lever, record


def _phase_sign(delta, sign: str) -> tuple[str, str]:
    """ "lag" or "lead" (module notes) and how it was chosen."""
    if sign not in PHASE_SIGNS:
        raise ContactresInputError(f"phase_sign must be one of {PHASE_SIGNS}, got {sign!r}")
    if sign != "auto":
        return sign, "given"
    s = np.sin(delta[np.isfinite(delta)])
    rising = np.count_nonzero(s > 0) >= np.count_nonzero(s < 0)
    how = "auto: the sign under which the phase rises from f1 to f2 on most pixels"
    return ("lag" if rising else "lead"), how


def _reconstruct(data: MapInput, s: Settings):
    """(f0, Q, extra variables, conventions) of a DART map."""
    from ..analysis import DART_FLAGS, dart_reconstruction

    width_note = _note_number(data.note, "DFRTFrequencyWidth")
    width = s.frequency_width if s.frequency_width is not None else width_note
    if width is None or not width > 0:
        raise ContactresInputError(
            f"no DART drive separation: the note of {data.source} has no DFRTFrequencyWidth; "
            "give --frequency-width (Hz)"
        )
    assert data.dart is not None  # run reconstructs only a map read with its DART layers
    a1, a2, p1, p2 = (np.asarray(x, dtype=float) for x in data.dart)
    p1, p2 = np.radians(p1), np.radians(p2)  # Asylum stores phases in degrees
    sign, how = _phase_sign(p2 - p1, s.phase_sign)
    factor = 1.0 if sign == "lag" else -1.0
    fc = data.frequency
    r = dart_reconstruction(
        fc - width / 2, fc + width / 2, a1, a2, factor * p1, factor * p2, min_sin=s.min_sin
    )
    if not np.isfinite(r.f0).any() and np.isfinite(fc).any():
        # Every tracked pixel voided: the phases read with the wrong sign (the phase then falls
        # from f1 to f2, which no damped oscillator does) or a wrong drive separation, not an
        # empty map; say which flags and what to check.
        counts = [
            f"{int(np.count_nonzero(r.flags & bit))} {name}"
            for bit, (name, _) in DART_FLAGS.items()
            if np.any(r.flags & bit)
        ]
        raise ContactresInputError(
            f"{data.source}: the DART reconstruction gives no resonance on any pixel "
            f"({', '.join(counts)} of {r.flags.size}; phases read as the {sign} ({s.phase_sign}), "
            f"drives {width:g} Hz apart): check --phase-sign and --frequency-width"
        )
    extra = {
        "dart_flags": (r.flags.astype(np.int32), "1"),
        "drive_amplitude": (r.A_drive, data.amplitude_unit),  # the unit of A1, A2
    }
    conv = {
        "dart": {
            "equations": "damped harmonic oscillator from two drives (Gannepalli et al., "
            "Nanotechnology 22, 355705 (2011) and corrigendum 24, 159501 (2013))",
            "drives_Hz": "f_c - width/2, f_c + width/2",
            "frequency_width_Hz": {
                "option": s.frequency_width,
                "note": width_note,
                "used": width,
            },
            "phase_unit": "degree (as stored)",
            "phase_sign": sign,
            "phase_sign_chosen": how,
            "min_sin_delta": s.min_sin,
            "flag_bits": {str(bit): text for bit, (_, text) in DART_FLAGS.items()},
        }
    }
    return r.f0, r.Q, extra, conv


def _summary(ds) -> dict:
    def median(name):
        v = ds[name].values
        v = v[np.isfinite(v)]
        return float(np.median(v)) if v.size else None

    out: dict[str, object] = {"shape": list(ds["k_star_N_per_m"].shape)}
    out["pixels_with_k_star"] = int(np.isfinite(ds["k_star_N_per_m"].values).sum())
    out["pixels_flagged"] = int((ds["flags"].values != 0).sum())
    out["pixels_modulus_flagged"] = int((ds["modulus_flags"].values != 0).sum())
    for name in ("k_star_N_per_m", "sigma_N_s_per_m", "tan_delta", "E_star_Pa", "M_Pa"):
        out[f"median_{name}"] = median(name)
    return out


def _map_flag_warnings(ds) -> list[str]:
    """One line per map flag (:data:`contactres.analysis.CR_MAP_FLAGS`) that pixels have."""
    from ..analysis import CR_MAP_FLAGS

    lines = []
    for bit, (name, text) in CR_MAP_FLAGS.items():
        n = int(np.count_nonzero(ds["flags"].values & bit))
        if n:
            lines.append(f"{n} pixels flagged {name}: {text}")
    return lines


#: The options behind each way to the modulus (for the warning where M is NaN).
_MODULUS_OPTIONS = {
    "hertz": "--force/--tip-radius (N, m)",
    "punch": "--punch-radius (m)",
    "reference": "--reference/--reference-modulus",
}


def _modulus_warnings(ds, method: str) -> list[str]:
    """One line when a modulus was asked for and M is NaN on pixels that have k*: how many,
    the flags' meanings (:data:`contactres.analysis.FLAG_DESCRIPTIONS`) and the options."""
    from ..analysis import FLAG_DESCRIPTIONS

    if method not in _MODULUS_OPTIONS:
        return []
    lacking = np.isfinite(ds["k_star_N_per_m"].values) & ~np.isfinite(ds["M_Pa"].values)
    n = int(np.count_nonzero(lacking))
    if not n:
        return []
    seen = int(np.bitwise_or.reduce(ds["modulus_flags"].values[lacking], axis=None))
    texts = [text for bit, text in FLAG_DESCRIPTIONS.items() if seen & int(bit)]
    why = "; ".join(texts) if texts else "no modulus"
    return [f"M is NaN on {n} pixels: {why}; check {_MODULUS_OPTIONS[method]} and --tip-modulus"]


@one_blas_thread()
def run(
    inputs: str | os.PathLike | MapInput, settings: Settings, progress: Progress | None = None
) -> Result:
    """The maps of physics of one map file (see the module docstring)."""
    from ..analysis import invert_cr_map

    s = settings
    if isinstance(inputs, MapInput):
        data = inputs
    else:
        say(progress, f"reading {Path(inputs).name}")
        data = read_input(inputs)
    lever, lever_record = _lever(data, s)
    conventions: dict = {"source": data.source, "lever": lever_record}
    extra: dict = {}
    if data.dart is not None:
        say(progress, f"DART reconstruction of {data.frequency.size} pixels")
        f0, q, extra, conv = _reconstruct(data, s)
        conventions.update(conv)
    else:
        f0, q = data.frequency, data.q_factor
        conventions["phases"] = "not used (frequency and Q given per pixel)"
    say(progress, f"inverting {np.count_nonzero(np.isfinite(f0))} pixels (mode 1)")
    ds = invert_cr_map(
        f0,
        q,
        lever,
        tip_position=s.tip_position,
        lateral_ratio=s.lateral_ratio,
        tip_height=s.tip_height,
        tilt=s.tilt,
        modulus=s.modulus,
        pixel_size=data.pixel_size,
        conventions=conventions,
    )
    for name, (values, unit) in extra.items():
        ds[name] = (("y", "x"), values, {"units": unit})
    conventions = json.loads(ds.attrs["conventions"])
    warnings = []
    if lever.free_q_factors is None and np.isfinite(ds["sigma_N_s_per_m"].values).any():
        warnings.append(
            "no free Q (ThermalQ in the note, or --free-q): σ and tan δ include the lever's own "
            "damping"
        )
    if not np.isfinite(ds["k_star_N_per_m"].values).any():
        warnings.append("no pixel gave a contact stiffness: check the lever's constants")
    warnings += _map_flag_warnings(ds)
    warnings += _modulus_warnings(ds, conventions["modulus"]["method"])
    return Result(
        dataset=ds,
        source=data.source,
        conventions=conventions,
        summary=_summary(ds),
        warnings=tuple(warnings),
    )


def series(paths, settings: Settings, scheduler: str | None = None, progress=None):
    """:func:`run` on each map of a series, on a dask cluster when ``scheduler`` is given (one
    task per map; each map calibrated against its own reference region: tip wear)."""
    if scheduler is None:
        return [run(p, settings, progress) for p in paths]
    try:
        import distributed
    except ImportError as exc:  # pragma: no cover - the test environment has the extra
        raise MissingExtraError(
            "dask.distributed is needed for --scheduler; install the optional extra: "
            "pip install 'contactres[maps]'"
        ) from exc
    say(progress, f"{len(paths)} maps on {scheduler}")
    with distributed.Client(scheduler) as client:
        return client.gather(client.map(run, list(paths), settings=settings, pure=False))
