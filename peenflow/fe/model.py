"""The static part of a run: mesh arrays, masses, fixities, material vector.

:class:`Model` is built once per run from the user's target, material and
options, and offers :meth:`Model.phase`, one call of the numba loop
(:func:`peenflow.fe.solver.run_phase`) on a :class:`KernelState`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from peenflow.fe import solver as S
from peenflow.fe.boundary import TIED, node_fixity
from peenflow.fe.johnson_cook import BULK_LINEAR, BULK_QUADRATIC, M_RATE_ON, Material
from peenflow.fe.mesh import BoxMesh
from peenflow.fe.periodic import check_periodic_mesh, tie_masters
from peenflow.fe.safety import check_status
from peenflow.fe.state import KernelState
from peenflow.fe.window import WindowBoundary, exterior_update


_MULTIGRID_CACHE: dict = {}

# Below this many elements in the active window a step is run serially even
# when threads > 1. Every step of the parallel element pass is a fork/join per
# row colour; when the step's work is small (5 M element-updates/s per core:
# 20 000 elements = 4 ms) the join costs more than it saves, and on a machine
# with other jobs a late thread stalls every step by a scheduler time slice.
# Measured: a coarse (60 um) strip run of 80 windowed impacts took 11.6-11.9 s
# serial against 68-101 s on 2 threads with the second core busy.
PARALLEL_MIN_ELEMENTS = 20_000


@dataclass(frozen=True)
class Target:
    """The target: a structured mesh and its boundary conditions.

    mesh : BoxMesh (m);  lateral : "symmetric" | "free" | "periodic";  bottom : "fixed" | "free".

    ``"periodic"`` ties the lateral faces (:mod:`peenflow.fe.periodic`) and
    needs a uniform lateral spacing along x and y (ValueError otherwise):
    the driver moves the state by whole elements so that each impact's
    window stays clear of the seam (:func:`peenflow.fe.impact.run_impacts`).
    """

    mesh: BoxMesh
    lateral: str = "symmetric"
    bottom: str = "fixed"

    def __post_init__(self):
        if self.lateral not in ("symmetric", "free", "periodic"):
            raise ValueError(f"lateral must be 'symmetric', 'free' or 'periodic', not {self.lateral!r}")
        if self.bottom not in ("fixed", "free"):
            raise ValueError(f"bottom must be 'fixed' or 'free', not {self.bottom!r}")
        if self.lateral == "periodic":
            check_periodic_mesh(self.mesh)

    @property
    def periodic(self) -> bool:
        return self.lateral == "periodic"


@dataclass(frozen=True)
class PhaseResult:
    """Summary of one phase: ``info`` (solver.N_INFO,) and records (n, solver.N_REC)."""

    status: int
    info: np.ndarray
    records: np.ndarray


class Model:
    """Static arrays of a run (built once; not part of the checkpointed state)."""

    def __init__(self, target: Target, material: Material, *, hourglass=0.05, hourglass_plastic_floor=0.1,
                 bulk_linear=BULK_LINEAR, bulk_quadratic=BULK_QUADRATIC, hourglass_type="physical"):
        mesh = target.mesh
        self.target = target
        self.mesh = mesh
        self.material = material
        self.nodes0 = mesh.node_coordinates()
        self.centroids = mesh.element_centroids()
        self.vol0 = mesh.element_volumes()
        self.bc = node_fixity(mesh, target.lateral, target.bottom)
        self.periodic = target.periodic
        self.nnx, self.nny, self.nnz = mesh.shape_nodes
        mass = mesh.lumped_mass(material.density)
        if self.periodic:
            # a master moves with its slaves' mass; a slave's own entry is 0
            self.masters = tie_masters(self.bc, self.nnx, self.nny)
            self._slaves = np.nonzero(self.bc & TIED)[0]
            tied = mass.copy()
            tied[self._slaves] = 0.0
            np.add.at(tied, self.masters[self._slaves], mass[self._slaves])  # in node order: deterministic
            mass = tied
            self.period = (float(mesh.x[-1] - mesh.x[0]), float(mesh.y[-1] - mesh.y[0]))
        else:
            self.masters = None
            self.period = None
        #: lumped nodal masses (kg); periodic: a master's includes its slaves', a slave's is 0
        self.mass = mass
        self.mat = material.to_array(bulk_linear, bulk_quadratic, hourglass, hourglass_plastic_floor, hourglass_type)
        self.mat_static = self.mat.copy()
        self.mat_static[M_RATE_ON] = 0.0
        self.nx, self.ny, self.nz = mesh.shape_elements
        self.cand = np.zeros(self.nnx * self.nny, dtype=np.int64)
        self.dn = np.zeros((self.nnx * self.nny, 4))
        self._multigrid = None

    def multigrid(self):
        """The multigrid hierarchy of the static relaxation (built on first use,
        then kept; shared by models with the same mesh, fixities and material)."""
        if self._multigrid is None:
            from peenflow.fe.multigrid import Multigrid

            key = tuple(np.ascontiguousarray(a).tobytes() for a in (self.mesh.x, self.mesh.y, self.mesh.z, self.bc,
                                                                    self.mat_static))
            mg = _MULTIGRID_CACHE.get(key)
            if mg is None:
                mg = Multigrid(self.mesh, self.bc, self.mat_static, periodic=self.periodic)
                _MULTIGRID_CACHE.clear()  # keep one: a hierarchy of the strip REV is ~100 MB
                _MULTIGRID_CACHE[key] = mg
            self._multigrid = mg
        return self._multigrid

    def fold(self, f: np.ndarray) -> np.ndarray:
        """Periodic target: add each slave's entry of ``f`` (n_nodes, 3) to its
        master's and zero it (in place, fixed order); other targets: unchanged."""
        if self.periodic:
            slaves = self._slaves
            np.add.at(f, self.masters[slaves], f[slaves])
            f[slaves] = 0.0
        return f

    def unfold(self, u: np.ndarray) -> np.ndarray:
        """Periodic target: copy each master's entry of ``u`` to its slaves (in place)."""
        if self.periodic:
            u[self._slaves] = u[self.masters[self._slaves]]
        return u

    def new_state(self) -> KernelState:
        m = self.material
        from peenflow.fe.johnson_cook import static_flow_stress, thermal_factor

        sy0 = static_flow_stress(0.0, thermal_factor(m.initial_temperature, self.mat), self.mat)
        return KernelState.initial(self.nodes0, self.mesh.n_elements, sy0, m.initial_temperature)

    @property
    def full_window(self) -> np.ndarray:
        return np.array([0, self.nx, 0, self.ny, 0, self.nz], dtype=np.int64)

    def hold_flags(self, win: np.ndarray) -> np.ndarray:
        """Window faces interior to the mesh are held fixed (order i0 i1 j0 j1 k0 k1)."""
        return np.array(
            [win[0] > 0, win[1] < self.nx, win[2] > 0, win[3] < self.ny, win[4] > 0, win[5] < self.nz], dtype=np.int64
        )

    def window_box(self, xc: float, yc: float, half_x: tuple, half_y: tuple, depth: float) -> np.ndarray:
        """Element index box covering ``[xc - half_x[0], xc + half_x[1]] x [...] x [0, depth]``."""
        m = self.mesh
        i0 = max(0, int(np.searchsorted(m.x, xc - half_x[0], side="right")) - 1)
        i1 = min(self.nx, int(np.searchsorted(m.x, xc + half_x[1], side="left")))
        j0 = max(0, int(np.searchsorted(m.y, yc - half_y[0], side="right")) - 1)
        j1 = min(self.ny, int(np.searchsorted(m.y, yc + half_y[1], side="left")))
        k1 = min(self.nz, int(np.searchsorted(m.z, depth, side="left")))
        return np.array([i0, max(i1, i0 + 1), j0, max(j1, j0 + 1), 0, max(k1, 1)], dtype=np.int64)

    def phase(
        self,
        state: KernelState,
        mode: int,
        win: np.ndarray,
        shot: np.ndarray,
        *,
        safety: float,
        alpha: float,
        rest_ke: float,
        rest_v: float,
        e_ref: float,
        force_scale: float = 1.0,
        dt_floor_fraction: float = 0.05,
        runaway: float = 0.25,
        max_steps: int = 1_000_000,
        record_every: int = 0,
        record_capacity: int = 0,
        threads: int = 1,
        sponge_layers: int = 0,
        sponge_alpha: float = 0.0,
        boundary: WindowBoundary | None = None,
        boundary_settle: int = 0,
        where: str = "impact",
        shot_index=None,
        raise_on_error: bool = True,
    ) -> PhaseResult:
        """Run one phase on ``state`` (in place) and raise on instability.

        ``boundary``: viscous-spring window faces
        (:func:`peenflow.fe.window.viscous_spring_boundary`)
        instead of held ones; their frozen reactions are taken here, from the
        window's element forces at the current state; ``boundary_settle``:
        what they do once the shot has left (0 springs and dashpots, 1 held,
        2 springs only; :func:`peenflow.fe.solver.run_phase`).
        """
        win = np.ascontiguousarray(win, dtype=np.int64)
        if win[3] - win[2] < 2 or win[5] - win[4] < 2:
            # the element pass reports no stable step for a box one element row thick (y or z)
            raise ValueError(f"phase: the integrated element box {tuple(int(w) for w in win)} must be at least 2 "
                             "elements along y and z (a mesh or window one element thick)")
        if self.periodic:
            for a, (lo, hi, n) in enumerate(((win[0], win[1], self.nx), (win[2], win[3], self.ny))):
                if (lo == 0) != (hi == n):
                    raise ValueError(
                        f"periodic target: a window that reaches the lateral seam must span the period along "
                        f"{'xy'[a]} (element box {tuple(int(w) for w in win)}); the driver moves the state so "
                        "that windows stay clear of the seam")
        hold = self.hold_flags(win)
        s = state
        # forces and stable step at the current state, from the window's elements
        s.f[:] = 0.0
        dt0, st = S.initial_dt(s.x, s.v, s.f, s.stress, s.eps_p, s.sy_static, s.hg, s.temp, self.vol0, self.mat,
                               self.nnx, self.nny, self.nx, self.ny, win)
        check_status(st, where=where, shot_index=shot_index, time=float(s.ctl[S.C_TIME]),
                     relaxing=mode == S.MODE_RELAX)
        self.fold(s.f)
        if boundary is None:
            bnodes = np.zeros(0, dtype=np.int64)
            bk = bcd = bf0 = bx0 = np.zeros((0, 3))
        else:
            bnodes, bk, bcd = boundary.nodes, boundary.stiffness, boundary.damping
            # the exterior's reaction that held the faces: balances the window's forces at the start
            bf0 = -s.f[bnodes]
            bx0 = s.x[bnodes].copy()
        ctl = s.ctl
        ctl[S.C_DT_PREV] = 0.0
        ctl[S.C_DT_NEXT] = dt0
        ctl[S.C_SAFETY] = safety
        ctl[S.C_ALPHA] = alpha
        ctl[S.C_REST_KE] = rest_ke
        ctl[S.C_REST_V] = rest_v
        ctl[S.C_E_REF] = e_ref
        ctl[S.C_DT_FLOOR] = dt_floor_fraction * safety * dt0
        ctl[S.C_RUNAWAY] = runaway
        ctl[S.C_OMEGA_C2] = 0.0
        ctl[S.C_FORCE_SCALE] = force_scale
        ctl[S.C_SPONGE_W] = sponge_layers
        ctl[S.C_SPONGE_A] = sponge_alpha
        info = np.zeros(S.N_INFO)
        rec = np.zeros((max(record_capacity, 1), S.N_REC))
        active = int((win[1] - win[0]) * (win[3] - win[2]) * (win[5] - win[4]))
        parallel = threads > 1 and active >= PARALLEL_MIN_ELEMENTS
        if parallel:
            numba.set_num_threads(threads)
        status = S.run_phase(
            mode, parallel, max_steps, record_every if record_capacity > 0 else 0,
            s.x, s.v, s.f, self.mass, self.bc, s.stress, s.eps_p, s.sy_static, s.hg, s.temp, self.vol0, self.mat, self.mat_static,
            self.mesh.x, self.mesh.y, self.nnx, self.nny, self.nx, self.ny, win, hold,
            shot, ctl, s.energy, rec, info, self.cand, self.dn, bnodes, bk, bcd, bf0, bx0, boundary_settle,
            self.periodic,
        )
        if raise_on_error:
            check_status(status, where=where, shot_index=shot_index, time=float(ctl[S.C_TIME]),
                         relaxing=mode == S.MODE_RELAX)
        if boundary is not None and status == S.ST_OK and len(bnodes) > 0:
            exterior_update(self, s, win, hold, bnodes, bx0, where, shot_index)
        return PhaseResult(int(status), info, rec[: int(info[S.I_NREC])].copy())

    def settle_alpha(self, win: np.ndarray, settle_damping: float) -> float:
        """Mass-proportional damping rate (1/s) for settling a window / the mesh.

        ``alpha = settle_damping * pi * c_shear / L`` with ``L`` the window's
        largest extent (lateral half width or depth): about twice the lowest
        shear-mode frequency of the held box, i.e. near-critical damping of
        the slowest mode; higher modes are damped at ``alpha / 2`` per second.
        """
        m = self.mesh
        lx = m.x[win[1]] - m.x[win[0]]
        ly = m.y[win[3]] - m.y[win[2]]
        lz = m.z[win[5]] - m.z[win[4]]
        L = max(0.5 * lx, 0.5 * ly, lz)
        cs = math.sqrt(self.material.mu / self.material.density)
        return settle_damping * math.pi * cs / L
