"""Symmetries shared by a robot and a cell-centred grid: solve each orbit of equal points once.

Let g be an isometry of the horizontal plane about the vertical axis through the grid box's centre
c, one of the eight of the dihedral group D4 (identity, the rotations by 90, 180, 270 degrees, the
mirrors x -> -x, y -> -y and the two diagonals),

    g(P) = (c + T_g (P_xy - c), P_z),    T_g in {[[±1, 0], [0, ±1]], [[0, ±1], [±1, 0]]}.

If g maps every cable onto a cable with the same pulley kind, h, r_p, dead length, E S, admissible
tension and winch (A_pi(i) = g(A_i) for a permutation pi of the cables), and the external wrench is
vertical (gravity), every model of the library is equivariant under g: the equilibrium from g(p)
is g(P*(p)) with the tensions permuted by pi, so

    ‖δp‖(g p) = ‖δp‖(p)   and   status(g p) = status(p)

in both redundancy modes (paper mode's least error over the 3-cable subsets is a minimum over a
set that g permutes; physical mode's force balance is covariant, and its commanded lengths L_TS
are). If g also maps the grid's cells onto cells (box symmetric about c, equal half widths in x
and y for a rotation or a diagonal), the n^3 grid splits into orbits of points with equal ‖δp‖
and status; solving one point per orbit and copying its result gives the full grid's table of
‖δp‖ and status at a fraction of the cost (CDPR4 on the RW_C box: the 8 elements of D4, 33,264
solved points instead of 250,047 at n = 63).

In floating point the copies differ from a direct solve of the mirrored points by round-off
(≤ 1e-12 m on ‖δp‖, tested on both modes and pulley kinds); the global index (eq. 15) is a mean
over the same N points either way.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling
considering pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263,
eq. (15) (the global index over the cell-centred grid of RW_C).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from cdpr.analyses.workspace import check_box, grid_points
from cdpr.solve import reached_answer, solve

#: The eight elements of D4 as 2 x 2 integer matrices acting on centred (x, y).
D4 = tuple(
    np.array(t, dtype=int)
    for t in (
        [[1, 0], [0, 1]],
        [[-1, 0], [0, 1]],
        [[1, 0], [0, -1]],
        [[-1, 0], [0, -1]],
        [[0, 1], [1, 0]],
        [[0, -1], [1, 0]],
        [[0, 1], [-1, 0]],
        [[0, -1], [-1, 0]],
    )
)
#: Relative tolerance of the geometric comparisons [-] (anchors, box half widths).
TOL = 1e-9


def _cable_key(robot, i):
    """Everything of cable i except its anchor's position, as a comparable tuple."""
    a = robot.arrays
    return (int(a.kind[i]), a.h[i], a.r_p[i], a.d[i], a.ES[i], a.T_a[i], robot.cables[i].winch)


def robot_symmetric(robot, T, centre, tol=TOL):
    """True when the horizontal isometry P_xy -> centre + T (P_xy - centre) maps ``robot`` onto
    itself: each cable's anchor onto an anchor of a cable with equal parameters (``_cable_key``), the
    fallback pulley planes (``inward``) onto each other, and a vertical external wrench.

    Parameters
    ----------
    robot : Robot
    T : array (2, 2) of int
        An element of ``D4``.
    centre : array (2,) [m]
    tol : float
        Relative tolerance on positions (times the frame's size) [-].

    Returns
    -------
    bool
    """
    a = robot.arrays
    w = robot.platform.w_ext
    if abs(w[0]) > 0 or abs(w[1]) > 0:
        return False
    c = np.asarray(centre, dtype=float)
    scale = max(1.0, float(np.abs(a.A).max()))
    Axy = c + (a.A[:, :2] - c) @ np.asarray(T, dtype=float).T
    for i in range(robot.m):
        d = np.abs(a.A[:, :2] - Axy[i]).max(axis=1) + np.abs(a.A[:, 2] - a.A[i, 2])
        j = int(np.argmin(d))
        if d[j] > tol * scale or _cable_key(robot, i) != _cable_key(robot, j):
            return False
        if np.abs(a.inward[j] - np.asarray(T, dtype=float) @ a.inward[i]).max() > 1e-9:
            return False
    return True


def grid_symmetries(robot, box, tol=TOL):
    """The elements of ``D4`` (about the box's vertical centre line) that map both the box's
    cell-centred grids and the robot onto themselves; the identity is always among them.

    Parameters
    ----------
    robot : Robot
    box : array_like (6,) [m]
        xmin, xmax, ymin, ymax, zmin, zmax.
    tol : float
        Relative tolerance of the geometric comparisons [-].

    Returns
    -------
    list of array (2, 2) of int
    """
    b = check_box(box)
    if not robot.suspended_point_mass:  # attachments, COM and axes are not compared: identity only
        return [D4[0]]
    centre = np.array([(b[0] + b[1]) / 2, (b[2] + b[3]) / 2])
    wx, wy = (b[1] - b[0]) / 2, (b[3] - b[2]) / 2
    square = abs(wx - wy) <= tol * max(wx, wy)
    return [T for T in D4 if (T[0, 0] != 0 or square) and robot_symmetric(robot, T, centre, tol)]


