"""A task's code fingerprint follows the modules of its own package that it
imports (issue 9 item 3): an edit to a helper module flags exactly the results
of the tasks that import it, directly or through another module."""

import importlib
import sys
import textwrap

import pytest

from peenflow.engine.fingerprint import clear_fingerprint_cache, local_imports

MODULES = {
    "__init__.py": '"""Stages."""\n',
    "_helper.py": "def flow_stress(eps):\n    return 1408e6 + 600.8e6 * eps ** 0.234\n",
    "_deep.py": "SCALE = 2.0\n",
    "_mid.py": "from ._deep import SCALE\n\ndef scaled(x):\n    return SCALE * x\n",
    "stage_a.py": """
        from peenflow.engine import task
        from ._helper import flow_stress

        @task(version="1")
        def stage_a(*, eps: float):
            return flow_stress(eps)
    """,
    "stage_b.py": """
        import math
        from peenflow.engine import task

        @task(version="1")
        def stage_b(*, x: float):
            return math.sqrt(x)
    """,
    "stage_c.py": """
        from peenflow.engine import task
        from . import _mid
        from .stage_a import stage_a

        @task(version="1")
        def stage_c(*, x: float):
            return _mid.scaled(x)
    """,
}


@pytest.fixture()
def stages(tmp_path, monkeypatch):
    pkg = tmp_path / "fpstages"
    pkg.mkdir()
    for name, text in MODULES.items():
        (pkg / name).write_text(textwrap.dedent(text))
    monkeypatch.syspath_prepend(str(tmp_path))
    clear_fingerprint_cache()

    def load():
        for m in [m for m in sys.modules if m == "fpstages" or m.startswith("fpstages.")]:
            del sys.modules[m]
        importlib.invalidate_caches()
        clear_fingerprint_cache()
        return {n: getattr(importlib.import_module(f"fpstages.{n}"), n) for n in ("stage_a", "stage_b", "stage_c")}

    yield pkg, load
    for m in [m for m in sys.modules if m == "fpstages" or m.startswith("fpstages.")]:
        del sys.modules[m]
    clear_fingerprint_cache()


def _hashes(tasks):
    return {n: t.source_hash() for n, t in tasks.items()}


def test_import_closure_is_transitive_and_stays_inside_the_package(stages):
    _, load = stages
    load()
    assert local_imports("fpstages.stage_a") == ("fpstages._helper",)
    assert local_imports("fpstages.stage_b") == ()
    # through _mid to _deep, and through stage_a to _helper; the package
    # __init__ is not a dependency of ``from . import _mid``
    assert local_imports("fpstages.stage_c") == ("fpstages._deep", "fpstages._helper", "fpstages._mid",
                                                 "fpstages.stage_a")


@pytest.mark.parametrize("module, edit, changed", [
    ("_helper.py", ("0.234", "0.235"), {"stage_a", "stage_c"}),
    ("_deep.py", ("2.0", "3.0"), {"stage_c"}),
    ("stage_b.py", ("math.sqrt(x)", "math.sqrt(2 * x)"), {"stage_b"}),
])
def test_an_edit_flags_exactly_the_dependent_tasks(stages, module, edit, changed):
    pkg, load = stages
    before = _hashes(load())
    path = pkg / module
    path.write_text(path.read_text().replace(*edit))
    after = _hashes(load())
    assert {n for n in before if before[n] != after[n]} == changed


def test_cosmetic_edit_of_a_helper_changes_nothing(stages):
    pkg, load = stages
    before = _hashes(load())
    path = pkg / "_helper.py"
    path.write_text('"""Johnson-Cook flow stress."""\n# eq. (1)\n' + path.read_text())
    assert _hashes(load()) == before


def test_the_shipped_stages_see_their_helpers():
    # the defects the issue found: _rev_run is the body of strip_runs and
    # target_runs, _kernel the translation every kernel-calling stage uses
    for stage in ("tasks.strip_runs", "tasks.target_runs"):
        assert {"tasks._rev_run", "tasks._kernel"} <= set(local_imports(stage))
    assert "tasks._rev_run" not in local_imports("tasks.single_impact")
    assert "tasks._kernel" in local_imports("tasks.single_impact")
