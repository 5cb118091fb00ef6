"""docs/study-files.md documents every key the schema accepts."""

from __future__ import annotations

from pathlib import Path

import pytest

from peenflow.study import Almen, Coverage, Dmin, Execution, Fidelity, Seeds, ShotSection, Target
from peenflow.study import JohnsonCook, Material, Shot, Strip

DOC = Path(__file__).resolve().parents[2] / "docs" / "study-files.md"
MODELS = [ShotSection, Almen, Dmin, Coverage, Target, Fidelity, Seeds, Execution, JohnsonCook, Material, Shot, Strip]
INTERNAL = {"overrides", "name"}  # resolved bookkeeping / registry key


@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.__name__)
def test_every_key_is_documented(model):
    text = DOC.read_text()
    missing = [k for k in model.model_fields if k not in INTERNAL and f"`{k}`" not in text and f"`johnson_cook.{k}`" not in text]
    assert not missing, f"{model.__name__}: undocumented keys {missing}"


def test_the_readme_study_example_is_a_valid_study(tmp_path):
    """The study file README.md shows is one `peenflow check` accepts (its keys and values exist)."""
    import re

    from peenflow.study import validate_study

    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    blocks = re.findall(r"```toml\n(.*?)```", readme, re.S)
    assert len(blocks) == 1, "README.md shows one study file"
    study = tmp_path / "example.toml"
    study.write_text(blocks[0])
    assert validate_study(study) == []
