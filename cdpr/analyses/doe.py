"""Global index (eq. 15), full factorial designs, effects and interactions (Paty 2021 section 4.2),
optimal lines (section 4.3).

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263.
"""

from __future__ import annotations

import itertools

import numpy as np
import pandas as pd


def global_index(dp, status):
    """Global index of a design (Paty 2021 eq. 15): the mean pose error over the evaluation points.

    .. math:: I = \\frac{1}{N} \\sum_{k=1}^{N} \\lVert \\delta p_k \\rVert

    Parameters
    ----------
    dp : array (N,) [m]
        Pose error ‖δp‖ at the N points evenly spread in RW_C (cell centres).
    status : array (N,) of str
        Per-point status; only ``ok`` points enter the mean.

    Returns
    -------
    (index [m], number of points that are not ``ok``). The paper's RW_C lies inside the workspace of
    every design, so the second number is 0 there; it is reported so that a box reaching outside a
    design's workspace does not go unseen.
    """
    ok = np.asarray(status) == "ok"
    dp = np.asarray(dp, dtype=float)
    return (float(dp[ok].mean()) if ok.any() else float("nan")), int((~ok).sum())


def orientation_index(dphi, status):
    """Orientation index of a design: the mean orientation error over the evaluation points, the
    statistic of eq. (15) applied to δφ (beyond the paper: a rigid platform's second response).

    .. math:: I_\\varphi = \\frac{1}{N_{ok}} \\sum_{k\\,ok} \\delta\\varphi_k

    Parameters
    ----------
    dphi : array (N,) [rad]
        Orientation error δφ (the rotation angle of R* R_d^T) at the N points.
    status : array (N,) of str
        Per-point status; only ``ok`` points enter the mean (as in ``global_index``).

    Returns
    -------
    (index [rad], number of points that are not ``ok``).
    """
    return global_index(dphi, status)


def full_factorial(k):
    """Coded 2^k design in the paper's standard order (Table 2: first factor slowest), shape (2^k, k).

    Paty 2021 section 4.2.1, Table 2 (k = 3: joint type, h, r_p).

    Parameters
    ----------
    k : int
        Number of factors.

    Returns
    -------
    X : ndarray (2^k, k) [-]
        Coded levels -1 / +1, one test per row.
    """
    return np.array(list(itertools.product((-1, 1), repeat=k)), dtype=float)


def model_matrix(X, names):
    """Saturated coded model: intercept, main effects, all interactions. Returns (M, term names).

    The columns of the effects analysis of Paty 2021 section 4.2.3 (Fig. 16).

    Parameters
    ----------
    X : ndarray (n, k) [-]
        Coded design (``full_factorial``).
    names : sequence of k str
        Factor names.

    Returns
    -------
    M : ndarray (n, 2^k) [-]
        Model matrix: a column of ones, then the products of every combination of factors, by
        order then in lexicographic order.
    terms : list of 2^k str
        Term names: ``mean``, then factor names joined by ``:`` (e.g. ``h:r_p``).
    """
    cols, terms = [np.ones(len(X))], ["mean"]
    k = X.shape[1]
    for order in range(1, k + 1):
        for combo in itertools.combinations(range(k), order):
            cols.append(np.prod(X[:, combo], axis=1))
            terms.append(":".join(names[i] for i in combo))
    return np.column_stack(cols), terms


def effects(X, y, names):
    """Coded coefficients (half-effects) by the orthogonal contrasts, classical effects (2x), and an
    OLS fit of the saturated model as a cross-check. One row per term.

    The effects and interactions of Paty 2021 section 4.2.3 (Fig. 16): coefficient = M^T y / n for
    a full factorial design (orthogonal columns).

    Parameters
    ----------
    X : array_like (n, k) [-]
        Coded design, one test per row.
    y : array_like (n,) [unit of the response, e.g. m]
        Responses (the global index of eq. 15 per test).
    names : sequence of k str
        Factor names.

    Returns
    -------
    DataFrame
        One row per term of ``model_matrix``: term; coefficient and effect [unit of y] (the
        ``mean`` row's effect is the mean itself); ols_coefficient [unit of y]; abs_effect_rank
        (1 = largest |coefficient|, the mean included).
    """
    M, terms = model_matrix(np.asarray(X, dtype=float), names)
    y = np.asarray(y, dtype=float)
    coef = M.T @ y / len(y)
    ols, *_ = np.linalg.lstsq(M, y, rcond=None)
    eff = 2 * coef
    eff[0] = coef[0]
    return pd.DataFrame(
        {
            "term": terms,
            "coefficient": coef,
            "effect": eff,
            "ols_coefficient": ols,
            "abs_effect_rank": pd.Series(np.abs(coef)).rank(ascending=False, method="first").astype(int),
        }
    )


