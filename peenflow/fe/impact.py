"""Driver: a sequence of rigid shots on an explicit FE target (the kernel's public API).

    result = run_impacts(target, material, shots, options)

or step by step, as a caller that drives its own sequence does (shot
ladders, checkpoints at its own times; ``tasks/_rev_run.py``)::

    run = ImpactRun(target, material, options, state=None)  # set up a model (or resume)
    record = run.impact(shots, run.shots_done)              # one impact -> ShotRecord (named fields)
    snapshot = run.snapshot(shots)                          # a relaxed copy -> Snapshot
    state = run.checkpoint()                                # dict of arrays: ImpactRun(..., state=state)
    result = run.result(shots)                              # final relaxation -> ImpactRunResult

:func:`run_impacts` is the loop over these steps.

Event-driven time (one shot at a time, in the given order):

1. The target is at rest. The next shot flies in a straight line to the
   exact instant it first touches a top-surface node (:func:`time_to_contact`);
   no target step is taken during free flight. It is placed
   :data:`LEAD_STEPS` stable steps before that instant, on its line (a
   given centre that already overlaps a pile-up is put back upstream: the
   shot comes from far away; :func:`time_to_contact`).
2. Impact phase on the ACTIVE WINDOW (``options.window``), an element box
   around the landing point sized in estimated contact radii, elements and
   wave travel, held or viscous-spring faces (:mod:`peenflow.fe.window`;
   measured errors there and in docs/validation.md section 6); elements outside
   are not integrated. ``window=False`` integrates the whole mesh.
3. When the shot has left (no node in contact, moving away) the window is
   damped (mass-proportional, :meth:`Model.settle_alpha`) until AT REST:
   ``KE_window <= rest_ke_fraction * E_impact`` AND
   ``max |v| <= rest_v_fraction * |v_shot|``. The shot is then discarded and
   its :class:`~peenflow.fe.records.ShotRecord` kept in the state.
4. A snapshot (:meth:`ImpactRun.snapshot`: at each count in
   ``snapshot_after``) and the result bring a COPY of the state to static
   equilibrium over the whole mesh (:mod:`peenflow.fe.relaxation`): the
   global relaxation before reading a profile is mandatory, the measuring
   region is wider than a window (~10 s on the strip REV).

Periodic lateral faces (``Target(lateral="periodic")``): before a shot
whose window would reach the seam the state is rolled by whole elements to
bring the landing point to the middle of the mesh, and rolled back once the
shot has settled (:mod:`peenflow.fe.periodic`). The recorded window
(``win_*``) is in the target's frame and may extend past the mesh (it
wraps); recorded shot centres likewise. No symmetric mass fraction applies.
"""

from __future__ import annotations

import math
import numbers
import time as _time
import warnings
from dataclasses import dataclass
from typing import Callable

import numpy as np

from peenflow.fe import solver as S
from peenflow.fe.contact import MIRROR_X, MIRROR_Y, N_SHOT, S_I, S_M, S_MIRROR, S_MU, S_R
from peenflow.fe.johnson_cook import Material
from peenflow.fe.model import Model, Target
from peenflow.fe.periodic import roll, seam_shift
from peenflow.fe.records import SHOT_RECORD_DTYPE, SHOT_RECORD_FIELDS, ShotRecord, record_columns, records_array
from peenflow.fe.relaxation import relax
from peenflow.fe.shots import Shots, time_to_contact
from peenflow.fe.state import KernelState
from peenflow.fe.window import (SETTLE_SPRINGS, WINDOW_VALIDATED, ViscousSpringFaces, WindowValidityWarning,
                                contact_estimates, impact_window, sponge, window_validity)

#: a shot starts this many stable steps before it touches (its free flight is skipped up to there)
LEAD_STEPS = 2

__all__ = ["Options", "ImpactRun", "ImpactRunResult", "Snapshot", "ShotRecord", "run_impacts", "reference_scales",
           "Target", "Material", "Shots", "WindowValidityWarning", "WINDOW_VALIDATED", "SHOT_RECORD_FIELDS",
           "SHOT_RECORD_DTYPE"]


