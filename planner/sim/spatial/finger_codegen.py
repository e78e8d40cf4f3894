"""The 3GM's reduced dynamics as one generated (and compiled) CasADi function: the hot path.

The same equations as :class:`planner.sim.spatial.finger.FingerDynamics` (which evaluates
them with Pinocchio's CRBA/RNEA and the closure Jacobian), derived here symbolically by
walking the ``pin.Model`` (:func:`robots.casadi_kinematics.joint_transforms`: joint
placements, axes, body inertias, armature) with the loop closed in closed form
(``q(θ)`` of eq. C.5, elbow-up):

.. math::

    T = \\tfrac12 \\sum_k (m_k |\\dot c_k|^2 + \\omega_k^T R_k I_k R_k^T \\omega_k)
        + \\tfrac12 \\sum_j a_j \\dot q_j^2, \\qquad V = -\\sum_k m_k\\, g\\cdot c_k,

    M_r = \\partial^2 T / \\partial\\dot\\theta^2, \\qquad
    b_r = \\frac{\\partial (M_r\\dot\\theta)}{\\partial\\theta}\\dot\\theta
          - \\frac{\\partial T}{\\partial\\theta} + \\frac{\\partial V}{\\partial\\theta}

(Lagrange's equations in the independent coordinates θ; the closure forces do no work).
The function returns everything one step needs: ``(θ, θ̇, τ, h) -> (c, J, J_ω, M_r⁻¹,
θ̇_free = θ̇ + h M_r⁻¹ (τ - b_r), γ1, b_r, M_r, sin(γ2 - γ1))`` (NaN where the loop cannot
close). It is compiled with gcc
(:func:`robots.casadi_kinematics.compile`, cached by a hash of the code) when a compiler is
available; the tests check it against the Pinocchio path to round-off. Why CasADi: one call
(a few µs) replaces ~10 Pinocchio calls and ~30 small numpy operations per step, which
dominated the step time in a profile.
"""

from __future__ import annotations

import numpy as np

__all__ = ["CompiledFunction", "reduced_dynamics_function"]

_CACHE: dict[tuple, object] = {}


class CompiledFunction:
    """A CasADi Function compiled to C and called through ``ctypes`` on preallocated buffers.

    ``casadi.Function.__call__`` converts every input and output (DM objects): ~100 µs for
    the 3GM function; calling the generated C symbol directly on numpy buffers costs a few
    µs. Inputs are copied into :attr:`inputs`; outputs are views of :attr:`outputs`
    (dense, column-major as CasADi stores them; matrices are exposed transposed back to
    row-major here), overwritten by the next call.

    Args:
        fn: the ``casadi.Function`` (dense inputs and outputs).
        directory: cache directory for the C file and the shared library.

    Raises:
        HapexError: no C compiler, or the build failed.
    """

    def __init__(self, fn, directory=None) -> None:
        import ctypes
        import hashlib
        import os
        import shutil
        import subprocess
        import tempfile
        from pathlib import Path

        import casadi as cs

        from planner.errors import HapexError

        cc = shutil.which("gcc") or shutil.which("cc")
        if cc is None:
            raise HapexError("no C compiler (gcc/cc) on PATH")
        d = Path(directory) if directory else Path(tempfile.gettempdir()) / "hapex-casadi"
        d.mkdir(parents=True, exist_ok=True)
        gen = cs.CodeGenerator(
            f"{fn.name()}.c", {"with_header": False, "casadi_int": "long long int"}
        )
        gen.add(fn)
        code = gen.dump()
        digest = hashlib.sha1(code.encode()).hexdigest()[:16]
        so = d / f"{fn.name()}_{digest}.so"
        if not so.exists():
            src = d / f"{fn.name()}_{digest}.c"
            src.write_text(code)
            tmp = so.with_suffix(f".{os.getpid()}.tmp")
            proc = subprocess.run(
                [cc, "-O1", "-shared", "-fPIC", str(src), "-o", str(tmp)],
                capture_output=True,
                text=True,
            )
            if proc.returncode != 0:
                raise HapexError(f"building {src} failed: {proc.stderr.strip()[:500]}")
            tmp.replace(so)
        self._lib = ctypes.CDLL(str(so))
        self._fn = getattr(self._lib, fn.name())
        self._fn.restype = ctypes.c_int
        self.function = fn
        self._bind()

    def clone(self) -> CompiledFunction:
        """The same compiled function with buffers of its own (for a second user: a world
        and its controller, or two worlds in threads, must not share buffers)."""
        new = object.__new__(CompiledFunction)
        new._lib, new._fn, new.function = self._lib, self._fn, self.function
        new._bind()
        return new

    def _bind(self) -> None:
        """Allocate the buffers and the argument arrays of the C call."""
        import ctypes

        fn = self.function
        n_in = [fn.nnz_in(i) for i in range(fn.n_in())]
        n_out = [fn.nnz_out(i) for i in range(fn.n_out())]
        #: one contiguous buffer: every input, then every output (the numba kernels use it)
        self.buffer = np.zeros(sum(n_in) + sum(n_out))
        offsets = np.concatenate([[0], np.cumsum(n_in + n_out)]).astype(int)
        views = [self.buffer[offsets[i] : offsets[i + 1]] for i in range(len(n_in + n_out))]
        self.inputs = views[: len(n_in)]
        raw = views[len(n_in) :]
        self.outputs = []
        for i, r in enumerate(raw):
            n, m = fn.size_out(i)
            self.outputs.append(r if m == 1 else r.reshape(m, n).T)
        #: offset of each output in :attr:`buffer`
        self.output_offsets = offsets[len(n_in) : -1].copy()
        ptr = ctypes.c_void_p
        args = [a.ctypes.data for a in self.inputs] + [None] * (fn.sz_arg() - fn.n_in())
        ress = [r.ctypes.data for r in raw] + [None] * (fn.sz_res() - fn.n_out())
        self._raw = raw
        self._arg = (ptr * len(args))(*args)
        self._res = (ptr * len(ress))(*ress)
        self._iw = np.zeros(max(fn.sz_iw(), 1), dtype=np.int64)
        self._w = np.zeros(max(fn.sz_w(), 1))
        self._iwp = ptr(self._iw.ctypes.data)
        self._wp = ptr(self._w.ctypes.data)
        #: (5,) int64 addresses: the C symbol, its arg and res pointer arrays, iw, w (for
        #: :func:`planner.sim.spatial.step_kernel.call_compiled`; valid while self lives)
        self.pointers = np.array(
            [
                ctypes.cast(self._fn, ptr).value,
                ctypes.addressof(self._arg),
                ctypes.addressof(self._res),
                self._iw.ctypes.data,
                self._w.ctypes.data,
            ],
            dtype=np.int64,
        )

    def __call__(self, *values) -> list[np.ndarray]:
        """Evaluate at ``values`` (one array or float per input); returns the outputs."""
        for buf, v in zip(self.inputs, values, strict=True):
            buf[:] = v
        if self._fn(self._arg, self._res, self._iwp, self._wp, 0) != 0:
            raise FloatingPointError("the generated 3GM dynamics failed")
        return self.outputs


