"""The validation package (peenflow/validation): the kernel, the engine, the methods and the stages never
import it, and a stored run is kept whole in the full records and summarised, as measured, in the summary
the tests and tables read."""

import ast
from pathlib import Path

from peenflow.validation import runs

REPO = Path(__file__).resolve().parents[1]


def _imports(path: Path) -> set[str]:
    names = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names |= {node.module} | {f"{node.module}.{a.name}" for a in node.names}
    return names


def test_the_kernel_engine_methods_and_stages_never_import_it():
    files = [p for d in ("peenflow/fe", "peenflow/engine", "peenflow/methods", "tasks")
             for p in sorted((REPO / d).rglob("*.py"))]
    assert len(files) > 40
    offenders = {str(p.relative_to(REPO)): sorted(n for n in _imports(p) if n.startswith("peenflow.validation"))
                 for p in files}
    assert not {p: n for p, n in offenders.items() if n}


def test_a_run_is_recorded_whole_and_summarised_as_measured(tmp_path, monkeypatch):
    monkeypatch.setattr(runs, "DATA", tmp_path / "data")
    (tmp_path / "data").mkdir()
    line = dict(surface_x_mm=[0.0, 0.00625, 0.0125], surface_uz_um=[12.345678901234567, 11.0, -0.1])
    fine = dict(dent_um=12.345678901234567, profile_z_mm=[0.003125, 0.009375], profile_mpa=[-512.3, -700.1],
                map_x0_mm=[0.0], map_x1_mm=[0.00625], map_z_mm=[0.003125], map_mpa=[[-512.3]],
                command="python benchmarks/single_impact.py run sae-25-90 physical 6.25", **line)
    coarse = dict(fine, dent_um=11.9, command="python benchmarks/single_impact.py run sae-25-90 physical 25")
    runs.record(tmp_path, "single_impact", "sae-25-90/physical/6.25", fine)
    runs.record(tmp_path, "single_impact", "sae-25-90/physical/25", coarse)

    full = runs.load_records(tmp_path, "single_impact")
    assert full == {"sae-25-90/physical/6.25": fine, "sae-25-90/physical/25": coarse}
    summary = runs.load("single_impact")
    # the 6.25 um run keeps its surface line (the references and the readings' limits are read on it), the
    # 25 um run does not; neither keeps its sigma_xx map or command; every kept value is the measured one
    assert summary["sae-25-90/physical/6.25"] == {k: v for k, v in fine.items()
                                                  if not k.startswith("map_") and k != "command"}
    assert summary["sae-25-90/physical/25"] == {k: v for k, v in coarse.items()
                                                if not k.startswith(("map_", "surface_")) and k != "command"}
    # one run per line: a new run is a one-line change of the file
    text = runs.path("single_impact").read_text()
    assert sum(row.startswith('"sae-25-90/physical/') for row in text.splitlines()) == 2
