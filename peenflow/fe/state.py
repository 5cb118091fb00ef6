"""The complete mutable kernel state, exportable to / restorable from plain arrays.

Everything the integration depends on lives here (the mesh, masses and
material are rebuilt from the inputs), so ``KernelState.from_dict(s.to_dict())``
resumes a run with bit-identical results.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from peenflow.fe.records import SHOT_RECORD_DTYPE, SHOT_RECORD_FIELDS, as_records
from peenflow.fe.solver import N_CTL, N_EN

__all__ = ["KernelState", "SHOT_RECORD_FIELDS"]


@dataclass(frozen=True)
class KernelState:
    """Mutable arrays of one run (the dataclass is frozen, its arrays are not).

    x : (n_nodes, 3) m, current node positions;  v : (n_nodes, 3) m/s,
    node velocities (at the last half step);  f : (n_nodes, 3) N, nodal forces;
    stress : (n_elements, 6) Pa, Cauchy stress, Voigt order xx yy zz yz xz xy;
    eps_p : (n_elements,) -, equivalent plastic strain;
    sy_static : (n_elements,) Pa, static flow stress (A + B eps_p^n)(1 - T*^m);
    hg : (n_elements, 12) N, hourglass forces (4 modes x 3);
    temp : (n_elements,) K, temperature;
    energy : (6,) J, cumulative W_int, W_plastic, W_hourglass, W_viscous,
      E_contact (lost in contact + friction), E_damping;
    ctl : (14,) solver control scalars (dt_prev s, dt_next s, time s, ...);
    shot_index : (1,) int64, number of shots processed;
    shot_records : (n_done,) per-shot summaries, a structured array of
      :data:`peenflow.fe.records.SHOT_RECORD_DTYPE` (fields by name).
    """

    x: np.ndarray
    v: np.ndarray
    f: np.ndarray
    stress: np.ndarray
    eps_p: np.ndarray
    sy_static: np.ndarray
    hg: np.ndarray
    temp: np.ndarray
    energy: np.ndarray
    ctl: np.ndarray
    shot_index: np.ndarray
    shot_records: np.ndarray

    @classmethod
    def initial(cls, nodes: np.ndarray, n_elements: int, sy0: float, temperature: float) -> "KernelState":
        n = len(nodes)
        return cls(
            x=nodes.copy(),
            v=np.zeros((n, 3)),
            f=np.zeros((n, 3)),
            stress=np.zeros((n_elements, 6)),
            eps_p=np.zeros(n_elements),
            sy_static=np.full(n_elements, sy0),
            hg=np.zeros((n_elements, 12)),
            temp=np.full(n_elements, temperature),
            energy=np.zeros(N_EN),
            ctl=np.zeros(N_CTL),
            shot_index=np.zeros(1, dtype=np.int64),
            shot_records=np.zeros(0, dtype=SHOT_RECORD_DTYPE),
        )

    def to_dict(self) -> dict[str, np.ndarray]:
        """Deep copy as a dict of numpy arrays (checkpoint)."""
        return {fl.name: np.array(getattr(self, fl.name), copy=True) for fl in fields(self)}

    @classmethod
    def from_dict(cls, d: dict) -> "KernelState":
        """Restore (deep copy) from :meth:`to_dict` output.

        The shot records are read by field name (:func:`peenflow.fe.records.as_records`):
        a state whose records are a table by column position (written before
        2026-12-02) is refused with ValueError."""
        missing = [fl.name for fl in fields(cls) if fl.name not in d]
        if missing:
            raise ValueError(f"state dict lacks {missing}")
        out = {fl.name: np.array(d[fl.name], copy=True) for fl in fields(cls) if fl.name != "shot_records"}
        return cls(**out, shot_records=as_records(d["shot_records"]))

    def copy(self) -> "KernelState":
        return KernelState.from_dict(self.to_dict())

    def with_records(self, records: np.ndarray) -> "KernelState":
        d = {fl.name: getattr(self, fl.name) for fl in fields(self)}
        d["shot_records"] = records
        return KernelState(**d)
