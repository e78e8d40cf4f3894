"""Translate a CasADi SX ``Function`` into vectorized numpy code.

CasADi's own ``Function.map`` evaluates about 1 M points/s for a surface's curvature form;
walking the SX algorithm once and replaying it with numpy ufuncs over whole arrays is several
times faster and keeps the result exactly the CasADi expression (no finite differences).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import casadi as ca
import numpy as np

from planner.errors import InvalidParameter

__all__ = ["numpy_function", "scalar_function"]

_BINARY = {
    "OP_ADD": "({a} + {b})",
    "OP_SUB": "({a} - {b})",
    "OP_MUL": "({a} * {b})",
    "OP_DIV": "({a} / {b})",
    "OP_POW": "np.power({a}, {b})",
    "OP_CONSTPOW": "np.power({a}, {b})",
    "OP_LT": "({a} < {b})",
    "OP_LE": "({a} <= {b})",
    "OP_EQ": "({a} == {b})",
    "OP_NE": "({a} != {b})",
    "OP_AND": "np.logical_and({a}, {b})",
    "OP_OR": "np.logical_or({a}, {b})",
    "OP_FMIN": "np.fmin({a}, {b})",
    "OP_FMAX": "np.fmax({a}, {b})",
    "OP_ATAN2": "np.arctan2({a}, {b})",
    "OP_HYPOT": "np.hypot({a}, {b})",
    "OP_FMOD": "np.fmod({a}, {b})",
    "OP_COPYSIGN": "np.copysign({a}, {b})",
    "OP_IF_ELSE_ZERO": "np.where({a}, {b}, 0.0)",
}
_UNARY = {
    "OP_ASSIGN": "{a}",
    "OP_NEG": "(-{a})",
    "OP_SQ": "({a} * {a})",
    "OP_TWICE": "(2.0 * {a})",
    "OP_INV": "(1.0 / {a})",
    "OP_SQRT": "np.sqrt({a})",
    "OP_EXP": "np.exp({a})",
    "OP_LOG": "np.log({a})",
    "OP_SIN": "np.sin({a})",
    "OP_COS": "np.cos({a})",
    "OP_TAN": "np.tan({a})",
    "OP_ASIN": "np.arcsin({a})",
    "OP_ACOS": "np.arccos({a})",
    "OP_ATAN": "np.arctan({a})",
    "OP_SINH": "np.sinh({a})",
    "OP_COSH": "np.cosh({a})",
    "OP_TANH": "np.tanh({a})",
    "OP_ASINH": "np.arcsinh({a})",
    "OP_ACOSH": "np.arccosh({a})",
    "OP_ATANH": "np.arctanh({a})",
    "OP_FABS": "np.abs({a})",
    "OP_SIGN": "np.sign({a})",
    "OP_FLOOR": "np.floor({a})",
    "OP_CEIL": "np.ceil({a})",
    "OP_NOT": "np.logical_not({a})",
    "OP_LOG1P": "np.log1p({a})",
    "OP_EXPM1": "np.expm1({a})",
}
_NAMES = {getattr(ca, n): n for n in dir(ca) if n.startswith("OP_")}
_SCALAR = {
    "OP_POW": "({a} ** {b})",
    "OP_CONSTPOW": "({a} ** {b})",
    "OP_AND": "float({a} and {b})",
    "OP_OR": "float({a} or {b})",
    "OP_FMIN": "min({a}, {b})",
    "OP_FMAX": "max({a}, {b})",
    "OP_ATAN2": "m.atan2({a}, {b})",
    "OP_HYPOT": "m.hypot({a}, {b})",
    "OP_FMOD": "m.fmod({a}, {b})",
    "OP_COPYSIGN": "m.copysign({a}, {b})",
    "OP_IF_ELSE_ZERO": "({b} if {a} else 0.0)",
    "OP_LT": "float({a} < {b})",
    "OP_LE": "float({a} <= {b})",
    "OP_EQ": "float({a} == {b})",
    "OP_NE": "float({a} != {b})",
    "OP_SQRT": "m.sqrt({a})",
    "OP_EXP": "m.exp({a})",
    "OP_LOG": "m.log({a})",
    "OP_SIN": "m.sin({a})",
    "OP_COS": "m.cos({a})",
    "OP_TAN": "m.tan({a})",
    "OP_ASIN": "m.asin({a})",
    "OP_ACOS": "m.acos({a})",
    "OP_ATAN": "m.atan({a})",
    "OP_SINH": "m.sinh({a})",
    "OP_COSH": "m.cosh({a})",
    "OP_TANH": "m.tanh({a})",
    "OP_ASINH": "m.asinh({a})",
    "OP_ACOSH": "m.acosh({a})",
    "OP_ATANH": "m.atanh({a})",
    "OP_FABS": "abs({a})",
    "OP_SIGN": "float(({a} > 0) - ({a} < 0))",
    "OP_FLOOR": "float(m.floor({a}))",
    "OP_CEIL": "float(m.ceil({a}))",
    "OP_NOT": "float(not {a})",
    "OP_LOG1P": "m.log1p({a})",
    "OP_EXPM1": "m.expm1({a})",
}


def numpy_function(fn: ca.Function) -> Callable[..., list[np.ndarray]]:
    """Compile an SX ``Function`` of scalar inputs into a numpy function over arrays.

    Args:
        fn: a CasADi SX function whose inputs are all scalars (1x1).

    Returns:
        ``g(*inputs) -> list`` with one ``(n_nz, *shape)`` float array per output of ``fn``
        (the output's non-zeros in column-major order), where ``shape`` is the broadcast shape
        of the inputs.
    """
    if not fn.is_a("SXFunction"):
        raise InvalidParameter(f"fn: expected a CasADi SX Function, got {fn.class_name()}")
    n_in = fn.n_in()
    lines = [f"def _g({', '.join(f'i{j}' for j in range(n_in))}):"]
    lines.append(
        f"    i0, {', '.join(f'i{j}' for j in range(1, n_in))}{',' if n_in > 1 else ''}"
        f" = np.broadcast_arrays({', '.join(f'i{j}' for j in range(n_in))})"
        if n_in > 1
        else "    i0 = np.asarray(i0, dtype=float)"
    )
    lines.append("    shape = i0.shape")
    outs = [f"o{j}" for j in range(fn.n_out())]
    for j in range(fn.n_out()):
        lines.append(f"    o{j} = np.zeros(({fn.nnz_out(j)},) + shape)")
    lines += _body(fn, (_BINARY, _UNARY), "numpy")
    lines.append(f"    return [{', '.join(outs)}]")
    namespace: dict = {"np": np, "inf": np.inf, "nan": np.nan}
    exec(compile("\n".join(lines), f"<sx2numpy {fn.name()}>", "exec"), namespace)  # noqa: S102
    return namespace["_g"]


def _body(fn: ca.Function, tables: tuple[dict, ...], target: str) -> list[str]:
    """Python source lines of ``fn``'s instructions, each operation translated by the first of
    ``tables`` (operation name -> format string with ``{a}``, ``{b}``) that knows it."""
    lines = []
    for k in range(fn.n_instructions()):
        name = _NAMES[fn.instruction_id(k)]
        ins, outp = fn.instruction_input(k), fn.instruction_output(k)
        if name == "OP_INPUT":
            lines.append(f"    w{outp[0]} = i{ins[0]}")
        elif name == "OP_OUTPUT":
            lines.append(f"    o{outp[0]}[{outp[1]}] = w{ins[0]}")
        elif name == "OP_CONST":
            lines.append(f"    w{outp[0]} = {float(fn.instruction_constant(k))!r}")
        else:
            table = next((t for t in tables if name in t), None)
            if table is None:  # pragma: no cover - an operation surfaces do not use
                raise NotImplementedError(f"CasADi operation {name} has no {target} translation")
            b = f"w{ins[1]}" if len(ins) > 1 else ""
            lines.append(f"    w{outp[0]} = " + table[name].format(a=f"w{ins[0]}", b=b))
    return lines


def scalar_function(fn: ca.Function) -> Callable[..., list[list[float]]]:
    """Compile an SX ``Function`` of scalar inputs into plain-Python float code.

    About ten times faster than a CasADi call for one point. Division by zero or a domain
    error raises the Python exception (``ZeroDivisionError``, ``ValueError``); callers fall
    back to the array path, which handles removable singularities.

    Returns:
        ``g(*floats) -> list`` with one list of floats per output (non-zeros, column-major).
    """
    n_in = fn.n_in()
    lines = [f"def _g({', '.join(f'i{j}' for j in range(n_in))}):"]
    for j in range(fn.n_out()):
        lines.append(f"    o{j} = [0.0] * {fn.nnz_out(j)}")
    lines += _body(fn, (_SCALAR, _BINARY, _UNARY), "scalar")
    lines.append(f"    return [{', '.join(f'o{j}' for j in range(fn.n_out()))}]")
    namespace: dict = {"m": math, "inf": math.inf, "nan": math.nan}
    exec(compile("\n".join(lines), f"<sx2scalar {fn.name()}>", "exec"), namespace)  # noqa: S102
    return namespace["_g"]
