"""Tests of the plausible magnitudes in ``contactres.units`` and of ``check_magnitude``.

The inside/outside values are physical data written out here (Cu C11, a 5 MHz quartz, ...), not
read from the module, so that a range that drifts away from them fails.
"""

import math

import numpy as np
import pytest

from contactres.units import (
    MAX_AMPLITUDE_M,
    POISSON_OPEN_RANGE,
    QUANTITIES,
    check_magnitude,
    format_number,
    unit_slip,
)

# quantity -> (plausible values, implausible values, unit in the message)
TABLE = {
    "amplitude": ([0.0, 1e-9, 20e-9, 1e-6], [2e-6, 20.0], "m"),
    "displacement": ([0.0, 1e-9, 1e-6], [1.5e-6, 1.0], "m"),
    "sphere_radius": ([1e-9, 20e-9, 100e-6, 1.0], [5e-10, 2.0], "m"),
    # paper 2's 1.1 mm sphere ... a 5 cm ball; 0.6 and 1 are radii in mm typed as m (issue 30)
    "qcm_sphere_radius": ([1e-9, 20e-6, 1.1e-3, 0.05], [5e-10, 0.06, 0.6, 1.0], "m"),
    # a 20 nm vesicle ... a 100 µm cell; 0.5 is a radius in µm typed as m (issue 30)
    "particle_radius": ([1e-9, 20e-9, 5e-7, 100e-6, 5e-3], [5e-10, 0.01, 0.5], "m"),
    # a 2 nm sharp tip ... a 25 µm colloidal probe; 20 is a radius in nm typed as m
    "tip_radius": ([1e-9, 2e-9, 5e-8, 25e-6, 1e-3], [5e-10, 2e-3, 20.0], "m"),
    "contact_radius": ([1e-10, 5e-6, 1.0], [5e-11, 5.0], "m"),
    # a TKD map's 2 nm step ... an SEM EBSD map's 0.5 µm ... a 1 mm overview scan
    "pixel_size": ([1e-10, 2e-9, 0.5e-6, 1e-3, 1e-2], [5e-11, 0.5, -1e-6], "m"),
    "force": ([1e-12, 5e-3, 1e3], [1e-13, 2e3], "N"),
    # soft rubber 1e5 Pa ... Cu C11 168.4 GPa ... diamond C11 1.08 TPa
    "modulus": ([1e5, 168.4e9, 1.08e12, 1e13], [9e4, 165.7, 2e13], "Pa"),
    "stress": ([1e2, 20e6, 1e11], [50.0, 2e11], "Pa"),
    # a gel ~1e5 Pa ... diamond's M ~1.2 TPa
    "sample_modulus": ([1e5, 3e9, 1.2e12], [5e4, 2e12], "Pa"),
    "stiffness": ([1e-3, 0.1, 4e5, 1e12], [5e-4, 2e12], "N/m"),
    # a contact-mode lever 0.006 N/m ... CR-AFM levers 1-50 N/m; 1e5 N/m is a contact's k*
    "lever_stiffness": ([1e-3, 0.006, 3.0, 45.0, 1e3], [5e-4, 2e3, 1e5], "N/m"),
    "friction": ([0.01, 0.8, 50.0], [0.0, 51.0], ""),
    "drag": ([0.0, 1e-3, 1e5], [2e5], "kg/s"),
    # water 1000, Cu 8960, osmium 22590 kg/m³
    "density": ([1e2, 1000.0, 8960.0, 22590.0, 3e4], [8.96, 4e4], "kg/m^3"),
    "frequency": ([1e3, 5e6, 1e10], [5.0, 2e10], "Hz"),
    # a 1 inch QCM electrode, ~0.2-1 cm²
    "area": ([1e-8, 2e-5, 1e-4, 1e-2], [5e-9, 0.5], "m^2"),
    # AT-cut quartz d26 = 3.1 pm/V; 3.3 is a value in pm/V typed as m/V
    "piezo_constant": ([1e-13, 3.1e-12, 1e-10], [5e-14, 3.3, 0.0], "m/V"),
    "amplitude_calibration": ([1e-13, 2e-9, 1e-5], [5e-14, 2.0, 0.0], "m/V"),
    # 50 Ω and 75 Ω
    "reference_impedance": ([1e-3, 50.0, 75.0, 1e6], [5e-4, 2e6, -5.0], "ohm"),
    # AT-cut quartz 8.8e6 kg m^-2 s^-1
    "impedance": ([1e5, 8.8e6, 1e9], [8.8, 2e9], "kg m^-2 s^-1"),
    "zener": ([0.01, 0.5, 3.2, 100.0], [0.0, 1e-3, 1e3], ""),
    "poisson": ([-0.99, 0.0, 0.25, 0.49], [-1.0, 0.5, 0.7], ""),
    "loss": ([0.0, 0.02, 0.99], [1.0, 2.0], ""),
    "ka": ([0.0, 1.0, 60.0], [61.0], ""),
    "rtol": ([1e-10, 1e-6, 0.5], [1e-11, 1.0], ""),
    # κ of two cantilever modes 0.01 % ... 5 % (default) ... 100 % apart
    "mode_tolerance": ([1e-4, 0.05, 1.0], [5e-5, 5.0], ""),
    "overtone": ([1, 3, 999], [0, 1001], ""),
    "contacts": ([1, 1000, 1e12], [0, 2e12], ""),
}


