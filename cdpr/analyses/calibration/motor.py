"""The motor-angle model of a spool robot (a Hangprinter): the line a motor angle releases, the
MAP problem with every position a nuisance, and each position solved from its readings.

The data (``MotorData``, ``read_motor_data`` in ``cdpr.analyses.calibration.data``): per sample the
motor angles ``motor_deg_1..m`` [deg], optional forces ``force_N_1..m`` [N] and an optional measured
position ``x_m, y_m, z_m``. A motor angle becomes line through the robot's spool
(``cdpr.models.winch.released_line``: phi = theta L / H, s = r0 phi - O Q phi^2 / 4, the U strands
between anchor and mover lengthen by s / U).

Every sample's position P_k is an unknown (three nuisance parameters); a measured position adds the
three rows (P_k - y_k) / sigma_k. Each sample gives m line rows, (l_i(P_k) - l_pred,ki) / sigma_L with
l_i(P) = |A_i - P| + d_i the line from the spool exit over the fixed anchor to the mover and

- ``standard`` (rigid lines, the Hangprinter tool's model): l_pred = l_i(0) + s_ki / U_i, i.e.
  |A_i - P_k| - |A_i| = s_ki / U_i;
- ``exact`` (the robot's model for a point mass on fixed anchors: straight lines, Hooke elasticity
  of the U strands K_i = U E S, the spool): the rest length is L0_ki = L0_ref,i + s_ki / U_i and the
  line under the measured force t_ki is l_pred = L0_ki (1 + t_ki / K_i); the encoder reference is
  the mover at the origin under the reference sample's forces t_ref (the first sample whose motor
  angles are all within ``REFERENCE_DEG`` of 0 and that has forces; none: t_ref = 0, said in the
  warnings), so L0_ref,i = l_i(0) / (1 + t_ref,i / K_i). A sample without forces is taken with rigid
  lines (status ``no forces: rigid lines``).

The parameters θ: ``anchors`` (A_i, names ``A_1_x`` ..) and ``spools`` (``r0_1`` .. the spool radius
at the origin, ``Q_1`` .. the buildup factor), each with a Gaussian prior around the robot file
(``DEFAULT_PRIORS``; ``spools=SD`` sets the radius' sd, the buildup factor's is
``BUILDUP_PRIOR_SD``). The MAP is proper whenever every estimated parameter has a prior, however few
the equations: nothing is refused for counting. The poses carry no prior; with m >= 3 lines each is
fixed by its own rows.

Gauge: the encoder reference puts the mover at the origin at zero motor angle, which fixes the
frame's translation; with no measured position the frame's rotation about the origin (3 directions)
is not seen by the data, and with ``spools`` also its scale (anchors, positions and spool radii
scaled together), so those are fixed by the priors alone (the Hangprinter tool fixes A_x = D_x =
D_y = 0 instead). Measured positions fix the frame (theirs).

The fit is ``estimator.fit_motor`` (its result ``result.MotorCalibration``), the check
``prediction.check_motor``, the K-fold cross-validation ``cv.cross_validate``, simulated data
``synthetic.simulate_motor``.

The Jacobian is analytic; identifiability is that of θ with the poses eliminated (measurement rows
projected on the orthogonal complement of the pose columns, ``identify.identifiability_without``),
as in ``self_calibrate_standard``.

References
----------
RepRapFirmware, HangprinterKinematics (M666 Q R U O L H), as derived in ``cdpr.models.winch``.
Tarantola, A. (2005). Inverse Problem Theory and Methods for Model Parameter Estimation, SIAM,
section 3.2 (least squares with a Gaussian prior, posterior covariance).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from cdpr.errors import CdprError
from cdpr.models import winch

#: Default line noise sd [m] of the motor-angle rows (one line, after the spool model).
SIGMA_LINE_DEFAULT = 1e-3
#: Prior sd by default: anchors [m]; spools: the spool radius at the origin [m].
DEFAULT_PRIORS = {"anchors": 5e-3, "spools": 1e-3}
#: Prior sd of the buildup factor Q [m] (M666 Q 0.05 mm).
BUILDUP_PRIOR_SD = 5e-5
#: The groups a motor-angle calibration estimates.
MOTOR_GROUPS = ("anchors", "spools")
#: A sample whose motor angles are all within this of 0 [deg] (and that has forces) is the reference.
REFERENCE_DEG = 1.0
#: The models of a motor-angle calibration.
MOTOR_MODELS = ("exact", "standard")


@dataclasses.dataclass
class SpoolModel:
    """What the motor-angle model needs of a robot: anchors A (m, 3) [m], dead lengths d (m,) [m],
    spool radii r0 (m,) [m], buildup factors Q (m,) [m], U, lines per spool O (``lines``), the gear ratio L/H (m,), the
    strands' axial stiffness K = U E S (m,) [N]."""

    A: np.ndarray
    d: np.ndarray
    r0: np.ndarray
    Q: np.ndarray
    U: np.ndarray
    lines: np.ndarray
    ratio: np.ndarray
    K: np.ndarray

    @classmethod
    def of(cls, robot):
        sp = robot.spools
        if any(s is None for s in sp):
            raise CdprError(f"{robot.source}: motor angles need a spool winch on every cable")
        if (robot.arrays.kind != 0).any():
            raise CdprError(
                f"{robot.source}: the motor-angle calibration knows fixed anchors only (pulley.kind: fixed)"
            )
        if any(np.any(np.asarray(c.B) != 0) for c in robot.cables):
            raise CdprError(f"{robot.source}: the motor-angle calibration is for a point mass")
        return cls(
            A=np.array([c.A for c in robot.cables], dtype=float),
            d=np.asarray(robot.arrays.d, dtype=float).copy(),
            r0=np.array([s.r0 for s in sp], dtype=float),
            Q=np.array([s.Q for s in sp], dtype=float),
            U=np.array([s.U for s in sp], dtype=float),
            lines=np.array([s.lines_per_spool for s in sp], dtype=float),
            ratio=np.array([s.motor_teeth / s.spool_teeth for s in sp], dtype=float),
            K=np.asarray(robot.arrays.ES, dtype=float).copy(),
        )

    def theta(self):
        return np.concatenate([self.A.ravel(), self.r0, self.Q])

    def with_theta(self, th):
        m = len(self.r0)
        return dataclasses.replace(
            self, A=th[: 3 * m].reshape(m, 3), r0=th[3 * m : 4 * m], Q=th[4 * m : 5 * m]
        )


