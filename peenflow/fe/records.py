"""The named record of one impact (:class:`ShotRecord`) and its array form.

One impact of the driver (:meth:`peenflow.fe.impact.ImpactRun.impact`)
returns a :class:`ShotRecord`; the records of a run travel in the
checkpointable state (:attr:`peenflow.fe.state.KernelState.shot_records`) as
a numpy structured array of dtype :data:`SHOT_RECORD_DTYPE`, read by field
name (``records["restitution"]``), never by column position.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field, fields

import numpy as np


def _f(units: str, doc: str = "", default=0.0):
    return field(default=default, metadata={"units": units, "doc": doc})


@dataclass(frozen=True)
class ShotRecord:
    """What one shot did (SI units; a shot that missed the target has ``hit = False`` and zeros
    for everything measured during contact).

    Velocities and spins are those of the modelled shot (on a symmetry plane the
    components that plane cannot hold are 0); the window is the element box
    integrated during the impact (periodic targets: in the target's frame, it may
    extend past the mesh and wraps).
    """

    shot_index: int = _f("1", "position of the shot in the run's sequence (0-based)", 0)
    hit: bool = _f("1", "True if the shot touched the target", False)
    t_contact: float = _f("s", "time of first contact")
    t_separate: float = _f("s", "time of separation")
    contact_duration: float = _f("s", "t_separate - t_contact")
    vin_x: float = _f("m/s", "velocity before the impact")
    vin_y: float = _f("m/s")
    vin_z: float = _f("m/s")
    vout_x: float = _f("m/s", "velocity after the impact (rebound)")
    vout_y: float = _f("m/s")
    vout_z: float = _f("m/s")
    restitution: float = _f("1", "coefficient of restitution -vout_z / vin_z")
    max_approach: float = _f("m", "deepest point of the shot below z = 0")
    max_overlap: float = _f("m", "largest overlap of the shot with a surface node")
    peak_force: float = _f("N", "peak contact force (full shot)")
    max_contact_radius: float = _f("m", "farthest node in contact from the shot axis (quantised by the node spacing)")
    steps: int = _f("1", "time steps of the impact phase", 0)
    energy_error: float = _f("1", "largest |energy balance error| of the impact / impact energy")
    impact_energy: float = _f("J", "kinetic energy of the full shot before the impact")
    win_i0: int = _f("1", "integrated element box: first column", 0)
    win_i1: int = _f("1", "... one past the last column", 0)
    win_j0: int = _f("1", "... first row", 0)
    win_j1: int = _f("1", "... one past the last row", 0)
    win_k0: int = _f("1", "... first layer", 0)
    win_k1: int = _f("1", "... one past the last layer", 0)
    contact_radius: float = _f("m", "Hertz-equivalent radius sqrt(5/2 <r^2>) of the normal impulse at peak force")
    hourglass_peak: float = _f("1", "peak hourglass energy of the impact / impact energy")
    internal_peak: float = _f("1", "peak internal (stress) energy of the impact / impact energy")
    spin_in_x: float = _f("rad/s", "spin before the impact")
    spin_in_y: float = _f("rad/s")
    spin_in_z: float = _f("rad/s")
    spin_out_x: float = _f("rad/s", "spin after the impact (unchanged for a miss)")
    spin_out_y: float = _f("rad/s")
    spin_out_z: float = _f("rad/s")
    window_validated: bool = _f("1", "False if a held face of the impact's window was nearer than the envelope the "
                                "window error was measured for (peenflow.fe.window.WINDOW_VALIDATED)", True)

    def as_row(self) -> np.ndarray:
        """This record as a 0-d structured array of :data:`SHOT_RECORD_DTYPE`."""
        return np.array(tuple(asdict(self).values()), dtype=SHOT_RECORD_DTYPE)

    @classmethod
    def from_row(cls, row) -> "ShotRecord":
        """The record of one element of a :data:`SHOT_RECORD_DTYPE` array (read by name)."""
        return cls(**{f.name: _PY[f.type](row[f.name]) for f in fields(cls)})


_NUMPY = {"int": np.int64, "bool": np.bool_, "float": np.float64}
_PY = {"int": int, "bool": bool, "float": float}

#: the per-shot fields, in the order of :class:`ShotRecord`
SHOT_RECORD_FIELDS = tuple(f.name for f in fields(ShotRecord))
#: the dtype of a run's records (:attr:`KernelState.shot_records`)
SHOT_RECORD_DTYPE = np.dtype([(f.name, _NUMPY[f.type]) for f in fields(ShotRecord)])
#: units of each field
SHOT_RECORD_UNITS = {f.name: f.metadata["units"] for f in fields(ShotRecord)}


def records_array(records) -> np.ndarray:
    """A sequence of :class:`ShotRecord` as a (n,) structured array of :data:`SHOT_RECORD_DTYPE`."""
    out = np.zeros(len(records), dtype=SHOT_RECORD_DTYPE)
    for k, r in enumerate(records):
        out[k] = r.as_row()
    return out


def as_records(a) -> np.ndarray:
    """``a`` as a (n,) :data:`SHOT_RECORD_DTYPE` array, each field taken by name (a copy).

    Extra fields are dropped; a missing field, or an array without field names
    (the per-shot table by column position of states written before
    2026-12-02), is refused with ValueError: its columns cannot be read by
    name, and the state it came with cannot be resumed."""
    a = np.asarray(a)
    names = a.dtype.names
    if names is None:
        raise ValueError(
            f"shot records without field names (a {a.dtype} array of shape {a.shape}: the per-shot table by "
            "column position of states written before 2026-12-02) cannot be read by name; the state they came "
            "with cannot be resumed (start the run again)")
    missing = [n for n in SHOT_RECORD_FIELDS if n not in names]
    if missing:
        raise ValueError(f"shot records lack the fields {missing}; the state they came with cannot be resumed")
    out = np.zeros(a.shape, dtype=SHOT_RECORD_DTYPE)
    for n in SHOT_RECORD_FIELDS:
        out[n] = a[n]
    return out.reshape(-1)


def record_columns(records: np.ndarray) -> dict[str, np.ndarray]:
    """``{field: (n,) array}`` of a records array (copies)."""
    return {n: np.array(records[n], copy=True) for n in SHOT_RECORD_FIELDS}
