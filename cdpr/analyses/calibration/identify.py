"""Identifiability: what the data can and cannot see of θ, in numbers and in words.

``identifiability``: singular values of the measurement rows scaled by the prior (rows / σ, columns
× prior sd), the rank (> ``RANK_TOL`` s_max), the condition number, the weakest directions in words
(``direction_words``; a degenerate null space read through ``sparse_basis``), and each parameter's
posterior-to-prior sd ratio: identified (≤ 0.3), partly (≤ 0.8) or prior-dominated (> 0.8).

References
----------
Tarantola, A. (2005). Inverse Problem Theory and Methods for Model Parameter Estimation, SIAM,
section 3.2 (the posterior covariance).
"""

from __future__ import annotations

import math

import numpy as np

#: Rank threshold: singular values > RANK_TOL s_max count.
RANK_TOL = 1e-9
#: Posterior-to-prior sd ratios of "identified" and "partly".
IDENTIFIED, PARTLY = 0.3, 0.8


def identifiability(Jm, names, rank_tol=RANK_TOL):
    """Singular values, rank, condition, posterior covariance and the weak directions in words.

    The posterior covariance in prior-scaled variables is (Jmᵀ Jm + I)^-1 (Gauss-Newton at the
    MAP); the posterior-to-prior sd ratio of parameter j is sqrt of its diagonal.

    Parameters
    ----------
    Jm : ndarray, shape (rows, k)
        Measurement rows / σ, columns × prior sd.
    names : list of str, length k
    rank_tol : float
        Singular values > rank_tol s_max count in the rank.

    Returns
    -------
    dict
        singular_values (k,) (0 where rows < k), rank, condition (inf when rank deficient),
        cov_scaled (k, k), ratio (k,), labels (k,) identified / partly / prior-dominated,
        unidentified: list of str, one per direction whose singular value is below 1 (the data
        see it less than the prior does), weakest first.
    """
    k = Jm.shape[1]
    s = np.zeros(k)
    if Jm.shape[0]:
        _, sv, Vt = np.linalg.svd(Jm, full_matrices=True)
        s[: len(sv)] = sv
    else:
        Vt = np.eye(k)
    smax = s.max() if k else 0.0
    rank = int((s > rank_tol * smax).sum()) if smax > 0 else 0
    cond = float(s[0] / s[-1]) if rank == k and k else math.inf
    cov = np.linalg.inv(Jm.T @ Jm + np.eye(k))
    ratio = np.sqrt(np.diag(cov))
    labels = np.where(
        ratio <= IDENTIFIED, "identified", np.where(ratio <= PARTLY, "partly", "prior-dominated")
    )
    words = []
    null = s <= rank_tol * smax if smax > 0 else np.ones(k, dtype=bool)
    if null.any():  # a degenerate null space: a sparse basis (reduced row echelon form) reads best
        words += [direction_words(v, names, 0.0, True) for v in sparse_basis(Vt[null])]
    for i in np.argsort(s, kind="stable"):
        if s[i] >= 1.0:
            break
        if not null[i]:
            words.append(direction_words(Vt[i], names, s[i], False))
    return {
        "singular_values": s,
        "rank": rank,
        "condition": cond,
        "cov_scaled": cov,
        "ratio": ratio,
        "labels": labels,
        "unidentified": words,
    }


def identifiability_without(Jth, Jn, names):
    """``identifiability`` of θ with nuisance parameters (the unknown poses of a self-calibration)
    eliminated: the measurement rows projected on the orthogonal complement of the nuisance
    columns, Jth - Q Qᵀ Jth with Jn = Q R.

    Parameters
    ----------
    Jth : ndarray, shape (rows, k)
        The θ columns of the measurement rows (rows / σ, columns × prior sd).
    Jn : ndarray, shape (rows, q)
        The nuisance columns of the same rows.
    names : list of str, length k

    Returns
    -------
    dict
        ``identifiability``.
    """
    Q, _ = np.linalg.qr(Jn)
    return identifiability(Jth - Q @ (Q.T @ Jth), names)


