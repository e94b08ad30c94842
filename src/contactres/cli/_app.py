"""The click application: the ``contactres`` group and its one-line error handling."""

from __future__ import annotations

import importlib
import os
import sys
from collections.abc import Iterator, Mapping, MutableMapping

import click

from ..errors import ContactresInputError, MissingExtraError

# Errors that mean "the user's input is wrong" (raised by contactres' own checks, and only by
# them) or "the system refused" (a path through a file, a full disk, no permission): one line,
# exit code 2, no traceback. Any other exception, a ValueError of numpy or pandas included, is
# a fault of contactres and is reported as an internal error.
USER_ERRORS = (ContactresInputError, MissingExtraError, OSError)
# Longest error line printed (the messages cut long values themselves; this is the backstop).
MAX_MESSAGE_CHARS = 2000
#: The variables OpenBLAS reads, in this order, for the thread count it starts with; one set by
#: the user is the user's choice and is kept.
THREAD_COUNT_VARIABLES = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")


# click >= 8.2 raises this for a bare group; older click prints the help itself.
_NO_ARGS_IS_HELP = getattr(click.exceptions, "NoArgsIsHelpError", ())


def _one_line(text) -> str:
    if isinstance(text, OSError) and text.strerror:  # "[Errno 20] ..." -> "path: Not a directory"
        names = [str(n) for n in (text.filename, text.filename2) if n is not None]
        text = f"{' -> '.join(names)}: {text.strerror}" if names else text.strerror
    line = " ".join(str(text).split())
    if len(line) > MAX_MESSAGE_CHARS:
        line = line[: MAX_MESSAGE_CHARS - 1] + "…"
    return line


def one_blas_thread_from_start() -> bool:
    """Have OpenBLAS start with one thread in this process, if it is not loaded yet (the first
    step of :meth:`App.main` run as the program: the console script and ``python -m
    contactres``, which pass it no arguments).

    Sets ``OPENBLAS_NUM_THREADS=1`` in the environment unless numpy (which loads OpenBLAS) is
    imported already, when the count is fixed and this changes nothing, or the user has set one
    of :data:`THREAD_COUNT_VARIABLES`. Every command runs its BLAS work inside
    :func:`contactres._threads.one_blas_thread` anyway; what this saves is the spinning of the
    threads OpenBLAS starts when it is loaded, which no later limit stops (~0.1 s of CPU each
    on an idle machine: :mod:`contactres._threads`). Child processes started afterwards (an
    analysis's workers) inherit the variable, as they inherit one thread from a fork inside a
    context. A program that runs a command in-process (``main([...])``, click's ``CliRunner``)
    is not the command line's: its environment, which it and its children keep for the rest of
    their lives, is left alone.

    Returns
    -------
    bool
        True if the variable was set.

    Examples
    --------
    >>> import numpy
    >>> from contactres.cli._app import one_blas_thread_from_start
    >>> one_blas_thread_from_start()  # numpy is loaded: too late, nothing is set
    False
    """
    if "numpy" in sys.modules or any(name in os.environ for name in THREAD_COUNT_VARIABLES):
        return False
    os.environ["OPENBLAS_NUM_THREADS"] = "1"
    return True


class LazyCommands(MutableMapping[str, click.Command]):
    """The commands of a group by name (click's ``Group.commands``), each registered by the
    module of :mod:`contactres.cli` that defines it when that module is first imported.

    A command looked up by name (click's ``get_command``: the command to run, or whose help is
    asked) imports its own module only; listing the commands (a group's help, iterating,
    ``len``) imports every module first, so a listing is always the whole group. The start of
    a command thus skips the imports of the other commands' modules (issue 31, point 5: ~5 %
    of the instructions of ``afm invert`` of a 512² map).

    Parameters
    ----------
    modules : mapping of str to str
        Command name -> module of :mod:`contactres.cli` (without the package) that registers
        it on this group; several commands may share a module.
    """

    def __init__(self, modules: Mapping[str, str]):
        self._modules = dict(modules)  # names whose module is not imported yet
        self._known: dict[str, click.Command] = {}

    def _import(self, module: str) -> None:
        # Importing the module runs its decorators: they register its commands via __setitem__.
        importlib.import_module(f"{__package__}.{module}")
        self._modules = {n: m for n, m in self._modules.items() if m != module}

    def _import_all(self) -> None:
        while self._modules:
            self._import(next(iter(self._modules.values())))

    def __getitem__(self, name: str) -> click.Command:
        if name not in self._known and name in self._modules:
            self._import(self._modules[name])
        return self._known[name]

    def __setitem__(self, name: str, command: click.Command) -> None:
        self._known[name] = command

    def __delitem__(self, name: str) -> None:
        self[name]  # its module imported first: a later import would register it again
        del self._known[name]

    def __iter__(self) -> Iterator[str]:
        self._import_all()
        return iter(self._known)

    def __len__(self) -> int:
        self._import_all()
        return len(self._known)


