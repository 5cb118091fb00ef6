"""Single impact of ``benchmarks/bench_hourglass.py`` run with a chosen element, on equal footing.

:func:`run` is ``bench_hourglass.run(case, element, h_um)`` -- same mesh (:func:`bench_hourglass.block`),
shot, contact (the kernel's :func:`peenflow.fe.contact.contact_kinematic`; or, ``contact="mortar"``, the
weighted-gap contact of :mod:`benchmarks.bbar.contact_mortar`), boundary conditions
(fixed bottom, symmetric sides; quarter model for normal impacts, half model for oblique ones), the
same event-driven start, impact and damped settle as :class:`peenflow.fe.impact.ImpactRun` (the
kernel's helpers :func:`_shot_vector`, :func:`time_to_contact`, :func:`contact_estimates`,
:meth:`Model.settle_alpha` are called, not copied) -- with the explicit loop of
:func:`benchmarks.bbar.element_bbar.run_phase_bbar` (a copy of the kernel's ``run_phase`` whose
element pass is chosen by ``kind``). One difference, the same for both elements: the final
spring-back is DAMPED DYNAMIC RELAXATION over the whole mesh (the kernel's ``relax_method =
"dynamic"``: ``alpha = relax_damping pi c_s / L``, at rest when ``KE <= relax_ke_fraction E_ref`` and
``max |v| <= relax_v_fraction v_ref``), because the kernel's static relaxation is built on the
one-point element's stiffness. The element kinds:

* ``"physical"``: the kernel's one-point element with physical hourglass control (``kind = 0``;
  identical to ``run_impacts(..., Options(relax_method="dynamic"))``, tests/fe/test_bbar_element.py);
* ``"bbar"``: the B-bar (mean-dilatation) 2 x 2 x 2 hexahedron of :mod:`benchmarks.bbar.element_bbar`.
* ``"physical8"``: the kernel's physical element with its assumed strain sampled at the 2 x 2 x 2 Gauss
  points, a Johnson-Cook return at each (:func:`benchmarks.bbar.element_bbar.p8_pass`; BENCHMARKS.md 4e).

The B-bar and physical8 elements' stress is kept per Gauss point; the metrics read each element's
volume-weighted mean (physical8: the plain mean, its points' weights being V / 8; what the one-point
element's single stress stands for), so :func:`bench_hourglass.metrics`
applies unchanged.
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

BENCH = Path(__file__).resolve().parents[1]
if str(BENCH) not in sys.path:
    sys.path.insert(0, str(BENCH))

import bench_hourglass as bh  # noqa: E402

from benchmarks.bbar.element_bbar import element_pass, run_phase_bbar  # noqa: E402
from peenflow.fe import solver as S  # noqa: E402
from peenflow.fe.impact import Options, _shot_vector, reference_scales  # noqa: E402
from peenflow.fe.johnson_cook import Material, static_flow_stress, thermal_factor  # noqa: E402
from peenflow.fe.mesh import BoxMesh  # noqa: E402
from peenflow.fe.model import Model, Target  # noqa: E402
from peenflow.fe.safety import check_status  # noqa: E402
from peenflow.fe.shots import Shots, time_to_contact  # noqa: E402
from peenflow.fe.window import contact_estimates  # noqa: E402

KINDS = {"physical": 0, "bbar": 1, "full": 2, "physical8": 3}
#: sphere contact forms: the kernel's node contact, the mortar contact of benchmarks/bbar/contact_mortar.py
CONTACTS = {"node": 0, "mortar": 1}


@dataclass
class _State:
    x: np.ndarray
    v: np.ndarray
    f: np.ndarray
    stress: np.ndarray
    eps_p: np.ndarray
    sy_static: np.ndarray
    hg: np.ndarray
    temp: np.ndarray
    energy: np.ndarray
    ctl: np.ndarray


def new_state(model: Model, kind: int) -> _State:
    m = model.material
    ne = model.mesh.n_elements
    npt = ne if kind == 0 else 8 * ne
    sy0 = static_flow_stress(0.0, thermal_factor(m.initial_temperature, model.mat), model.mat)
    n = len(model.nodes0)
    return _State(model.nodes0.copy(), np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((npt, 6)), np.zeros(npt),
                  np.full(npt, sy0), np.zeros((ne if kind == 0 else 1, 12)), np.full(npt, m.initial_temperature),
                  np.zeros(S.N_EN), np.zeros(S.N_CTL))


def phase(model: Model, st: _State, kind: int, mode: int, shot: np.ndarray, *, safety, alpha, rest_ke, rest_v,
          e_ref, force_scale=1.0, dt_floor_fraction=0.05, runaway=0.25, max_steps=2_000_000, record_every=0,
          record_capacity=0, where="impact", contact=0):
    """:meth:`peenflow.fe.model.Model.phase` on the whole mesh (no window, no viscous-spring faces, serial)
    with the element ``kind`` and the contact form ``contact`` (:data:`CONTACTS`); returns ``(info, records)``."""
    win = model.full_window
    hold = model.hold_flags(win)
    st.f[:] = 0.0
    dt0, status, *_ = element_pass(kind, st.x, st.v, st.f, st.stress, st.eps_p, st.sy_static, st.hg, st.temp,
                                   model.vol0, model.mat, 0.0, model.nnx, model.nny, model.nx, model.ny, *win)
    check_status(status, where=where, time=float(st.ctl[S.C_TIME]))
    ctl = st.ctl
    ctl[S.C_DT_PREV] = 0.0
    ctl[S.C_DT_NEXT] = dt0
    ctl[S.C_SAFETY] = safety
    ctl[S.C_ALPHA] = alpha
    ctl[S.C_REST_KE] = rest_ke
    ctl[S.C_REST_V] = rest_v
    ctl[S.C_E_REF] = e_ref
    ctl[S.C_DT_FLOOR] = dt_floor_fraction * safety * dt0
    ctl[S.C_RUNAWAY] = runaway
    ctl[S.C_OMEGA_C2] = 0.0
    ctl[S.C_FORCE_SCALE] = force_scale
    ctl[S.C_SPONGE_W] = 0
    ctl[S.C_SPONGE_A] = 0.0
    info = np.zeros(S.N_INFO)
    rec = np.zeros((max(record_capacity, 1), S.N_REC))
    status = run_phase_bbar(kind, mode, max_steps, record_every if record_capacity > 0 else 0, st.x, st.v, st.f,
                            model.mass, model.bc, st.stress, st.eps_p, st.sy_static, st.hg, st.temp, model.vol0,
                            model.mat, model.mat_static, model.mesh.x, model.mesh.y, model.nnx, model.nny, model.nx,
                            model.ny, win, hold, shot, ctl, st.energy, rec, info, model.cand, model.dn, contact)
    check_status(status, where=where, time=float(ctl[S.C_TIME]))
    return info, rec[: int(info[S.I_NREC])].copy()


@dataclass
class Result:
    """The fields of :class:`peenflow.fe.impact.ImpactRunResult` that :func:`bench_hourglass.metrics` reads,
    plus the step counts of the two phases."""
    stress: np.ndarray
    eps_p: np.ndarray
    displacement: np.ndarray
    centroids: np.ndarray
    nodes: np.ndarray
    shots: dict
    histories: list
    impact_steps: int
    relax_steps: int
    gp_stress: np.ndarray | None = None


def simulate(target: Target, material: Material, shots: Shots, options: Options, element: str,
             contact: str = "node") -> Result:
    """One shot (``shots`` of length 1) on ``target`` with the element ``element`` and the sphere contact
    ``contact`` (:data:`CONTACTS`); dynamic final relaxation.

    Mirrors :meth:`peenflow.fe.impact.ImpactRun.impact` / :meth:`~peenflow.fe.impact.ImpactRun.result` for
    ``window=False`` on a non-periodic target, step for step."""
    kind = KINDS[element]
    model = Model(target, material, hourglass=options.hourglass, hourglass_type=options.hourglass_type,
                  hourglass_plastic_floor=options.hourglass_plastic_floor, bulk_linear=options.bulk_linear,
                  bulk_quadratic=options.bulk_quadratic)
    st = new_state(model, kind)
    top = model.nnx * model.nny
    shot, frac = _shot_vector(shots, 0, model, options.friction)
    vel = shot[3:6].copy()
    speed = float(np.linalg.norm(vel))
    e_imp = 0.5 * shots.mass * speed ** 2 * frac
    t_hit = time_to_contact(st.x[:top], shot[0:3].copy(), vel, shots.radius)
    a_est, t_est = contact_estimates(shots, material, abs(vel[2]))
    dt_est = options.dt_safety * float(np.min(np.diff(model.mesh.z))) / material.wave_speed
    t_fly = t_hit - options.lead_steps * dt_est
    shot[0:3] += vel * t_fly
    st.ctl[S.C_TIME] += max(t_fly, 0.0)
    win = model.full_window
    info, r = phase(model, st, kind, S.MODE_IMPACT, shot, safety=options.dt_safety,
                    alpha=model.settle_alpha(win, options.settle_damping), rest_ke=options.rest_ke_fraction * e_imp,
                    rest_v=options.rest_v_fraction * speed, e_ref=e_imp, force_scale=1.0 / frac,
                    dt_floor_fraction=options.dt_floor_fraction, runaway=options.runaway_fraction,
                    max_steps=options.max_steps, record_every=options.record_every,
                    record_capacity=200_000 if options.record else 0, contact=CONTACTS[contact])
    hist = {"w_int": r[:, 12], "w_hourglass": r[:, 14], "time": r[:, 0], "velocity": r[:, 7:10]}
    shot_rec = {"restitution": np.array([-info[S.I_VZ] / vel[2]]), "vout_x": np.array([info[S.I_VX]]),
                "steps": np.array([int(info[S.I_STEPS])]), "energy_error": np.array([info[S.I_E_ERR] / e_imp]),
                "hit": np.array([info[S.I_T_CONTACT] >= 0]),
                # as fe/impact.py's shot record (bench_hourglass.metrics reads them)
                "max_approach": np.array([info[S.I_MAX_APPROACH]]), "peak_force": np.array([info[S.I_PEAK_FORCE]]),
                "max_contact_radius": np.array([info[S.I_MAX_RADIUS]]),
                "contact_radius": np.array([np.sqrt(2.5 * info[S.I_R2_AT_PEAK])])}
    impact_steps = int(info[S.I_STEPS])
    # final relaxation: dynamic (kernel's relax_dynamic), on the state itself (the copy is not needed here)
    e_ref, v_ref = reference_scales(shots)
    rinfo, _ = phase(model, st, kind, S.MODE_RELAX, _no_shot(), safety=options.dt_safety,
                     alpha=model.settle_alpha(win, options.relax_damping),
                     rest_ke=options.relax_ke_fraction * e_ref, rest_v=options.relax_v_fraction * v_ref, e_ref=0.0,
                     max_steps=options.max_steps, where="final relaxation")
    st.v[:] = 0.0
    ne = model.mesh.n_elements
    gp = None
    if kind == 0:
        stress, eps_p = st.stress.copy(), st.eps_p.copy()
    else:
        gp = st.stress.copy()
        # physical8: equal point weights V / 8, as its forces
        w = gauss_volumes(model, st.x).reshape(ne, 8) if kind != 3 else np.ones((ne, 8))
        stress = np.einsum("eg,egc->ec", w, gp.reshape(ne, 8, 6)) / w.sum(1)[:, None]
        eps_p = (w * st.eps_p.reshape(ne, 8)).sum(1) / w.sum(1)
    return Result(stress, eps_p, st.x - model.nodes0, model.centroids, model.nodes0, shot_rec, [hist], impact_steps,
                  int(rinfo[S.I_STEPS]), gp)


def gauss_volumes(model: Model, x: np.ndarray) -> np.ndarray:
    """Volume share ``det J`` of each Gauss point at positions ``x``, (8 n_elements,)."""
    from benchmarks.bbar.element_bbar import DN

    conn = model.mesh.connectivity()  # corner order of the solver's element
    xe = x[conn]  # (ne, 8, 3)
    J = np.einsum("gik,eia->egak", DN, xe)  # dx_a / dxi_k
    return np.linalg.det(J).ravel()


def _no_shot():
    from peenflow.fe.contact import N_SHOT

    s = np.zeros(N_SHOT)
    s[9] = s[10] = s[11] = 1.0
    return s


def _options(**extra) -> Options:
    return Options(window=False, record=True, record_every=20, **bh.ELEMENTS["physical"], **extra)


def warm_up(element: str, mat: dict, contact: str = "node") -> None:
    """Compile (or load) the kernels outside the timing: a tiny impact on a 100 um mesh, as bench_hourglass."""
    tiny = BoxMesh(*(np.arange(5) * 1e-4,) * 2, np.arange(4) * 1e-4)
    simulate(Target(tiny), Material(**mat), Shots(centres=[[0, 0, -bh.R - 1e-6]], velocities=[[0, 0, 5.0]],
                                                  radius=bh.R, density=7800.0), _options(), element, contact)


def run(case: str, element: str, h_um: float, contact: str = "node", **extra) -> dict:
    """``bench_hourglass.run(case, element, h_um)`` with ``element`` in :data:`KINDS`, the sphere contact
    ``contact`` (:data:`CONTACTS`) and the dynamic final
    relaxation; the metrics of :func:`bench_hourglass.metrics`, CPU s (process time, this process only),
    wall s, the step counts."""
    mat, speed, angle = bh.CASES[case]
    oblique = angle != 90.0
    mesh = bh.block(h_um * 1e-6, oblique)
    th = np.radians(angle)
    shots = Shots(centres=[[0.0, 0.0, -bh.R - 1e-6]], velocities=[speed * np.array([np.cos(th), 0.0, np.sin(th)])],
                  radius=bh.R, density=7800.0)
    warm_up(element, mat, contact)
    t0 = time.process_time()
    w0 = time.perf_counter()
    res = simulate(Target(mesh), Material(**mat), shots, _options(**extra), element, contact)
    cpu = time.process_time() - t0
    out = bh.metrics(res, mesh)
    out.update(cpu_s=cpu, wall_s=time.perf_counter() - w0, elements=mesh.n_elements, impact_steps=res.impact_steps,
               relax_steps=res.relax_steps, element=element, h_um=h_um, case=case, contact=contact,
               command=f"PYTHONPATH=. python benchmarks/bench_bbar.py run {case} {element} {h_um:g}")
    return out


if __name__ == "__main__":
    import json

    o = run(sys.argv[1], sys.argv[2], float(sys.argv[3]))
    print(json.dumps({k: v for k, v in o.items() if not isinstance(v, list)}, indent=1))
