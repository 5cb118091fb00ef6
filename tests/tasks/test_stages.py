"""One list of stage names (issue 9 item 5): the graph's, documented in
docs/study-files.md, taken by `show` and listed by `check`."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

import peenflow.api
from tasks.pipeline import STAGES

REPO = Path(__file__).resolve().parents[2]


def test_docs_list_exactly_the_pipeline_stages_in_order():
    text = (REPO / "docs" / "study-files.md").read_text()
    section = text[text.index("## Which stages run"):text.index("## `[study]`")]
    assert re.findall(r"^\| `([a-z_]+)` \|", section, flags=re.M) == list(STAGES)


@pytest.mark.parametrize("name", ["quickstart", "paper_almen_s230", "paper_al7075", "paper_al7075_v47",
                                  "paper_al7075_coarse", "paper_al7075_standard", "paper_fast", "paper_fast_25um",
                                  *(f"../benchmarks/reference/studies/{p.stem}"
                                    for p in sorted((REPO / "benchmarks" / "reference" / "studies").glob("*.toml")))])
def test_shipped_graphs_use_only_listed_stages_in_their_order(name):
    """Every shipped study, and every study-level reference template, builds its graph."""
    stages = peenflow.api.load_study_graph(REPO / "studies" / f"{name}.toml").stages
    order = list(STAGES)
    assert [order.index(s) for s in stages] == sorted(order.index(s) for s in stages)


def test_check_lists_and_show_takes_the_same_names():
    study = REPO / "tests" / "tasks" / "micro.toml"
    out = subprocess.run([sys.executable, "-m", "peenflow.cli", "check", str(study)], capture_output=True,
                         text=True, timeout=300, check=True).stdout
    listed = re.findall(r"^  ([a-z_]+): \d+", out, flags=re.M)
    assert listed and set(listed) <= set(STAGES)
    bad = subprocess.run([sys.executable, "-m", "peenflow.cli", "show", str(study), "control_curves"],
                         capture_output=True, text=True, timeout=300)
    assert bad.returncode != 0 and "Traceback" not in bad.stderr
    assert "no stage 'control_curves'" in bad.stderr and ", ".join(listed) in bad.stderr
