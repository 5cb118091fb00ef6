"""Speed and window-error figures of the numba FE/DEM kernel (prints them; not a test).

Usage (from the repository root)::

    PYTHONPATH=. python benchmarks/bench_kernel.py throughput   # element-updates/s, 1 and 2 threads
    PYTHONPATH=. python benchmarks/bench_kernel.py rev          # one impact on the strip REV, window vs full
    PYTHONPATH=. python benchmarks/bench_kernel.py rev-relax    # global relaxation only (static vs dynamic), 1 and 20 shots
    PYTHONPATH=. python benchmarks/bench_kernel.py window       # window error vs full mesh: held / viscous-spring faces
    PYTHONPATH=. python benchmarks/bench_kernel.py window-timing  # (last part of window) their cost, interleaved runs
    PYTHONPATH=. python benchmarks/bench_kernel.py window-seq   # held / viscous-spring in 4- and 80-shot sequences (~25 min)
    PYTHONPATH=. python benchmarks/bench_kernel.py springback   # spring-back cost/error vs the impact (single, REV snapshots)
    PYTHONPATH=. python benchmarks/bench_kernel.py springback-study  # snapshot vs impact CPU on the REVs studies build
    PYTHONPATH=. python benchmarks/bench_kernel.py springback-tolerance  # the 6D REV's snapshots by relaxation tolerance
    PYTHONPATH=. python benchmarks/bench_kernel.py springback-tolerance 1e-4,1e-3 20,80,200  # chosen tolerances, rungs
    PYTHONPATH=. python benchmarks/bench_kernel.py springback-mismatch  # why the 6D REV needs ~10 outer corrections
    PYTHONPATH=. python benchmarks/bench_kernel.py window-min   # window minimum size at 1 and 5 m/s vs the full mesh
    PYTHONPATH=. python benchmarks/bench_kernel.py hertz        # Hertz convergence table (quarter model)
    PYTHONPATH=. python benchmarks/bench_kernel.py plastic      # plastic dents at 25/55 m/s, refinement, rate on/off

JIT compilation is excluded (each kernel is warmed up on a tiny case first).
"""

from __future__ import annotations

import os
import sys
import time

import numba
import numpy as np

from peenflow.fe.element import element_rows, element_rows_parallel
from peenflow.fe.element_reference import element_pass, element_pass_parallel
from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots, hertz, johnson_plastic
from peenflow.testing import SAE1070  # paper Table 1, from the study library

R = 0.29e-3


def loadavg() -> str:
    with open("/proc/loadavg") as f:
        return f.read().split()[0]


def _pass_arrays(mesh, plastic):
    X = mesh.node_coordinates()
    n, ne = mesh.n_nodes, mesh.n_elements
    mat = Material(**SAE1070)
    G = np.array([[1.0, 0.2, 0.0], [0.0, -0.5, 0.1], [0.3, 0.0, -0.5]]) * (1e5 if plastic else 1e2)
    v = X @ G.T
    sy = np.full(ne, 1e3 if plastic else 1e12)  # plastic: every element yields every step
    return dict(x=X, v=v, f=np.zeros((n, 3)), stress=np.zeros((ne, 6)), eps_p=np.zeros(ne) + 0.1, sy=sy,
                hg=np.zeros((ne, 12)), temp=np.full(ne, 293.0), vol0=mesh.element_volumes(), mat=mat.to_array())


def element_rate(shape, threads, plastic, reps=None, blocked=True, dtype=np.float64, kernels=None):
    """Element-updates/s (M/s) of one element pass over a ``shape`` box: ``(wall, cpu)``.

    ``cpu`` divides by the process CPU time (per thread): the rate of the
    cores we actually got, less sensitive to other jobs on the machine than
    ``wall``. ``kernels``: ``(serial, parallel)`` to time instead of the
    solver's (the float32 copy).
    """
    nx, ny, nz = shape
    h = 25e-6
    mesh = BoxMesh(np.arange(nx + 1) * h, np.arange(ny + 1) * h, np.arange(nz + 1) * h)
    a = _pass_arrays(mesh, plastic)
    for k in ("x", "v", "f", "stress", "eps_p", "sy", "hg", "temp", "vol0"):
        a[k] = a[k].astype(dtype)
    nnx, nny, _ = mesh.shape_nodes
    if kernels is not None:
        fn = kernels[1] if threads > 1 else kernels[0]
    elif blocked:
        fn = element_rows_parallel if threads > 1 else element_rows
    else:
        fn = element_pass_parallel if threads > 1 else element_pass
    numba.set_num_threads(threads)
    args = lambda: (a["x"], a["v"], a["f"], a["stress"], a["eps_p"], a["sy"], a["hg"], a["temp"], a["vol0"],
                    a["mat"], 4e-9, nnx, nny, nx, ny, 0, nx, 0, ny, 0, nz)
    fn(*args())  # warm-up (compiled already by the tiny call in main)
    if plastic and reps is None:
        # the stress starts at zero and reaches the yield surface in the ~20th pass; before, the
        # (deliberately low) stored flow stress sends every element into the return, which exits
        # at once. Time only passes in plastic flow.
        for _ in range(25):
            fn(*args())
    reps = reps or max(3, int(2e7 / mesh.n_elements))
    t = time.perf_counter()
    c = time.process_time()
    for _ in range(reps):
        fn(*args())
    dt = time.perf_counter() - t
    dc = time.process_time() - c
    n = reps * mesh.n_elements / 1e6
    return n / dt, n / dc * threads


