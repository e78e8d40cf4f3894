"""The compiled control step of the planar grasp: CasADi C code + DAQP, one ctypes call.

:func:`planner.control.grasp_qp.grasp_qp_function` (kinematics, Jacobians, mass matrix,
gravity, impedance laws and the QP data) is generated as C, a small driver is appended that
hands the QP to DAQP's C entry point ``daqp_quadprog`` (taken from the installed ``daqp``
Python extension, which exports it) and forms ``tau = tau_0 + J_h^T f*``, and the whole is
built with gcc once (cached by the hash of the code). A step is then one ctypes call on
preallocated arrays: no Python-level numpy work, no allocation.

DAQP's workspace is set up once and updated in place at every step (``daqp_update_ldp`` +
``daqp_solve``, warm-started from the last active set). The problem-struct layout is checked
at construction by solving two known QPs against ``daqp.solve``; if the check fails (a DAQP
build with another layout), the step falls back to Python and says so in
:attr:`GraspStep.backend`.
"""

from __future__ import annotations

import ctypes
import hashlib
import os
import shutil
import subprocess
import tempfile
from pathlib import Path

import numpy as np

from planner.control.grasp_layout import N_CON, N_DIAG, N_PAR, N_REF, N_VAR
from planner.errors import HapexError

#: doubles of the per-step inputs ``q`` (6), ``qd`` (6), ``geo`` (8), ``ref`` (N_REF), stored
#: back to back at the start of :attr:`GraspStep.inputs` (``par`` follows them)
STEP_INPUTS = 20 + N_REF

_DRIVER = r"""
#include <stdlib.h>
typedef struct { int n; int m; int ms; double *H; double *f; double *A; double *bupper;
  double *blower; int *sense; int *break_points; int nh; int problem_type; } hx_problem;
typedef struct { double *x; double *lam; double fval; double soft_slack; int exitflag;
  int iter; int nodes; double solve_time; double setup_time; double pad[16]; } hx_result;
typedef struct { hx_problem p; double H[NV * NV]; double f[NV]; double A[NV * NC];
  double bu[NC]; double bl[NC]; int sense[NC]; double lam[NC]; void* work; int ready; } hx_ctx;

static void (*hx_alloc_settings)(void*);
static int (*hx_setup)(hx_problem*, void*, double*, int);
static int (*hx_update)(int, void*, hx_problem*);
static void (*hx_solve)(hx_result*, void*);

void hx_init(void* a, void* s, void* u, void* v) {
  hx_alloc_settings = (void (*)(void*))a; hx_setup = (int (*)(hx_problem*, void*, double*, int))s;
  hx_update = (int (*)(int, void*, hx_problem*))u; hx_solve = (void (*)(hx_result*, void*))v;
}

void* hx_create(void) {
  hx_ctx* c = (hx_ctx*)calloc(1, sizeof(hx_ctx));
  c->work = calloc(1, 65536);  /* DAQPWorkspace is a few hundred bytes; generous */
  c->p.n = NV; c->p.m = NC; c->p.ms = 0; c->p.H = c->H; c->p.f = c->f; c->p.A = c->A;
  c->p.bupper = c->bu; c->p.blower = c->bl; c->p.sense = c->sense;
  return c;
}

double* hx_data(void* ctx, int which) {
  hx_ctx* c = (hx_ctx*)ctx;
  return which == 0 ? c->H : which == 1 ? c->f : which == 2 ? c->A : which == 3 ? c->bu : c->bl;
}

int hx_qp(void* ctx, double* x) {
  hx_ctx* c = (hx_ctx*)ctx; hx_result r; int i, flag;
  r.x = x; r.lam = c->lam; r.exitflag = -99;
  if (!c->ready) {
    for (i = 0; i < NC; ++i) c->sense[i] = 0;
    hx_alloc_settings(c->work);
    flag = hx_setup(&c->p, c->work, 0, 0);
    if (flag < 0) return flag;
    c->ready = 1;
  } else {
    for (i = 0; i < NC; ++i) c->sense[i] &= 0;
    flag = hx_update(1 | 2 | 4 | 8 | 16, c->work, &c->p);
    if (flag < 0) return flag;
  }
  hx_solve(&r, c->work);
  return r.exitflag;
}

int hx_step(void* ctx, const double* q, const double* qd, const double* geo, const double* ref,
            const double* par, double* tau, double* f, double* diag) {
  hx_ctx* c = (hx_ctx*)ctx;
  double tau0[6], JT[6 * NV];
  const casadi_real* arg[5]; casadi_real* res[8];
  casadi_int iw[SZ_IW + 1]; casadi_real w[SZ_W + 1];
  int i, j, flag;
  arg[0] = q; arg[1] = qd; arg[2] = geo; arg[3] = ref; arg[4] = par;
  res[0] = c->H; res[1] = c->f; res[2] = c->A; res[3] = c->bu; res[4] = c->bl;
  res[5] = tau0; res[6] = JT; res[7] = diag;
  FNAME(arg, res, iw, w, 0);
  flag = hx_qp(ctx, f);
  if (flag < 1) { for (j = 0; j < NV; ++j) f[j] = 0.0; }
  for (i = 0; i < 6; ++i) {
    double s = tau0[i];
    for (j = 0; j < NV; ++j) s += JT[i + 6 * j] * f[j];
    tau[i] = s;
  }
  return flag;
}

/* the step on arrays bound once (hx_bind): one pointer crosses ctypes per step */
typedef struct { void* ctx; const double *q, *qd, *geo, *ref, *par; double *tau, *f, *diag; }
  hx_bound;

void* hx_bind(void* ctx, const double* q, const double* qd, const double* geo,
              const double* ref, const double* par, double* tau, double* f, double* diag) {
  hx_bound* b = (hx_bound*)calloc(1, sizeof(hx_bound));
  b->ctx = ctx; b->q = q; b->qd = qd; b->geo = geo; b->ref = ref; b->par = par;
  b->tau = tau; b->f = f; b->diag = diag;
  return b;
}

int hx_run(void* bound) {
  hx_bound* b = (hx_bound*)bound;
  return hx_step(b->ctx, b->q, b->qd, b->geo, b->ref, b->par, b->tau, b->f, b->diag);
}
"""


