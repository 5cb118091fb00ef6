"""The study's folder is importable but cannot shadow an installed package (issue 9 item 4)."""

import sys

from peenflow.engine.graph import Graph
from peenflow.engine.plugin import load_graph


def test_a_tasks_module_beside_the_study_does_not_shadow_the_package(tmp_path, monkeypatch):
    (tmp_path / "tasks.py").write_text("raise ImportError('the study folder shadowed the tasks package')\n")
    (tmp_path / "beside.py").write_text(
        "import tasks\n"
        "from peenflow.engine.graph import Graph\n\n"
        "def build(path):\n"
        "    g = Graph('beside')\n"
        "    g.tasks_file = tasks.__file__\n"
        "    return g\n")
    study = tmp_path / "s.toml"
    study.write_text('[study]\nname = "s"\npipeline = "beside:build"\n')
    # import ``tasks`` afresh, as a new process would
    for name in [m for m in sys.modules if m == "tasks" or m.startswith("tasks.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setattr(sys, "meta_path", list(sys.meta_path))
    monkeypatch.delitem(sys.modules, "beside", raising=False)
    graph = load_graph(study, "tasks.pipeline:build_graph")
    assert isinstance(graph, Graph)
    assert str(tmp_path) not in graph.tasks_file  # the installed package won
    # the pipeline module beside the study was still found
    assert sys.modules["beside"].__file__.startswith(str(tmp_path))
