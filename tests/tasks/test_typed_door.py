"""The one door in: the stage graph is built from the typed parameters alone.

``tasks.pipeline.build_graph`` reads the study file once into
:class:`tasks.params.StudyParams`; everything after that (``graph_for`` and its
helpers) sees only those parameters.  Checked twice: by reading the module's
source (no function but ``build_graph`` names the study or its loader), and by
building the graph from the parameters alone and comparing it with the file's.
"""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import pytest

import tasks.pipeline as pipeline
from peenflow.engine.canonical import canonical_json
from peenflow.study import load_study
from tasks.params import study_params

HERE = Path(__file__).parent
STUDIES = [HERE / "micro.toml", HERE / "micro_extrapolated.toml", HERE / "micro_dent.toml"]


def test_only_build_graph_reads_the_study():
    tree = ast.parse(inspect.getsource(pipeline))
    readers = {}
    for fn in ast.walk(tree):
        if isinstance(fn, ast.FunctionDef):
            names = {n.id for n in ast.walk(fn) if isinstance(n, ast.Name)}
            if names & {"study", "load_study"}:
                readers[fn.name] = sorted(names & {"study", "load_study"})
    assert readers == {"build_graph": ["load_study"]}
    build = next(f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and f.name == "build_graph")
    body = [s for s in build.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]
    assert ast.unparse(body[0]) == "return graph_for(study_params(load_study(path)))"


def _points(graph) -> list[tuple]:
    return [(n.stage, n.label, canonical_json(n.params), sorted(u.node_id for u in n.upstream_nodes()))
            for n in graph.nodes]


@pytest.mark.parametrize("path", STUDIES, ids=lambda p: p.stem)
def test_graph_from_parameters_alone(path):
    p = study_params(load_study(path))
    from_file = pipeline.build_graph(path)
    from_params = pipeline.graph_for(p)
    assert _points(from_params) == _points(from_file)
    assert from_params.result_attrs == from_file.result_attrs
    assert from_params.stage_result_attrs == from_file.stage_result_attrs
    assert len(from_file.nodes) > 5
