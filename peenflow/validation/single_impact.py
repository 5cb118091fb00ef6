"""The single-impact validation cases: one S230 shot on a block, refined until the figures stop
changing; the converged reference of each case; the keys its runs are stored under.

Cases (rate term off, friction 0.2, S230 shot D = 0.58 mm, 7800 kg/m^3): 25 and 55 m/s normal and
55 m/s at 45 deg on SAE 1070; 47 m/s at 65 deg on Al 7075-T73 (the paper's Table 2). Target: the
6D x 6D x 1.29 mm block, fixed bottom, symmetric sides, no window; normal impacts on the quarter
model, oblique ones on the half model (both equal the full block to 1e-5, tests/fe/test_symmetry.py).
Fine zone of cubic elements ``h`` to 0.3 mm laterally (0.45 mm along the stream for oblique shots)
and 0.3 mm deep, graded 1.2 outside (:func:`block`). The figures of a run: :mod:`.readings`.

A run's key: ``CASE/ELEMENT/H`` (the shot aimed at a node), ``CASE/physical-offset/H/OFFSET`` (aimed
``OFFSET`` elements off it), ``CASE/physical-core/H/HC/HALF/DEPTH`` (a finer core under the shot),
``CASE/physical-studycore/H/HC[/fineF]`` (the core a study makes), ``CASE/physical-fine/H/F`` (a wider
fine zone). The measured runs: :func:`peenflow.validation.runs.single_impact`; the driver that makes
and tables them: ``benchmarks/single_impact.py``.
"""

from __future__ import annotations

import time

import numpy as np

from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots
from peenflow.testing import AL7075_T73, SAE1070 as SAE1070_LIBRARY

from .readings import PROFILE_DEPTH, metrics

#: shot radius m and diameter m (S230)
R = 0.29e-3
D = 2 * R
SAE1070 = {**SAE1070_LIBRARY, "C": 0.0}  # paper Table 1 (the library's), rate-independent here
AL7075 = AL7075_T73  # paper Table 2 (the library's): C = 0, m = 0
CASES = {  # name: (material, speed m/s, angle to the surface deg)
    "sae-25-90": (SAE1070, 25.0, 90.0),
    "sae-55-90": (SAE1070, 55.0, 90.0),
    "sae-55-45": (SAE1070, 55.0, 45.0),
    "sae-55-30": (SAE1070, 55.0, 30.0),
    "al-47-65": (AL7075, 47.0, 65.0),
}
ELEMENTS = {  # name: Options fields
    "stiffness": dict(hourglass_type="stiffness", hourglass=0.05, hourglass_plastic_floor=0.1),
    "physical": dict(hourglass_type="physical"),
}


def cored(axis: np.ndarray, fine: float, h: float, hc: float, core: float) -> np.ndarray:
    """``axis`` (nodes on [0, ...], elements ``h`` up to ``fine`` m) with elements ``hc`` m up to
    ``core`` m, growing by at most 1.2 per element to ``h`` before ``fine``; the nodes beyond
    ``fine`` are kept as they are, so the block outside the fine zone is the same (:func:`block`)."""
    inner = graded_axis(core, hc, fine, 1.2, h_max=h)
    return np.concatenate([inner, axis[axis > fine * (1 + 1e-9)]])


#: the tables' fine zone across the stream and in depth, mm (:func:`block`)
FINE_ZONE_MM = 0.3


def block(h: float, oblique: bool, surface_layers: tuple[float, float] | None = None,
          core: tuple[float, float, float] | None = None, study_core=None,
          fine_zone: float = FINE_ZONE_MM * 1e-3) -> BoxMesh:
    """Quarter (normal) or half (oblique; y >= 0) model of the 6D x 6D x 1.29 mm block.

    ``surface_layers``: (depth, layer thickness) m of thinner top layers (the ``variants`` of
    ``benchmarks/single_impact_diagnostics.py``); ``core``: (element size, half width, depth) m of a
    finer core under the shot (:data:`CORES`; along the stream of an oblique shot the same half width
    either side of the aim); ``study_core``: a :class:`tasks._impact_core.ImpactCore`, graded as a
    study grades it (:data:`STUDY_CORES`);
    ``fine_zone``: extent (m) of the uniform fine zone across the stream and in depth (along the stream
    of an oblique shot 0.15 mm more): :data:`FINE_ZONE_MM`, the tables' block, leaves no room for a core's grading
    back to 50 um elements, which a study's fine zone (0.6 of 3 D laterally, 0.75-1 D deep) has."""
    half, depth, fine_depth = 3 * D, 1.29e-3, max(PROFILE_DEPTH, fine_zone)
    lat = graded_axis(fine_zone, h, half, 1.2)
    z = graded_axis(fine_depth, h, depth, 1.2)
    along = graded_axis(fine_zone + 0.15e-3, h, half, 1.2)
    if surface_layers is not None:
        top, hz = surface_layers
        rest = graded_axis(fine_depth - top, h, depth - top, 1.2, start=top)
        z = np.concatenate([np.arange(0.0, top + 1e-12, hz), rest[1:]])
    if core is not None:
        hc, core_half, core_depth = core
        lat, along = cored(lat, 0.3e-3, h, hc, core_half), cored(along, 0.45e-3, h, hc, core_half)
        z = cored(z, fine_depth, h, hc, core_depth)
    if study_core is not None:
        from tasks._impact_core import cored_axis

        c = study_core
        lat, along = (cored_axis(a, h, c.element_size_m, c.half_width_m, 1.2) for a in (lat, along))
        z = cored_axis(z, h, c.element_size_m, c.depth_m, 1.2)
    if not oblique:
        return BoxMesh(lat, lat.copy(), z)
    return BoxMesh(np.concatenate([-along[::-1], along[1:]]), lat, z)


