"""Error budget joining both papers: what each effect the standard model neglects adds to the pose
error, one at a time and all together, and what is left after compensating each.

The standard model (Paty 2021 eq. 1-2) sees fixed cable exit points A_i, rigid cables and a drum
that pays out exactly the length it is told. The robot differs from it by three effects:

* ``pulley``: pulley geometry, the swivelling (SR) or double-revolute (DR) pulleys of Paty 2021
  (eq. 3-7) with the design's h and r_p, instead of fixed exit points at A_i;
* ``elasticity``: Hooke cables of modulus E (eq. 10, 13) instead of rigid ones;
* ``winch``: the drum's exit point slides along E1E2 as the drum turns (Métillon 2022, eq. 12-32),
  so the drum angle that a controller neglecting it commands, q_nw (eq. 32), pays out a rest
  length off by δl = k_w (q1 - q_nw) (eq. 31).

A *variant* is a pair (actual effects, model effects), subsets of the three. The model robot
computes the commanded rest lengths at the desired point p, the controller turns them into drum
angles, the actual drum pays them out, and the platform of the actual robot settles at its
physical equilibrium P* (``equilibrium``, all cables, slack allowed); the error is δp = P* - p:

1. model rest lengths: with ``elasticity`` in the model, the compensated lengths
   L0 = L_TE(p) / (1 + t / (E S)) of ``compensation.compensate`` (tensions ``distribution`` with
   at least ``t_min`` in every cable); without it, L0 = L_TE(p), the rigid cable's length (the
   model's geometry: L_TE with the pulleys when ``pulley`` is in the model, else L_TS, eq. 2);
2. the drum: when the actual robot and the model agree on the winch (both with or both without
   ``winch``), the drum pays out L0 exactly; a model without ``winch`` on an actual robot with it
   commands q_nw(L0 - d) and gets L0' = d + l_pm(q_nw) (``drive``); a model with ``winch`` on a
   drum without exit-point motion commands q1(L0 - d) and gets d + l_pm,nw(q1);
3. the actual robot: ``pulley`` on: the design's pulleys, else fixed exit points at A_i;
   ``elasticity`` on: the cables' E, else E x ``RIGID`` (E -> infinity; the stretch left is
   1e-6 of the elastic one, ~1e-8 m); ``winch``: the drum of step 2. Rigid cables make Newton's
   problem stiff: where it stops ``not_converged`` from the desired pose, the point is solved again
   by the continuation in stiffness ``solve.solve_stiff`` (the cables' own E, then x 10, x 100, ...
   x ``RIGID``, each stage from the previous pose; the same Newton, tolerance and statuses at the
   last stage); every other point keeps its answer bit for bit. A point still not converged after it
   stays flagged, and ``over_tension`` is an answer, not a failure: the rigid robot needs more than
   T_a there, or has no inextensible equilibrium at all (its tensions grow with E).

The budget of a design at p (``error_budget``):

* single effects: δp_k = δp({k}, {}) for k in ``EFFECTS`` (pulley geometry only = pulleys with
  E -> infinity and an exact drum; elasticity only = fixed exit points with Hooke cables; winch only
  = fixed exit points, rigid cables, drum angles q_nw of the standard lengths L_TS);
* all together: δp_all = δp(EFFECTS, {}), the physical study's robot commanded in drum angles;
* interaction: δp_int = δp_all - Σ_k δp_k (the vector the single effects do not add up to);
* residual after compensating k: δp(EFFECTS, {k}); after compensating all: δp(EFFECTS, EFFECTS),
  zero by construction (the model is the robot); neglecting only k: δp(EFFECTS, EFFECTS - {k}).
* with no effect, δp({}, {}) = 0 (fixed points, rigid cables, exact drum: the standard model is
  exact); both limits are tested.

Heavy cables (issue 38; a design whose cables have a linear density > 0, ``Robot.heavy``: the
robot's density decides, nothing else turns it on): a fourth effect

* ``sag``: the cables' weight, Irvine's elastic catenary (``cables.HeavyCables``) instead of a
  straight cable; in the model, the sag-consistent compensated lengths
  (``compensation.compensate`` on the heavy model: ``heavy_distribution``, at least ``t_min`` at
  B_i, in every model with ``sag``, with or without ``elasticity``).

joins the variants (``effects_of``): the single effect ``sag`` (fixed exit points, rigid cables,
exact drum, standard lengths L_TS), ``all`` (all four effects: what the heavy robot has),
``compensated_sag``, ``neglected_sag`` = δp(EFFECTS + sag, EFFECTS): **what sag adds** when the
robot is commanded with the massless compensated lengths of the model with every other effect, and
``compensated_all`` = δp(all four, all four): what compensating with the heavy model leaves, zero
up to the solver's tolerance (the heavy inverse's round trip, ≤ 1e-9 m). Every variant whose actual
robot lacks ``sag`` is the massless one (its cables' density set to 0), so the single effects
pulley, elasticity and winch are those of the massless design. A massless design (w = 0) has the
three effects only: its budget, table and figures are byte-identical to those without this rule
(no ``sag`` entry, no new column). A heavy budget's summary adds the 95th percentiles p95_m (and
p95_rad) over the points ok in every entry.

Norms do not add, so the stacked bars use the exact additive split of the all-effects error along
its own direction û = δp_all / ‖δp_all‖: ‖δp_all‖ = Σ_k δp_k · û + δp_int · û (``summarise``).

A rigid platform (a robot that is not a suspended point mass, or any robot given an orientation
``rotvec``): the same budget at the fixed desired orientation R_d = exp([rotvec]x) (default the
identity). The model's rest lengths are taken at the attachment points B_i = p + R_d b_i: the rigid
cable's length L_TE(B_i) of the 6-DoF inverse model (``inverse.pose_state``, the pulley
geometry at B_i, as ``cdpr inverse`` gives it), or with ``elasticity`` in the model the compensated
lengths of ``tension_distribution.compensated_lengths`` (the minimum-norm distribution of the 6 x m wrench
matrix, at least ``t_min`` in every cable); the actual robot settles at its 6-DoF equilibrium
(p*, R*) (``equilibrium``, through ``solve.solve``) under the realised lengths, and
every entry also gets the orientation error δφ = rotvec(R* R_dᵀ) (N, 3) [rad] (its interaction
δφ_all - Σ_k δφ_k, first order in the small rotations), summarised by its mean and largest norm.
A point-mass robot given ``rotvec`` goes the same way (its moment rows vanish): equal to the
point-mass budget, which is how the 6-DoF path is tested.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling
considering pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263,
eq. (1)-(7), (10)-(15).
Métillon, M., Charron, C., Subrin, K., Caro, S. (2022). Geometrical modelling of a cable-driven
parallel robot winch. 25e Congrès Français de Mécanique, hal-03758222, eq. (12)-(32).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from cdpr.analyses.compensation import compensate
from cdpr.models import winch as winch_model
from cdpr.models.inverse import igm_e, pose_state
from cdpr.models.platform import pose_arrays, rotvec_of
from cdpr.models.tension_distribution import T_MIN_DEFAULT, compensated_lengths
from cdpr.robot import TABLE1
from cdpr.solve import check_engine, reached_answer, solve, solve_stiff

#: The effects the standard model neglects, in the order of the budget.
EFFECTS = ("pulley", "elasticity", "winch")
#: The heavy cable's effect (issue 38): a budget has it when its design's cables have a linear
#: density > 0 (``effects_of``).
SAG = "sag"
#: Factor on E standing for rigid cables (E -> infinity).
RIGID = 1e6


def _names(effects):
    eff = frozenset(effects)
    bad = eff - {*EFFECTS, SAG}
    if bad:
        raise ValueError(f"unknown effect(s) {sorted(bad)}; allowed: {', '.join((*EFFECTS, SAG))}")
    return eff


def effects_of(design):
    """The effects of the budget of ``design``: ``EFFECTS``, and ``sag`` after them when its cables
    have a linear density > 0 (``Robot.heavy``, issue 38).

    Parameters
    ----------
    design : Robot

    Returns
    -------
    tuple of str
    """
    return (*EFFECTS, SAG) if design.heavy else EFFECTS


def _single(budget):
    """The single effects an ``error_budget`` result has (``EFFECTS``, and ``sag`` if there)."""
    return (*EFFECTS, SAG) if SAG in budget else EFFECTS


def spatial(design, rotvec=None):
    """True when the budget of ``design`` runs on the 6-DoF path (module docstring): a robot that is
    not a suspended point mass (``Robot.suspended_point_mass``), or an orientation ``rotvec`` given.

    Parameters
    ----------
    design : Robot
    rotvec : array_like (3,) or (N, 3) [rad], optional

    Returns
    -------
    bool
    """
    return rotvec is not None or not design.suspended_point_mass


def effect_robot(design, effects):
    """``design`` with only ``effects`` on: fixed exit points at A_i unless ``pulley``, E x RIGID
    unless ``elasticity``, massless cables (linear density 0) unless ``sag``. Every cable keeps (or gets) a winch: the design's own, else Table 1 of
    Métillon 2022 (whether its exit point moves is decided by the variant, ``realised_lengths``).

    Parameters
    ----------
    design : Robot
        The robot with its pulleys, cables and (optionally) winches.
    effects : iterable of str
        Subset of ``EFFECTS``.

    Returns
    -------
    Robot
    """
    eff = _names(effects)
    cables = []
    for c in design.cables:
        pulley = c.pulley if "pulley" in eff else dataclasses.replace(c.pulley, kind="fixed", h=0.0, r_p=0.0)
        material = (
            c.material if "elasticity" in eff else dataclasses.replace(c.material, E=c.material.E * RIGID)
        )
        if SAG not in eff and material.rho:
            material = dataclasses.replace(material, rho=0.0)
        cables.append(dataclasses.replace(c, pulley=pulley, material=material, winch=c.winch or TABLE1))
    return dataclasses.replace(design, cables=tuple(cables))


def with_drums(design, drum):
    """``design`` with ``drum`` on every cable that has no winch of its own (the cables' own winches
    are kept); ``effect_robot`` then keeps them in every variant instead of Table 1's drum.

    Parameters
    ----------
    design : Robot
    drum : WinchParams
        Métillon 2022 Table 1 parameters of the drum (SI units).

    Returns
    -------
    Robot
    """
    cables = tuple(dataclasses.replace(c, winch=c.winch or drum) for c in design.cables)
    return dataclasses.replace(design, cables=cables)


def model_lengths(design, p, model, t_min=T_MIN_DEFAULT, rotvec=None):
    """Rest lengths the model with effects ``model`` commands at p (step 1 of the module docstring).

    .. math:: L_{0,i} = L_{TE,i}(B_i) / (1 + t_i / (E_i S_i)),\\quad B_i = p + R_d b_i
              \\quad (t = 0 without elasticity)

    With ``sag`` in the model, the sag-consistent compensated lengths of the heavy model
    (``compensation.compensate``: the heavy inverse at the sag-consistent distribution).

    Parameters
    ----------
    design : Robot
    p : array (N, 3) [m]
        Desired positions.
    model : iterable of str
        Subset of ``EFFECTS`` the model includes.
    t_min : float [N]
        Least planned tension of the elasticity compensation (``compensation.compensate``, or
        ``tension_distribution.compensated_lengths`` on the 6-DoF path).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientation of a rigid platform (default identity); given, or for a robot that is
        not a suspended point mass, the 6-DoF path (``spatial``).

    Returns
    -------
    L0 : array (N, m) [m]
        NaN where no tension distribution exists (elasticity modelled).

    References
    ----------
    Paty et al. 2021, eq. (3)-(5), (10), (13).
    """
    robot = effect_robot(design, model)
    if SAG in _names(model):
        return compensate(robot, p, method="min_norm", t_min=t_min, rotvec=rotvec)["L0"]
    if spatial(design, rotvec):
        if "elasticity" in _names(model):
            return compensated_lengths(robot, p, rotvec, t_min=t_min, method="min_norm")["L0"]
        return pose_state(robot, *pose_arrays(p, rotvec))[1].L_TE
    if "elasticity" in _names(model):
        return compensate(robot, p, method="min_norm", t_min=t_min)["L0"]
    return igm_e(robot, p).L_TE


def realised_lengths(design, L0, actual, model):
    """Rest lengths the actual drums pay out when the controller's model commands L0 (step 2 of the
    module docstring).

    L0' = d + l_pm,actual(q),   q = q1(L0 - d) (model with winch) or q_nw(L0 - d) (without)

    Parameters
    ----------
    design : Robot
        Its winches (Table 1 of Métillon 2022 where it gives none) and dead lengths d.
    L0 : array (N, m) [m]
        Rest lengths the model commands.
    actual, model : iterable of str
        Subsets of ``EFFECTS`` of the robot and of the model; only ``winch`` matters here.

    Returns
    -------
    array (N, m) [m]
        L0 itself when both or neither have the winch; NaN where a drum angle leaves [0, q_max].

    References
    ----------
    Métillon et al. 2022, eq. (15)-(17), (22), (29)-(32).
    """
    wa, wm = "winch" in _names(actual), "winch" in _names(model)
    L0 = np.asarray(L0, dtype=float)
    if wa == wm:
        return L0
    robot = effect_robot(design, ())
    out = np.empty_like(L0)
    for i, (w, d) in enumerate(zip(robot.winches, robot.d)):
        l_pm = L0[:, i] - d
        if wm:
            q = winch_model.roots(w, l_pm)[0]
            pay = winch_model.l_pm_of_q_no_winch(w, q)
        else:
            q = winch_model.q_no_winch(w, l_pm)
            pay = winch_model.l_pm_of_q(w, np.clip(q, 0.0, w.q_max))
        out[:, i] = np.where((q >= 0) & (q <= w.q_max), d + pay, np.nan)
    return out


def _rigid_where_not_converged(design, actual, p, rotvec, L0, res, engine, threads):
    """``res`` (the solve of ``effect_robot(design, actual)``, cables E x ``RIGID``) with its
    ``not_converged`` points solved again by the continuation in stiffness from the cables' own E
    (``solve.solve_stiff``); the other points are kept as they are (module docstring, rigid cables)."""
    redo = np.flatnonzero(res["status"] == "not_converged")
    if redo.size == 0:
        return res
    elastic = effect_robot(design, (*_names(actual), "elasticity"))
    rv = None if rotvec is None else rotvec[redo]
    again = solve_stiff(elastic, p[redo], RIGID, rv, L0=L0[redo], engine=engine, threads=threads)
    out = dict(res)
    for key in ("P_s", "R_s", "status"):
        if key in res:
            out[key] = np.array(res[key], copy=True)
            out[key][redo] = again[key]
    return out


def variant(design, p, actual, model, t_min=T_MIN_DEFAULT, threads=None, engine=None, rotvec=None):
    """The platform of the robot with effects ``actual`` commanded by the model with effects
    ``model`` (module docstring).

    .. math:: \\delta p = p^* - p,\\qquad \\delta\\varphi = \\operatorname{rotvec}(R^* R_d^T)

    Parameters
    ----------
    design : Robot
    p : array (N, 3) [m]
        Desired positions.
    actual, model : iterable of str
        Subsets of ``EFFECTS``.
    t_min : float [N]
        Least planned tension of the elasticity compensation.
    threads : int, optional
        Threads of the compiled equilibrium.
    engine : {"compiled", "numpy", None}
        Engine of the physical equilibrium (``solve.check_engine``: None is the solver's default,
        compiled, heavy cables in ``actual`` too: it models every pulley).
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientation of a rigid platform (default identity; the 6-DoF path, ``spatial``).

    Returns
    -------
    dict
        dp (N, 3) [m] the vector P* - p; status (N,) str (``results.STATUSES``, and
        ``infeasible`` where the model has no tension distribution or a drum angle leaves its range);
        on the 6-DoF path also dphi (N, 3) [rad], the rotation vector of R* R_dᵀ (NaN where
        infeasible).

    References
    ----------
    Paty et al. 2021, eq. (2)-(5), (10)-(14); Métillon et al. 2022, eq. (29)-(32).
    """
    p = np.atleast_2d(np.asarray(p, dtype=float))
    robot = effect_robot(design, actual)
    engine = check_engine(engine, "newton")
    six = spatial(design, rotvec)
    L0 = realised_lengths(design, model_lengths(design, p, model, t_min, rotvec), actual, model)
    good = np.isfinite(L0).all(axis=1)
    dp = np.full(p.shape, np.nan)
    dphi = np.full(p.shape, np.nan)
    status = np.full(len(p), "infeasible", dtype=object)
    if good.any():
        rv = None
        if rotvec is not None:
            rv = np.broadcast_to(np.asarray(rotvec, dtype=float), p.shape)[good]
        res = solve(
            robot,
            p[good],
            engine=engine,
            threads=threads,
            redundancy="physical",
            L0=L0[good],
            rotvec=rv,
        )
        res = reached_answer(robot, res, engine=engine, threads=threads)  # issue 39
        if "elasticity" not in _names(actual):  # rigid cables: the points Newton did not solve
            res = _rigid_where_not_converged(design, actual, p[good], rv, L0[good], res, engine, threads)
        dp[good] = res["P_s"] - p[good]
        status[good] = res["status"]
        if six:
            _, R_d = pose_arrays(p[good], rv)
            dphi[good] = rotvec_of(res["R_s"] @ np.swapaxes(R_d, 1, 2))
    out = {"dp": dp, "status": status.astype(str)}
    if six:
        out["dphi"] = dphi
    return out


def variants(effects=EFFECTS):
    """The variants of the budget (module docstring).

    Parameters
    ----------
    effects : tuple of str
        The effects of the budget (default ``EFFECTS``).

    Returns
    -------
    dict
        name -> (actual effects, model effects): ``none``, each single effect, ``all``,
        ``compensated_<k>``, ``neglected_<k>`` and ``compensated_all``.
    """
    _names(effects)  # unknown effects raise ValueError
    allk = tuple(effects)
    v = {"none": ((), ())}
    v.update({k: ((k,), ()) for k in allk})
    v["all"] = (allk, ())
    v.update({f"compensated_{k}": (allk, (k,)) for k in allk})
    v.update({f"neglected_{k}": (allk, tuple(e for e in allk if e != k)) for k in allk})
    v["compensated_all"] = (allk, allk)
    return v


def error_budget(design, p, t_min=T_MIN_DEFAULT, threads=None, rotvec=None, engine=None):
    """Every variant of the budget at p, plus the interaction (module docstring).

    .. math:: \\delta p_{int} = \\delta p_{all} - \\sum_k \\delta p_k

    Parameters
    ----------
    design : Robot
    p : array (N, 3) [m]
    t_min : float [N]
    threads : int, optional
    rotvec : array_like (3,) or (N, 3) [rad], optional
        Desired orientation of a rigid platform (default identity; the 6-DoF path, ``spatial``).
    engine : {"compiled", "numpy", None}
        Engine of the physical equilibrium (None is compiled).

    Returns
    -------
    dict
        name -> {dp (N, 3) [m], status (N,)} (and dphi (N, 3) [rad] on the 6-DoF path) for every
        name of ``variants(effects_of(design))`` (with heavy cables also ``sag``,
        ``compensated_sag`` and ``neglected_sag``), and ``interaction`` -> {dp = δp_all - Σ_k δp_k (dphi likewise),
        status ok where all four are ok}.

    References
    ----------
    Paty et al. 2021, eq. (1)-(7), (10)-(15); Métillon et al. 2022, eq. (12)-(32).
    """
    effects = effects_of(design)
    out = {
        name: variant(design, p, a, m, t_min, threads, engine, rotvec)
        for name, (a, m) in variants(effects).items()
    }
    parts = [out["all"]] + [out[k] for k in effects]
    ok = np.logical_and.reduce([r["status"] == "ok" for r in parts])
    out["interaction"] = {
        "dp": out["all"]["dp"] - sum(out[k]["dp"] for k in effects),
        "status": np.where(ok, "ok", "not_ok"),
    }
    if "dphi" in out["all"]:
        out["interaction"]["dphi"] = out["all"]["dphi"] - sum(out[k]["dphi"] for k in effects)
    return out


def norms(budget):
    """‖δp‖ of every entry of an error budget and the points ok in every entry.

    Parameters
    ----------
    budget : dict
        An ``error_budget`` result.

    Returns
    -------
    norms : DataFrame (N rows, one column per entry) [m]
    ok : array (N,) of bool
    """
    ok = np.logical_and.reduce([r["status"] == "ok" for r in budget.values()])
    return pd.DataFrame({k: np.linalg.norm(r["dp"], axis=1) for k, r in budget.items()}), ok


def summarise(budget):
    """One row per budget entry over the points ok in every entry.

    The share of effect k in the all-effects error is its projection on û = δp_all / ‖δp_all‖,

        s_k = mean(δp_k · û),   Σ_k s_k + s_int = mean ‖δp_all‖

    (exactly, since the single effects and the interaction add up to δp_all).

    Parameters
    ----------
    budget : dict
        An ``error_budget`` result.

    Returns
    -------
    DataFrame
        Columns entry, mean_m and max_m (‖δp‖ [m]), share_m (s_k [m], for the single effects, the
        interaction and ``all``), largest_fraction (share of the points where a single effect is
        the largest of the three, of the four with ``sag``), points, ok_points; on the 6-DoF path
        (entries with ``dphi``) also mean_rad and max_rad (‖δφ‖ [rad]); a heavy budget (a ``sag``
        entry) then p95_m (and p95_rad on the 6-DoF path), the 95th percentiles, last.
    """
    nm, ok = norms(budget)
    effects = _single(budget)
    d_all = budget["all"]["dp"][ok]
    n_all = np.linalg.norm(d_all, axis=1)
    u = np.divide(d_all, n_all[:, None], out=np.zeros_like(d_all), where=n_all[:, None] > 0)
    largest = nm.loc[ok, list(effects)].to_numpy().argmax(axis=1) if ok.any() else np.array([], int)
    rows = []
    for k in budget:
        share = np.nan
        if k in (*effects, "interaction", "all"):
            share = float(np.einsum("na,na->n", budget[k]["dp"][ok], u).mean()) if ok.any() else np.nan
        frac = float((largest == effects.index(k)).mean()) if k in effects and ok.any() else np.nan
        rows.append(
            {
                "entry": k,
                "mean_m": float(nm.loc[ok, k].mean()) if ok.any() else np.nan,
                "max_m": float(nm.loc[ok, k].max()) if ok.any() else np.nan,
                "share_m": share,
                "largest_fraction": frac,
                "points": int(len(ok)),
                "ok_points": int(ok.sum()),
            }
        )
        if "dphi" in budget[k]:
            a = np.linalg.norm(budget[k]["dphi"][ok], axis=1)
            rows[-1]["mean_rad"] = float(a.mean()) if ok.any() else np.nan
            rows[-1]["max_rad"] = float(a.max()) if ok.any() else np.nan
        if SAG in effects:  # a heavy budget: the 95th percentiles too
            rows[-1]["p95_m"] = float(np.percentile(nm.loc[ok, k], 95)) if ok.any() else np.nan
            if "dphi" in budget[k]:
                rows[-1]["p95_rad"] = float(np.percentile(a, 95)) if ok.any() else np.nan
    return pd.DataFrame(rows)


#: Words for the effects in sentences.
LABELS = {
    "pulley": "pulley geometry",
    "elasticity": "cable elasticity",
    "winch": "the winch exit point",
    "sag": "cable sag",
}


def dominant(summary):
    """The single effect with the largest mean ‖δp‖.

    Parameters
    ----------
    summary : DataFrame
        A ``summarise`` table.

    Returns
    -------
    str, one of ``EFFECTS`` (or ``sag`` in a heavy budget).
    """
    s = summary.set_index("entry")
    return max(_single(s.index), key=lambda k: s.loc[k, "mean_m"])


def sentence(design_label, summary, path=None):
    """One sentence on which effect dominates where (in a heavy budget, with what sag adds under
    the massless compensated lengths, ``neglected_sag``, and what the heavy compensation leaves).

    Parameters
    ----------
    design_label : str
    summary : DataFrame
        ``summarise`` table over RW_C.
    path : DataFrame, optional
        ``summarise`` table along the section 3.3.1 path.

    Returns
    -------
    str
    """
    s = summary.set_index("entry")
    top = dominant(summary)
    rest = sorted((k for k in EFFECTS if k != top), key=lambda k: -s.loc[k, "mean_m"])[:2]
    mm = lambda k: f"{s.loc[k, 'mean_m'] * 1e3:.3g} mm"  # noqa: E731
    text = (
        f"{design_label}: {LABELS[top]} dominates over RW_C (mean ‖δp‖ {mm(top)} alone, the largest "
        f"single effect at {s.loc[top, 'largest_fraction']:.0%} of the points), then "
        f"{LABELS[rest[0]]} ({mm(rest[0])}) and {LABELS[rest[1]]} ({mm(rest[1])}); all together "
        f"{mm('all')} with an interaction of {mm('interaction')}; compensating {LABELS[top]} leaves "
        f"{mm('compensated_' + top)}"
    )
    if SAG in s.index:
        text += (
            f"; cable sag adds {mm('neglected_sag')} to the robot commanded with the massless compensated "
            f"lengths, and compensating with the heavy model leaves {mm('compensated_all')}"
        )
    if path is not None:
        p = path.set_index("entry")
        ptop = max(_single(p.index), key=lambda k: p.loc[k, "mean_m"])
        text += (
            f"; along the section 3.3.1 path {LABELS[ptop]} dominates "
            f"({p.loc[ptop, 'mean_m'] * 1e3:.3g} mm mean, the largest at "
            f"{p.loc[ptop, 'largest_fraction']:.0%} of its points)"
        )
    return text + "."