@dataclass(frozen=True)
class Options:
    """Numerical options (all dimensionless unless stated).

    dt_safety : fraction of the stable step (recomputed every step).
    friction : Coulomb coefficient shot/target (paper: 0.2).
    hourglass_type : hourglass control of the one-point hexahedron: "physical"
      (default: assumed-strain stabilisation from the element's elastic-plastic
      tangent, co-rotational, no coefficient; pure bending exact; single-impact
      errors docs/validation.md section 4) or "stiffness" (Flanagan-Belytschko
      stiffness form with ``hourglass`` and ``hourglass_plastic_floor``, the
      default before 2026-12: dent -5.8 % instead of -2.4 % at 25 um, 55 m/s).
      Bulk viscosity: the kernel's own coefficients
      (:data:`peenflow.fe.johnson_cook.BULK_LINEAR`, ``BULK_QUADRATIC``).
    hourglass : Flanagan-Belytschko stiffness coefficient Q_hg (stiffness form only).
    hourglass_plastic_floor : lowest factor on the hourglass stiffness of a
      yielding element (the factor is the element's actual/elastic deviatoric
      stress increment; 1 = plain elastic hourglass stiffness).
    window : integrate only an active window around each impact.
    window_lateral, window_depth : window half width / depth in estimated contact radii.
    window_min_elements : the window's half width and depth are at least this
      many elements (of the mesh at the landing point). Sized in contact radii
      only, a slow shot's window shrinks to a few elements (1 m/s on 60 um:
      2 x 2 x 1), which meets a limit of the element pass (one element thick:
      no stable step, "NaN or Inf"). 3, not more: on the 100 um micro study
      6 made every window the whole 12-element REV and changed its arc-height
      curves (docs/validation.md section 6, "Slow shots").
    window_min_wave : ... and at least this fraction of the distance a
      dilatational wave travels during the estimated contact (``c_p t_c``):
      the held faces must not sit much closer, in wave transit, than in the
      cases the window was measured for (:data:`WINDOW_VALIDATED`).
    window_warning : warn (:class:`WindowValidityWarning`, once per call)
      when a window is smaller than that. Callers whose window sizes are
      chosen and measured at a higher level (a study's fidelity preset) turn
      it off; the result's ``window_outside_validated`` says it all the same.
    window_sponge : absorbing layer along the held window faces, as a fraction
      of the window's smaller extent (half width or depth); 0 = none (its peak
      damping: :data:`peenflow.fe.window.SPONGE_DAMPING`).
    window_faces : the window faces inside the mesh: None (held fixed;
      default) or a variant passed in, :class:`peenflow.fe.window.ViscousSpringFaces`
      (Lysmer-Kuhlemeyer dashpots in parallel with half-space + slab springs on
      top of the frozen reaction that held them). Better for a single impact,
      worse in sequences (docs/validation.md section 6, "In a sequence"), hence
      not the default and set by no stage.
    settle_damping : damping factor for settling after each impact (x pi c_s / L).
    rest_ke_fraction, rest_v_fraction : "at rest" after an impact (x impact energy / speed).
    relax_method : global relaxation (snapshots, end): "static" (default:
      multigrid-preconditioned defect correction on the true forces,
      :mod:`peenflow.fe.relaxation`; ~10x cheaper on the strip REV) or
      "dynamic" (damped dynamic relaxation; used anyway when the bottom is
      not fixed, or when the static loop does not converge).
    relax_ke_fraction : "at rest" for global relaxations, x the largest
      impact energy: static -- estimated elastic energy of the remaining force
      imbalance (1/2 r . K^-1 r); dynamic -- kinetic energy. Default 1e-7:
      averaged residual profile within 0.04 % of its peak of a strict
      reference either way (docs/performance.md section 3).
    relax_cg_rtol, relax_max_outer : static method: relative residual of each
      linear (CG + multigrid) solve (0.3: loose, 1-3 V-cycles; the outer loop
      corrects on the true forces, so a tighter inner solve only costs
      V-cycles, docs/performance.md section 3), most corrections before falling
      back to dynamic relaxation.
    relax_damping, relax_v_fraction : dynamic method: damping factor (x pi
      c_s / L), max speed <= relax_v_fraction x the largest shot speed.
    final_relaxation : relax the whole mesh after the last shot (False: the
      result fields are the unrelaxed final state; for timing and callers
      that relax themselves).
    threads : numba threads for the element loop (1 = serial kernel).
    record : keep per-step histories (contact force, shot trajectory, energies).
    record_every : record one step in this many.
    max_steps : step budget per phase.
    dt_floor_fraction, runaway_fraction : safety thresholds (see safety.py).
    """

    dt_safety: float = 0.9
    friction: float = 0.2
    hourglass_type: str = "physical"
    hourglass: float = 0.05
    hourglass_plastic_floor: float = 0.1
    window: bool = True
    window_lateral: float = 4.0
    window_depth: float = 4.0
    window_min_elements: float = 3.0
    window_min_wave: float = 0.05
    window_warning: bool = True
    window_sponge: float = 0.0
    window_faces: ViscousSpringFaces | None = None
    settle_damping: float = 1.0
    rest_ke_fraction: float = 1e-6
    rest_v_fraction: float = 1e-4
    relax_method: str = "static"
    relax_damping: float = 1.0
    relax_ke_fraction: float = 1e-7
    relax_v_fraction: float = 1e-4
    relax_cg_rtol: float = 0.3
    relax_max_outer: int = 20
    final_relaxation: bool = True
    threads: int = 1
    record: bool = False
    record_every: int = 1
    max_steps: int = 2_000_000
    dt_floor_fraction: float = 0.05
    runaway_fraction: float = 0.25

    def __post_init__(self):
        # (field, lowest, lowest allowed?, highest or None): checked before any compute, and
        # written so that NaN fails too
        ranges = (
            ("dt_safety", 0.0, False, 1.0), ("friction", 0.0, True, None), ("hourglass", 0.0, True, None),
            ("hourglass_plastic_floor", 0.0, False, 1.0), ("window_lateral", 0.0, False, None),
            ("window_depth", 0.0, False, None), ("window_min_elements", 2.0, True, None),
            ("window_min_wave", 0.0, True, None), ("window_sponge", 0.0, True, 1.0),
            ("settle_damping", 0.0, False, None), ("rest_ke_fraction", 0.0, False, None),
            ("rest_v_fraction", 0.0, False, None), ("relax_damping", 0.0, False, None),
            ("relax_ke_fraction", 0.0, False, None), ("relax_v_fraction", 0.0, False, None),
            ("relax_cg_rtol", 0.0, False, 1.0), ("relax_max_outer", 1, True, None),
            ("threads", 1, True, None), ("record_every", 1, True, None), ("max_steps", 1, True, None),
            ("dt_floor_fraction", 0.0, True, 1.0), ("runaway_fraction", 0.0, False, None),
        )
        for name, low, closed, high in ranges:
            value = getattr(self, name)
            ok = isinstance(value, numbers.Real) and not isinstance(value, bool) and (
                value >= low if closed else value > low) and (high is None or value <= high)
            if not ok:
                interval = f"{'[' if closed else '('}{low}, {'inf)' if high is None else f'{high}]'}"
                raise ValueError(f"Options.{name} = {value!r}: expected a number in {interval}")
        if self.window_faces is not None and not isinstance(self.window_faces, ViscousSpringFaces):
            raise ValueError(f"Options.window_faces = {self.window_faces!r}: expected None (held faces) or a "
                             "peenflow.fe.window.ViscousSpringFaces")
        for name, allowed in (("hourglass_type", ("physical", "stiffness")), ("relax_method", ("static", "dynamic"))):
            if getattr(self, name) not in allowed:
                raise ValueError(f"Options.{name} = {getattr(self, name)!r}: expected one of {allowed}")


