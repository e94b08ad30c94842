"""The example files installed with contactres: what each one is, where it is, a copy of it.

The files live in the package (``contactres/data``), so an installed contactres has them
wherever it was installed: :func:`example_path` gives the path of one (to pass to a function or
a command), :func:`copy_examples` copies them into a folder of the user's (to open, edit or
hand to a command line that names them plainly, as the commands' ``--help`` examples do).
``contactres examples`` is the same on the command line.

Only the example inputs are listed (:data:`EXAMPLES`); the package's own tables of crystals and
materials beside them are data of the library, not examples.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from importlib.resources import files
from pathlib import Path
from types import MappingProxyType

from ._summary import Summarised, clipped
from .errors import ContactresInputError
from .fileio import ensure_dir, write_bytes

__all__ = ["EXAMPLES", "Example", "copy_examples", "example_path"]


# repr=False: the summary (Summarised, _facts) clips the description and leaves out the
# command (an attribute).
@dataclass(frozen=True, repr=False)
class Example(Summarised):
    """One example file.

    Attributes
    ----------
    name : str
        File name (in ``contactres/data``).
    description : str
        What the file holds, in one sentence.
    command : str
        A command that reads it, as run from a folder holding a copy of it.
    extra : str
        The optional extras that command needs (``pip install 'contactres[EXTRA]'``, comma
        separated), "" when the base install runs it.
    """

    name: str
    description: str
    command: str
    extra: str = ""

    def _facts(self) -> list[tuple[str, str]]:
        """The file's name, its description (clipped) and the extras its command needs."""
        facts = [("", repr(self.name)), ("", clipped(self.description))]
        return [*facts, ("extra", self.extra)] if self.extra else facts


def _example(name: str, description: str, command: str, extra: str = "") -> tuple[str, Example]:
    return name, Example(name, description, command, extra)


#: The example inputs, by file name, in the order of the workflows.
EXAMPLES: Mapping[str, Example] = MappingProxyType(
    dict(
        (
            _example(
                "example_sweeps.csv",
                "QCM amplitude sweeps in the manner of paper 2 (synthetic, known truth): 384 "
                "sweeps of SiO2 spheres of 1.1 and 0.6 mm radius on quartz, in air and water, "
                "four experiments",
                "contactres qcm analyze example_sweeps.csv --out qcm_results",
            ),
            _example(
                "example_spectra.csv",
                "admittance spectra (G, B against frequency) of a part of those sweeps, with "
                "the reference spectra of each overtone",
                "contactres qcm spectra example_spectra.csv --out sweeps.csv --fits fits.csv",
            ),
            _example(
                "example_qcmd.csv",
                "a QCM-D time series in the AWSensors export layout (Δf/n and D of overtones "
                "3, 5 and 7)",
                "contactres qcm stiffness example_qcmd.csv --dissipation-scale 1e-6 "
                "--fundamental 4.95e6 --area 2e-5 --n-contacts 3 --out qcmd_stiffness",
            ),
            _example(
                "example_particles.csv",
                "QCM-D shifts of 1 µm silica spheres adsorbing in water (synthetic, known "
                "truth): the tidy table time_s, overtone, df_Hz, dgamma_Hz of overtones 1-13 "
                "over an hour, the coupled resonance inside the overtone comb",
                "contactres qcm particles example_particles.csv --particle-radius 5e-7 "
                "--particle-density 2200 --fundamental 5e6 --medium water --out particles",
            ),
            _example(
                "example_afm.csv",
                "contact-resonance AFM frequencies of two flexural modes, free and in contact, "
                "per pixel, with the lever, tip and load",
                "contactres afm invert example_afm.csv --out afm_moduli.csv",
            ),
            _example(
                "example_rum.csv",
                "resonance-ultrasound-microscope frequencies, free and in contact, per pixel",
                "contactres rum invert example_rum.csv --out rum_kstar.csv",
            ),
            _example(
                "example_dart.ibw",
                "an Asylum Research DART image (Igor .ibw, 64 x 64 pixels over 2 µm, synthetic: "
                "a polymer film with a round stiffer inclusion, contact resonance 266 and 305 kHz "
                "on a 3 N/m lever with its tip at r = L1/L = 0.95, 20 nm Si tip at 50 nN; six "
                "layers and the instrument's note)",
                "contactres afm map example_dart.ibw --tip-position 0.95 --tip-radius 2e-8 "
                "--force 5e-8 --tip-modulus 1.65e11 --out cr-map",
                "afm,maps",  # igor2 reads the .ibw, xarray holds the maps
            ),
            _example(
                "example_cu_map.ang",
                "an EBSD orientation map of polycrystalline copper (64 x 64 pixels, TSL .ang)",
                "contactres maps predict example_cu_map.ang --crystal Cu --tip-radius 2e-8 "
                "--force 1e-6 --out cu_predicted.zarr",
                "maps",  # the Zarr store
            ),
            _example(
                "example_cu_kstar.csv",
                "a measured contact-stiffness map (N/m, 64 x 64 grid) on that copper map",
                "contactres maps fit example_cu_map.ang --values example_cu_kstar.csv "
                "--out cu_fit.json",
            ),
        )
    )
)


