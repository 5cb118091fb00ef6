"""Typed task parameters: an object with ``__canonical__`` enters the key as that form and reaches the
task rebuilt from it by the class its annotation names (``X`` or ``X | None``)."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from peenflow.engine import task
from peenflow.engine.canonical import ParameterError, canonical_json, canonical_value


@dataclass(frozen=True)
class Box:
    width_m: float
    name: str

    def __canonical__(self):
        return {"width_m": self.width_m, "name": self.name}

    @classmethod
    def from_canonical(cls, value):
        return cls(**value)


@task(version="1")
def measure(*, box: Box, spare: Box | None = None, scale: float = 1.0):
    return box, spare, scale


def test_a_typed_parameter_is_keyed_by_its_canonical_form():
    assert canonical_value({"box": Box(0.1 + 0.2, "a")}) == {"box": {"name": "a", "width_m": 0.3}}
    assert canonical_json(Box(1e-3, "a")) != canonical_json(Box(2e-3, "a"))


def test_the_task_receives_the_objects_rebuilt_from_the_key():
    params = canonical_value({"box": Box(1e-3, "a"), "spare": None, "scale": 2.0})
    kwargs = measure.bind(params)
    assert kwargs == {"box": Box(1e-3, "a"), "spare": None, "scale": 2}
    assert measure.bind(canonical_value({"box": Box(1e-3, "a"), "spare": Box(2e-3, "b")}))["spare"] == Box(2e-3, "b")


def test_an_object_without_a_canonical_form_is_still_refused():
    class Opaque:
        pass

    with pytest.raises(ParameterError, match="params.x"):
        canonical_value({"x": Opaque()})
