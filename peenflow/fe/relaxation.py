"""Global relaxation: bring the whole target to static equilibrium.

Used after the last impact and at snapshots, on a COPY of the state so the
continuing run is not disturbed. Only the final static state matters (no
physical path), and it restores equilibrium across the edges of the active
windows used during the impacts. Two methods (``Options.relax_method``):

``"static"`` (default; needs a fixed bottom, else it falls back to DR)
    Newton-like defect correction on the true nonlinear forces::

        r = f(x)                         (element pass with dt = 0, v = 0)
        repeat:
            E = 1/2 r . M r              (M: one multigrid V-cycle ~ K^-1)
            stop if E <= STATIC_ENERGY_FACTOR * relax_ke_fraction * E_ref
            du = K^-1 r                  (CG + multigrid, relative residual relax_cg_rtol)
            x += du; r = f(x)            (one element pass over a 1 s "step"
                                          with v = du: the solver's own stress
                                          update, Jaumann rotation and
                                          Johnson-Cook return map, rate term off)

    ``K`` is the linear elastic stiffness of the solver's element on the
    undeformed box grid (:mod:`peenflow.fe.multigrid`); it differs from the
    true tangent only under the dents (deformed geometry, stress stiffness,
    yielding), which the outer loop corrects. ``E`` estimates the elastic
    energy still locked in the force imbalance (``1/2 r . K^-1 r``, the
    energy dynamic relaxation would still have to dissipate); it is
    measured on the state that is returned. ``STATIC_ENERGY_FACTOR = 0.001``
    with loose inner solves (``relax_cg_rtol = 0.3``: 1-3 V-cycles per
    correction; the outer loop corrects on the true forces anyway) reaches
    the accuracy that 0.01 with ``relax_cg_rtol = 1e-2`` had (10x closer to a
    strict reference than dynamic relaxation at the same ``relax_ke_fraction``)
    in half the V-cycles (docs/performance.md section 3, "Cost and error against a strict solve").
    Plasticity is not frozen: an
    element that the correction loads past yield goes through the same
    return map as in dynamic relaxation. If the outer loop does not converge
    in ``relax_max_outer`` corrections (or diverges), dynamic relaxation
    takes over from the current state.

``"dynamic"``
    Damped dynamic relaxation. Mass-proportional damping
    (``alpha = relax_damping * pi * c_shear / L``, ``L`` the larger of the
    mesh's half width and depth, see :meth:`Model.settle_alpha`) over the
    whole mesh, no shot, until ``KE <= relax_ke_fraction * E_ref`` and
    ``max |v| <= relax_v_fraction * v_ref`` (checked every 10 steps).

Periodic lateral faces (:mod:`peenflow.fe.boundary`): the static method
works in the tied space -- residuals folded onto the masters, the multigrid
built for ``K_p = T^T K T`` on every level (``T`` copies masters to
slaves), corrections unfolded -- and dynamic relaxation ties the faces in
the solver's node update.

Both leave ``v = 0``. Both are deterministic and independent of the thread
count (the multigrid is serial; the element pass is bit-identical on any
number of threads).
"""

from __future__ import annotations

import numba
import numpy as np

from peenflow.fe import solver as S
from peenflow.fe.element import element_rows, element_rows_parallel
from peenflow.fe.model import PhaseResult
from peenflow.fe.boundary import mask_fixed
from peenflow.fe.multigrid import dot, pcg
from peenflow.fe.safety import check_status
from peenflow.fe.state import KernelState

#: static "at rest": imbalance energy <= STATIC_ENERGY_FACTOR * relax_ke_fraction * E_ref
STATIC_ENERGY_FACTOR = 0.001

#: columns of the static relaxation's records (one row per outer correction)
STATIC_RECORD_FIELDS = ("energy_estimate", "cg_iterations", "cg_residual", "max_correction")


