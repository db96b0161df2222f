"""Helpers of the wheelset tests: the nonlinear right-hand side with a law's forces, central differences."""

import numpy as np
import pytest

from rollcontact_cosim.wheelset import creepages


@pytest.fixture
def law_rhs():
    """``law_rhs(model, law, state)``: :func:`rhs_with_law`."""
    return rhs_with_law


@pytest.fixture
def finite_difference():
    """``finite_difference(function, x, step)``: :func:`central_differences`."""
    return central_differences


def rhs_with_law(model, law, state):
    """ds/dt with the law's forces at the state's creepages (the nonlinear right-hand side)."""
    p = model.parameters
    c = creepages(p, state)
    forces = np.array([law(p.normal_load, *c[k], p.speed) for k in range(2)])
    return model.rhs(state, forces)


def central_differences(function, x, step):
    """The Jacobian of ``function`` at ``x`` by central differences of ``step`` (a scalar or one per entry)."""
    x = np.asarray(x, dtype=float)
    columns = []
    for j in range(x.size):
        d = np.zeros_like(x)
        d[j] = step[j] if np.ndim(step) else step
        columns.append((np.asarray(function(x + d)) - np.asarray(function(x - d))) / (2.0 * d[j]))
    return np.stack(columns, axis=-1)
