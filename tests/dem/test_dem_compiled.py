"""How the engine's functions are compiled (dem.compiled): kernels called only from other
kernels have no entry from Python and refuse a call from it with a clear error instead
of a jump to a null entry point; small functions are inlined by LLVM into their callers;
both give their Python function's results; an inlined function is compiled once for the
plain types of constant arguments."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit, types

from dominowave.dem import contact, engine, integrate
from dominowave.dem.compiled import InnerKernel, inline_kernel, inner_kernel


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


@inline_kernel()
def _halved(x):
    return 0.5 * x


@inline_kernel(python_entry=True)
def _doubled(x):
    return 2.0 * x


def _sum_of_halves(values):
    total = 0.0
    for v in values:
        total += _halved(v)
    return total


def test_an_inline_kernel_is_inlined_into_its_caller_with_the_same_arithmetic():
    caller = njit(_sum_of_halves)  # (not cached: its LLVM IR is read below)
    values = np.linspace(-1.0, 3.0, 9)
    expected = 0.0
    for v in values:  # (the same operations in the same order, in Python floats)
        expected += 0.5 * float(v)
    assert caller(values) == expected
    (llvm_ir,) = caller.inspect_llvm().values()
    assert not [line for line in llvm_ir.splitlines() if " call " in line and "_halved" in line]
    with pytest.raises(TypeError, match="_halved is compiled to be called from other"):
        _halved(1.0)
    assert _doubled(1.5) == 3.0  # (python_entry: callable from Python too)


@inline_kernel()
def _scaled(x, factor):
    return factor * x


_scaled_by_numba = njit(_scaled.py_func)  # (numba's own rule, for the contrast)


@inner_kernel()
def _scaled_if(x, factor, flag):
    return factor * x if flag else x


def _constant_arguments(x):
    total = _scaled(x, 2) + _scaled(x, 3) + _scaled_by_numba(x, 2) + _scaled_by_numba(x, 3)
    return total + _scaled_if(x, 2, True) + _scaled_if(x, 3, True) + _scaled_if(x, 2, False)


def test_a_kernel_is_compiled_once_for_the_plain_types_of_constant_arguments():
    caller = njit(_constant_arguments)  # (not cached: so that it is compiled here)
    assert caller(1.5) == 1.5 * 2 + 1.5 * 3 + 1.5 * 2 + 1.5 * 3 + 1.5 * 2 + 1.5 * 3 + 1.5
    assert list(_scaled.overloads) == [(types.float64, types.int64)]
    assert sorted(str(args[1]) for args in _scaled_by_numba.overloads) == [
        "Literal[int](2)",
        "Literal[int](3)",
    ]
    assert list(_scaled_if.overloads) == [(types.float64, types.int64, types.boolean)]


def test_the_engine_s_steps_are_inner_kernels_and_its_python_entries_are_not():
    # steps that only the time loop calls
    for kernel in (contact._scan_cells, contact._merge_history, engine._bookkeep,
                   engine._advance_planar, integrate.kick_planar, integrate.kick_body,
                   contact.apply_at_lever):  # fmt: skip
        assert isinstance(kernel, InnerKernel)
    # kernels the Python front end calls
    for kernel in (contact.build_verlet_list, contact.compute_forces, engine.active_energy,
                   integrate.update_sphere_positions):  # fmt: skip
        assert not isinstance(kernel, InnerKernel)
