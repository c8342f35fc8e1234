"""How the engine's kernels are compiled: entries from Python, and inlining.

numba compiles every ``@njit`` function with two entry points besides the function
itself: a CPython wrapper, which unboxes each argument (for the engine's state, named
tuples of arrays) and boxes the result, and a C-callable wrapper.  A kernel
that only the time loop or another kernel calls never runs either, yet their code is
generated, optimised and compiled to machine code on the first run.  Leaving them out
(numba's ``no_cpython_wrapper`` and ``no_cfunc_wrapper`` options, with which it compiles
its own internal functions) cut the README's main job's compiling by a sixth
(benchmarks/README.md, "First run").  The compiled code of the kernel, and so
every trajectory, is the same to the bit.

Without a CPython wrapper a call from Python would jump to a null entry point; an
:class:`InnerKernel` instead refuses it with a ``TypeError`` naming the kernel.

The small functions the kernels are made of -- a contact law, a shape pair's geometry,
the update of one body -- are inlined into every kernel that calls them
(:func:`inline_kernel`).  numba's own inlining (``inline="always"``) types and lowers a
function again at each call site; LLVM's (numba's ``forceinline``, the ``alwaysinline``
attribute) compiles it once and copies the optimised code.  Both give the same
arithmetic, and so the same trajectories to the bit (no fast-math: LLVM may not
reorder a floating-point operation); the second compiles a box chain's kernels in about
half the time, and they run faster (benchmarks/README.md, "First run").
"""

from __future__ import annotations

from numba import njit
from numba.core import config
from numba.core.registry import CPUDispatcher

__all__ = ["InnerKernel", "inline_kernel", "inner_kernel"]


class InnerKernel(CPUDispatcher):
    """A numba dispatcher whose compiled versions are reachable from compiled code only.

    Compiled callers find a version through ``overloads`` (numba's typing and linking);
    the table of entry points for calls from Python stays empty, so that such a call
    ends in :meth:`_compile_for_args`, which refuses it."""

    def add_overload(self, cres):
        self.overloads[tuple(cres.signature.args)] = cres

    def _compile_for_args(self, *args, **kws):
        func = self.py_func
        raise TypeError(
            f"{func.__module__}.{func.__qualname__} is compiled to be called from other"
            " compiled kernels only (it has no entry point from Python); call it from an"
            " @njit function"
        )


def inner_kernel(**options):
    """``@njit(cache=True, error_model="numpy", **options)`` for a kernel that only other
    kernels call, compiled without the CPython and C-callable wrappers
    (:class:`InnerKernel`).  ``options``: numba's target options, e.g. ``_nrt=False``."""
    targetoptions = {"nopython": True, "error_model": "numpy", **options}
    targetoptions.update(no_cpython_wrapper=True, no_cfunc_wrapper=True)

    def compile_lazily(func):
        if config.DISABLE_JIT:  # (NUMBA_DISABLE_JIT: run the Python function)
            return func
        kernel = InnerKernel(py_func=func, locals={}, targetoptions=targetoptions)
        kernel.enable_caching()
        return kernel

    return compile_lazily


def inline_kernel(*, python_entry: bool = False):
    """A small function of the kernels, compiled once and inlined by LLVM into each kernel
    that calls it (module docstring).  Compiled without numba's reference counting, so
    that its callers' loops pay no reference-count updates of the arrays it is given:
    it must allocate nothing, and a view of an array it returns may go only to callers
    compiled without the counting too (``shapes.cuboid.rows_from``: box_box and
    rect_rect).  ``python_entry``: callable from Python as well (the Python
    front end and the tests call some), with numba's wrappers; otherwise an
    :class:`InnerKernel`."""
    options = {"forceinline": True, "_nrt": False}
    if python_entry:
        return njit(cache=True, error_model="numpy", **options)
    return inner_kernel(**options)
