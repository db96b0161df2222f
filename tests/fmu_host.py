"""The FMU host of the FMU tests: a RollingContact2D instance through fmpy's ``FMU2Slave`` with its log captured,
the library's outputs to compare with, the Discard expected of a refused step, and a small C host (also run by
``tests/tools/exit_study.py``).

Imported by name (``tests/`` is on pytest's ``pythonpath``); the tests themselves are imported by path.
"""

from __future__ import annotations

import sysconfig
from pathlib import Path

import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, defaultCallbacks, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

from rollcontact.stepping import ContactModel, ContactParameters, StepOutputs

DISCARD = 2
H = 1e-3
OUTPUTS = StepOutputs._fields


class Instance:
    """One FMU2Slave instance, initialised, with its log messages captured."""

    def __init__(self, unzipped: Path, description, name="rc", start_time=0.0, stop_time=None, **parameters):
        self.description = description
        self.variables = {v.name: v for v in description.modelVariables}
        self.log: list[tuple[int, str, str]] = []
        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = fmi2CallbackLoggerTYPE(self.logger)
        self.callbacks.allocateMemory = defaultCallbacks.allocateMemory
        self.callbacks.freeMemory = defaultCallbacks.freeMemory
        self.fmu = FMU2Slave(guid=description.guid, unzipDirectory=str(unzipped),
                             modelIdentifier=description.coSimulation.modelIdentifier, instanceName=name)
        self.fmu.instantiate(callbacks=self.callbacks, loggingOn=True)
        self.set(**parameters)
        self.fmu.setupExperiment(startTime=start_time, stopTime=stop_time)
        self.fmu.enterInitializationMode()
        self.fmu.exitInitializationMode()
        self.inputs = [self.variables[n].valueReference for n in ("normal_load", "creep", "velocity")]
        self.reals = [self.variables[n].valueReference for n in OUTPUTS if n != "method_used"]
        self.integer = [self.variables["method_used"].valueReference]

    def logger(self, environment, instance_name, status, category, message):
        self.log.append((status, category.decode(), message.decode()))

    def set(self, **values):
        for name, value in values.items():
            v = self.variables[name]
            setter = {"Real": self.fmu.setReal, "Integer": self.fmu.setInteger, "Enumeration": self.fmu.setInteger,
                      "String": self.fmu.setString}[v.type]
            setter([v.valueReference], [value])

    def step(self, t, h, normal_load, creep, velocity) -> StepOutputs:
        """Set the inputs, do the step and read every output (raises FMICallException on Discard)."""
        self.fmu.setReal(self.inputs, [normal_load, creep, velocity])
        self.fmu.doStep(t, h)
        return self.outputs()

    def outputs(self) -> StepOutputs:
        reals = iter(self.fmu.getReal(self.reals))
        method = self.fmu.getInteger(self.integer)[0]
        return StepOutputs(*(method if n == "method_used" else next(reals) for n in OUTPUTS))

    def free(self):
        self.fmu.terminate()
        self.fmu.freeInstance()


def model_outputs(parameters: dict, rows, start=0.0, h=H) -> list[StepOutputs]:
    """The library's ContactModel over the same rows (normal_load, creep, velocity)."""
    model = ContactModel(ContactParameters(**parameters), start_time=start)
    return [model.step(start + n * h, h, *row) for n, row in enumerate(rows)]


def discarded(fmu: Instance, *args) -> str:
    """Step expecting a Discard; the logged message (printf-unescaped)."""
    before = len(fmu.log)
    with pytest.raises(FMICallException) as caught:
        fmu.step(*args)
    assert caught.value.status == DISCARD, f"{args}: expected fmi2Discard, got status {caught.value.status}"
    new = [(status, message) for status, _, message in fmu.log[before:]]
    assert new and new[-1][0] == DISCARD, f"{args}: the reason must be logged with status Discard: {new}"
    raw = new[-1][1]
    assert "%" not in raw.replace("%%", ""), f"log messages must be printf-safe: {raw!r}"
    return raw.replace("%%", "%")