def _closed_loop_q(cs, p, th):
    t1, t2, t3 = th[0], th[1], th[2]
    a1 = p["l1"] * cs.cos(t1) - p["l2"] * cs.cos(t2)
    a2 = p["l1"] * cs.sin(t1) - p["l2"] * cs.sin(t2) + p["h1"]
    aa = a1 * a1 + a2 * a2
    na = cs.sqrt(aa)
    b1 = (p["l3"] ** 2 - p["l4"] ** 2 - aa) / (2 * p["l4"])
    b2 = (p["l3"] ** 2 - p["l4"] ** 2 + aa) / (2 * p["l3"])
    c = cs.atan2(a2, a1)
    g1 = c - cs.acos(b1 / na)
    g2 = c - cs.acos(b2 / na)
    return cs.vertcat(t3, t1, g1 - t1, t2, g2 - t2), g1


def _symbolic_terms(model, params, gravity) -> dict:
    """Symbolic ``θ, θ̇, τ, h`` and the terms of the reduced dynamics (module docstring).

    ``M_r`` and ``b_r`` are assembled from the link Jacobians (Kane's form of Lagrange's
    equations, equal to the derivatives of ``T`` and ``V`` above and ~4x cheaper):
    ``M_r = Σ m Jvᵀ Jv + Jωᵀ I Jω + Jqᵀ A Jq`` and
    ``b_r = Σ m Jvᵀ (J̇v θ̇ - g) + Jωᵀ (I J̇ω θ̇ + ω × I ω) + Jqᵀ A J̇q θ̇``.
    """
    import casadi as cs

    from robots.casadi_kinematics import joint_transforms

    th = cs.SX.sym("theta", 3)
    thd = cs.SX.sym("theta_dot", 3)
    q, g1 = _closed_loop_q(cs, params, th)
    closure_sin = cs.sin((q[4] + q[3]) - g1)  # sin(γ2 - γ1): 0 where l3 and l4 align
    Jq = cs.jacobian(q, th)
    qd = Jq @ thd
    Rs, ts = joint_transforms(model, q)
    g = cs.DM(np.asarray(gravity, float))
    omegas = [cs.DM.zeros(3, 1)]
    M = cs.SX.zeros(3, 3)
    b = cs.SX.zeros(3, 1)
    grav = cs.SX.zeros(3, 1)
    for i in range(1, model.njoints):
        qi = qd[model.idx_vs[i]]
        omegas.append(omegas[model.parents[i]] + Rs[i][:, 2] * qi)  # RZ joints
        Y = model.inertias[i]
        if Y.mass <= 0 and np.all(Y.inertia == 0):
            continue
        c = ts[i] + Rs[i] @ cs.DM(Y.lever)
        Jv = cs.jacobian(c, th)
        Jw = cs.jacobian(omegas[i], thd)
        w = omegas[i]
        Iw = Rs[i] @ cs.DM(Y.inertia) @ Rs[i].T
        M += Y.mass * (Jv.T @ Jv) + Jw.T @ Iw @ Jw
        a_vp = cs.jtimes(Jv @ thd, th, thd)
        dw_vp = cs.jtimes(w, th, thd)
        b += Y.mass * (Jv.T @ a_vp) + Jw.T @ (Iw @ dw_vp + cs.cross(w, Iw @ w))
        grav -= Y.mass * (Jv.T @ g)
    arm = cs.DM(np.asarray(model.armature, float))
    M += Jq.T @ cs.diag(arm) @ Jq
    b += Jq.T @ (arm * cs.jtimes(qd, th, thd)) + grav
    fid = model.getFrameId("endpoint")
    fr = model.frames[fid]
    j = fr.parentJoint
    center = ts[j] + Rs[j] @ cs.DM(fr.placement.translation)
    J = cs.jacobian(center, th)
    Jw = cs.jacobian(omegas[j], thd)
    return {
        "theta": th, "theta_dot": thd, "center": center, "J": J, "Jw": Jw, "M": M,
        "b": b, "gravity": grav, "gamma1": g1, "closure_sin": closure_sin,
    }  # fmt: skip