def _resource(name: str):
    if not isinstance(name, str) or name not in EXAMPLES:
        known = ", ".join(EXAMPLES)
        raise ContactresInputError(f"no example named {name!r}; the examples are: {known}")
    return files("contactres").joinpath("data").joinpath(name)


def example_path(name: str) -> Path:
    """The path of an installed example file.

    Parameters
    ----------
    name : str
        A key of :data:`EXAMPLES`, e.g. ``"example_sweeps.csv"``.

    Returns
    -------
    pathlib.Path
        The file inside the installed package (read it; do not write to it: copy it with
        :func:`copy_examples` to edit it).

    Raises
    ------
    ContactresInputError
        For a name that is not an example.

    Examples
    --------
    >>> from contactres import read_sweeps
    >>> from contactres.examples import example_path
    >>> table = read_sweeps(example_path("example_sweeps.csv"))
    >>> len(table), table.data["sweep"].nunique()
    (4608, 384)
    """
    resource = _resource(name)
    if not isinstance(resource, os.PathLike):  # a package imported from a zip archive
        raise RuntimeError(
            f"contactres is installed as an archive: {name} has no path of its own; copy it "
            "with copy_examples (or 'contactres examples --copy DIR')"
        )
    return Path(os.fspath(resource))


def copy_examples(
    folder: str | os.PathLike,
    names: str | Iterable[str] | None = None,
    *,
    overwrite: bool = False,
) -> list[Path]:
    """Copy example files into ``folder`` (created if missing), each written atomically.

    Parameters
    ----------
    folder : str or path-like
        Where the copies go.
    names : str or iterable of str, optional
        Keys of :data:`EXAMPLES` (one name as a string is one file); all of them by default.
    overwrite : bool
        Replace a file of the same name in ``folder``; by default such a file is kept and the
        copy refused (nothing is copied then).

    Returns
    -------
    list of pathlib.Path
        The copies, in the order of ``names``.

    Raises
    ------
    ContactresInputError
        For an unknown name, or a file of the same name already in ``folder`` (without
        ``overwrite``).
    """
    if isinstance(names, str):  # one name, not its letters
        names = [names]
    chosen = list(EXAMPLES) if names is None else list(dict.fromkeys(names))
    resources = [(name, _resource(name)) for name in chosen]  # every name checked first
    target = Path(folder)
    if not overwrite:
        present = [name for name in chosen if (target / name).exists()]
        if present:
            raise ContactresInputError(
                f"{target}: already holds {', '.join(present)}; nothing copied (to replace them: "
                "--overwrite on the command line, overwrite=True in Python)"
            )
    ensure_dir(target)
    return [write_bytes(target / name, resource.read_bytes()) for name, resource in resources]