def motor_names(m):
    """Names of the motor-angle parameter vector: A_1_x .. A_m_z, r0_1 .. r0_m, Q_1 .. Q_m."""
    return (
        [f"A_{i + 1}_{a}" for i in range(m) for a in "xyz"]
        + [f"r0_{i + 1}" for i in range(m)]
        + [f"Q_{i + 1}" for i in range(m)]
    )


def motor_index(m, groups):
    """Entries of ``motor_names(m)`` the ``groups`` estimate: anchors A_1_x .. A_m_z, spools r0 and Q.

    Parameters
    ----------
    m : int
        Cables.
    groups : sequence of str
        Among ``MOTOR_GROUPS``.

    Returns
    -------
    ndarray of int
    """
    idx = []
    if "anchors" in groups:
        idx += list(range(3 * m))
    if "spools" in groups:
        idx += list(range(3 * m, 5 * m))
    return np.array(idx, dtype=int)


def motor_prior_sd(m, index, priors):
    """Prior sd of the entries ``index`` of ``motor_names(m)``: anchors and spool radii from
    ``priors``, the buildup factors ``priors["buildup"]`` where given (a study's wider prior; the
    command line has no such group), else ``BUILDUP_PRIOR_SD``.

    Parameters
    ----------
    m : int
        Cables.
    index : ndarray of int
        ``motor_index``.
    priors : dict group -> float [m]
        ``estimator.parse_motor_priors``, optionally with ``buildup``.

    Returns
    -------
    sd : ndarray (len(index),) [m]
    """
    q_sd = priors.get("buildup", BUILDUP_PRIOR_SD)
    if not (np.isfinite(q_sd) and q_sd > 0):
        raise CdprError(f"the prior sd of the buildup factor must be > 0 m, got {q_sd!r}")
    sd = np.empty(len(index))
    for j, k in enumerate(index):
        sd[j] = priors["anchors"] if k < 3 * m else (priors["spools"] if k < 4 * m else q_sd)
    return sd