def sparse_basis(B):
    """A basis of the row space of B (r, k) with one pivot parameter per vector (reduced row echelon
    form), each row normalised: e.g. the directions d_i - offset_i one by one instead of an
    arbitrary rotation of them.

    The pivots are chosen greedily, each the parameter whose column has the largest norm left after
    projecting out the pivots already chosen (column-pivoted Gram-Schmidt). The norms are rounded
    to ``TIE_DIGITS`` significant digits relative to the largest before ranking and ties go to the
    first parameter, so that equal loadings (a symmetric robot's d_1 - offset_1, d_2 - offset_2,
    ...) give the same basis, in the same order, on every machine. The result depends only on the
    row space of B, not on which orthonormal basis of it B holds.

    Parameters
    ----------
    B : ndarray, shape (r, k)
        Orthonormal rows spanning a subspace.

    Returns
    -------
    V : ndarray, shape (r, k)
    """

    r = B.shape[0]
    Q = np.array(B, dtype=float)  # columns of B, orthogonalised against the chosen pivots
    piv = []
    for _ in range(r):
        norms = np.linalg.norm(Q, axis=0)
        norms[piv] = 0.0
        j = _first_max(norms)
        piv.append(j)
        q = Q[:, j] / norms[j]
        Q -= np.outer(q, q @ Q)
    V = np.linalg.solve(B[:, piv], B)
    V[:, piv] = np.eye(r)  # exact zeros and ones at the pivots (no round-off left to rank on)
    return V / np.linalg.norm(V, axis=1, keepdims=True)


#: Significant digits kept when ranking loadings: closer values are a tie, broken by parameter order.
TIE_DIGITS = 6


def _first_max(values):
    """Index of the largest of ``values`` (>= 0) after rounding to ``TIE_DIGITS`` significant digits
    relative to the largest; ties go to the lowest index."""
    top = float(np.max(values))
    if top <= 0:
        return 0
    return int(np.argmax(np.round(np.asarray(values) / top, TIE_DIGITS)))


def _ranked(v):
    """Parameter indices by decreasing |v|, rounded to ``TIE_DIGITS`` significant digits relative to
    the largest; ties in parameter order."""
    a = np.abs(np.asarray(v, dtype=float))
    top = a.max() if len(a) else 0.0
    key = np.round(a / top, TIE_DIGITS) if top > 0 else a
    return np.lexsort((np.arange(len(a)), -key))


def direction_words(v, names, s, null):
    """A direction of parameter space in words: the leading parameter, then 'against' those that
    move against it along the unseen direction (opposite sign), 'with' those that move with it.

    Parameters
    ----------
    v : ndarray, shape (k,)
        Unit singular vector (prior-scaled).
    names : list of str
    s : float
        Its singular value.
    null : bool
        Below the rank threshold.

    Returns
    -------
    str, e.g. "d_1 against offset_1 (not seen by the data)".
    """
    order = _ranked(v)  # ties: the first parameter leads
    lead = order[0]
    big = [j for j in order[1:5] if abs(v[j]) >= 0.2 * abs(v[lead])]
    # along v the data do not change: opposite signs move against each other, equal signs together
    against = [names[j] for j in big if v[j] * v[lead] < 0]
    withs = [names[j] for j in big if v[j] * v[lead] > 0]
    text = names[lead]
    if against:
        text += " against " + " and ".join(against)
    if withs:
        text += (";" if against else "") + " with " + " and ".join(withs)
    if not big:
        text += " alone"
    tail = "not seen by the data" if null else f"weak: s = {below_one(s)} < 1, the prior decides"
    return f"{text} ({tail})"


def below_one(s):
    """A singular value below 1 written so that it reads below 1: two significant digits, or, where
    those round up to 1 (s = 0.996), the digits down to the first that differs from 9 (0.996).

    Parameters
    ----------
    s : float
        A singular value in [0, 1).

    Returns
    -------
    str
    """
    text = f"{s:.2g}"
    if float(text) < 1.0 or s >= 1.0:
        return text
    digits = max(2, -math.floor(math.log10(1.0 - s)))
    return f"{math.floor(s * 10**digits) / 10**digits:.{digits}f}"
