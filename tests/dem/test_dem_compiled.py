"""Kernels called only from other kernels (dem.compiled.inner_kernel): compiled without
an entry from Python, the same results from compiled callers, and a clear error from
Python instead of a jump to a null entry point."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit, types

from dominowave.dem import contact, engine, integrate
from dominowave.dem.compiled import InnerKernel, inner_kernel


@inner_kernel(_nrt=False)
def _weighted_sum(values, weight):
    total = 0.0
    for v in values:
        total += weight * v
    return total


# (not cached: it would share the cache entry of the same function without its entry)
_weighted_sum_with_entry = njit(_weighted_sum.py_func)


@njit(cache=True)
def _caller(values):
    return _weighted_sum(values, 0.5)


def test_an_inner_kernel_gives_its_python_function_s_result_to_a_compiled_caller():
    values = np.linspace(-1.0, 3.0, 9)
    assert _caller(values) == _weighted_sum.py_func(values, 0.5)


def test_an_inner_kernel_has_no_python_entry_and_says_so():
    signature = (types.float64[::1], types.float64)
    _weighted_sum.compile(signature)
    _weighted_sum_with_entry.compile(signature)

    def entry_point(kernel):
        cres = kernel.overloads[signature]
        return cres.library.get_pointer_to_function(cres.fndesc.llvm_cpython_wrapper_name)

    assert entry_point(_weighted_sum) == 0 and entry_point(_weighted_sum_with_entry) != 0
    with pytest.raises(TypeError, match=r"_weighted_sum is compiled to be called from other"):
        _weighted_sum(np.ones(3), 0.5)


def test_the_engine_s_steps_are_inner_kernels_and_its_python_entries_are_not():
    # steps that only the time loop calls
    for kernel in (contact._scan_cells, contact._merge_history, engine._bookkeep,
                   engine._advance_planar, integrate.kick_planar):  # fmt: skip
        assert isinstance(kernel, InnerKernel)
    # kernels the Python front end calls
    for kernel in (contact.build_verlet_list, contact.compute_forces, engine.active_energy,
                   integrate.update_sphere_positions):  # fmt: skip
        assert not isinstance(kernel, InnerKernel)
