"""Errors with a type: the user's input error is one line (exit 2); anything else is a fault of
contactres and says so (exit 1), a ValueError of numpy or pandas included (issue 25)."""

from __future__ import annotations

import click
import numpy as np
import pandas as pd
import pytest

from contactres.cli._app import App
from contactres.errors import ContactresInputError, MissingExtraError


def _run(exc: BaseException, capsys, monkeypatch) -> tuple[int, str]:
    monkeypatch.delenv("CONTACTRES_DEBUG", raising=False)

    @click.group(cls=App)
    def app() -> None:
        """A stand-in for the contactres group."""

    @app.command()
    def boom() -> None:
        raise exc

    with pytest.raises(SystemExit) as info:
        app.main(["boom"], prog_name="contactres")
    captured = capsys.readouterr()
    assert captured.out == ""
    return int(info.value.code), captured.err


def test_the_input_error_is_a_value_error():
    assert issubclass(ContactresInputError, ValueError)


def test_an_input_error_is_one_line_and_exit_2(capsys, monkeypatch):
    code, err = _run(
        ContactresInputError("x.csv, row 3, column df_Hz: 'a' is not a number"), capsys, monkeypatch
    )
    assert code == 2
    assert err == "contactres: error: x.csv, row 3, column df_Hz: 'a' is not a number\n"


@pytest.mark.parametrize(
    "exc",
    [
        np.linalg.LinAlgError("Singular matrix"),
        pd.errors.MergeError("Merge keys are not unique"),
        ValueError("operands could not be broadcast together"),
        KeyError("kappa"),
    ],
    ids=["LinAlgError", "MergeError", "ValueError", "KeyError"],
)
def test_anything_else_is_an_internal_error_not_the_users(exc, capsys, monkeypatch):
    code, err = _run(exc, capsys, monkeypatch)
    assert code == 1
    assert len(err.splitlines()) == 1
    assert err.startswith(f"contactres: internal error: {type(exc).__name__}: ")
    assert "please report" in err and "CONTACTRES_DEBUG=1" in err
    assert ": error: " not in err  # never dressed as the user's fault


def test_a_refusal_of_the_system_stays_a_one_line_error(capsys, monkeypatch, tmp_path):
    missing = tmp_path / "nope.csv"
    code, err = _run(
        FileNotFoundError(2, "No such file or directory", str(missing)), capsys, monkeypatch
    )
    assert code == 2
    assert err == f"contactres: error: {missing}: No such file or directory\n"


def test_debug_shows_the_traceback(monkeypatch):
    monkeypatch.setenv("CONTACTRES_DEBUG", "1")

    @click.group(cls=App)
    def app() -> None:
        """A stand-in."""

    @app.command()
    def boom() -> None:
        raise np.linalg.LinAlgError("Singular matrix")

    with pytest.raises(np.linalg.LinAlgError):
        app.main(["boom"], prog_name="contactres")


def test_a_missing_optional_extra_says_what_to_install(capsys, monkeypatch):
    """Not the user's input and not a bug: one line naming the extra, exit 2, no report asked."""
    message = "xarray is needed for polycrystal maps; install the optional extra: pip install x"
    code, err = _run(MissingExtraError(message), capsys, monkeypatch)
    assert code == 2
    assert err == f"contactres: error: {message}\n"
    # A plain ImportError (a module of contactres that does not import) is still internal.
    code, err = _run(ImportError("cannot import name 'nope'"), capsys, monkeypatch)
    assert code == 1 and "internal error: ImportError" in err