def reference_forces(data, model):
    """The forces at the encoder reference t_ref (m,) [N] and a warning (or None): the first sample
    whose motor angles are all within ``REFERENCE_DEG`` of 0 and that has forces (the exact model
    only; zero for ``standard``).

    Parameters
    ----------
    data : MotorData
    model : {"exact", "standard"}

    Returns
    -------
    t_ref : ndarray (m,) [N]
    warning : str or None
    """
    m = data.motor_deg.shape[1]
    if model == "standard" or not data.has_force.any():
        return np.zeros(m), None
    ref = np.flatnonzero((np.abs(data.motor_deg) <= REFERENCE_DEG).all(axis=1) & data.has_force)
    if not len(ref):
        return np.zeros(m), (
            f"{data.source}: no sample at the encoder reference (motor angles within {REFERENCE_DEG:g} deg of 0) "
            "has forces; the line stretch at the reference is taken as zero"
        )
    return data.force[ref[0]].copy(), None


def stretch_factors(model, data, t_ref, K):
    """The line stretch of each sample and of the encoder reference.

    Parameters
    ----------
    model : {"exact", "standard"}
    data : MotorData
    t_ref : ndarray (m,) [N]
        ``reference_forces``.
    K : ndarray (m,) [N]
        The strands' axial stiffness ``SpoolModel.K``.

    Returns
    -------
    f : ndarray (n, m)
        1 + t / K where the exact model has forces, 1 elsewhere.
    g : ndarray (m,)
        1 / (1 + t_ref / K).
    """
    n, m = data.motor_deg.shape
    f = np.ones((n, m))
    if model == "exact":
        hf = data.has_force
        f[hf] = 1.0 + data.force[hf] / K
    return f, 1.0 / (1.0 + t_ref / K)


def line_terms(sm, motor_deg, f, g):
    """The predicted line l_pred (n, m) [m] minus d (so it compares with |A_i - P|) and the spool
    angle phi (n, m) [rad]."""
    phi = np.deg2rad(motor_deg) * sm.ratio
    s = winch.released_line(phi, sm.r0, sm.Q, sm.lines)
    l0 = np.linalg.norm(sm.A, axis=1) + sm.d
    return (l0 * g + s / sm.U) * f - sm.d, phi


def line_residuals(sm, data, P, f, g):
    """Line residuals |A_i - P_k| + d_i - l_pred,ki (n, m) [m] of the motor-angle model.

    Parameters
    ----------
    sm : SpoolModel
    data : MotorData
    P : ndarray (n, 3) [m]
        Mover positions.
    f, g : ndarray
        ``stretch_factors``.

    Returns
    -------
    r : ndarray (n, m) [m]
    """
    pred, _ = line_terms(sm, data.motor_deg, f, g)
    return np.linalg.norm(P[:, None, :] - sm.A, axis=-1) - pred


# ---- solving positions -------------------------------------------------------------------------
def solve_positions(sm, data, f, g, start=None, iterations=60):
    """Each sample's position from its readings alone: Gauss-Newton on its m line residuals
    (least squares, 3 unknowns), vectorised over samples.

    Parameters
    ----------
    sm : SpoolModel
    data : MotorData
    f, g : ndarray
        ``stretch_factors``.
    start : ndarray (n, 3), optional
        Start positions [m] (default: the anchors' centroid).
    iterations : int

    Returns
    -------
    P : ndarray (n, 3) [m]
    line_rms : ndarray (n,) [m]
        RMS of the m line residuals at P (NaN where not converged).
    """
    n = len(data.sample)
    pred, _ = line_terms(sm, data.motor_deg, f, g)
    P = np.tile(sm.A.mean(axis=0), (n, 1)) if start is None else np.array(start, dtype=float)
    for _ in range(iterations):
        diff = P[:, None, :] - sm.A
        dist = np.linalg.norm(diff, axis=-1)
        r = dist - pred
        u = diff / dist[..., None]
        JtJ = np.einsum("nia,nib->nab", u, u) + 1e-12 * np.eye(3)
        step = np.linalg.solve(JtJ, np.einsum("nia,ni->na", u, r)[..., None])[..., 0]
        P = P - step
        if np.nanmax(np.abs(step)) < 1e-13:
            break
    r = np.linalg.norm(P[:, None, :] - sm.A, axis=-1) - pred
    rms = np.sqrt(np.mean(r**2, axis=1))
    return P, np.where(np.isfinite(rms), rms, np.nan)


