"""``cdpr point``'s reached equilibrium (physical mode, issue 39): the equilibrium reached by
continuation (``cdpr.solve.reach``) beside the lowest-energy one over restarts, as the JSON objects
``reached`` and ``global`` (docs/interference.md)."""

from __future__ import annotations

import numpy as np

from cdpr.errors import CdprError


def start_options(args, robot):
    """``solve.reach``'s start options from --t-min/--t-max or --from/--from-rotvec/--from-lengths;
    CdprError in one line for a partial or contradictory start."""
    given = args.from_p is not None or args.from_lengths is not None or args.from_rotvec is not None
    if not given:
        if args.t_min is not None and args.t_max is not None and not args.t_min < args.t_max:
            raise CdprError(f"--t-min must be below --t-max, got {args.t_min:g} N and {args.t_max:g} N")
        return {"start": "compensated", "t_min": args.t_min, "t_max": args.t_max}
    if args.from_p is None or args.from_lengths is None:
        raise CdprError("a given start needs both --from X Y Z and --from-lengths L1 .. Lm")
    if args.t_min is not None or args.t_max is not None:
        raise CdprError("--t-min/--t-max set the compensated start; a start given with --from takes neither")
    if len(args.from_lengths) != robot.m:
        raise CdprError(
            f"--from-lengths needs one rest length per cable ({robot.m}), got {len(args.from_lengths)}"
        )
    return {
        "start": "given",
        "from_p": np.array(args.from_p, dtype=float),
        "from_rotvec": None if args.from_rotvec is None else np.array(args.from_rotvec, dtype=float),
        "from_lengths": np.array(args.from_lengths, dtype=float),
    }


def reach_point(robot, args, P, rv, L0, engine):
    """The reached equilibrium at the poses P (``solve.reach``) under the rest lengths L0 (None:
    L_TS at P), from the start the options give (``start_options``)."""
    from cdpr.solve import reach  # lazy: the solvers, for the solver commands only

    return reach(robot, P, rv, L0=L0, engine=engine, **start_options(args, robot))


def _energy(robot, res, reference):
    """The potential energy [J] at the first pose of a result without one (the point-mass fast
    path's keys), relative to the same origin as ``reference``'s (its desired pose and rest lengths)."""
    from cdpr.models.cables import Cables, HeavyCables  # lazy: the solver commands only

    cab = HeavyCables(robot) if robot.heavy else Cables(robot)
    R = reference["R_s"][:1] if "R_s" not in res else res["R_s"][:1]
    ev = cab.evaluate(res["P_s"][:1], R, reference["L0"][:1], reference["p"][:1], jacobian=False)
    return ev["merit"][0]


def _object(robot, res, rigid, reference):
    """The JSON object of one equilibrium of a result (its first pose); ``reference`` (the reached
    result) gives the energy's origin where ``res`` has no energy."""
    from cdpr.models.interference import interference_free  # lazy: the solver commands only

    t = res["t"][0]
    out = {"solved": res["P_s"][0].tolist()}
    rv = res["rotvec_s"][0].tolist() if rigid else None
    if rigid:
        out["solved_rotvec"] = rv
    out.update(
        energy_J=float(res["energy"][0] if "energy" in res else _energy(robot, res, reference)),
        taut=[int(i) + 1 for i in np.flatnonzero(res["taut"][0])],
        tensions=[None if np.isnan(v) else float(v) for v in t],
        interference_free=interference_free(
            robot, out["solved"], rv, L0=(res if "L0" in res else reference)["L0"][0]
        ),
        status=str(res["status"][0]),
    )
    return out


def table_answer(robot, args, res, engine):
    """``point --points``: a physical-mode chunk's result answered with the reached equilibrium
    where the restarts found more than one (``solve.reach_where_multiple``, the studies' rule), with
    --sensitivities taken there (``with_sensitivities``); unchanged with --equilibrium global, in
    paper mode or where all are unique."""
    from cdpr.solve import reach_where_multiple  # lazy: the solvers, for the solver commands only

    if args.redundancy != "physical" or args.equilibrium == "global":
        return res
    if "unique" not in res or np.all(res["unique"]):
        return res
    out = reach_where_multiple(robot, res, engine=engine, threads=args.threads, **start_options(args, robot))
    moved = np.flatnonzero(~out["reached_is_global"])
    if args.sensitivities and moved.size:  # dP*/dθ where the robot is
        out = with_sensitivities(robot, out, out, moved, engine, args.threads)
    return out


#: The keys of a solve result that the reached equilibrium replaces in ``point``'s answer.
KEYS = ("P_s", "dp", "rotvec_s", "R_s", "dphi", "t", "taut", "n_taut", "status", "iterations", "energy")


def answer(res, reached):
    """``res`` (the global solve) with the pose, tensions and status of the reached equilibrium;
    its ``unique`` and ``alternatives`` (the other equilibria the restarts know, ``others``) are
    those of the reached equilibrium, not of the global one."""
    out = {**res, **{k: reached[k] for k in KEYS if k in res}}
    if "alternatives" in res:
        out["alternatives"] = [others(res, reached, i) for i in range(len(res["P_s"]))]
        out["unique"] = np.array([not a for a in out["alternatives"]])
    return out


