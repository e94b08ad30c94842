"""The package's own exception: bad input, as opposed to a fault of contactres itself.

Every check of what a user gives contactres (a file, a table cell, an option, a physical
parameter) raises :class:`ContactresInputError`. It subclasses :class:`ValueError`, so code
written against earlier versions that catches ``ValueError`` keeps working. The command line
prints it as one line naming the input and the rule, and exits with status 2; any other
exception (numpy's ``LinAlgError``, pandas' ``MergeError``, a ``KeyError`` ...) is a fault of
contactres and is reported as an internal error, with a request to report it.

A value that contactres computed but could not bring to the accuracy it was asked for is not an
error: it is returned, and :class:`AccuracyWarning` says which value, and the accuracy reached.
"""

from __future__ import annotations

__all__ = ["AccuracyWarning", "ContactresInputError", "ContactresWarning", "MissingExtraError"]


class ContactresInputError(ValueError):
    """Input that breaks a stated rule; the message names the input, the value and the rule.

    Examples
    --------
    >>> from contactres.errors import ContactresInputError
    >>> issubclass(ContactresInputError, ValueError)
    True
    """


class MissingExtraError(ImportError):
    """An optional dependency is not installed; the message names the extra that brings it.

    Neither the user's input nor a fault of contactres: the command line prints it as one line
    (exit 2) saying what to install.
    """


class AccuracyWarning(UserWarning):
    """A computed value misses the accuracy it was asked for (``rtol``); the message names the
    input (material, arguments) and the estimated accuracy reached.

    Raised as a warning, not an error: the value returned is the best one found. Turn it into an
    error with ``warnings.simplefilter("error", AccuracyWarning)``.

    Examples
    --------
    >>> from contactres.errors import AccuracyWarning
    >>> issubclass(AccuracyWarning, UserWarning)
    True
    """


class ContactresWarning(UserWarning):
    """A result given with a reservation: computed from valid input, but outside the range
    where its theory holds (a Hertz contact wider than a tenth of its sphere, a/R > 0.1).

    The message names the quantity and the rule. To turn such results into errors:
    ``warnings.simplefilter("error", ContactresWarning)``.
    """