def throughput():
    print(f"# element-updates/s (M/s), element pass only; loadavg at start {loadavg()}, {os.cpu_count()} cores")
    print("# each cell: wall-clock rate / rate per CPU-second actually received (process CPU time / threads)")
    for b in (True, False):
        for th in (1, 2):
            element_rate((4, 4, 4), th, False, 2, b)
    print("| mesh | elements | threads | blocked elastic | blocked plastic | per-element elastic | per-element plastic "
          "| load |")
    print("|---|---|---|---|---|---|---|---|")
    for shape in ((20, 20, 20), (60, 60, 60), (120, 120, 40)):
        for th in (1, 2):
            l0 = loadavg()
            r = [element_rate(shape, th, p) for p in (False, True)]
            r += [element_rate(shape, th, p, blocked=False) for p in (False, True)]
            print(f"| {shape[0]}x{shape[1]}x{shape[2]} | {np.prod(shape)} | {th} | "
                  + " | ".join(f"{w:.2f} / {c:.2f}" for w, c in r) + f" | {l0}-{loadavg()} |", flush=True)
    numba.set_num_threads(1)
    print(f"# loadavg at end {loadavg()}")


def rev_mesh(h=25e-6, fine_depth=0.3e-3):
    """Strip REV 6D x 6D x h_strip = 3.48 x 3.48 x 1.29 mm, uniform h laterally, graded (1.2) below fine_depth."""
    half = 1.74e-3
    lat = np.linspace(-half, half, int(round(2 * half / h)) + 1)
    z = graded_axis(fine_depth, h, 1.29e-3, 1.2)
    return BoxMesh(lat, lat.copy(), z)


def profile(res, mesh, half=0.58e-3):
    """sigma_xx averaged over the central 2D x 2D measuring region, per element layer (Pa)."""
    c = mesh.element_centroids()
    sel = (np.abs(c[:, 0]) <= half) & (np.abs(c[:, 1]) <= half)
    zs = np.unique(c[:, 2])
    return zs, np.array([res.stress[sel & (c[:, 2] == z), 0].mean() for z in zs])


def rev(windows=((4.0, 4.0), (3.0, 3.0), (6.0, 6.0)), full=True, speed=55.0, n_shots=1, relax_dynamic=True, sponge=0.0):
    mesh = rev_mesh()
    t = Target(mesh)
    mat = Material(**SAE1070)
    rng = np.random.default_rng(0)
    if n_shots == 1:
        c = [[0.0, 0.0, -R - 1e-6]]
    else:
        c = np.column_stack([rng.uniform(-0.3e-3, 0.3e-3, n_shots), rng.uniform(-0.3e-3, 0.3e-3, n_shots),
                             np.full(n_shots, -R - 1e-6)])
    shots = Shots(centres=c, velocities=[[0.0, 0.0, speed]] * n_shots, radius=R, density=7800.0)
    nnx, nny, _ = mesh.shape_nodes
    print(f"# strip REV {mesh.shape_elements} = {mesh.n_elements} elements, {n_shots} shot(s) at {speed} m/s; "
          f"loadavg {loadavg()}")
    # warm-up compile on a tiny case
    run_impacts(Target(BoxMesh(*(np.linspace(-2e-4, 2e-4, 9),) * 2, np.linspace(0, 2e-4, 5))), mat,
                Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 10.0]], radius=R, density=7800.0), Options())
    results = {}
    cases = ([("full", Options(window=False, final_relaxation=False))] if full else []) + [
        (f"window {w[0]:g}x{w[1]:g}", Options(window_lateral=w[0], window_depth=w[1], final_relaxation=False,
                                             window_sponge=sponge))
        for w in windows]
    from peenflow.fe.model import Model
    from peenflow.fe.relaxation import relax
    m = Model(t, mat)
    e_ref = 0.5 * shots.mass * speed**2
    mg_t0 = time.perf_counter()
    m.multigrid()
    print(f"# multigrid setup (once per run and mesh) {time.perf_counter() - mg_t0:.1f} s, levels "
          f"{[lv.nn for lv in m.multigrid().levels]}; loadavg {loadavg()}", flush=True)
    for name, opt in cases:
        t0 = time.perf_counter()
        res = run_impacts(t, mat, shots, opt)
        wall = time.perf_counter() - t0
        out = {}
        # reference: static relaxation at a very strict tolerance; then the two methods at their defaults
        for tol, ropt in (("reference", Options(relax_ke_fraction=1e-13, relax_cg_rtol=1e-4)),
                          ("static", Options()), ("dynamic", Options(relax_method="dynamic"))):
            if tol == "dynamic" and not relax_dynamic:
                continue
            t1 = time.perf_counter()
            rs, rr = relax(m, res.final_state, ropt, e_ref, speed)
            out[tol] = (rs, time.perf_counter() - t1, int(rr.info[1]), loadavg())
        win = res.shots
        rs = out["reference"][0]
        uz = (rs.x - m.nodes0)[: nnx * nny, 2]
        zs, p = profile(rs, mesh)
        results[name] = (uz.max(), p, res.shots["restitution"].mean())
        rel = []
        for tol in ("static", "dynamic"):
            if tol in out:
                _, p2 = profile(out[tol][0], mesh)
                rel.append(f"{tol} {out[tol][1]:.1f} s / {out[tol][2]} {'passes' if tol == 'static' else 'steps'} "
                           f"(load {out[tol][3]}), profile vs reference {100*np.abs(p2-p).max()/np.abs(p).max():.3f} %, "
                           f"eps_p changed in {int(np.sum(out[tol][0].eps_p != res.final_state.eps_p))} elements")
        print(f"{name}: impact+settle wall {wall:.2f} s ({win['steps'].sum():.0f} steps on "
              f"{int(((win['win_i1']-win['win_i0'])*(win['win_j1']-win['win_j0'])*(win['win_k1']-win['win_k0'])).mean())}"
              f" elements); global relaxation: " + "; ".join(rel) + f"; dent {uz.max()*1e6:.3f} um, "
              f"restitution {res.shots['restitution'].mean():.4f}, E err {res.energy_error:.4f}, "
              f"hourglass {res.hourglass_ratio:.3f}", flush=True)
    if full:
        d0, p0, e0 = results["full"]
        print("| window (x contact radius) | dent error | restitution error | profile error (max abs / max abs full) |")
        print("|---|---|---|---|")
        for name, (d, p, e) in results.items():
            if name == "full":
                continue
            print(f"| {name} | {100*(d/d0-1):+.2f} % | {100*(e/e0-1):+.2f} % | "
                  f"{100*np.abs(p-p0).max()/np.abs(p0).max():.2f} % |")
        print("# full-mesh averaged sigma_xx profile (MPa) by depth (um):")
        print(" ".join(f"{z*1e6:.0f}:{s/1e6:.0f}" for z, s in zip(zs[:16], p0[:16])))


