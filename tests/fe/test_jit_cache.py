"""The numba cache is keyed by the whole kernel source (numba alone would run a stale element loop)."""

from __future__ import annotations

import shutil

import numba
import pytest

import peenflow.fe  # noqa: F401  (decorates the kernels)
from peenflow import _jit


def test_kernels_cache_in_the_folder_of_the_current_kernel_source():
    if _jit.DISABLE_JIT:
        pytest.skip("PEENFLOW_DISABLE_JIT=1: nothing is compiled or cached")
    assert numba.config.CACHE_DIR == str(_jit.kernel_cache_dir())
    assert _jit.kernel_cache_dir().name == _jit.kernel_source_hash()


def test_editing_any_kernel_module_changes_the_cache_folder(tmp_path, monkeypatch):
    shutil.copytree(_jit._PACKAGE / "fe", tmp_path / "fe")
    monkeypatch.setattr(_jit, "_PACKAGE", tmp_path)
    before = _jit.kernel_source_hash()
    assert _jit.kernel_source_hash() == before  # stable
    element = tmp_path / "fe" / "element.py"
    element.write_text(element.read_text() + "\n# an edit in a module solver.run_phase calls\n")
    assert _jit.kernel_source_hash() != before


def test_serial_and_parallel_twins_cache_separately_and_agree(tmp_path):
    """One source compiled twice (peenflow._jit.jit_twins): each variant has its
    own cache entry (a shared one would hand one variant the other's code),
    a fresh process loads both from the cache, and they agree bit for bit."""
    import os
    import subprocess
    import sys

    if _jit.DISABLE_JIT:
        pytest.skip("PEENFLOW_DISABLE_JIT=1: nothing is compiled or cached")
    code = """
import numpy as np
from peenflow.fe.element import element_rows, element_rows_parallel
from peenflow.fe.johnson_cook import Material
from peenflow.fe.mesh import box_mesh
from peenflow.fe.model import Model, Target
m = Model(Target(box_mesh(np.linspace(0, 1e-4, 5), np.linspace(0, 1e-4, 5), np.linspace(0, 1e-4, 5))),
          Material(E=205e9, nu=0.29, density=7800.0, A=1408e6, B=600.8e6, n=0.234))
s = m.new_state()
rng = np.random.default_rng(1)
s.v[:] = rng.standard_normal(s.v.shape)
out = []
for fn in (element_rows, element_rows_parallel):
    f = np.zeros_like(s.x)
    out.append(fn(s.x.copy(), s.v, f, s.stress.copy(), s.eps_p.copy(), s.sy_static.copy(), s.hg.copy(),
                  s.temp.copy(), m.vol0, m.mat, 1e-9, 5, 5, 4, 4, 0, 4, 0, 4, 0, 4) + (f,))
assert out[0][:6] == out[1][:6] and np.array_equal(out[0][6], out[1][6])
print(sum(element_rows.stats.cache_hits.values()), sum(element_rows_parallel.stats.cache_hits.values()),
      element_rows_parallel.targetoptions.get("parallel"))
"""
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    first = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert first.returncode == 0, first.stderr
    second = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert second.returncode == 0, second.stderr
    hits_serial, hits_parallel, parallel = second.stdout.split()[-3:]
    assert parallel == "True"
    assert int(hits_serial) >= 1 and int(hits_parallel) >= 1  # both loaded from the cache in a new process
    names = {p.name.split(".")[1].split("-")[0] for p in tmp_path.rglob("*.nbi") if "element" in p.name}
    assert {"_rows_pass", "_rows_pass_parallel"} <= names  # two entries, not one shared
