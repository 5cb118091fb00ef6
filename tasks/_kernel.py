"""Kernel helpers the stages share: meshes, stop messages in study keys, fields, checkpoints.

The parameters themselves and their conversion to the kernel's objects
(``Material``, ``Options``, ``Target``, ``Shots``) are in :mod:`tasks.params`;
here: the meshes of single impacts, two-shot plates and REVs (from
:class:`tasks.params.FidelityParams`), :func:`run_impacts` with stop messages
naming study keys, surface fields mirrored from quarter/half models, and the
kernel state as an xarray Dataset for checkpoints.
"""

from __future__ import annotations

from contextlib import contextmanager

import numpy as np
import xarray as xr

from peenflow.fe import impact as _impact
from peenflow.fe.impact import ImpactRun  # noqa: F401 - the REV run drives the kernel step by step
from peenflow.fe.mesh import BoxMesh, graded_axis, uniform_lateral_elements
from peenflow.fe.records import SHOT_RECORD_FIELDS
from peenflow.fe.safety import KernelInstabilityError, Knob, Stop, knobs

from .params import FidelityParams

#: the knobs of a kernel stop (:class:`peenflow.fe.safety.Knob`) named as a study user meets them: a study key,
#: or (where no study key reaches it) the kernel's own limit; (settling, relaxation) where the two differ
STUDY_TERMS = {
    Knob.DT_SAFETY: "fidelity.time_step_safety",
    Knob.MESH: "the mesh (a smaller fidelity.element_size_um)",
    Knob.SHOT_VELOCITY: "the shot velocity (target.velocity_m_s, almen.velocities_m_s)",
    Knob.HOURGLASS: "the kernel's hourglass coefficient (stiffness form)",
    Knob.DT_FLOOR: "the kernel's step floor",
    Knob.RUNAWAY: "the kernel's runaway limit",
    Knob.MAX_STEPS: "the kernel's step budget",
    Knob.DAMPING: ("the kernel's settle damping", "the kernel's relaxation damping"),
    Knob.REST: ("fidelity.settle_tolerance", "fidelity.relaxation_tolerance"),
}
#: the knobs a study file sets
STUDY_KEY_KNOBS = frozenset({Knob.DT_SAFETY, Knob.MESH, Knob.SHOT_VELOCITY, Knob.REST})
_NOT_A_STUDY_KEY = " (the kernel's own limits and coefficients named here are not study keys)"


def study_stop(exc: KernelInstabilityError) -> KernelInstabilityError:
    """The kernel stop ``exc`` with its message naming study keys (``options.dt_safety`` ->
    ``fidelity.time_step_safety``, ...); a note says when it names a kernel limit no study key sets."""
    if not isinstance(exc.reason, Stop):
        return exc
    kernel_only = any(k not in STUDY_KEY_KNOBS for k in knobs(exc.reason))
    return exc.in_terms(STUDY_TERMS, note=_NOT_A_STUDY_KEY if kernel_only else "")


@contextmanager
def in_study_terms():
    """Kernel stop messages raised inside the block name study keys (:func:`study_stop`)."""
    try:
        yield
    except KernelInstabilityError as exc:
        raise study_stop(exc) from None


def run_impacts(*args, **kwargs):
    """:func:`peenflow.fe.impact.run_impacts`, its stop messages naming study keys."""
    with in_study_terms():
        return _impact.run_impacts(*args, **kwargs)


# -- meshes ----------------------------------------------------------------------
def _z_axis(f: FidelityParams, thickness: float) -> np.ndarray:
    return graded_axis(f.fine_depth_m, f.element_size_m, thickness, f.grading_ratio)


def _lateral(f: FidelityParams, fine_half: float, half: float, lower: bool) -> np.ndarray:
    """Axis on [0, half] (lower=False) or [-half, half]: fine within ``fine_half`` of 0."""
    right = graded_axis(fine_half, f.element_size_m, half, f.grading_ratio)
    return np.concatenate([-right[::-1], right[1:]]) if lower else right


def impact_block(f: FidelityParams, half_width: float, thickness: float, fine_half: float,
                 symmetric_x: bool, symmetric_y: bool) -> BoxMesh:
    """Block around an impact at the origin; ``symmetric_*`` keeps only the >= 0 half
    (the plane through the impact is then a symmetry face)."""
    x = _lateral(f, fine_half, half_width, lower=not symmetric_x)
    y = _lateral(f, fine_half, half_width, lower=not symmetric_y)
    return BoxMesh(x, y, _z_axis(f, thickness))


def rev_mesh(f: FidelityParams, side: float, thickness: float) -> BoxMesh:
    """REV block ``[-side/2, side/2]^2 x [0, thickness]``, uniformly fine laterally.

    Shots land anywhere on the peening surface, so the fine zone covers it all;
    lateral node lines fall on the measuring-region edges when the sizes allow.
    """
    n = uniform_lateral_elements(side, f.element_size_m)
    axis = np.linspace(-0.5 * side, 0.5 * side, n + 1)
    return BoxMesh(axis, axis.copy(), _z_axis(f, thickness))