def run(case: str, element: str, h_um: float, offset: float = 0.0, friction: float | None = None,
        surface_layers: tuple[float, float] | None = None, core: tuple[float, float, float] | None = None,
        study_core_um: float | None = None, fine_zone: float = FINE_ZONE_MM * 1e-3) -> dict:
    """One run of ``case``; ``offset``: the shot's aim along the plane of incidence in elements from a
    node (0: on a node, the tables' runs; else on the half model, normal impacts too); ``friction``:
    the Coulomb coefficient if not the kernel's default 0.2; ``surface_layers``: thinner top layers
    (:func:`block`; on the half model); ``core``: a finer core under the shot (:func:`block`);
    ``study_core_um``: a core of that element size sized and graded as a study's
    ``fidelity.dent_refinement = "core"`` makes it (:mod:`tasks._impact_core`); ``fine_zone``: the
    block's fine zone (m, :func:`block`). Returns the figures of :func:`.readings.metrics` with the
    process CPU s and wall s of the impact (the kernels compiled beforehand), the element count and
    the command that makes the run."""
    mat, speed, angle = CASES[case]
    oblique = angle != 90.0 or offset != 0.0 or surface_layers is not None
    th = np.radians(angle)
    shots = Shots(centres=[[offset * h_um * 1e-6, 0.0, -R - 1e-6]],
                  velocities=[speed * np.array([np.cos(th), 0.0, np.sin(th)])], radius=R, density=7800.0)
    study_core = None
    if study_core_um is not None:
        from tasks._impact_core import core_for

        study_core = core_for(Material(**mat), shots, speed, angle, study_core_um * 1e-6)
    mesh = block(h_um * 1e-6, oblique, surface_layers, core, study_core, fine_zone)
    extra = {} if friction is None else {"friction": friction}
    opt = Options(window=False, record=True, record_every=20, **ELEMENTS[element], **extra)
    # compile (or load) the kernels outside the timing: a tiny impact on a 100 um mesh
    tiny = BoxMesh(*(np.arange(5) * 1e-4,) * 2, np.arange(4) * 1e-4)
    run_impacts(Target(tiny), Material(**mat), Shots(centres=[[0, 0, -R - 1e-6]], velocities=[[0, 0, 5.0]],
                                                     radius=R, density=7800.0), opt)
    t0 = time.process_time()
    w0 = time.perf_counter()
    res = run_impacts(Target(mesh), Material(**mat), shots, opt)
    out = metrics(res, mesh)
    out.update(cpu_s=time.process_time() - t0, wall_s=time.perf_counter() - w0, elements=mesh.n_elements,
               command=f"python benchmarks/single_impact.py run {case} {element} {h_um:g}"
                       + (f" {offset:g}" if offset else ""), offset_elements=offset)
    return out


