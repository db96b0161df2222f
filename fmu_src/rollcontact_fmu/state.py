"""The FMU state of a :class:`~rollcontact_fmu.slave.TableSlave`: what it holds, its bytes and the check of a state
handed back (``canGetAndSetFMUstate``, ``canSerializeFMUstate``).

A state is a JSON-compatible dict (:class:`FmuState`): the format and layout version, the FMU's name, every non-output
variable, the outputs, the life-cycle fields and the model's own state dict.  Its bytes are UTF-8 JSON with a SHA-256
checksum (:func:`serialise_state`); pythonfmu calls the byte converters on the class.  Bytes that are no such state
(not UTF-8, not JSON, no or a wrong checksum) become a marker dict that ``_set_fmu_state`` refuses, and a state is
checked completely before anything changes (:meth:`FmuState.check_state`): a refused state changes nothing.
"""

from __future__ import annotations

import hashlib
import json
import math

from pythonfmu import Real
from pythonfmu.variables import Integer, String

STATE_FORMAT = "rollcontact TableSlave FMU state"
"""``format`` of every FMU state of a :class:`~rollcontact_fmu.slave.TableSlave`."""

STATE_VERSION = 1
"""Layout version of the FMU state (``version``); states of another version are refused."""

STATE_KEYS = frozenset({"format", "version", "fmu", "variables", "outputs", "start_time", "initialised", "next_time",
                        "model"})
"""The keys of an FMU state."""

UNDECODABLE = "undecodable FMU state"
"""Key of the marker dict ``_fmu_state_from_bytes`` returns for bytes that are no serialised state."""

CHECKSUM = "sha256"
"""Key of the serialised state's checksum: SHA-256 of :func:`canonical_json` of the state without it."""

NOT_INITIALISED = "the FMU is not initialised: exit initialisation mode before stepping"
"""Why a step of an instance before ``exit_initialization_mode`` (or of such a state) is discarded."""

INT32 = (-(2**31), 2**31 - 1)


class StateRefused(ValueError):
    """An FMU state that cannot be set; the message says why."""


def canonical_json(value) -> str:
    """The JSON text a state is serialised and checksummed as (sorted keys: the same text after a round trip)."""
    return json.dumps(value, sort_keys=True)


def serialise_state(state) -> bytes:
    """UTF-8 JSON of the FMU state ``state`` (a dict) with its checksum added."""
    return canonical_json({**state, CHECKSUM: hashlib.sha256(canonical_json(state).encode()).hexdigest()}).encode()


def deserialise_state(data: bytes):
    """The FMU state of :func:`serialise_state`'s bytes; ValueError (saying why) for anything else.

    The checksum catches accidental corruption (a flipped digit still parses); the state's content is checked when
    it is set, since anyone can compute a checksum.
    """
    try:
        state = json.loads(bytes(data).decode("utf-8"))
    except Exception as exc:  # noqa: BLE001 - UnicodeDecodeError, JSONDecodeError, RecursionError, ...
        raise ValueError(f"the serialised FMU state ({len(data)} bytes) is not UTF-8 JSON: "
                         f"{type(exc).__name__}: {clip(str(exc))}") from None
    if not isinstance(state, dict) or not isinstance(state.get(CHECKSUM), str):
        raise ValueError(f"the serialised FMU state ({len(data)} bytes) is no JSON object with a checksum")
    digest = state.pop(CHECKSUM)
    if hashlib.sha256(canonical_json(state).encode()).hexdigest() != digest:
        raise ValueError(f"the serialised FMU state ({len(data)} bytes) does not match its checksum: it is corrupt")
    return state


def clip(text: str, limit: int = 200) -> str:
    """``text`` cut to ``limit`` characters."""
    return text if len(text) <= limit else text[:limit - 3] + "..."


def short(value, limit: int = 80) -> str:
    """``repr(value)`` cut to ``limit`` characters: a log message never carries a whole crafted state."""
    return clip(repr(value), limit)


def is_real(value) -> bool:
    """An int or float, not a bool (JSON numbers)."""
    return type(value) in (int, float)


