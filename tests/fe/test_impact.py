"""Driver-level tests: energy, symmetry, determinism, checkpoint/resume, plastic dents, window, threads."""

import numpy as np
import pytest

from peenflow.fe.impact import Options, run_impacts
from peenflow.fe.window import ViscousSpringFaces
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import graded_box
from peenflow.fe.model import Target
from peenflow.fe.shots import Shots, johnson_plastic, time_to_contact
from peenflow.testing import SAE1070

R = 0.29e-3
RHO = 7800.0


def coarse_target(h=25e-6):
    # 25 um is the paper's fine element size; the box is small to keep the suite fast
    return Target(graded_box(0.6e-3, 0.6e-3, h, fine_half_width=0.15e-3, fine_depth=0.1e-3))


def one_shot(speed, x=0.0, y=0.0, angle_deg=90.0):
    th = np.radians(angle_deg)
    v = speed * np.array([np.cos(th), 0.0, np.sin(th)])
    return Shots(centres=[[x, y, -R - 1e-6]], velocities=[v], radius=R, density=RHO)


def surface_uz(res, target):
    nnx, nny, _ = target.mesh.shape_nodes
    return res.displacement[: nnx * nny, 2]


def dent_depth(res, target):
    return surface_uz(res, target).max()


@pytest.fixture(scope="module")
def runs():
    """The plastic impacts shared by several tests (coarse mesh, window on)."""
    t = coarse_target()
    out = {}
    for speed in (25.0, 55.0):
        for rate in (True, False):
            mat = Material(**{**SAE1070, "C": SAE1070["C"] if rate else 0.0})
            out[speed, rate] = run_impacts(t, mat, one_shot(speed), Options())
    return t, out


def test_energy_balance_elastic_plastic(runs):
    t, out = runs
    for key, res in out.items():
        # total energy (kinetic + internal + hourglass + viscous + contact +
        # damping) stays within 1 % of the impact energy through the impact
        assert res.energy_error < 0.01, key
        # plastic work is most of the absorbed energy
        e_imp = res.shots["impact_energy"][0]
        absorbed = e_imp * (1 - res.shots["restitution"][0] ** 2)
        assert 0.5 * absorbed < res.energy["w_plastic"] < absorbed, key
        # usual acceptance criterion: hourglass energy below 10 % of the
        # internal energy -- met at 55 m/s (contact radius ~4 elements of
        # 25 um); at 25 m/s (~2.8 elements) it is 12 % on this mesh and 3 %
        # at 12.5 um (slow test below), so only 55 m/s is held to it here
        if key[0] == 55.0:
            assert res.hourglass_ratio < 0.10, key


def test_plastic_dent_and_restitution(runs):
    t, out = runs
    mat = Material(**SAE1070)
    m = one_shot(55.0).mass
    d25, d55 = dent_depth(out[25.0, True], t), dent_depth(out[55.0, True], t)
    e25, e55 = out[25.0, True].shots["restitution"][0], out[55.0, True].shots["restitution"][0]
    # faster -> bigger dent, lower restitution
    assert d55 > 1.5 * d25 and e55 < e25
    # Johnson's fully plastic estimate (mean pressure 3A, no hardening, no
    # elastic recovery) bounds the residual depth from above at 55 m/s
    # (17.7 um); hardening and spring-back make it smaller, but not by more than half
    j = johnson_plastic(R, m, 55.0, 3 * mat.A)
    assert 0.5 * j["delta"] < d55 < j["delta"]
    assert 0.3 < e55 < 0.65
    # maximum approach during contact is close to Johnson's depth
    assert out[55.0, True].shots["max_approach"][0] == pytest.approx(j["delta"], rel=0.15)
    # the rate term (C = 0.0134 at ~1e5 /s: +15 % flow stress) makes the dent shallower
    assert dent_depth(out[55.0, True], t) < dent_depth(out[55.0, False], t)
    assert out[55.0, True].shots["restitution"][0] > out[55.0, False].shots["restitution"][0]
    # compressive residual stress at the surface under the dent
    res = out[55.0, True]
    c = res.centroids
    under = (np.hypot(c[:, 0], c[:, 1]) < 50e-6) & (c[:, 2] < 60e-6)
    assert res.stress[under, 0].mean() < -200e6


