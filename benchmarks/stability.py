"""Numerical stability stress test: does every impact either finish with a closed energy balance or stop with a named cause?

Sweeps shot speed x element size x time-step safety factor x hourglass
coefficient for one S230 shot on SAE 1070 (Johnson-Cook with the rate term),
normal incidence, default window, quarter-free box 1.2 x 1.2 x 0.6 mm with a
uniform fine zone. For every case it prints the outcome: finished (energy
balance error, dent depth, restitution, hourglass / internal energy) or the
KernelInstabilityError's status; and then the worst energy error among the
cases that finished. A finished case with an energy error of more than a
few % would be a silent bad result: the table shows whether there is one.

    python benchmarks/stability.py            # full sweep (~5 min on one core)
    python benchmarks/stability.py quick      # 18 cases (1, 55, 200 m/s)
    python benchmarks/stability.py slow       # 1, 2, 5 m/s, SAE 1070 and Al 7075, 100-25 um
    python benchmarks/stability.py dense      # long sequences at the largest allowed coverage on the
                                              # micro REV (item 11)

Every case runs with the kernel's window minimum (``Options.window_min_elements``,
``window_min_wave``).
"""

from __future__ import annotations

import argparse
import itertools
import time

from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import graded_box
from peenflow.fe.model import Target
from peenflow.fe.safety import KernelInstabilityError, status_label
from peenflow.fe.shots import Shots
from peenflow.validation.kernel_cases import R, SAE1070, loadavg



def one(speed, h, dt_safety, hourglass, mat):
    fine = max(0.15e-3, 4 * h)
    t = Target(graded_box(0.6e-3, 0.6e-3, h, fine_half_width=fine, fine_depth=max(0.1e-3, 3 * h)))
    shots = Shots(centres=[[0.0, 0.0, -R - 1e-6]], velocities=[[0.0, 0.0, speed]], radius=R, density=7800.0)
    t0 = time.perf_counter()
    try:
        res = run_impacts(t, mat, shots, Options(dt_safety=dt_safety, hourglass=hourglass))
    except KernelInstabilityError as err:
        return dict(ok=False, status=status_label(err.status), wall=time.perf_counter() - t0)
    nnx, nny, _ = t.mesh.shape_nodes
    return dict(ok=True, err=res.energy_error, dent=res.displacement[: nnx * nny, 2].max(),
                e=res.shots["restitution"][0], hg=res.hourglass_ratio, wall=time.perf_counter() - t0)


def dense(n_full: int = 59) -> None:
    """The micro study's target REV (Al 7075-T73, 45 m/s, 1.2 mm, 100 um) at 1000 % coverage
    (10 x its N_f = 59 shots), three seeds; and the 10 000 % case that ran away (issue 12)."""
    from pathlib import Path

    from peenflow.fe.safety import KernelInstabilityError as KIE
    from peenflow.study import load_study
    from tasks._rev_run import run_rev
    from tasks.params import study_params

    s = load_study(Path(__file__).resolve().parents[1] / "tests" / "tasks" / "micro.toml")
    p = study_params(s)
    shot, fid, mat = p.shot, p.fidelity, p.target_material
    print(f"# dense sequences on the micro target REV, N_f = {n_full}; loadavg {loadavg()}")
    print("| coverage % | shots | seed | outcome | largest energy error | mean | largest hourglass peak | wall s |")
    print("|---|---|---|---|---|---|---|---|")
    for pct, seeds in ((1000, (1, 2, 3)), (10000, (1,))):
        n = int(round(n_full * pct / 100))
        for seed in seeds:
            t0 = time.perf_counter()
            try:
                ds = run_rev(None, material=mat, shot=shot, fidelity=fid, side_m=1.2e-3, measure_side_m=0.4e-3,
                             thickness_m=1e-3, angle_deg=90.0, velocity_m_s=45.0, seed=seed, ladder=[n])
                e = ds.energy_error.values
                print(f"| {pct} | {n} | {seed} | finished | {e.max():.4f} | {e.mean():.4f} | "
                      f"{ds.hourglass_peak.values.max():.2f} | {time.perf_counter() - t0:.0f} |", flush=True)
            except KIE as err:
                print(f"| {pct} | {n} | {seed} | stopped at shot {err.shot_index}: {status_label(err.status)} | | | | "
                      f"{time.perf_counter() - t0:.0f} |", flush=True)


