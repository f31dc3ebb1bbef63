"""The paper's analyses as functions of a robot: trajectories (section 3.3.1), planes (3.3.2),
error-limited volumes (3.3.3), regular workspaces and the global index (4.1), factorial designs
(4.2), optimal lines (4.3); and the winch curves over the cable length (Métillon 2022, Fig. 7).
Each returns a DataFrame or a small dict; no files, no Snakemake.

Section and figure numbers are those of Paty 2021; every point's pose error is |dp| of its eq. (14).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
Métillon, M., Charron, C., Subrin, K., Caro, S. (2022). Geometrical modelling of a cable-driven
parallel robot winch. 25e Congrès Français de Mécanique, hal-03758222.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from cdpr.analyses.compensation import heavy_distribution
from cdpr.analyses.workspace import cell_centres, frame_box
from cdpr.models import catenary, pulleys, winch
from cdpr.models.cables import HeavyCables
from cdpr.models.interference import interference
from cdpr.models.inverse import pose_state
from cdpr.models.platform import pose_arrays
from cdpr.robot import TABLE1
from cdpr.tables import solve_table


def trajectory_points(start, end, n):
    """n evenly spaced points on the segment start -> end and their arc length s [m].

    Parameters
    ----------
    start : array_like (3,) [m]
        First point.
    end : array_like (3,) [m]
        Last point.
    n : int
        Number of points, ends included.

    Returns
    -------
    P : ndarray (n, 3) [m]
        The points.
    s : ndarray (n,) [m]
        Arc length from ``start``.
    """
    start, end = np.asarray(start, dtype=float), np.asarray(end, dtype=float)
    f = np.linspace(0.0, 1.0, n)
    return start + f[:, None] * (end - start), f * np.linalg.norm(end - start)


def trajectory(robot, start, end, n, method="newton", **solver):
    """|dp| along a straight path (Fig. 10, 19): the point table plus the arc length ``s``.

    Paty 2021 section 3.3.1 (and 5.2 for Fig. 19); |dp| is eq. (14).

    Parameters
    ----------
    robot : Robot
    start : array_like (3,) [m]
        First point of the path.
    end : array_like (3,) [m]
        Last point of the path.
    n : int
        Number of points.
    method : {"newton", "fixed_point"}
        DEGM_E solver.
    solver : options of ``tables.solve_table`` (engine, threads, redundancy, tolerances).

    Returns
    -------
    DataFrame
        Column s [m] followed by the columns of ``tables.solve_table`` (x, y, z, ..., dp [m], ...,
        status), one row per point.
    """
    P, s = trajectory_points(start, end, n)
    df = solve_table(robot, P, method=method, **solver)
    df.insert(0, "s", s)
    return df


def plane_points(robot, z, n):
    """n x n cell centres over the anchors' horizontal bounding box at height z (Fig. 9, 12).

    Parameters
    ----------
    robot : Robot
        Supplies the joint points (``workspace.frame_box``).
    z : float [m]
        Height of the plane.
    n : int
        Cells per horizontal axis.

    Returns
    -------
    points : ndarray (n * n, 3) [m]
        x slowest, then y.
    """
    x0, x1, y0, y1, _, _ = frame_box(robot)
    X, Y = np.meshgrid(cell_centres(x0, x1, n), cell_centres(y0, y1, n), indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel(), np.full(X.size, float(z))])


def plane(robot, z, n, method="newton", **solver):
    """|dp| over the horizontal plane at height z (Fig. 12) with the chosen subsets (Fig. 9).

    Paty 2021 section 3.3.2; |dp| is eq. (14).

    Parameters
    ----------
    robot : Robot
    z : float [m]
        Height of the plane.
    n : int
        Cells per horizontal axis (``plane_points``).
    method : {"newton", "fixed_point"}
        DEGM_E solver.
    solver : options of ``tables.solve_table``.

    Returns
    -------
    DataFrame
        The table of ``tables.solve_table``, n * n rows.
    """
    return solve_table(robot, plane_points(robot, z, n), method=method, **solver)


def ok_extremes(df, column="dp"):
    """min and max |dp| (or another column) over the rows with status ok (NaN when there are none).

    Parameters
    ----------
    df : DataFrame
        Point table with columns ``status`` and ``dp`` [m].
    column : str
        The column: ``dp`` [m] by default, ``dphi`` [rad] of a rigid platform's table.

    Returns
    -------
    tuple of 2 float [unit of the column]
        (min, max) of the column over the ``ok`` rows.
    """
    ok = df.loc[df["status"] == "ok", column]
    return (float(ok.min()), float(ok.max())) if len(ok) else (float("nan"), float("nan"))


def crossings(s, a, b):
    """Arc lengths where curve a - b changes sign (linear interpolation), e.g. E_max vs E_min (Fig. 19).

    Parameters
    ----------
    s : array_like (n,) [m]
        Arc lengths along the path.
    a : array_like (n,) [any unit]
        First curve (e.g. |dp| [m] with the largest modulus); NaN points are dropped.
    b : array_like (n,) [unit of a]
        Second curve.

    Returns
    -------
    list of float [m]
        Arc lengths of the strict sign changes of a - b (a point where a - b is exactly 0 is not
        counted).
    """
    s, diff = np.asarray(s), np.asarray(a) - np.asarray(b)
    good = np.isfinite(diff)
    s, diff = s[good], diff[good]
    on = [float(s[i]) for i in np.flatnonzero(diff == 0)]  # a crossing that lands on a sample
    idx = np.flatnonzero(np.sign(diff[:-1]) * np.sign(diff[1:]) < 0)
    between = [float(s[i] - diff[i] * (s[i + 1] - s[i]) / (diff[i + 1] - diff[i])) for i in idx]
    return sorted(on + between)


# ---- the robot at a pose (``cdpr view``, the study's robot figure) ------------------------------
#: Points per sheave circle of ``pose_geometry``.
SHEAVE_POINTS = 41


def view_position(robot):
    """The platform position a picture of ``robot`` shows by default (no paper equation): the
    anchors' centroid in x and y; in z the middle of the frame's extent (``frame_box``: the floor,
    or the lowest anchor, to the highest anchor), for a suspended point mass 60 % of the middle of
    the anchors' height range (every anchor is above it).

    Parameters
    ----------
    robot : Robot
        Supplies the joint points A (m, 3) [m].

    Returns
    -------
    p : ndarray (3,) [m]
        The position.
    """
    A = robot.A
    if robot.suspended_point_mass:
        z = robot.floor_z + 0.3 * (A[:, 2].min() + A[:, 2].max() - 2 * robot.floor_z)
    else:
        box = frame_box(robot)
        z = 0.5 * (box[4] + box[5])
    return np.array([A[:, 0].mean(), A[:, 1].mean(), z])


def pose_geometry(robot, p, rotvec=None):
    """Every point a picture of the robot at the desired pose (p, rotvec) draws, from the extended
    inverse model of each cable (Paty 2021 eq. 3-7 at the attachment points B_i = p + R b_i; no
    equilibrium is solved: the platform is where it is asked to be).

    Parameters
    ----------
    robot : Robot
        The robot (m cables).
    p : array_like (3,) [m]
        Platform reference point.
    rotvec : array_like (3,) [rad], optional
        Platform orientation as a rotation vector (default identity).

    Returns
    -------
    dict
        ``A`` (m, 3) [m] joint points; ``axis`` (m, 3) [-] unit swivel axes k_i; ``C`` (m, 3) [m]
        winch exit points C_i = A_i - d_i k_i; ``H``, ``K``, ``D`` (m, 3) [m] sheave centres and
        the tangent points where the cable enters and leaves the sheave; ``B`` (m, 3) [m]
        attachment points; ``sheave`` (m, SHEAVE_POINTS, 3) [m] each sheave's circle (radius r_p
        about H_i, in the plane of k_i and D_i - H_i; empty for a fixed pulley: NaN); ``p`` (3,)
        [m]; ``R`` (3, 3) [-] and ``rotvec`` (3,) [rad] the orientation; ``com`` (3,) [m] the centre of mass; ``point_mass`` bool; ``name``;
        ``interfering`` (m,) bool: the cables that interfere at the pose (in an interfering
        cable-cable pair or through the platform body, ``models.interference``; never on a point mass;
        heavy cables: their catenaries under the drawn distribution's rest lengths); heavy cables
        add ``catenary_geometry``'s keys.
    """
    p_, R = pose_arrays([p], None if rotvec is None else [rotvec])
    B, st = pose_state(robot, p_, R)
    heavy = catenary_geometry(robot, p_[0], R[0]) if robot.heavy else {}
    a = robot.arrays
    B, H, K, D = B[0], st.H[0], st.K[0], st.D[0]
    r_p = np.asarray(robot.r_p, dtype=float)
    e_s = D - H
    e_s /= np.maximum(np.linalg.norm(e_s, axis=1), 1e-12)[:, None]
    w = np.cross(np.cross(e_s, a.axis), e_s)
    w /= np.maximum(np.linalg.norm(w, axis=1), 1e-12)[:, None]
    t = np.linspace(0.0, 2.0 * np.pi, SHEAVE_POINTS)[None, :, None]
    sheave = H[:, None, :] + r_p[:, None, None] * (np.cos(t) * e_s[:, None, :] + np.sin(t) * w[:, None, :])
    sheave[r_p <= 0] = np.nan
    return {
        "A": a.A.copy(),
        "axis": a.axis.copy(),
        "C": a.A - a.d[:, None] * a.axis,
        "H": H,
        "K": K,
        "D": D,
        "B": B,
        "sheave": sheave,
        "p": p_[0],
        "R": R[0],
        "rotvec": np.zeros(3) if rotvec is None else np.asarray(rotvec, dtype=float).copy(),
        "com": p_[0] + R[0] @ a.com,
        "point_mass": robot.point_mass,
        "name": robot.name,
        "interfering": interfering_cables(
            robot, p_[0], None if rotvec is None else rotvec, heavy.get("catenary_L0")
        ),
        **heavy,
    }


#: Points of each heavy cable's polyline in ``catenary_geometry`` (B to D).
CATENARY_POINTS = 101


def catenary_geometry(robot, p, R, n=CATENARY_POINTS):
    """The heavy cables (issue 38) at the desired pose, as drawn: the sag-consistent tension
    distribution that holds the platform there (``compensation.heavy_distribution``, tensions at
    B_i at least ``compensation``'s default least tension) and each free span's elastic catenary
    (``catenary.shape``, Irvine 1981 ch. 2) from B_i to its exit point D_i, placed in the vertical
    plane through B_i and D_i: point = B_i + x e_h,i + z up.

    Parameters
    ----------
    robot : Robot
        A robot with heavy cables (``Robot.heavy``).
    p : array_like (3,) [m]
        Platform reference point.
    R : array_like (3, 3) [-]
        Platform orientation.
    n : int
        Points of each polyline (>= 2).

    Returns
    -------
    dict
        ``catenary`` (m, n, 3) [m] the polylines from B_i to D_i (NaN where no distribution holds
        the pose); ``catenary_D`` (m, 3) [m] the exit points of the heavy pulley coupling;
        ``catenary_t`` (m,) [N] the tensions at B_i; ``catenary_sag`` (m,) [m] each cable's sag
        (``catenary.sag``: the largest deflection from the chord D_i-B_i); ``catenary_L0`` (m,) [m]
        the whole cables' rest lengths of that distribution (NaN where none holds the pose).
    """
    p = np.asarray(p, dtype=float)[None, :]
    R = np.asarray(R, dtype=float)[None, :, :]
    h = heavy_distribution(robot, p, R)
    inv = h["inverse"]
    cab = HeavyCables(robot)
    w, EA = cab.w, cab.EA
    x, z = catenary.shape(inv["H"][0], inv["V_B"][0], inv["L0_free"][0], w, EA, n=n)
    B = p[0] + np.einsum("ab,mb->ma", R[0], cab.b)
    poly = B[:, None, :] + x[..., None] * inv["e_h"][0][:, None, :] + z[..., None] * cab.up
    ok = bool(h["feasible"][0])
    sag = catenary.sag(inv["H"][0], inv["V_B"][0], inv["L0_free"][0], w, EA, inv["l_h"][0], inv["l_v"][0])
    nan = np.full(len(B), np.nan)
    return {
        "catenary": poly if ok else np.full_like(poly, np.nan),
        "catenary_D": inv["D"][0] if ok else np.full_like(B, np.nan),
        "catenary_t": h["t"][0],
        "catenary_sag": sag if ok else nan,
        "catenary_L0": inv["L0"][0] if ok else nan,
    }


def interfering_cables(robot, p, rotvec=None, L0=None):
    """The cables that interfere at one pose (``models.interference``): those of an interfering
    cable-cable pair and those that run through the platform body.

    Parameters
    ----------
    robot : Robot
    p : array_like (3,) [m]
        Platform reference point.
    rotvec : array_like (3,) [rad], optional
        Orientation (default identity).
    L0 : array_like (m,) [m], optional
        Rest lengths of heavy cables (their catenaries' polylines are tested; required when the
        robot's cables are heavy and a pair or a platform body is tested).

    Returns
    -------
    ndarray (m,) bool
    """
    res = interference(
        robot, np.asarray(p, dtype=float).reshape(1, 3), None if rotvec is None else [rotvec], L0=L0
    )
    out = res.cp[0].copy()
    for q in np.flatnonzero(res.cc[0]):
        out[res.pairs[q]] = True
    return out


#: Points of the sheave circle and of the wrapped arc in ``pulley_plane_geometry``.
ARC_POINTS = 181


def pulley_plane_geometry(robot, i, B):
    r"""Every point of one pulley that a picture of its cable plane draws, from the extended inverse
    model of that cable (``models.pulleys.pulley_state``, Paty 2021 eq. 3-7) with the attachment
    point B: the plane through the swivel axis k_i (through A_i) that contains B, with in-plane
    coordinates (s, w), origin A_i, s perpendicular to k_i toward B, w along k_i:

    .. math:: s = (X - A_i)\cdot\mathbf e_s,\qquad w = (X - A_i)\cdot\mathbf k_i,
        \qquad C_i = A_i - d_i\,\mathbf k_i

    No equilibrium is solved and nothing else of the robot is used.

    Parameters
    ----------
    robot : Robot
        Supplies the pulley of cable ``i`` (A_i, kind, h, r_p, d, frame, fallback plane).
    i : int
        Cable index (0-based).
    B : array_like (3,) [m]
        Attachment point (base frame).

    Returns
    -------
    dict
        ``plane``: name -> (s, w) [m] of the points C (winch exit), A (joint point), H (sheave
        centre), K (entry tangent point), D (exit tangent point), B; ``points``: the same names ->
        (3,) base-frame points [m]; ``arc`` (ARC_POINTS, 2) [m] the wrapped arc K -> D over the +k
        side and ``sheave`` (ARC_POINTS, 2) [m] the sheave circle (NaN for a fixed pulley), in (s, w);
        ``top``: name -> components along (i_i, j_i) [m] of B - A_i and of H - A_i, and ``e_s``
        (2,) [-] the plane's direction in (i_i, j_i); ``frame`` (3, 3) [-] rows i_i, j_i, k_i;
        ``e_s3`` (3,) [-]; ``swivel`` [rad] (``pulleys.swivel``); ``gamma`` wrap [rad]; ``L_TE``,
        ``l_E`` = |B - D|, ``l_d`` = |K - C| [m]; ``kind`` (str), ``h``, ``r_p``, ``d`` [m];
        ``cable`` (1-based) and ``name`` (the robot's).

    References
    ----------
    Paty et al. 2021, eq. (3)-(7).
    """
    a = robot.arrays
    sl = slice(i, i + 1)
    B = np.asarray(B, dtype=float).reshape(1, 3)
    args = (a.A[sl], a.kind[sl], a.h[sl], a.r_p[sl], a.d[sl], a.inward[sl], a.frame[sl])
    st = pulleys.pulley_state(B, *args, per_cable=True)
    A, F = a.A[i], a.frame[i]
    e_s3, k = st.e_s3[0], F[2]
    pts = {
        "C": A - a.d[i] * k,
        "A": A.copy(),
        "H": st.H[0],
        "K": st.K[0],
        "D": st.D[0],
        "B": B[0].copy(),
    }
    plane = {n: np.array([(X - A) @ e_s3, (X - A) @ k]) for n, X in pts.items()}
    r_p, gamma = float(a.r_p[i]), float(st.gamma[0])
    Hs, Hw = plane["H"]
    th_K = np.arctan2(plane["K"][1] - Hw, plane["K"][0] - Hs)
    t = np.linspace(0.0, 1.0, ARC_POINTS)
    th = th_K - gamma * t  # from K over the +k side to D
    arc = np.column_stack([Hs + r_p * np.cos(th), Hw + r_p * np.sin(th)])
    full = 2.0 * np.pi * t
    sheave = np.column_stack([Hs + r_p * np.cos(full), Hw + r_p * np.sin(full)])
    if r_p <= 0:
        sheave[:] = np.nan
    return {
        "plane": plane,
        "points": pts,
        "arc": arc,
        "sheave": sheave,
        "top": {n: np.array([(pts[n] - A) @ F[0], (pts[n] - A) @ F[1]]) for n in ("B", "H")},
        "e_s": st.e_s[0].copy(),
        "frame": F.copy(),
        "e_s3": e_s3.copy(),
        "swivel": float(pulleys.swivel(B, a.A[sl], a.frame[sl], a.inward[sl], per_cable=True)[0]),
        "gamma": gamma,
        "L_TE": float(st.L_TE[0]),
        "l_E": float(st.l_E[0]),
        "l_d": float(st.l_d[0]),
        "kind": robot.cables[i].pulley.kind,
        "h": float(a.h[i]),
        "r_p": r_p,
        "d": float(a.d[i]),
        "cable": i + 1,
        "name": robot.name,
    }


# ---- winch (Métillon 2022, Fig. 7) ---------------------------------------------------------
def winch_table(p=TABLE1, lpm_from=0.0, lpm_to=5.0, steps=101):
    """q1, q2, q_nw and dl over l_pm in [lpm_from, lpm_to] as a DataFrame (SI units).

    Métillon 2022 Fig. 7: the two roots (eq. 29-30 corrected), the no-winch angle (eq. 32) and the
    length error (eq. 31).

    Parameters
    ----------
    p : WinchParams
        Default Table 1 (``robot.TABLE1``).
    lpm_from : float [m]
        First length l_pm.
    lpm_to : float [m]
        Last length l_pm.
    steps : int
        Number of evenly spaced lengths.

    Returns
    -------
    DataFrame
        ``steps`` rows, columns l_pm [m], q1 [rad], q2 [rad], q_nw [rad], dl [m].

    References
    ----------
    Métillon et al. 2022, eq. (29)-(32), Fig. 7.
    """
    l_pm = np.linspace(lpm_from, lpm_to, steps)
    q1, q2 = winch.roots(p, l_pm)
    q_nw = winch.q_no_winch(p, l_pm)
    return pd.DataFrame({"l_pm": l_pm, "q1": q1, "q2": q2, "q_nw": q_nw, "dl": p.k_w * (q1 - q_nw)})