def friction(v: dict, case: str, mu: float = 0.2) -> dict:
    """The Coulomb friction's share of a run ``v`` of ``case`` (friction coefficient ``mu``, the kernel's
    default 0.2), from the shot's rebound alone.

    ``ratio``: friction impulse over normal impulse. Normal impulses point at the shot's centre and give
    it no moment, so the friction impulse is ``I |omega_y| / R = 2/5 m R |omega_y|`` (spin about y, the
    only one the half model's plane holds); the normal impulse is the shot's normal momentum change
    ``m (v_in,z - v_out,z)``. Coulomb's law makes the ratio ``<= mu`` node by node, ``= mu`` where the
    contact slides throughout (over a dent whose walls tilt the normal, within a few per cent).
    ``slip_out``: the contact point's velocity along the surface at separation, ``v_out,x + omega_y R``
    (m/s; > 0: still sliding). A rigid sphere sliding throughout loses ``mu dv_n`` of its tangential
    speed and gains ``5/2 mu dv_n / R`` of spin (``dv_n = v_in,z - v_out,z``), so its contact point
    slows by ``7/2 mu dv_n``: ``slip_rigid`` = ``v_in,x - 7/2 mu dv_n``, > 0 when it slides throughout
    (at 30 deg and mu = 0.2: v_t / v_n = 1.73 against 7/2 mu (1 + e) = 1.1; at 45 deg: 1.0 against 1.05,
    the contact reaches rolling)."""
    _, speed, angle = CASES[case]
    th = np.radians(angle)
    dvn = speed * np.sin(th) - v["vout_z"]
    return dict(ratio=0.4 * R * abs(v["spin_out_y"]) / dvn, slip_out=v["vout_x"] + v["spin_out_y"] * R,
                slip_rigid=speed * np.cos(th) - 3.5 * mu * dvn)


#: shot aims, in elements from a node along the plane of incidence, of the ``offsets`` runs, and
#: their element sizes um
OFFSETS = (0.0, 0.25, 0.5, 0.75)
OFFSET_SIZES = (60.0, 50.0, 40.0, 25.0, 12.5)


def offset_key(case: str, h_um: float, offset: float) -> str:
    return f"{case}/physical-offset/{h_um:g}/{offset:g}"


#: finer cores under the shot (element size, half width, depth um) on a 25 um block (``cores`` runs)
CORES = ((12.5, 150.0, 100.0), (12.5, 150.0, 150.0), (12.5, 200.0, 100.0), (6.25, 150.0, 100.0))


def core_key(case: str, h_um: float, core_um: tuple[float, float, float]) -> str:
    return f"{case}/physical-core/{h_um:g}/" + "/".join(f"{c:g}" for c in core_um)


#: core element sizes (um) of the cores a study makes (``study-cores`` runs)
STUDY_CORES = (12.5, 6.25)


def study_core_key(case: str, h_um: float, hc_um: float, fine_mm: float = FINE_ZONE_MM) -> str:
    return f"{case}/physical-studycore/{h_um:g}/{hc_um:g}" + ("" if fine_mm == FINE_ZONE_MM else f"/fine{fine_mm:g}")


def fine_zone_key(case: str, h_um: float, fine_mm: float) -> str:
    """Key of the uncored ``h_um`` block with a fine zone of ``fine_mm`` (``study-cores`` runs)."""
    return f"{case}/physical-fine/{h_um:g}/{fine_mm:g}"


#: the figures a run is compared on: key, table label, kind ("rel": relative error, "abs": difference)
QUANTITIES = (
    ("dent_um", "dent", "rel"), ("dent_radius_mm", "dent radius", "rel"), ("sxx_peak_mpa", "σxx peak", "rel"),
    ("sxx_peak_depth_mm", "peak depth", "rel"), ("zero_depth_mm", "zero crossing", "rel"),
    ("crest_radius_mm", "crest radius", "rel"), ("crest_height_um", "crest height", "rel"),
    ("restitution", "restitution", "abs"),
)


def error(v: dict, ref: dict, key: str, kind: str) -> float:
    """Error of run ``v`` against ``ref`` in ``key``: relative ("rel") or a difference ("abs")."""
    return v[key] - ref[key] if kind == "abs" else v[key] / ref[key] - 1.0


def kind_of(key: str) -> str:
    """The kind (:data:`QUANTITIES`) of figure ``key``."""
    return next(kind for k, _, kind in QUANTITIES if k == key)


def reference(data: dict, case: str) -> tuple[dict, str]:
    """Converged reference of a case: the finest physical-element run, Richardson-extrapolated per
    quantity where h, h/2, h/4 converge monotonically with an order in [1, 3] (else the finest value)."""
    levels = sorted((float(k.split("/")[2]), v) for k, v in data.items() if k.startswith(f"{case}/physical/"))
    if not levels:
        return {}, "none"
    ref = dict(levels[0][1])
    note = f"{levels[0][0]:g} um physical"
    if len(levels) >= 3:
        f3, f2, f1 = (lv[1] for lv in levels[:3])
        extr = []
        for key, _, _ in QUANTITIES:
            a, b, c = f1[key], f2[key], f3[key]
            if (a - b) * (b - c) > 0 and abs(b - c) > 0:
                p = np.log2((a - b) / (b - c))
                if 1.0 <= p <= 3.0:
                    ref[key] = c + (c - b) / (2**p - 1)
                    extr.append(key)
        if extr:
            note += "; Richardson on " + ", ".join(extr)
    return ref, note