@dataclass(frozen=True)
class Snapshot:
    """Relaxed target after ``n_shots`` shots.

    stress : (n_elements, 6) Pa (xx yy zz yz xz xy); eps_p : (n_elements,);
    displacement : (n_nodes, 3) m.
    """

    n_shots: int
    stress: np.ndarray
    eps_p: np.ndarray
    displacement: np.ndarray


@dataclass(frozen=True)
class ImpactRunResult:
    """What :func:`run_impacts` returns (SI units).

    stress : (n_elements, 6) Pa, relaxed residual stress, Voigt xx yy zz yz xz xy.
    eps_p : (n_elements,) equivalent plastic strain.
    displacement : (n_nodes, 3) m, relaxed nodal displacements.
    centroids : (n_elements, 3) m, reference element centroids.
    nodes : (n_nodes, 3) m, reference node positions.
    snapshots : {n_shots: Snapshot}.
    shots : dict of per-shot arrays, keys ``SHOT_RECORD_FIELDS`` (:class:`ShotRecord`: hit bool, steps and
      win_* int, the rest float; times s,
      velocities m/s, restitution = -v_out,z / v_in,z, max_approach m = deepest
      point of the shot below z = 0, max_overlap m, peak_force N (full shot),
      max_contact_radius m (farthest node in contact; quantised by the node
      spacing), contact_radius m (Hertz-equivalent radius sqrt(5/2 <r^2>) from
      the normal-impulse distribution at peak force), hourglass_peak (peak hourglass energy / impact energy),
      internal_peak (peak internal energy / impact energy), spin_in_* / spin_out_* rad/s (the shot's
      spin before and after the impact; on a symmetry plane the components it cannot hold are 0),
      energy_error = max |balance error| / impact energy, window_validated = the window was inside
      :data:`WINDOW_VALIDATED`).
    histories : list (one per shot, if options.record) of dicts of arrays:
      time s, force (n,3) N on the shot, centre (n,3) m, velocity (n,3) m/s,
      ke_target, ke_shot, w_int, w_plastic, w_hourglass, w_viscous, e_contact,
      e_damping (J), dt s.
    energy : dict of cumulative energies (J) of the final state before relaxation.
    hourglass_ratio : peak hourglass energy / peak internal energy of an impact,
      the largest over the shots (elastic runs too: the final W_hourglass / W_int
      of an elastic run is noise, e.g. -0.45); per shot: shots["hourglass_peak"] /
      shots["internal_peak"].
    energy_error : largest per-shot energy balance error / impact energy.
    final_state : KernelState (unrelaxed; resume from it).
    wall_time : s.
    window_outside_validated : "" or why the first shot whose active window was
      smaller than any the window error was measured for is outside
      (:data:`WINDOW_VALIDATED`).
    """

    stress: np.ndarray
    eps_p: np.ndarray
    displacement: np.ndarray
    centroids: np.ndarray
    nodes: np.ndarray
    snapshots: dict
    shots: dict
    histories: list
    energy: dict
    hourglass_ratio: float
    energy_error: float
    final_state: KernelState
    wall_time: float
    window_outside_validated: str = ""


