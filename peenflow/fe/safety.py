"""Instability detection: numba kernels return status codes, Python raises.

The status codes are defined here, once (the element pass and the solver
import them; numba reads them as compile-time constants). A non-OK code
becomes a :class:`KernelInstabilityError` carrying a typed reason
(:class:`Stop`), where it happened, and the parameters to change as
:class:`Knob` values, not as text: its message names them in the kernel's
terms (``options.dt_safety``, :data:`KERNEL_TERMS`), and a caller that
speaks another vocabulary (a study's keys, :mod:`tasks._kernel`) renders the
same stop in its own terms with :meth:`KernelInstabilityError.in_terms`.
"""

from __future__ import annotations

import enum
from typing import Mapping

# status codes of the element pass and the explicit loop (numba returns them as ints)
ST_OK = 0
ST_NEGATIVE_VOLUME = 2
ST_DISTORTION = 3
ST_NAN = 4
ST_DT_COLLAPSE = 5
ST_RUNAWAY = 6
ST_MAX_STEPS = 7


class Stop(enum.IntEnum):
    """Why the kernel stopped (its value is the status code)."""

    NEGATIVE_VOLUME = ST_NEGATIVE_VOLUME
    DISTORTION = ST_DISTORTION
    NAN = ST_NAN
    DT_COLLAPSE = ST_DT_COLLAPSE
    RUNAWAY = ST_RUNAWAY
    MAX_STEPS = ST_MAX_STEPS


class Knob(enum.Enum):
    """A parameter a stop message tells the user to change (its name depends on who reads the message)."""

    DT_SAFETY = "dt_safety"            # the time-step safety factor
    MESH = "mesh"                      # refining the mesh under the impact
    SHOT_VELOCITY = "shot_velocity"    # the shot velocity
    HOURGLASS = "hourglass"            # the stiffness-form hourglass coefficient
    DT_FLOOR = "dt_floor"              # the step-collapse floor
    RUNAWAY = "runaway"                # the runaway-energy limit
    MAX_STEPS = "max_steps"            # the step budget of a phase
    DAMPING = "damping"                # the damping of settling (impact) or of a relaxation
    REST = "rest"                      # the "at rest" energy tolerance of settling or of a relaxation


#: a vocabulary: Knob -> its name; or (impact name, relaxation name) where the two phases differ
Terms = Mapping[Knob, "str | tuple[str, str]"]

#: the kernel's own vocabulary (:class:`peenflow.fe.impact.Options` fields)
KERNEL_TERMS: Terms = {
    Knob.DT_SAFETY: "options.dt_safety",
    Knob.MESH: "the mesh under the impact (smaller h_fine)",
    Knob.SHOT_VELOCITY: "the shot velocity",
    Knob.HOURGLASS: "options.hourglass (with options.hourglass_type = 'stiffness')",
    Knob.DT_FLOOR: "options.dt_floor_fraction",
    Knob.RUNAWAY: "options.runaway_fraction",
    Knob.MAX_STEPS: "options.max_steps",
    Knob.DAMPING: ("options.settle_damping", "options.relax_damping"),
    Knob.REST: ("options.rest_ke_fraction", "options.relax_ke_fraction"),
}

# Stop -> (what happened, likely cause, what to change), the knobs written {KNOB_NAME}
_MESSAGES = {
    Stop.NEGATIVE_VOLUME: (
        "an element turned inside out (negative volume)",
        "the time step is too large for the deformation rate, or the mesh is too coarse for the "
        "shot velocity (elements under the shot crushed)",
        "lower {DT_SAFETY} (e.g. 0.6) or refine {MESH}",
    ),
    Stop.DISTORTION: (
        "excessive element distortion (volume ratio V/V0 outside [0.1, 10])",
        "the mesh is too coarse for the shot velocity, or hourglass modes grew unchecked",
        "refine {MESH}, or raise {HOURGLASS} to e.g. 0.1",
    ),
    Stop.NAN: (
        "NaN or Inf appeared in the state",
        "numerical blow-up, usually an unstable time step",
        "lower {DT_SAFETY}; check material parameters (E, nu, density, A) for typos",
    ),
    Stop.DT_COLLAPSE: (
        "the stable time step collapsed below {DT_FLOOR} of its initial value",
        "an element is being crushed (very large compression under the shot)",
        # a lower floor is what lets the step shrink further
        "refine {MESH} or lower {SHOT_VELOCITY}; lower {DT_FLOOR} only if this is expected",
    ),
    Stop.RUNAWAY: (
        "runaway energy: the energy balance error exceeds {RUNAWAY} of the impact energy",
        "numerical instability (time step too large) or contact correction failure",
        "lower {DT_SAFETY}",
    ),
    Stop.MAX_STEPS: (
        "the phase did not finish within {MAX_STEPS} steps (target never came to rest)",
        "damping too weak for this window/mesh, or a rest tolerance too strict",
        "raise {MAX_STEPS} or {DAMPING}, or loosen {REST}",
    ),
}


