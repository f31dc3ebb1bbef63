"""Synthetic calibration data: a true robot measured at commanded poses (``simulate``), robots
drawn from the prior (``perturbed``), admissible random 6-DoF poses (``random_poses``) and the
taut-cable and second-equilibrium flags of samples (``equilibrium_flags``); a spool robot's motor
angles at given positions (``simulate_motor``).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Mechanism and Machine Theory 159, 104263,
eq. (2) (the commanded standard lengths L_TS).
Métillon, M. et al. (2022), eq. 31-32 (the drums' realised lengths).
"""

from __future__ import annotations

import numpy as np

from cdpr.analyses.calibration.data import (
    SIGMA_DEFAULT,
    SIGMA_POSITION_DEFAULT,
    SIGMA_RAD_DEFAULT,
    SIGMA_T_DEFAULT,
    Data,
    MotorData,
)
from cdpr.analyses.calibration.model import (
    check_command,
    commanded_lengths,
    equilibria,
    realised_lengths,
)
from cdpr.analyses.calibration.motor import SpoolModel
from cdpr.errors import CdprError
from cdpr.models import winch
from cdpr.models.inverse import L_TS
from cdpr.models.platform import pose_arrays, rotation_matrix, rotvec_of
from cdpr.parameters import (
    calibrated_robot,
    calibration_values,
    is_spatial,
)


def simulate(
    truth,
    nominal,
    P,
    sigma=SIGMA_DEFAULT,
    rng=None,
    offsets=None,
    engine=None,
    tensions=False,
    sigma_t=SIGMA_T_DEFAULT,
    rotvec=None,
    sigma_rad=SIGMA_RAD_DEFAULT,
    command="standard",
):
    """Synthetic tracker data: the lengths the nominal robot would command to reach P (L_TS, eq. 2),
    the pose where the true robot settles under them, plus Gaussian noise. A true robot with
    winches realises the commands through its drums (``realised_lengths``: a controller that
    neglects the exit point's motion, Métillon 2022 eq. 31-32); the data keep the commands. A
    robot settles where ``equilibria`` says (the pose model on a rigid platform and under a tilted
    pulley axis).

    Parameters
    ----------
    truth : Robot
        The real robot.
    nominal : Robot
        The model that computes the commands.
    P : ndarray, shape (n, 3) [m]
        Targets.
    sigma : float [m]
        Tracker noise sd.
    rng : numpy Generator, optional
        Noise source (None: noise-free).
    offsets : ndarray, shape (m,) [m], optional
        Encoder offsets: the data are then readings L0 + offsets.
    tensions : bool
        Also measure the cable tensions (noise sd ``sigma_t`` [N]).
    rotvec : ndarray, shape (n, 3) or (3,) [rad], optional
        Target orientations of a 6-DoF platform (default identity; or P of shape (n, 6)): the
        commands are then L_TS,i = |p + R b_i - A_i| + d_i and the tracker also measures the
        orientation, R_meas = exp([w]) R*, w ~ N(0, ``sigma_rad``² I) [rad].
    command : {"standard", "compensated"}
        ``COMMANDS``; "compensated" only for a 6-DoF platform.

    Returns
    -------
    Data
        With status "ok" samples only (the others are dropped here: this is the simulator, not the fit).
    """
    check_command(command, truth)
    spatial = is_spatial(truth)
    if spatial:  # the pose's orientation: commanded, settled and measured
        p, R = pose_arrays(P, rotvec)
        rv = rotvec_of(R)
        L0 = commanded_lengths(nominal, p, R, command)
        fin = np.isfinite(L0).all(axis=1)
        p, rv, L0 = p[fin], rv[fin], L0[fin]
    else:
        p, rv, L0 = P, None, L_TS(nominal, P)
    L_real = realised_lengths(truth, L0)  # through the true robot's drums when it has winches
    drum = np.isfinite(L_real).all(axis=1)
    res = equilibria(truth, p, np.where(drum[:, None], L_real, L0), rotvec=rv, engine=engine)
    ok = (res["status"] == "ok") & res["smooth"] & drum
    n = int(ok.sum())
    y = res["P_s"][ok]
    Rs = res["R_s"][ok] if spatial else None
    if rng is not None:  # the tracker's noise: position, then the orientation of a rigid platform
        y = y + rng.normal(0.0, sigma, y.shape)
        Rs = None if Rs is None else rotation_matrix(rng.normal(0.0, sigma_rad, (n, 3))) @ Rs
    orientation = {} if Rs is None else {"rotvec": rotvec_of(Rs), "sigma_rad": np.full(n, float(sigma_rad))}
    t = np.full((n, truth.m), np.nan)
    if tensions:
        t = _measured_tensions(res["t"][ok], sigma_t, rng)
    return Data(
        tension=t,
        sigma_t=np.full(n, float(sigma_t)),
        sample=np.array([f"s{i + 1}" for i in range(n)]),
        L=L0[ok] if offsets is None else L0[ok] + np.asarray(offsets),
        pose=y,
        sigma=np.full(n, float(sigma)),
        encoder=offsets is not None,
        source="<simulated>",
        **orientation,
    )


