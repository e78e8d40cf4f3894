"""What the gait's controllers know about the grasp, from sensors only (§2.2.2, Fig. 2.7).

"Contact point sensing ... can be done using intrinsic or extrinsic tactile sensors, or
using assumptions based on fingertip motion history if the local object shape is known."
Here:

* left (flat pad with the 8x8 array): the contact position ``u`` across the pad is the
  pressure centroid of the tactile image (extrinsic sensing); the pad's pose comes from the
  encoders, so the contact point and the object's outward normal there
  (``n = (sin phi, -cos phi)``) are sensed;
* right (round tip, no array): the contact lies on the tip towards the estimated object
  centre (the nominal shape's local radius ``R``);
* object centre: ``c = p_L + R n_L`` while the pad touches; otherwise from the right tip
  and the palm (the object resting on the palm, ``c_y = R``);
* object rotation during rolling (eq. 2.4 integrated): ``theta = Δbeta_L - Δu / R`` with
  ``beta_L = phi_L - pi/2`` the world angle of the pad contact;
* strain gauges give the fingertip forces (applied on the object, WCS);
* a hand with a round left tip instead of the pad (no tactile array): both contacts lie on
  their tips towards the estimated centre, which comes from both tips (the circle of radius
  ``R`` tangent to them) while both press, else from a tip and the palm; ``u`` is the left
  contact's arclength from its tip's apex and the rotation ``theta = Δbeta_L + Δu / R``
  (:func:`_round_left`).

The whole update is one compiled call (:func:`sense_kernel`, numba) writing into one flat
buffer; the :class:`GraspEstimate`'s arrays are views of that buffer, so an update allocates
nothing and the controller reads every sensed scalar with one ``buffer.tolist()``.
"""

from __future__ import annotations

import math

import numpy as np

from planner.jit import njit

#: tactile force [N] above which the pad is considered in contact
TOUCH_FORCE = 0.02
#: the pad-contact entry of an estimate whose pad lies where the start grasp put it on the
#: object and has not been pressed yet (:meth:`GraspSensing.mark_placed`)
PLACED = 2.0

#: where the centre estimate comes from (``source`` of :meth:`GraspSensing.update`)
SOURCES = {"auto": 0, "pad": 1, "palm": 2}

# layout of the estimate buffer (indices; the controller reads it by these names)
B_U, B_TOUCH = 0, 1
B_P = slice(2, 6)  # (2, 2) contact points
B_N = slice(6, 10)  # (2, 2) outward object normals
B_C = slice(10, 12)  # object centre
B_BETA = slice(12, 14)
B_F = slice(14, 18)  # (2, 2) strain-gauge forces
B_FN = slice(18, 20)
B_OFF = slice(20, 24)
B_TN = slice(24, 28)
B_TIPS = slice(28, 32)  # (2, 2) fingertip points
B_PHI = slice(32, 34)  # fingertip orientations phi_L, phi_R [rad]
N_BUF = 34

# layout of the geometry vector of the kernel
_G_BASE_L, _G_LEN_L, _G_BASE_R, _G_LEN_R = 0, 2, 5, 7
_G_R, _G_TIP_R, _G_PITCH2, _G_TOUCH, _G_TIP_L = 10, 11, 12, 13, 14
N_GEO = 15


