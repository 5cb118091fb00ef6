"""Reading a study file: TOML, extends, includes, references, validation.

Pipeline (every step collects problems instead of stopping at the first):

1. read the TOML of the study file, then of each parent named by
   ``study.extends`` (relative to the file that names it; cycles reported);
   deep-merge parent <- child (child wins, lists replaced whole, includes
   accumulated, name/description not inherited);
2. read the included libraries (``peenflow:library`` = the packaged one,
   other entries relative to the including file) and the study's own
   ``[materials.*]``, ``[shots.*]``, ``[strips.*]`` tables, later ones
   deep-merged over earlier ones; validate every item;
3. replace names (``target.material = "Al7075-T73"``) by the items, or
   validate inline tables; expand the fidelity preset; fill defaults that
   depend on other sections (dmin strip velocity and angles);
4. validate each section on its own (so one broken section does not hide
   another's problems), then the checks that span sections;
5. build the frozen :class:`Study`, or raise one :class:`StudyError`.

Length: one pipeline in one class (``_Loader``), whose steps share the problems
collected so far and the partly read study, so that a study file's problems are
reported all at once; what its steps apply (the sections' models, bounds,
errors, variants, items and the measured-data readers) is in its own modules.
"""

from __future__ import annotations

import copy
import dataclasses
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError

from .._toml import describe_toml_error
from ..units import MM, UM
from .bounds import bound_keys, check_bounds, check_table_bounds
from .errors import Problem, StudyError, format_value, suggest, translate
from .fidelity import REMOVED_KEYS, Fidelity, expand_preset
from .items import Material, Shot, Strip
from .almen_strips import AlmenStripsError, read_almen_strips
from .measured_profile import PROFILE_COMPONENTS, ProfileError, read_measured_profile
from .model import Study, StudyInfo
from .requirements import FEATURES, MINIMISE_SHOTS, Requirements
from .sections import Almen, Coverage, Dmin, Execution, Seeds, ShotSection, Target
from .variants import BASELINE, SENSITIVITY_DIM, ListProblem, apply_overrides, expand

__all__ = ["load_study", "validate_study", "LIBRARY_DIR", "LIBRARY_PREFIX", "PROFILE_COMPONENTS"]

LIBRARY_DIR = Path(__file__).resolve().parent / "library"
LIBRARY_PREFIX = "peenflow:"
DEFAULT_INCLUDE = (LIBRARY_PREFIX + "library",)

SECTIONS: dict[str, type[BaseModel]] = {
    "shot": ShotSection,
    "almen": Almen,
    "dmin": Dmin,
    "coverage": Coverage,
    "target": Target,
    "fidelity": Fidelity,
    "seeds": Seeds,
    "execution": Execution,
}
REGISTRY: dict[str, type[BaseModel]] = {"materials": Material, "shots": Shot, "strips": Strip}
SINGULAR = {"materials": "material", "shots": "shot", "strips": "Almen strip"}
STUDY_KEYS = ("name", "description", "include", "extends", "allow_outside_bounds")
#: tables beside the sections: named targets, the sweep of any key, what the part needs
FAMILY_KEYS = ("targets", "sweep", "sensitivity", "requirements")
TOP_KEYS = ("study", *SECTIONS, *REGISTRY, *FAMILY_KEYS)
# Where a section names a library item: (section, key, registry kind).
REFERENCES = (("shot", "type", "shots"), ("almen", "strip", "strips"), ("target", "material", "materials"))


def _drop_baseline_copies(dims: list, studies: list) -> tuple[list, list]:
    """A ``[sensitivity]`` change to the value the study already has (written or by default) is the baseline:
    its point and its label go (the same study twice would be one point under two names)."""
    if not dims or dims[-1].name != SENSITIVITY_DIM:
        return dims, studies
    dim = dims[-1]
    baseline = {}
    for coords, st in studies:
        if coords[dim.name] == BASELINE:
            baseline[tuple(sorted((k, repr(v)) for k, v in coords.items() if k != dim.name))] = st.digest()
    same = set()
    for coords, st in studies:
        other = tuple(sorted((k, repr(v)) for k, v in coords.items() if k != dim.name))
        if coords[dim.name] != BASELINE and st.digest() == baseline.get(other):
            same.add(coords[dim.name])
    if not same:
        return dims, studies
    kept = tuple(v for v in dim.values if v not in same)
    new = dataclasses.replace(dim, values=kept, given=kept)
    return dims[:-1] + [new], [(c, st) for c, st in studies if c[dim.name] not in same]