# -- fields on the structured mesh ----------------------------------------------------------
def cell_centres(mesh: BoxMesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x, y, z) element-centre coordinates (m) along each axis of a structured mesh."""
    return tuple(0.5 * (a[1:] + a[:-1]) for a in (mesh.x, mesh.y, mesh.z))


def grid_fields(mesh: BoxMesh, stress: np.ndarray, eps_p: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(stress (nz, ny, nx, 6), eps_p (nz, ny, nx)) from element arrays (numbering i + nx (j + ny k))."""
    nx, ny, nz = mesh.shape_elements
    return stress.reshape(nz, ny, nx, 6), eps_p.reshape(nz, ny, nx)


def von_mises(s: np.ndarray) -> np.ndarray:
    """Von Mises stress of Voigt stress arrays (..., 6) (xx yy zz yz xz xy), Pa."""
    xx, yy, zz, yz, xz, xy = (s[..., k] for k in range(6))
    return np.sqrt(0.5 * ((xx - yy) ** 2 + (yy - zz) ** 2 + (zz - xx) ** 2) + 3.0 * (yz ** 2 + xz ** 2 + xy ** 2))


def surface_uz(mesh: BoxMesh, displacement: np.ndarray) -> np.ndarray:
    """Top-surface z displacement, (nnx, nny) m, positive into the target."""
    nnx, nny, _ = mesh.shape_nodes
    return displacement[: nnx * nny, 2].reshape(nny, nnx).T.copy()


def mirror_axis(a: np.ndarray) -> np.ndarray:
    return np.concatenate([-a[:0:-1], a])


def mirror_nodes(values: np.ndarray, axis: int) -> np.ndarray:
    """Mirror a node field about coordinate 0 (the first node row is on the plane)."""
    return np.concatenate([np.flip(values, axis=axis).take(range(values.shape[axis] - 1), axis=axis), values],
                          axis=axis)


def mirror_cells(values: np.ndarray, axis: int) -> np.ndarray:
    """Mirror a cell field about coordinate 0 (the first cell face is on the plane)."""
    return np.concatenate([np.flip(values, axis=axis), values], axis=axis)


# -- checkpoints: kernel state <-> Dataset -------------------------------------------------------
def state_to_dataset(state: dict, **extra) -> xr.Dataset:
    """A kernel state dict (arrays) as a Dataset, plus ``extra`` variables (name -> (dims, values)).

    An array ``a`` of the state becomes ``kernel__<name>``; a structured one
    (the shot records) one variable per field, ``kernel__<name>__<field>``
    along ``kernel__<name>__0``, so that its fields are stored by name."""
    data = {}
    for name, arr in state.items():
        arr = np.asarray(arr)
        if arr.dtype.names is not None:
            for fld in arr.dtype.names:
                data[f"kernel__{name}__{fld}"] = ([f"kernel__{name}__0"], np.asarray(arr[fld]).reshape(-1))
        else:
            data[f"kernel__{name}"] = ([f"kernel__{name}__{d}" for d in range(arr.ndim)], arr)
    for name, (dims, values) in extra.items():
        data[name] = (dims, np.asarray(values))
    return xr.Dataset(data)


def state_from_dataset(ds: xr.Dataset) -> dict:
    """The kernel state dict of :func:`state_to_dataset`'s Dataset (structured entries reassembled by field
    name; :class:`peenflow.fe.state.KernelState` then reads the shot records by name)."""
    plain, fields = {}, {}
    for var in ds.data_vars:
        if not var.startswith("kernel__"):
            continue
        name, _, fld = var[len("kernel__"):].partition("__")
        if fld:
            fields.setdefault(name, {})[fld] = np.asarray(ds[var].values)
        else:
            plain[name] = np.asarray(ds[var].values)
    for name, cols in fields.items():
        n = len(next(iter(cols.values())))
        rec = np.zeros(n, dtype=[(f, c.dtype) for f, c in cols.items()])
        for f, c in cols.items():
            rec[f] = c
        plain[name] = rec
    return plain


def checkpoint_problem(ds: xr.Dataset) -> str:
    """Why the kernel state in checkpoint ``ds`` cannot be resumed ("" if it can): shot records stored
    as a table by column position (checkpoints written before 2026-12-02) or without every field."""
    if "kernel__shot_records" in ds.variables:
        return ("its shot records are a table by column position (written before 2026-12-02), which this "
                "version does not read")
    missing = [f for f in SHOT_RECORD_FIELDS if f"kernel__shot_records__{f}" not in ds.variables]
    if missing:
        return f"its shot records lack {', '.join(missing)}"
    return ""