class GraspEstimate:
    """The sensed grasp at one instant (updated in place by every :meth:`GraspSensing.update`).

    Every array is a view of the sensing buffer (do not keep it across updates without a
    ``copy()``).

    Attributes:
        u: contact position across the left pad [m] (tactile centroid; kept while the pad
            does not touch).
        pad_touch: whether the tactile array sees a contact (or the pad still lies, not yet
            pressed, where the start grasp placed it: :meth:`GraspSensing.mark_placed`).
        p: (2, 2) contact points of the left and right fingers [m].
        n: (2, 2) outward object normals at them (the fingers push along ``-n``).
        centre: (2,) estimated object centre [m].
        beta: (2,) world polar angles of the contacts about ``centre`` [rad].
        forces: (2, 2) strain-gauge forces on the object [N].
        normal_force: (2,) their components along ``-n`` [N].
        offsets: (4,) contact points in the fingertip frames [m] (for the control step).
        tip_normals: (4,) tip-frame unit normals pointing into the object.
        tips: (2, 2) fingertip points from the encoders (pad centre, tip-disc centre) [m].
        phi: (2,) fingertip orientations ``q1 + q2 + q3`` of the two fingers [rad].
    """

    def __init__(self, buffer: np.ndarray) -> None:
        self.buffer = buffer
        self.p = buffer[B_P].reshape(2, 2)
        self.n = buffer[B_N].reshape(2, 2)
        self.centre = buffer[B_C]
        self.beta = buffer[B_BETA]
        self.forces = buffer[B_F].reshape(2, 2)
        self.normal_force = buffer[B_FN]
        self.offsets = buffer[B_OFF]
        self.tip_normals = buffer[B_TN]
        self.tips = buffer[B_TIPS].reshape(2, 2)
        self.phi = buffer[B_PHI]

    @property
    def u(self) -> float:
        return float(self.buffer[B_U])

    @u.setter
    def u(self, value: float) -> None:
        self.buffer[B_U] = value

    @property
    def pad_touch(self) -> bool:
        return bool(self.buffer[B_TOUCH])

    @pad_touch.setter
    def pad_touch(self, value: bool) -> None:
        self.buffer[B_TOUCH] = 1.0 if value else 0.0


