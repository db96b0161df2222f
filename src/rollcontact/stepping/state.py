"""The stepping model's state: :class:`ModelState`, everything a :class:`~rollcontact.stepping.model.ContactModel`
remembers between communication points.

A module of its own because the FMU saves and restores it (FMI ``getFMUstate``/``setFMUstate`` and serialisation):
it is a plain dataclass, copied, turned into a JSON dict or bytes and read back, with a layout version
(:data:`STATE_VERSION`) checked on reading.
"""

from __future__ import annotations

import base64
import dataclasses
import json
from dataclasses import dataclass

from rollcontact.instationary.model import InstationaryState
from rollcontact.stepping.parameters import STATIONARY, ModelError, StepOutputs

STATE_VERSION = 3


READABLE_STATE_VERSIONS = (1, 2, 3)  # 1: no instationary state (read as quasi-steady history); 2: no creep envelope


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
        ``(high, low)`` creep [1 of mu a/R] of :func:`rollcontact.instationary.creep_envelope`, kept by
        ``transient`` = 1 with a tolerance (the lag's error bound); None otherwise and after an unloaded step.
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
    version: int = STATE_VERSION

    @classmethod
    def initial(cls, start_time: float, initial_position: float) -> ModelState:
        """State at ``start_time`` [s] with the axis at ``initial_position`` [m] and no history."""
        outputs = StepOutputs(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, STATIONARY, 0, float(initial_position))
        return cls(float(start_time), float(initial_position), 0.0, None, None, 0, outputs)

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
                "creep_envelope": None if self.creep_envelope is None else list(self.creep_envelope)}

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
                       None if envelope is None else (float(envelope[0]), float(envelope[1])), STATE_VERSION)
        except (KeyError, TypeError, ValueError) as exc:
            raise ModelError(f"invalid model state: {exc!r}") from None

    def to_bytes(self) -> bytes:
        """UTF-8 JSON of :meth:`to_dict`."""
        return json.dumps(self.to_dict()).encode("utf-8")

    @classmethod
    def from_bytes(cls, data: bytes) -> ModelState:
        """Inverse of :meth:`to_bytes`."""
        return cls.from_dict(json.loads(data.decode("utf-8")))
