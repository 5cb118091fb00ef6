"""Everything a result depends on is inside its task's code fingerprint, and nothing else is.

An edit to a module (simulated by changing that file's fingerprint) must mark
exactly the results that depend on it as made by other code: the kernel's
compile settings (``peenflow._jit``, imported by the kernel package, not by the
stages) and the REV mesh rule (``peenflow.fe.mesh``) reach every stage, the
declared outputs every stage, and the checks made before compute
(``tasks.preflight``, ``peenflow.study.bounds``), which refuse a study but change
no result, none.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import peenflow.engine.fingerprint as fp
import tasks.pipeline  # noqa: F401 - every stage module
from peenflow.engine.task import Task


def _stage_tasks() -> dict[str, Task]:
    import tasks as pkg

    found = {}
    for f in Path(pkg.__file__).parent.glob("*.py"):
        module = __import__(f"tasks.{f.stem}", fromlist=["_"])
        found.update({t.name: t for t in vars(module).values() if isinstance(t, Task)})
    return found


ALL = {"arc_height", "control_curve", "coverage_curve", "dmin", "indentation", "intensity_extrapolation",
       "process_map", "residual_profile", "rev_size", "rev_thickness", "saturation", "single_impact", "strip_runs",
       "sensitivity", "suggested_settings", "target_runs", "target_velocity", "verified_settings", "verify_runs"}


@pytest.mark.parametrize("module, dependants", [
    ("peenflow._jit", ALL),
    ("peenflow.fe.mesh", ALL),
    ("tasks.outputs", ALL),
    ("tasks.preflight", set()),
    ("peenflow.study.bounds", set()),
])
def test_an_edit_marks_exactly_its_dependants(monkeypatch, module, dependants):
    stages = _stage_tasks()
    assert set(stages) == ALL
    fp.clear_fingerprint_cache()
    before = {n: t.source_hash() for n, t in stages.items()}
    edited = str(Path(__import__(module, fromlist=["_"]).__file__))
    real = fp.file_fingerprint
    monkeypatch.setattr(fp, "file_fingerprint", lambda path: "edited" if str(path) == edited else real(path))
    fp.clear_fingerprint_cache()
    try:
        after = {n: t.source_hash() for n, t in stages.items()}
    finally:
        monkeypatch.undo()
        fp.clear_fingerprint_cache()
    assert {n for n in stages if after[n] != before[n]} == dependants
