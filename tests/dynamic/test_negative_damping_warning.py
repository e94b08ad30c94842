"""Negative damping of the approximate displacement models is flagged at run time (issue 27,
point 7): the API warns as the CLI's table flags (``contactres dcsf``, tests/cli/test_cli_dcsf.py).

The warning is checked against the returned values themselves: it names a model exactly when
some of its values have Im DCSF < 0, and the k a span of those values.
"""

from __future__ import annotations

import re
import warnings

import numpy as np
import pytest

from contactres import Material
from contactres.dynamic import dcsf, dcsf_models, dynamic_contact_stiffness
from contactres.errors import ContactresWarning

MODELS = ("R0", "R1", "SA", "WA", "TP", "exact")


def _caught(fn, *args, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = fn(*args, **kwargs)
    return out, [w for w in caught if issubclass(w.category, ContactresWarning)]


def test_dcsf_models_warns_once_per_model_with_negative_damping():
    ka = np.linspace(0.5, 2.0, 7)
    out, caught = _caught(dcsf_models, Material.crystal("Cu"), ka, MODELS, loss=0.02)
    negative = {name for name, v in out.items() if np.any(v.imag < 0)}
    assert "R0" in negative and "exact" not in negative  # paper 1: R0 turns negative near 1.6-2
    named = [re.search(r"\((\w+) model\)", str(w.message)).group(1) for w in caught]
    assert sorted(named) == sorted(negative)
    for w in caught:
        text = str(w.message)
        name = re.search(r"\((\w+) model\)", text).group(1)
        where = ka[out[name].imag < 0]
        span = f"{where.min():.4g}" if where.size == 1 else f"{where.min():.4g}-{where.max():.4g}"
        assert f"k_l a = {span} " in text and "negative damping" in text


def test_dcsf_warns_and_a_caller_may_opt_out():
    cu = Material.crystal("Cu")
    value, caught = _caught(dcsf, cu, 2.0, "R0", loss=0.02)
    assert value.imag < 0 and len(caught) == 1 and "R0" in str(caught[0].message)
    _, caught = _caught(dcsf_models, cu, 2.0, ("R0",), loss=0.02, warn_negative=False)
    assert not caught
    value, caught = _caught(dcsf, cu, 2.0, "exact", loss=0.02)
    assert value.imag > 0 and not caught


@pytest.mark.parametrize("model", ["R0", "exact"])
def test_dynamic_contact_stiffness_warns_where_its_damping_is_negative(model):
    f = np.logspace(6, 8.5, 11)
    k, caught = _caught(dynamic_contact_stiffness, Material.crystal("Cu"), 1e-3, 1.0, f, model)
    assert bool(caught) == bool(np.any(k.imag < 0))
    assert bool(caught) == (model == "R0")