def _build(code: str, stem: str) -> Path:
    cc = shutil.which("gcc") or shutil.which("cc")
    if cc is None:
        raise HapexError("no C compiler (gcc/cc) on PATH; the compiled grasp step needs one")
    d = Path(tempfile.gettempdir()) / "hapex-casadi"
    d.mkdir(parents=True, exist_ok=True)
    digest = hashlib.sha1(code.encode()).hexdigest()[:16]
    so = d / f"{stem}_{digest}.so"
    if not so.exists():
        src = d / f"{stem}_{digest}.c"
        src.write_text(code)
        tmp = so.with_suffix(f".{os.getpid()}.tmp")
        proc = subprocess.run(
            [cc, "-O2", "-shared", "-fPIC", str(src), "-o", str(tmp), "-lm"],
            capture_output=True,
            text=True,
        )
        if proc.returncode != 0:
            raise HapexError(f"building {src} failed: {proc.stderr.strip()[:500]}")
        tmp.replace(so)
    return so


def _daqp_symbols() -> tuple[int, int, int, int] | None:
    """Addresses of DAQP's C workspace API in the installed ``daqp`` extension, or None."""
    try:
        import daqp

        lib = ctypes.CDLL(daqp.__file__)
        names = ("allocate_daqp_settings", "setup_daqp_main", "daqp_update_ldp", "daqp_solve")
        return tuple(ctypes.cast(getattr(lib, n), ctypes.c_void_p).value for n in names)
    except (ImportError, OSError, AttributeError):
        return None