def _measured_tensions(t, sigma_t, rng):
    """Tension-sensor readings of the equilibrium tensions t (n, m) [N] (NaN on a slack cable, read
    as 0 N): plus N(0, sigma_t²) noise with ``rng``, clipped at 0 N."""
    t = np.nan_to_num(t)
    if rng is not None:
        t = np.maximum(t + rng.normal(0.0, sigma_t, t.shape), 0.0)
    return t


def perturbed(robot, index, sd, rng):
    """A robot whose parameters ``index`` are drawn from the prior N(nominal, sd²); returns (robot, θ)."""
    th = calibration_values(robot)
    th[index] += sd * rng.standard_normal(len(index))
    return calibrated_robot(robot, th), th


def random_poses(robot, rng, n, box, tilt=0.1, margin=100.0, command="standard"):
    """n random poses of a 6-DoF platform where the robot under the ``command`` lengths
    (``commanded_lengths``) settles ``ok`` with every cable taut by more than ``margin``.

    Positions are uniform in ``box`` (x, then y, then z drawn), rotation vectors uniform in
    [-tilt, tilt]³; 4n candidates are drawn and the first n admissible kept (the others are
    rejected: this draws targets, it is not the fit).

    Parameters
    ----------
    robot : Robot
        6-DoF platform that computes the commands and judges admissibility (the nominal robot).
    rng : numpy Generator
    n : int
        Number of poses.
    box : list of 6 float [m]
        [xmin, xmax, ymin, ymax, zmin, zmax] of the positions.
    tilt : float [rad]
        Largest rotation-vector component.
    margin : float [N]
        Least tension of every cable at an admissible pose.
    command : {"standard", "compensated"}
        ``COMMANDS``.

    Returns
    -------
    P6 : ndarray, shape (n, 6) [m, rad]
        Target positions and rotation vectors.

    Raises
    ------
    CdprError
        Fewer than n admissible poses among the 4n drawn.
    """
    p = np.column_stack([rng.uniform(box[2 * k], box[2 * k + 1], 4 * n) for k in range(3)])
    P6 = np.concatenate([p, rng.uniform(-tilt, tilt, (4 * n, 3))], axis=1)
    L = commanded_lengths(robot, P6[:, :3], rotation_matrix(P6[:, 3:]), command)
    fin = np.isfinite(L).all(axis=1)
    P6, L = P6[fin], L[fin]
    res = equilibria(robot, P6[:, :3], L, rotvec=P6[:, 3:])
    good = (res["status"] == "ok") & (np.nan_to_num(res["t"]) > margin).all(axis=1)
    if good.sum() < n:
        raise CdprError(
            f"only {int(good.sum())} admissible poses of {4 * n} drawn in {list(box)} (tilt {tilt} rad, "
            f"every cable above {margin} N, {command} commands); ask for fewer or widen the box"
        )
    return P6[good][:n]


