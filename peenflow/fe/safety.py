"""Instability detection: numba kernels return status codes, Python raises.

:class:`KernelInstabilityError` carries what happened, the likely cause and
the parameter to change; the driver raises it instead of returning garbage.
"""

from __future__ import annotations

from peenflow.fe import solver as _s


class KernelInstabilityError(RuntimeError):
    """The explicit integration became unstable or unphysical.

    Attributes: ``status`` (int code), ``shot_index`` (int or None),
    ``time`` (s).
    """

    def __init__(self, message: str, status: int, shot_index=None, time: float = float("nan")):
        super().__init__(message)
        self.status = status
        self.shot_index = shot_index
        self.time = time


_MESSAGES = {
    _s.ST_NEGATIVE_VOLUME: (
        "an element turned inside out (negative volume)",
        "the time step is too large for the deformation rate, or the mesh is too coarse for the "
        "shot velocity (elements under the shot crushed)",
        "lower options.dt_safety (e.g. 0.6) or refine the mesh under the impact (smaller h_fine)",
    ),
    _s.ST_DISTORTION: (
        "excessive element distortion (volume ratio V/V0 outside [0.1, 10])",
        "the mesh is too coarse for the shot velocity, or hourglass modes grew unchecked",
        "refine the mesh under the impact (with options.hourglass_type = 'stiffness': raise "
        "options.hourglass, e.g. 0.1)",
    ),
    _s.ST_NAN: (
        "NaN or Inf appeared in the state",
        "numerical blow-up, usually an unstable time step",
        "lower options.dt_safety; check material parameters (E, nu, density, A) for typos",
    ),
    _s.ST_DT_COLLAPSE: (
        "the stable time step collapsed below options.dt_floor_fraction of its initial value",
        "an element is being crushed (very large compression under the shot)",
        "refine the mesh or lower the shot velocity; raise options.dt_floor_fraction only if this is expected",
    ),
    _s.ST_RUNAWAY: (
        "runaway energy: the energy balance error exceeds options.runaway_fraction of the impact energy",
        "numerical instability (time step too large) or contact correction failure",
        "lower options.dt_safety",
    ),
    _s.ST_MAX_STEPS: (
        "the phase did not finish within options.max_steps steps (target never came to rest)",
        "damping too weak for this window/mesh, or a rest tolerance too strict",
        "raise options.max_steps or options.settle_damping, or loosen options.rest_ke_fraction",
    ),
}



def status_label(status: int) -> str:
    """What a kernel status code means, in a few words (``"an element turned inside out ..."``)."""
    return _MESSAGES[status][0] if status in _MESSAGES else f"status {status}"

def check_status(status: int, *, where: str, shot_index=None, time: float = float("nan")) -> None:
    """Raise :class:`KernelInstabilityError` if ``status`` is not OK."""
    status = int(status)
    if status == _s.ST_OK:
        return
    what, cause, fix = _MESSAGES.get(status, (f"unknown kernel status {status}", "a bug", "report it"))
    shot = "" if shot_index is None else f" during shot {shot_index}"
    raise KernelInstabilityError(
        f"peenflow.fe {where}{shot} at t = {time:.4e} s: {what}. Likely cause: {cause}. What to change: {fix}.",
        status,
        shot_index,
        time,
    )