def with_sensitivities(robot, res, at, rows, engine, threads=None):
    """``res`` (a result with sensitivities whose pose at ``rows`` is the reached equilibrium) with
    ``S``, ``smooth``, ``margin_t`` and ``cond`` at ``rows`` taken at the equilibria of ``at`` there
    (``solve.sensitivities_at``: the implicit-function theorem at that pose under its rest lengths
    ``L0``); a point mass's S keeps its three rows dp*/dθ.

    Parameters
    ----------
    robot : Robot
    res : dict
        A result with names, S (N, 3 or 6, n), smooth and the reached pose at ``rows``.
    at : dict
        The equilibria the sensitivities are taken at: P_s, R_s, L0 and status (N, ...).
    rows : array_like of int
        The poses to replace.
    engine : {"compiled", "numpy"}
    threads : int, optional

    Returns
    -------
    dict
    """
    from cdpr.solve import sensitivities_at  # lazy: --sensitivities only

    rows = np.asarray(rows, dtype=int)
    sub = {k: np.asarray(at[k])[rows] for k in ("P_s", "R_s", "L0", "status")}
    sens = sensitivities_at(robot, sub, names=list(res["names"]), engine=engine, threads=threads)
    out = dict(res)
    for k in ("S", "smooth", "margin_t", "cond"):
        if k in res and k in sens:
            out[k] = np.array(res[k], copy=True)
            out[k][rows] = sens[k][:, : out[k].shape[1]] if k == "S" else sens[k]
    return out


def others(res, reached, i):
    """The equilibria other than the reached one at pose i: the global one (``res``, the solve with
    restarts) and its ``alternatives``, less any within ``equilibrium.DISTINCT`` in m and rad of the
    reached equilibrium, in ascending energy; the entries as ``alternatives``' (P_s, rotvec_s,
    energy, taut).

    Parameters
    ----------
    res : dict
        The global solve (``solve.solve``'s keys with ``alternatives`` and ``rotvec_s``).
    reached : dict
        The reached equilibrium (``solve.reach``'s keys).
    i : int
        The pose.

    Returns
    -------
    list of dict
    """
    from cdpr.models.equilibrium import DISTINCT  # lazy: the solver commands only
    from cdpr.models.platform import rotation_error, rotation_matrix  # lazy: the solver commands only

    glob = {
        "P_s": res["P_s"][i].tolist(),
        "rotvec_s": res["rotvec_s"][i].tolist(),
        "energy": float(res["energy"][i]),
        "taut": [int(k) + 1 for k in np.flatnonzero(res["taut"][i])],
    }
    P, R = reached["P_s"][i], reached["R_s"][i]

    def distinct(a):
        Ra = rotation_matrix(np.asarray(a["rotvec_s"], dtype=float))
        far = np.linalg.norm(np.subtract(a["P_s"], P)) > DISTINCT
        return far or rotation_error(Ra[None], R[None])[0] > DISTINCT

    return sorted((a for a in [glob, *res["alternatives"][i]] if distinct(a)), key=lambda a: a["energy"])


def both(robot, reached, glob, rigid):
    """``point --json``'s ``reached`` (with ``folds`` and ``start``) and ``global`` objects and
    ``reached_is_global`` (the two within ``equilibrium.DISTINCT`` in m and rad)."""
    from cdpr.models.continuation import pose_distance  # lazy: the solver commands only
    from cdpr.models.equilibrium import DISTINCT  # lazy: the solver commands only

    r = _object(robot, reached, rigid, reached)
    r["folds"] = reached["folds"][0]
    r["start"] = str(reached["start"][0])
    r["steps"] = len(reached["lambdas"][0]) - 1
    g = _object(robot, glob, rigid, reached)
    R_g = glob["R_s"] if rigid else reached["R_s"]
    same = pose_distance(reached["P_s"], reached["R_s"], glob["P_s"], R_g)[0] <= DISTINCT
    return {"reached": r, "global": g, "reached_is_global": bool(same)}


def text(out):
    """The readable lines of the reached equilibrium in ``point``'s report."""
    r, g = out["reached"], out["global"]
    lines = [f"  start          : {r['start']}"]
    for f in r["folds"]:
        lines.append(
            f"  fold           : at lambda = {f['lambda']:.6g}, jump {f['jump_m']:.4g} m and {f['jump_rad']:.4g} rad, "
            f"taut {'-'.join(map(str, f['taut_before'])) or '-'} -> {'-'.join(map(str, f['taut_after'])) or '-'}"
        )
    fmt = lambda v: "(" + ", ".join(f"{x:.6f}" for x in v) + ")"  # noqa: E731
    if out["reached_is_global"]:
        lines.append("  global         : the reached equilibrium is the lowest-energy one")
    else:
        rot = f", rotvec {fmt(g['solved_rotvec'])}" if "solved_rotvec" in g else ""
        lines.append(
            f"  global         : {fmt(g['solved'])}{rot}, energy {g['energy_J']:.6g} J "
            f"(reached {r['energy_J']:.6g} J), interference-free: {str(g['interference_free']).lower()}"
        )
    return lines