def _window_case(t, mat, shots, opt, model, e_ref, speed, half):
    """One run (impact + settle timed), then a strict static relaxation: (dent m, restitution, profile, eps_p, info)."""
    from peenflow.fe.relaxation import relax

    load0 = loadavg()
    t0 = time.perf_counter()
    res = run_impacts(t, mat, shots, opt)
    wall = time.perf_counter() - t0
    strict = Options(relax_ke_fraction=1e-13, relax_cg_rtol=1e-4)
    rs, _ = relax(model, res.final_state, strict, e_ref, speed)
    nnx, nny, _ = t.mesh.shape_nodes
    _, p = profile(rs, t.mesh, half)
    s = res.shots
    n_el = int(((s["win_i1"] - s["win_i0"]) * (s["win_j1"] - s["win_j0"]) * (s["win_k1"] - s["win_k0"])).sum())
    info = dict(wall=wall, steps=int(s["steps"].sum()), elements=n_el, load=f"{load0}/{loadavg()}")
    return (rs.x - model.nodes0)[: nnx * nny, 2].max(), s["restitution"][0], p, rs.eps_p, info


def window_error(speed=55.0):
    """Window error against the full mesh (held vs viscous-spring window faces), strip REV and small test box.

    Both sides are relaxed to rest over the whole mesh by a strict static
    relaxation; profile error = max |delta sigma_xx| over depth / max |sigma_xx full|
    (sigma_xx averaged per element layer over the measuring region).
    """
    from peenflow.fe.mesh import graded_box
    from peenflow.fe.model import Model

    mat = Material(**SAE1070)
    shots = Shots(centres=[[0.0, 0.0, -R - 1e-6]], velocities=[[0.0, 0.0, speed]], radius=R, density=7800.0)
    e_ref = 0.5 * shots.mass * speed**2
    vs = dict(window_boundary="viscous-spring")
    # warm-up compile (both boundaries) on a tiny case
    tiny = Target(BoxMesh(*(np.linspace(-2e-4, 2e-4, 17),) * 2, np.linspace(0, 2e-4, 9)))
    for kw in (dict(window_boundary="held"), vs):
        run_impacts(tiny, mat, Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 10.0]], radius=R,
                                     density=7800.0), Options(window_lateral=2.0, window_depth=2.0, **kw))
    boxes = (("strip REV", Target(rev_mesh()), 0.58e-3),
             ("test box (tests/fe/test_impact.py)",
              Target(graded_box(0.6e-3, 0.6e-3, 25e-6, fine_half_width=0.15e-3, fine_depth=0.1e-3)), 0.15e-3))
    for box, t, half in boxes:
        model = Model(t, mat)
        model.multigrid()
        held = dict(window_boundary="held")
        cases = [("viscous-spring 4 x 4", vs), ("held 4 x 4 (default)", held),
                 ("viscous-spring 3 x 3", dict(vs, window_lateral=3.0, window_depth=3.0)),
                 ("held 3 x 3", dict(held, window_lateral=3.0, window_depth=3.0))]
        if box == "strip REV":
            cases += [("viscous-spring 6 x 6", dict(vs, window_lateral=6.0, window_depth=6.0)),
                      ("held 6 x 6", dict(held, window_lateral=6.0, window_depth=6.0)),
                      ("held 4 x 4 + window_sponge=0.3", dict(held, window_sponge=0.3)),
                      ("held, full width x 4 deep", dict(held, window_lateral=18.0)),
                      ("viscous-spring 4 x 4, no slab term", dict(vs, boundary_slab=0.0)),
                      ("viscous-spring 4 x 4, no dashpots", dict(vs, boundary_dashpot=0.0)),
                      ("viscous-spring 4 x 4, dashpots kept while settling", dict(vs, boundary_settle="viscous-spring"))]
        print(f"# {box}: {t.mesh.shape_elements} = {t.mesh.n_elements} elements, S230 at {speed:g} m/s normal; "
              f"one thread; loadavg {loadavg()}", flush=True)
        d0, e0, p0, ep0, i0 = _window_case(t, mat, shots, Options(window=False, final_relaxation=False), model,
                                           e_ref, speed, half)
        print(f"# full mesh: impact + settle {i0['wall']:.1f} s, {i0['steps']} steps (load {i0['load']}); dent "
              f"{d0*1e6:.3f} um, restitution {e0:.4f}", flush=True)
        print("| window | dent error | restitution error | profile error | sum eps_p / full | impact + settle wall "
              "| steps | elements | load avg (start/end) |")
        print("|---|---|---|---|---|---|---|---|---|")
        for name, kw in cases:
            d, e, p, ep, i = _window_case(t, mat, shots, Options(final_relaxation=False, **kw), model, e_ref, speed,
                                          half)
            print(f"| {name} | {100*(d/d0-1):+.2f} % | {100*(e/e0-1):+.2f} % | "
                  f"{100*np.abs(p-p0).max()/np.abs(p0).max():.2f} % | {ep.sum()/ep0.sum():.4f} | {i['wall']:.2f} s | "
                  f"{i['steps']} | {i['elements']} | {i['load']} |", flush=True)
    window_timing()


