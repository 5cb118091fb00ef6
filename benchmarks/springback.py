"""Spring-back (the global static relaxation of a snapshot) against the impacts: its cost and error,
on a single impact, the strip REV and the REVs a study builds (prints its figures; not a test;
docs/performance.md section 3, "Cost and error against a strict solve", "On the REVs a study makes").

Usage (from the repository root; one thread, one BLAS thread)::

    python benchmarks/springback.py compare     # cost / error by relaxation variant: single impact, REV snapshots
    python benchmarks/springback.py study       # snapshot vs impact CPU on the REVs studies build
    python benchmarks/springback.py tolerance [TOLERANCES [RUNGS]]   # the 6D REV's snapshots by relaxation tolerance
                                                # (comma-separated, default 1e-8,1e-7,1e-6,1e-5 and 5,10,20)
    python benchmarks/springback.py mismatch    # why the 6D REV needs ~10 outer corrections

Errors are against a strict solve (``relax_ke_fraction=1e-13``, ``relax_cg_rtol=1e-4``); CPU is the
process time. The REVs: :mod:`peenflow.validation.kernel_cases`.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots
from peenflow.validation.kernel_cases import (R, REV_6D_STANDARD, SAE1070, STUDY_REVS, layer_profile, loadavg,
                                              strip_rev_mesh, study_rev_run)


def _springback_errors(rs, ref, mesh, nodes0):
    """(profile error % of peak, dent error %, max |d sigma| MPa) of relaxed state ``rs`` against ``ref``."""
    nn = mesh.shape_nodes[0] * mesh.shape_nodes[1]
    _, p = layer_profile(rs, mesh)
    _, p0 = layer_profile(ref, mesh)
    d, d0 = (rs.x - nodes0)[:nn, 2].max(), (ref.x - nodes0)[:nn, 2].max()
    return 100 * np.abs(p - p0).max() / np.abs(p0).max(), 100 * (d / d0 - 1), np.abs(rs.stress - ref.stress).max() / 1e6


#: (name, Options keywords, STATIC_ENERGY_FACTOR, multigrid setup: every element size probed)
#: the looser factors: what a larger ``relax_ke_fraction`` (study key ``fidelity.relaxation_tolerance``,
#: the criterion scales with factor x that fraction) buys in CPU and costs in accuracy
SPRINGBACK_VARIANTS = (("old default (CG rtol 1e-2, factor 1e-2)", dict(relax_cg_rtol=1e-2), 1e-2, True),
                       ("new default (CG rtol 0.3, factor 1e-3)", dict(relax_cg_rtol=0.3), 1e-3, False),
                       ("CG rtol 0.3, factor 1e-2", dict(relax_cg_rtol=0.3), 1e-2, False),
                       ("CG rtol 0.3, factor 1e-1", dict(relax_cg_rtol=0.3), 1e-1, False),
                       ("CG rtol 0.3, factor 1", dict(relax_cg_rtol=0.3), 1.0, False),
                       ("CG rtol 0.3, factor 10", dict(relax_cg_rtol=0.3), 10.0, False))


def springback(speed=55.0, n_rev=12, snaps=(4, 8, 12)):
    """Spring-back (global static relaxation) against the impact: CPU s and error vs a strict solve.

    (1) one windowed impact on a graded 104 k-element block (6D x 6D x 1.29 mm,
    25 um fine zone of 1 x 1 x 0.3 mm, graded 1.2 outside): impact CPU, then
    per variant the multigrid setup CPU (old: every element size probed and
    30 power iterations per level; new: six probes spanning all sizes, an
    element-wise spectral bound on the fine levels) and the relaxation CPU;
    (2) a strip-REV sequence (463 k elements, ``n_rev`` shots, snapshots at
    ``snaps``), each snapshot relaxed per variant. Errors against
    ``relax_ke_fraction=1e-13, relax_cg_rtol=1e-4``. CPU = process time (one thread).
    """
    from peenflow.engine.blas import pin_blas_threads
    from peenflow.fe import box_stiffness as BS
    from peenflow.fe import multigrid as MG
    from peenflow.fe import relaxation as RX
    from peenflow.fe.mesh import graded_box
    from peenflow.fe.model import Model
    from peenflow.fe.state import KernelState

    pin_blas_threads()  # one BLAS thread, as in a study: idle BLAS threads spin and inflate process CPU

    mat = Material(**SAE1070)
    strict = Options(relax_ke_fraction=1e-13, relax_cg_rtol=1e-4)
    e_ref = 0.5 * 7800.0 * 4.0 / 3.0 * np.pi * R**3 * speed**2
    run_impacts(Target(BoxMesh(*(np.linspace(-2e-4, 2e-4, 9),) * 2, np.linspace(0, 2e-4, 5))), mat,
                Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 10.0]], radius=R, density=7800.0), Options())

    def setup(mesh, bc, mat_static, old):
        saved = BS.SPAN_TOLERANCE, MG.POWER_MAX_NODES
        if old:  # the span check fails and every level runs its power iterations: the old setup
            BS.SPAN_TOLERANCE, MG.POWER_MAX_NODES = -1.0, 1 << 62
        try:
            c0 = time.process_time()
            mg = MG.Multigrid(mesh, bc, mat_static)
            return mg, time.process_time() - c0
        finally:
            BS.SPAN_TOLERANCE, MG.POWER_MAX_NODES = saved

    def relaxed(m, st, name, kw, factor):
        saved, RX.STATIC_ENERGY_FACTOR = RX.STATIC_ENERGY_FACTOR, factor
        try:
            c0 = time.process_time()
            rs, rr = RX.relax(m, st, Options(**kw), e_ref, speed)
            return rs, rr, time.process_time() - c0
        finally:
            RX.STATIC_ENERGY_FACTOR = saved

    print(f"# spring-back vs impact; loadavg {loadavg()}", flush=True)
    print("| case | variant | multigrid setup CPU s | relaxation CPU s | element passes / V-cycles | "
          "profile error % of peak | dent error % | max abs d sigma MPa |")
    print("|---|---|---|---|---|---|---|---|")
    # (1) single impact, 104 k-element block
    mesh = graded_box(1.74e-3, 1.29e-3, 25e-6, fine_half_width=0.5e-3, fine_depth=0.3e-3)
    t = Target(mesh)
    shots = Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, speed]], radius=R, density=7800.0)
    c0 = time.process_time()
    res = run_impacts(t, mat, shots, Options(final_relaxation=False))
    print(f"# block {mesh.shape_elements} = {mesh.n_elements} elements: impact + settle CPU "
          f"{time.process_time() - c0:.2f} s", flush=True)
    m = Model(t, mat)
    m._multigrid, _ = setup(mesh, m.bc, m.mat_static, False)
    ref, _ = RX.relax(m, res.final_state, strict, e_ref, speed)
    for name, kw, factor, old in SPRINGBACK_VARIANTS:
        m._multigrid, cpu_setup = setup(mesh, m.bc, m.mat_static, old)
        rs, rr, cpu = relaxed(m, res.final_state, name, kw, factor)
        vc = int(rr.records[:, 1].sum()) + 1 if len(rr.records) else 1
        print(f"| single impact, 104 k block | {name} | {cpu_setup:.2f} | {cpu:.2f} | {int(rr.info[1])} / {vc} | "
              + " | ".join(f"{e:.4f}" for e in _springback_errors(rs, ref, mesh, m.nodes0)) + " |", flush=True)
    # (2) strip-REV snapshot sequence
    mesh = strip_rev_mesh()
    t = Target(mesh)
    rng = np.random.default_rng(0)
    c = np.column_stack([rng.uniform(-0.3e-3, 0.3e-3, n_rev), rng.uniform(-0.3e-3, 0.3e-3, n_rev),
                         np.full(n_rev, -R - 1e-6)])
    shots = Shots(centres=c, velocities=[[0.0, 0.0, speed]] * n_rev, radius=R, density=7800.0)
    states = {}

    def keep(i, exporter):
        if i + 1 in snaps:
            states[i + 1] = KernelState.from_dict(exporter())

    c0 = time.process_time()
    run_impacts(t, mat, shots, Options(final_relaxation=False), on_shot_done=keep)
    cpu_rev = time.process_time() - c0
    print(f"# strip REV {mesh.n_elements} elements: {n_rev} impacts CPU {cpu_rev:.1f} s "
          f"({cpu_rev / n_rev:.2f} s per impact)", flush=True)
    m = Model(t, mat)
    for old in (True, False):
        m._multigrid, cpu_setup = setup(mesh, m.bc, m.mat_static, old)
        print(f"# REV multigrid setup ({'old' if old else 'new'}) CPU {cpu_setup:.2f} s", flush=True)
    for n in snaps:
        ref, _ = RX.relax(m, states[n], strict, e_ref, speed)
        for name, kw, factor, old in SPRINGBACK_VARIANTS:
            rs, rr, cpu = relaxed(m, states[n], name, kw, factor)
            vc = int(rr.records[:, 1].sum()) + 1 if len(rr.records) else 1
            print(f"| REV snapshot after {n} shots | {name} | - | {cpu:.2f} | {int(rr.info[1])} / {vc} | "
                  + " | ".join(f"{e:.4f}" for e in _springback_errors(rs, ref, mesh, m.nodes0)) + " |", flush=True)
    print(f"# loadavg at end {loadavg()}")



def springback_study(rungs=(5, 10, 20), seed=1):
    """Snapshot relaxation against the impacts on the REVs a study builds (issue 13 section 3).

    Each REV of :data:`STUDY_REVS` is made by the study's own code (``tasks._kernel.rev_mesh``,
    ``FidelityParams.boundary`` / ``options`` with the preset's values, the study's shot stream),
    S230 at mu = 0.2; ``rungs[-1]`` shots, each impact's process CPU, and a relaxed snapshot at
    each rung (the first one again, without the one-off multigrid setup). One thread.
    """
    from peenflow.engine.blas import pin_blas_threads

    pin_blas_threads()
    print(f"# spring-back on study REVs; loadavg {loadavg()}", flush=True)
    print("| REV | preset, h | elements | impact CPU s (mean, min-max) | snapshot CPU s at " + " / ".join(map(str, rungs))
          + " shots | first snapshot with the multigrid setup | snapshot / impact |")
    print("|---|---|---|---|---|---|---|")
    for row in STUDY_REVS:
        label, preset, h_um = row[0], row[5], row[6]
        _, shot, mesh, stream, shots, run = study_rev_run(row, rungs[-1], seed)
        impact_cpu, snap_cpu, first = [], [], None
        for i in range(rungs[-1]):
            c0 = time.process_time()
            run.impact(shots, i)
            impact_cpu.append(time.process_time() - c0)
            if i + 1 in rungs:
                sub = shot.shots(stream.centres[:i + 1], stream.velocities[:i + 1])
                c0 = time.process_time()
                run.snapshot(sub)
                cpu = time.process_time() - c0
                if first is None:
                    first = cpu
                    c0 = time.process_time()
                    run.snapshot(sub)
                    cpu = time.process_time() - c0
                snap_cpu.append(cpu)
        imp = np.array(impact_cpu[1:])  # the first impact of a process also loads the kernels
        print(f"| {label} | {preset}, {h_um:g} um | {mesh.n_elements} | {imp.mean():.2f} ({imp.min():.2f}-{imp.max():.2f}) | "
              + " / ".join(f"{c:.2f}" for c in snap_cpu) + f" | {first:.2f} | "
              f"{min(snap_cpu) / imp.mean():.2f}-{max(snap_cpu) / imp.mean():.2f} |", flush=True)
    print(f"# loadavg at end {loadavg()}")


def springback_tolerance(tolerances=(1e-8, 1e-7, 1e-6, 1e-5), rungs=(5, 10, 20), seed=1):
    """The paper's fixed 6D x 6D strip REV (:data:`REV_6D_STANDARD`: ``standard`` preset at 25 um,
    symmetric faces, 1 D fine zone): each snapshot relaxed at each ``fidelity.relaxation_tolerance`` of ``tolerances`` and at a
    strict one (1e-13); CPU against the mean impact, error against the strict state (sigma_xx
    profile over the central 2D x 2D measuring region, max |d| / max |sigma|; largest |d sigma| of any
    element component). One thread."""
    import dataclasses

    import peenflow.testing as PT
    from peenflow.engine.blas import pin_blas_threads
    from peenflow.fe.impact import reference_scales
    from peenflow.fe.relaxation import relax

    pin_blas_threads()
    f, shot, mesh, stream, shots, run = study_rev_run(REV_6D_STANDARD, rungs[-1], seed)
    opts = {t: dataclasses.replace(f, relaxation_tolerance=t).options(shot) for t in (1e-13, *tolerances)}
    run.snapshot(shot.shots(stream.centres[:1], stream.velocities[:1]))  # multigrid setup, kernels loaded
    print(f"# 6D x 6D strip REV, standard at 25 um: {mesh.n_elements} elements; loadavg {loadavg()}", flush=True)
    print("| after shots | relaxation_tolerance | snapshot CPU s | snapshot / mean impact | profile error % of peak | "
          "max abs d sigma MPa |")
    print("|---|---|---|---|---|---|")
    impact_cpu, rows = [], []
    for i in range(rungs[-1]):
        c0 = time.process_time()
        run.impact(shots, i)
        impact_cpu.append(time.process_time() - c0)
        if i + 1 in rungs:
            scales = reference_scales(shot.shots(stream.centres[:i + 1], stream.velocities[:i + 1]))
            ref, _ = relax(run.model, run.state, opts[1e-13], *scales)
            _, p0 = layer_profile(ref, mesh, half=PT.S230.diameter_m)
            for t in tolerances:
                c0 = time.process_time()
                rs, _ = relax(run.model, run.state, opts[t], *scales)
                cpu = time.process_time() - c0
                _, p1 = layer_profile(rs, mesh, half=PT.S230.diameter_m)
                rows.append((i + 1, t, cpu, 100 * np.abs(p1 - p0).max() / np.abs(p0).max(),
                             np.abs(rs.stress - ref.stress).max() / 1e6))
    mean = float(np.mean(impact_cpu[1:]))
    for n, t, cpu, e_prof, e_max in rows:
        print(f"| {n} | {t:g} | {cpu:.2f} | {cpu / mean:.2f} | {e_prof:.4f} | {e_max:.3f} |")
    print(f"# impacts: mean {mean:.2f} s (the first, {impact_cpu[0]:.2f} s, left out); loadavg at end {loadavg()}")


def springback_mismatch(n_shots=10, seed=1, probe_after=4):
    """Why the static relaxation's outer loop needs ~10 corrections on the 6D REV (issue 13 section 3).

    On the paper's 6D x 6D strip REV (:data:`REV_6D_STANDARD`) after ``n_shots`` impacts: the outer
    corrections' imbalance energy (the kernel's own static records) at the preset's tolerance (1e-8)
    with the default inner tolerance, with 100x and 10 000x stricter inner solves, and with yielding
    switched off on the relaxed copy (static flow stress 1e15 Pa); then, at the correction after
    ``probe_after`` ones, the true tangent's product ``J du`` (finite difference of the element pass
    over the step ``du``, from a copy) against the multigrid operator's ``K du`` (the elastic box grid),
    on the state as is and with geometry / stress / yielding taken apart, and where on the mesh the
    difference lies. One thread."""
    import dataclasses

    from peenflow.engine.blas import pin_blas_threads
    from peenflow.fe import solver as S
    from peenflow.fe.impact import reference_scales
    from peenflow.fe.multigrid import dot, pcg
    from peenflow.fe.relaxation import STATIC_ENERGY_FACTOR, _forces, relax_static

    pin_blas_threads()
    f, shot, mesh, stream, shots, run = study_rev_run(REV_6D_STANDARD, n_shots, seed)
    for i in range(n_shots):
        run.impact(shots, i)
    model, st = run.model, run.state
    e_ref, _ = reference_scales(shot.shots(stream.centres[:n_shots], stream.velocities[:n_shots]))
    base = f.options(shot)
    print(f"# 6D x 6D strip REV, standard at 25 um: {mesh.n_elements} elements, after {n_shots} shots; "
          f"loadavg {loadavg()}", flush=True)
    print("| outer loop | corrections to 1e-8 | imbalance energy / tolerance after each correction | CPU s |")
    print("|---|---|---|---|")
    for label, opts, elastic in (("default (inner CG rtol 0.3)", base, False),
                                 ("inner CG rtol 1e-2", dataclasses.replace(base, relax_cg_rtol=1e-2), False),
                                 ("inner CG rtol 1e-4", dataclasses.replace(base, relax_cg_rtol=1e-4), False),
                                 ("default, yielding off", base, True)):
        s = st.copy()
        if elastic:
            s.sy_static[:] = 1e15
        c0 = time.process_time()
        res = relax_static(model, s, opts, e_ref)
        cpu = time.process_time() - c0
        tol = STATIC_ENERGY_FACTOR * opts.relax_ke_fraction * e_ref
        energies = list(res.records[:, 0]) + [res.info[S.I_KE_END]]
        print(f"| {label} | {len(res.records)} | " + ", ".join(f"{e / tol:.1e}" for e in energies[1:])
              + f" | {cpu:.2f} |", flush=True)
    # the kernel's loop stopped after `probe_after` corrections, its next correction, the true tangent along it
    mg = model.multigrid()
    s = st.copy()
    relax_static(model, s, dataclasses.replace(base, relax_max_outer=probe_after), e_ref)
    r = _forces(model, s, 0.0, 1, "mismatch")
    du, _, _ = pcg(mg, r, rtol=base.relax_cg_rtol)
    model.unfold(du)
    kdu = np.empty_like(du)
    mg.levels[0].apply(du, kdu)

    def tangent(state):
        def step(d):
            t = state.copy()
            t.v[:] = d
            t.x[:] += d
            return _forces(model, t, 1.0, 1, "mismatch")
        return step(0.0 * du) - step(du)

    print()
    print("| state the tangent is taken on | abs(J du - K du) / abs(K du) | du.(J - K) du / du.K du |")
    print("|---|---|---|")
    variants = (("as relaxed so far", {}), ("yielding off", dict(sy=True)),
                ("deformed geometry, zero stress, yielding off", dict(sy=True, stress=True)),
                ("reference geometry, current stress, yielding off", dict(sy=True, geometry=True)))
    jdu0 = None
    for label, kw in variants:
        t = s.copy()
        if kw.get("sy"):
            t.sy_static[:] = 1e15
        if kw.get("stress"):
            t.stress[:] = 0.0
            t.hg[:] = 0.0
        if kw.get("geometry"):
            t.x[:] = model.nodes0
        jdu = tangent(t)
        jdu0 = jdu if jdu0 is None else jdu0
        d = jdu - kdu
        print(f"| {label} | {np.linalg.norm(d) / np.linalg.norm(kdu):.4f} | {dot(du, d) / dot(du, kdu):+.4f} |", flush=True)
    nnx, nny, nx, ny, nz = model.nnx, model.nny, model.nx, model.ny, model.nz
    plastic = (st.eps_p > 1e-3).reshape(nz, ny, nx)
    touch = np.zeros((nz + 1, nny, nnx), bool)
    for a in (0, 1):
        for b in (0, 1):
            for c in (0, 1):
                touch[a:a + nz, b:b + ny, c:c + nx] |= plastic
    touch = touch.ravel()
    d2 = np.sum((jdu0 - kdu) ** 2, axis=1)
    k2 = np.sum(kdu ** 2, axis=1)
    print(f"\n# elements with eps_p > 1e-3: {int(plastic.sum())} of {mesh.n_elements}; their {int(touch.sum())} nodes carry "
          f"{100 * d2[touch].sum() / d2.sum():.1f} % of |J du - K du|^2 and {100 * k2[touch].sum() / k2.sum():.1f} % of "
          f"|K du|^2; loadavg at end {loadavg()}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    sub.add_parser("compare", help="spring-back cost and error by variant: 104 k block, strip REV snapshots")
    sub.add_parser("study", help="snapshot against impact CPU on the REVs a study builds")
    p = sub.add_parser("tolerance", help="the 6D REV's snapshots by fidelity.relaxation_tolerance")
    p.add_argument("tolerances", nargs="?", help="comma-separated, e.g. 1e-4,1e-3")
    p.add_argument("rungs", nargs="?", help="comma-separated shot counts, e.g. 20,80,200")
    sub.add_parser("mismatch", help="the outer loop's corrections and the true tangent against the multigrid's")
    a = ap.parse_args(argv)
    if a.mode == "compare":
        springback()
    elif a.mode == "study":
        springback_study()
    elif a.mode == "tolerance":
        kw = {}
        if a.tolerances:
            kw["tolerances"] = tuple(float(t) for t in a.tolerances.split(","))
        if a.rungs:
            kw["rungs"] = tuple(int(n) for n in a.rungs.split(","))
        springback_tolerance(**kw)
    else:
        springback_mismatch()


if __name__ == "__main__":
    main()
