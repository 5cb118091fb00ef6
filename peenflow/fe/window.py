"""The active window of an impact: its size, its validity, and its faces.

An impact integrates only an element box around the landing point (the
ACTIVE WINDOW, ``Options.window``; :func:`impact_window`): ``window_lateral``
x the estimated contact radius (:func:`contact_estimates`) laterally, plus
the shot's tangential travel, and ``window_depth`` x it in depth, but at
least ``window_min_elements`` elements and ``window_min_wave`` x the wave
travel during the contact each way (:func:`window_size`; a slow shot's
window would otherwise shrink to a few held elements: +5-6 % on the peak
force at 1-5 m/s, 0.4 % with the minimum). A window smaller than any
measured (:data:`WINDOW_VALIDATED`) is said so (:func:`window_validity`,
:class:`WindowValidityWarning`).

Its faces inside the mesh are held fixed (``Options.window_faces = None``,
default) or stand on the exterior through a viscous-spring boundary
(``Options.window_faces = ViscousSpringFaces()``, a variant passed in;
:func:`viscous_spring_boundary`): Lysmer-Kuhlemeyer dashpots absorb the
waves that held faces send back to the contact, springs carry the slow
contact load and the residual field, starting from the reaction that held
the faces; once the shot has left, the exterior elements on the faces are
told how far the faces moved (:func:`exterior_update`). It halves the
single-impact window error but is worse than held faces in sequences: on the
strip REV it makes 9-10 % more plastic strain than the full mesh and closes
the energy balance only to ~5 % of an impact energy, against 0.4 % with held
faces (docs/validation.md section 6, "In a sequence").
An optional absorbing layer along held faces: :func:`sponge`.

Measured window error (docs/validation.md section 6, "Window variants";
``python benchmarks/window.py error``; strip REV, 25 um, 55 m/s, one
impact, stiffness hourglass form): held faces dent depth +1.7 %,
restitution +3 %, averaged sigma_x profile 3.9 % (max abs difference / max
abs value); viscous-spring faces +1.0 %, -1.9 %, 1.8 %; for ~48x less work
per impact.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from peenflow.fe import solver as S
from peenflow.fe.boundary import TIED
from peenflow.fe.element import element_rows
from peenflow.fe.johnson_cook import Material
from peenflow.fe.safety import check_status
from peenflow.fe.shots import Shots, hertz, johnson_plastic

#: The window's measured envelope (docs/validation.md section 6, window error and
#: window size: strip REV, 25 um, 55 m/s, windows of 3-6 contact radii =
#: 12-24 elements, 0.07-0.15 c_p t_c; "Slow shots": 1 and 5 m/s,
#: 0.05 c_p t_c, force within 0.4 % of the full mesh): held faces at least
#: this many elements from the landing point, and at least this fraction of
#: the dilatational wave travel during the contact (``c_p t_c``) away. A run
#: whose window is smaller on either count gets a
#: :class:`WindowValidityWarning` (once per :class:`peenflow.fe.impact.ImpactRun`).
WINDOW_VALIDATED = {"elements": 12.0, "wave": 0.05}


class WindowValidityWarning(UserWarning):
    """A shot's active window is smaller than any the window error was measured for."""


def contact_estimates(shots: Shots, material: Material, vn: float, i: int = 0) -> tuple[float, float]:
    """(contact radius m, contact time s) estimates of shot ``i`` for window sizing (:func:`contact_estimate`)."""
    return contact_estimate(shots.radius_of(i), shots.mass_of(i), vn, material.E, material.nu, material.A)


