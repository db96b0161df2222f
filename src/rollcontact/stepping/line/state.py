"""The stepping model's state: :class:`ModelState`, everything a :class:`~rollcontact.stepping.line.model.ContactModel`
remembers between communication points.

A module of its own because the FMU saves and restores it (FMI ``getFMUstate``/``setFMUstate`` and serialisation):
it is a plain dataclass, copied, turned into a JSON dict or bytes and read back, with a layout version
(:data:`STATE_VERSION`) checked on reading.
"""

from __future__ import annotations

import base64
import binascii
import dataclasses
import json
import math
from dataclasses import dataclass

import numpy as np

from rollcontact.line.instationary.model import MODES, InstationaryState
from rollcontact.stepping.base import ModelError
from rollcontact.stepping.line.parameters import STATIONARY, StepOutputs

STATE_VERSION = 5


READABLE_STATE_VERSIONS = (1, 2, 3, 4, 5)  # 1: no instationary state (quasi-steady history); 2: no creep
# envelope; 3: no table; 4: the table domain as one real, w_max (0: none)


@dataclass(slots=True)
class ModelState:
    """Everything a :class:`ContactModel` remembers between steps (plain, copyable, JSON-serialisable).

    Attributes
    ----------
    time : float
        Last communication point t_n [s] (the start time before the first step).
    position : float
        Axis position X(t_n) [m], high part of a compensated sum.
    position_error : float
        Low part [m] of the compensated sum; ``X = position + position_error``.
    previous : tuple or None
        ``(X, normal_load, creep, velocity)`` sampled at t_n; None before the first step.
    older : tuple or None
        The same one communication point earlier (second differences of the stationarity measure).
    steps : int
        Successful steps taken.
    outputs : StepOutputs
        Outputs of the last successful step (start values before the first).
    instationary : InstationaryState or None
        State of the instationary model while it is in use (None: quasi-steady).  Never modified in place.
    grid_load : float
        N' [N/m] the discretised transient's grid was built for (0: none yet; about twice the load it was
        aligned to, :meth:`ContactModel.prepare_grid`); part of the state because the traction history lives on
        that grid.
    creep_envelope : tuple or None
        ``(high, low)`` creep [1 of mu a/R] of :func:`rollcontact.line.instationary.creep_envelope`, kept by
        ``transient`` = 1 with a tolerance (the lag's error bound); None otherwise and after an unloaded step.
    table_domain : tuple of float
        Domain of the certified table the steps answer from (:mod:`rollcontact.stepping.line.table`: ``(w_max,)`` of
        falling friction, ``(N_low, N_high)`` [N/m] of a corrugation); ``()``: none.  A model restored into this
        state builds the same table (a deterministic function of the parameters and of this domain) before its next
        step, so restore -> step repeats the steps.
    version : int
        Layout version of this state; states of another version are refused by :meth:`from_dict`.
    """

    time: float
    position: float
    position_error: float
    previous: tuple[float, float, float, float] | None
    older: tuple[float, float, float, float] | None
    steps: int
    outputs: StepOutputs
    instationary: InstationaryState | None = None
    grid_load: float = 0.0
    creep_envelope: tuple[float, float] | None = None
    table_domain: tuple[float, ...] = ()
    version: int = STATE_VERSION

    @classmethod
    def initial(cls, start_time: float, initial_position: float) -> ModelState:
        """State at ``start_time`` [s] with the axis at ``initial_position`` [m] and no history."""
        outputs = StepOutputs(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, STATIONARY, 0, float(initial_position))
        return cls(float(start_time), float(initial_position), 0.0, None, None, 0, outputs)

    def commit(self, current_time: float, high: float, low: float, normal_load: float, creep: float, velocity: float,
               outputs: StepOutputs, lag, table_domain: tuple[float, ...] | None) -> None:
        """Make an evaluated step the state: time [s], axis position ``high + low`` [m]
        (:func:`rollcontact.stepping.line.model.advanced_position`), the samples (N [N], creep [1], V [m/s]), the
        outputs, the instationary state ``lag`` and the domain of the table in use (None: a model without a table)."""
        self.instationary = lag
        if table_domain is not None:
            self.table_domain = table_domain
        self.time = current_time
        self.older = self.previous
        self.position = high
        self.position_error = low
        self.previous = (high + low, normal_load, creep, velocity)
        self.steps += 1
        self.outputs = outputs

    def copy(self) -> ModelState:
        """An independent copy (all fields are immutable values)."""
        return dataclasses.replace(self)

    def to_dict(self) -> dict:
        """JSON-compatible dict; floats survive ``json`` exactly (``repr`` round trip), the instationary state as
        base64 of its exact bytes."""
        return {"version": self.version, "time": self.time, "position": self.position,
                "position_error": self.position_error,
                "previous": None if self.previous is None else list(self.previous),
                "older": None if self.older is None else list(self.older),
                "steps": self.steps, "outputs": list(self.outputs),
                "instationary": None if self.instationary is None
                else base64.b64encode(self.instationary.to_bytes()).decode("ascii"),
                "grid_load": self.grid_load,
                "creep_envelope": None if self.creep_envelope is None else list(self.creep_envelope),
                "table_domain": list(self.table_domain)}

    @classmethod
    def from_dict(cls, data: dict) -> ModelState:
        """Inverse of :meth:`to_dict`; raises ModelError for an unknown layout version or missing fields."""
        if data.get("version") not in READABLE_STATE_VERSIONS:
            raise ModelError(f"model state version {data.get('version')!r} is not supported "
                             f"(this rollcontact reads versions {READABLE_STATE_VERSIONS})")
        try:
            previous = data["previous"]
            older = data["older"]
            packed = data.get("instationary")
            envelope = data.get("creep_envelope")
            instationary = None if packed is None else InstationaryState.from_bytes(base64.b64decode(packed))
            return cls(float(data["time"]), float(data["position"]), float(data["position_error"]),
                       None if previous is None else tuple(float(v) for v in previous),
                       None if older is None else tuple(float(v) for v in older),
                       int(data["steps"]), StepOutputs(*data["outputs"]), instationary,
                       float(data.get("grid_load", 0.0)),
                       None if envelope is None else (float(envelope[0]), float(envelope[1])),
                       _domain(data.get("table_domain", [])), STATE_VERSION)
        except (KeyError, TypeError, ValueError) as exc:
            raise ModelError(f"invalid model state: {exc!r}") from None

    @classmethod
    def parse(cls, data) -> ModelState:
        """Strict inverse of :meth:`to_dict` for a dict from outside (e.g. an FMU state a host hands back).

        Unlike :meth:`from_dict`, which converts whatever it can, every field is checked: only the keys of
        :meth:`to_dict`, a readable ``version``, finite reals (``bool`` is no real), the ranges of the inputs in
        ``previous``/``older`` (N, V >= 0), a whole ``steps`` >= 0, the outputs' count, types and ranges, and an
        ``instationary`` string that is strict base64 of a state with a known mode, consistent shapes and finite
        values.  Nothing is changed; raises ModelError naming the first problem.
        """
        if not isinstance(data, dict):
            raise ModelError(f"a model state must be a dict, got {type(data).__name__}")
        required = {"version", "time", "position", "position_error", "previous", "older", "steps", "outputs"}
        optional = {"instationary", "grid_load", "creep_envelope", "table_domain"}
        unknown = [k for k in data if k not in required | optional]
        if unknown:
            raise ModelError(f"model state: unknown key(s) {_short(sorted(map(str, unknown)))}")
        missing = sorted(required - set(data))
        if missing:
            raise ModelError(f"model state: missing key(s) {missing}")
        version = data["version"]
        if type(version) is not int or version not in READABLE_STATE_VERSIONS:
            raise ModelError(f"model state version {_short(version)} is not supported "
                             f"(this rollcontact reads versions {READABLE_STATE_VERSIONS})")
        time, position, error = (_finite(f"model state {k}", data[k]) for k in ("time", "position", "position_error"))
        samples = [_samples(f"model state {k}", data[k]) for k in ("previous", "older")]
        if samples[0] is None and samples[1] is not None:
            raise ModelError("model state: 'older' is set but 'previous' is not")
        steps = data["steps"]
        if type(steps) is not int or steps < 0:
            raise ModelError(f"model state steps = {_short(steps)} must be a whole number >= 0")
        if (steps == 0) != (samples[0] is None):
            raise ModelError(f"model state: steps = {steps} contradicts previous = {_short(data['previous'])}")
        outputs = _outputs(data["outputs"])
        grid_load = _finite("model state grid_load", data.get("grid_load", 0.0))
        if grid_load < 0.0:
            raise ModelError(f"model state grid_load = {grid_load!r} must be >= 0")
        envelope = data.get("creep_envelope")
        if envelope is not None:
            if not isinstance(envelope, list | tuple) or len(envelope) != 2:
                raise ModelError(f"model state creep_envelope must be null or two reals, got {_short(envelope)}")
            envelope = tuple(_finite("model state creep_envelope", v) for v in envelope)
        instationary = _instationary(data.get("instationary"))
        domain = data.get("table_domain", [])
        if not (isinstance(domain, list | tuple) and len(domain) <= 2 or type(domain) in (int, float)):
            raise ModelError(f"model state table_domain must be at most two reals, got {_short(domain)}")
        domain = _domain([_finite("model state table_domain", v) for v in domain]
                         if isinstance(domain, list | tuple) else _finite("model state table_domain", domain))
        if any(v <= 0.0 for v in domain):
            raise ModelError(f"model state table_domain = {list(domain)!r} must be positive")
        return cls(time, position, error, samples[0], samples[1], steps, outputs, instationary, grid_load,
                   envelope, domain, STATE_VERSION)

    def to_bytes(self) -> bytes:
        """UTF-8 JSON of :meth:`to_dict`."""
        return json.dumps(self.to_dict()).encode("utf-8")

    @classmethod
    def from_bytes(cls, data: bytes) -> ModelState:
        """Inverse of :meth:`to_bytes`."""
        return cls.from_dict(json.loads(data.decode("utf-8")))