def _symbolic(model, params, gravity):
    """The dynamics Function ``(θ, θ̇, τ, h) -> (c, J, J_ω, M_r⁻¹, θ̇_free, γ1, b_r, M_r,
    sin(γ2 - γ1))`` (common subexpressions eliminated)."""
    import casadi as cs

    s = _symbolic_terms(model, params, gravity)
    tau = cs.SX.sym("tau", 3)
    h = cs.SX.sym("h")
    Minv = cs.inv(s["M"])
    thd_free = s["theta_dot"] + h * (Minv @ (tau - s["b"]))
    outs = [s["center"], s["J"], s["Jw"], Minv, thd_free, s["gamma1"], s["b"], s["M"]]
    outs.append(s["closure_sin"])
    return cs.Function(
        "three_gm_reduced",
        [s["theta"], s["theta_dot"], tau, h],
        cs.cse([cs.densify(x) for x in outs]),
        ["theta", "theta_dot", "tau", "h"],
        ["center", "J", "Jw", "Minv", "theta_dot_free", "gamma1", "b", "M", "closure_sin"],
    )


def _symbolic_kinematics(model, params, gravity):
    """The kinematics Function ``θ -> (c, J, J_ω, γ1, sin(γ2 - γ1), g_r)`` (``g_r``: the
    gravity torques, ``b_r(θ, 0)``)."""
    import casadi as cs

    s = _symbolic_terms(model, params, gravity)
    names = ["center", "J", "Jw", "gamma1", "closure_sin", "gravity"]
    return cs.Function(
        "three_gm_kinematics",
        [s["theta"]],
        cs.cse([cs.densify(s[n]) for n in names]),
        ["theta"],
        names,
    )


class _Uncompiled:
    """Same interface as :class:`CompiledFunction` on the CasADi virtual machine."""

    def __init__(self, fn) -> None:
        self.fn = fn

    def clone(self) -> _Uncompiled:
        """Itself (no buffers to share)."""
        return self

    def __call__(self, *values) -> list[np.ndarray]:
        out = self.fn(*values)
        return [np.array(o.full()).ravel() if o.shape[1] == 1 else np.array(o.full()) for o in out]


def reduced_dynamics_function(
    gm, gravity=(0.0, 0.0, -9.81), compiled: bool = True, kinematics: bool = False
):
    """The CasADi function of the module docstring for a :class:`~robots.three_gm.ThreeGM`.

    Args:
        gm: the finger (its ``model`` and ``params``).
        gravity: (3,) [m/s²] in the WCS.
        compiled: build C code with gcc (falls back to the SX virtual machine when no
            compiler is found).
        kinematics: the cheaper kinematics Function ``θ -> (c, J, J_ω, γ1, sin(γ2 - γ1),
            g_r)`` (gravity torques ``g_r = b_r(θ, 0)``) instead of the dynamics.
    """
    key = (tuple(sorted(gm.params.items())), tuple(np.round(gravity, 12)), compiled, kinematics)
    if key in _CACHE:
        return _CACHE[key]
    build = _symbolic_kinematics if kinematics else _symbolic
    fn = build(gm.model, gm.params, gravity)
    if compiled:
        from planner.errors import HapexError

        try:
            fn = CompiledFunction(fn)
        except HapexError:
            fn = _Uncompiled(fn)
    else:
        fn = _Uncompiled(fn)
    _CACHE[key] = fn
    return fn