C_HOST = r"""
#include <dlfcn.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

typedef void *fmi2Component;
typedef unsigned int fmi2ValueReference;
typedef struct {
    void (*logger)(void *, const char *, int, const char *, const char *, ...);
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, int);
    void *componentEnvironment;
} fmi2CallbackFunctions;
typedef fmi2Component (*Instantiate)(const char *, int, const char *, const char *, const fmi2CallbackFunctions *,
                                     int, int);
typedef int (*SetupExperiment)(fmi2Component, int, double, double, int, double);
typedef int (*Mode)(fmi2Component);
typedef int (*SetReal)(fmi2Component, const fmi2ValueReference *, size_t, const double *);
typedef int (*GetReal)(fmi2Component, const fmi2ValueReference *, size_t, double *);
typedef int (*GetInteger)(fmi2Component, const fmi2ValueReference *, size_t, int *);
typedef int (*DoStep)(fmi2Component, double, double, int);
typedef void (*FreeInstance)(fmi2Component);

static void logger(void *env, const char *name, int status, const char *category, const char *message, ...) {
    va_list args;
    va_start(args, message);
    fprintf(stderr, "[%s|%d|%s] ", name, status, category);
    vfprintf(stderr, message, args);
    fputc('\n', stderr);
    va_end(args);
}

static void *load(void *lib, const char *name) {
    void *f = dlsym(lib, name);
    if (!f) { fprintf(stderr, "missing %s\n", name); exit(3); }
    return f;
}

/* host <binary> <guid> <resource-uri> <h> <3 input vrs> <integer output vr> <real output vrs...>
   stdin: "normal_load creep velocity" per step; stdout: "status reals... integer" per step */
int main(int argc, char **argv) {
    if (argc < 10 || argc > 9 + 64) { fprintf(stderr, "usage: see source\n"); return 2; }
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "dlopen: %s\n", dlerror()); return 3; }
    Instantiate instantiate = (Instantiate)load(lib, "fmi2Instantiate");
    SetupExperiment setup = (SetupExperiment)load(lib, "fmi2SetupExperiment");
    Mode enter = (Mode)load(lib, "fmi2EnterInitializationMode"), leave = (Mode)load(lib, "fmi2ExitInitializationMode");
    Mode terminate = (Mode)load(lib, "fmi2Terminate");
    SetReal set_real = (SetReal)load(lib, "fmi2SetReal");
    GetReal get_real = (GetReal)load(lib, "fmi2GetReal");
    GetInteger get_integer = (GetInteger)load(lib, "fmi2GetInteger");
    DoStep do_step = (DoStep)load(lib, "fmi2DoStep");
    FreeInstance free_instance = (FreeInstance)load(lib, "fmi2FreeInstance");
    double h = atof(argv[4]), u[3], y[64];
    fmi2ValueReference in[3], integer_vr = (fmi2ValueReference)atoi(argv[8]), out[64];
    size_t n_out = (size_t)(argc - 9);
    for (int i = 0; i < 3; i++) in[i] = (fmi2ValueReference)atoi(argv[5 + i]);
    for (size_t i = 0; i < n_out; i++) out[i] = (fmi2ValueReference)atoi(argv[9 + i]);
    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2Component c = instantiate("c_host", 1, argv[2], argv[3], &callbacks, 0, 1);
    if (!c) { fprintf(stderr, "fmi2Instantiate failed\n"); return 4; }
    if (setup(c, 0, 0.0, 0.0, 0, 0.0) || enter(c) || leave(c)) { fprintf(stderr, "initialisation failed\n"); return 5; }
    int method, n = 0;
    while (scanf("%lf %lf %lf", &u[0], &u[1], &u[2]) == 3) {
        set_real(c, in, 3, u);
        int status = do_step(c, n * h, h, 1);
        get_real(c, out, n_out, y);
        get_integer(c, &integer_vr, 1, &method);
        printf("%d", status);
        for (size_t i = 0; i < n_out; i++) printf(" %.17g", y[i]);
        printf(" %d\n", method);
        n++;
    }
    terminate(c);
    free_instance(c);
    return 0; /* exit(): the static destructors and Py_Finalize of the interpreter pythonfmu started (docs/fmu.md,
                 "Exit") */
}
"""


def shared_libpython() -> Path | None:
    if not sysconfig.get_config_var("Py_ENABLE_SHARED"):
        return None
    path = Path(sysconfig.get_config_var("LIBDIR"), sysconfig.get_config_var("LDLIBRARY"))
    return path if path.is_file() else None