def window_size(cases=((4.0, 4.0), (4.0, 6.0), (4.0, 8.0), (4.0, 12.0), (6.0, 8.0), (3.0, 8.0), (18.0, 4.0)),
                speed=55.0):
    """Held window faces: error against the full mesh vs window lateral x depth (contact radii), strip REV, one shot."""
    from peenflow.fe.model import Model

    mat = Material(**SAE1070)
    shots = Shots(centres=[[0.0, 0.0, -R - 1e-6]], velocities=[[0.0, 0.0, speed]], radius=R, density=7800.0)
    e_ref = 0.5 * shots.mass * speed**2
    t = Target(rev_mesh())
    model = Model(t, mat)
    model.multigrid()
    half = 0.58e-3
    d0, e0, p0, ep0, i0 = _window_case(t, mat, shots, Options(window=False, final_relaxation=False), model, e_ref,
                                       speed, half)
    print(f"# strip REV, full mesh: {i0['wall']:.1f} s, {i0['steps']} steps (load {i0['load']})", flush=True)
    print("| held window | dent error | restitution error | profile error | sum eps_p / full | wall | steps | elements "
          "| load |")
    print("|---|---|---|---|---|---|---|---|---|")
    for lat, dep in cases:
        d, e, p, ep, i = _window_case(t, mat, shots, Options(final_relaxation=False, window_lateral=lat,
                                                             window_depth=dep), model, e_ref, speed, half)
        print(f"| {lat:g} x {dep:g} | {100*(d/d0-1):+.2f} % | {100*(e/e0-1):+.2f} % | "
              f"{100*np.abs(p-p0).max()/np.abs(p0).max():.2f} % | {ep.sum()/ep0.sum():.4f} | {i['wall']:.2f} s | "
              f"{i['steps']} | {i['elements']} | {i['load']} |", flush=True)


def settle_tolerance(n=10, speed=55.0):
    """Run time against error of the 'at rest' criterion that ends each shot's settle (strip REV, n shots)."""
    from peenflow.fe.model import Model
    from peenflow.fe.relaxation import relax

    mesh = rev_mesh()
    t = Target(mesh)
    mat = Material(**SAE1070)
    m = Model(t, mat)
    m.multigrid()
    rng = np.random.default_rng(0)
    c = np.column_stack([rng.uniform(-0.3e-3, 0.3e-3, n), rng.uniform(-0.3e-3, 0.3e-3, n), np.full(n, -R - 1e-6)])
    shots = Shots(centres=c, velocities=[[0.0, 0.0, speed]] * n, radius=R, density=7800.0)
    strict = Options(relax_ke_fraction=1e-13, relax_cg_rtol=1e-4)
    e_ref = 0.5 * shots.mass * speed**2
    print(f"# strip REV, {n} shots at {speed:g} m/s over +-0.3 mm; profile against the default criterion after a "
          f"strict static relaxation; loadavg {loadavg()}")
    print("| rest_ke_fraction | rest_v_fraction | steps | impacts wall | profile change | sum eps_p / default "
          "| largest energy error | load |")
    print("|---|---|---|---|---|---|---|---|")
    ref = None
    for ke, vf in ((1e-6, 1e-4), (1e-5, 1e-4), (1e-4, 1e-3), (1e-3, 1e-2)):
        t0 = time.perf_counter()
        r = run_impacts(t, mat, shots, Options(final_relaxation=False, rest_ke_fraction=ke, rest_v_fraction=vf))
        wall = time.perf_counter() - t0
        rs, _ = relax(m, r.final_state, strict, e_ref, speed)
        _, p = profile(rs, mesh)
        if ref is None:
            ref = (p, rs.eps_p.sum())
        print(f"| {ke:g} | {vf:g} | {int(r.shots['steps'].sum())} | {wall:.1f} s | "
              f"{100*np.abs(p-ref[0]).max()/np.abs(ref[0]).max():.3f} % | {rs.eps_p.sum()/ref[1]:.5f} | "
              f"{r.energy_error:.4f} | {loadavg()} |", flush=True)


