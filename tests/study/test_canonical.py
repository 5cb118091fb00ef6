"""The canonical dict: same study -> same dict, whatever the spelling."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from peenflow.study import canonical, load_study

DELETE = "__delete__"
REPO = Path(__file__).resolve().parents[2]


def test_same_study_same_dict(write_study):
    a = load_study(write_study())
    b = load_study(write_study())
    assert a.to_canonical_dict() == b.to_canonical_dict()
    assert a.digest() == b.digest()
    json.dumps(a.to_canonical_dict())  # JSON-able


def test_key_order_in_the_file_does_not_matter(tmp_path):
    one = tmp_path / "one.toml"
    two = tmp_path / "two.toml"
    one.write_text(
        '[study]\nname = "x"\n[shot]\ntype = "S230"\nfriction_coefficient = 0.2\n'
        '[almen]\nstrip = "A"\nangles_deg = [45, 90]\nvelocities_m_s = [25, 55]\nshot_counts = [10, 20, 40]\n'
    )
    two.write_text(
        '[almen]\nshot_counts = [10, 20, 40]\nvelocities_m_s = [55.0, 25.0]\nangles_deg = [90.0, 45.0]\n'
        'strip = "A"\n[shot]\nfriction_coefficient = 0.2\ntype = "S230"\n[study]\nname = "y"\n'
    )
    assert load_study(one).to_canonical_dict() == load_study(two).to_canonical_dict()


def test_float_spelling_does_not_matter(write_study):
    a = load_study(write_study({"shot.friction_coefficient": 0.1, "target.thickness_mm": 9.5}))
    b = load_study(write_study({"shot.friction_coefficient": 0.10000000000000001, "target.thickness_mm": 9.500000000000002}))
    c = load_study(write_study({"shot.friction_coefficient": 0.1, "target.thickness_mm": 9.6}))
    assert a.to_canonical_dict() == b.to_canonical_dict() != c.to_canonical_dict()
    assert canonical({"x": -0.0, "y": (1, 2.0)}) == {"x": 0.0, "y": [1, 2.0]}


def test_intensity_notations_agree(write_study):
    shop = load_study(write_study({"target.almen_intensity": "12A"}))
    inch = load_study(write_study({"target.almen_intensity": "0.012 inA"}))
    mm = load_study(write_study({"target.almen_intensity": DELETE, "target.almen_intensity_mm": 0.3048,
                                 "target.almen_strip": "A"}))
    assert shop.target.intensity_mm == pytest.approx(0.3048)
    assert shop.to_canonical_dict() == inch.to_canonical_dict() == mm.to_canonical_dict()


def test_cosmetic_and_execution_keys_are_not_in_the_dict(write_study):
    a = load_study(write_study())
    b = load_study(write_study({"study.name": "renamed", "study.description": "other words",
                                "execution": {"workers": 4, "threads_per_worker": 2}}))
    assert a.to_canonical_dict() == b.to_canonical_dict()
    assert "description" not in json.dumps(a.to_canonical_dict())


def test_fidelity_values_not_preset_names_count(write_study):
    from peenflow.study import FIDELITY_PRESETS

    paper = load_study(write_study({"fidelity": {"preset": "paper"}}))
    spelled = load_study(write_study({"fidelity": {"preset": "standard", **FIDELITY_PRESETS["paper"]}}))
    assert paper.to_canonical_dict() == spelled.to_canonical_dict()
    assert spelled.fidelity.describe().startswith("standard + ")
    assert paper.fidelity.describe() == "paper"
    finer = load_study(write_study({"fidelity": {"preset": "paper", "element_size_um": 20.0}}))
    assert finer.to_canonical_dict()["fidelity"]["element_size_um"] == 20.0
    assert finer.to_canonical_dict() != paper.to_canonical_dict()


def test_measured_profile_enters_by_content(write_study, tmp_path):
    (tmp_path / "p.csv").write_text("depth_mm,stress_MPa,component\n0.1,-300,xx\n")
    a = load_study(write_study({"target.measured_profile_csv": "p.csv"}))
    digest = a.to_canonical_dict()["target"]["measured_profile_sha256"]
    assert len(digest) == 64
    (tmp_path / "p.csv").write_text("depth_mm,stress_MPa,component\n0.1,-310,xx\n")
    assert load_study(write_study({"target.measured_profile_csv": "p.csv"})).to_canonical_dict() != a.to_canonical_dict()


def test_digest_is_the_same_in_another_process():
    study = REPO / "studies" / "paper_al7075.toml"
    code = "import sys; from peenflow.study import load_study; print(load_study(sys.argv[1]).digest())"
    env = {**os.environ, "PYTHONHASHSEED": "12345", "PYTHONPATH": str(REPO)}
    out = subprocess.run([sys.executable, "-c", code, str(study)], capture_output=True, text=True, env=env, check=True)
    assert out.stdout.strip() == load_study(study).digest()
