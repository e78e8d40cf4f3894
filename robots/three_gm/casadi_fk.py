"""The 3GM closed form (eqs. C.4-C.6) as a CasADi Function, for optimizers and code generation.

The Jacobian is CasADi's exact derivative of the same expressions (equal to eq. C.7-C.9 with the
corrected C.8; tested). Outside the closure domain the arccos arguments leave [-1, 1] and the
generated code returns NaN: this Function is for hot loops and optimizers that stay inside the
workspace; use :class:`~robots.three_gm.ThreeGM` where the check matters.
"""

from __future__ import annotations


def casadi_kinematics(params: dict[str, float], name: str = "three_gm_fk"):
    """``casadi.Function`` ``theta (3,) -> (x (3,) [m], J (3, 3) [m/rad])`` of eqs. C.4-C.7.

    Args:
        params: ``l1..l5, h1..h3`` [m] (e.g. ``ThreeGM().params``).
        name: Function name (used when it is compiled).
    """
    import casadi as cs

    p = params
    th = cs.SX.sym("theta", 3)
    t1, t2, t3 = th[0], th[1], th[2]
    a1 = p["l1"] * cs.cos(t1) - p["l2"] * cs.cos(t2)
    a2 = p["l1"] * cs.sin(t1) - p["l2"] * cs.sin(t2) + p["h1"]
    aa = a1 * a1 + a2 * a2
    na = cs.sqrt(aa)
    b1 = (p["l3"] ** 2 - p["l4"] ** 2 - aa) / (2 * p["l4"])
    c = cs.atan2(a2 / na, a1 / na)
    g1 = c - cs.acos(b1 / na)
    r = p["l1"] * cs.cos(t1) + p["l5"] * cs.cos(g1)
    z = p["l1"] * cs.sin(t1) + p["l5"] * cs.sin(g1)
    x = cs.vertcat(
        (r + p["h2"]) * cs.cos(t3) + p["h3"] * cs.sin(t3),
        (r + p["h2"]) * cs.sin(t3) - p["h3"] * cs.cos(t3),
        z,
    )
    return cs.Function(name, [th], [x, cs.densify(cs.jacobian(x, th))], ["theta"], ["x", "J"])