def window_timing(reps=4, speed=55.0):
    """Impact + settle wall of the default 4 x 4 window, held vs viscous-spring faces, interleaved (same load)."""
    from peenflow.fe.mesh import graded_box

    mat = Material(**SAE1070)
    shots = Shots(centres=[[0.0, 0.0, -R - 1e-6]], velocities=[[0.0, 0.0, speed]], radius=R, density=7800.0)
    tiny = Target(BoxMesh(*(np.linspace(-2e-4, 2e-4, 17),) * 2, np.linspace(0, 2e-4, 9)))
    kinds = ("held", "viscous-spring")
    for b in kinds:
        run_impacts(tiny, mat, shots, Options(window_lateral=2.0, window_depth=2.0, window_boundary=b))
    for name, t, n in (("strip REV", Target(rev_mesh()), reps),
                       ("test box", Target(graded_box(0.6e-3, 0.6e-3, 25e-6, fine_half_width=0.15e-3,
                                                      fine_depth=0.1e-3)), 2 * reps)):
        walls = {b: [] for b in kinds}
        steps = {}
        load0 = loadavg()
        for _ in range(n):
            for b in kinds:
                t0 = time.perf_counter()
                r = run_impacts(t, mat, shots, Options(window_boundary=b, final_relaxation=False))
                walls[b].append(time.perf_counter() - t0)
                steps[b] = int(r.shots["steps"][0])
        print(f"# {name}, {n} interleaved runs each (load {load0}/{loadavg()}): " + "; ".join(
            f"{b} median {np.median(walls[b]):.2f} s, min {min(walls[b]):.2f} s, {steps[b]} steps" for b in kinds),
            flush=True)


def window_sequence(n_error=4, n_long=80, speed=55.0):
    """Held vs viscous-spring window faces in shot sequences on the strip REV (shots over +-0.3 mm, seed 0).

    (1) ``n_error`` shots: errors against the full mesh after a strict static
    relaxation (the full-mesh run takes ~3 min per shot); (2) ``n_long``
    shots, windowed only: largest per-shot energy balance error (runaway
    check off, so a run that would stop at ``runaway_fraction`` is reported).
    """
    from peenflow.fe.model import Model
    from peenflow.fe.relaxation import relax

    mesh = rev_mesh()
    t = Target(mesh)
    mat = Material(**SAE1070)
    m = Model(t, mat)
    rng = np.random.default_rng(0)
    n = max(n_error, n_long)
    c = np.column_stack([rng.uniform(-0.3e-3, 0.3e-3, n), rng.uniform(-0.3e-3, 0.3e-3, n), np.full(n, -R - 1e-6)])
    strict = Options(relax_ke_fraction=1e-13, relax_cg_rtol=1e-4)
    nnx, nny, _ = mesh.shape_nodes
    kinds = (("held 4 x 4 (default)", dict(window_boundary="held")),
             ("held 4 x 8", dict(window_boundary="held", window_depth=8.0)),
             ("held 4 x 12", dict(window_boundary="held", window_depth=12.0)),
             ("viscous-spring 4 x 4", dict(window_boundary="viscous-spring")),
             ("viscous-spring 4 x 8", dict(window_boundary="viscous-spring", window_depth=8.0)))
    shots = Shots(centres=c[:n_error], velocities=[[0.0, 0.0, speed]] * n_error, radius=R, density=7800.0)
    e_ref = 0.5 * shots.mass * speed**2
    print(f"# strip REV, {n_error} shots at {speed:g} m/s over +-0.3 mm; loadavg {loadavg()}", flush=True)
    out = {}
    for name, kw in (("full", dict(window=False)),) + kinds:
        t0 = time.perf_counter()
        r = run_impacts(t, mat, shots, Options(final_relaxation=False, **kw))
        wall = time.perf_counter() - t0
        rs, _ = relax(m, r.final_state, strict, e_ref, speed)
        _, p = profile(rs, mesh)
        out[name] = ((rs.x - m.nodes0)[: nnx * nny, 2].max(), r.shots["restitution"], p, rs.eps_p.sum(), wall,
                     r.energy_error)
        print(f"# {name}: impact + settle {wall:.1f} s (load {loadavg()}), largest energy error {r.energy_error:.3f}",
              flush=True)
    d0, e0, p0, s0, _, _ = out["full"]
    print("| window faces | dent error | restitution error (mean; worst shot) | profile error | sum eps_p / full | wall "
          "| largest energy error |")
    print("|---|---|---|---|---|---|---|")
    for name, _ in kinds:
        d, e, p, s, w, ee = out[name]
        print(f"| {name} | {100*(d/d0-1):+.2f} % | {100*(e.mean()/e0.mean()-1):+.2f} %; {100*np.abs(e/e0-1).max():.2f} % | "
              f"{100*np.abs(p-p0).max()/np.abs(p0).max():.2f} % | {s/s0:.4f} | {w:.1f} s | {ee:.3f} |", flush=True)
    shots = Shots(centres=c[:n_long], velocities=[[0.0, 0.0, speed]] * n_long, radius=R, density=7800.0)
    for name, kw in (kinds[0], kinds[3]):
        t0 = time.perf_counter()
        r = run_impacts(t, mat, shots, Options(final_relaxation=False, runaway_fraction=1e9, **kw))
        err = r.shots["energy_error"]
        print(f"# {n_long} shots, {name}: {time.perf_counter() - t0:.1f} s (load {loadavg()}); per-shot energy error "
              f"max {err.max():.3f} (shot {int(np.argmax(err))}), mean {err.mean():.4f}, shots above the runaway "
              f"threshold 0.25: {int(np.sum(err > 0.25))}", flush=True)