def test_every_quantity_is_in_the_table():
    assert set(QUANTITIES) == set(TABLE)


def test_ranges_agree_with_the_other_rules_of_the_module():
    assert QUANTITIES["amplitude"].hi == MAX_AMPLITUDE_M
    assert (QUANTITIES["poisson"].lo, QUANTITIES["poisson"].hi) == POISSON_OPEN_RANGE


@pytest.mark.parametrize("quantity", sorted(TABLE))
def test_plausible_values_pass_as_floats_and_as_text(quantity):
    for v in TABLE[quantity][0]:
        assert check_magnitude(quantity, v, "--x") == v
        assert check_magnitude(quantity, repr(float(v)), "--x") == v


@pytest.mark.parametrize("quantity", sorted(TABLE))
def test_implausible_values_fail_in_one_line_naming_option_value_and_range(quantity):
    unit = TABLE[quantity][2]
    for v in TABLE[quantity][1]:
        with pytest.raises(ValueError) as info:
            check_magnitude(quantity, str(v), "--opt")
        message = str(info.value)
        assert "\n" not in message and "np.float64" not in message
        assert message.startswith(f"--opt {v} is ")
        assert QUANTITIES[quantity].name in message
        assert unit in message


@pytest.mark.parametrize("quantity", sorted(TABLE))
@pytest.mark.parametrize("bad, why", [("nan", "not a finite number"), ("inf", "not a finite")])
def test_nan_and_inf_are_refused(quantity, bad, why):
    with pytest.raises(ValueError, match=f"^--v {bad} is {why}"):
        check_magnitude(quantity, bad, "--v")


@pytest.mark.parametrize("quantity", ["amplitude", "drag", "loss", "ka", "force", "modulus"])
def test_negative_is_named_as_such(quantity):
    with pytest.raises(ValueError, match=r"^--v -1 is negative: the .* lies in \["):
        check_magnitude(quantity, "-1", "--v")


def test_text_is_the_value_as_typed_and_not_a_number_is_refused():
    with pytest.raises(ValueError, match=r"^--u0 2e\+01 \(in 0:2e\+01:3\) is outside"):
        check_magnitude("amplitude", 20.0, "--u0", text="2e+01 (in 0:2e+01:3)")
    with pytest.raises(ValueError, match=r"^--kappa 'abc' is not a number: the contact stiff"):
        check_magnitude("stiffness", " abc ", "--kappa")
    with pytest.raises(ValueError, match="unknown quantity 'length'"):
        check_magnitude("length", 1.0, "--x")