def relax(model, state: KernelState, options, e_ref: float, v_ref: float, *, copy: bool = True, where="relaxation"):
    """Bring ``state`` (a copy if ``copy``) to rest over the whole mesh.

    Returns ``(relaxed_state, PhaseResult)``. For the static method,
    ``info[I_STEPS]`` counts element passes, ``info[I_KE_END]`` is the final
    energy estimate ``E`` (J) and the records are :data:`STATIC_RECORD_FIELDS`.
    """
    st = state.copy() if copy else state
    method = getattr(options, "relax_method", "dynamic")
    if method not in ("static", "dynamic"):
        raise ValueError(f"relax_method must be 'static' or 'dynamic', not {method!r}")
    if method == "static" and model.target.bottom == "fixed":
        res = relax_static(model, st, options, e_ref, where=where)
        if res.status == S.ST_OK:
            return st, res
    res = relax_dynamic(model, st, options, e_ref, v_ref, where=where)
    return st, res


def relax_dynamic(model, st: KernelState, options, e_ref: float, v_ref: float, *, where="relaxation") -> PhaseResult:
    """Damped dynamic relaxation of ``st`` in place (see the module docstring)."""
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
    return res


def _forces(model, st: KernelState, dt: float, threads: int, where: str) -> np.ndarray:
    """Element pass over the whole mesh with step ``dt`` (updates the state); free-dof forces (N)."""
    st.f[:] = 0.0
    fn = element_rows_parallel if threads > 1 else element_rows
    if threads > 1:
        numba.set_num_threads(threads)
    _, status, wi, wp, wh, wv = fn(st.x, st.v, st.f, st.stress, st.eps_p, st.sy_static, st.hg, st.temp, model.vol0,
                                   model.mat_static, dt, model.nnx, model.nny, model.nx, model.ny,
                                   0, model.nx, 0, model.ny, 0, model.nz)
    check_status(status, where=where, time=float(st.ctl[S.C_TIME]), relaxing=True)
    st.energy[S.E_INT] += wi
    st.energy[S.E_PL] += wp
    st.energy[S.E_HG] += wh
    st.energy[S.E_VISC] += wv
    r = model.fold(st.f.copy())  # periodic: the tied space's forces live on the masters
    mask_fixed(r, model.bc)
    return r


def relax_static(model, st: KernelState, options, e_ref: float, *, where="relaxation") -> PhaseResult:
    """Static relaxation of ``st`` in place (see the module docstring).

    Status ``ST_OK`` when converged, ``ST_MAX_STEPS`` when not (the state is
    then left wherever the corrections brought it, at ``v = 0``).
    """
    mg = model.multigrid()
    tol = STATIC_ENERGY_FACTOR * options.relax_ke_fraction * e_ref
    threads = options.threads
    st.v[:] = 0.0
    r = _forces(model, st, 0.0, threads, where)
    passes = 1
    rows = []
    info = np.zeros(S.N_INFO)
    status = S.ST_MAX_STEPS
    e_first = None
    energy = np.inf
    for _ in range(options.relax_max_outer + 1):
        z = mg.vcycle(r)
        energy = 0.5 * dot(r, z)
        if e_first is None:
            e_first = energy
        if energy <= tol:
            status = S.ST_OK
            break
        if len(rows) == options.relax_max_outer or energy > 100.0 * e_first:
            break
        du, its, rel = pcg(mg, r, rtol=options.relax_cg_rtol, z0=z)
        model.unfold(du)  # periodic: slaves move with their masters
        rows.append((energy, its, rel, float(np.abs(du).max())))
        st.v[:] = du  # applied over a step of 1 s: v = du / (1 s)
        st.x[:] += du
        r = _forces(model, st, 1.0, threads, where)
        passes += 1
        st.v[:] = 0.0
    st.v[:] = 0.0
    info[S.I_STATUS] = status
    info[S.I_STEPS] = passes
    info[S.I_KE_END] = energy
    rec = np.array(rows, dtype=np.float64).reshape(-1, len(STATIC_RECORD_FIELDS))
    return PhaseResult(int(status), info, rec)


def _no_shot():
    from peenflow.fe.contact import N_SHOT

    s = np.zeros(N_SHOT)
    s[9] = s[10] = s[11] = 1.0
    return s
