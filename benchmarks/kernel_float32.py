"""A float32 copy of the blocked element kernel, for measurement only.

The solver's kernel is float64 (``Options.precision`` accepts only
"float64"; BENCHMARKS.md section 1 gives the measured reasons). To measure
what float32 state would buy, this module rebuilds ``_row`` / ``_rows_pass``
and their inlined helpers from the float64 source with every float literal
and every material constant cast to ``np.float32`` and the lane scratch in
float32 (with ``BLOCK`` = 8 the lane loops compile to 8-lane ``ymm``
instructions; ``build(16)`` gives 16-lane ``zmm`` ones, measured no faster).
The plastic return (scalar, Newton) is shared with the float64 kernel. Not
cached, not used by the solver.
"""

from __future__ import annotations

import inspect
import re
import textwrap

import numba
import numpy as np

from peenflow.fe import element, johnson_cook

_FLOAT = re.compile(r"(?<![\w.])(\d+\.\d*(?:e[+-]?\d+)?)")


def _f32_source(fn) -> str:
    src = textwrap.dedent(inspect.getsource(fn.py_func if hasattr(fn, "py_func") else fn))
    src = "\n".join(line for line in src.splitlines() if not line.startswith("@"))
    src = _FLOAT.sub(r"F(\1)", src)
    src = src.replace("float(", "F(").replace("np.empty(_NSCR)", "np.empty(_NSCR, np.float32)")
    if "np.empty(_NSCR, np.float32)" not in src and "def _row(" in src:
        raise RuntimeError("kernel_float32: the scratch allocation of _row was not found (source changed?)")
    src = src.replace("hdt = F(0.5) * dt", "dt = F(dt)\n    hdt = F(0.5) * dt")
    src = re.sub(r"= (mat\[M_\w+\])", r"= F(\1)", src)  # material constants
    src = src.replace("mod = F(mat[M_LAM]) + F(2.0) * mat[M_MU]", "mod = F(mat[M_LAM] + 2.0 * mat[M_MU])")
    return src


def build(block: int = element.BLOCK):
    """Return ``(serial, parallel)`` float32 element passes (same contract as
    ``element_rows``), ``block`` elements per lane loop."""
    ns = dict(vars(johnson_cook))
    ns.update(vars(element))
    ns.update(F=np.float32, np=np, math=__import__("math"), prange=numba.prange)
    # the scratch layout of element.py for this block size
    nds = block + 8
    ns.update(BLOCK=block, _NDS=nds, _RS=6 * nds, _FLO=4 * 6 * nds, _FHI=4 * 6 * nds + 12 * nds,
              _L0=4 * 6 * nds + 24 * nds)
    ns["_NSCR"] = ns["_L0"] + element._NLANE * block
    assert block != element.BLOCK or all(ns[k] == getattr(element, k) for k in ("_NDS", "_RS", "_FLO", "_FHI", "_L0", "_NSCR"))
    for helper in (johnson_cook.jaumann_trial, johnson_cook.von_mises, element._corner_sums, element._corner_forces):
        src = _f32_source(helper)
        exec(src, ns)
        ns[helper.__name__] = numba.njit(inline="always", error_model="numpy", nogil=True)(ns[helper.__name__])
    exec(_f32_source(element._row), ns)
    ns["_row"] = numba.njit(error_model="numpy", nogil=True)(ns["_row"])
    exec(textwrap.dedent(inspect.getsource(element._rows_pass)), ns)
    # one source for both, as in the kernel (peenflow._jit.jit_twins); not cached, so no rename needed
    return (numba.njit(error_model="numpy", nogil=True)(ns["_rows_pass"]),
            numba.njit(error_model="numpy", nogil=True, parallel=True)(ns["_rows_pass"]))