def _domain(value) -> tuple[float, ...]:
    """A table domain as a tuple: a list of reals (version 5), or the ``w_max`` of version 4 (0: none)."""
    if isinstance(value, list | tuple):
        return tuple(float(v) for v in value)
    return (float(value),) if value else ()


def _short(value, limit: int = 80) -> str:
    """``repr(value)`` cut to ``limit`` characters (messages must not carry a whole crafted state)."""
    text = repr(value)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def _finite(name: str, value) -> float:
    """``value`` as float if it is a finite int or float (not bool), else ModelError."""
    if type(value) not in (int, float) or not math.isfinite(value):
        raise ModelError(f"{name} = {_short(value)} must be a finite real number")
    return float(value)


def _samples(name: str, value) -> tuple[float, float, float, float] | None:
    """None, or an input sample ``(X, N, xi, V)`` of four finite reals with N >= 0 and V >= 0."""
    if value is None:
        return None
    if not isinstance(value, list | tuple) or len(value) != 4:
        raise ModelError(f"{name} must be null or four reals (X, N, xi, V), got {_short(value)}")
    sample = tuple(_finite(name, v) for v in value)
    if sample[1] < 0.0 or sample[3] < 0.0:
        raise ModelError(f"{name} = {_short(value)}: load and speed must be >= 0")
    return sample


