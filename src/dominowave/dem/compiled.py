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

numba compiles a function once per tuple of argument types, and a constant argument
(``log_change(..., ONSET, lag)``, ``_place_spheres(..., True, planar)``) has a
literal type of its own value: each constant at each call site would be one more
compilation of the callee.  Such a version buys nothing: numba removes a branch on a
constant it finds in the function (a global, or a closure's variable, as the time
loop's ``PLANAR``), not on one passed as an argument, and once inlined LLVM propagates
the constant anyway.  A kernel that Python does not call, and an inlined function, are
therefore compiled for the plain types of constant arguments (:class:`OneVersion`).

numba counts the references to the arrays a compiled function holds, with atomic
increments and decrements that it cannot all remove from a loop.  A kernel that allocates
nothing is compiled without the counting (numba's ``_nrt=False``): the time loop, the
kernels of each step and the inlined functions (with the counting, a box chain's step
takes several times as long: benchmarks/README.md, "Rounded-cuboid contacts").  A kernel
inherits the setting of the kernel that calls it, so one that allocates (the build
of a neighbour list) is compiled with ``_nrt=True``.
"""

from __future__ import annotations

import functools

from numba.core import config, types
from numba.core.registry import CPUDispatcher

__all__ = ["InlineKernel", "InnerKernel", "OneVersion", "inline_kernel", "inner_kernel"]


class OneVersion:
    """A numba dispatcher (mixin) that a compiled kernel calling it with a constant argument
    reaches through the version for the constant's plain type (``int64``, ``bool``), not
    through one for its value (``Literal[int](0)``; module docstring)."""

    def get_call_template(self, args, kws):
        args = [types.unliteral(a) for a in args]
        kws = {k: types.unliteral(v) for k, v in kws.items()}
        return super().get_call_template(args, kws)


class InnerKernel(OneVersion, CPUDispatcher):
    """A numba dispatcher whose compiled versions are reachable from compiled code only
    (and one version for the plain types of constant arguments: :class:`OneVersion`).

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


class InlineKernel(OneVersion, CPUDispatcher):
    """The dispatcher of an inlined function that Python may call too
    (``inline_kernel(python_entry=True)``)."""


def _dispatcher(cls, func, targetoptions):
    """The dispatcher ``cls`` of ``func``, with numba's disk cache; or ``func`` itself
    under ``NUMBA_DISABLE_JIT``."""
    if config.DISABLE_JIT:  # (NUMBA_DISABLE_JIT: run the Python function)
        return func
    kernel = cls(py_func=func, locals={}, targetoptions=targetoptions)
    kernel.enable_caching()
    return kernel


def _compiler(cls, options, python_entry):
    """The decorator that compiles a function with the dispatcher ``cls``, numba's target
    ``options``, and the CPython and C-callable wrappers if ``python_entry``."""
    targetoptions = {"nopython": True, "error_model": "numpy", **options}
    if not python_entry:
        targetoptions.update(no_cpython_wrapper=True, no_cfunc_wrapper=True)
    return functools.partial(_dispatcher, cls, targetoptions=targetoptions)


def inner_kernel(**options):
    """``@njit(cache=True, error_model="numpy", **options)`` for a kernel that only other
    kernels call, compiled without the CPython and C-callable wrappers
    (:class:`InnerKernel`).  ``options``: numba's target options, e.g. ``_nrt=False``."""
    return _compiler(InnerKernel, options, python_entry=False)


def inline_kernel(*, python_entry: bool = False):
    """A small function of the kernels, compiled once and inlined by LLVM into each kernel
    that calls it (module docstring).  Compiled without numba's reference counting, so
    that its callers' loops pay no reference-count updates of the arrays it is given:
    it must allocate nothing, and a view of an array it returns may go only to callers
    compiled without the counting too (``shapes.cuboid.rows_from``: box_box and
    rect_rect).  ``python_entry``: callable from Python as well (the Python
    front end and the tests call some), with numba's wrappers; otherwise an
    :class:`InnerKernel`.  Either is compiled for the plain types of constant arguments
    (:class:`OneVersion`)."""
    options = {"forceinline": True, "_nrt": False}
    if python_entry:
        return _compiler(InlineKernel, options, python_entry=True)
    return _compiler(InnerKernel, options, python_entry=False)