def load_study(path: str | Path) -> Study:
    """Load and validate a study file; raise StudyError listing every problem."""
    loader = _Loader(Path(path))
    study = loader.run()
    if loader.problems or study is None:
        raise StudyError(loader.path, loader.messages())
    return study


def validate_study(path: str | Path) -> list[str]:
    """Every problem of a study file, one message each; [] when it is valid."""
    loader = _Loader(Path(path))
    loader.run()
    return loader.messages()


# ---------------------------------------------------------------------------


def deep_merge(base: dict, over: dict) -> dict:
    """base <- over: tables merge key by key, everything else (lists too) is replaced."""
    out = copy.deepcopy(base)
    for key, value in over.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = deep_merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def _tupleize(value: Any) -> Any:
    """TOML arrays -> tuples (the models are frozen and strict)."""
    if isinstance(value, dict):
        return {k: _tupleize(v) for k, v in value.items()}
    if isinstance(value, list):
        return tuple(_tupleize(v) for v in value)
    return value


def _is_number(x: Any) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


_NO_VALUE = object()


@dataclass
class _Raw:
    """One study file after its extends chain is merged."""

    data: dict
    info: dict
    includes: list[tuple[str, list[Path]]] = field(default_factory=list)
    chain: list[Path] = field(default_factory=list)


