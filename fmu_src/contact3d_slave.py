"""PythonFMU entry module of the RollingContact3D FMU (FMI 2.0 co-simulation); the slave class is
:class:`rollcontact_fmu_contact3d.RollingContact3D`.

Deliberately tiny, for the reasons in ``rollcontact_fmu_slave.py``'s docstring: pythonfmu 0.7 re-executes this
source on every instantiation, leaks the MRO of every class bound here and releases one reference to this
module's namespace it never took (balanced below); :func:`rollcontact_fmu_contact3d.slave_class` returns the same
class on every execution.  ``build_fmu.py --contacts n`` builds from this text with the variant's model name
(``RollingContact3D_n``) and arguments in place of these.
"""

from rollcontact_fmu_contact3d import slave_class

RollingContact3D = slave_class(contacts=1, integer_codes=False)

if locals() is not globals():  # executed again by pythonfmu's findClass (fresh locals): balance its Py_DECREF
    try:
        import ctypes

        ctypes.pythonapi.Py_IncRef(ctypes.py_object(globals()))
    except Exception:  # noqa: BLE001 - no C API through ctypes: a method's reference, kept by findClass's leak
        class _Pin:
            def hold(self):
                """Holds a reference to the module namespace (``__globals__``)."""

__all__ = ["RollingContact3D"]
