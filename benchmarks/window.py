"""The impact window against the full mesh: its error, its cost and its minimum size (prints its figures;
not a test; docs/validation.md section 6, "Window variants", "Slow shots").

Usage (from the repository root)::

    python benchmarks/window.py error      # held / viscous-spring faces vs the full mesh, strip REV and test box
    python benchmarks/window.py timing     # impact + settle wall of both faces, interleaved (the end of error too)
    python benchmarks/window.py size       # held window lateral x depth vs error, strip REV
    python benchmarks/window.py sequence   # both faces in 4- and 80-shot sequences (~25 min)
    python benchmarks/window.py minimum    # the window minimum at 1 and 5 m/s vs the full mesh

Both sides of a comparison are relaxed to rest over the whole mesh by a strict static relaxation;
profile error = max |delta sigma_xx| over depth / max |sigma_xx full| (sigma_xx averaged per element
layer over the measuring region). JIT compilation is excluded.
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
from peenflow.fe.window import ViscousSpringFaces
from peenflow.validation.kernel_cases import R, SAE1070, layer_profile, loadavg, strip_rev_mesh


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
    _, p = layer_profile(rs, t.mesh, half)
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
    vs = dict(window_faces=ViscousSpringFaces())
    # warm-up compile (both boundaries) on a tiny case
    tiny = Target(BoxMesh(*(np.linspace(-2e-4, 2e-4, 17),) * 2, np.linspace(0, 2e-4, 9)))
    for kw in (dict(), vs):
        run_impacts(tiny, mat, Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 10.0]], radius=R,
                                     density=7800.0), Options(window_lateral=2.0, window_depth=2.0, **kw))
    boxes = (("strip REV", Target(strip_rev_mesh()), 0.58e-3),
             ("test box (tests/fe/test_impact.py)",
              Target(graded_box(0.6e-3, 0.6e-3, 25e-6, fine_half_width=0.15e-3, fine_depth=0.1e-3)), 0.15e-3))
    for box, t, half in boxes:
        model = Model(t, mat)
        model.multigrid()
        held = dict()  # the default faces
        cases = [("viscous-spring 4 x 4", vs), ("held 4 x 4 (default)", held),
                 ("viscous-spring 3 x 3", dict(vs, window_lateral=3.0, window_depth=3.0)),
                 ("held 3 x 3", dict(held, window_lateral=3.0, window_depth=3.0))]
        if box == "strip REV":
            cases += [("viscous-spring 6 x 6", dict(vs, window_lateral=6.0, window_depth=6.0)),
                      ("held 6 x 6", dict(held, window_lateral=6.0, window_depth=6.0)),
                      ("held 4 x 4 + window_sponge=0.3", dict(held, window_sponge=0.3)),
                      ("held, full width x 4 deep", dict(held, window_lateral=18.0)),
                      ("viscous-spring 4 x 4, no slab term", dict(window_faces=ViscousSpringFaces(slab=0.0))),
                      ("viscous-spring 4 x 4, no dashpots", dict(window_faces=ViscousSpringFaces(dashpot=0.0))),
                      ("viscous-spring 4 x 4, dashpots kept while settling", dict(window_faces=ViscousSpringFaces(settle="viscous-spring")))]
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
    t = Target(strip_rev_mesh())
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



def window_timing(reps=4, speed=55.0):
    """Impact + settle wall of the default 4 x 4 window, held vs viscous-spring faces, interleaved (same load)."""
    from peenflow.fe.mesh import graded_box

    mat = Material(**SAE1070)
    shots = Shots(centres=[[0.0, 0.0, -R - 1e-6]], velocities=[[0.0, 0.0, speed]], radius=R, density=7800.0)
    tiny = Target(BoxMesh(*(np.linspace(-2e-4, 2e-4, 17),) * 2, np.linspace(0, 2e-4, 9)))
    kinds = ("held", "viscous-spring")
    faces = {"held": None, "viscous-spring": ViscousSpringFaces()}
    for b in kinds:
        run_impacts(tiny, mat, shots, Options(window_lateral=2.0, window_depth=2.0, window_faces=faces[b]))
    for name, t, n in (("strip REV", Target(strip_rev_mesh()), reps),
                       ("test box", Target(graded_box(0.6e-3, 0.6e-3, 25e-6, fine_half_width=0.15e-3,
                                                      fine_depth=0.1e-3)), 2 * reps)):
        walls = {b: [] for b in kinds}
        steps = {}
        load0 = loadavg()
        for _ in range(n):
            for b in kinds:
                t0 = time.perf_counter()
                r = run_impacts(t, mat, shots, Options(window_faces=faces[b], final_relaxation=False))
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

    mesh = strip_rev_mesh()
    t = Target(mesh)
    mat = Material(**SAE1070)
    m = Model(t, mat)
    rng = np.random.default_rng(0)
    n = max(n_error, n_long)
    c = np.column_stack([rng.uniform(-0.3e-3, 0.3e-3, n), rng.uniform(-0.3e-3, 0.3e-3, n), np.full(n, -R - 1e-6)])
    strict = Options(relax_ke_fraction=1e-13, relax_cg_rtol=1e-4)
    nnx, nny, _ = mesh.shape_nodes
    kinds = (("held 4 x 4 (default)", dict()),
             ("held 4 x 8", dict(window_depth=8.0)),
             ("held 4 x 12", dict(window_depth=12.0)),
             ("viscous-spring 4 x 4", dict(window_faces=ViscousSpringFaces())),
             ("viscous-spring 4 x 8", dict(window_faces=ViscousSpringFaces(), window_depth=8.0)))
    shots = Shots(centres=c[:n_error], velocities=[[0.0, 0.0, speed]] * n_error, radius=R, density=7800.0)
    e_ref = 0.5 * shots.mass * speed**2
    print(f"# strip REV, {n_error} shots at {speed:g} m/s over +-0.3 mm; loadavg {loadavg()}", flush=True)
    out = {}
    for name, kw in (("full", dict(window=False)),) + kinds:
        t0 = time.perf_counter()
        r = run_impacts(t, mat, shots, Options(final_relaxation=False, **kw))
        wall = time.perf_counter() - t0
        rs, _ = relax(m, r.final_state, strict, e_ref, speed)
        _, p = layer_profile(rs, mesh)
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


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="mode", required=True)
    sub.add_parser("error", help="held / viscous-spring window faces against the full mesh (then timing)")
    sub.add_parser("timing", help="impact + settle wall of the default window, both faces, interleaved")
    sub.add_parser("size", help="held window faces: error against lateral x depth")
    sub.add_parser("sequence", help="both faces in 4-shot (errors) and 80-shot (energy balance) sequences")
    sub.add_parser("minimum", help="the window minimum for slow shots against the full mesh")
    {"error": window_error, "timing": window_timing, "size": window_size, "sequence": window_sequence,
     "minimum": window_minimum}[ap.parse_args(argv).mode]()


if __name__ == "__main__":
    main()