class GraspStep:
    """One compiled control step of the planar grasp (see the module docstring).

    Write the step's inputs into :attr:`q`, :attr:`qd`, :attr:`geo`, :attr:`ref` and
    :attr:`par` (layout in :mod:`planner.control.grasp_layout`), then call the object. The
    five are consecutive views of one array, :attr:`inputs`.

    Args:
        hand: the ``robots.planar_hand.PlanarHand``.

    Attributes:
        tau: (6,) joint torques of the last step [N m] (reused array).
        forces: (4,) QP solution, the fingertip forces on the object [N] (reused array).
        diag: (17,) diagnostics (contacts, normals, object estimate, wrench).
        backend: ``"c-daqp"`` (one C call: generated code + DAQP's C API, workspace kept
            and updated in place) or ``"python-daqp"`` (fallback through Python).
        flag: DAQP exit flag of the last step (1 = solved; < 1 failure, forces set to 0).
    """

    def __init__(self, hand) -> None:
        import casadi as cs

        from planner.control.grasp_qp import grasp_qp_function

        self.function = grasp_qp_function(hand.model)
        fn = self.function
        gen = cs.CodeGenerator("hapex_grasp_qp.c", {"with_header": False})
        gen.add(fn)
        driver = (
            _DRIVER.replace("FNAME", fn.name())
            .replace("SZ_IW", str(fn.sz_iw()))
            .replace("SZ_W", str(fn.sz_w()))
            .replace("NV", str(N_VAR))
            .replace("NC", str(N_CON))
        )
        lib = ctypes.CDLL(str(_build(gen.dump() + driver, "hapex_grasp_step")))
        lib.hx_init.argtypes = [ctypes.c_void_p] * 4
        lib.hx_create.restype = ctypes.c_void_p
        lib.hx_data.restype = ctypes.POINTER(ctypes.c_double)
        lib.hx_data.argtypes = [ctypes.c_void_p, ctypes.c_int]
        lib.hx_qp.restype = ctypes.c_int
        lib.hx_qp.argtypes = [ctypes.c_void_p, ctypes.c_void_p]
        lib.hx_step.restype = ctypes.c_int
        lib.hx_step.argtypes = [ctypes.c_void_p] * 9
        self._lib = lib
        # one contiguous input block (q, qd, geo, ref, par): a caller can fill the per-step
        # part q..ref with a single ``struct.pack_into`` (:data:`STEP_INPUTS` doubles)
        self.inputs = np.zeros(STEP_INPUTS + N_PAR)
        self.q, self.qd, self.geo = self.inputs[0:6], self.inputs[6:12], self.inputs[12:20]
        self.ref, self.par = self.inputs[20:STEP_INPUTS], self.inputs[STEP_INPUTS:]
        self.tau, self.forces, self.diag = np.zeros(6), np.zeros(N_VAR), np.zeros(N_DIAG)
        self.flag = 0
        symbols = _daqp_symbols()
        self._ctx = None
        if symbols is not None:
            lib.hx_init(*symbols)
            self._ctx = lib.hx_create()
        self.backend = "c-daqp" if self._ctx and self._selftest() else "python-daqp"
        if self.backend == "c-daqp":  # fresh workspace for the real problem
            self._ctx = lib.hx_create()
        arrays = (self.q, self.qd, self.geo, self.ref, self.par, self.tau, self.forces, self.diag)
        self._args = (self._ctx,) + tuple(a.ctypes.data for a in arrays)
        lib.hx_bind.restype = ctypes.c_void_p
        lib.hx_bind.argtypes = [ctypes.c_void_p] * 9
        lib.hx_run.restype = ctypes.c_int
        lib.hx_run.argtypes = [ctypes.c_void_p]
        self._bound = lib.hx_bind(*self._args) if self._ctx else None
        self._run = lib.hx_run

    @property
    def c_entry(self) -> tuple[int, int] | None:
        """``(address of int hx_run(void*), its argument)`` for compiled callers that run
        the step themselves (it reads and writes the arrays of this object; :attr:`flag` is
        then not updated, the caller gets it as the return value); ``None`` without the C
        backend."""
        if self.backend != "c-daqp":
            return None
        return ctypes.cast(self._run, ctypes.c_void_p).value, int(self._bound)

    def _selftest(self) -> bool:
        """Solve two QPs through the C workspace path (setup, then update) and compare with
        ``daqp.solve`` from Python; False when the struct layouts do not match."""
        import daqp

        rng = np.random.default_rng(7)
        view = {k: np.ctypeslib.as_array(self._lib.hx_data(self._ctx, k), (n,))
                for k, n in ((0, N_VAR**2), (1, N_VAR), (2, N_VAR * N_CON), (3, N_CON),
                             (4, N_CON))}  # fmt: skip
        x = np.zeros(N_VAR)
        for _ in range(2):
            L = rng.normal(size=(N_VAR, N_VAR))
            H = L @ L.T + np.eye(N_VAR)
            f, A = rng.normal(size=N_VAR), rng.normal(size=(N_CON, N_VAR))
            bu, bl = rng.uniform(0.1, 1.0, N_CON), np.full(N_CON, -1e30)
            view[0][:], view[1][:], view[2][:] = H.ravel(), f, A.ravel()
            view[3][:], view[4][:] = bu, bl
            flag = self._lib.hx_qp(self._ctx, x.ctypes.data)
            ref, _, rflag, _ = daqp.solve(H, f, A, bu, bl, np.zeros(N_CON, dtype=np.int32))
            if flag != 1 or rflag != 1 or not np.allclose(x, ref, atol=1e-8):
                return False
        return True

    def __call__(self) -> np.ndarray:
        """Run one step on the current contents of ``q, qd, geo, ref, par``.

        Returns:
            ``tau`` (6,) [N m] (the reused attribute array).
        """
        if self.backend == "c-daqp":
            self.flag = self._run(self._bound)
            return self.tau
        return self._python_step()

    def _python_step(self) -> np.ndarray:
        import daqp

        out = self.function(self.q, self.qd, self.geo, self.ref, self.par)
        H, c, AT, bu, bl, tau0, JT, diag = (np.asarray(o, dtype=float) for o in out)
        x, _, flag, _ = daqp.solve(
            H, c.ravel(), np.ascontiguousarray(AT.T), bu.ravel(), bl.ravel(),
            np.zeros(N_CON, dtype=np.int32),
        )  # fmt: skip
        self.flag = int(flag)
        self.forces[:] = x if flag >= 1 else 0.0
        self.diag[:] = diag.ravel()
        self.tau[:] = tau0.ravel() + JT @ self.forces
        return self.tau


__all__ = ["STEP_INPUTS", "GraspStep"]