HERTZ_CASES = (
    # (speed m/s, a/h, domain extent in contact radii, target density kg/m^3)
    *((55.0, n, 25.0, 7800.0) for n in (4, 6, 8)),
    *((1.0, n, 25.0, 7800.0) for n in (4, 6, 8)),
    (1.0, 4, 100.0, 7800.0), (1.0, 4, 300.0, 7800.0),
    (20.0, 4, 25.0, 7800.0), (20.0, 4, 100.0, 7800.0), (20.0, 6, 100.0, 7800.0),
    (55.0, 4, 100.0, 7800.0), (55.0, 4, 300.0, 7800.0),
    # the target's inertia taken out: same stiffness and strains, waves 10x faster
    *((55.0, n, 100.0, 78.0) for n in (4, 6, 8)),
)


# mesh layout at 55 m/s, a/h = 4, 25 a: (fine-zone half width in a, grading ratio); the default is (2, 1.2)
HERTZ_LAYOUTS = ((2.0, 1.2), (2.0, 1.1), (4.0, 1.2), (6.0, 1.1))


def hertz_layouts(layouts=HERTZ_LAYOUTS, v=55.0, n=4, extent=25.0):
    """The 55 m/s deviation against the mesh layout (fine zone fine x a wide, 0.75 fine x a deep; grading ratio)."""
    mat = Material(E=205e9, nu=0.29, density=7800.0, A=1e13)
    print(f"# Hertz at {v:g} m/s, a/h = {n}, extent {extent:g} a: mesh layout; loadavg {loadavg()}")
    print("| fine zone / a | grading | elements | approach err | force err | restitution | wall s |")
    print("|---|---|---|---|---|---|---|")
    for fine, ratio in layouts:
        shots = Shots(centres=[[0, 0, -R - 1e-9]], velocities=[[0, 0, v]], radius=R, density=7800.0)
        ref = hertz(R, shots.mass, v, mat.E, mat.nu)
        a = ref["a"]
        ax = graded_axis(fine * a, a / n, extent * a, ratio)
        mesh = BoxMesh(ax, ax.copy(), graded_axis(0.75 * fine * a, a / n, extent * a, ratio))
        t0 = time.perf_counter()
        s = run_impacts(Target(mesh), mat, shots, Options(window=False, friction=0.0)).shots
        print(f"| {fine:g} | {ratio:g} | {mesh.n_elements} | {100*(s['max_approach'][0]/ref['delta']-1):+.2f} % | "
              f"{100*(s['peak_force'][0]/ref['F']-1):+.2f} % | {s['restitution'][0]:.4f} | "
              f"{time.perf_counter()-t0:.1f} |", flush=True)


def hertz_table(cases=HERTZ_CASES):
    print(f"# Hertz, quarter model, frictionless; loadavg {loadavg()}")
    print("| v m/s | a/h | extent / a | target density | elements | approach err | force err | radius err "
          "| duration err | restitution | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for v, n, extent, rho in cases:
        mat = Material(E=205e9, nu=0.29, density=rho, A=1e13)
        shots = Shots(centres=[[0, 0, -R - 1e-9]], velocities=[[0, 0, v]], radius=R, density=7800.0)
        ref = hertz(R, shots.mass, v, mat.E, mat.nu)
        a = ref["a"]
        ax = graded_axis(2 * a, a / n, extent * a, 1.2)
        mesh = BoxMesh(ax, ax.copy(), graded_axis(1.5 * a, a / n, extent * a, 1.2))
        t0 = time.perf_counter()
        res = run_impacts(Target(mesh), mat, shots, Options(window=False, friction=0.0))
        s = res.shots
        err = lambda got, k: 100 * (got / ref[k] - 1)
        print(f"| {v:g} | {n} | {extent:g} | {rho:g} | {mesh.n_elements} | "
              f"{err(s['max_approach'][0], 'delta'):+.2f} % | "
              f"{err(s['peak_force'][0], 'F'):+.2f} % | {err(s['contact_radius'][0], 'a'):+.2f} % | "
              f"{err(s['contact_duration'][0], 't'):+.2f} % | {s['restitution'][0]:.4f} | "
              f"{time.perf_counter()-t0:.1f} |", flush=True)


def plastic_table():
    print(f"# S230 on SAE 1070, single normal impact, box 1.2 x 1.2 x 0.6 mm; loadavg {loadavg()}")
    m = 7800.0 * 4 / 3 * np.pi * R**3
    for v in (25.0, 55.0):
        j = johnson_plastic(R, m, v, 3 * SAE1070["A"])
        print(f"# Johnson fully plastic at {v} m/s: depth {j['delta']*1e6:.1f} um, diameter {2*j['a']*1e3:.3f} mm")
    print("| v m/s | rate term | h um | dent depth um | crest diameter mm | contact diameter mm | max approach um | "
          "restitution | peak force N | hourglass | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    conv = {}
    for v in (25.0, 55.0):
        for rate in (True, False):
            for h in (25e-6, 12.5e-6, 6.25e-6):
                if h < 20e-6 and not rate:
                    continue
                from peenflow.fe.mesh import graded_box
                mesh = graded_box(0.6e-3, 0.6e-3, h, fine_half_width=0.15e-3, fine_depth=0.1e-3)
                mat = Material(**{**SAE1070, "C": SAE1070["C"] if rate else 0.0})
                shots = Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, v]], radius=R, density=7800.0)
                t0 = time.perf_counter()
                res = run_impacts(Target(mesh), mat, shots, Options())
                nnx, nny, _ = mesh.shape_nodes
                uz = res.displacement[: nnx * nny, 2]
                X = res.nodes[: nnx * nny]
                # dent diameter through the pile-up crest (highest point, min u_z) along the x axis
                row = np.abs(X[:, 1]) < 1e-12
                xs, us = X[row, 0], uz[row]
                right = xs > 0
                diam = 2.0 * xs[right][np.argmin(us[right])]
                s = res.shots
                if rate:
                    conv.setdefault(v, []).append((uz.max(), s["max_approach"][0], s["restitution"][0]))
                print(f"| {v:g} | {'on' if rate else 'off'} | {h*1e6:g} | {uz.max()*1e6:.2f} | {diam*1e3:.3f} | "
                      f"{2*s['max_contact_radius'][0]*1e3:.3f} | "
                      f"{s['max_approach'][0]*1e6:.2f} | {s['restitution'][0]:.3f} | {s['peak_force'][0]:.0f} | "
                      f"{res.hourglass_ratio:.3f} | {time.perf_counter()-t0:.1f} |", flush=True)
    # Richardson extrapolation from h, h/2, h/4 (rate term on): observed order p and the h -> 0 value
    print("| v m/s | quantity | 25 / 12.5 / 6.25 um | observed order | extrapolated h -> 0 | 6.25 um vs extrapolated |")
    print("|---|---|---|---|---|---|")
    for v, rows in conv.items():
        for k, (name, scale) in enumerate((("dent depth um", 1e6), ("max approach um", 1e6), ("restitution", 1.0))):
            f1, f2, f3 = (r[k] * scale for r in rows)
            ratio = (f1 - f2) / (f2 - f3) if f2 != f3 else float("nan")
            if ratio > 1.0:
                order = np.log2(ratio)
                f0 = f3 + (f3 - f2) / (2**order - 1)
                print(f"| {v:g} | {name} | {f1:.3f} / {f2:.3f} / {f3:.3f} | {order:.2f} | {f0:.3f} | "
                      f"{100*(f3/f0-1):+.2f} % |")
            else:  # not monotone / not converging at a fixed rate: no extrapolation
                print(f"| {v:g} | {name} | {f1:.3f} / {f2:.3f} / {f3:.3f} | - | - | - |")


