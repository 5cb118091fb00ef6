"""Regenerate ``driver_golden.json``: digests of the driver's outputs on small cases (run from the repository root).

    .venv/bin/python tests/fe/data/make_driver_golden.py            # rewrite the file
    .venv/bin/python tests/fe/data/make_driver_golden.py --print    # print the digests as JSON (the test)

The file pins :func:`peenflow.fe.impact.run_impacts` bit for bit
(``tests/fe/test_driver_golden.py``); it was first written on main 88837bb,
before the driver was split into small steps. Regenerate it only for a
change meant to alter the kernel's numbers, and say so in the commit.

The multigrid's setup and coarsest solve go through LAPACK / BLAS, whose
OpenBLAS kernels are chosen per CPU at load time and differ in summation
order (the relaxed outputs then differ in their last bits between, say, an
AVX2 and an AVX-512 machine). So this script runs with one thread and the
OpenBLAS kernel set pinned to :data:`BLAS_CORETYPE` (AVX2, which every x86-64
machine this project runs on has); it must be set before numpy loads, which
is why the test runs this script in a subprocess.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
import time
import warnings
from pathlib import Path

#: OpenBLAS kernel set the digests are written and checked with (see the module docstring)
BLAS_CORETYPE = "Haswell"
os.environ["OPENBLAS_CORETYPE"] = BLAS_CORETYPE
os.environ["OPENBLAS_NUM_THREADS"] = "1"

import numpy as np  # noqa: E402
from threadpoolctl import threadpool_info, threadpool_limits  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parents[3]))

from peenflow.fe.impact import Options, WindowValidityWarning, run_impacts  # noqa: E402
from peenflow.fe.window import ViscousSpringFaces  # noqa: E402
from peenflow.fe.johnson_cook import Material  # noqa: E402
from peenflow.fe.mesh import BoxMesh, graded_axis, graded_box  # noqa: E402
from peenflow.fe.model import Target  # noqa: E402
from peenflow.fe.shots import Shots  # noqa: E402

R, RHO = 0.29e-3, 7800.0
MAT = Material(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234, C=0.0134, m=0.0)
#: per-shot fields of the result, as named on main 88837bb (their order there is irrelevant here)
FIELDS = ("shot_index", "hit", "t_contact", "t_separate", "contact_duration", "vin_x", "vin_y", "vin_z", "vout_x",
          "vout_y", "vout_z", "restitution", "max_approach", "max_overlap", "peak_force", "max_contact_radius",
          "steps", "energy_error", "impact_energy", "win_i0", "win_i1", "win_j0", "win_j1", "win_k0", "win_k1",
          "contact_radius", "hourglass_peak", "internal_peak", "spin_in_x", "spin_in_y", "spin_in_z",
          "spin_out_x", "spin_out_y", "spin_out_z")


def quarter():
    return Target(graded_box(0.4e-3, 0.4e-3, 40e-6, fine_half_width=0.12e-3, fine_depth=0.1e-3))


def rev(lateral, n=24):
    ax = np.linspace(-0.5 * n * 50e-6, 0.5 * n * 50e-6, n + 1)
    return Target(BoxMesh(ax, ax.copy(), graded_axis(0.15e-3, 50e-6, 0.5e-3, 1.3)), lateral=lateral)


def stream(xy, v, spin=None):
    return Shots(centres=[[x, y, -R - 2e-6] for x, y in xy], velocities=v, radius=R, density=RHO, spins=spin)


def cases():
    """name -> (target, shots, options, snapshot_after)"""
    three = stream([(0.0, 0.0), (90e-6, -60e-6), (-0.25e-3, 0.2e-3)],
                   [[0, 0, 45.0], [8.0, -3.0, 40.0], [0, 5.0, 50.0]], spin=[[0, 0, 0], [100.0, -50.0, 20.0], [0, 0, 0]])
    return {
        "quarter_record": (quarter(), stream([(0.0, 0.0)], [[0, 0, 55.0]]), Options(record=True, record_every=7), ()),
        "rev_sym_snap": (rev("symmetric"), three, Options(), (1, 2)),
        "rev_periodic": (rev("periodic", 22), stream([(0.5e-3, -0.52e-3), (0.0, 0.1e-3), (0.58e-3, 0.2e-3)],
                                                     [[0, 0, 45.0], [8.0, -3.0, 40.0], [0, 5.0, 50.0]]),
                         Options(), (2,)),
        "rev_viscous": (rev("symmetric"), three, Options(window_faces=ViscousSpringFaces()), ()),
        "rev_sponge": (rev("symmetric"), three, Options(window_sponge=0.3), ()),
        "rev_full_dynamic": (rev("symmetric", 12), stream([(20e-6, 0.0), (2e-3, 0.0)], [[0, 0, 30.0], [0, 0, 30.0]]),
                             Options(window=False, relax_method="dynamic"), ()),
        "rev_stiffness_nofinal": (rev("symmetric"), three, Options(hourglass_type="stiffness",
                                                                   final_relaxation=False), ()),
    }


def flatten(res, prefix, out):
    out[f"{prefix}stress"] = res.stress
    out[f"{prefix}eps_p"] = res.eps_p
    out[f"{prefix}displacement"] = res.displacement
    for k in FIELDS:
        out[f"{prefix}shots.{k}"] = np.asarray(res.shots[k], float)
    for n, s in res.snapshots.items():
        out[f"{prefix}snap{n}.stress"] = s.stress
        out[f"{prefix}snap{n}.eps_p"] = s.eps_p
        out[f"{prefix}snap{n}.displacement"] = s.displacement
    for j, h in enumerate(res.histories):
        for k, v in h.items():
            out[f"{prefix}hist{j}.{k}"] = np.asarray(v, float)
    for k, v in res.energy.items():
        out[f"{prefix}energy.{k}"] = np.asarray(v, float)
    out[f"{prefix}hourglass_ratio"] = np.asarray(res.hourglass_ratio)
    out[f"{prefix}energy_error"] = np.asarray(res.energy_error)
    st = res.final_state
    for k in ("x", "v", "f", "stress", "eps_p", "sy_static", "hg", "temp", "energy", "ctl", "shot_index"):
        out[f"{prefix}final.{k}"] = np.asarray(getattr(st, k))
    out[f"{prefix}window_note"] = np.asarray(res.window_outside_validated)


def golden(only=()) -> dict:
    """The outputs, BLAS pinned to one thread as the engine pins it (the multigrid's coarsest solve is a
    BLAS product whose last bits depend on its thread count)."""
    out = {}
    with warnings.catch_warnings(), threadpool_limits(limits=1, user_api="blas"):
        warnings.simplefilter("ignore", WindowValidityWarning)
        for name, (t, sh, opt, snaps) in cases().items():
            if only and name not in only:
                continue
            saved = {}

            def keep(i, exporter):
                if i == 0:
                    saved["state"] = exporter()

            t0 = time.process_time()
            res = run_impacts(t, MAT, sh, opt, snapshot_after=snaps, on_shot_done=keep)
            print(name, f"{time.process_time() - t0:.1f} s CPU", file=sys.stderr, flush=True)
            flatten(res, f"{name}/", out)
            if len(sh) > 1:  # resumed after the first shot
                flatten(run_impacts(t, MAT, sh, opt, state=saved["state"], snapshot_after=snaps),
                        f"{name}/resumed/", out)
    return out


def digest(a: np.ndarray) -> dict:
    """What is kept of an output: the SHA-256 of its bytes (bit for bit), its dtype kind and shape, and its
    sum (to see how far off a changed output is)."""
    a = np.ascontiguousarray(a)
    total = float(np.sum(a, dtype=float)) if a.dtype.kind in "fiub" else None
    return {"sha256": hashlib.sha256(a.tobytes()).hexdigest(), "shape": list(a.shape), "sum": total}


def blas_coretypes() -> set[str]:
    """The kernel sets ('architecture') of the OpenBLAS libraries loaded in this process."""
    return {str(i.get("architecture")) for i in threadpool_info() if i.get("internal_api") == "openblas"}


if __name__ == "__main__":
    cores = blas_coretypes()
    if cores != {BLAS_CORETYPE}:
        raise SystemExit(f"OpenBLAS kernels {sorted(cores)}, not {BLAS_CORETYPE}: digests would not be comparable")
    if sys.argv[1:2] == ["--print"]:  # stdout is the digests alone (golden() reports on stderr)
        print(json.dumps({k: digest(v) for k, v in golden().items()}, sort_keys=True))
    else:
        path = Path(__file__).with_name("driver_golden.json")
        out = {k: digest(v) for k, v in golden(sys.argv[1:]).items()}
        path.write_text(json.dumps(out, indent=0, sort_keys=True) + "\n")
        print(f"wrote {path} ({len(out)} outputs)")