def main(quick: bool) -> None:
    mat = Material(**SAE1070)
    if quick:
        grid = list(itertools.product((1.0, 55.0, 200.0), (50e-6, 25e-6), (0.5, 0.9, 1.0), (0.05,)))
    else:
        grid = list(itertools.product((1.0, 2.0, 5.0, 25.0, 55.0, 100.0, 200.0, 400.0), (100e-6, 50e-6, 25e-6),
                                      (0.5, 0.9, 1.0),
                                      (0.02, 0.05, 0.15)))
    one(55.0, 100e-6, 0.9, 0.05, mat)  # JIT warm-up
    print(f"# stability sweep, {len(grid)} cases; loadavg {loadavg()}")
    print("| v m/s | h um | dt_safety | Q_hg | outcome | energy error | dent um | restitution | hourglass / internal | wall s |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    worst = 0.0
    raised = 0
    for speed, h, safety, q in grid:
        r = one(speed, h, safety, q, mat)
        if r["ok"]:
            worst = max(worst, r["err"])
            print(f"| {speed:g} | {h*1e6:g} | {safety:g} | {q:g} | finished | {r['err']:.4f} | {r['dent']*1e6:.2f} | "
                  f"{r['e']:.3f} | {r['hg']:.3f} | {r['wall']:.1f} |", flush=True)
        else:
            raised += 1
            print(f"| {speed:g} | {h*1e6:g} | {safety:g} | {q:g} | stopped: {r['status']} | | | | | {r['wall']:.1f} |",
                  flush=True)
    print(f"# {len(grid) - raised} finished (largest energy error {worst:.4f} of the impact energy), "
          f"{raised} stopped with a named cause; loadavg {loadavg()}")


AL7075 = dict(E=71e9, nu=0.33, density=2810.0, A=434e6, B=303.58e6, n=0.39)


def slow() -> None:
    """The low-speed end: 1, 2, 5 m/s on SAE 1070 and Al 7075-T73, 100 / 60 / 50 / 25 um, defaults otherwise.

    At 1 m/s on 60 um the window sized in contact radii alone was 2 x 2 x 1
    elements, and a box one element thick gets no stable step from the element
    pass ("NaN or Inf"); the window minimum (Options.window_min_elements /
    window_min_wave) keeps it >= 3 elements and >= 0.05 c_p t_c."""
    import warnings

    from peenflow.fe.impact import WindowValidityWarning

    warnings.simplefilter("ignore", WindowValidityWarning)
    one(55.0, 100e-6, 0.9, 0.05, Material(**SAE1070))  # JIT warm-up
    print(f"# low-speed sweep; loadavg {loadavg()}")
    print("| material | v m/s | h um | outcome | energy error | dent um | restitution | hourglass / internal (peaks) | wall s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, props in (("SAE 1070", SAE1070), ("Al 7075-T73", AL7075)):
        mat = Material(**props)
        for speed, h in itertools.product((1.0, 2.0, 5.0), (100e-6, 60e-6, 50e-6, 25e-6)):
            r = one(speed, h, 0.9, 0.05, mat)
            if r["ok"]:
                print(f"| {name} | {speed:g} | {h*1e6:g} | finished | {r['err']:.4f} | {r['dent']*1e6:.3f} | "
                      f"{r['e']:.4f} | {r['hg']:.3f} | {r['wall']:.1f} |", flush=True)
            else:
                print(f"| {name} | {speed:g} | {h*1e6:g} | stopped: {r['status']} | | | | | {r['wall']:.1f} |", flush=True)
    print(f"# loadavg at end {loadavg()}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("mode", nargs="?", default="", choices=("", "quick", "slow", "dense"),
                    help="quick: 18 cases; slow: 1-5 m/s; dense: long sequences (default: the full sweep)")
    mode = ap.parse_args().mode
    if mode == "slow":
        slow()
    elif mode == "dense":
        dense()
    else:
        main(quick=mode == "quick")