def _shot_vector(shots: Shots, i: int, model: Model, friction: float) -> tuple[np.ndarray, float]:
    """Kernel shot vector and the modelled mass fraction (symmetry planes)."""
    s = np.zeros(N_SHOT)
    s[0:3] = shots.centres[i]
    s[3:6] = shots.velocities[i]
    s[6:9] = shots.spins[i]
    frac = 1.0
    mirror = 0
    m = model.mesh
    if model.target.lateral == "symmetric":
        tol = 1e-9 * (m.x[-1] - m.x[0])
        for val, lo, hi, flag in ((s[0], m.x[0], m.x[-1], MIRROR_X), (s[1], m.y[0], m.y[-1], MIRROR_Y)):
            if abs(val - lo) <= tol or abs(val - hi) <= tol:
                frac *= 0.5
                mirror |= flag
    held = ([3, 7, 8] if mirror & MIRROR_X else []) + ([4, 6, 8] if mirror & MIRROR_Y else [])
    # round-off (cos 90 deg) is cleared; a real component is refused
    radius = shots.radius_of(i)
    scale = 1e-9 * (np.linalg.norm(s[3:6]) + np.linalg.norm(s[6:9]) * radius + 1e-30)
    if held and np.any(np.abs(s[held]) * np.where(np.array(held) >= 6, radius, 1.0) > scale):
        raise ValueError(f"shot {i} lies on a symmetry plane of the mesh but its velocity/spin "
                         f"{s[3:9].tolist()} has components that plane cannot hold (v normal to it, "
                         "spin about axes in it): use a larger model or align the shot with the plane")
    s[held] = 0.0
    s[S_MIRROR] = mirror
    s[S_M] = shots.mass_of(i) * frac
    s[S_I] = shots.inertia_of(i) * frac
    s[S_R] = radius
    s[S_MU] = friction
    return s, frac


