"""The kernel's node contact against a mortar (weighted-gap) contact on the single impacts of
``bench_hourglass.py`` (issue 13 §1: where the 25 um normal dents' elastic recovery error comes from).

Both through the same driver (:mod:`benchmarks.bbar.driver`: the kernel's one-point physical element, mesh,
shot, boundary conditions and settle of ``bench_hourglass.run``, dynamic final relaxation), the contact
chosen by ``contact``: ``"node"`` (the kernel's :func:`peenflow.fe.contact.contact_kinematic`) or
``"mortar"`` (:mod:`benchmarks.bbar.contact_mortar`). Results and conclusion: BENCHMARKS.md 4c,
"Mortar contact".

Usage (from the repository root, one thread)::

    PYTHONPATH=. python benchmarks/bench_contact.py run CASE CONTACT H_UM   # one run, stored
    PYTHONPATH=. python benchmarks/bench_contact.py all H_UM [H_UM ...]    # every case and contact not stored yet
    PYTHONPATH=. python benchmarks/bench_contact.py table                   # the table, from the store only

Runs are stored in ``benchmarks/bbar/contact.json``; errors are against ``bench_hourglass.reference`` (the
kernel's 6.25 um node-contact runs, Richardson-extrapolated per quantity where that function says so).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import bench_hourglass as bh  # noqa: E402

STORE = HERE / "bbar" / "contact.json"
CONTACTS = ("node", "mortar")


def _load() -> dict:
    return json.loads(STORE.read_text()) if STORE.exists() else {}


def _key(case: str, contact: str, h: float) -> str:
    return f"{case}/{contact}/{h:g}"


def run_one(case: str, contact: str, h: float) -> dict:
    from benchmarks.bbar.driver import run

    out = run(case, "physical", h, contact=contact)
    out["command"] = f"PYTHONPATH=. python benchmarks/bench_contact.py run {case} {contact} {h:g}"
    data = _load()
    data[_key(case, contact, h)] = out
    STORE.write_text(json.dumps(data, indent=1, sort_keys=True))
    return out


def table() -> None:
    """Per case and element size: the errors of both contacts against the reference, the shot's largest
    approach and the elastic recovery (approach - residual dent, um; the reference's from its stored
    approach where it has one), the Hertz-equivalent contact radius at peak force (um), CPU s."""
    data, kernel = _load(), bh._load()
    print("| case | contact | h um | " + " | ".join(q[1] for q in bh.QUANTITIES) +
          " | profile RMS | approach um | recovery um | contact radius um | energy error | CPU s |")
    print("|---|---|---|" + "---|" * (len(bh.QUANTITIES) + 6))
    for case in bh.CASES:
        ref, _ = bh.reference(kernel, case)
        for h in (50.0, 25.0, 12.5, 6.25):
            for contact in CONTACTS:
                v = data.get(_key(case, contact, h))
                if v is None:
                    continue
                print(f"| {case} | {contact} | {h:g} | " + " | ".join(bh.error_cells(v, ref)) +
                      f" | {100 * bh.profile_rms(v, ref):.1f} % | {v['max_approach_um']:.2f} | "
                      f"{v['max_approach_um'] - v['dent_um']:.2f} | {v['contact_radius_um']:.1f} | "
                      f"{v['energy_error']:.4f} | {v['cpu_s']:.1f} |")
    print("\n#### Largest |error| over the four cases\n")
    print("| contact | h um | " + " | ".join(q[1] for q in bh.QUANTITIES) + " | profile RMS |")
    print("|---|---|" + "---|" * (len(bh.QUANTITIES) + 1))
    refs = {case: bh.reference(kernel, case)[0] for case in bh.CASES}
    for contact in CONTACTS:
        for h in (50.0, 25.0, 12.5):
            runs = [(data.get(_key(c, contact, h)), refs[c]) for c in bh.CASES]
            if any(v is None for v, _ in runs):
                continue
            cells, rms = bh.worst_cells(runs)
            print(f"| {contact} | {h:g} | " + " | ".join(cells) + f" | {100 * rms:.1f} % |")


if __name__ == "__main__":
    cmd = sys.argv[1] if len(sys.argv) > 1 else "table"
    if cmd == "run":
        o = run_one(sys.argv[2], sys.argv[3], float(sys.argv[4]))
        print(json.dumps({k: v for k, v in o.items() if not isinstance(v, list)}, indent=1))
    elif cmd == "all":
        for h in (float(a) for a in sys.argv[2:]):
            for case in bh.CASES:
                for contact in CONTACTS:
                    if _key(case, contact, h) not in _load():
                        o = run_one(case, contact, h)
                        print(f"{case} {contact} {h:g}: dent {o['dent_um']:.3f} um, CPU {o['cpu_s']:.1f} s",
                              flush=True)
    else:
        table()
