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
    assert readers == {"build_graph": ["load_study", "study"]}
    build = next(f for f in ast.walk(tree) if isinstance(f, ast.FunctionDef) and f.name == "build_graph")
    body = [s for s in build.body if not (isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant))]
    # read, translate, check against the kernel's limits (before any compute), build from the parameters
    assert [ast.unparse(s) for s in body] == [
        "study = load_study(path)", "family = study_family(study)",
        "for (_, variant), (_, p) in zip(study.variants, family.points):\n    check_before_compute(variant, p)",
        "return graph_for_family(family)"]


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


# -- the one door out: declared outputs ------------------------------------------------------------------
def test_every_stored_result_is_its_stage_declaration(micro):
    """Each result of the micro study holds exactly what its task declares (names, dims, units), so a
    stage downstream that reads a declared output reads what was written."""
    import xarray as xr

    import tasks.pipeline  # noqa: F401 - imports every stage, which registers its declaration
    from tasks.outputs import DECLARED

    files = sorted((micro.parent / ".peenflow" / "results").glob("*/*.nc"))
    seen = set()
    for f in files:
        with xr.open_dataset(f) as ds:
            task = ds.attrs["peenflow_task"]
            point = ds.attrs["peenflow_point"]  # "stage[dim=value,...]" or "stage"
            point_dims = [kv.split("=")[0] for kv in point.partition("[")[2].rstrip("]").split(",") if kv]
            assert task in DECLARED, f"{task} declares no outputs"
            assert DECLARED[task].problems(ds, point_dims) == [], f.name
            seen.add(task)
    assert {"single_impact", "strip_runs", "target_runs", "residual_profile", "saturation"} <= seen


def test_a_declaration_refuses_what_it_does_not_declare():
    import numpy as np

    from tasks.outputs import Output, Outputs

    out = Outputs("test_declaration", depth_m=Output(("layer",), "m", "a depth"),
                  note=Output((), "1", "an optional count", optional=True))
    ds = out.dataset({"depth_m": np.array([1e-4, 2e-4])})
    assert ds.depth_m.attrs == {"long_name": "a depth", "units": "m"}
    np.testing.assert_array_equal(out.depth_m.read(ds), [1e-4, 2e-4])
    with pytest.raises(KeyError, match="not declared"):
        out.dataset({"depth_m": np.zeros(2), "depth_mm": np.zeros(2)})
    with pytest.raises(KeyError, match="not given"):
        out.dataset({"note": 1})
    with pytest.raises(ValueError, match="declared with dims"):
        out.dataset({"depth_m": 1.0})
    with pytest.raises(AttributeError, match="declares no output 'depth_mm'"):
        out.depth_mm
    ds.depth_m.attrs["units"] = "mm"
    with pytest.raises(ValueError, match="declared 'm'"):
        out.depth_m.read(ds)
    assert out.problems(ds) == ["depth_m: units 'mm', declared 'm'"]