def same_value(a, b) -> bool:
    """Equal numbers (both NaN included), equal strings or arrays of such values: a host re-setting the value in
    force changes nothing."""
    if isinstance(a, list | tuple) and isinstance(b, list | tuple):
        return len(a) == len(b) and all(map(same_value, a, b))
    if is_real(a) and is_real(b):
        return a == b or (a != a and b != b)
    return type(a) is type(b) and a == b


def checked_value(name: str, value, kind):
    """A state's value of the variable ``name`` of type ``kind`` (Real as float); StateRefused for another type."""
    if kind is Real and is_real(value):
        return float(value)
    if (kind is Integer and type(value) is int and INT32[0] <= value <= INT32[1]) or (
            kind is String and type(value) is str):
        return value
    raise StateRefused(f"variables: {name} = {short(value)} is not of type {kind.__name__}")


class FmuState:
    """The FMU state methods pythonfmu and pythonfmu3 call, for a :class:`~rollcontact_fmu.slave.TableSlave` (whose
    table, life-cycle fields, model hooks and ``refuse`` they use).

    Never raises: bytes that are no state, and a state that does not check out, are refused (emulated fmi2Error,
    the instance keeps its state).
    """

    def _get_fmu_state(self):
        return {"format": STATE_FORMAT, "version": STATE_VERSION, "fmu": self.modelName,
                "variables": {name: getattr(self, name) for name in self.state_variables},
                "outputs": list(self.outputs), "start_time": self.start_time, "initialised": self.initialised,
                "next_time": self.next_time, "model": None if self.model is None else self.model.state.to_dict()}

    def _set_fmu_state(self, state):
        try:
            checked = self.check_state(state)
            if checked["model"] is not None:  # before anything changes: a refused model state changes nothing
                self.restore_model(checked["model"], checked["model_state"])
        except Exception as exc:  # noqa: BLE001 - StateRefused, or anything unforeseen: never fmi2Fatal
            reason = str(exc) if isinstance(exc, StateRefused) else f"{type(exc).__name__}: {clip(str(exc), 200)}"
            self.refuse(f"{self.WORDS['set_state']} refused, the instance keeps its previous state: {reason}")
            return
        for name, value in checked["variables"].items():
            setattr(self, name, value)
        self.start_time, self.initialised, self.next_time = (checked[k] for k in ("start_time", "initialised",
                                                                                    "next_time"))
        self.model, self.model_values, self.problem = checked["model"], checked["values"], checked["problem"]
        self.outputs = checked["outputs"]
        if self.model is not None:
            self.outputs = tuple(self.restored_outputs(self.outputs))
        self.error = None

    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        try:
            return serialise_state(state)
        except Exception as exc:  # noqa: BLE001 - never fmi2Fatal: the bytes are refused when set
            return f"the FMU state could not be serialised: {clip(str(exc))}".encode()

    @staticmethod
    def _fmu_state_from_bytes(state):
        try:
            return deserialise_state(state)
        except Exception as exc:  # noqa: BLE001 - never fmi2Fatal: the marker is refused when set
            return {UNDECODABLE: str(exc)}

    def check_state(self, state):
        """Everything ``_set_fmu_state`` needs from ``state`` as a dict, checked completely; raises StateRefused
        and changes nothing (a new model may be built, but is not installed)."""
        if isinstance(state, dict) and set(state) == {UNDECODABLE}:
            raise StateRefused(str(state[UNDECODABLE]))
        if not isinstance(state, dict):
            raise StateRefused(f"an FMU state is a JSON object, got {type(state).__name__} {short(state)}")
        if state.get("format") != STATE_FORMAT:
            raise StateRefused(f"not an FMU state of this FMU (format {short(state.get('format'))})")
        version = state.get("version")
        if type(version) is not int or version != STATE_VERSION:
            raise StateRefused(f"FMU state version {short(version)} is not supported (this FMU reads version "
                               f"{STATE_VERSION})")
        if set(state) != STATE_KEYS:
            unknown, missing = sorted(map(str, set(state) - STATE_KEYS)), sorted(STATE_KEYS - set(state))
            raise StateRefused(f"unknown key(s) {short(unknown)}, missing key(s) {missing}")
        if state["fmu"] != self.modelName:
            raise StateRefused(f"the state belongs to the FMU {short(state['fmu'])}, not {self.modelName}")
        variables = self.check_variables(state["variables"])
        outputs = self.check_outputs(state["outputs"])
        start_time, initialised, next_time = state["start_time"], state["initialised"], state["next_time"]
        if not is_real(start_time) or not math.isfinite(start_time):
            raise StateRefused(f"start_time = {short(start_time)} must be a finite real number")
        if type(initialised) is not bool:
            raise StateRefused(f"initialised = {short(initialised)} must be true or false")
        if initialised != (next_time is not None) or (
                next_time is not None and (not is_real(next_time) or not math.isfinite(next_time))):
            raise StateRefused(f"next_time = {short(next_time)} must be a finite real number once initialised, "
                               f"else null (initialised = {initialised})")
        data = state["model"]
        if data is not None and not isinstance(data, dict):
            raise StateRefused(f"model must be null or an object, got {type(data).__name__}")
        values = {name: variables[name] for name in self.parameter_names}
        checked = {"variables": variables, "outputs": outputs, "start_time": float(start_time),
                   "initialised": initialised, "next_time": None if next_time is None else float(next_time),
                   "model": None, "model_state": None, "values": None, "problem": NOT_INITIALISED}
        if not initialised:
            if data is not None:
                raise StateRefused("a state saved before initialisation holds no model state")
            return checked
        if self.model is not None and self.model_values is not None and all(
                same_value(values[k], self.model_values[k]) for k in values):
            model = self.model  # same parameters: the model is kept (only its state is set)
        else:
            try:
                model, _ = self.new_model(dict(values))
            except Exception as exc:  # noqa: BLE001 - the state's own parameters are invalid
                if data is not None:
                    raise StateRefused(f"its parameters are invalid ({clip(str(exc), 200)}) but it holds a model "
                                       "state") from None
                return {**checked, "values": values, "problem": f"invalid parameters: {exc}"}
        if data is None:
            raise StateRefused("an initialised state with valid parameters must hold the model's state")
        try:
            model_state = self.parse_model_state(data)
        except Exception as exc:  # noqa: BLE001
            raise StateRefused(clip(str(exc), 300)) from None
        return {**checked, "model": model, "model_state": model_state, "values": values, "problem": None}

    def check_variables(self, variables) -> dict:
        """The state's variables: exactly the non-output variables, each of its type."""
        if not isinstance(variables, dict):
            raise StateRefused(f"variables must be an object, got {type(variables).__name__}")
        unknown = [k for k in variables if k not in self.state_variables]
        missing = [k for k in self.state_variables if k not in variables]
        if unknown or missing:
            raise StateRefused(f"variables: unknown {short(sorted(map(str, unknown)))}, missing {short(missing)} "
                               "(a state holds exactly the FMU's input and parameter variables)")
        checked = {}
        for name in self.state_variables:
            value, kind, size = variables[name], self.kinds[name], self.DIMENSIONS.get(name)
            if size is None:
                checked[name] = checked_value(name, value, kind)
            elif type(value) is list and len(value) == size:
                checked[name] = [checked_value(name, element, kind) for element in value]
            else:
                raise StateRefused(f"variables: {name} = {short(value)} is not a list of {size} values")
        return checked

    def check_outputs(self, outputs) -> tuple:
        """The state's outputs: one finite value of its type per output."""
        if not isinstance(outputs, list) or len(outputs) != len(self.output_names):
            raise StateRefused(f"outputs must be a list of {len(self.output_names)} values, got {short(outputs)}")
        for name, kind, value in zip(self.output_names, self.output_kinds, outputs, strict=True):
            ok = (is_real(value) and math.isfinite(value)) if kind is Real else \
                (type(value) is int and INT32[0] <= value <= INT32[1])
            if not ok:
                raise StateRefused(f"outputs: {name} = {short(value)} is not a finite value of type {kind.__name__}")
        return tuple(float(v) if kind is Real else v for kind, v in zip(self.output_kinds, outputs, strict=True))
