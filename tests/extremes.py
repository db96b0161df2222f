"""The valid domain of issue 7 (numerical stability at the extremes), shared by the property-based tests.

``test_properties.py`` (library) and ``test_fmu_properties.py`` (the built FMU through fmpy) draw from the same
strategies and judge stepping outputs by the same :func:`check_outputs`.  The hypothesis profile registered here,
``"rollcontact-properties"``, is derandomised (the same examples in every CI run) and has no deadline (a loaded
2-core machine); each test sets its own small ``max_examples``.

Tolerance tiers (relative to the scale named in each assertion):

``ULP`` (4 eps)
    bounds and symmetries that hold to a rounding or two (|T| <= mu N, oddness, exact saturation).
``ROUND_OFF`` (1e-14)
    closed forms against a 40-digit evaluation of the same formulas: a dozen roundings.
``CONVERGED`` (1e-12)
    iterative methods against the closed forms where they are exact: Newton stops at ~1e-13 of its scales.
``SOLVER`` (1e-9)
    results of an iteration or a discretisation with a 1e-9 tolerance (the polynomial method's validity checks,
    the slip iteration of velocity-dependent friction).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, settings
from hypothesis import strategies as st

settings.register_profile("rollcontact-properties", deadline=None, derandomize=True, database=None,
                          suppress_health_check=[HealthCheck.too_slow])
PROFILE = settings.get_profile("rollcontact-properties")

EPS = float(np.finfo(float).eps)
ULP = 4.0 * EPS
ROUND_OFF = 1e-14
CONVERGED = 1e-12
SOLVER = 1e-9

NOMINAL_LOAD = 1e6
"""N' [N/m] of the domain's centre: 100 kN on a 0.1 m wide line contact; loads span 1e-6 to 1e3 times it."""
ELEMENTS = 32
"""Elements of the discretised method wherever it may be chosen: a coarse grid keeps fallbacks cheap."""
STATIONARY = 1e9  # upper bound of the stationarity output


def log_uniform(lo: float, hi: float):
    """Floats spread evenly in log10 between lo and hi (both > 0)."""
    return st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0**e)


signs = st.sampled_from((1.0, -1.0))
one_in_ten = st.sampled_from((False,) * 9 + (True,))
"""True once in ten draws (hypothesis favours small integers, so ``integers(0, 9) == 0`` would come far more often)."""


INVALID_PARAMETERS = ("youngs_modulus", "poisson_ratio", "radius", "contact_width", "friction_coefficient",
                      "corrugation_wavelength", "corrugation_amplitude")
INPUT_NAMES = ("step_size", "normal_load", "creep", "velocity")


@st.composite
def model_parameters(draw):
    """``(parameters, problem)``: ``ContactParameters`` keywords over the domain and the name the refusal must
    give, None when they are valid.  One draw in ten has an invalid value, and about as many ask for the closed
    form (``method`` = 1) on a scene it cannot solve.

    E 1e6..1e12 Pa, R 1e-3..1e2 m, mu 1e-6..2, Coulomb or exponential falling friction, corrugation amplitude 0 or
    1e-9..1e-2 m at wavelengths 1e-4..10 m (k a from ~1e-6 to ~1e5 over the loads of :func:`model_inputs`), any
    method, polynomial orders 0 (automatic), 1, 40, 200, and a discretised grid of :data:`ELEMENTS`.
    """
    kw = {"youngs_modulus": draw(log_uniform(1e6, 1e12)), "poisson_ratio": draw(st.floats(0.0, 0.49)),
          "radius": draw(log_uniform(1e-3, 1e2)), "contact_width": draw(log_uniform(1e-3, 1.0)),
          "friction_coefficient": draw(log_uniform(1e-6, 2.0)), "friction_law": draw(st.sampled_from((0, 1))),
          "friction_kinetic_ratio": draw(log_uniform(1e-3, 1.0)), "friction_decay": draw(log_uniform(1e-3, 1e3)),
          "corrugation_wavelength": draw(log_uniform(1e-4, 10.0)),
          "corrugation_amplitude": draw(st.one_of(st.just(0.0), log_uniform(1e-9, 1e-2))),
          "corrugation_phase": draw(st.floats(-10.0, 10.0)), "initial_position": draw(st.floats(-1e3, 1e3)),
          "polynomial_order": draw(st.sampled_from((0, 1, 40, 200))), "elements": ELEMENTS}
    if draw(one_in_ten):
        problem = draw(st.sampled_from(INVALID_PARAMETERS))
        # the bound itself where it is excluded: nu = 0.5, a zero modulus, radius, width, mu or wavelength (a zero
        # amplitude is no corrugation, valid)
        edge = {"poisson_ratio": (0.5,), "corrugation_amplitude": ()}.get(problem, (0.0,))
        kw[problem] = draw(st.sampled_from((math.nan, math.inf, -1.0, *edge)))
        kw["method"] = draw(st.sampled_from((0, 2, 3)))
        return kw, problem
    # the exponential law with mu_k = mu_s (a ratio drawn at its bound 1.0) is constant friction: closed form
    flat = kw["corrugation_amplitude"] == 0.0 and (kw["friction_law"] == 0 or kw["friction_kinetic_ratio"] == 1.0)
    kw["method"] = draw(st.sampled_from((0, 1, 2, 3) if flat or draw(one_in_ten) else (0, 2, 3)))
    return kw, None if flat or kw["method"] != 1 else "method"


@st.composite
def model_inputs(draw, contact_width: float):
    """``((h, N, xi, V), problem)``: one step's inputs and the name a refusal must give, None when they are valid.

    h 1e-6..1 s, N 1e-6..1e3 times the nominal load over the width (0 one time in ten), |xi| 1e-12..10 (both
    signs), V 1e-6..1e3 m/s; one draw in ten has a non-finite value, or a negative one where it is invalid.
    """
    load = 0.0 if draw(one_in_ten) else draw(log_uniform(1e-6 * NOMINAL_LOAD, 1e3 * NOMINAL_LOAD))
    row = [draw(log_uniform(1e-6, 1.0)), load * contact_width,
           draw(signs) * draw(log_uniform(1e-12, 10.0)), draw(log_uniform(1e-6, 1e3))]
    if not draw(one_in_ten):
        return tuple(row), None
    index = draw(st.integers(0, 3))
    row[index] = draw(st.sampled_from((math.nan, math.inf, -math.inf) if index == 2 else (math.nan, math.inf, -1.0)))
    return tuple(row), INPUT_NAMES[index]


def check_outputs(out, parameters: dict, normal_load: float, creep: float, velocity: float,
                  instationary: bool = False) -> None:
    """A successful step's outputs (``StepOutputs`` or the FMU's) are valid for these inputs.

    Finite; |T| <= mu N; ``method_used`` 0 exactly without load; 0 <= a* <= a; p0 >= 0; stationarity in
    [0, 1e9]; frictional power V xi T >= 0 (the slip power ``V int q s dx``, q s >= 0 pointwise); on the closed-form
    path beyond saturation (|xi| R >= mu a) exact full slip.  ``instationary`` (``transient`` = 1, 2): also the
    instationary models' codes 4 and 5, and no sign of V xi T (T lags the creep, so the creep power changes sign
    with the stored elastic energy).
    """
    assert all(math.isfinite(v) for v in out), f"non-finite outputs {out}"
    mu = parameters["friction_coefficient"]
    mu_n = mu * normal_load
    assert abs(out.tangential_force) <= mu_n * (1.0 + SOLVER), f"|T| = {out.tangential_force!r} > mu N = {mu_n!r}"
    codes = (1, 2, 3, 4, 5) if instationary else (1, 2, 3)
    assert out.method_used in ((0,) if normal_load == 0.0 else codes), f"method_used {out.method_used}"
    assert out.contact_half_width >= 0.0 and 0.0 <= out.stick_half_width <= out.contact_half_width, \
        f"a = {out.contact_half_width!r}, a* = {out.stick_half_width!r}"
    assert out.max_pressure >= 0.0 and 0.0 <= out.stationarity <= STATIONARY, f"{out}"
    assert instationary or out.frictional_power >= -SOLVER * mu_n * abs(creep) * velocity, \
        f"negative frictional power V xi T = {out.frictional_power!r}"
    if out.method_used == 1 and abs(creep) * parameters["radius"] >= mu * out.contact_half_width * (1.0 + ULP):
        assert abs(abs(out.tangential_force) - mu_n) <= ULP * mu_n and out.stick_half_width == 0.0, \
            f"closed form beyond saturation must be in full slip: {out}"
