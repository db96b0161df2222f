"""The exit-time fix of pythonfmu's Linux export library, applied to the copy of it in a built FMU.

pythonfmu 0.7.0 and pythonfmu3 0.3.4 keep the embedded interpreter's owner in a static
``std::shared_ptr<pythonfmu::PyState> pyState`` (made by ``std::make_shared`` at the first instantiation) and release
it twice at process exit:

1. the static destructor ``~shared_ptr`` (registered with ``__cxa_atexit`` by the library's static initialiser
   ``_GLOBAL__sub_I_PySlaveInstance.cpp``) runs from ``exit()``'s handlers, releases the shared state and leaves
   the pointer's two words as they were (libstdc++ does not clear them);
2. ``onLibraryUnload``, an ``__attribute__((destructor))`` run later by ``_dl_fini``, calls
   ``finalizePythonInterpreter``, whose ``pyState = nullptr`` releases the stale control block again: an atomic
   decrement of 4 bytes at offset 8 of the freed 128-byte block (the use count), which glibc has by then reused for
   its free-list links.  glibc aborts later (``corrupted double-linked list``) or not, depending on the heap layout.

The fix redirects the static destructor's registration to ``finalizePythonInterpreter`` itself: the initialiser's
``mov ~shared_ptr@GOT(%rip), %rdi`` (7 bytes, ``48 8b 3d`` + displacement) becomes ``lea
finalizePythonInterpreter(%rip), %rdi`` (``48 8d 3d`` + displacement), so ``exit()`` releases the shared state with
``pyState = nullptr``, which leaves the pointer empty, and the second call finds nothing to release.  The release
happens once, at the same moment as before, so a C host whose interpreter pythonfmu started still gets
``Py_Finalize`` (``~PyState`` asks its worker thread for it) with Python's atexit handlers and buffer flushes.
The binary has ``STB_GNU_UNIQUE`` symbols, so glibc never unloads it before exit and the order above holds in
every process.

:func:`patch_library` applies it to a library only if its SHA-256 is that of a pinned release
(:data:`LIBRARIES`), and checks every byte it relies on through the ELF tables; anything else stops the build
with the reason.  The Windows DLLs are left as they are (docs/fmu-internals.md, "Exit").
"""

from __future__ import annotations

import hashlib
import shutil
import struct
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

FINALIZER = "finalizePythonInterpreter"
INITIALISER = "_GLOBAL__sub_I_PySlaveInstance.cpp"
DESTRUCTOR = "_ZNSt10shared_ptrIN9pythonfmu7PyStateEED1Ev"
"""``std::shared_ptr<pythonfmu::PyState>::~shared_ptr()``, the static destructor the initialiser registers."""
MOV_RDI_RIP, LEA_RDI_RIP = b"\x48\x8b\x3d", b"\x48\x8d\x3d"
"""x86-64 ``mov disp32(%rip), %rdi`` and ``lea disp32(%rip), %rdi``, each followed by a 4-byte displacement."""
R_X86_64_GLOB_DAT = 6


@dataclass(frozen=True)
class Library:
    """A pinned release's Linux export library: where the FMU holds it and its SHA-256 before and after the fix."""

    release: str
    folder: str
    sha256: str
    patched_sha256: str


LIBRARIES = (
    Library("pythonfmu 0.7.0", "binaries/linux64/",
            "4be156a552c16f30eb4395805c59855d8d4086056d0f165442565f6c5fbac0c9",
            "7a1f8bf5558a491916a77362c463883136dc561e36263d715a7b9c86f73262fa"),
    Library("pythonfmu3 0.3.4", "binaries/x86_64-linux/",
            "53fd71ba834c18dea2df15d7e67b3a42441e7a607757cb5ac825ff98b505b580",
            "49814447d61d13619e0c57299d2d47e062d62832f6d2036609a33a3038beced7"),
)