def _springback_errors(rs, ref, mesh, nodes0):
    """(profile error % of peak, dent error %, max |d sigma| MPa) of relaxed state ``rs`` against ``ref``."""
    nn = mesh.shape_nodes[0] * mesh.shape_nodes[1]
    _, p = profile(rs, mesh)
    _, p0 = profile(ref, mesh)
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
        saved = MG.SPAN_TOLERANCE, MG.POWER_MAX_NODES
        if old:  # the span check fails and every level runs its power iterations: the old setup
            MG.SPAN_TOLERANCE, MG.POWER_MAX_NODES = -1.0, 1 << 62
        try:
            c0 = time.process_time()
            mg = MG.Multigrid(mesh, bc, mat_static)
            return mg, time.process_time() - c0
        finally:
            MG.SPAN_TOLERANCE, MG.POWER_MAX_NODES = saved

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
    mesh = rev_mesh()
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


#: (label, material, angle deg, speed m/s, REV thickness m, preset, element um, REV side mm, lateral faces)
#: the REVs the shipped studies make (periodic 1.2 mm: paper_fast*.toml, the section-9 references; a 3 d_min
#: symmetric REV, d_min ~ 0.6 mm: the rev.rule = "dmin" default; the paper's fixed 6D x 6D strip REV)
#: the paper's fixed 6D x 6D strip REV with the standard preset (also :func:`springback_tolerance`'s)
REV_6D_STANDARD = ("strip, symmetric 3.48 mm (6D)", "SAE1070", 90.0, 55.0, 1.29e-3, "standard", 25.0, 3.48, "symmetric")
STUDY_REVS = (("strip, periodic 1.2 mm", "SAE1070", 90.0, 55.0, 1.29e-3, "standard", 25.0, 1.2, "periodic"),
              ("strip, periodic 1.2 mm", "SAE1070", 90.0, 55.0, 1.29e-3, "standard", 40.0, 1.2, "periodic"),
              ("strip, periodic 1.2 mm", "SAE1070", 90.0, 55.0, 1.29e-3, "paper", 25.0, 1.2, "periodic"),
              ("Al 7075 target, periodic 1.2 mm", "AL7075_T73", 65.0, 30.0, 0.9e-3, "standard", 25.0, 1.2, "periodic"),
              ("strip, symmetric 1.8 mm (3 d_min)", "SAE1070", 90.0, 55.0, 1.29e-3, "standard", 25.0, 1.8, "symmetric"),
              REV_6D_STANDARD,
              ("strip, symmetric 3.48 mm (6D)", "SAE1070", 90.0, 55.0, 1.29e-3, "paper", 25.0, 3.48, "symmetric"))