def _hourglass_ratio(rec: np.ndarray) -> float:
    """Largest over the shots that touched of (peak hourglass energy / peak internal energy) of the impact.

    Peaks, not the final energies: in an elastic impact both return to ~0 once
    the shot has left, and their final ratio is noise of either sign."""
    hit = rec["hit"] & (rec["internal_peak"] > 0)
    return float(np.max(rec["hourglass_peak"][hit] / rec["internal_peak"][hit])) if np.any(hit) else 0.0


def reference_scales(shots: Shots) -> tuple[float, float]:
    """(energy J, speed m/s) that scale the global relaxations' rest criteria: the largest impact
    energy and shot speed of ``shots`` (1, 1 for no shots)."""
    if not len(shots):
        return 1.0, 1.0
    v2 = np.sum(shots.velocities**2, axis=1)
    # 0.5 m max(v^2) for one radius; a size spread takes the largest per-shot energy
    return float(np.max(0.5 * shots.mass * v2)), float(np.sqrt(np.max(v2)))


class ImpactRun:
    """The small steps of the driver: a target set up for impacts and the state they act on.

        run = ImpactRun(target, material, options, state=None)   # set up (or resume)
        record = run.impact(shots, run.shots_done)               # one shot -> ShotRecord
        snap = run.snapshot(shots)                               # relaxed copy -> Snapshot
        run.checkpoint()                                         # state dict (resume from it)
        result = run.result(shots)                               # final relaxation -> ImpactRunResult

    :func:`run_impacts` is the loop over these. A caller that drives its own
    sequence (shot ladders, checkpoints at its own times) uses them directly;
    resuming from :meth:`checkpoint` with the same inputs gives bit-identical
    results.

    Attributes: ``model`` (:class:`Model`, static arrays), ``options``,
    ``state`` (:class:`KernelState`, unrelaxed, changed in place by each
    impact; its ``shot_records`` are refreshed by :meth:`checkpoint`),
    ``histories`` (per-step histories of the impacts of this object, if
    ``options.record``), ``window_note`` ("" or why the first window of this
    object outside :data:`WINDOW_VALIDATED` is).
    """

    def __init__(self, target: Target, material: Material, options: Options = Options(), *,
                 state: dict | KernelState | None = None):
        self.options = options
        self.material = material
        self.model = model = Model(
            target, material, hourglass=options.hourglass, hourglass_type=options.hourglass_type,
            hourglass_plastic_floor=options.hourglass_plastic_floor)
        if state is None:
            st = model.new_state()
        elif isinstance(state, KernelState):
            st = state.copy()
        else:
            st = KernelState.from_dict(state)
        if st.x.shape != model.nodes0.shape or st.stress.shape[0] != model.mesh.n_elements:
            raise ValueError("restored state does not match the target mesh")
        self.state = st
        self._records = [ShotRecord.from_row(r) for r in st.shot_records]
        self.histories: list[dict] = []
        self.window_note = ""

    @property
    def shots_done(self) -> int:
        """Number of shots processed (the index of the next one)."""
        return int(self.state.shot_index[0])

    @property
    def records(self) -> np.ndarray:
        """The shot records so far, (shots_done,) structured array (:data:`SHOT_RECORD_DTYPE`)."""
        return records_array(self._records)

    def impact(self, shots: Shots, i: int) -> ShotRecord:
        """Fly shot ``i`` of ``shots`` onto the target at rest, run the impact, settle; return its record.

        ``i`` must be :attr:`shots_done` (shots are processed in order, each once).
        Raises KernelInstabilityError (NaN, negative volume, distortion, step
        collapse, runaway energy, a phase that never settles) or ValueError
        (a shot the model cannot hold: symmetry plane, period too short).
        """
        if i != self.shots_done:
            raise ValueError(f"ImpactRun.impact: shot {i} is not the next one (shots_done = {self.shots_done})")
        model, options, material, st = self.model, self.options, self.material, self.state
        top = model.nnx * model.nny
        shot, frac = _shot_vector(shots, i, model, options.friction)
        vel = shot[3:6].copy()
        speed = float(np.linalg.norm(vel))
        e_imp = 0.5 * shots.mass_of(i) * speed**2 * frac
        spin_in = shot[6:9].copy()  # components a symmetry plane cannot hold are 0
        sx = sy = 0
        if model.periodic and vel[2] > 0:
            sx, sy = seam_shift(model, shot, vel, shots, material, options, i)
            if sx or sy:
                roll(model, st, sx, sy)
                # the shot moves with the material; one landing beyond the domain wraps into it
                shot[0] -= sx * model.mesh.x_step
                shot[1] -= sy * model.mesh.y_step
        t_hit = time_to_contact(st.x[:top], shot[0:3].copy(), vel, shots.radius_of(i)) if speed > 0 else math.inf
        common = dict(shot_index=i, vin_x=vel[0], vin_y=vel[1], vin_z=vel[2], impact_energy=e_imp / frac,
                      spin_in_x=spin_in[0], spin_in_y=spin_in[1], spin_in_z=spin_in[2])
        if not math.isfinite(t_hit):  # missed the target
            rec = ShotRecord(hit=False, spin_out_x=spin_in[0], spin_out_y=spin_in[1], spin_out_z=spin_in[2],
                             **common)
        else:
            rec = self._contact(shots, i, shot, vel, speed, e_imp, frac, t_hit, (sx, sy), common)
        if sx or sy:
            roll(model, st, -sx, -sy)
        st.shot_index[0] = i + 1
        self._records.append(rec)
        return rec

    def _contact(self, shots, i, shot, vel, speed, e_imp, frac, t_hit, shift, common) -> ShotRecord:
        """The impact phase of a shot that will touch at ``t_hit`` (s from now); its record."""
        model, options, material, st = self.model, self.options, self.material, self.state
        # event-driven skip: free flight to just before contact
        a_est, t_est = contact_estimates(shots, material, abs(vel[2]), i)
        dt_est = options.dt_safety * float(np.min(np.diff(model.mesh.z))) / material.wave_speed
        lead = LEAD_STEPS * dt_est
        # negative when the given centre overlaps the surface: the shot is
        # put back on its line (time_to_contact), the clock never runs back
        t_fly = t_hit - lead
        shot[0:3] += vel * t_fly
        st.ctl[S.C_TIME] += max(t_fly, 0.0)
        hit_xy = shot[0:2] + vel[0:2] * (t_hit - t_fly)
        win = impact_window(model, material, options, a_est, t_est, hit_xy, vel)
        why = window_validity(model, material, win, hit_xy[0], hit_xy[1], t_est) if options.window else None
        if why is not None and not self.window_note:  # said once per ImpactRun, recorded for every shot
            self.window_note = f"shot {i}: {why}"
            if options.window_warning:
                warnings.warn(f"shot {i}: the active window {tuple(int(w) for w in win)} (element box) is "
                              f"outside what it was validated for: {why}", WindowValidityWarning, stacklevel=3)
        sponge_n, sponge_a = sponge(model, material, options, win)
        faces = options.window_faces if options.window else None
        boundary = None if faces is None else faces.boundary(model, win, hit_xy, st.eps_p)
        res = model.phase(
            st, S.MODE_IMPACT, win, shot,
            safety=options.dt_safety,
            alpha=model.settle_alpha(win, options.settle_damping),
            rest_ke=options.rest_ke_fraction * e_imp,
            rest_v=options.rest_v_fraction * speed,
            e_ref=e_imp,
            force_scale=1.0 / frac,
            dt_floor_fraction=options.dt_floor_fraction,
            runaway=options.runaway_fraction,
            max_steps=options.max_steps,
            record_every=options.record_every,
            record_capacity=200_000 if options.record else 0,
            threads=options.threads,
            sponge_layers=sponge_n,
            sponge_alpha=sponge_a,
            boundary=boundary,
            boundary_settle=SETTLE_SPRINGS if faces is None else faces.settle_code,
            where="impact",
            shot_index=i,
        )
        info = res.info
        sx, sy = shift
        w = win + np.array([sx, sx, sy, sy, 0, 0])  # periodic: may extend beyond the mesh (wraps)
        if options.record:
            r = res.records
            self.histories.append({
                "time": r[:, 0], "force": r[:, 1:4], "centre": r[:, 4:7], "velocity": r[:, 7:10],
                "ke_target": r[:, 10], "ke_shot": r[:, 11], "w_int": r[:, 12], "w_plastic": r[:, 13],
                "w_hourglass": r[:, 14], "w_viscous": r[:, 15], "e_contact": r[:, 16], "e_damping": r[:, 17],
                "dt": r[:, 18], "mass_fraction": frac,
            })
            if sx or sy:
                self.histories[-1]["centre"] += np.array([sx * model.mesh.x_step, sy * model.mesh.y_step, 0.0])
        return ShotRecord(
            hit=bool(info[S.I_T_CONTACT] >= 0),
            t_contact=info[S.I_T_CONTACT], t_separate=info[S.I_T_SEPARATE],
            contact_duration=info[S.I_T_SEPARATE] - info[S.I_T_CONTACT],
            vout_x=info[S.I_VX], vout_y=info[S.I_VY], vout_z=info[S.I_VZ],
            restitution=-info[S.I_VZ] / vel[2] if vel[2] != 0 else np.nan,
            max_approach=info[S.I_MAX_APPROACH], max_overlap=info[S.I_MAX_OVERLAP],
            peak_force=info[S.I_PEAK_FORCE], max_contact_radius=info[S.I_MAX_RADIUS],
            steps=int(info[S.I_STEPS]), energy_error=info[S.I_E_ERR] / e_imp,
            win_i0=w[0], win_i1=w[1], win_j0=w[2], win_j1=w[3], win_k0=w[4], win_k1=w[5],
            contact_radius=math.sqrt(2.5 * info[S.I_R2_AT_PEAK]),
            hourglass_peak=info[S.I_HG_PEAK] / e_imp, internal_peak=info[S.I_INT_PEAK] / e_imp,
            # the phase leaves the rebound spin in the shot vector
            spin_out_x=shot[6], spin_out_y=shot[7], spin_out_z=shot[8],
            window_validated=why is None,
            **common,
        )

    def snapshot(self, reference: Shots, *, where: str | None = None) -> Snapshot:
        """A copy of the state brought to static equilibrium over the whole mesh (the run's state is untouched).

        ``reference``: the shots whose largest impact energy and speed scale the
        rest criteria (:func:`reference_scales`; the run's shots)."""
        n = self.shots_done
        rs, _ = relax(self.model, self.state, self.options, *reference_scales(reference),
                      where=where or f"snapshot relaxation after {n} shots")
        return Snapshot(n, rs.stress.copy(), rs.eps_p.copy(), rs.x - self.model.nodes0)

    def checkpoint(self) -> dict[str, np.ndarray]:
        """The full state as a dict of numpy arrays, records included (resume from it)."""
        return self._final_state().to_dict()

    def _final_state(self) -> KernelState:
        return self.state.with_records(self.records)

    def result(self, reference: Shots, *, snapshots: dict | None = None, wall_time: float = 0.0) -> ImpactRunResult:
        """The run so far as an :class:`ImpactRunResult`: the state relaxed over the whole mesh
        (``options.final_relaxation``; rest criteria scaled by ``reference``, :meth:`snapshot`)."""
        final = self._final_state()
        model = self.model
        if self.options.final_relaxation:
            rs, _ = relax(model, final, self.options, *reference_scales(reference), where="final relaxation")
        else:
            rs = final
        rec = final.shot_records
        en = final.energy
        energy = {"w_int": en[S.E_INT], "w_plastic": en[S.E_PL], "w_hourglass": en[S.E_HG],
                  "w_viscous": en[S.E_VISC], "e_contact": en[S.E_CONTACT], "e_damping": en[S.E_DAMP]}
        return ImpactRunResult(
            stress=rs.stress.copy(),
            eps_p=rs.eps_p.copy(),
            displacement=rs.x - model.nodes0,
            centroids=model.centroids,
            nodes=model.nodes0,
            snapshots=dict(snapshots or {}),
            shots=record_columns(rec),
            histories=list(self.histories),
            energy=energy,
            hourglass_ratio=_hourglass_ratio(rec),
            energy_error=float(np.max(rec["energy_error"][rec["hit"]])) if np.any(rec["hit"]) else 0.0,
            final_state=final,
            wall_time=wall_time,
            window_outside_validated=self.window_note,
        )