class _Loader:
    def __init__(self, path: Path):
        self.path = Path(path).absolute()
        self.problems: list[Problem] = []
        self.suppressed: set[str] = set()
        self.unknown_names: list[Problem] = []  # unknown [study] keys and sections: the tables still build

    # --- problems ---------------------------------------------------------
    def add(self, key: str, message: str, file: Path | None = None, value: Any = _NO_VALUE) -> None:
        shown = None if value is _NO_VALUE else format_value(value)
        self.problems.append(Problem(key, message, None if file == self.path else file, shown))

    def add_unknown_name(self, key: str, message: str, file: Path | None = None) -> None:
        """A key of [study] or a section that does not exist: a problem that changes no table, so the
        sections are still built and checked (one ``check`` lists every problem)."""
        self.add(key, message, file)
        self.unknown_names.append(self.problems[-1])

    def is_suppressed(self, key: str) -> bool:
        """Under a reference already reported as unknown or broken."""
        return any(key == s or key.startswith(s + ".") or key.startswith(s + "[") for s in self.suppressed)

    def messages(self) -> list[str]:
        seen, out = set(), []
        for p in self.problems:
            text = p.render(self.path)
            if text not in seen:
                seen.add(text)
                out.append(text)
        return out

    # --- files --------------------------------------------------------------
    def read_toml(self, file: Path, key: str = "", referrer: Path | None = None) -> dict | None:
        """The file's tables (read once per loader: every variant of a study sees the same file)."""
        cache = self.__dict__.setdefault("_toml", {})
        if file not in cache:
            cache[file] = self._read_toml(file, key, referrer)
        return copy.deepcopy(cache[file])

    def _read_toml(self, file: Path, key: str = "", referrer: Path | None = None) -> dict | None:
        try:
            if file.is_dir():
                self.add(key, f"{file} is a directory; expected a TOML file", referrer)
                return None
            with open(file, "rb") as fh:
                return tomllib.load(fh)
        except FileNotFoundError:
            self.add(key, f"file not found: {file}", referrer)
        except UnicodeDecodeError as exc:
            self.add("", f"{file.name} is not a text TOML file (byte {exc.start} is not UTF-8)", file)
        except tomllib.TOMLDecodeError as exc:
            self.add("", f"TOML syntax error in {file.name}: {describe_toml_error(file, exc)}", file)
        except OSError as exc:
            self.add(key, f"cannot read {file}: {exc}", referrer)
        return None

    def resolve_include(self, spec: Any, base: Path, key: str, file: Path) -> list[Path] | None:
        if not isinstance(spec, str) or not spec:
            self.add(key, 'expected a file name such as "peenflow:library" or "my_materials.toml"', file, spec)
            return None
        if spec.startswith(LIBRARY_PREFIX):
            name = spec[len(LIBRARY_PREFIX):]
            stems = sorted(p.stem for p in LIBRARY_DIR.glob("*.toml"))
            if name == "library":
                return sorted(LIBRARY_DIR.glob("*.toml"))
            if name in stems:
                return [LIBRARY_DIR / f"{name}.toml"]
            self.add(key, f"no such packaged library{suggest(name, ['library', *stems])} "
                     f'(expected "peenflow:library" or one of ' + ", ".join(f'"peenflow:{s}"' for s in stems) + ")",
                     file, spec)
            return None
        target = (base / spec).resolve()
        if not target.is_file():
            self.add(key, f"included file not found (looked for {target})", file, spec)
            return None
        return [target]

    def read_study(self, file: Path, chain: tuple[Path, ...]) -> _Raw | None:
        data = self.read_toml(file, "study.extends" if chain else "", chain[-1] if chain else None)
        if data is None:
            return None
        table = data.pop("study", None)
        if table is None:
            if not chain:
                self.add("study", 'missing [study] table (expected at least name = "...")', file)
            table = {}
        elif not isinstance(table, dict):
            self.add("study", "expected a [study] table", file, table)
            table = {}
        for key in table:
            if key not in STUDY_KEYS:
                self.add_unknown_name(f"study.{key}", f"unknown key{suggest(key, STUDY_KEYS)} (valid keys here: "
                         f"{', '.join(STUDY_KEYS)})", file)

        includes: list[tuple[str, list[Path]]] = []
        specs = table.get("include", list(DEFAULT_INCLUDE))
        if not isinstance(specs, list):
            self.add("study.include", 'expected a list of file names, e.g. ["peenflow:library", "my_materials.toml"]',
                     file, specs)
            specs = []
        for i, spec in enumerate(specs):
            paths = self.resolve_include(spec, file.parent, f"study.include[{i}]", file)
            if paths is not None:
                shown = spec if spec.startswith(LIBRARY_PREFIX) else str(paths[0])
                includes.append((shown, paths))

        # Paths in a file are relative to that file, whoever extends it.
        target = data.get("target")
        for csv_key in ("measured_profile_csv", "almen_strips_csv"):
            if isinstance(target, dict) and isinstance(target.get(csv_key), str) and target[csv_key]:
                target[csv_key] = str((file.parent / target[csv_key]).resolve())

        info = {k: table[k] for k in ("name", "description", "extends", "allow_outside_bounds") if k in table}
        raw = _Raw(data=data, info=info, includes=includes, chain=[file])
        parent_spec = table.get("extends")
        if parent_spec is None:
            return raw
        if not isinstance(parent_spec, str) or not parent_spec:
            self.add("study.extends", "expected the path of a parent study file, relative to this one", file, parent_spec)
            return raw
        parent_path = (file.parent / parent_spec).resolve()
        if parent_path == file.resolve() or parent_path in [c.resolve() for c in chain]:
            loop = " -> ".join(p.name for p in (*chain, file, parent_path))
            self.add("study.extends", f"circular extends ({loop}); expected a chain without loops", file, parent_spec)
            return raw
        if not parent_path.is_file():
            self.add("study.extends", f"parent study file not found (looked for {parent_path})", file, parent_spec)
            return raw
        parent = self.read_study(parent_path, (*chain, file))
        if parent is None:
            return raw
        seen = {s for s, _ in parent.includes}
        merged_includes = parent.includes + [(s, p) for s, p in includes if s not in seen]
        return _Raw(
            data=deep_merge(parent.data, data),
            info=info,
            includes=merged_includes,
            chain=[file, *parent.chain],
        )

    # --- library ----------------------------------------------------------
    def build_registry(self, raw: _Raw, data: dict) -> tuple[dict[str, dict[str, BaseModel]], dict[str, set[str]]]:
        """The library items (the included files', then the study's own tables in ``data``), validated."""
        merged: dict[str, dict[str, dict]] = {kind: {} for kind in REGISTRY}
        origin: dict[tuple[str, str], Path] = {}
        sources: list[tuple[Path, dict]] = []
        done: set[Path] = set()
        for _, paths in raw.includes:
            for p in paths:
                if p in done:
                    continue
                done.add(p)
                d = self.read_toml(p)
                if d is None:
                    continue
                for key in d:
                    if key not in REGISTRY:
                        self.add(key, f"unknown table in an included file{suggest(key, REGISTRY)}; included files "
                                 "may only define [materials.*], [shots.*] and [strips.*]", p)
                sources.append((p, d))
        sources.append((self.path, {k: data[k] for k in REGISTRY if k in data}))
        for file, d in sources:
            for kind in REGISTRY:
                table = d.get(kind)
                if table is None:
                    continue
                if not isinstance(table, dict):
                    self.add(kind, f"expected [{kind}.NAME] tables", file, table)
                    continue
                for name, entry in table.items():
                    if not isinstance(entry, dict):
                        self.add(f"{kind}.{name}", f"expected a [{kind}.{name}] table", file, entry)
                        continue
                    merged[kind][name] = deep_merge(merged[kind].get(name, {}), entry)
                    origin[(kind, name)] = file

        items: dict[str, dict[str, BaseModel]] = {kind: {} for kind in REGISTRY}
        broken: dict[str, set[str]] = {kind: set() for kind in REGISTRY}
        for kind in ("materials", "shots", "strips"):  # strips refer to materials
            model = REGISTRY[kind]
            for name, entry in merged[kind].items():
                file = origin[(kind, name)]
                entry = {**entry, "name": name}
                ok = True
                if kind == "strips":
                    ok = self.resolve_ref(entry, "material", "materials", f"strips.{name}", items, broken, file)
                try:
                    items[kind][name] = model.model_validate(_tupleize(entry))
                except ValidationError as exc:
                    broken[kind].add(name)
                    for p in translate(exc, model, (kind, name), None if file == self.path else file):
                        if not self.is_suppressed(p.key):
                            self.problems.append(p)
                if not ok:
                    broken[kind].add(name)
                    items[kind].pop(name, None)
        return items, broken

    def resolve_ref(
        self, section: dict, key: str, kind: str, prefix: str,
        items: dict[str, dict[str, BaseModel]], broken: dict[str, set[str]], file: Path | None = None,
    ) -> bool:
        """Replace section[key] (a name) by the library item; False if it cannot be."""
        value = section.get(key)
        path = f"{prefix}.{key}"
        if isinstance(value, str):
            if value in items[kind]:
                section[key] = items[kind][value]
                return True
            self.suppressed.add(path)
            section[key] = None
            if value in broken[kind]:
                return False  # its own problems are already reported where it is defined
            known = sorted(items[kind]) + sorted(broken[kind])
            self.add(path, f"unknown {SINGULAR[kind]}{suggest(value, known)} "
                     f"(known: {', '.join(known) if known else 'none; include peenflow:library?'})", file, value)
            return False
        if isinstance(value, dict):  # inline definition
            value = dict(value)
            if kind in ("materials", "shots"):
                value.setdefault("name", f"inline-{SINGULAR[kind]}")
            if kind == "strips" and "material" in value:
                self.resolve_ref(value, "material", "materials", path, items, broken, file)
            section[key] = value
        return True

    # --- the whole study ----------------------------------------------------
    def run(self) -> Study | None:
        raw = self.read_study(self.path, ())
        if raw is None:
            return None
        for key in raw.data:
            if key not in TOP_KEYS:
                self.add_unknown_name(key, f"unknown section{suggest(key, TOP_KEYS)} (valid sections: {', '.join(TOP_KEYS)})")
        try:
            dims, variants = expand(raw.data)
        except ListProblem as exc:
            self.add(exc.key, exc.message, value=exc.value if exc.value is not None else _NO_VALUE)
            return None
        if raw.data.get("sensitivity") is not None and raw.data.get("target") is None \
                and raw.data.get("targets") is None:
            self.add("sensitivity", "[sensitivity] reports each input's change of the part's velocity and profile: "
                     "it needs a [target] (or [targets.NAME])")
            return None
        base = {k: v for k, v in raw.data.items() if k not in FAMILY_KEYS}
        for table in ("sweep", "sensitivity"):
            if isinstance(raw.data.get(table), dict):
                self.check_sweep_keys(raw.data[table], raw, table)
        if any(p not in self.unknown_names for p in self.problems):
            return None
        studies = []
        for v in variants:
            data = copy.deepcopy(base)
            if v.target is not None:
                data["target"] = copy.deepcopy(v.target)
            if v.overrides:
                apply_overrides(data, v.overrides)
            studies.append((v.coords, self.build(raw, data)))
            if self.problems:  # the first variant's problems are the study's: the others would repeat them
                return None
        dims, studies = _drop_baseline_copies(dims, studies)
        if dims and dims[-1].name == SENSITIVITY_DIM and len(dims[-1].values) == 1:
            self.add("sensitivity", "every value given is the study's own: give values to change to")
            return None
        requirements = self.requirements(raw.data.get("requirements"), dims)
        if requirements is None and raw.data.get("requirements") is not None:
            return None
        first = studies[0][1]
        if dims:
            object.__setattr__(first, "_dims", tuple(dims))
            object.__setattr__(first, "_variants", tuple(studies))
        object.__setattr__(first, "_requirements", requirements)
        return first

    def check_sweep_keys(self, overrides: dict, raw: "_Raw", table: str = "sweep") -> None:
        """A key of ``[sweep]`` or ``[sensitivity]`` (``table``): a library item it names is one the study can
        see, and the field exists."""
        for key in overrides:
            kind, _, rest = key.partition(".")
            name, _, field_path = rest.partition(".")
            if kind in REGISTRY:
                known = self.registry_names(raw).get(kind, set())
                if name not in known:
                    self.add(f'{table}."{key}"', f"no {SINGULAR[kind]} {name!r}{suggest(name, sorted(known))} to sweep "
                             f"(known: {', '.join(sorted(known))})")
                    continue
                model, path = REGISTRY[kind], field_path.split(".")
            elif kind in SECTIONS:
                model, path = SECTIONS[kind], rest.split(".")
            else:
                continue
            for i, part in enumerate(path):
                fields = getattr(model, "model_fields", {})
                if part not in fields:
                    self.add(f'{table}."{key}"', f"no key {part!r}{suggest(part, list(fields))} in "
                             f"{'.'.join([kind, name] if kind in REGISTRY else [kind])}"
                             f"{'.' + '.'.join(path[:i]) if i else ''}: expected an existing numeric key")
                    break
                model = _nested_model(fields[part].annotation)

    def registry_names(self, raw: "_Raw") -> dict[str, set[str]]:
        """Names of the library items the study can refer to, per kind (``materials``, ...)."""
        names = {kind: set(raw.data.get(kind, {}) or {}) for kind in REGISTRY}
        for _, paths in raw.includes:
            for p in paths:
                d = self.read_toml(p) or {}
                for kind in REGISTRY:
                    if isinstance(d.get(kind), dict):
                        names[kind] |= set(d[kind])
        return names

    def requirements(self, table, dims) -> Requirements | None:
        if table is None:
            return None
        if not isinstance(table, dict):
            self.add("requirements", "expected a [requirements] table", value=table)
            return None
        validated = None
        try:
            validated = Requirements.from_table(_tupleize(table))
        except ValidationError as exc:
            for p in translate(exc, Requirements, ("requirements",)):
                self.problems.append(p)
            return None
        allowed = [d.name for d in dims if not d.labels] + ["coverage_percent", MINIMISE_SHOTS]
        if validated.minimise not in allowed:
            self.add("requirements.minimise", f"expected a process dimension of this study or \"{MINIMISE_SHOTS}\" "
                     f"(here: {', '.join(allowed)})", value=validated.minimise)
            return None
        return validated

    def build(self, raw: "_Raw", data: dict) -> Study | None:
        """The single-point study of the merged tables ``data`` (one variant), or None with its problems."""
        items, broken = self.build_registry(raw, data)
        for section, key, kind in REFERENCES:
            if isinstance(data.get(section), dict):
                self.resolve_ref(data[section], key, kind, section, items, broken)
        if isinstance(data.get("fidelity"), dict):
            if "overrides" in data["fidelity"]:  # bookkeeping field of the resolved model, not a key
                self.add("fidelity.overrides", "unknown key (override a preset by giving the key itself, "
                         "e.g. element_size_um = 30)", value=data["fidelity"].pop("overrides"))
            for key, why in REMOVED_KEYS.items():
                if key in data["fidelity"]:
                    self.add(f"fidelity.{key}", why, value=data["fidelity"].pop(key))
            data["fidelity"] = expand_preset(data["fidelity"])
        self.fill_dmin_defaults(data)

        info = self.validate(StudyInfo, {**raw.info, "include": tuple(s for s, _ in raw.includes)}, "study")
        sections: dict[str, Any] = {}
        failed: set[str] = set()
        refused: dict[str, dict] = {}  # the tables of sections their model refused
        for name, model in SECTIONS.items():
            value = data.get(name)
            if value is None:
                if name == "shot":
                    self.add("shot", 'missing [shot] section (expected type = "S230" or another shot)')
                    failed.add(name)
                elif name == "fidelity":
                    sections[name] = Fidelity.model_validate(expand_preset({}))
                elif name in ("almen", "target"):
                    sections[name] = None
                else:
                    sections[name] = model()
                continue
            if not isinstance(value, dict):
                self.add(name, f"expected a [{name}] section (a table)", value=value)
                failed.add(name)
                continue
            validated = self.validate(model, value, name)
            if validated is None:
                failed.add(name)
                refused[name] = value
            else:
                sections[name] = validated

        self.cross_checks(sections, failed)
        # the sections that validated are checked against their bounds even when others failed, and a
        # refused section's values that are numbers too, so one `check` lists every problem
        outside = self.bounds(sections, info, refused) if info is not None else []
        if self.problems or info is None or failed:
            self.problems += outside
            return None
        try:
            study = Study(
                info=info,
                path=self.path,
                extends_chain=tuple(raw.chain),
                **sections,
            )
        except ValidationError as exc:  # a check that spans sections (e.g. a periodic REV too small)
            self.problems += translate(exc, Study)
            study = None
        self.problems += outside
        return None if outside else study

    def bounds(self, sections: dict, info: StudyInfo, refused: dict[str, dict]) -> list[Problem]:
        """Values outside their validated range (bounds.py), except the keys the study allows; in the
        ``refused`` sections' tables, those of keys without a problem of their own."""
        out = []
        allowed = set(info.allow_outside_bounds)
        reported = {p.key for p in self.problems}
        for name, table in refused.items():
            for key, value, message in check_table_bounds(name, table, allowed):
                if key not in reported and key.split("[")[0] not in reported:
                    out.append(Problem(key, message, None, format_value(value)))
        known = bound_keys()
        for i, k in enumerate(info.allow_outside_bounds):
            if k not in known:
                out.append(Problem(f"study.allow_outside_bounds[{i}]", f"no bound on this key{suggest(k, known)} "
                                   f"(keys with bounds: {', '.join(known)})", None, format_value(k)))
        for key, value, message in check_bounds(sections, allowed):
            out.append(Problem(key, message, None, format_value(value)))
        return out

    def validate(self, model: type[BaseModel], value: dict, prefix: str) -> BaseModel | None:
        try:
            return model.model_validate(_tupleize(value))
        except ValidationError as exc:
            for p in translate(exc, model, (prefix,)):
                if not self.is_suppressed(p.key):
                    self.problems.append(p)
            return None

    def fill_dmin_defaults(self, data: dict) -> None:
        """dmin.strip_velocity_m_s / strip_angles_deg default to the extremes of the almen sweep."""
        almen, dmin = data.get("almen"), data.get("dmin", {})
        if not isinstance(almen, dict) or not isinstance(dmin, dict):
            return
        dmin = dict(dmin)
        velocities, angles = almen.get("velocities_m_s"), almen.get("angles_deg")
        if "strip_velocity_m_s" not in dmin and isinstance(velocities, list) and velocities \
                and all(_is_number(v) and v > 0 for v in velocities):
            dmin["strip_velocity_m_s"] = float(max(velocities))
        if "strip_angles_deg" not in dmin and isinstance(angles, list) and angles \
                and all(_is_number(a) and 0 < a <= 90 for a in angles):
            dmin["strip_angles_deg"] = sorted({float(min(angles)), float(max(angles))})
        data["dmin"] = dmin

    def cross_checks(self, s: dict[str, Any], failed: set[str]) -> None:
        almen, target, shot, fidelity = s.get("almen"), s.get("target"), s.get("shot"), s.get("fidelity")
        if almen is None and target is None and not ({"almen", "target"} & failed):
            self.add("", "nothing to compute: add an [almen] section (control curves) and/or a [target] section")
        if target is not None:
            uses_curve = target.velocity_m_s is None
            key = ("target.almen_intensity" if target.almen_intensity is not None else
                   "target.almen_strips_csv" if target.almen_strips_csv else "target.almen_intensity_mm")
            if uses_curve and almen is None and "almen" not in failed:
                self.add(key, "a target intensity needs control curves: add an [almen] section, or give "
                         "target.velocity_m_s instead")
            if uses_curve and almen is not None:
                if target.intensity_strip != almen.strip.name:
                    where = "target.almen_strip" if target.almen_strip is not None else key
                    self.add(where, f"the target intensity is on strip {target.intensity_strip} but the control "
                             f'curves are computed on almen.strip = "{almen.strip.name}"; expected the same strip type')
                if len(almen.velocities_m_s) < 2:
                    self.add("almen.velocities_m_s", "a control curve needs at least 2 velocities to find the "
                             "target's velocity", value=almen.velocities_m_s)
                lo, hi = almen.angles_deg[0], almen.angles_deg[-1]
                if target.control_angle_rule == "interpolate" and not lo <= target.angle_deg <= hi:
                    self.add("target.angle_deg", "outside the control-curve angles "
                             f"[{lo!r}, {hi!r}]; expected an angle in that range, or control_angle_rule = \"nearest\"",
                             value=target.angle_deg)
            if target.measured_profile_csv:
                self.check_profile(Path(target.measured_profile_csv), target)
            if target.almen_strips_csv:
                self.check_strips(Path(target.almen_strips_csv), target)
        if fidelity is not None and shot is not None:
            if fidelity.element_size_um * UM >= 0.5 * shot.diameter_mm * MM:
                self.add("fidelity.element_size_um", "an element as large as the "
                         f"shot radius ({0.5 * shot.diameter_mm * MM / UM:g} um) cannot resolve a dent; expected a "
                         "much smaller element", value=fidelity.element_size_um)
            depth_mm = fidelity.fine_depth_mm if fidelity.fine_depth_mm is not None \
                else fidelity.fine_depth_D * shot.diameter_mm
            if depth_mm * MM < fidelity.element_size_um * UM:
                key = "fidelity.fine_depth_mm" if fidelity.fine_depth_mm is not None else "fidelity.fine_depth_D"
                self.add(key, f"the fine zone ({depth_mm * MM / UM:g} um deep) is thinner than one element "
                         f"({fidelity.element_size_um:g} um); expected at least one element")

    def check_strips(self, file: Path, target: Target) -> None:
        """Read the measured strips once; the target keeps them (their intensity is solved with the stage
        parameters, and a set no fit can use is refused there, before compute)."""
        target._strips = self._read_csv("target.almen_strips_csv", "measured strips", file, read_almen_strips,
                                        AlmenStripsError)

    def check_profile(self, file: Path, target: Target) -> None:
        """Parse the measured profile once; the target keeps it (the pipeline
        and the result key use what was validated here)."""
        target._measured = self._read_csv("target.measured_profile_csv", "measured profile", file,
                                          read_measured_profile, ProfileError)

    def _read_csv(self, key: str, what: str, file: Path, read, error):
        """``read(file)``, or None with each of its problems (``error.problems``) reported under ``key``."""
        if not file.is_file():
            self.add(key, f"{what} not found; expected an existing CSV file (or \"\" for none)", value=str(file))
            return None
        try:
            return read(file)
        except error as exc:
            for problem in exc.problems:
                self.add(key, problem)
            return None


def _nested_model(annotation):
    """The study model a field holds (a nested table such as ``johnson_cook``), or None for a value."""
    import typing

    for t in (annotation, *typing.get_args(annotation)):
        if isinstance(t, type) and issubclass(t, BaseModel):
            return t
    return None