class ElfTables:
    """The section headers, symbols (``.symtab`` and ``.dynsym``) and ``.rela.dyn`` relocations of an ELF64
    little-endian x86-64 file, read with :mod:`struct` (System V gABI, ELF-64 object file format)."""

    def __init__(self, data: bytes):
        if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1 or struct.unpack_from("<H", data, 18)[0] != 62:
            raise ValueError("not an ELF64 little-endian x86-64 file")
        shoff, = struct.unpack_from("<Q", data, 0x28)
        shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x3A)
        raw = [struct.unpack_from("<IIQQQQIIQQ", data, shoff + i * shentsize) for i in range(shnum)]
        names = raw[shstrndx][4]
        self.data = data
        self.sections = {self._string(names, s[0]): s for s in raw}
        self.symbols: dict[str, tuple[int, int]] = {}  # name -> (value, size)
        self.dynamic: list[str] = []  # .dynsym names by index
        for table in (".symtab", ".dynsym"):
            _, _, _, _, offset, size, link, _, _, entsize = self.sections[table]
            strings = raw[link][4]
            for i in range(size // entsize):
                name_at, _, _, _, value, length = struct.unpack_from("<IBBHQQ", data, offset + i * entsize)
                name = self._string(strings, name_at)
                if table == ".dynsym":
                    self.dynamic.append(name)
                if value and name not in self.symbols:
                    self.symbols[name] = (value, length)
        _, _, _, _, offset, size, _, _, _, entsize = self.sections[".rela.dyn"]
        self.relocations = {}  # address -> (type, symbol name)
        for i in range(size // entsize):
            address, info, _ = struct.unpack_from("<QQq", data, offset + i * entsize)
            self.relocations[address] = (info & 0xFFFFFFFF, self.dynamic[info >> 32])

    def _string(self, offset: int, at: int) -> str:
        return self.data[offset + at:self.data.index(b"\0", offset + at)].decode()

    def file_offset(self, address: int) -> int:
        """File offset of the virtual ``address`` (in a section with file contents)."""
        for _, kind, _, start, offset, size, *_ in self.sections.values():
            if kind != 8 and start <= address < start + size:  # 8: SHT_NOBITS
                return offset + address - start
        raise ValueError(f"address {address:#x} is in no section with file contents")

    def symbol(self, name: str) -> tuple[int, int]:
        """Address and size of the symbol ``name``; ValueError if the library has none."""
        if name not in self.symbols:
            raise ValueError(f"the library has no symbol {name}")
        return self.symbols[name]


def registration(tables: ElfTables) -> int:
    """Address of the initialiser's one ``mov ~shared_ptr@GOT(%rip), %rdi`` (the static destructor's registration):
    the GOT slot it reads must carry an ``R_X86_64_GLOB_DAT`` relocation of :data:`DESTRUCTOR`."""
    start, size = tables.symbol(INITIALISER)
    at, code = tables.file_offset(start), tables.data
    found = []
    for i in range(size - 6):
        if code[at + i:at + i + 3] == MOV_RDI_RIP:
            slot = start + i + 7 + struct.unpack_from("<i", code, at + i + 3)[0]
            if tables.relocations.get(slot) == (R_X86_64_GLOB_DAT, DESTRUCTOR):
                found.append(start + i)
    if len(found) != 1:
        raise ValueError(f"{INITIALISER} loads the address of {DESTRUCTOR} {len(found)} times, not once")
    return found[0]


def redirected(data: bytes) -> bytes:
    """``data`` with the static destructor's registration redirected to :data:`FINALIZER` (module docstring)."""
    tables = ElfTables(data)
    instruction = registration(tables)
    target, _ = tables.symbol(FINALIZER)
    at = tables.file_offset(instruction)
    patched = bytearray(data)
    patched[at:at + 7] = LEA_RDI_RIP + struct.pack("<i", target - (instruction + 7))
    return bytes(patched)


def patch_library(data: bytes, name: str = "library") -> bytes:
    """The fixed library for the bytes of a pinned release's Linux export library (:data:`LIBRARIES`).

    Bytes that are already the fixed library come back unchanged.  RuntimeError, naming the SHA-256 found and the
    pinned ones, for any other bytes, and if the fixed bytes are not those expected.
    """
    digest = hashlib.sha256(data).hexdigest()
    for library in LIBRARIES:
        if digest == library.patched_sha256:
            return data
        if digest == library.sha256:
            patched = redirected(data)
            got = hashlib.sha256(patched).hexdigest()
            if got != library.patched_sha256:
                raise RuntimeError(f"{name}: the exit fix of {library.release} gave SHA-256 {got}, expected "
                                   f"{library.patched_sha256}")
            return patched
    pinned = ", ".join(f"{lib.release} {lib.sha256}" for lib in LIBRARIES)
    raise RuntimeError(f"{name} has SHA-256 {digest}, not that of a pinned pythonfmu release ({pinned}): the exit "
                       f"fix (pythonfmu_exit_fix.py, docs/fmu-internals.md 'Exit') is made for those bytes only; "
                       f"install the pinned versions (pip install -e '.[fmu]') or check the fix against the new "
                       f"release")


def patch_fmu(fmu: Path | str) -> list[str]:
    """Apply :func:`patch_library` to the Linux export libraries in the FMU file ``fmu`` (rewritten in place, every
    other member as it was); the names of the members fixed.  RuntimeError if the FMU has none."""
    fmu = Path(fmu)
    with zipfile.ZipFile(fmu) as source:
        members = [(info, source.read(info)) for info in source.infolist()]
    fixed = []
    with tempfile.NamedTemporaryFile(dir=fmu.parent, suffix=".fmu", delete=False) as tmp:
        try:
            with zipfile.ZipFile(tmp, "w") as target:
                for info, data in members:
                    if info.filename.endswith(".so") and any(info.filename.startswith(lib.folder)
                                                             for lib in LIBRARIES):
                        data = patch_library(data, f"{fmu.name}:{info.filename}")
                        fixed.append(info.filename)
                    target.writestr(info, data)
            if not fixed:
                raise RuntimeError(f"{fmu} holds no Linux export library of pythonfmu "
                                   f"({', '.join(lib.folder for lib in LIBRARIES)})")
        except BaseException:
            Path(tmp.name).unlink()
            raise
    shutil.move(tmp.name, fmu)
    return fixed
