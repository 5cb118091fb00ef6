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
from peenflow.fe.boundary import TIE_X, TIE_Y, TIED, check_periodic_mesh, node_fixity, tie_masters
from peenflow.fe.element import element_rows
from peenflow.fe.johnson_cook import M_RATE_ON, Material
from peenflow.fe.mesh import BoxMesh
from peenflow.fe.safety import check_status
from peenflow.fe.state import KernelState


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

    ``"periodic"`` ties the lateral faces (:mod:`peenflow.fe.boundary`) and
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
class WindowBoundary:
    """Viscous-spring window faces (:meth:`Model.window_boundary`).

    nodes : (nb,) node indices; stiffness : (nb, 3) N/m and damping :
    (nb, 3) N s/m per global component (diagonal: the faces are axis-aligned).
    """

    nodes: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray


@dataclass(frozen=True)
class PhaseResult:
    """Summary of one phase: ``info`` (solver.N_INFO,) and records (n, solver.N_REC)."""

    status: int
    info: np.ndarray
    records: np.ndarray


class Model:
    """Static arrays of a run (built once; not part of the checkpointed state)."""

    def __init__(self, target: Target, material: Material, *, hourglass=0.05, hourglass_plastic_floor=0.1,
                 bulk_linear=0.06, bulk_quadratic=1.5, hourglass_type="physical"):
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

    def roll(self, state: KernelState, sx: int, sy: int) -> None:
        """Periodic target: move the material by ``(-sx, -sy)`` whole elements, in place.

        What was at element column ``i`` is afterwards at ``(i - sx) mod nx``
        (rows likewise): the displacements ``x - X0``, velocities, forces and
        every element field are permuted; slaves are unfolded again. The
        target is translation-invariant laterally (uniform spacing), so a
        rolled state is the same physical state seen from another origin;
        ``roll(s, -sx, -sy)`` undoes it up to the round-off of ``x - X0``.
        """
        if not self.periodic:
            raise ValueError("roll: only a periodic target can be rolled")
        sx %= self.nx
        sy %= self.ny
        if sx == 0 and sy == 0:
            return
        nnz, nny, nnx, nz, ny, nx = self.nnz, self.nny, self.nnx, self.nz, self.ny, self.nx

        def nodal(a, unfold):
            # on a new array, assigned back (a reshape of a non-contiguous array would be a copy)
            a3 = np.array(a).reshape(nnz, nny, nnx, 3)
            u = np.roll(a3[:, :ny, :nx], (-sy, -sx), axis=(1, 2))
            a3[:, :ny, :nx] = u
            a3[:, :ny, nx] = u[:, :, 0] if unfold else 0.0
            a3[:, ny, :] = a3[:, 0, :] if unfold else 0.0
            a[:] = a3.reshape(a.shape)

        u = state.x - self.nodes0
        nodal(u, True)
        state.x[:] = self.nodes0 + u
        lx, ly = self.period
        slaves = self._slaves
        state.x[slaves] = state.x[self.masters[slaves]]
        state.x[slaves, 0] += np.where(self.bc[slaves] & TIE_X, lx, 0.0)
        state.x[slaves, 1] += np.where(self.bc[slaves] & TIE_Y, ly, 0.0)
        nodal(state.v, True)
        nodal(state.f, False)
        for a in (state.stress, state.eps_p, state.sy_static, state.hg, state.temp):
            a[:] = np.roll(a.reshape((nz, ny, nx) + a.shape[1:]), (-sy, -sx), axis=(1, 2)).reshape(a.shape)

    def periodic_shift(self, xl: float, yl: float, reach_x: tuple, reach_y: tuple) -> tuple[int, int]:
        """Whole-element shift ``(sx, sy)`` for :meth:`roll` that keeps
        ``[xl - reach_x[0], xl + reach_x[1]] x [...]`` clear of the seam: 0
        along an axis where that box already is (at least one element from
        it), else the one that brings ``xl`` (``yl``) to the middle column (row)."""
        out = []
        for c, (lo, hi), ax, n in ((xl, reach_x, self.mesh.x, self.nx), (yl, reach_y, self.mesh.y, self.ny)):
            if c - lo >= ax[1] and c + hi <= ax[-2]:
                out.append(0)
            else:
                h = (ax[-1] - ax[0]) / n
                out.append(int(math.floor((c - ax[0]) / h)) - n // 2)
        return out[0], out[1]

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
        boundary: "WindowBoundary | None" = None,
        boundary_settle: int = 0,
        where: str = "impact",
        shot_index=None,
        raise_on_error: bool = True,
    ) -> PhaseResult:
        """Run one phase on ``state`` (in place) and raise on instability.

        ``boundary``: viscous-spring window faces (:meth:`window_boundary`)
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
        check_status(st, where=where, shot_index=shot_index, time=float(s.ctl[S.C_TIME]))
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
            check_status(status, where=where, shot_index=shot_index, time=float(ctl[S.C_TIME]))
        if boundary is not None and status == S.ST_OK and len(bnodes) > 0:
            self._exterior_update(s, win, hold, bnodes, bx0, where, shot_index)
        return PhaseResult(int(status), info, rec[: int(info[S.I_NREC])].copy())

    def _exterior_update(self, s: KernelState, win, hold, bnodes, bx0, where, shot_index) -> None:
        """Let the exterior elements touching a viscous-spring face see how far its nodes moved.

        The exterior is not integrated during the phase, so without this the
        face nodes' displacement ``du`` would be lost to the elements on the
        other side (they would take their moved shape as stress-free: an
        eigenstrain at the window's edge, +50 MPa on the strip REV's
        averaged profile). One element pass over that layer of elements
        (rate term off) with ``v = du`` on the face nodes, ``v = 0`` on the
        others and a 1 s step applies it, as a static relaxation's
        correction would; the global relaxation then spreads it.
        """
        i0, i1, j0, j1, k0, k1 = (int(w) for w in win)
        a0, a1 = i0 - int(hold[0]), i1 + int(hold[1])
        b0, b1 = j0 - int(hold[2]), j1 + int(hold[3])
        boxes = [(a0, a1, b0, b1, k1, k1 + int(hold[5]))]  # below the window (with the corners)
        boxes += [(a0, i0, b0, b1, k0, k1), (i1, a1, b0, b1, k0, k1), (i0, i1, b0, j0, k0, k1), (i0, i1, j1, b1, k0, k1)]
        v_save = s.v.copy()
        f_save = s.f.copy()
        s.v[:] = 0.0
        s.v[bnodes] = s.x[bnodes] - bx0
        for bi0, bi1, bj0, bj1, bk0, bk1 in boxes:
            if bi1 <= bi0 or bj1 <= bj0 or bk1 <= bk0:
                continue
            _, st, wi, wp, wh, wv = element_rows(s.x, s.v, s.f, s.stress, s.eps_p, s.sy_static, s.hg, s.temp,
                                                 self.vol0, self.mat_static, 1.0, self.nnx, self.nny, self.nx,
                                                 self.ny, bi0, bi1, bj0, bj1, bk0, bk1)
            check_status(st, where=where + " (exterior update)", shot_index=shot_index,
                         time=float(s.ctl[S.C_TIME]))
            s.energy[S.E_INT] += wi
            s.energy[S.E_PL] += wp
            s.energy[S.E_HG] += wh
            s.energy[S.E_VISC] += wv
        s.v[:] = v_save
        s.f[:] = f_save

    def window_boundary(self, win: np.ndarray, source: np.ndarray, *, spring: float = 1.0,
                        dashpot: float = 1.0, slab: float = 1.0,
                        eps_p: np.ndarray | None = None) -> "WindowBoundary | None":
        """Viscous-spring boundary on the window faces interior to the mesh.

        Each node of such a face gets, per unit of its tributary area on the
        face: Lysmer-Kuhlemeyer dashpots ``rho c_p`` normal and ``rho c_s``
        tangential (they absorb waves hitting the face head-on), in parallel
        with springs ``alpha_N G / R + M / e`` normal and
        ``alpha_T G / R + G / e`` tangential. ``alpha G / R`` is the static
        stiffness of an exterior half-space seen from a point source (``R``
        the node's distance from ``source``, the impact point at z = 0;
        ``alpha_N = 4/3``, ``alpha_T = 2/3``: the 3-D viscous-spring
        boundary of Liu et al. 2006, Earthq. Eng. Eng. Vib. 5:93). ``M / e``
        and ``G / e`` (``M = rho c_p^2``) are those of the slab of thickness
        ``e`` between the face and the mesh face beyond it, counted only for
        the components that mesh face holds (normal for a symmetric side,
        all three for a fixed bottom): the exterior of a finite target is
        stiffer than a half-space, and a thin one (a window nearly as large
        as the mesh) should act almost as held faces. The sum reaches both
        limits; it is an interpolation, checked against full-mesh runs
        (BENCHMARKS.md section 2). The springs let the window rest on
        something while the shot presses slowly (contact time >> wave
        transit) and while it settles. ``spring`` scales the springs,
        ``dashpot`` the dashpots, ``slab`` the slab term (1 = the values
        above). Nodes on two or three faces (edges, corners) add the faces'
        contributions.

        Given ``eps_p`` (n_elements,), face nodes touching an element that
        has already yielded stay held: there the frozen reaction acts as a
        dead load on material at yield, which soft springs cannot stop from
        flowing (a 20-shot sequence on the strip REV drifted such faces by
        7 um and ran away; BENCHMARKS.md section 2).

        Returns None when no face is interior (full mesh).
        """
        hold = self.hold_flags(win)
        if not hold.any():
            return None
        m = self.mesh
        mat = self.material
        rho = mat.density
        G = mat.mu
        cp = mat.wave_speed
        cs = math.sqrt(G / rho)
        alpha_n, alpha_t = 4.0 / 3.0, 2.0 / 3.0
        i0, i1, j0, j1, k0, k1 = (int(w) for w in win)

        def trib(ax, lo, hi):
            idx = np.arange(lo, hi + 1)
            return 0.5 * (ax[np.minimum(idx + 1, hi)] - ax[np.maximum(idx - 1, lo)])

        tx, ty, tz = trib(m.x, i0, i1), trib(m.y, j0, j1), trib(m.z, k0, k1)
        X = self.nodes0.reshape(self.nnz, self.nny, self.nnx, 3)[k0:k1 + 1, j0:j1 + 1, i0:i1 + 1]
        R = np.sqrt((X[..., 0] - source[0]) ** 2 + (X[..., 1] - source[1]) ** 2 + X[..., 2] ** 2)
        R = np.maximum(R, float(np.min(np.diff(m.z))))
        M = rho * cp * cp
        sym = self.target.lateral == "symmetric"
        fixed = self.target.bottom == "fixed"
        stiff = np.zeros(X.shape)
        damp = np.zeros(X.shape)
        on = np.zeros(X.shape[:3], dtype=bool)
        # faces: (hold flag, normal axis, node slice, tributary area, distance to the mesh face beyond,
        #         that mesh face holds the normal / the tangential components)
        faces = (
            (hold[0], 0, np.s_[:, :, 0], np.outer(tz, ty), X[:, :, 0, 0] - m.x[0], sym, False),
            (hold[1], 0, np.s_[:, :, -1], np.outer(tz, ty), m.x[-1] - X[:, :, -1, 0], sym, False),
            (hold[2], 1, np.s_[:, 0, :], np.outer(tz, tx), X[:, 0, :, 1] - m.y[0], sym, False),
            (hold[3], 1, np.s_[:, -1, :], np.outer(tz, tx), m.y[-1] - X[:, -1, :, 1], sym, False),
            (hold[4], 2, np.s_[0, :, :], np.outer(ty, tx), X[0, :, :, 2] - m.z[0], False, False),
            (hold[5], 2, np.s_[-1, :, :], np.outer(ty, tx), m.z[-1] - X[-1, :, :, 2], fixed, fixed),
        )
        for held, d, sl, area, e, n_held, t_held in faces:
            if not held:
                continue
            on[sl] = True
            kn = alpha_n * G / R[sl] + (slab * M / e if n_held else 0.0)
            kt = alpha_t * G / R[sl] + (slab * G / e if t_held else 0.0)
            for c in range(3):
                stiff[sl + (c,)] += spring * area * (kn if c == d else kt)
                damp[sl + (c,)] += dashpot * rho * area * (cp if c == d else cs)
        if eps_p is not None:
            # nodes touching a yielded element (any of the up to 8 around it) stay held
            ep = eps_p.reshape(self.nz, self.ny, self.nx)
            yielded = np.pad(ep > 0.0, 1)  # element (k, j, i) at [k + 1, j + 1, i + 1]
            near = np.zeros((self.nnz, self.nny, self.nnx), dtype=bool)
            for dk in (0, 1):
                for dj in (0, 1):
                    for di in (0, 1):
                        near |= yielded[dk:dk + self.nnz, dj:dj + self.nny, di:di + self.nnx]
            on &= ~near[k0:k1 + 1, j0:j1 + 1, i0:i1 + 1]
        kk, jj, ii = np.nonzero(on)
        nodes = (ii + i0) + self.nnx * ((jj + j0) + self.nny * (kk + k0))
        stiff = stiff[kk, jj, ii]
        damp = damp[kk, jj, ii]
        if self.periodic and np.any(self.bc[nodes] & TIED):
            # a slave on a face (window spanning the period): its springs and dashpots act on its master
            mnodes = self.masters[nodes]
            uniq, inv = np.unique(mnodes, return_inverse=True)
            st_, dp_ = np.zeros((len(uniq), 3)), np.zeros((len(uniq), 3))
            np.add.at(st_, inv, stiff)
            np.add.at(dp_, inv, damp)
            nodes, stiff, damp = uniq, st_, dp_
        return WindowBoundary(nodes.astype(np.int64), np.ascontiguousarray(stiff), np.ascontiguousarray(damp))

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
