"""The driver's outputs, bit for bit, against digests written on main 88837bb before it was split into
small steps (``tests/fe/data/make_driver_golden.py``): windowed quarter model with histories, REV with
snapshots, periodic REV with rolls across the seam, viscous-spring faces, sponge, full mesh with dynamic
relaxation and a missed shot, stiffness hourglass without final relaxation; each run also resumed from
the checkpoint after its first shot. The OpenBLAS kernel set is pinned (tests/fe/data/make_driver_golden.py)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"
SCRIPT = DATA / "make_driver_golden.py"


@pytest.fixture(scope="module")
def outputs():
    """Digests of every output, computed in a subprocess: the OpenBLAS kernel set (which sets the last
    bits of the multigrid's LAPACK / BLAS steps) is pinned there before numpy loads (the script's
    docstring)."""
    run = subprocess.run([sys.executable, str(SCRIPT), "--print"], capture_output=True, text=True,
                         cwd=Path(__file__).resolve().parents[2])
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout)


def test_every_output_is_bit_identical_to_the_base_driver(outputs):
    want = json.loads((DATA / "driver_golden.json").read_text())
    assert sorted(outputs) == sorted(want)  # the same outputs (snapshots, histories, shot fields, ...)
    changed = {k: (want[k]["sum"], outputs[k]["sum"]) for k in outputs if outputs[k] != want[k]}
    assert not changed, f"{len(changed)} outputs differ from the base driver (old sum, new sum): {changed}"