class GraspSensing:
    """Turns :class:`planner.sim.Observation` readings into a :class:`GraspEstimate`.

    Args:
        hand: the ``robots.planar_hand.PlanarHand`` (flat or round left tip, round right).
        radius: the nominal object radius used by the estimate [m].
        tactile: the ``robots.sensors.TactileArray`` model (for reading images).
    """

    def __init__(self, hand, radius: float, tactile=None) -> None:
        from robots.sensors import TactileArray

        self.hand = hand
        self.radius = float(radius)
        self.r = hand.params.right.tip_radius
        self.array = tactile or TactileArray()
        self._geom = tuple(
            (tuple(float(v) for v in f.base), tuple(float(v) for v in f.lengths))
            for f in (hand.params.left, hand.params.right)
        )
        (bl, ll), (br, lr) = self._geom
        #: radius of a round left tip [m] (0: the flat pad)
        self.r_left = hand.params.left.round_radius
        self.geo = np.array(
            [*bl, *ll, *br, *lr, self.radius, self.r, self.array.pitch**2, TOUCH_FORCE,
             self.r_left]
        )  # fmt: skip
        self.taxel_u = np.ascontiguousarray(self.array.u, dtype=float)
        self._no_image = np.zeros((self.array.rows, self.array.cols))
        self.buffer = np.zeros(N_BUF)
        self.buffer[B_TN] = (0.0, 1.0, 0.0, 1.0)
        self.est = GraspEstimate(self.buffer)

    def mark_placed(self) -> None:
        """The pad lies on the object where the start grasp placed it (contact at its centre,
        ``u = 0``) and is not pressed yet: until the tactile array first reads a pressure the
        estimate treats it as touching, so the object centre comes from the pad (``p_L - R
        n_L``) from the very first update instead of from the palm (``c_y = R``). On a
        non-round object the two differ (12 x 10 cm ellipse: 12 mm), and the switch at the
        first touch jumped the pad's contact angle and so the rolling-integrated rotation
        (eq. 2.4) by -17 deg, which the object impedance then 'corrected' by turning the
        ellipse +15 deg the wrong way. For a round model only: a pad placed flat on a
        square's face does not touch it at its centre, and square_gait (posed outline)
        turned +29.7 deg the wrong way with it (-30.9 deg without). Not called by
        ``explore_object`` yet: with it ellipse_gait's seeds 0-3 failed at -99 to -63 deg
        (-101 to -107 without) and the ball was neutral (measured 2026-11-23). Since
        2026-11-24 phase 1's rolling reference is its own first touching reading
        (``controller_kernel.S_REF``), so the first touch no longer jumps the rotation
        estimate; only the centre's source still switches there."""
        self.buffer[B_U] = 0.0
        self.buffer[B_TOUCH] = PLACED

    def set_radius(self, radius: float) -> None:
        """Use ``radius`` [m] as the estimate's radius from the next update on."""
        self.radius = float(radius)
        self.geo[_G_R] = self.radius

    def _tip(self, k: int, q) -> np.ndarray:
        """Fingertip point of finger ``k`` (0 left, 1 right) [m]: the closed-form forward
        kinematics of ``PlanarHand.fingertip_pose`` (equal to it to rounding, tested)."""
        (bx, by), lengths = self._geom[k]
        a, x, y = 0.0, bx, by
        for i in range(3):
            a += float(q[3 * k + i])
            x -= lengths[i] * math.sin(a)
            y += lengths[i] * math.cos(a)
        return np.array((x, y))

    def update(self, obs, source: str = "auto") -> GraspEstimate:
        """Refresh the estimate from one observation (see the module docstring).

        Args:
            obs: the :class:`planner.sim.Observation`.
            source: where the object centre comes from: ``"pad"`` (left pad + nominal
                radius), ``"palm"`` (right tip + palm), ``"auto"`` (pad while it touches).
        """
        self.update_raw(obs, SOURCES[source])
        return self.est

    def update_raw(self, obs, source: int) -> np.ndarray:
        """:meth:`update` with the source as its code in :data:`SOURCES`; returns the
        buffer (layout ``B_*``)."""
        tactile = obs.tactile
        image = tactile.get("left") if tactile is not None else None
        if image is None:
            sense_kernel(obs.q, obs.tip_forces, self._no_image, False, source, self.geo,
                         self.taxel_u, self.buffer)  # fmt: skip
        else:
            sense_kernel(obs.q, obs.tip_forces, image, True, source, self.geo, self.taxel_u,
                         self.buffer)  # fmt: skip
        return self.buffer


@njit(cache=True, nogil=True)
def sense_kernel(q, forces, image, has_image, source, geo, taxel_u, out):  # pragma: no cover
    """The estimate of :class:`GraspSensing` written into ``out`` (layout ``B_*``).

    Args:
        q: (6,) encoder angles [rad]; forces: (2, 2) strain-gauge forces on the object [N].
        image: (rows, cols) left tactile image [Pa] (ignored unless ``has_image``).
        source: 0 auto, 1 pad, 2 palm (:data:`SOURCES`).
        geo: (14,) finger bases and link lengths, ``R``, tip radius, taxel area, touch force.
        taxel_u: (cols,) taxel centres across the pad [m].
        out: (N_BUF,) the buffer; its ``u`` and pad-contact entries are kept when no image
            (and the pad-contact entry stays :data:`PLACED` while the image is all zero).
    """
    if has_image:
        total = 0.0
        moment = 0.0
        for j in range(image.shape[1]):
            col = 0.0
            for i in range(image.shape[0]):
                col += image[i, j]
            total += col
            moment += col * taxel_u[j]
        touch = total > 0.0 and total * geo[_G_PITCH2] > geo[_G_TOUCH]
        if touch:
            out[B_TOUCH] = 1.0
            out[B_U] = moment / total
        elif total > 0.0 or out[B_TOUCH] != PLACED:  # PLACED lasts until a first pressure
            out[B_TOUCH] = 0.0
    tLx, tLy, out[32] = _fingertip(q, 0, geo, _G_BASE_L, _G_LEN_L)
    tRx, tRy, out[33] = _fingertip(q, 3, geo, _G_BASE_R, _G_LEN_R)
    R, r = geo[_G_R], geo[_G_TIP_R]
    rL = geo[_G_TIP_L]
    if rL > 0.0:
        _round_left(forces, source, geo, out, tLx, tLy, tRx, tRy)
        return
    u = out[B_U]
    cL, sL = math.cos(out[32]), math.sin(out[32])
    pLx, pLy = tLx + u * cL, tLy + u * sL
    nLx, nLy = sL, -cL
    if source == 1 or (source == 0 and out[B_TOUCH] != 0.0):
        cx, cy = pLx - R * nLx, pLy - R * nLy
    else:  # resting on the palm, touching the right tip
        cx, cy = _palm_centre(tRx, tRy, R + r, R, -1.0)
    _write_rest(forces, out, pLx, pLy, nLx, nLy, u, cx, cy, tLx, tLy, tRx, tRy, r)