def contact_estimate(radius: float, mass: float, normal_speed: float, E: float, nu: float,
                     yield_stress: float) -> tuple[float, float]:
    """(contact radius m, contact time s) of a rigid sphere (``radius`` m, ``mass`` kg) hitting at
    ``normal_speed`` (m s-1) a target of modulus ``E`` (Pa), Poisson ratio ``nu`` and initial yield
    stress ``yield_stress`` (Pa, Johnson-Cook A): the larger of the Hertz values and those of
    Johnson's fully plastic contact at mean pressure 3 A.  On floats, so the stage layer checks a
    study with the rule the kernel sizes its windows, seams and cores by."""
    h = hertz(radius, mass, max(normal_speed, 1e-9), E, nu)
    p = johnson_plastic(radius, mass, max(normal_speed, 1e-9), 3.0 * yield_stress)
    a = max(h["a"], p["a"])
    # plastic contact lasts about pi/2 sqrt(m / (2 pi R p)) ~ the Hertz time; take the larger
    tp = 0.5 * math.pi * math.sqrt(mass / (2.0 * math.pi * radius * 3.0 * yield_stress))
    return a, max(h["t"], tp)


def local_size(axis: np.ndarray, c: float) -> float:
    """Size (m) of the element of ``axis`` that holds coordinate ``c`` (the nearest end one outside)."""
    k = int(np.clip(np.searchsorted(axis, c), 1, len(axis) - 1))
    return float(axis[k] - axis[k - 1])


def window_size(model, material: Material, options, a_est: float, t_est: float,
                xc: float, yc: float) -> tuple[float, float, float]:
    """Window half widths along x, y and depth (m) for a shot landing at ``(xc, yc)``.

    The largest of: ``window_lateral`` (``window_depth``) contact radii,
    ``window_min_elements`` elements of the mesh there, and
    ``window_min_wave`` of the wave travel during the contact ``c_p t_c``.
    """
    m = model.mesh
    wave = options.window_min_wave * material.wave_speed * t_est
    n = options.window_min_elements
    lat_x = max(options.window_lateral * a_est, n * local_size(m.x, xc), wave)
    lat_y = max(options.window_lateral * a_est, n * local_size(m.y, yc), wave)
    depth = max(options.window_depth * a_est, float(m.z[min(int(math.ceil(n)), len(m.z) - 1)]), wave)
    return lat_x, lat_y, depth


def impact_window(model, material: Material, options, a_est: float, t_est: float, hit_xy, vel) -> np.ndarray:
    """The element box (i0 i1 j0 j1 k0 k1) integrated for a shot landing at ``hit_xy`` (m) with velocity
    ``vel`` (m/s): :func:`window_size` each way plus 1.5 contact times of tangential travel downstream, or
    the whole mesh without a window. On a periodic target a box that reaches the seam spans the period
    along that axis (the tying needs both sides)."""
    if options.window:
        travel = 1.5 * t_est * vel[0:2]
        lat_x, lat_y, depth = window_size(model, material, options, a_est, t_est, hit_xy[0], hit_xy[1])
        win = model.window_box(
            hit_xy[0], hit_xy[1],
            (lat_x + max(-travel[0], 0.0), lat_x + max(travel[0], 0.0)),
            (lat_y + max(-travel[1], 0.0), lat_y + max(travel[1], 0.0)),
            depth,
        )
    else:
        win = model.full_window
    if model.periodic:
        if win[0] == 0 or win[1] == model.nx:
            win[0], win[1] = 0, model.nx
        if win[2] == 0 or win[3] == model.ny:
            win[2], win[3] = 0, model.ny
    return win


#: peak damping rate of the absorbing layer (:func:`sponge`), x c_dilatational / layer thickness
SPONGE_DAMPING = 10.0


def sponge(model, material: Material, options, win: np.ndarray) -> tuple[int, float]:
    """(layers, peak damping rate 1/s) of the absorbing layer along the held faces of ``win``
    (``Options.window_sponge`` x the window's smaller extent, at least 2 layers of the finest
    element; :data:`SPONGE_DAMPING` x c_p / its thickness); (0, 0.0) when there is none."""
    if not (options.window and options.window_sponge > 0):
        return 0, 0.0
    m_ = model.mesh
    ext = min(0.5 * (m_.x[win[1]] - m_.x[win[0]]), 0.5 * (m_.y[win[3]] - m_.y[win[2]]), m_.z[win[5]])
    hmin = float(np.min(np.diff(m_.z)))
    n = max(2, int(round(options.window_sponge * ext / hmin)))
    return n, SPONGE_DAMPING * material.wave_speed / (n * hmin)