def test_allow_zero_and_signed():
    with pytest.raises(ValueError) as info:
        check_magnitude("force", 0.0, "--force")
    assert str(info.value) == (
        "--force 0 is outside the plausible range: the normal force per contact lies in "
        "[1e-12, 1000] N"
    )
    assert check_magnitude("force", 0.0, "--force", allow_zero=True) == 0.0
    with pytest.raises(ValueError, match=r"lies in \[1e-12, 1000\] N or is 0$"):
        check_magnitude("force", 1e-13, "--force", allow_zero=True)
    # C12 may be negative (a cubic crystal needs only C11 > |C12|): the magnitude is judged
    assert check_magnitude("modulus", -4.7e9, "--c12", signed=True) == -4.7e9
    with pytest.raises(ValueError, match=r"^--c12 -4.7 is outside .*±\[1e5, 1e13\] Pa"):
        check_magnitude("modulus", "-4.7", "--c12", signed=True, allow_zero=True)
    with pytest.raises(ValueError, match=r"gigapascals \(-4.7 GPa = -4.7e9 Pa\)"):
        check_magnitude("modulus", "-4.7", "--c12", signed=True)


def test_accepts_works_element_wise_on_arrays():
    q = QUANTITIES["force"]
    got = q.accepts(np.array([0.0, 1e-13, 1e-3, np.nan, np.inf, 2e3]), allow_zero=True)
    assert got.tolist() == [True, False, True, False, False, False]
    assert q.accepts(np.array([0.0, 1e-3])).tolist() == [False, True]


# (quantity, typed, the suggestion): every slip of every quantity, worked out by hand.
SLIPS = [
    ("amplitude", 1e-5, "millimetres (1e-5 mm = 1e-8 m)"),
    ("amplitude", 0.01, "micrometres (0.01 µm = 1e-8 m)"),
    ("amplitude", 20, "nanometres (20 nm = 2e-8 m)"),
    ("displacement", 2e-6, "millimetres (2e-6 mm = 2e-9 m)"),
    ("displacement", 0.01, "micrometres (0.01 µm = 1e-8 m)"),
    ("displacement", 5, "nanometres (5 nm = 5e-9 m)"),
    ("sphere_radius", 2, "millimetres (2 mm = 0.002 m)"),
    ("sphere_radius", 100, "micrometres (100 µm = 1e-4 m)"),
    ("sphere_radius", 1e6, "nanometres (1e6 nm = 0.001 m)"),
    ("qcm_sphere_radius", 0.6, "millimetres (0.6 mm = 6e-4 m)"),
    ("qcm_sphere_radius", 1, "millimetres (1 mm = 0.001 m)"),
    ("qcm_sphere_radius", 500, "micrometres (500 µm = 5e-4 m)"),
    ("qcm_sphere_radius", 1e6, "nanometres (1e6 nm = 0.001 m)"),
    ("particle_radius", 0.5, "micrometres (0.5 µm = 5e-7 m)"),
    ("particle_radius", 500, "nanometres (500 nm = 5e-7 m)"),
    ("tip_radius", 0.05, "micrometres (0.05 µm = 5e-8 m)"),
    ("tip_radius", 20, "nanometres (20 nm = 2e-8 m)"),
    ("contact_radius", 5, "micrometres (5 µm = 5e-6 m)"),
    ("contact_radius", 5000, "nanometres (5000 nm = 5e-6 m)"),
    ("pixel_size", 0.02, "millimetres (0.02 mm = 2e-5 m)"),
    ("pixel_size", 0.5, "micrometres (0.5 µm = 5e-7 m)"),
    ("pixel_size", 200, "nanometres (200 nm = 2e-7 m)"),
    ("force", 5000, "micronewtons (5000 µN = 0.005 N)"),
    ("force", 2e5, "nanonewtons (2e5 nN = 2e-4 N)"),
    ("modulus", 5e4, "megapascals (5e4 MPa = 5e10 Pa)"),
    ("modulus", 165.7, "gigapascals (165.7 GPa = 1.657e11 Pa)"),
    ("stress", 20, "megapascals (20 MPa = 2e7 Pa)"),
    ("stress", 0.05, "gigapascals (0.05 GPa = 5e7 Pa)"),
    ("stiffness", 4e-4, "N/nm (4e-4 N/nm = 4e5 N/m)"),
    ("density", 8.96, "grams per cm^3 (8.96 g/cm^3 = 8960 kg/m^3)"),
    ("frequency", 500, "kilohertz (500 kHz = 5e5 Hz)"),
    ("frequency", 5, "megahertz (5 MHz = 5e6 Hz)"),
    ("frequency", 0.01, "gigahertz (0.01 GHz = 1e7 Hz)"),
    ("area", 0.5, "square centimetres (0.5 cm^2 = 5e-5 m^2)"),
    ("area", 20, "square millimetres (20 mm^2 = 2e-5 m^2)"),
    ("area", 1e7, "square micrometres (1e7 µm^2 = 1e-5 m^2)"),
    ("piezo_constant", 3.1, "pm/V (3.1 pm/V = 3.1e-12 m/V)"),
    ("impedance", 8800, "kilorayl (8800 kRayl = 8.8e6 kg m^-2 s^-1)"),
    ("impedance", 8.8, "megarayl (8.8 MRayl = 8.8e6 kg m^-2 s^-1)"),
]


