"""The driver's outputs, bit for bit, against digests written on main 88837bb before it was split into
small steps (``tests/fe/data/make_driver_golden.py``): windowed quarter model with histories, REV with
snapshots, periodic REV with rolls across the seam, viscous-spring faces, sponge, full mesh with dynamic
relaxation and a missed shot, stiffness hourglass without final relaxation; each run also resumed from
the checkpoint after its first shot."""

import importlib.util
import json
from pathlib import Path

import pytest

DATA = Path(__file__).parent / "data"
_spec = importlib.util.spec_from_file_location("make_driver_golden", DATA / "make_driver_golden.py")
gen = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(gen)


@pytest.fixture(scope="module")
def outputs():
    return gen.golden()


def test_every_output_is_bit_identical_to_the_base_driver(outputs):
    want = json.loads((DATA / "driver_golden.json").read_text())
    assert sorted(outputs) == sorted(want)  # the same outputs (snapshots, histories, shot fields, ...)
    changed = {k: (want[k]["sum"], gen.digest(v)["sum"]) for k, v in outputs.items() if gen.digest(v) != want[k]}
    assert not changed, f"{len(changed)} outputs differ from the base driver (old sum, new sum): {changed}"