def window_validity(model, material: Material, win: np.ndarray, xc: float, yc: float,
                     t_est: float) -> str | None:
    """Why the window ``win`` lies outside :data:`WINDOW_VALIDATED` (None when it does not).

    Each held face counts: its distance from the landing point in elements of
    the mesh there, and as a fraction of the wave travel ``c_p t_c``."""
    m = model.mesh
    hold = model.hold_flags(win)
    hx, hy = local_size(m.x, xc), local_size(m.y, yc)
    faces = ((hold[0], xc - m.x[win[0]], hx), (hold[1], m.x[win[1]] - xc, hx), (hold[2], yc - m.y[win[2]], hy),
             (hold[3], m.y[win[3]] - yc, hy), (hold[5], m.z[win[5]], float(m.z[1] - m.z[0])))
    held = [(d, d / h) for flag, d, h in faces if flag]
    if not held:
        return None
    dist = min(d for d, _ in held)
    elements = min(e for _, e in held)
    wave = dist / (material.wave_speed * t_est)
    if elements >= WINDOW_VALIDATED["elements"] and wave >= WINDOW_VALIDATED["wave"]:
        return None
    return (f"its nearest held face is {elements:.1f} elements and {wave:.3f} x c_p t_c (the wave travel during "
            f"the {t_est * 1e6:.3g} us contact) from the landing point; the window error was measured only for "
            f">= {WINDOW_VALIDATED['elements']:g} elements and >= {WINDOW_VALIDATED['wave']:g} c_p t_c "
            "(docs/validation.md section 6). Raise Options.window_min_elements / window_min_wave / "
            "window_lateral, or run without a window (window=False) to check")


@dataclass(frozen=True)
class WindowBoundary:
    """Viscous-spring window faces (:func:`viscous_spring_boundary`).

    nodes : (nb,) node indices; stiffness : (nb, 3) N/m and damping :
    (nb, 3) N s/m per global component (diagonal: the faces are axis-aligned).
    """

    nodes: np.ndarray
    stiffness: np.ndarray
    damping: np.ndarray


#: what viscous-spring faces do once the shot has left (:func:`peenflow.fe.solver.run_phase`'s ``boundary_settle``)
SETTLE_CODES = {"viscous-spring": 0, "held": 1, "spring": 2}
SETTLE_SPRINGS = SETTLE_CODES["spring"]


@dataclass(frozen=True)
class ViscousSpringFaces:
    """Window faces on the exterior's springs and dashpots instead of held (``Options.window_faces``).

    A research variant passed in, not the default: better for a single impact, worse in sequences
    (module docstring; docs/validation.md section 6, "In a sequence"). Each shot's faces are
    :func:`viscous_spring_boundary` of its window. ``dashpot`` scales the dashpots, ``slab`` the
    springs' slab term (stiffness of the exterior between a face and a held mesh face; 0 = half-space
    springs only; 1 = the standard values). ``settle``: the faces while the window settles after the
    shot has left: "spring" (springs only: the dashpots would only slow the settling, 400 instead of
    240 steps on the strip REV), "viscous-spring" (both), "held" (frozen where they are; not
    recommended: the exterior then receives the faces' dynamic sag and yields).
    """

    dashpot: float = 1.0
    slab: float = 1.0
    settle: str = "spring"

    def __post_init__(self):
        for name in ("dashpot", "slab"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and not isinstance(value, bool) and value >= 0.0):
                raise ValueError(f"ViscousSpringFaces.{name} = {value!r}: expected a number in [0.0, inf)")
        if self.settle not in SETTLE_CODES:
            raise ValueError(f"ViscousSpringFaces.settle = {self.settle!r}: expected one of {tuple(SETTLE_CODES)}")

    @property
    def settle_code(self) -> int:
        return SETTLE_CODES[self.settle]

    def boundary(self, model, win: np.ndarray, source, eps_p: np.ndarray) -> "WindowBoundary | None":
        """The faces of window ``win`` around impact point ``source`` (:func:`viscous_spring_boundary`)."""
        return viscous_spring_boundary(model, win, source, dashpot=self.dashpot, slab=self.slab, eps_p=eps_p)