@pytest.mark.parametrize("quantity, typed, slip", SLIPS)
def test_unit_slip_suggestion(quantity, typed, slip):
    assert unit_slip(quantity, typed) == slip
    with pytest.raises(ValueError) as info:
        check_magnitude(quantity, str(typed), "--opt")
    assert str(info.value).endswith(f"; it looks like {slip}: check the unit of --opt")


def test_every_slip_of_every_quantity_is_tested():
    tested = {(q, s.split(" (")[0]) for q, _, s in SLIPS}
    listed = {(q, words) for q, p in QUANTITIES.items() for _, _, words in p.slips}
    assert tested == listed


@pytest.mark.parametrize("factor", [1e-3, 1e-6, 1e-9, 1e3, 1e6, 1e9])
def test_each_factor_of_a_thousand_is_a_slip_somewhere(factor):
    assert any(f == factor for p in QUANTITIES.values() for f, _, _ in p.slips)


def test_no_slip_for_plausible_values_far_values_or_dimensionless_numbers():
    assert unit_slip("amplitude", 20e-9) is None  # plausible: taken as typed
    assert unit_slip("sphere_radius", 1e300) is None  # no unit puts it in range
    assert unit_slip("force", 1e-13) is None  # forces are not typed in kN
    assert unit_slip("friction", 80) is None
    assert unit_slip("amplitude", math.nan) is None
    with pytest.raises(ValueError) as info:
        check_magnitude("sphere_radius", "1e300", "--radius")
    assert str(info.value) == (
        "--radius 1e300 is outside the plausible range: the sphere radius lies in [1e-9, 1] m"
    )


@pytest.mark.parametrize(
    "x, text",
    [(2e-8, "2e-8"), (1.657e11, "1.657e11"), (1e5, "1e5"), (20.0, "20"), (0.005, "0.005"),
     (9999.0, "9999"), (-4.2e-9, "-4.2e-9"), (1.23456789e-7, "1.23457e-7"), (0.0, "0")],
)  # fmt: skip
def test_format_number(x, text):
    assert format_number(x) == text


def test_describe_shows_open_and_closed_bounds():
    assert QUANTITIES["poisson"].describe() == "the Poisson ratio lies in (-1, 0.5)"
    assert QUANTITIES["friction"].describe() == "the friction coefficient lies in (0, 50]"
    assert QUANTITIES["loss"].describe() == "the loss factor Q^-1 lies in [0, 1)"
    assert QUANTITIES["area"].describe() == "the electrode area lies in [1e-8, 0.01] m^2"