@njit(cache=True, nogil=True)
def _write_rest(  # pragma: no cover
    forces, out, pLx, pLy, nLx, nLy, u, cx, cy, tLx, tLy, tRx, tRy, r
):
    """The right contact (on its tip towards the centre ``c``), the polar angles, forces
    and the grasp step's tip-frame contact geometry; the left contact is given."""
    dx, dy = cx - tRx, cy - tRy
    norm = max(math.hypot(dx, dy), 1e-12)
    dx, dy = dx / norm, dy / norm
    pRx, pRy = tRx + r * dx, tRy + r * dy
    out[2], out[3], out[4], out[5] = pLx, pLy, pRx, pRy
    out[6], out[7], out[8], out[9] = nLx, nLy, -dx, -dy
    out[10], out[11] = cx, cy
    out[12] = math.atan2(pLy - cy, pLx - cx)
    out[13] = math.atan2(pRy - cy, pRx - cx)
    for k in range(2):
        fx, fy = forces[k, 0], forces[k, 1]
        out[14 + 2 * k], out[15 + 2 * k] = fx, fy
        out[18 + k] = -(fx * out[6 + 2 * k] + fy * out[7 + 2 * k])
    cR, sR = math.cos(out[33]), math.sin(out[33])
    tx, ty = cR * dx + sR * dy, -sR * dx + cR * dy  # d in the right tip frame
    out[20], out[21], out[22], out[23] = u, 0.0, r * tx, r * ty
    out[24], out[25], out[26], out[27] = 0.0, 1.0, tx, ty
    out[28], out[29], out[30], out[31] = tLx, tLy, tRx, tRy


@njit(cache=True, nogil=True)
def _palm_centre(tx, ty, offset, R, side):  # pragma: no cover
    """Centre (x, y) [m] of the circle of radius ``R`` resting on the palm (``c_y = R``) at
    distance ``offset`` from the tip centre ``t``, on the ``side`` (+1: right of it)."""
    dy = R - ty
    return tx + side * math.sqrt(max(offset * offset - dy * dy, 0.0)), R


@njit(cache=True, nogil=True)
def _presses(fx, fy, dx, dy, threshold):  # pragma: no cover
    """Whether the force ``f`` on the object [N] has more than ``threshold`` [N] along the
    direction ``d`` from the tip to the object's centre."""
    return fx * dx + fy * dy >= threshold * max(math.hypot(dx, dy), 1e-12)


