"""Global dynamic relaxation: damp the whole target to rest.

Used after the last impact and at snapshots, on a COPY of the state so the
continuing run is not disturbed. Mass-proportional damping
(``alpha = relax_damping * pi * c_shear / L``, ``L`` the larger of the
mesh's half width and depth, see :meth:`Model.settle_alpha`) over the whole
mesh, no shot, until ``KE <= relax_ke_fraction * E_ref`` and
``max |v| <= relax_v_fraction * v_ref`` (checked every 10 steps). Static
equilibrium is all that matters here, so the damping does not bias the
result; it also restores equilibrium across the edges of the active windows
used during the impacts.
"""

from __future__ import annotations

from peenflow.fe import solver as S
from peenflow.fe.state import KernelState


def relax(model, state: KernelState, options, e_ref: float, v_ref: float, *, copy: bool = True, where="relaxation"):
    """Damp ``state`` (a copy if ``copy``) to rest over the whole mesh.

    Returns ``(relaxed_state, PhaseResult)``.
    """
    st = state.copy() if copy else state
    win = model.full_window
    res = model.phase(
        st,
        S.MODE_RELAX,
        win,
        _no_shot(),
        safety=options.dt_safety,
        alpha=model.settle_alpha(win, options.relax_damping),
        rest_ke=options.relax_ke_fraction * e_ref,
        rest_v=options.relax_v_fraction * v_ref,
        e_ref=0.0,
        max_steps=options.max_steps,
        threads=options.threads,
        where=where,
    )
    st.v[:] = 0.0
    return st, res


def _no_shot():
    import numpy as np

    from peenflow.fe.contact import N_SHOT

    s = np.zeros(N_SHOT)
    s[9] = s[10] = s[11] = 1.0
    return s
