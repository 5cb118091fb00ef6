"""The kernel benchmarks' shared cases: the shot, the strip REV, the REVs a study builds, the state an
element pass is timed on, and the layer profile every window / relaxation error is read on.

S230 shot (R = 0.29 mm, 7800 kg/m^3) on SAE 1070 (paper Table 1, the study library's). The drivers
(``benchmarks/element_rate.py``, ``strip_rev.py``, ``window.py``, ``springback.py``, ``hertz.py``,
``plastic.py``, ``stability.py``, ``dense_sequence.py``) print their figures beside the machine's load
(:func:`loadavg`): their timings are only as good as the machine was idle.
"""

from __future__ import annotations

import numpy as np

from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import BoxMesh, graded_axis
from peenflow.testing import SAE1070  # paper Table 1, from the study library

__all__ = ["R", "REV_6D_STANDARD", "SAE1070", "STUDY_REVS", "element_pass_state", "layer_profile", "loadavg",
           "strip_rev_mesh", "study_rev_run"]

#: shot radius m (S230)
R = 0.29e-3


def loadavg() -> str:
    """The machine's 1-minute load average, as printed beside the timings."""
    with open("/proc/loadavg") as f:
        return f.read().split()[0]


def element_pass_state(mesh: BoxMesh, plastic: bool) -> dict:
    """The arrays of one element pass over ``mesh`` (``peenflow.fe.element.element_rows`` arguments by
    name): velocities of a uniform velocity gradient, SAE 1070; ``plastic``: a gradient 1000x larger
    and a stored flow stress of 1 kPa, so that every element yields in every pass once its stress has
    reached the yield surface (about the 20th pass from zero stress)."""
    X = mesh.node_coordinates()
    n, ne = mesh.n_nodes, mesh.n_elements
    mat = Material(**SAE1070)
    G = np.array([[1.0, 0.2, 0.0], [0.0, -0.5, 0.1], [0.3, 0.0, -0.5]]) * (1e5 if plastic else 1e2)
    v = X @ G.T
    sy = np.full(ne, 1e3 if plastic else 1e12)  # plastic: every element yields every step
    return dict(x=X, v=v, f=np.zeros((n, 3)), stress=np.zeros((ne, 6)), eps_p=np.zeros(ne) + 0.1, sy=sy,
                hg=np.zeros((ne, 12)), temp=np.full(ne, 293.0), vol0=mesh.element_volumes(), mat=mat.to_array())



def strip_rev_mesh(h=25e-6, fine_depth=0.3e-3):
    """Strip REV 6D x 6D x h_strip = 3.48 x 3.48 x 1.29 mm, uniform h laterally, graded (1.2) below fine_depth."""
    half = 1.74e-3
    lat = np.linspace(-half, half, int(round(2 * half / h)) + 1)
    z = graded_axis(fine_depth, h, 1.29e-3, 1.2)
    return BoxMesh(lat, lat.copy(), z)


def layer_profile(res, mesh, half=0.58e-3):
    """(centroid depths m, sigma_xx Pa) averaged per element layer over the central 2 ``half`` x 2 ``half``
    measuring region (default 2D x 2D) of a result or state with ``stress`` (n_elements, 6)."""
    c = mesh.element_centroids()
    sel = (np.abs(c[:, 0]) <= half) & (np.abs(c[:, 1]) <= half)
    zs = np.unique(c[:, 2])
    return zs, np.array([res.stress[sel & (c[:, 2] == z), 0].mean() for z in zs])


#: a REV row: (label, material, angle deg, speed m/s, REV thickness m, preset, element um, REV side mm,
#: lateral faces). The paper's fixed 6D x 6D strip REV with the standard preset:
REV_6D_STANDARD = ("strip, symmetric 3.48 mm (6D)", "SAE1070", 90.0, 55.0, 1.29e-3, "standard", 25.0, 3.48, "symmetric")
#: the REVs the shipped studies make (periodic 1.2 mm: paper_fast*.toml, the study-level references; a
#: 3 d_min symmetric REV, d_min ~ 0.6 mm: the rev.rule = "dmin" default; the paper's fixed 6D x 6D strip REV)
STUDY_REVS = (("strip, periodic 1.2 mm", "SAE1070", 90.0, 55.0, 1.29e-3, "standard", 25.0, 1.2, "periodic"),
              ("strip, periodic 1.2 mm", "SAE1070", 90.0, 55.0, 1.29e-3, "standard", 40.0, 1.2, "periodic"),
              ("strip, periodic 1.2 mm", "SAE1070", 90.0, 55.0, 1.29e-3, "paper", 25.0, 1.2, "periodic"),
              ("Al 7075 target, periodic 1.2 mm", "AL7075_T73", 65.0, 30.0, 0.9e-3, "standard", 25.0, 1.2, "periodic"),
              ("strip, symmetric 1.8 mm (3 d_min)", "SAE1070", 90.0, 55.0, 1.29e-3, "standard", 25.0, 1.8, "symmetric"),
              REV_6D_STANDARD,
              ("strip, symmetric 3.48 mm (6D)", "SAE1070", 90.0, 55.0, 1.29e-3, "paper", 25.0, 3.48, "symmetric"))


def study_rev_run(row, n_shots: int, seed: int):
    """A :data:`STUDY_REVS` row as a study builds it (``tasks._kernel.rev_mesh``, the preset's values,
    ``FidelityParams.boundary`` / ``options``, the study's shot stream of ``n_shots``; S230 at
    mu = 0.2): ``(fidelity, shot, mesh, stream, shots, ImpactRun)``, no impact run yet."""
    import peenflow.testing as PT
    from peenflow.fe.impact import ImpactRun
    from peenflow.methods.shot_stream import shot_stream
    from peenflow.study.fidelity import PRESETS
    from tasks import _kernel as K
    from tasks.params import FidelityParams, ShotParams

    _, mat, angle, speed, thick, preset, h_um, side_mm, lateral = row
    shot = ShotParams(PT.S230.radius_m, PT.S230.density_kg_m3, 0.2)
    p = PRESETS[preset]
    f = FidelityParams(h_um * 1e-6, p["fine_depth_D"] * PT.S230.diameter_m, p["grading_ratio"],
                       p["time_step_safety"], p["window_contact_radii"], p["settle_tolerance"],
                       p["relaxation_tolerance"], lateral)
    side = side_mm * 1e-3
    mesh = K.rev_mesh(f, side, thick)
    stream = shot_stream(n_shots, shot.radius_m, side / 2, side / 2, angle, speed, seed)
    shots = shot.shots(stream.centres, stream.velocities)
    return f, shot, mesh, stream, shots, ImpactRun(f.boundary(mesh), Material(**getattr(PT, mat)), f.options(shot))