class App(click.Group):
    """A click group that turns every error into one readable line on stderr."""

    def main(self, args=None, prog_name=None, complete_var=None, **extra):
        extra.pop("standalone_mode", None)
        # Before a command's module imports numpy: OpenBLAS's threads would spin at its load
        # (~0.1 s of CPU each on an idle machine) for work the jobs run on one thread. Only as
        # the program (no arguments given, the command line's own): a caller that passes its
        # arguments runs the command in-process, and its environment is its own to keep.
        if args is None:
            one_blas_thread_from_start()
            # Likewise glibc's allocator keeps freed memory for the next array, as in the
            # analyses' worker processes (contactres._allocator: ~0.9 s less of system CPU of
            # `qcm analyze` at 10^5 sweeps); a caller's process keeps its own allocator.
            from .._allocator import keep_freed_memory

            keep_freed_memory()
        prog = prog_name or "contactres"
        try:
            rv = super().main(
                args=args,
                prog_name=prog,
                complete_var=complete_var,
                standalone_mode=False,
                **extra,
            )
        except click.exceptions.Abort:
            click.echo(f"{prog}: aborted", err=True)
            sys.exit(1)
        except _NO_ARGS_IS_HELP as exc:
            # A bare group (e.g. plain "contactres") shows its help, as a new user expects.
            click.echo(exc.ctx.get_help())
            sys.exit(0)
        except click.UsageError as exc:
            where = exc.ctx.command_path if exc.ctx is not None else prog
            click.echo(
                f"{where}: error: {_one_line(exc.format_message())} (see '{where} --help')",
                err=True,
            )
            sys.exit(2)
        except click.ClickException as exc:
            click.echo(f"{prog}: error: {_one_line(exc.format_message())}", err=True)
            sys.exit(exc.exit_code)
        except USER_ERRORS as exc:
            if os.environ.get("CONTACTRES_DEBUG"):
                raise
            click.echo(f"{prog}: error: {_one_line(exc)}", err=True)
            sys.exit(2)
        except Exception as exc:
            if os.environ.get("CONTACTRES_DEBUG"):
                raise
            click.echo(
                f"{prog}: internal error: {type(exc).__name__}: {_one_line(exc)} (a fault of "
                "contactres, not of your input: please report it, with the command; set "
                "CONTACTRES_DEBUG=1 for a traceback)",
                err=True,
            )
            sys.exit(1)
        sys.exit(rv if isinstance(rv, int) else 0)


#: Where each command is defined: group ("" the top level) -> command -> module of
#: contactres.cli that registers it (:class:`LazyCommands` imports it when it is needed).
#: tests/cli/test_cli_lazy.py checks this against the modules and what they register.
COMMAND_MODULES: Mapping[str, Mapping[str, str]] = {
    "": {
        "contact": "contact",
        "crystals": "crystals",
        "dcsf": "dcsf",
        "demo": "demo",
        "examples": "examples",
    },
    "qcm": {
        "analyze": "qcm_analyze",
        "loop": "qcm_loop",
        "particles": "qcm_particles",
        "spectra": "qcm_spectra",
        "stiffness": "qcm_stiffness",
    },
    "afm": {"invert": "afm_invert", "map": "afm_map"},
    "rum": {"invert": "rum_invert"},
    "maps": {"synthetic": "maps", "predict": "maps", "fit": "maps"},
    "figures": {"paper1": "figures_paper1", "paper2": "figures_paper2"},
}


@click.group(
    cls=App,
    commands=LazyCommands(COMMAND_MODULES[""]),
    context_settings={"help_option_names": ["-h", "--help"]},
)
# package_name: click reads the installed version only when --version is given, so that
# neither the library nor importlib.metadata is imported to build the command tree.
@click.version_option(None, "--version", "-V", package_name="contactres", prog_name="contactres")
def main() -> None:
    """contactres: contact mechanics at resonance.

    Forward models of normal, tangential and dynamic contacts, and the analysis of QCM amplitude
    sweeps. SI units everywhere (m, N, Pa, Hz, kg); an option may carry its unit instead
    (--radius 1.1mm, --force 2mN). Run 'contactres COMMAND --help' for details.
    """


@main.group(commands=LazyCommands(COMMAND_MODULES["qcm"]))
def qcm() -> None:
    """Quartz crystal microbalance: contact loops and amplitude-sweep analysis (paper 2)."""


@main.group(commands=LazyCommands(COMMAND_MODULES["afm"]))
def afm() -> None:
    """Contact-resonance AFM: resonances of the coupled lever -> contact stiffness -> modulus."""


@main.group(commands=LazyCommands(COMMAND_MODULES["rum"]))
def rum() -> None:
    """Resonance ultrasound microscope: contact resonance -> contact stiffness."""


@main.group(commands=LazyCommands(COMMAND_MODULES["maps"]))
def maps() -> None:
    """Polycrystal maps: EBSD orientations -> M and k* per pixel, and back to the constants."""


@main.group(commands=LazyCommands(COMMAND_MODULES["figures"]))
def figures() -> None:
    """Reproduce the figures of the two core papers (figures in --figure-format, data as CSV)."""