def gauge_words(data, groups):
    """The gauge of a motor-angle calibration in words (module docstring)."""
    if data.has_pose.any():
        return (
            "the encoder reference fixes the origin (mover at the origin at zero motor angle); "
            f"{int(data.has_pose.sum())} measured positions fix the frame's orientation"
            + (" and scale" if "spools" in groups else "")
        )
    return (
        "no measured position: the encoder reference fixes the origin (mover at the origin at zero motor "
        "angle); the frame's rotation about the origin"
        + (
            " and its scale (anchors, positions and spool radii together) are"
            if "spools" in groups
            else " is"
        )
        + " not seen by the data and fixed by the priors alone"
    )


def motor_problem(sm0, data, index, sd, f, g, sigma_line=SIGMA_LINE_DEFAULT):
    """The MAP residual of a motor-angle calibration and its exact Jacobian, in the variables
    x = [(θ_index - θ0_index) / sd, P_1, .., P_n] (module docstring).

    Rows: the n m line rows (``line_residuals`` / sigma_line), 3 rows (P_k - y_k) / sigma_k per
    measured position, the k prior rows.

    Parameters
    ----------
    sm0 : SpoolModel
        The nominal robot (the prior mean).
    data : MotorData
    index : ndarray of int
        Estimated entries of ``motor_names``.
    sd : ndarray [m]
        Their prior sd.
    f, g : ndarray
        The stretch factors (``stretch_factors``).
    sigma_line : float [m]

    Returns
    -------
    residual, jacobian, unpack : callables of x
        unpack(x) gives (SpoolModel, P (n, 3) [m]).
    """
    m, n, k = len(sm0.r0), len(data.sample), len(index)
    th0 = sm0.theta()
    hp = data.has_pose
    ip = np.flatnonzero(hp)

    def unpack(x):
        th = th0.copy()
        th[index] += sd * x[:k]
        return sm0.with_theta(th), x[k:].reshape(n, 3)

    def residual(x):
        sm, P = unpack(x)
        r = line_residuals(sm, data, P, f, g) / sigma_line
        rp = (P[ip] - data.pose[ip]) / data.sigma[ip, None]
        return np.concatenate([r.ravel(), rp.ravel(), x[:k]])

    def jacobian(x):
        sm, P = unpack(x)
        diff = P[:, None, :] - sm.A
        u = diff / np.linalg.norm(diff, axis=-1, keepdims=True)  # (n, m, 3)
        phi = np.deg2rad(data.motor_deg) * sm.ratio
        nA = sm.A / np.linalg.norm(sm.A, axis=1, keepdims=True)
        J = np.zeros((n * m + 3 * len(ip) + k, k + 3 * n))
        for kk in range(n):
            J[kk * m : (kk + 1) * m, k + 3 * kk : k + 3 * kk + 3] = u[kk] / sigma_line
        for j, col in enumerate(index):
            dr = np.zeros((n, m))
            if col < 3 * m:
                c, ax = divmod(col, 3)
                dr[:, c] = -u[:, c, ax] - f[:, c] * g[c] * nA[c, ax]
            elif col < 4 * m:
                c = col - 3 * m
                dr[:, c] = -f[:, c] * phi[:, c] / sm.U[c]
            else:
                c = col - 4 * m
                dr[:, c] = f[:, c] * sm.lines[c] * phi[:, c] ** 2 / (4 * sm.U[c])
            J[: n * m, j] = (dr * sd[j] / sigma_line).ravel()
        for q, kk in enumerate(ip):
            J[n * m + 3 * q : n * m + 3 * q + 3, k + 3 * kk : k + 3 * kk + 3] = np.eye(3) / data.sigma[kk]
        J[n * m + 3 * len(ip) :, :k] = np.eye(k)
        return J

    return residual, jacobian, unpack