def test_symmetric_field_for_centred_normal_impact(runs):
    t, out = runs
    res = out[55.0, True]
    nx, ny, nz = t.mesh.shape_elements
    s = res.stress.reshape(nz, ny, nx, 6)
    mx = s[:, :, ::-1, :]  # mirror x -> -x: xz and xy change sign
    sign = np.array([1, 1, 1, 1, -1, -1])
    scale = np.abs(s).max()
    assert np.abs(s - mx * sign).max() < 1e-6 * scale
    my = s[:, ::-1, :, :]  # mirror y -> -y: yz and xy change sign
    sign = np.array([1, 1, 1, -1, 1, -1])
    assert np.abs(s - my * sign).max() < 1e-6 * scale
    # and the shot comes back straight
    assert abs(res.shots["vout_x"][0]) < 1e-9 and abs(res.shots["vout_y"][0]) < 1e-9


def test_bit_identical_rerun_and_resume():
    t = coarse_target()
    mat = Material(**SAE1070)
    shots = Shots(centres=[[0, 0, -R - 1e-6], [60e-6, -40e-6, -R - 5e-6], [-50e-6, 30e-6, -R - 1e-6]],
                  velocities=[[0, 0, 40.0], [5.0, 0, 40.0], [0, 0, 40.0]], radius=R, density=RHO)
    saved = {}

    def cb(i, exporter):
        if i == 0:
            saved["state"] = exporter()

    a = run_impacts(t, mat, shots, Options(), on_shot_done=cb)
    b = run_impacts(t, mat, shots, Options())
    assert np.array_equal(a.stress, b.stress) and np.array_equal(a.displacement, b.displacement)
    c = run_impacts(t, mat, shots, Options(), state=saved["state"])
    assert np.array_equal(a.stress, c.stress)
    assert np.array_equal(a.eps_p, c.eps_p)
    assert np.array_equal(a.displacement, c.displacement)
    for k in a.shots:
        np.testing.assert_array_equal(a.shots[k], c.shots[k])


def test_snapshot_does_not_disturb_run():
    t = coarse_target()
    mat = Material(**SAE1070)
    shots = Shots(centres=[[0, 0, -R - 1e-6], [80e-6, 0, -R - 1e-6]], velocities=[[0, 0, 40.0]] * 2,
                  radius=R, density=RHO)
    a = run_impacts(t, mat, shots, Options(), snapshot_after=(1,))
    b = run_impacts(t, mat, shots, Options())
    assert np.array_equal(a.stress, b.stress)
    snap = a.snapshots[1]
    assert snap.n_shots == 1 and snap.stress.shape == a.stress.shape
    assert snap.eps_p.max() > 0 and not np.array_equal(snap.eps_p, a.eps_p)


def test_two_threads_give_identical_fields(monkeypatch):
    from peenflow.fe import model

    monkeypatch.setattr(model, "PARALLEL_MIN_ELEMENTS", 0)  # this window is small: force the parallel pass
    t = coarse_target()
    mat = Material(**SAE1070)
    a = run_impacts(t, mat, one_shot(55.0), Options(threads=1))
    b = run_impacts(t, mat, one_shot(55.0), Options(threads=2))
    assert np.array_equal(a.stress, b.stress) and np.array_equal(a.displacement, b.displacement)


@pytest.fixture(scope="module")
def full55():
    return run_impacts(coarse_target(), Material(**SAE1070), one_shot(55.0), Options(window=False))


def window_errors(win, full, t):
    """(dent, restitution) relative errors and the averaged sigma_xx profile error against the full mesh."""
    c = t.mesh.element_centroids()
    zs = np.unique(c[:, 2])
    meas = (np.abs(c[:, 0]) <= 0.15e-3) & (np.abs(c[:, 1]) <= 0.15e-3)
    pf = np.array([full.stress[meas & (c[:, 2] == z), 0].mean() for z in zs])
    pw = np.array([win.stress[meas & (c[:, 2] == z), 0].mean() for z in zs])
    return (dent_depth(win, t) / dent_depth(full, t) - 1, win.shots["restitution"][0] / full.shots["restitution"][0] - 1,
            np.abs(pw - pf).max() / np.abs(pf).max())


