"""Symmetric vs periodic lateral faces on a small REV block (prints its figures; not a test).

Usage (from the repository root)::

    python benchmarks/periodic.py [n_shots] [seeds...]     # default 40 shots, seeds 1-6

Block: ``SIDE x SIDE x 1.29 mm`` (the strip REV's thickness), 50 um
elements laterally (uniform) and down to 0.3 mm, graded (1.2) below; fixed
bottom. SAE 1070 (peenflow.testing, as the kernel benchmarks), S230 (R = 0.29 mm) at
55 m/s, normal, landing uniformly over the whole top face
(:func:`peenflow.methods.shot_stream`, the REV tasks' stream). Default
options (window 4 contact radii, held faces, static relaxation), 1 thread.

Figures: per seed, sigma_xx averaged per element layer over the central
CENTRE x CENTRE measuring region (symmetric vs periodic, and the
seed-to-seed scatter); for the first seed also over the bands of elements
within EDGE of the x faces / y faces; over all seeds, the face-normal
stress (sigma_xx near the x faces, sigma_yy near the y faces, pooled) and
the stress along the face, per band of EDGE of distance from the nearer
face, over the elements at least AWAY from the other two faces, averaged
over two depth ranges (mean +- standard error over seeds, and the paired
difference);
CPU time per run, and the cost of one Model.roll. The same shots hit both
targets (a shot near a symmetric face is not mirrored by the driver: the
face is a mirror plane, the image shot is implied).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots
from peenflow.methods import shot_stream
from peenflow.testing import SAE1070  # paper Table 1, from the study library

R = 0.29e-3
RHO = 7800.0
H = 50e-6
SIDE = 2.0e-3  # 40 x 40 elements laterally, ~3.4 D
CENTRE = 0.6e-3  # central measuring region (about 1 D)
EDGE = 0.1e-3  # edge bands: 2 elements
AWAY = 0.3e-3  # distance-from-face statistics: elements at least this far from the other faces
SPEED = 55.0


def loadavg() -> str:
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def mesh() -> BoxMesh:
    n = int(round(SIDE / H))
    lat = np.linspace(-0.5 * SIDE, 0.5 * SIDE, n + 1)
    return BoxMesh(lat, lat.copy(), graded_axis(0.3e-3, H, 1.29e-3, 1.2))


def profiles(stress, m: BoxMesh) -> tuple[np.ndarray, dict]:
    c = m.element_centroids()
    zs = np.unique(c[:, 2])
    half = 0.5 * SIDE
    sel = {
        "centre": (np.abs(c[:, 0]) <= 0.5 * CENTRE) & (np.abs(c[:, 1]) <= 0.5 * CENTRE),
        "x-faces": np.abs(c[:, 0]) >= half - EDGE,
        "y-faces": np.abs(c[:, 1]) >= half - EDGE,
    }
    return zs, {k: np.array([stress[s & (c[:, 2] == z), 0].mean() for z in zs]) for k, s in sel.items()}


def by_distance(stress, m: BoxMesh, zmax: float, zmin: float = 0.0, normal: bool = True) -> np.ndarray:
    """Stress along the face normal (``normal``: sigma_xx by distance from the x
    faces, sigma_yy from the y faces, pooled) or along the face (sigma_yy from
    the x faces, sigma_xx from the y faces), averaged over the layers with
    zmin < centroid z <= zmax and over the elements at least AWAY from the
    other pair of faces, per band of EDGE of distance from the nearer face
    (Pa; band 0 = at the faces)."""
    c = m.element_centroids()
    half = 0.5 * SIDE
    lay = (c[:, 2] > zmin) & (c[:, 2] <= zmax)
    nb = int(round(half / EDGE))
    out = np.zeros(nb)
    for b in range(nb):
        vals = []
        for ax in (0, 1):
            d = half - np.abs(c[:, ax])
            other = half - np.abs(c[:, 1 - ax])
            sel = lay & (d >= b * EDGE) & (d < (b + 1) * EDGE) & (other >= AWAY)
            vals.append(stress[sel, ax if normal else 1 - ax])
        out[b] = np.concatenate(vals).mean()
    return out


def main(n_shots: int = 40, seeds=(1, 2, 3, 4, 5, 6)) -> None:
    m = mesh()
    mat = Material(**SAE1070)
    print(f"# block {SIDE * 1e3:.2f} x {SIDE * 1e3:.2f} x 1.29 mm, h = {H * 1e6:.0f} um, {m.n_elements} elements; "
          f"{n_shots} shots S230 at {SPEED} m/s, normal; seeds {seeds}; centre region {CENTRE * 1e3:.2f} mm "
          f"square, edge bands {EDGE * 1e3:.2f} mm")
    # warm-up (JIT) on a tiny case, both conditions
    tiny = np.linspace(-0.6e-3, 0.6e-3, 25)
    tm = BoxMesh(tiny, tiny.copy(), graded_axis(0.2e-3, H, 0.6e-3, 1.2))
    for lat in ("symmetric", "periodic"):
        run_impacts(Target(tm, lateral=lat), mat,
                    Shots([[0, 0, -R - 1e-6]], [[0, 0, SPEED]], R, RHO), Options())
    # cost of one roll of this block's state (a rolled shot pays two)
    from peenflow.fe.model import Model
    from peenflow.fe.periodic import roll

    model = Model(Target(m, lateral="periodic"), mat)
    st = model.new_state()
    c0 = time.process_time()
    for k in range(10):
        roll(model, st, 7, -5)
    print(f"# peenflow.fe.periodic.roll on this block: {(time.process_time() - c0) / 10 * 1e3:.1f} ms cpu")
    out, cpu_t = {}, {}
    for seed in seeds:
        stream = shot_stream(n_shots, R, 0.5 * SIDE, 0.5 * SIDE, 90.0, SPEED, seed)
        shots = Shots(np.array(stream.centres), np.array(stream.velocities), R, RHO)
        for lat in ("symmetric", "periodic"):
            l0 = loadavg()
            t0 = time.perf_counter()
            c0 = time.process_time()
            res = run_impacts(Target(m, lateral=lat), mat, shots, Options())
            wall, cpu = time.perf_counter() - t0, time.process_time() - c0
            out[seed, lat] = res.stress
            cpu_t[seed, lat] = cpu
            hit = res.shots["hit"] > 0
            print(f"seed {seed} {lat:9s}: wall {wall:6.1f} s, cpu {cpu:6.1f} s, {int(hit.sum())} hits, "
                  f"energy error max {res.energy_error:.4f}, max eps_p {res.eps_p.max():.3f}, "
                  f"load {l0} -> {loadavg()}", flush=True)
    seed = seeds[0]
    zs, s = profiles(out[seed, "symmetric"], m)
    _, p = profiles(out[seed, "periodic"], m)
    zs = zs * 1e6
    print(f"\n## seed {seed}: sigma_xx (MPa) per layer; depth um | centre sym / per | x-face bands sym / per "
          f"| y-face bands sym / per")
    for k, z in enumerate(zs):
        if z > 700:
            break
        print(f"{z:6.0f} | {s['centre'][k] / 1e6:8.1f} {p['centre'][k] / 1e6:8.1f} | "
              f"{s['x-faces'][k] / 1e6:8.1f} {p['x-faces'][k] / 1e6:8.1f} | "
              f"{s['y-faces'][k] / 1e6:8.1f} {p['y-faces'][k] / 1e6:8.1f}")
    print("\n## central region: max over depth |sigma_xx profile sym - per| (MPa) and / peak; seed-to-seed")
    cent = {k: profiles(v, m)[1]["centre"] for k, v in out.items()}
    for seed in seeds:
        d = np.abs(cent[seed, "symmetric"] - cent[seed, "periodic"]).max()
        peak = np.abs(cent[seed, "symmetric"]).max()
        print(f"seed {seed}: peak {peak / 1e6:.0f}, sym-per {d / 1e6:.1f} ({100 * d / peak:.2f} %)")
    for lat in ("symmetric", "periodic"):
        prof = np.array([cent[sd, lat] for sd in seeds])
        print(f"{lat}: seed-to-seed std of the centre profile, max over depth {prof.std(axis=0, ddof=1).max() / 1e6:.1f}")
    print(f"\n## stress by distance from the nearer face (MPa; elements >= {AWAY * 1e3:.1f} mm from the other "
          "faces), mean over seeds +- std error")
    for zmin, zmax, name, normal in ((0.0, 150e-6, "z <= 150 um (compressive plateau), face-normal", True),
                                     (150e-6, 250e-6, "150 < z <= 250 um (zero crossing), face-normal", True),
                                     (0.0, 150e-6, "z <= 150 um, along the face", False),
                                     (150e-6, 250e-6, "150 < z <= 250 um, along the face", False)):
        print(f"# {name}; bands of {EDGE * 1e3:.1f} mm from the face")
        a = {}
        for lat in ("symmetric", "periodic"):
            a[lat] = np.array([by_distance(out[sd, lat], m, zmax, zmin, normal) for sd in seeds]) / 1e6
            mu, se = a[lat].mean(axis=0), a[lat].std(axis=0, ddof=1) / np.sqrt(len(seeds))
            print(f"{lat:9s} " + " ".join(f"{x:7.0f}+-{e:3.0f}" for x, e in zip(mu, se)))
        d = a["symmetric"] - a["periodic"]  # paired: same shots
        mu, se = d.mean(axis=0), d.std(axis=0, ddof=1) / np.sqrt(len(seeds))
        print(f"{'sym - per':9s} " + " ".join(f"{x:7.0f}+-{e:3.0f}" for x, e in zip(mu, se)))
    for lat in ("symmetric", "periodic"):
        print(f"cpu {lat}: mean {np.mean([cpu_t[sd, lat] for sd in seeds]):.1f} s")
    print(f"# load at end {loadavg()}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("n_shots", type=int, nargs="?", default=40)
    ap.add_argument("seeds", type=int, nargs="*", help="shot-stream seeds (default 1-6)")
    a = ap.parse_args()
    main(a.n_shots, tuple(a.seeds) or (1, 2, 3, 4, 5, 6))
