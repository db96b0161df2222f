"""PythonFMU entry module of the RollingContact2D FMU (FMI 2.0 co-simulation); the slave class is
:class:`rollcontact_fmu_contact.RollingContact2D`.

This module is deliberately tiny.  pythonfmu 0.7's binary (``PySlaveInstance.cpp``, ``findClass``) re-executes
the entry module's source on *every* instantiation, in a fresh locals dict, and leaks, for every class bound
there, the list of its MRO and two strings per MRO entry; a class defined here would be created anew each time
and kept alive by that leak (about 14 KB per instance).  Importing the class binds one existing class only.

``findClass`` also releases one reference to this module's ``__dict__`` that it never took (``Py_DECREF`` of the
borrowed ``PyModule_GetDict``).  A module that creates no new functions per execution would see its namespace
freed after a few instantiations, so each such execution (recognised by its locals not being its globals) takes
one reference that is never given back (``Py_IncRef`` through ctypes; else a small class whose method holds it,
kept alive by findClass's leak).  A Python-level holder (a list of references) would not do: it is cleared at
interpreter exit and would release them all (heap corruption at exit).
"""

from rollcontact_fmu_contact import VARIABLES, RollingContact2D

if locals() is not globals():  # executed again by pythonfmu's findClass (fresh locals): balance its Py_DECREF
    try:
        import ctypes

        ctypes.pythonapi.Py_IncRef(ctypes.py_object(globals()))
    except Exception:  # noqa: BLE001 - no C API through ctypes: a method's reference, kept by findClass's leak
        class _Pin:
            def hold(self):
                """Holds a reference to the module namespace (``__globals__``)."""

__all__ = ["VARIABLES", "RollingContact2D"]