@pytest.fixture(scope="module")
def vs55():
    return run_impacts(coarse_target(), Material(**SAE1070), one_shot(55.0), Options(window_faces=ViscousSpringFaces()))


def test_window_error_small(runs, full55):
    """Default window (4 x 4 contact radii, held faces) against the full mesh.

    Measured (docs/validation.md section 6): dent -0.38 %, restitution +1.66 %, profile 1.90 %.
    """
    t, out = runs
    d, e, p = window_errors(out[55.0, True], full55, t)
    assert abs(d) < 0.02 and abs(e) < 0.03 and p < 0.03, (d, e, p)


def test_viscous_spring_window_error_small(vs55, full55):
    """Viscous-spring window faces: measured dent -0.33 %, restitution +0.35 %, profile 0.79 %."""
    d, e, p = window_errors(vs55, full55, coarse_target())
    assert abs(d) < 0.01 and abs(e) < 0.01 and p < 0.015, (d, e, p)
    assert vs55.energy_error < 0.01


def test_exterior_sees_the_face_displacement(vs55):
    """The viscous-spring faces move; the layer of exterior elements on them is updated, nothing beyond."""
    t = coarse_target()
    res = vs55
    s = res.shots
    i0, i1, j0, j1, k1 = (int(s[k][0]) for k in ("win_i0", "win_i1", "win_j0", "win_j1", "win_k1"))
    nx, ny, nz = t.mesh.shape_elements
    stress = res.final_state.stress.reshape(nz, ny, nx, 6)
    assert np.abs(stress[k1]).max() > 0 and np.abs(stress[:k1, :, i0 - 1]).max() > 0
    assert np.abs(stress[k1 + 1:]).max() == 0 and np.abs(stress[:, :, : i0 - 1]).max() == 0
    assert np.abs(stress[:, :, i1 + 1:]).max() == 0 and np.abs(stress[:, j1 + 1:]).max() == 0


def test_oblique_impact_slides_and_spins():
    t = coarse_target()
    mat = Material(**SAE1070)
    res = run_impacts(t, mat, one_shot(55.0, x=-60e-6, angle_deg=45.0), Options(record=True, record_every=5))
    s = res.shots
    assert s["hit"][0] == 1
    # friction slows the tangential velocity but cannot reverse it
    assert 0 < s["vout_x"][0] < s["vin_x"][0]
    # dent is displaced in the direction of travel (+x) from the first-contact point
    uz = surface_uz(res, t)
    X = res.nodes[: len(uz)]
    assert X[np.argmax(uz), 0] > -60e-6
    h = res.histories[0]
    assert h["force"].shape[1] == 3 and np.all(np.diff(h["time"]) > 0)


def test_missed_shot_is_recorded_and_skipped():
    t = coarse_target()
    mat = Material(**SAE1070)
    shots = Shots(centres=[[5e-3, 0, -1e-3]], velocities=[[0, 0, 50.0]], radius=R, density=RHO)
    res = run_impacts(t, mat, shots, Options())
    assert res.shots["hit"][0] == 0 and res.eps_p.max() == 0


def test_time_to_contact_is_the_first_touch_on_the_line():
    # a sphere falling on a single point at the origin touches it when its centre is R above it;
    # a centre that already overlaps the point gives the (negative) time it touched, not 0
    xs = np.zeros((1, 3))
    v = np.array([0.0, 0.0, 50.0])
    for gap in (10e-6, -3e-6):
        assert time_to_contact(xs, np.array([0.0, 0.0, -R - gap]), v, R) == pytest.approx(gap / 50.0, rel=1e-9, abs=1e-18)
    # oblique: the entry root of |c + v t|^2 = R^2 for an offset point
    c, v = np.array([-2e-4, 1e-4, -1e-3]), np.array([20.0, 0.0, 40.0])
    a, b, cc = v @ v, 2 * c @ v, c @ c - R**2
    assert time_to_contact(xs, c, v, R) == pytest.approx((-b - np.sqrt(b * b - 4 * a * cc)) / (2 * a), rel=1e-12)
    assert time_to_contact(xs, np.array([1e-3, 0.0, -1e-3]), np.array([0.0, 0.0, 50.0]), R) == np.inf