@njit(cache=True, nogil=True)
def _round_left(forces, source, geo, out, tLx, tLy, tRx, tRy):  # pragma: no cover
    """:func:`sense_kernel` for a round left tip of radius ``rL`` (no tactile array): the
    contact lies on each tip towards the estimated centre, the centre from the left tip and
    the palm (``source`` 1), the right tip and the palm (2) or, while both tips press
    (``source`` 0: strain gauges above :data:`TOUCH_FORCE` along the line to the last
    centre), the circle tangent to both tips nearest the last estimate (else the palm's).
    ``u`` is the left contact's arclength from the tip's apex [m]; the contact flag is
    whether the left tip presses."""
    R, r, rL = geo[_G_R], geo[_G_TIP_R], geo[_G_TIP_L]
    a, b = R + rL, R + r
    px, py = out[10], out[11]
    if py == 0.0:  # no estimate yet: the object on the palm at the right tip
        px, py = _palm_centre(tRx, tRy, b, R, -1.0)
    left = _presses(forces[0, 0], forces[0, 1], px - tLx, py - tLy, geo[_G_TOUCH])
    touch = left and _presses(forces[1, 0], forces[1, 1], px - tRx, py - tRy, geo[_G_TOUCH])
    out[B_TOUCH] = 1.0 if left else 0.0
    if source == 1:
        cx, cy = _palm_centre(tLx, tLy, a, R, 1.0)
    elif source == 2 or not touch:
        cx, cy = _palm_centre(tRx, tRy, b, R, -1.0)
    else:  # the circle tangent to both tips: the two-circle intersection nearest the last
        ex, ey = tRx - tLx, tRy - tLy
        d = max(math.hypot(ex, ey), 1e-12)
        ex, ey = ex / d, ey / d
        along = (a * a - b * b + d * d) / (2 * d)
        h = math.sqrt(max(a * a - along * along, 0.0))
        mx, my = tLx + along * ex, tLy + along * ey
        c1x, c1y = mx - h * ey, my + h * ex
        c2x, c2y = mx + h * ey, my - h * ex
        if (c1x - px) ** 2 + (c1y - py) ** 2 <= (c2x - px) ** 2 + (c2y - py) ** 2:
            cx, cy = c1x, c1y
        else:
            cx, cy = c2x, c2y
    dx, dy = cx - tLx, cy - tLy
    norm = max(math.hypot(dx, dy), 1e-12)
    dx, dy = dx / norm, dy / norm
    pLx, pLy = tLx + rL * dx, tLy + rL * dy
    cL, sL = math.cos(out[32]), math.sin(out[32])
    tx, ty = cL * dx + sL * dy, -sL * dx + cL * dy  # d in the left tip frame
    alpha = math.atan2(ty, tx)  # tip-frame angle of the contact direction
    u = rL * (alpha - 0.5 * math.pi)
    out[B_U] = u
    _write_rest(forces, out, pLx, pLy, -dx, -dy, u, cx, cy, tLx, tLy, tRx, tRy, r)
    out[20], out[21] = rL * tx, rL * ty
    out[24], out[25] = tx, ty


@njit(cache=True, nogil=True)
def _fingertip(q, first, geo, base, length):  # pragma: no cover
    """Fingertip point (x, y) [m] and orientation [rad] of the finger whose joints start at
    ``q[first]`` (the closed-form forward kinematics of ``PlanarHand.fingertip_pose``)."""
    a, x, y = 0.0, geo[base], geo[base + 1]
    for i in range(3):
        a += q[first + i]
        x -= geo[length + i] * math.sin(a)
        y += geo[length + i] * math.cos(a)
    return x, y, a


def round_contact_arclength(beta: float, phi: float, tip_radius: float) -> float:
    """Contact location on the round right tip as an arclength from its apex [m]
    (:func:`planner.control.rolling_pd.contact_arclength` for the contact at world polar
    angle ``beta`` of the object and tip orientation ``phi``)."""
    alpha = (beta + math.pi) - phi  # tip-frame angle of the contact direction
    a = math.atan2(math.sin(alpha), math.cos(alpha))
    return tip_radius * (a - 0.5 * math.pi)


__all__ = [
    "GraspEstimate",
    "GraspSensing",
    "N_BUF",
    "PLACED",
    "SOURCES",
    "TOUCH_FORCE",
    "round_contact_arclength",
    "sense_kernel",
]
