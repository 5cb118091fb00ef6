"""Test helpers: the paper's materials and shot from the packaged library, and checks of result Datasets.

The paper's numbers live once, in the study library
(``peenflow/study/library/*.toml``); tests and benchmarks take them from
here instead of copying them::

    from peenflow.testing import SAE1070, AL7075_T73, S230
    Material(**SAE1070)                 # the kernel's material, SI
    S230.radius_m, S230.density_kg_m3   # the shot, SI

``SAE1070`` / ``AL7075_T73`` are the keyword arguments of
:class:`peenflow.fe.johnson_cook.Material` (E, nu, density in Pa, 1,
kg m-3; A, B in Pa; n, C, m; ref_strain_rate in s-1), so a test changes one
with ``{**SAE1070, "C": 0.0}``.

Result checks: :func:`assert_cf_variables` (every stored number says what it
is and in which unit, SI for lengths and stresses) and
:func:`assert_results_equal` (two results agree variable by variable).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np

from .study.items import Material, Shot
from .study.sections import ShotSection

LIBRARY = Path(__file__).parent / "study" / "library"

__all__ = ["LIBRARY", "library_material", "library_shot", "kernel_material_kwargs", "SAE1070", "AL7075_T73",
           "S230", "ShotConstants", "SI_UNITS", "assert_cf_variables", "assert_results_equal"]


@cache
def _table(kind: str) -> dict:
    with open(LIBRARY / f"{kind}.toml", "rb") as f:
        return tomllib.load(f)[kind]


def library_material(name: str) -> Material:
    """A material of the packaged library, validated as a study would read it (GPa, MPa there)."""
    return Material.model_validate({"name": name, **_table("materials")[name]})


def library_shot(name: str) -> Shot:
    return Shot.model_validate({"name": name, **_table("shots")[name]})


def kernel_material_kwargs(name: str) -> dict:
    """The keyword arguments of the kernel's ``Material`` for a library material, SI: the stages' own
    translation (:meth:`tasks.params.MaterialParams.kernel_kwargs`)."""
    from tasks.params import MaterialParams

    return MaterialParams.from_study(library_material(name)).kernel_kwargs()


@dataclass(frozen=True)
class ShotConstants:
    """A shot in SI: ``radius_m``, ``diameter_m`` (m), ``density_kg_m3``."""

    radius_m: float
    diameter_m: float
    density_kg_m3: float


#: SAE 1070 spring steel (the Almen strip; paper Table 1), kernel keyword arguments
SAE1070 = kernel_material_kwargs("SAE1070")
#: Al 7075-T73 (the paper's part; Table 2), kernel keyword arguments
AL7075_T73 = kernel_material_kwargs("Al7075-T73")
def _shot_constants(name: str) -> ShotConstants:
    from tasks.params import ShotParams

    shot = ShotParams.from_study(ShotSection(type=library_shot(name)))
    return ShotConstants(shot.radius_m, shot.diameter_m, shot.density_kg_m3)


#: S230 cast steel shot (D = 0.58 mm, 7800 kg m-3; paper §4)
S230 = _shot_constants("S230")

#: the units result variables may carry for lengths, stresses and speeds (the store is SI)
SI_UNITS = {"m", "Pa", "m s-1", "s", "N", "N m", "m2", "m-1", "K", "kg", "1", "%", "degree"}


def assert_cf_variables(ds, si: bool = False) -> None:
    """Every data variable and coordinate of a result has a ``long_name``, and every
    numeric one ``units``; with ``si``, only the units of :data:`SI_UNITS`."""
    problems = []
    for name in list(ds.data_vars) + list(ds.coords):
        attrs = ds[name].attrs
        if not attrs.get("long_name"):
            problems.append(f"{name}: no long_name")
        if ds[name].dtype.kind in "fiu":
            units = attrs.get("units")
            if units is None:
                problems.append(f"{name}: no units")
            elif si and units not in SI_UNITS:
                problems.append(f"{name}: units {units!r} not SI")
    assert not problems, "; ".join(problems)


def assert_results_equal(a, b, rtol: float = 0.0, names=None) -> None:
    """Two results hold the same variables (or ``names``) with the same values within ``rtol``
    of each variable's largest magnitude, and NaN in the same places."""
    names = sorted(set(a.data_vars) | set(b.data_vars)) if names is None else list(names)
    missing = [n for n in names if n not in a or n not in b]
    assert not missing, f"variables in only one result: {missing}"
    for n in names:
        x, y = np.asarray(a[n].values), np.asarray(b[n].values)
        assert x.shape == y.shape, f"{n}: shapes {x.shape} and {y.shape}"
        if x.dtype.kind not in "fiub":
            assert np.array_equal(x, y), f"{n}: {x!r} != {y!r}"
            continue
        x, y = x.astype(float), y.astype(float)
        assert np.array_equal(np.isnan(x), np.isnan(y)), f"{n}: NaN in different places"
        ok = ~np.isnan(x)
        if ok.any():
            scale = np.max(np.abs(x[ok]))
            diff = np.max(np.abs(x[ok] - y[ok]))
            relative = diff / scale if scale else np.inf
            assert diff <= rtol * scale, (f"{n}: largest difference {diff:.3g} is {relative:.3g} of its scale "
                                          f"{scale:.3g} (rtol {rtol:g})")


def run_study(study, *args, workers: int = 1, timeout: float = 900.0) -> str:
    """``peenflow run STUDY --workers N ARGS...`` in a subprocess, as a user runs it; its stdout
    (the assertion message carries stdout and stderr when it fails)."""
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-m", "peenflow.cli", "run", str(study), "--workers", str(workers), *args],
                          capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return proc.stdout
