"""What pythonfmu 0.7's and pythonfmu3 0.3.4's binaries need from a slave beyond FMI (docs/fmu-internals.md).

* Log messages are printf formats on pythonfmu 0.7's C side (:func:`printf_safe`).
* pythonfmu 0.7 hands a message to the host's logger only while debug logging is on for its category; the slave
  reads pythonfmu's C++ logger object to know whether a refusal reached the host (:func:`logger_categories`).
* The instance constructor inserts the resources folder into ``sys.path`` on every instantiation
  (:func:`drop_repeated_path`).
* scipy's ``_uarray`` frees an exception type at ``Py_Finalize`` that a dictionary still reads, in an interpreter a C
  host's pythonfmu binary started (:func:`hold_uarray_error_type`, run once when this module is first imported).
* pythonfmu 0.7's ``findClass`` re-executes the entry module on every instantiation and releases one reference to its
  namespace it never took (:func:`balance_entry_module`, called by every FMI 2.0 entry module).
"""

from __future__ import annotations

import ctypes
import sys
import types


def printf_safe(message: str) -> str:
    """The message as a literal printf format (pythonfmu 0.7's C side formats log messages)."""
    return message.replace("%", "%%")


def hold_uarray_error_type() -> None:
    """Give scipy's ``_uarray.BackendNotImplementedError`` type one reference that is never released.

    In an interpreter that pythonfmu's binary started (a C host), ``Py_Finalize`` frees ``_uarray``'s module state
    (its ``globals_free``) and afterwards a dictionary still reads that exception type: memcheck shows the read of
    the freed type, and it crashes the host at exit now and then (``benchmarks/results/exit.md``;
    docs/fmu-internals.md, "Exit").  One more reference keeps the type alive through finalisation; in a Python host
    it costs nothing.  Called once, when this module is first imported (pythonfmu re-runs the entry module at every
    instantiation, not this one).
    """
    try:
        from scipy._lib._uarray._uarray import BackendNotImplementedError
    except ImportError:  # a scipy without _uarray has nothing to hold
        return
    ctypes.pythonapi.Py_IncRef(ctypes.py_object(BackendNotImplementedError))


hold_uarray_error_type()


def drop_repeated_path(entry: str) -> None:
    """Remove all but the first occurrence of ``entry`` from ``sys.path`` (the same list object).

    pythonfmu's instance constructor inserts the resources folder at ``sys.path[0]`` on every instantiation and
    never removes it: without this, ``sys.path`` grows by one entry per instance.
    """
    if entry in sys.path:
        first = sys.path.index(entry)
        sys.path[first + 1:] = [path for path in sys.path[first + 1:] if path != entry]


def _hold(self):
    """Holds a reference to the namespace it is made with (``__globals__``)."""


def balance_entry_module(namespace: dict, local: dict) -> None:
    """Balance the ``Py_DECREF`` of the entry module's namespace ``namespace`` that pythonfmu 0.7's ``findClass``
    makes on every re-execution (``local``, the execution's fresh locals dict, is not ``namespace`` then).

    ``findClass`` runs the entry module's source again per instantiation and releases one reference to the module's
    ``__dict__`` that it never took (``Py_DECREF`` of the borrowed ``PyModule_GetDict``): a module that creates no
    new functions per execution would see its namespace freed after a few instantiations.  Each re-execution takes
    one reference that is never given back: ``Py_IncRef`` through ctypes, else a small class bound in ``local``
    whose method holds the namespace as its globals, kept alive by ``findClass``'s leak of every class bound there.
    A Python-level holder (a list of references) would not do: it is cleared at interpreter exit and would release
    them all (heap corruption at exit).  On a normal import (``local`` is ``namespace``) it does nothing.
    """
    if local is namespace:
        return
    try:
        ctypes.pythonapi.Py_IncRef(ctypes.py_object(namespace))
    except Exception:  # noqa: BLE001 - no C API through ctypes: a method's reference, kept by findClass's leak
        hold = types.FunctionType(_hold.__code__, namespace, "hold")
        local["_Pin"] = type("_Pin", (), {"hold": hold, "__module__": namespace.get("__name__")})


def logger_categories(address: int, instance_name: str):
    """What pythonfmu 0.7's logger object at ``address`` hands to the host's logger callback: None while debug
    logging is off, ``()`` for every category, else the tuple of categories of ``fmi2SetDebugLogging``.

    The object is a ``pythonfmu::PyLogger`` (``Logger.hpp``; ``fmi2.cpp``'s ``Fmi2Logger`` adds the callbacks
    pointer), whose address pythonfmu passes to the slave as the keyword ``logger``.  With the GNU C++ library on a
    64-bit platform its members lie at: 8 ``bool debugLogging_``, 16 ``std::string instanceName_`` (data pointer,
    size, then the local buffer of short strings or the capacity), 48 ``std::vector<std::string> categories_``
    (begin, end, end of storage; 32 bytes per string).  The layout is accepted only when the instance name read
    there is ``instance_name``, the flag is 0 or 1 and the vector is well formed; raises ValueError otherwise (another
    platform, compiler or pythonfmu version).
    """
    if sys.platform != "linux" or ctypes.sizeof(ctypes.c_void_p) != 8:
        raise ValueError(f"the layout of pythonfmu's logger is known for 64-bit Linux only (this is {sys.platform})")
    if not address:
        raise ValueError("no logger object (address 0): unknown layout")
    name = instance_name.encode()
    if ctypes.c_size_t.from_address(address + 24).value != len(name) or string_at(address + 16) != name:
        # the size first: a pointer is followed only where the object already looks like the expected one
        raise ValueError("the instance name in pythonfmu's logger object does not match: unknown layout")
    flag = ctypes.c_uint8.from_address(address + 8).value
    begin, end, storage = (ctypes.c_size_t.from_address(address + offset).value for offset in (48, 56, 64))
    if flag > 1 or not begin <= end <= storage or (end - begin) % 32 or (end - begin) // 32 > 64 or \
            (end > begin and not begin):
        raise ValueError("the debug flag or the categories in pythonfmu's logger object are malformed: unknown layout")
    if not flag:
        return None
    return tuple(string_at(element).decode(errors="replace") for element in range(begin, end, 32))


def string_at(address: int, limit: int = 1024) -> bytes:
    """The bytes of the GNU C++ library's ``std::string`` at ``address`` (ValueError when it is none: a short string
    not in its local buffer, a long one in it, or longer than ``limit``)."""
    data, size, capacity = (ctypes.c_size_t.from_address(address + offset).value for offset in (0, 8, 16))
    local = address + 16
    if size > limit or (size <= 15) != (data == local) or (data != local and capacity < size):
        raise ValueError(f"no std::string at {address:#x}")
    return ctypes.string_at(data, size)