def valley(r_p, h, index):
    """For each h, the r_p minimising the index (the valley r_p*(h) of Fig. 17), refined by a
    parabola through the grid minimum and its two neighbours when both exist.

    Inputs are 1-D arrays over map cells (missing cells allowed). Returns a DataFrame h, r_p_star,
    index_min, refined (bool).

    Paty 2021 section 4.3: the valley is what the lines of eq. (17)-(18) are fitted to.

    Parameters
    ----------
    r_p : array_like (n,) [m]
        Sheave radius of each map cell.
    h : array_like (n,) [m]
        Lever arm of each map cell.
    index : array_like (n,) [m]
        Global index (eq. 15) of each cell; NaN for missing cells (dropped).

    Returns
    -------
    DataFrame
        One row per h value, sorted by h: h [m]; r_p_star [m] the minimising r_p (refined by the
        parabola when ``refined``); index_min [m] the grid minimum (not the parabola's); interior
        (bool) the grid minimum has neighbours on both sides; refined (bool) the parabola was
        used (interior and convex).
    """
    df = pd.DataFrame({"r_p": r_p, "h": h, "index": index}).dropna()
    rows = []
    for hv, g in df.groupby("h", sort=True):
        g = g.sort_values("r_p")
        i = int(np.argmin(g["index"].to_numpy()))
        x, y = g["r_p"].to_numpy(), g["index"].to_numpy()
        r_star, refined = x[i], False
        if 0 < i < len(g) - 1:
            x0, x1, x2 = x[i - 1 : i + 2]
            y0, y1, y2 = y[i - 1 : i + 2]
            denom = (x0 - x1) * (x0 - x2) * (x1 - x2)
            A = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / denom
            B = (x2**2 * (y0 - y1) + x1**2 * (y2 - y0) + x0**2 * (y1 - y2)) / denom
            if A > 0:
                r_star, refined = -B / (2 * A), True
        rows.append(
            {
                "h": hv,
                "r_p_star": r_star,
                "index_min": y[i],
                "interior": 0 < i < len(g) - 1,
                "refined": refined,
            }
        )
    return pd.DataFrame(rows)


def line_through_origin(r_p, h):
    """Least-squares slope k of h = k r_p through the origin.

    The optimal lines D_SR, D_DR of Paty 2021 eq. (17)-(18) (printed slopes 40/13 and 5/4):
    k = sum(r_p h) / sum(r_p^2).

    Parameters
    ----------
    r_p : array_like (n,) [m]
        Sheave radii of the valley points (``valley``'s r_p_star).
    h : array_like (n,) [m]
        Lever arms of the valley points.

    Returns
    -------
    k : float [-]
        Slope of the line.
    """
    r_p, h = np.asarray(r_p, dtype=float), np.asarray(h, dtype=float)
    return float(np.sum(r_p * h) / np.sum(r_p * r_p))


def line_field_point(k, r_p_range, h_range):
    """Point of the line h = k r_p inside the study field [r_p_range] x [h_range] nearest the
    origin (I_SR, I_DR of Fig. 17), or None when the line misses the field.

    Paty 2021 section 4.3, Table 3 (the optimal designs CDPR4_SR*, CDPR4_DR*).

    Parameters
    ----------
    k : float [-]
        Slope of the line (``line_through_origin``), > 0.
    r_p_range : sequence of 2 float [m]
        Low and high levels of r_p.
    h_range : sequence of 2 float [m]
        Low and high levels of h.

    Returns
    -------
    tuple of 2 float [m] or None
        (r_p, h) of the point, or None when the line misses the field.
    """
    lo = max(r_p_range[0], h_range[0] / k)
    hi = min(r_p_range[1], h_range[1] / k)
    if lo > hi:
        return None
    return float(lo), float(k * lo)