def _study_rev_run(row, n_shots: int, seed: int):
    """A :data:`STUDY_REVS` row as a study builds it (``tasks._kernel.rev_mesh``, the preset's values,
    ``FidelityParams.boundary`` / ``options``, the study's shot stream of ``n_shots``; S230 at
    mu = 0.2): ``(fidelity, shot, mesh, stream, shots, ImpactRun)``, no impact run yet."""
    import peenflow.testing as PT
    from peenflow.fe.impact import ImpactRun
    from peenflow.methods.shot_stream import shot_stream
    from peenflow.study.fidelity import PRESETS
    from tasks import _kernel as K
    from tasks.params import FidelityParams, ShotParams

    _, mat, angle, speed, thick, preset, h_um, side_mm, lateral = row
    shot = ShotParams(PT.S230.radius_m, PT.S230.density_kg_m3, 0.2)
    p = PRESETS[preset]
    f = FidelityParams(h_um * 1e-6, p["fine_depth_D"] * PT.S230.diameter_m, p["grading_ratio"],
                       p["time_step_safety"], p["window_contact_radii"], p["settle_tolerance"],
                       p["relaxation_tolerance"], lateral)
    side = side_mm * 1e-3
    mesh = K.rev_mesh(f, side, thick)
    stream = shot_stream(n_shots, shot.radius_m, side / 2, side / 2, angle, speed, seed)
    shots = shot.shots(stream.centres, stream.velocities)
    return f, shot, mesh, stream, shots, ImpactRun(f.boundary(mesh), Material(**getattr(PT, mat)), f.options(shot))


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
        _, shot, mesh, stream, shots, run = _study_rev_run(row, rungs[-1], seed)
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
    f, shot, mesh, stream, shots, run = _study_rev_run(REV_6D_STANDARD, rungs[-1], seed)
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
            _, p0 = profile(ref, mesh, half=PT.S230.diameter_m)
            for t in tolerances:
                c0 = time.process_time()
                rs, _ = relax(run.model, run.state, opts[t], *scales)
                cpu = time.process_time() - c0
                _, p1 = profile(rs, mesh, half=PT.S230.diameter_m)
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
    f, shot, mesh, stream, shots, run = _study_rev_run(REV_6D_STANDARD, n_shots, seed)
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


def window_minimum(speeds=(1.0, 5.0), h=25e-6):
    """Window minimum size for slow shots: peak force / restitution against the full mesh
    (stability sweep's 1.2 x 1.2 x 0.6 mm box, SAE 1070, normal; not relaxed)."""
    import warnings

    from peenflow.fe.impact import WindowValidityWarning
    from peenflow.fe.mesh import graded_box

    warnings.simplefilter("ignore", WindowValidityWarning)
    mat = Material(**SAE1070)
    t = Target(graded_box(0.6e-3, 0.6e-3, h, fine_half_width=0.15e-3, fine_depth=0.1e-3))
    run_impacts(t, mat, Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 5.0]], radius=R, density=7800.0),
                Options(final_relaxation=False))  # JIT warm-up
    print(f"# window minimum; loadavg {loadavg()}")
    print("| v m/s | window sizing | window (elements) | peak force N | vs full mesh | restitution | energy error | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    cases = (("full mesh", dict(window=False)),
             ("contact radii only (>= 2 elements)", dict(window_min_elements=2.0, window_min_wave=0.0)),
             (">= 3 elements", dict(window_min_elements=3.0, window_min_wave=0.0)),
             (">= 6 elements", dict(window_min_elements=6.0, window_min_wave=0.0)),
             (">= 3 elements, >= 0.05 c_p t_c (default)", {}),
             (">= 6 elements, >= 0.05 c_p t_c", dict(window_min_elements=6.0)),
             (">= 12 elements, >= 0.07 c_p t_c", dict(window_min_elements=12.0, window_min_wave=0.07)))
    for v in speeds:
        shots = Shots(centres=[[0.0, 0.0, -R - 1e-6]], velocities=[[0.0, 0.0, v]], radius=R, density=7800.0)
        f0 = None
        for name, kw in cases:
            c0 = time.process_time()
            r = run_impacts(t, mat, shots, Options(final_relaxation=False, **kw))
            cpu = time.process_time() - c0
            s = r.shots
            f = s["peak_force"][0]
            f0 = f if f0 is None else f0
            shape = f"{int(s['win_i1'][0] - s['win_i0'][0])} x {int(s['win_j1'][0] - s['win_j0'][0])} x {int(s['win_k1'][0])}"
            print(f"| {v:g} | {name} | {shape} | {f:.3f} | {100 * (f / f0 - 1):+.1f} % | {s['restitution'][0]:.4f} | "
                  f"{s['energy_error'][0]:.4f} | {cpu:.2f} |", flush=True)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "throughput"
    if what == "rev-relax":  # relaxation only: default window, 1 and 20 shots, no full-mesh run
        rev(windows=((4.0, 4.0),), full=False)
        rev(windows=((4.0, 4.0),), full=False, n_shots=20)
    elif what == "springback-tolerance" and len(sys.argv) > 2:  # tolerances [rungs], comma-separated
        springback_tolerance(tuple(float(t) for t in sys.argv[2].split(",")),
                             *([tuple(int(n) for n in sys.argv[3].split(","))] if len(sys.argv) > 3 else []))
    else:
        {"throughput": throughput, "rev": rev, "hertz": hertz_table, "hertz-layout": hertz_layouts, "plastic": plastic_table,
         "window": window_error, "window-timing": window_timing, "window-size": window_size, "settle": settle_tolerance, "window-seq": window_sequence, "springback": springback,
         "springback-study": springback_study,
         "springback-tolerance": springback_tolerance,
         "springback-mismatch": springback_mismatch,
         "window-min": window_minimum}[what]()