def _name(terms: Terms, knob: Knob, relaxing: bool) -> str:
    name = terms[knob]
    return name if isinstance(name, str) else name[1 if relaxing else 0]


def advice(stop: Stop, terms: Terms = KERNEL_TERMS, *, relaxing: bool = False) -> tuple[str, str, str]:
    """(what happened, likely cause, what to change) of ``stop``, its knobs named by ``terms``
    (``relaxing``: the stop came from a relaxation, whose damping and rest tolerance are its own)."""
    names = {k.name: _name(terms, k, relaxing) for k in Knob}
    return tuple(text.format(**names) for text in _MESSAGES[stop])


def knobs(stop: Stop) -> tuple[Knob, ...]:
    """The knobs the message of ``stop`` names, in order of first mention."""
    text = " ".join(_MESSAGES[stop])
    return tuple(sorted((k for k in Knob if "{" + k.name + "}" in text), key=lambda k: text.index("{" + k.name)))


class KernelInstabilityError(RuntimeError):
    """The explicit integration became unstable or unphysical.

    Attributes: ``reason`` (:class:`Stop`, or the int code of an unknown
    status), ``status`` (int code), ``where`` (the phase: ``"impact"``,
    ``"final relaxation"``, ...), ``shot_index`` (int or None), ``time`` (s),
    ``relaxing`` (the stop came from a relaxation), ``terms`` (the vocabulary
    its message names the knobs in; :meth:`in_terms`).
    """

    def __init__(self, reason: "Stop | int", *, where: str, shot_index=None, time: float = float("nan"),
                 relaxing: bool = False, terms: Terms = KERNEL_TERMS, note: str = ""):
        try:
            reason = Stop(int(reason))
        except ValueError:
            reason = int(reason)
        self.reason, self.where, self.shot_index, self.time = reason, where, shot_index, time
        self.relaxing, self.terms, self.note = relaxing, terms, note
        if isinstance(reason, Stop):
            what, cause, fix = advice(reason, terms, relaxing=relaxing)
        else:
            what, cause, fix = f"unknown kernel status {reason}", "a bug", "report it"
        shot = "" if shot_index is None else f" during shot {shot_index}"
        super().__init__(f"peenflow.fe {where}{shot} at t = {time:.4e} s: {what}. Likely cause: {cause}. "
                         f"What to change: {fix}.{note}")

    @property
    def status(self) -> int:
        return int(self.reason)

    def in_terms(self, terms: Terms, note: str = "") -> "KernelInstabilityError":
        """The same stop, its message naming the knobs by ``terms`` (``note`` appended)."""
        return KernelInstabilityError(self.reason, where=self.where, shot_index=self.shot_index, time=self.time,
                                      relaxing=self.relaxing, terms=terms, note=note)

    def __reduce__(self):  # pickles (a dask worker's stop reaches the scheduler whole)
        return _rebuild, (self.reason, self.where, self.shot_index, self.time, self.relaxing, dict(self.terms),
                          self.note)


def _rebuild(reason, where, shot_index, time, relaxing, terms, note):
    return KernelInstabilityError(reason, where=where, shot_index=shot_index, time=time, relaxing=relaxing,
                                  terms=terms, note=note)


def status_label(status: int) -> str:
    """What a kernel status code means, in a few words (``"an element turned inside out ..."``)."""
    return advice(Stop(status))[0] if status in Stop._value2member_map_ else f"status {status}"


def check_status(status: int, *, where: str, shot_index=None, time: float = float("nan"),
                 relaxing: bool = False) -> None:
    """Raise :class:`KernelInstabilityError` if ``status`` is not OK (``relaxing``: in a relaxation)."""
    status = int(status)
    if status != ST_OK:
        raise KernelInstabilityError(status, where=where, shot_index=shot_index, time=time, relaxing=relaxing)
