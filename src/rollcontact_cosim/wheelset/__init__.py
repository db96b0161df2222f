"""The wheelset hunting scene: a suspended wheelset on straight track as the host of an elliptic contact FMU.

* :mod:`.model`: the host model (no FMI: the ``Wheelset`` FMU maps its variables to it), its kinematics, the
  in-process creep-force laws (Kalker's linear theory, a saturated law) and :func:`~.model.simulate`, the in-process
  run of a Gauss-Seidel or Jacobi master;
* :mod:`.stability`: the linearised wheelset, its eigenvalues, critical speed and Klingel's wavelength;
* :mod:`.study`: the in-process hunting study (a speed sweep on dask against the eigenvalues, Klingel's wavelength);
* :mod:`.cosim`: the scene co-simulated with the ``Wheelset`` and ``RollingContact3D_2`` FMUs through either master;
* :mod:`.profiles`: the wheelset on real profiles (the ``Wheelset`` host with a ``WheelsetContact``), its nonlinear
  hunting study and the equivalent linearisation.

This module imports the host model only: the ``Wheelset`` FMU imports it in hosts without fmpy, dask or matplotlib.
"""

from rollcontact_cosim.wheelset.model import (
    ContactForces,
    CreepForceLaw,
    KalkerLinearLaw,
    SaturatedKalkerLaw,
    WheelsetError,
    WheelsetModel,
    WheelsetParameters,
    WheelsetState,
    creepage_jacobian,
    creepages,
    linear_law,
    simulate,
    simulate_profiles,
)

__all__ = ["ContactForces", "CreepForceLaw", "KalkerLinearLaw", "SaturatedKalkerLaw", "WheelsetError",
           "WheelsetModel", "WheelsetParameters", "WheelsetState", "creepage_jacobian", "creepages", "linear_law",
           "simulate", "simulate_profiles"]
