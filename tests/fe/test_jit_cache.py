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