def orbits(n, transforms):
    """One representative per orbit of the n^3 grid under ``transforms`` (a group of ``D4``
    elements acting on the centred cell indices) and, for every grid point, its orbit's position
    among the representatives.

    Parameters
    ----------
    n : int
        Points per axis (C order: x slowest, z fastest, as ``workspace.grid_points``).
    transforms : list of array (2, 2) of int

    Returns
    -------
    reps : array (K,) of int
        Linear indices of the representatives (the least index of each orbit), increasing.
    inverse : array (n^3,) of int
        ``reps[inverse[k]]`` is the representative of point k.
    """
    idx = np.arange(n**3)
    i, rem = np.divmod(idx, n * n)
    j, k = np.divmod(rem, n)
    u, v = 2 * i - (n - 1), 2 * j - (n - 1)  # centred cell indices (odd or even integers)
    key = idx.copy()
    for T in transforms:
        uu, vv = T[0, 0] * u + T[0, 1] * v, T[1, 0] * u + T[1, 1] * v
        key = np.minimum(key, ((uu + n - 1) // 2 * n + (vv + n - 1) // 2) * n + k)
    reps, inverse = np.unique(key, return_inverse=True)
    return reps, inverse


def solve_grid(robot, box, n, symmetric=True, **solver):
    """‖δp‖ and status at every point of the n^3 cell-centred grid of ``box``, solving one point per
    orbit of the symmetries the robot and the grid share (``grid_symmetries``).

    Parameters
    ----------
    robot : Robot
    box : array_like (6,) [m]
    n : int
    symmetric : bool
        False solves every point (the reference the symmetric solve is tested against).
    solver : passed to ``solve.solve`` (method, engine, threads, redundancy); commanded
        lengths ``L0`` are not allowed (they need not share the symmetry).

    Returns
    -------
    dp : array (n^3,) [m]
    status : array (n^3,) of str
    solved : int
        Number of points actually solved.
    """
    res, solved = solve_grid_columns(robot, box, n, ("dp", "status"), symmetric, **solver)
    return res["dp"], res["status"].astype(str), solved


def solve_grid_columns(robot, box, n, keys, symmetric=True, **solver):
    """``solve_grid`` returning the per-point arrays ``keys`` of the solve (``dp``, ``status``,
    ``dphi`` of a 6-DoF solve, ...) at every point of the n^3 grid.

    Parameters
    ----------
    robot : Robot
    box : array_like (6,) [m]
    n : int
    keys : sequence of str
        Keys of the ``solve.solve`` result; ``dphi`` [rad] is 0 for a point-mass
        solve that has none (a point has no orientation).
    symmetric : bool
    solver : as ``solve_grid`` (a fixed orientation ``rotvec`` is allowed: a robot that is not a
        suspended point mass is solved without symmetries, ``grid_symmetries``).

    Returns
    -------
    columns : dict
        key -> array (n^3,) in the grid's C order.
    solved : int
        Number of points actually solved.
    """
    if solver.get("L0") is not None:
        raise ValueError("solve_grid: commanded lengths L0 need not be symmetric; solve the full grid")
    if solver.get("rotvec") is not None:
        symmetric = False  # an orientation breaks the horizontal symmetries of the frame
    transforms = grid_symmetries(robot, box) if symmetric else [D4[0]]
    P, inverse = _orbit_points(tuple(check_box(box).tolist()), int(n), tuple(T.tobytes() for T in transforms))
    res = reached_answer(
        robot, solve(robot, P, **solver), engine=solver.get("engine"), threads=solver.get("threads")
    )
    out = {}
    for k in keys:
        v = np.asarray(res[k]) if k in res or k != "dphi" else np.zeros(len(P))
        out[k] = v[inverse]
    return out, len(P)


@lru_cache(maxsize=8)
def _orbit_points(box, n, transforms):
    """The representatives' coordinates (K, 3) [m] and the grid's orbit index (n^3,), computed once
    per box, n and group (a map job solves hundreds of cells on the same grid); callers must not
    modify them."""
    reps, inverse = orbits(n, [np.frombuffer(t, dtype=int).reshape(2, 2) for t in transforms])
    P = grid_points(box, n)[reps]
    inverse.flags.writeable = False  # P stays writeable: numba compiles read-only arrays anew
    return P, inverse
