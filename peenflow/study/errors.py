"""Study-file problems: one clear message per problem, all reported together.

A *problem* names the key path (``almen.velocities_m_s[2]``), the bad value
and what is expected. The loader collects every problem it can find (TOML
syntax, includes, extends, unknown keys, types, physical ranges, cross-section
consistency) and raises one :class:`StudyError` listing them all. Pydantic's
own errors are translated here; users never see a pydantic traceback.
"""

from __future__ import annotations

import difflib
import typing
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable, Sequence

from pydantic import BaseModel, ValidationError

__all__ = ["Problem", "StudyError", "format_path", "format_value", "suggest", "translate"]


@dataclass(frozen=True)
class Problem:
    """One problem found in a study file (or a file it includes or extends)."""

    key: str  # key path, e.g. "almen.velocities_m_s[2]"; "" for the whole file
    message: str  # what is wrong and what is expected
    file: Path | None = None  # the file the key is in, if not the study file itself
    value: str | None = None  # the bad value as written in TOML, if there is one

    def render(self, study_file: Path | None = None) -> str:
        where = ""
        if self.file is not None and (study_file is None or Path(self.file) != Path(study_file)):
            where = f"[in {_display_file(self.file, study_file)}] "
        head = self.key + (f" = {self.value}" if self.value is not None else "")
        return f"{where}{head}: {self.message}" if head else f"{where}{self.message}"


class StudyError(ValueError):
    """A study file is invalid. ``problems`` lists every problem found."""

    def __init__(self, path: Path | str, problems: Sequence[str]):
        self.path = Path(path)
        self.problems = list(problems)
        n = len(self.problems)
        lines = [f"{self.path}: {n} problem{'s' if n != 1 else ''} in study file"]
        lines += [f"  - {p}" for p in self.problems]
        super().__init__("\n".join(lines))


def _display_file(file: Path, study_file: Path | None) -> str:
    file = Path(file)
    if study_file is not None:
        try:
            return str(file.relative_to(Path(study_file).parent))
        except ValueError:
            pass
    return str(file)


def format_path(loc: Iterable[Any]) -> str:
    """('almen', 'velocities_m_s', 2) -> 'almen.velocities_m_s[2]'."""
    out = ""
    for part in loc:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += ("." if out else "") + str(part)
    return out


def format_value(value: Any, limit: int = 80) -> str:
    """A value as the user wrote it in TOML (lists, not tuples; true/false), at most ``limit``
    characters. A long string keeps its end as well as its start: a file path's name is at its
    end (``"/long/.../nope.csv"``)."""
    text = _toml_repr(value)
    if len(text) <= limit:
        return text
    if isinstance(value, str):
        head = (limit - 3) // 3
        return text[:head] + "..." + text[len(text) - (limit - 3 - head):]
    return text[: limit - 3] + "..."


def _toml_repr(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return '"' + value.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_repr(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k} = {_toml_repr(v)}" for k, v in value.items()) + "}"
    if isinstance(value, BaseModel):
        return getattr(value, "name", type(value).__name__)
    if hasattr(value, "isoformat"):  # TOML dates and times
        return value.isoformat()
    return repr(value)


def _type_name(value: Any) -> str:
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int):
        return "integer"
    if isinstance(value, float):
        return "number"
    if isinstance(value, str):
        return "string"
    if isinstance(value, (list, tuple)):
        return "list"
    if isinstance(value, dict):
        return "table"
    return type(value).__name__


def suggest(word: str, choices: Iterable[str]) -> str:
    """' (did you mean "x"?)' for a close match among choices, else ''."""
    choices = list(choices)
    lowered = {c.lower(): c for c in choices}
    if word.lower() in lowered:
        return f'; did you mean "{lowered[word.lower()]}"?'
    # a unit suffix left off or added ("friction" for "friction_coefficient")
    prefixed = [c for c in choices if len(word) >= 4 and (c.startswith(word) or word.startswith(c))]
    if len(prefixed) == 1:
        return f'; did you mean "{prefixed[0]}"?'
    close = difflib.get_close_matches(word, choices, n=1, cutoff=0.6)
    if not close:
        close = difflib.get_close_matches(word.lower(), list(lowered), n=1, cutoff=0.6)
        close = [lowered[c] for c in close]
    return f'; did you mean "{close[0]}"?' if close else ""


