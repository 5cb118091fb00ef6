"""One impact on the strip REV, and n shots: the window against the full mesh, the global
relaxation, the settle's at-rest criterion (prints its figures; not a test;
docs/validation.md section 6; docs/performance.md sections 2 and 3).

Usage (from the repository root)::

    python benchmarks/strip_rev.py impact     # one 55 m/s impact, windows 4x4 / 3x3 / 6x6 against the full mesh
    python benchmarks/strip_rev.py impact 90 45 30   # the same at each impingement angle (deg; no dynamic relaxation)
    python benchmarks/strip_rev.py relax      # global relaxation only (static vs dynamic), 1 and 20 shots
    python benchmarks/strip_rev.py settle     # the at-rest criterion that ends a shot's settle: run time vs error

The strip REV: 6D x 6D x 1.29 mm, 25 um laterally
(:func:`peenflow.validation.kernel_cases.strip_rev_mesh`); profiles are sigma_xx per element layer
over the central 2D x 2D region. JIT compilation is excluded (each kernel is warmed up on a tiny case
first).
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
from peenflow.validation.kernel_cases import R, SAE1070, layer_profile, loadavg, strip_rev_mesh


def rev(windows=((4.0, 4.0), (3.0, 3.0), (6.0, 6.0)), full=True, speed=55.0, n_shots=1, relax_dynamic=True, sponge=0.0,
        angle_deg=90.0):
    """Windows against the full mesh (and the relaxations' cost and error) for ``n_shots`` shots at
    ``speed`` m/s and ``angle_deg`` to the surface (the slide along +x); one shot lands at the centre."""
    mesh = strip_rev_mesh()
    t = Target(mesh)
    mat = Material(**SAE1070)
    rng = np.random.default_rng(0)
    if n_shots == 1:
        c = [[0.0, 0.0, -R - 1e-6]]
    else:
        c = np.column_stack([rng.uniform(-0.3e-3, 0.3e-3, n_shots), rng.uniform(-0.3e-3, 0.3e-3, n_shots),
                             np.full(n_shots, -R - 1e-6)])
    th = np.radians(angle_deg)
    shots = Shots(centres=c, velocities=[[speed * np.cos(th), 0.0, speed * np.sin(th)]] * n_shots, radius=R,
                  density=7800.0)
    nnx, nny, _ = mesh.shape_nodes
    print(f"# strip REV {mesh.shape_elements} = {mesh.n_elements} elements, {n_shots} shot(s) at {speed} m/s, "
          f"{angle_deg:g} deg; "
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
        zs, p = layer_profile(rs, mesh)
        results[name] = (uz.max(), p, res.shots["restitution"].mean(), res.shots["vout_x"].mean(), res.energy_error)
        rel = []
        for tol in ("static", "dynamic"):
            if tol in out:
                _, p2 = layer_profile(out[tol][0], mesh)
                rel.append(f"{tol} {out[tol][1]:.1f} s / {out[tol][2]} {'passes' if tol == 'static' else 'steps'} "
                           f"(load {out[tol][3]}), profile vs reference {100*np.abs(p2-p).max()/np.abs(p).max():.3f} %, "
                           f"eps_p changed in {int(np.sum(out[tol][0].eps_p != res.final_state.eps_p))} elements")
        print(f"{name}: impact+settle wall {wall:.2f} s ({win['steps'].sum():.0f} steps on "
              f"{int(((win['win_i1']-win['win_i0'])*(win['win_j1']-win['win_j0'])*(win['win_k1']-win['win_k0'])).mean())}"
              f" elements); global relaxation: " + "; ".join(rel) + f"; dent {uz.max()*1e6:.3f} um, "
              f"restitution {res.shots['restitution'].mean():.4f}, E err {res.energy_error:.4f}, "
              f"hourglass {res.hourglass_ratio:.3f}", flush=True)
    if full:
        d0, p0, e0, t0, _ = results["full"]
        print("| window (x contact radius) | dent error | restitution error | tangential rebound error | "
              "profile error (max abs / max abs full) | energy error |")
        print("|---|---|---|---|---|---|")
        for name, (d, p, e, t, ee) in results.items():
            if name == "full":
                continue
            tang = f"{100*(t/t0-1):+.2f} %" if t0 else "-"
            print(f"| {name} | {100*(d/d0-1):+.2f} % | {100*(e/e0-1):+.2f} % | {tang} | "
                  f"{100*np.abs(p-p0).max()/np.abs(p0).max():.2f} % | {ee:.4f} |")
        print("# full-mesh averaged sigma_xx profile (MPa) by depth (um):")
        print(" ".join(f"{z*1e6:.0f}:{s/1e6:.0f}" for z, s in zip(zs[:16], p0[:16])))



def settle_tolerance(n=10, speed=55.0):
    """Run time against error of the 'at rest' criterion that ends each shot's settle (strip REV, n shots)."""
    from peenflow.fe.model import Model
    from peenflow.fe.relaxation import relax

    mesh = strip_rev_mesh()
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
        _, p = layer_profile(rs, mesh)
        if ref is None:
            ref = (p, rs.eps_p.sum())
        print(f"| {ke:g} | {vf:g} | {int(r.shots['steps'].sum())} | {wall:.1f} s | "
              f"{100*np.abs(p-ref[0]).max()/np.abs(ref[0]).max():.3f} % | {rs.eps_p.sum()/ref[1]:.5f} | "
              f"{r.energy_error:.4f} | {loadavg()} |", flush=True)


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    p = sub.add_parser("impact", help="one impact: windows against the full mesh, with both relaxations")
    p.add_argument("angles", type=float, nargs="*",
                   help="impingement angles deg: the windows at each (the static relaxation only); default 90, both")
    sub.add_parser("relax", help="global relaxation only (static vs dynamic), default window, 1 and 20 shots")
    sub.add_parser("settle", help="the at-rest criterion: run time against error, 10 shots")
    a = ap.parse_args(argv)
    mode = a.mode
    if mode == "impact" and a.angles:
        for angle in a.angles:
            rev(relax_dynamic=False, angle_deg=angle)
    elif mode == "impact":
        rev()
    elif mode == "relax":
        rev(windows=((4.0, 4.0),), full=False)
        rev(windows=((4.0, 4.0),), full=False, n_shots=20)
    else:
        settle_tolerance()


if __name__ == "__main__":
    main()
