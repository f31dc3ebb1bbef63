"""Do the paper's conclusions hold on another robot? Paty et al. 2021's conclusions, statement by
statement, on a reference study and on a study of another robot, with a verdict each.

Paty 2021 drew its conclusions on two point-mass robots (CDPR3, CDPR4): DR pulleys give smaller
errors and larger error-limited volumes than SR, test 1 of the DOE is the best design and test 7
the worst, the joint × r_p interaction is the largest effect, the optimal lines D_SR and D_DR have
slopes 40/13 and 5/4, the optimal DR design beats the optimal SR one, and SR* is more robust than
DR* to the cables' modulus. A study of another robot (``config/studies/cogiro.yaml``: CoGiRo, a
rigid 6-DoF platform on 8 cables) names a reference study (its ``conclusions`` key: the paper's
study in physical mode, ``config/studies/physical.yaml``), and ``robot_conclusions`` evaluates every
statement on both results folders, the same way ``cdpr.pipeline.comparison.conclusions`` does for
the two redundancy modes of one study, and with the same verdicts (``comparison.verdict``):

* ``holds``: the statement has the same truth value on both robots (and, for a number without a
  statement, the value moves by at most the tolerance);
* ``reverses``: it is true on one robot and false on the other;
* ``changes``: same truth value but a categorical value differs (the DOE's best test, the largest
  term), or a number moves by more than the tolerance;
* ``undetermined``: a value is missing on one robot (e.g. no interior valley point on a map).

Both studies run in physical mode (a spatial robot has no other), so the comparison is of robots
and not of models. The DOE tests are numbered the same way in both (joint, h, r_p at their low and
high levels, ``doe.doe_tests``), but each study scales its levels to its own pulleys; the volume
limits are each study's own (``volumes.limits_m``, paired in order). The numbers of a spatial
robot are those of its reference point's position ‖δp‖; its orientation error δφ has no
counterpart in the paper and is left to the study's summary.

References
----------
Paty, T., Binaud, N., Caro, S., Segonds, S. (2021). Cable-driven parallel robot modelling considering
pulley kinematics and cable elasticity. Mechanism and Machine Theory 159, 104263 (sections 3.3, 4, 5).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from cdpr import io, table_io
from cdpr.pipeline import comparison as cm
from cdpr.pipeline.results import Layout
from cdpr.pipeline.study import load_study

#: Relative tolerance of a number without a statement (the slopes): this fraction of the reference.
REL = cm.DEFAULT_REL
COLUMNS = [
    "group",
    "quantity",
    "statement",
    "unit",
    "reference",
    "robot",
    "tolerance",
    "claim_reference",
    "claim_robot",
    "verdict",
    "paper",
    "verdict_paper",
    "headline",
    "note",
]
#: The paper's slopes of the optimal lines h = k r_p (section 4.3): for the page's text.
PAPER_SLOPES = {"SR": "40/13 ≈ 3.08", "DR": "5/4 = 1.25"}


def reference_of(st):
    """The reference of a study's conclusions: (reference study, its results folder), or None when
    the study has no ``conclusions`` key."""
    ref = st.get("conclusions")
    if not ref:
        return None
    return load_study(ref["study"]), ref["results"]


def conclusion_inputs(st, results):
    """The tables of a results folder that ``robot_conclusions`` reads (for the rule's input)."""
    lay = Layout(st, results)
    robot = st["doe"]["robot"]
    return lay.paths("plane_table", "table", robot=robot) + [
        lay.path("volumes", "table"),
        lay.path("doe", "table"),
        lay.path("doe", "effects"),
        lay.path("maps", "lines"),
        lay.path("elasticity", "bands"),
    ]


def _effects(res):
    """The DOE effects on the ‖δp‖ index (term -> effect [m]); a spatial study's table also has
    the δφ index's rows (``response``), left out."""
    d, e = cm.doe_tables(res)
    if e is not None and "response" in e.columns:
        e = e[e.response == "index_m"]
    return d, e


def _opt(st, kind):
    """The study's optimal design of a pulley kind (``optimal``), or None."""
    return next((k for k, v in st["optimal"].items() if v["kind"] == kind), None)


def robot_conclusions(ref_st, ref_res, st, res):
    """Every statement of the paper's conclusions on the reference study and on the study (module
    docstring).

    Parameters
    ----------
    ref_st, st : Study
        The reference study (the paper's robot) and the study of the other robot.
    ref_res, res : path
        Their results folders.

    Returns
    -------
    DataFrame with ``COLUMNS``: values in the row's unit (mm for indices, '-' for ratios and
    categories), the truth of each row's statement on each robot, the verdict.
    """
    rows = []
    sides = ((ref_st, ref_res), (st, res))

    printed = cm.printed_values()

    def add(
        group, quantity, statement, unit, a, b, tol=None, claim=None, headline=False, note="", paper=None
    ):
        """One row; ``paper``: the paper's own value of the row: True for a statement it concludes,
        or the quantity of its printed number (``printed_values``)."""
        if tol is None and claim is None and not isinstance(a, str) and not cm.is_missing(a):
            tol = REL * abs(a)
        if paper is True:  # the paper concludes the statement: its truth on the robot is the verdict
            pv = "yes"
            vp = "undetermined" if claim is None else ("holds" if claim[1] else "reverses")
        elif paper in printed:
            val, ptol = printed[paper]
            pv = val
            vp = cm.verdict(val, b, ptol if ptol else REL * abs(val))
        else:
            pv, vp = None, None
        rows.append(
            {
                "group": group,
                "quantity": quantity,
                "statement": statement,
                "unit": unit,
                "reference": a,
                "robot": b,
                "tolerance": tol,
                "claim_reference": None if claim is None else bool(claim[0]),
                "claim_robot": None if claim is None else bool(claim[1]),
                "verdict": cm.verdict(a, b, np.inf if tol is None else tol, claim),
                "paper": pv,
                "verdict_paper": vp,
                "headline": headline,
                "note": note,
            }
        )

    def both(f):
        return [f(s, r) for s, r in sides]

    def claim(values, test):
        return None if any(cm.is_missing(v) for v in values) else tuple(test(v) for v in values)

    names = both(lambda s, r: s["doe"]["robot"])
    kinds = both(lambda s, r: cm.first_designs(s))
    pair = all("SR" in k and "DR" in k for k in kinds)
    on = f"{names[0]} / {names[1]}"
    # -- the plane (section 3.3.2, Fig. 12)
    if pair:
        r = [
            cm.plane_extremes(res_, rk, k["DR"])[1] / cm.plane_extremes(res_, rk, k["SR"])[1]
            for (_, res_), rk, k in zip(sides, names, kinds)
        ]
        z = both(lambda s, r_: s["plane"]["z_m"])
        add(
            "plane",
            "plane max ‖δp‖ DR / SR",
            "DR pulleys give smaller errors than SR on the working plane (largest ‖δp‖)",
            "-",
            *r,
            claim=claim(r, lambda v: v < 1),
            headline=True,
            paper=True,
            note=f"planes z = {z[0]:g} m / {z[1]:g} m ({on})",
        )
        # -- error-limited volumes (section 3.3.3, Fig. 13), the limits paired in order
        limits = both(lambda s, r_: list(s["volumes"]["limits_m"]))
        for la, lb in zip(*limits):
            d = [
                cm.regular_volume(res_, rk, k["DR"], lim) - cm.regular_volume(res_, rk, k["SR"], lim)
                for (_, res_), rk, k, lim in zip(sides, names, kinds, (la, lb))
            ]
            add(
                "volumes",
                f"R_V(DR) - R_V(SR) at {la:g} m / {lb:g} m",
                f"DR pulleys give a larger error-limited volume than SR (‖δp‖ limit {la:g} m / {lb:g} m)",
                "-",
                *d,
                claim=claim(d, lambda v: v > 0),
                headline=True,
                paper=True,
                note=f"limits on ‖δp‖ of {on}, each study's own",
            )
    # -- the 2^3 DOE (section 4.2, Fig. 15-16)
    doe_ = both(lambda s, r_: _effects(r_))
    if all(d is not None and e is not None for d, e in doe_):
        best = [int(d.loc[d.index_m.idxmin(), "test"]) for d, _ in doe_]
        worst = [int(d.loc[d.index_m.idxmax(), "test"]) for d, _ in doe_]
        add(
            "doe",
            "DOE best and worst tests",
            "test 1 (SR, small h, small r_p) is the best design and test 7 (DR, large h, small r_p) the worst",
            "-",
            *(f"best {b}, worst {w}" for b, w in zip(best, worst)),
            claim=tuple(b == 1 and w == 7 for b, w in zip(best, worst)),
            headline=True,
            paper=True,
        )
        gap = [(d[d.kind == "DR"].index_m.min() - d[d.kind == "SR"].index_m.min()) * 1e3 for d, _ in doe_]
        add(
            "doe",
            "best DR test - best SR test",
            "the best DR test has a smaller global index than the best SR test",
            "mm",
            *gap,
            claim=claim(gap, lambda v: v < 0),
        )
        top = [str(e.effect.abs().idxmax()) for _, e in doe_]
        add(
            "doe",
            "largest DOE effect",
            "the joint × r_p interaction is the largest effect on the index (Fig. 16)",
            "-",
            *top,
            claim=tuple(t == "joint:r_p" for t in top),
            headline=True,
            paper=True,
        )
        for term in doe_[0][1].index:
            v = [float(e.effect.get(term, np.nan)) * 1e3 for _, e in doe_]
            add(
                "doe",
                f"effect {term}",
                f"the effect of {term} on the index is positive",
                "mm",
                *v,
                claim=claim(v, lambda x: x > 0),
            )
    # -- the optimal lines (section 4.3, Fig. 17, Table 3)
    slopes = {}
    for kind in ("SR", "DR"):
        slopes[kind] = both(lambda s, r_, kind=kind: cm.line_value(r_, kind, "slope_k"))
        add(
            "maps",
            f"D_{kind} slope h / r_p",
            f"the optimal line D_{kind}: h = k r_p (paper: k = {PAPER_SLOPES[kind]})",
            "-",
            *slopes[kind],
            headline=True,
            paper=f"D_{kind} slope h/r_p",
        )
    s = [a - b for a, b in zip(slopes["SR"], slopes["DR"])]
    add(
        "maps",
        "slope D_SR - slope D_DR",
        "D_SR is steeper than D_DR",
        "-",
        *s,
        claim=claim(s, lambda v: v > 0),
        paper=True,
    )
    ix = [
        (cm.line_value(r_, "DR", "index_opt_m") - cm.line_value(r_, "SR", "index_opt_m")) * 1e3
        for _, r_ in sides
    ]
    add(
        "maps",
        "index at I_DR - index at I_SR",
        "DR pulleys beat SR: the optimal DR design has the smaller global index (Table 3)",
        "mm",
        *ix,
        claim=claim(ix, lambda v: v < 0),
        headline=True,
        paper=True,
    )
    # -- Young's modulus (section 5, Fig. 18)
    sr, dr = both(lambda s, r_: _opt(s, "SR")), both(lambda s, r_: _opt(s, "DR"))
    if all(sr) and all(dr):
        ratio = [
            cm.band_value(r_, a, "total_m") / cm.band_value(r_, b, "total_m")
            for (_, r_), a, b in zip(sides, sr, dr)
        ]
        add(
            "elasticity",
            "E band total SR* / DR*",
            "SR* is more robust to E than DR* (a smaller band of the index over E)",
            "-",
            *ratio,
            claim=claim(ratio, lambda v: v < 1),
            headline=True,
            paper=True,
            note=f"designs {sr[0]}, {dr[0]} / {sr[1]}, {dr[1]}",
        )
    return pd.DataFrame(rows, columns=COLUMNS)


def _fmt(v, unit):
    if isinstance(v, str):
        return v
    if cm.is_missing(v):
        return "—"
    return f"{v:.4g}" + ("" if unit == "-" else f" {unit}")


def _text(v):
    """A cell's text: empty for None and NaN."""
    return "" if v is None or (isinstance(v, float) and np.isnan(v)) else str(v)


def _truth(c):
    return "" if c is None or (isinstance(c, float) and np.isnan(c)) else ("yes" if c else "no")


def _cell(v, unit, c=None):
    """A value with its unit, and the truth of the row's statement in brackets."""
    t = _truth(c)
    return _fmt(v, unit) + (f" ({t})" if t else "")


def _statement_cells(r):
    """A row's cells from its statement to its verdict against the paper (both tables of
    ``conclusions_page``): statement, paper, reference, robot, verdict, verdict_paper."""
    return [
        r.statement,
        _fmt(r.paper, r.unit) if _text(r.paper) else "",
        _cell(r.reference, r.unit, r.claim_reference),
        _cell(r.robot, r.unit, r.claim_robot),
        r.verdict,
        _text(r.verdict_paper),
    ]


def conclusions_page(ref_st, st, rows):
    """The page: what is compared, the headline table and every row (Markdown)."""
    ref_name, name = ref_st["doe"]["robot"], st["doe"]["robot"]
    counts = rows.verdict.value_counts()
    vp = rows.verdict_paper.dropna().value_counts()
    lines = [
        f"# Do the paper's conclusions hold on {name}?",
        "",
        f"Study `{st['name']}` ({name}) against the reference study `{ref_st['name']}` ({ref_name}, "
        "the paper's robot), both in physical mode: every statement of Paty et al. (2021)'s conclusions "
        f"evaluated on both robots' results (`cdpr.pipeline.conclusions`). {name}'s numbers are of ‖δp‖, "
        "its reference point's position error; its orientation error δφ is in its summary. Each "
        "study scales the DOE levels and the volume limits to its own robot (the row's note).",
        "",
        "Verdicts (`cdpr.pipeline.comparison.verdict`): **holds** = the statement has the same truth value "
        "on both; **reverses** = true on one, false on the other; **changes** = a categorical value "
        f"differs, or a number without a statement moves by more than {REL:.0%} (against the paper: the "
        "tolerance of its printed number, cdpr/data/paper_values.yaml); **undetermined** = a value is missing. "
        f"*vs {ref_name}* compares {name} with our {ref_name} study; *vs paper* with what the paper "
        "concludes (yes: the paper states it) or prints.",
        "",
        f"Verdicts vs {ref_name}: "
        + ", ".join(f"{v} {int(counts.get(v, 0))}" for v in cm.VERDICTS)
        + ". Verdicts vs the paper: "
        + ", ".join(f"{v} {int(vp.get(v, 0))}" for v in cm.VERDICTS)
        + ".",
        "",
        "## Headline",
        "",
        f"| statement | paper | {ref_name} | {name} | vs {ref_name} | vs paper |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows[rows.headline].itertuples():
        lines.append(io.md_row(_statement_cells(r)))
    lines += [
        "",
        "## Every row",
        "",
        f"| group | quantity | statement | paper | {ref_name} | {name} | vs {ref_name} | vs paper | note |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows.itertuples():
        lines.append(io.md_row([r.group, r.quantity, *_statement_cells(r), r.note]))
    return "\n".join(lines) + "\n"


def write_conclusions(st, results, table, markdown):
    """Write the conclusions table (CSV) and page (Markdown) of a study with a ``conclusions`` key."""
    ref_st, ref_res = reference_of(st)
    rows = robot_conclusions(ref_st, ref_res, st, results)
    table_io.write_table(rows, table)
    io.write_text(conclusions_page(ref_st, st, rows), markdown)
    return rows