def equilibrium_flags(robot, data, kick=(0.05, 0.05), tol=1e-3):
    """Per sample: the number of taut cables of ``robot``'s equilibrium under the data's lengths
    (started at the measured pose), and whether a second equilibrium exists (``robot`` settles
    more than ``tol`` away when started from the measured pose moved by ±kick[0] along each axis or
    turned by ±kick[1] about each axis: 12 starts, a heuristic, not a proof of uniqueness).

    A 6-DoF platform on fewer than 6 taut cables has a soft mode (it swings until gravity
    balances), where a small parameter error moves the pose far.

    Parameters
    ----------
    robot : Robot
        6-DoF platform (the true robot of a simulation).
    data : Data
        Samples with poses and orientations.
    kick : tuple of 2 float [m, rad]
        Start offsets.
    tol : float [m]
        Distance beyond which an equilibrium counts as another one.

    Returns
    -------
    n_taut : ndarray, shape (N,) of int
        Taut cables that hold the platform (``equilibria``'s holding: a heavy cable hanging at
        about its own weight does not), 0 where the equilibrium is not ``ok``.
    second : ndarray, shape (N,) of bool
    """
    ref = equilibria(robot, data.pose, data.L, rotvec=data.rotvec)
    ok_ref = ref["status"] == "ok"
    second = np.zeros(len(data.sample), dtype=bool)
    for k in range(6):
        for s in (-1.0, 1.0):
            P, rv = data.pose.copy(), data.rotvec.copy()
            if k < 3:
                P[:, k] += s * kick[0]
            else:
                rv[:, k - 3] += s * kick[1]
            r = equilibria(robot, P, data.L, rotvec=rv)
            ok = (r["status"] == "ok") & ok_ref
            second |= ok & (np.linalg.norm(r["P_s"] - ref["P_s"], axis=1) > tol)
    n_taut = np.where(ok_ref, ref["holding"].sum(axis=1), 0).astype(int)
    return n_taut, second


def simulate_motor(
    truth, P, force=None, sigma_line=0.0, rng=None, measured=None, sigma=SIGMA_POSITION_DEFAULT
):
    """Motor-angle samples of a robot ``truth`` at positions P, the inverse of the model
    (``cdpr.analyses.calibration.motor``): the line l_i(P) = |A_i - P| + d_i under the force t stretches from the rest length
    L0 = l / (1 + t / K); the spool released s = U (L0 - L0_ref) with L0_ref = l_i(0) / (1 + t_ref / K),
    t_ref the forces of the first sample (put it at the origin: the encoders are zeroed there, so it
    reads 0 without noise); the motor angle releasing s
    (``winch.spool_angle_of_line``, ``winch.motor_degrees``). Without forces, rigid lines.

    Parameters
    ----------
    truth : Robot
    P : ndarray (n, 3) [m]
        True positions.
    force : ndarray (n, m) [N], optional
        Line forces (recorded in the data); None: rigid lines, no force columns.
    sigma_line : float [m]
        Noise sd added to each line (through its motor angle).
    rng : numpy Generator, optional
    measured : ndarray of bool (n,), optional
        Samples whose position is recorded (with noise ``sigma``); default none.
    sigma : float [m]
        Position noise sd.

    Returns
    -------
    MotorData
    """
    sm = SpoolModel.of(truth)
    P = np.asarray(P, dtype=float)
    n, m = len(P), len(sm.r0)
    rng = np.random.default_rng(0) if rng is None else rng
    ell = np.linalg.norm(P[:, None, :] - sm.A, axis=-1) + sm.d
    ell0 = np.linalg.norm(sm.A, axis=1) + sm.d
    if force is None:
        L0, L0_ref, F = ell, ell0, np.full((n, m), np.nan)
    else:
        F = np.asarray(force, dtype=float)
        L0, L0_ref = ell / (1.0 + F / sm.K), ell0 / (1.0 + F[0] / sm.K)
    noise = sigma_line * rng.standard_normal((n, m))
    noise[0] = 0.0  # the encoders are zeroed at the first sample: it reads 0 exactly
    L0 = L0 + noise
    s = sm.U * (L0 - L0_ref)
    phi = winch.spool_angle_of_line(s, sm.r0, sm.Q, sm.lines)
    deg = np.rad2deg(phi) / sm.ratio
    meas = np.zeros(n, dtype=bool) if measured is None else np.asarray(measured, dtype=bool)
    pose = np.full((n, 3), np.nan)
    pose[meas] = P[meas] + sigma * rng.standard_normal((int(meas.sum()), 3))
    return MotorData(
        sample=np.array([str(i) for i in range(n)]),
        motor_deg=deg,
        force=F,
        pose=pose,
        sigma=np.full(n, sigma),
        source="simulated",
    )
