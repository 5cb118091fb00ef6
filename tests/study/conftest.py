"""Fixtures for study-file tests: a valid base study, written as TOML with
single keys changed, deleted or added."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any, Callable

import pytest

REPO = Path(__file__).resolve().parents[2]
STUDIES = REPO / "studies"

DELETE = "__delete__"  # marker value: remove this key (a string, so test modules can repeat it)


def base_study() -> dict:
    """A small valid study with every stage."""
    return {
        "study": {"name": "base", "description": "test study", "include": ["peenflow:library"]},
        "shot": {"type": "S230", "friction_coefficient": 0.2},
        "almen": {
            "strip": "A",
            "angles_deg": [45.0, 67.5, 90.0],
            "velocities_m_s": [25.0, 35.0, 45.0, 55.0],
            "shot_counts": [10, 20, 40, 80],
            "sequences": 2,
        },
        "dmin": {"threshold": 0.05},
        "coverage": {"grid_points": 51, "sequences": 2},
        "target": {
            "material": "Al7075-T73",
            "thickness_mm": 9.5,
            "angle_deg": 65.0,
            "almen_intensity": "12A",
            "coverage_percent": 200.0,
            "sequences": 2,
        },
        "fidelity": {"preset": "coarse"},
        "seeds": {"base": 7},
    }


def _scalar(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_scalar(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{_key(k)} = {_scalar(x)}" for k, x in v.items()) + " }"
    raise TypeError(type(v))


def _key(k: str) -> str:
    return k if k.replace("_", "").replace("-", "").isalnum() else _scalar(k)


def to_toml(data: dict) -> str:
    """Tiny TOML writer: top-level tables and one level of sub-tables."""
    lines: list[str] = []

    def table(prefix: str, tbl: dict) -> None:
        scalars = {k: v for k, v in tbl.items() if not isinstance(v, dict)}
        subs = {k: v for k, v in tbl.items() if isinstance(v, dict)}
        lines.append(f"[{prefix}]")
        lines.extend(f"{_key(k)} = {_scalar(v)}" for k, v in scalars.items())
        lines.append("")
        for k, v in subs.items():
            table(f"{prefix}.{_key(k)}", v)

    top = {k: v for k, v in data.items() if not isinstance(v, dict)}
    lines.extend(f"{_key(k)} = {_scalar(v)}" for k, v in top.items())
    for k, v in data.items():
        if isinstance(v, dict):
            table(_key(k), v)
    return "\n".join(lines) + "\n"


def set_path(data: dict, path: str, value: Any) -> None:
    keys = path.split(".")
    node = data
    for k in keys[:-1]:
        node = node.setdefault(k, {})
    if value is DELETE:
        node.pop(keys[-1], None)
    else:
        node[keys[-1]] = value


@pytest.fixture
def write_study(tmp_path: Path) -> Callable[..., Path]:
    """write_study(changes={"almen.sequences": 0}, name="study.toml", data=None) -> path."""

    def _write(changes: dict | None = None, name: str = "study.toml", data: dict | None = None) -> Path:
        d = copy.deepcopy(base_study() if data is None else data)
        for path, value in (changes or {}).items():
            set_path(d, path, value)
        p = tmp_path / name
        p.write_text(to_toml(d))
        return p

    return _write