def test_start_inside_the_surface_is_put_back_on_the_line():
    # A start centre 3 um INSIDE the surface (as a pile-up higher than the caller's gap would
    # give) must give the impact of the same shot started upstream: same dent, same rebound,
    # and a closed energy balance. Taken as contact at t = 0 instead, the kinematic contact
    # snapped the overlapped nodes out in one step: energy errors of 0.1-0.3 impact energies.
    t = coarse_target()
    mat = Material(**SAE1070)
    out = []
    for z in (-R + 3e-6, -R - 20e-6):
        shots = Shots(centres=[[0.0, 0.0, z]], velocities=[[0.0, 0.0, 55.0]], radius=R, density=RHO)
        out.append(run_impacts(t, mat, shots, Options()))
    inside, upstream = out
    assert inside.shots["energy_error"][0] < 0.02
    assert dent_depth(inside, t) == pytest.approx(dent_depth(upstream, t), rel=1e-6)
    assert inside.shots["restitution"][0] == pytest.approx(upstream.shots["restitution"][0], rel=1e-6)


@pytest.mark.slow
@pytest.mark.parametrize("speed,tol", [(25.0, 0.12), (55.0, 0.07)])
def test_plastic_impact_converges(speed, tol):
    """25 um (the paper's fine size) against 12.5 um.

    Measured (docs/validation.md section 3): the dent deepens by 5.5 % at 55 m/s (contact
    radius ~4 elements at 25 um) and by 10 % at 25 m/s (~2.8 elements);
    restitution moves by 2 % / 5 %. The test pins the direction (converging
    from below: one-point elements with hourglass control are stiff on coarse
    meshes) and those bounds.
    """
    mat = Material(**SAE1070)
    out = {}
    for h in (25e-6, 12.5e-6):
        t = coarse_target(h)
        r = run_impacts(t, mat, one_shot(speed), Options())
        out[h] = (dent_depth(r, t), r.shots["restitution"][0], r.hourglass_ratio)
    assert out[12.5e-6][0] > out[25e-6][0]
    assert out[25e-6][0] == pytest.approx(out[12.5e-6][0], rel=tol)
    assert out[25e-6][1] == pytest.approx(out[12.5e-6][1], rel=tol)
    assert out[12.5e-6][2] < 0.10


def test_adiabatic_heating_and_thermal_softening():
    """m > 0 with adiabatic heating: each element heats by beta sigma_y d eps_p / (rho c_p)."""
    t = coarse_target()
    base = dict(SAE1070, C=0.0)
    cold = run_impacts(t, Material(**base), one_shot(55.0), Options())
    hot_mat = Material(**{**base, "m": 1.0}, adiabatic=True, T_melt=1793.0, taylor_quinney=0.9, specific_heat=477.0)
    hot = run_impacts(t, hot_mat, one_shot(55.0), Options())
    temp = hot.final_state.temp
    ep = hot.eps_p
    e = np.argmax(ep)
    rise = temp[e] - hot_mat.initial_temperature
    # bounds: flow stress between A (softened by the final T*) and the hardened JC value
    k = hot_mat.taylor_quinney / (hot_mat.density * hot_mat.specific_heat)
    lo = k * hot_mat.A * ep[e] * (1 - rise / (hot_mat.T_melt - hot_mat.T_room))
    hi = k * hot_mat.flow_stress(ep[e]) * ep[e]
    assert lo < rise < hi
    assert np.all(temp[ep == 0] == hot_mat.initial_temperature)
    # thermal softening: deeper dent than without
    assert dent_depth(hot, t) > dent_depth(cold, t)