def viscous_spring_boundary(model, win: np.ndarray, source, *, spring: float = 1.0, dashpot: float = 1.0,
                            slab: float = 1.0, eps_p: np.ndarray | None = None) -> WindowBoundary | None:
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
    (docs/validation.md section 6). The springs let the window rest on
    something while the shot presses slowly (contact time >> wave
    transit) and while it settles. ``spring`` scales the springs,
    ``dashpot`` the dashpots, ``slab`` the slab term (1 = the values
    above). Nodes on two or three faces (edges, corners) add the faces'
    contributions.

    Given ``eps_p`` (n_elements,), face nodes touching an element that
    has already yielded stay held: there the frozen reaction acts as a
    dead load on material at yield, which soft springs cannot stop from
    flowing (a 20-shot sequence on the strip REV drifted such faces by
    7 um and ran away; docs/validation.md section 6, "The viscous-spring faces").

    Returns None when no face is interior (full mesh).
    """
    hold = model.hold_flags(win)
    if not hold.any():
        return None
    m = model.mesh
    mat = model.material
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
    X = model.nodes0.reshape(model.nnz, model.nny, model.nnx, 3)[k0:k1 + 1, j0:j1 + 1, i0:i1 + 1]
    R = np.sqrt((X[..., 0] - source[0]) ** 2 + (X[..., 1] - source[1]) ** 2 + X[..., 2] ** 2)
    R = np.maximum(R, float(np.min(np.diff(m.z))))
    M = rho * cp * cp
    sym = model.target.lateral == "symmetric"
    fixed = model.target.bottom == "fixed"
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
        ep = eps_p.reshape(model.nz, model.ny, model.nx)
        yielded = np.pad(ep > 0.0, 1)  # element (k, j, i) at [k + 1, j + 1, i + 1]
        near = np.zeros((model.nnz, model.nny, model.nnx), dtype=bool)
        for dk in (0, 1):
            for dj in (0, 1):
                for di in (0, 1):
                    near |= yielded[dk:dk + model.nnz, dj:dj + model.nny, di:di + model.nnx]
        on &= ~near[k0:k1 + 1, j0:j1 + 1, i0:i1 + 1]
    kk, jj, ii = np.nonzero(on)
    nodes = (ii + i0) + model.nnx * ((jj + j0) + model.nny * (kk + k0))
    stiff = stiff[kk, jj, ii]
    damp = damp[kk, jj, ii]
    if model.periodic and np.any(model.bc[nodes] & TIED):
        # a slave on a face (window spanning the period): its springs and dashpots act on its master
        mnodes = model.masters[nodes]
        uniq, inv = np.unique(mnodes, return_inverse=True)
        st_, dp_ = np.zeros((len(uniq), 3)), np.zeros((len(uniq), 3))
        np.add.at(st_, inv, stiff)
        np.add.at(dp_, inv, damp)
        nodes, stiff, damp = uniq, st_, dp_
    return WindowBoundary(nodes.astype(np.int64), np.ascontiguousarray(stiff), np.ascontiguousarray(damp))


def exterior_update(model, s, win, hold, bnodes, bx0, where, shot_index) -> None:
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
                                             model.vol0, model.mat_static, 1.0, model.nnx, model.nny, model.nx,
                                             model.ny, bi0, bi1, bj0, bj1, bk0, bk1)
        check_status(st, where=where + " (exterior update)", shot_index=shot_index,
                     time=float(s.ctl[S.C_TIME]))
        s.energy[S.E_INT] += wi
        s.energy[S.E_PL] += wp
        s.energy[S.E_HG] += wh
        s.energy[S.E_VISC] += wv
    s.v[:] = v_save
    s.f[:] = f_save
