"""B-bar (mean-dilatation, 2 x 2 x 2) hexahedron against the kernel's one-point physical element on the single
impacts of ``bench_hourglass.py`` (issue 13 §1: "if another element measures better for the same cost, use it
and show the comparison"). The element: :mod:`benchmarks.bbar.element_bbar`; the driver (same mesh, shot,
contact, boundary conditions and settle as ``bench_hourglass.run``, dynamic final relaxation for both
elements): :mod:`benchmarks.bbar.driver`. Results and conclusion: BENCHMARKS.md section 4d. The element
``physical8`` (the kernel's physical element with plasticity at its eight Gauss points) runs through the same
driver: BENCHMARKS.md section 4e.

Usage (from the repository root, one thread)::

    PYTHONPATH=. python benchmarks/bench_bbar.py run CASE ELEMENT H_UM   # one run (ELEMENT: bbar | physical | physical8), stored
    PYTHONPATH=. python benchmarks/bench_bbar.py all H_UM [H_UM ...]    # every case and element not stored yet
    PYTHONPATH=. python benchmarks/bench_bbar.py table                   # the tables, from the store only
    PYTHONPATH=. python benchmarks/bench_bbar.py cost                    # CPU s per 10^6 element updates
    PYTHONPATH=. python benchmarks/bench_bbar.py remetric                # surface figures again from the stored lines

Runs are stored in ``benchmarks/bbar/results.json`` (metrics as ``bench_hourglass.metrics``, CPU s of this
process, steps). The errors are against ``bench_hourglass.reference`` (the 6.25 um physical runs of
``benchmarks/reference/hourglass.json``, Richardson-extrapolated per quantity where that function says so),
with ``bench_hourglass._error`` / ``QUANTITIES`` / ``profile_rms``.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import bench_hourglass as bh  # noqa: E402

STORE = HERE / "bbar" / "results.json"
ELEMENTS = ("physical", "bbar", "physical8")
SIZES = (50.0, 25.0, 12.5, 6.25)


def _load() -> dict:
    return json.loads(STORE.read_text()) if STORE.exists() else {}


def _store(key: str, value: dict) -> None:
    data = _load()
    data[key] = value
    STORE.write_text(json.dumps(data, indent=1, sort_keys=True))


def _key(case, element, h):
    return f"{case}/{element}/{h:g}"


def remetric() -> None:
    """The surface figures of every stored run again from its stored surface line, by the present
    ``bench_hourglass.surface_metrics`` (after a change of that reading; the runs are not repeated)."""
    data = _load()
    for v in data.values():
        v.update(bh.surface_metrics(np.array(v["surface_x_mm"]) * 1e-3, np.array(v["surface_uz_um"]) * 1e-6))
    STORE.write_text(json.dumps(data, indent=1, sort_keys=True))


def run_one(case: str, element: str, h: float) -> dict:
    from benchmarks.bbar.driver import run

    out = run(case, element, h)
    _store(_key(case, element, h), out)
    return out


def table() -> None:
    """Per case: errors of each stored run against the reference, CPU s; then the kernel's stored physical
    runs (static relaxation) at the same sizes for comparison; then the equal-cost pairs."""
    data, kernel = _load(), bh._load()
    for case in bh.CASES:
        ref, note = bh.reference(kernel, case)
        print(f"\n#### {case} (reference: {note})")
        print("| element | h um | " + " | ".join(q[1] for q in bh.QUANTITIES) + " | profile RMS | CPU s | steps |")
        print("|---|---|" + "---|" * (len(bh.QUANTITIES) + 3))
        rows = [(f"{el} (driver)", data.get(_key(case, el, h)), h) for el in ELEMENTS for h in SIZES]
        rows += [("physical (kernel, stored)", kernel.get(f"{case}/physical/{h:g}"), h) for h in SIZES]
        for label, v, h in rows:
            if v is None:
                continue
            steps = f"{v['impact_steps']} + {v['relax_steps']}" if "impact_steps" in v else ""
            print(f"| {label} | {h:g} | " + " | ".join(bh.error_cells(v, ref)) +
                  f" | {100 * bh.profile_rms(v, ref):.1f} % | {v['cpu_s']:.1f} | {steps} |")
    print("\n#### Largest |error| over the four cases (driver runs)\n")
    print("| element | h um | " + " | ".join(q[1] for q in bh.QUANTITIES) + " | profile RMS | CPU s (sum of 4) |")
    print("|---|---|" + "---|" * (len(bh.QUANTITIES) + 2))
    refs = {case: bh.reference(kernel, case)[0] for case in bh.CASES}
    for el in ELEMENTS:
        for h in SIZES:
            runs = [(data.get(_key(c, el, h)), refs[c]) for c in bh.CASES]
            if any(v is None for v, _ in runs):
                continue
            cells, rms = bh.worst_cells(runs)
            print(f"| {el} | {h:g} | " + " | ".join(cells) + f" | {100 * rms:.1f} % | "
                  f"{sum(v['cpu_s'] for v, _ in runs):.0f} |")
    print("\n#### Equal cost: B-bar at h against physical at h / 2 (driver runs; |error|, the closer one in bold)\n")
    print("| case | pair | CPU s | " + " | ".join(q[1] for q in bh.QUANTITIES) + " | profile RMS | B-bar closer on |")
    print("|---|---|---|" + "---|" * (len(bh.QUANTITIES) + 2))
    for case in bh.CASES:
        ref = refs[case]
        for hb, hp in ((50.0, 25.0), (25.0, 12.5)):
            b, p = data.get(_key(case, "bbar", hb)), data.get(_key(case, "physical", hp))
            if b is None or p is None:
                continue
            cells, wins = [], 0
            for k, _, kind in bh.QUANTITIES + (("rms", "", "rms"),):
                if kind == "rms":
                    eb, ep = bh.profile_rms(b, ref), bh.profile_rms(p, ref)
                else:
                    eb, ep = abs(bh._error(b, ref, k, kind)), abs(bh._error(p, ref, k, kind))
                fmt = (lambda e: f"{e:.3f}") if kind == "abs" else (lambda e: f"{100 * e:.1f} %")
                sb, sp = fmt(eb), fmt(ep)
                sb, sp = (f"**{sb}**", sp) if eb < ep else (sb, f"**{sp}**")
                wins += eb < ep
                cells.append(f"{sb} / {sp}")
            print(f"| {case} | B-bar {hb:g} / physical {hp:g} | {b['cpu_s']:.1f} / {p['cpu_s']:.1f} | "
                  + " | ".join(cells) + f" | {wins} of {len(bh.QUANTITIES) + 1} |")
    print("\n#### The driver's physical runs (dynamic relaxation) against the kernel's stored ones (static)\n")
    print("| case | h um | " + " | ".join(q[1] for q in bh.QUANTITIES) + " | profile RMS |")
    print("|---|---|" + "---|" * (len(bh.QUANTITIES) + 1))
    for case in bh.CASES:
        for h in SIZES:
            v, s = data.get(_key(case, "physical", h)), kernel.get(f"{case}/physical/{h:g}")
            if v is None or s is None:
                continue
            cells = []
            for k, _, kind in bh.QUANTITIES:
                e = bh._error(v, s, k, kind)
                cells.append(f"{e:+.4f}" if kind == "abs" else f"{100 * e:+.3f} %")
            print(f"| {case} | {h:g} | " + " | ".join(cells) + f" | {100 * bh.profile_rms(v, s):.3f} % |")


def cost(shape=(40, 40, 40), rounds=3, reps=5) -> None:
    """CPU s per million element updates (1 thread, process CPU, best round): the kernel's vectorised one-point
    physical element (``element_rows``), its one-element-at-a-time reference (``element_reference.element_pass``),
    the B-bar element one point at a time (``bbar_pass``) and with its points as lanes (``bbar_pass_v``, the
    driver's), the physical element with plasticity at its Gauss points (``p8_pass``, one element at a time, the
    driver's); elastic and every element (every Gauss point) yielding: the state of ``bench_hourglass.cost``,
    25 passes before the timing put the stress on the yield surface, and the timed passes are checked to do
    plastic work."""
    import numba

    from benchmarks.bbar.element_bbar import bbar_pass, bbar_pass_v, p8_pass
    from peenflow.fe.element import element_rows
    from peenflow.fe.element_reference import element_pass
    from peenflow.fe.johnson_cook import Material
    from peenflow.fe.mesh import BoxMesh

    numba.set_num_threads(1)
    nx, ny, nz = shape
    h = 25e-6
    mesh = BoxMesh(np.arange(nx + 1) * h, np.arange(ny + 1) * h, np.arange(nz + 1) * h)
    X = mesh.node_coordinates()
    n, ne = mesh.n_nodes, mesh.n_elements
    nnx, nny, _ = mesh.shape_nodes
    mat = Material(**bh.SAE1070)
    arr = mat.to_array(hourglass_type="physical")
    best = {}
    names = ("one-point physical, vectorised rows (kernel)", "one-point physical, reference (one element at a time)",
             "B-bar, one Gauss point at a time (bbar_pass)", "B-bar, Gauss points as lanes (bbar_pass_v, driver)",
             "physical8, one element at a time (p8_pass, driver)")
    for _ in range(rounds):
        for plastic in (False, True):
            for which in range(5):
                G = np.array([[1.0, 0.2, 0.0], [0.0, -0.5, 0.1], [0.3, 0.0, -0.5]]) * (1e5 if plastic else 1e2)
                v = X @ G.T + np.random.default_rng(0).normal(0, 1e-2, X.shape)
                npt = 8 * ne if which >= 2 else ne
                st = [np.zeros((npt, 6)), np.zeros(npt) + 0.1, np.full(npt, 1e3 if plastic else 1e12)]
                if which >= 2:
                    a = [X, v, np.zeros((n, 3)), *st, np.full(npt, 293.0), mesh.element_volumes(), arr, 4e-9,
                         nnx, nny, nx, ny, 0, nx, 0, ny, 0, nz]
                    fn = (bbar_pass, bbar_pass_v, p8_pass)[which - 2]
                else:
                    a = [X, v, np.zeros((n, 3)), *st, np.zeros((ne, 12)), np.full(ne, 293.0),
                         mesh.element_volumes(), arr, 4e-9, nnx, nny, nx, ny, 0, nx, 0, ny, 0, nz]
                    fn = element_rows if which == 0 else element_pass
                for _ in range(25):  # compiled, and (plastic) the stress on the yield surface
                    fn(*a)
                c = time.process_time()
                wp = 0.0
                for _ in range(reps):
                    wp += fn(*a)[3]
                per = (time.process_time() - c) / (reps * ne / 1e6)
                assert (wp > 0.0) == plastic, (names[which], plastic, wp)
                best[(which, plastic)] = min(best.get((which, plastic), 1e30), per)
    print("| element | elastic CPU s / 10^6 element updates | all yielding | vs kernel rows (elastic / yielding) |")
    print("|---|---|---|---|")
    for which in range(5):
        e, p = best[(which, False)], best[(which, True)]
        print(f"| {names[which]} | {e:.3f} | {p:.3f} | {e / best[(0, False)]:.1f}x / {p / best[(0, True)]:.1f}x |")


if __name__ == "__main__":
    cmd = sys.argv[1] if len(sys.argv) > 1 else "table"
    if cmd == "run":
        o = run_one(sys.argv[2], sys.argv[3], float(sys.argv[4]))
        print(json.dumps({k: v for k, v in o.items() if not isinstance(v, list)}, indent=1))
    elif cmd == "all":
        for h in (float(a) for a in sys.argv[2:]):
            for case in bh.CASES:
                for el in ELEMENTS:
                    if _key(case, el, h) not in _load():
                        o = run_one(case, el, h)
                        print(f"{case} {el} {h:g}: dent {o['dent_um']:.3f} um, CPU {o['cpu_s']:.1f} s", flush=True)
    elif cmd == "cost":
        cost()
    elif cmd == "remetric":
        remetric()
    else:
        table()