def _outputs(value) -> StepOutputs:
    """The outputs of a state: one finite real per field, a known ``method_used`` code, no negative magnitude."""
    fields = StepOutputs._fields
    if not isinstance(value, list | tuple) or len(value) != len(fields):
        raise ModelError(f"model state outputs must be {len(fields)} values ({', '.join(fields)}), got "
                         f"{_short(value)}")
    values = []
    for name, v in zip(fields, value, strict=True):
        if name == "method_used":
            if type(v) is not int or not 0 <= v <= 6:
                raise ModelError(f"model state outputs: method_used = {_short(v)} must be a whole number 0 to 6")
            values.append(v)
            continue
        x = _finite(f"model state outputs: {name}", v)
        if name in ("contact_half_width", "stick_half_width", "max_pressure", "stationarity") and x < 0.0:
            raise ModelError(f"model state outputs: {name} = {x!r} must be >= 0")
        values.append(x)
    return StepOutputs(*values)


def _instationary(value) -> InstationaryState | None:
    """None, or the InstationaryState packed as strict base64 (known mode, consistent shapes, finite values)."""
    if value is None:
        return None
    if not isinstance(value, str):
        raise ModelError(f"model state instationary must be null or a base64 string, got {type(value).__name__}")
    try:
        state = InstationaryState.from_bytes(base64.b64decode(value.encode("ascii"), validate=True))
    except (UnicodeEncodeError, binascii.Error, ValueError) as exc:
        raise ModelError(f"model state instationary: {str(exc)[:200]}") from None
    if state.mode not in MODES:
        raise ModelError(f"model state instationary: unknown mode {_short(state.mode)}")
    scalars = (state.tangential_force_per_length, state.distance, *state.pending, *state.coarse_pending)
    grids = [(state.traction, state.stick, state.slip)]
    if state.coarse is not None:
        scalars += (state.coarse.tangential_force_per_length,)
        grids.append((state.coarse.traction, state.coarse.stick, state.coarse.slip))
    history = state.history
    arrays = [history.distance, history.normal_load_per_length, history.creep]
    if not all(math.isfinite(v) for v in scalars) or state.steps < 0:
        raise ModelError("model state instationary: a force, distance or pending roll is not finite")
    for traction, stick, slip in grids:
        if not (traction.ndim == stick.ndim == slip.ndim == 1 and traction.shape == stick.shape == slip.shape):
            raise ModelError("model state instationary: traction, stick and slip differ in shape")
        arrays += [traction, slip]
    if len({a.shape for a in arrays[:3]}) != 1 or arrays[0].ndim != 1:
        raise ModelError("model state instationary: the input history's arrays differ in shape")
    if not all(bool(np.all(np.isfinite(a))) for a in arrays):
        raise ModelError("model state instationary: an array holds a non-finite value")
    return state