# ---------------------------------------------------------------------------
# pydantic -> Problem

_TYPE_EXPECTED = {
    "float_type": "a number",
    "float_parsing": "a number",
    "int_type": "an integer",
    "int_parsing": "an integer",
    "int_from_float": "an integer (no fractional part)",
    "string_type": "a string",
    "bool_type": "true or false",
    "tuple_type": "a list (TOML array)",
    "list_type": "a list (TOML array)",
    "dict_type": "a table",
    "model_type": "a table",
    "model_attributes_type": "a table",
}


def _model_at(model: type[BaseModel] | None, loc: Sequence[Any]) -> type[BaseModel] | None:
    """The pydantic model class that holds the keys at ``loc`` (best effort)."""
    for part in loc:
        if model is None:
            return None
        if isinstance(part, int):
            continue
        field = model.model_fields.get(part)
        if field is None:
            return None
        model = _find_model(field.annotation)
    return model


def _find_model(annotation: Any) -> type[BaseModel] | None:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in typing.get_args(annotation):
        found = _find_model(arg)
        if found is not None:
            return found
    return None


def _field_doc(model: type[BaseModel] | None, name: Any) -> str:
    if model is None or not isinstance(name, str):
        return ""
    field = model.model_fields.get(name)
    return (field.description or "") if field is not None else ""


def translate(
    error: ValidationError, model: type[BaseModel], prefix: Sequence[Any] = (), file: Path | None = None
) -> list[Problem]:
    """Turn a pydantic ValidationError into one Problem per error, with key paths."""
    problems: list[Problem] = []
    errors = error.errors(include_url=False)
    item_locs = [tuple(e["loc"]) for e in errors]
    for err in errors:
        loc = tuple(err["loc"])
        if err["type"] == "too_short" and any(len(o) > len(loc) and o[: len(loc)] == loc for o in item_locs):
            continue  # pydantic counts only the valid items; the bad items are reported already
        key = format_path(tuple(prefix) + loc)
        kind = err["type"]
        value = err.get("input")
        ctx = err.get("ctx") or {}
        parent = _model_at(model, loc[:-1])
        shown: str | None = format_value(value)
        if kind == "missing":
            doc = _field_doc(parent, loc[-1] if loc else None)
            msg, shown = "required key is missing" + (f" (expected {doc})" if doc else ""), None
        elif kind == "extra_forbidden":
            allowed = sorted(parent.model_fields) if parent is not None else []
            name = str(loc[-1]) if loc else ""
            msg = f"unknown key{suggest(name, allowed)}"
            if allowed:
                msg += f" (valid keys here: {', '.join(allowed)})"
        elif kind in ("value_error", "assertion_error"):
            msg = str(ctx.get("error", err["msg"]))
            if not loc or isinstance(value, dict) or isinstance(value, BaseModel):
                shown = None  # a whole-table check: its message names the keys
                if msg.startswith(f"{key}."):  # ... first the one at fault: no "almen: almen.x" stutter
                    key = ""
        elif kind == "finite_number":
            msg = "expected a finite number (not nan or inf)"
        elif kind in _TYPE_EXPECTED:
            doc = _field_doc(parent, loc[-1] if loc else None)
            msg = f"expected {_TYPE_EXPECTED[kind]}, got a {_type_name(value)}"
            if doc and not isinstance(loc[-1], int):
                msg += f" ({doc})"
            if isinstance(value, (dict, BaseModel)):
                shown = None
        elif kind == "literal_error":
            msg = f"expected one of {ctx.get('expected')}"
            if isinstance(value, str):
                options = [o.strip().strip("'\"") for o in str(ctx.get("expected", "")).replace(" or ", ",").split(",")]
                msg += suggest(value, [o for o in options if o])
        elif kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
            op = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<", "less_than_equal": "<="}[kind]
            bound = next(iter(ctx.values()), "?")
            msg = f"expected a value {op} {bound}"
        elif kind == "too_short":
            msg = f"expected at least {ctx.get('min_length')} item(s)"
        elif kind == "too_long":
            msg = f"expected at most {ctx.get('max_length')} item(s)"
        else:  # anything we did not anticipate: still one line, with the path
            msg = str(err["msg"])
        problems.append(Problem(key, msg, file, shown))
    return problems