def run_impacts(
    target: Target,
    material: Material,
    shots: Shots,
    options: Options = Options(),
    *,
    state: dict | KernelState | None = None,
    snapshot_after=(),
    on_shot_done: Callable | None = None,
) -> ImpactRunResult:
    """Simulate ``shots`` hitting ``target`` one after the other; return the relaxed residual state.

    Parameters
    ----------
    target : Target -- mesh (m) + boundary conditions.
    material : Material -- elastic constants + Johnson-Cook parameters (eq. 1).
    shots : Shots -- centres (n,3) m, velocities (n,3) m/s, radius m, density kg/m^3, spins.
    options : Options -- numerics.
    state : a dict from :meth:`ImpactRun.checkpoint` / ``KernelState.to_dict()`` (or a
        KernelState) to resume from; shots before its ``shot_index`` are skipped.
    snapshot_after : shot counts (e.g. 10, 20, 40) after which a relaxed copy is stored.
    on_shot_done : ``f(shot_index, state_exporter)`` called between shots, after
        shot ``shot_index`` (0-based) has settled; ``state_exporter()`` returns
        the full state as a dict of numpy arrays (checkpoint). Resuming from
        that dict with the same inputs gives bit-identical results. Per-shot
        records travel in the state; snapshots do not (a resumed run returns
        the snapshots taken after the resume point, the caller keeps earlier ones).

    The loop over :class:`ImpactRun`'s steps; the rest criteria of every
    relaxation are scaled by the largest impact of ``shots``.

    Raises
    ------
    KernelInstabilityError : NaN, negative volume, distortion, step collapse,
        runaway energy, or a phase that never settles.
    """
    t_wall = _time.perf_counter()
    run = ImpactRun(target, material, options, state=state)
    snap_set = {int(n) for n in snapshot_after}
    snapshots = {}
    for i in range(run.shots_done, len(shots)):
        run.impact(shots, i)
        if i + 1 in snap_set:
            snapshots[i + 1] = run.snapshot(shots)
        if on_shot_done is not None:
            on_shot_done(i, run.checkpoint)
    return run.result(shots, snapshots=snapshots, wall_time=_time.perf_counter() - t_wall)
