"""The robot drawn from its model (nothing solved): the robot in 3-D at a pose with its boxes (``cdpr
view``, the study's ``robot`` part) and the pulley-axis convention of docs/spatial.md.
"""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.lines import Line2D
from scipy.spatial import ConvexHull

from cdpr.pipeline.plots.style import anchor_groups, mode_suffix, save

# ---- the robot in 3-D (``cdpr view``, the study's robot figure) --------------------------------
#: The colour of a cable D_i → B_i, and of one that interferes at the pose (``geom["interfering"]``).
CABLE_COLOUR, INTERFERING_COLOUR = "tab:blue", "tab:pink"


def cable_colours(geom):
    """The colour of each cable D_i → B_i in ``robot_view``: ``INTERFERING_COLOUR`` for the cables
    that interfere at the pose (``scans.pose_geometry``'s ``interfering``), ``CABLE_COLOUR`` else.

    Parameters
    ----------
    geom : dict
        ``scans.pose_geometry`` of the robot at the pose.

    Returns
    -------
    list of str
        One colour per cable.
    """
    bad = geom.get("interfering", np.zeros(len(geom["A"]), dtype=bool))
    return [INTERFERING_COLOUR if b else CABLE_COLOUR for b in bad]


#: Colours and line styles of the boxes ``robot_view`` draws, in the order given.
BOX_STYLES = [("0.45", "--"), ("tab:purple", "-"), ("tab:brown", "-."), ("tab:olive", ":")]


def _box_edges(box):
    """The 12 edges of the axis-aligned box (xmin, xmax, ymin, ymax, zmin, zmax) [m], each (2, 3)."""
    b = np.asarray(box, dtype=float)
    corners = np.array([[b[i], b[2 + j], b[4 + k]] for i in (0, 1) for j in (0, 1) for k in (0, 1)])
    # corners differ in one coordinate along an edge: index bits (x, y, z) = (4, 2, 1)
    return [corners[[c, c | bit]] for c in range(8) for bit in (4, 2, 1) if not c & bit]


def cable_line(geom, i):
    """The points drawn for cable ``i`` of ``geom`` (``scans.pose_geometry``): the heavy cable's
    catenary from B_i to its exit point (``scans.catenary_geometry``) where the robot's cables have
    weight, else the straight segment D_i → B_i.

    Parameters
    ----------
    geom : dict
        ``scans.pose_geometry`` of the robot at the pose.
    i : int
        Cable index (0-based).

    Returns
    -------
    ndarray (k, 3) [m]
        The polyline.
    """
    if "catenary" in geom and np.isfinite(geom["catenary"][i]).all():
        return geom["catenary"][i]
    return np.stack([geom["D"][i], geom["B"][i]])


def _cable_label(geom):
    """The legend entry of the cables: catenaries (and at which tensions) or straight lines."""
    if "catenary" not in geom:
        return "cables D_i → B_i"
    if not np.isfinite(geom["catenary_t"]).all():
        return "cables D_i → B_i (straight: no tensions hold the pose)"
    return "cables: catenaries B_i → D_i"


def _plan_panel(ax, geom, boxes, span):
    """The plan (top) view of ``robot_view``: the same elements seen from +z, x and y to equal scale,
    with every anchor's cable numbers (anchors that coincide from above share one label)."""
    A, B, colours = geom["A"], geom["B"], cable_colours(geom)
    for (label, box), (colour, ls) in zip(boxes.items(), BOX_STYLES * 4):
        x0, x1, y0, y1 = box[:4]
        ax.plot([x0, x1, x1, x0, x0], [y0, y0, y1, y1, y0], color=colour, ls=ls, lw=0.9)
    for i in range(len(A)):
        ax.plot(*np.stack([geom["C"][i], geom["K"][i]])[:, :2].T, color="0.6", lw=0.8)
        ax.plot(*cable_line(geom, i)[:, :2].T, color=colours[i], lw=1.1)
        if np.isfinite(geom["sheave"][i]).all():
            ax.plot(*geom["sheave"][i][:, :2].T, color="tab:orange", lw=0.9)
    ax.scatter(*A[:, :2].T, color="k", marker="^", s=18, zorder=3)
    for g in anchor_groups(A[:, :2], span):
        c = A[g, :2].mean(axis=0)
        ax.annotate(",".join(str(i + 1) for i in g), c, xytext=(4, 4), textcoords="offset points", fontsize=7)
    if not geom["point_mass"]:
        try:
            hull = ConvexHull(B[:, :2]).vertices
            ax.plot(*B[np.append(hull, hull[0]), :2].T, color="tab:green", lw=0.8)
        except Exception:  # attachment points on a line from above: their outline
            ax.plot(*B[:, :2].T, color="tab:green", lw=0.8)
        ax.scatter(*geom["com"][:2], color="tab:green", marker="x", s=30, zorder=3)
    ax.scatter(*geom["p"][:2], color="tab:green", s=20, zorder=3)
    ax.set(xlabel="x [m]", ylabel="y [m]", aspect="equal", title="plan (top) view, from +z")
    ax.title.set_fontsize(9)
    ax.tick_params(labelsize=7)
    ax.grid(alpha=0.3)


def robot_view(geom, out, boxes=None, mode=None, plan=False):
    """A 3-D picture of a robot at a pose: the joint points A_i with their cable numbers, the swivel
    axes k_i, the sheaves, the dead lengths C_i → K_i, the cables D_i → B_i, the platform (the
    attachment points' hull, its centre of mass and reference point) and the given boxes as
    wireframes; the cables that interfere at the pose (another cable or the platform body,
    ``cable_colours``) in ``INTERFERING_COLOUR``. Nothing is solved: ``geom`` is ``cdpr.analyses.scans.pose_geometry`` (the desired
    pose). Drawn to equal scale on every axis.

    Parameters
    ----------
    geom : dict
        ``scans.pose_geometry`` of the robot at the pose.
    out : str or Path
        The .png written (a .pdf beside it, ``save``).
    boxes : dict, optional
        Label -> box (xmin, xmax, ymin, ymax, zmin, zmax) [m] drawn as a wireframe (e.g. the frame
        box of the volumes' grid, the study's RW_C), in the styles of ``BOX_STYLES``.
    mode : {"paper", "physical", None}
        The study's redundancy mode, named in the title (``cdpr view`` has none).
    plan : bool
        Also draw the plan (top) view, seen from +z, beside the 3-D one (``cdpr view --plan``).
    """
    boxes = dict(boxes or {})
    A, B, axis = geom["A"], geom["B"], geom["axis"]
    colours = cable_colours(geom)
    allp = np.vstack([A, B, geom["C"], geom["H"]] + [e for b in boxes.values() for e in _box_edges(b)])
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    span = float((hi - lo).max())
    lo, hi = lo - 0.03 * span, hi + 0.03 * span
    fig = plt.figure(figsize=(14.0, 7.0) if plan else (8.0, 7.0), layout="constrained")
    ax = fig.add_subplot(1, 2 if plan else 1, 1, projection="3d")
    if plan:
        _plan_panel(fig.add_subplot(1, 2, 2), geom, boxes, span)
    handles = []
    for (label, box), (colour, ls) in zip(boxes.items(), BOX_STYLES * 4):
        for e in _box_edges(box):
            ax.plot(*e.T, color=colour, ls=ls, lw=0.9)
        handles.append(Line2D([], [], color=colour, ls=ls, label=label))
    ax.scatter(*A.T, color="k", marker="^", s=18, depthshade=False)
    for i in range(len(A)):
        ax.plot(*np.stack([geom["C"][i], geom["K"][i]]).T, color="0.6", lw=0.8)
        ax.plot(*cable_line(geom, i).T, color=colours[i], lw=1.1, gid=f"cable {i + 1}")
        ax.plot(*np.stack([A[i], A[i] + 0.06 * span * axis[i]]).T, color="tab:red", lw=1.2)
        if np.isfinite(geom["sheave"][i]).all():
            ax.plot(*geom["sheave"][i].T, color="tab:orange", lw=0.9)
    for g in anchor_groups(A, span):
        c = A[g].mean(axis=0)
        ax.text(*(c + 0.04 * span * np.array([0, 0, 1])), ",".join(str(i + 1) for i in g), fontsize=7)
    if not geom["point_mass"]:
        try:
            for s in ConvexHull(B).simplices:
                ax.plot(*B[np.append(s, s[0])].T, color="tab:green", lw=0.5)
        except Exception:  # coplanar attachment points: their outline
            ax.plot(*np.vstack([B, B[:1]]).T, color="tab:green", lw=0.8)
        ax.scatter(*geom["com"], color="tab:green", marker="x", s=30, depthshade=False)
        handles += [
            Line2D([], [], color="tab:green", lw=0.5, label="platform: attachment points B_i (hull)"),
            Line2D([], [], color="tab:green", marker="x", ls="none", label="centre of mass"),
        ]
    ax.scatter(*geom["p"], color="tab:green", s=20, depthshade=False)
    handles += [
        Line2D([], [], color="tab:green", marker="o", ls="none", label="platform point p"),
        Line2D([], [], color="k", marker="^", ls="none", label="joint points A_i (cable numbers)"),
        Line2D([], [], color="tab:red", label="swivel axes k_i"),
        Line2D([], [], color="tab:orange", label="sheaves (radius r_p)"),
        Line2D([], [], color="0.6", label="dead length C_i → K_i"),
        Line2D([], [], color=CABLE_COLOUR, label=_cable_label(geom)),
    ]
    if INTERFERING_COLOUR in colours:  # only then: a robot free of interference keeps its picture
        handles.append(
            Line2D([], [], color=INTERFERING_COLOUR, label="interfering cables (cable or platform)")
        )
    ax.set(xlim=(lo[0], hi[0]), ylim=(lo[1], hi[1]), zlim=(lo[2], hi[2]))
    ax.set_box_aspect(hi - lo, zoom=0.9)
    ax.set_xlabel("x [m]", labelpad=4)
    ax.set_ylabel("y [m]", labelpad=4)
    ax.set_zlabel("z [m]", labelpad=2)
    ax.tick_params(labelsize=7, pad=0)
    rv = geom["rotvec"]
    pose = f"p = [{_numbers(geom['p'])}] m, rotvec = [{_numbers(rv)}] rad"
    ax.set_title(f"{geom['name']} at the desired pose {pose}{mode_suffix(mode)}", fontsize=9, wrap=True)
    fig.legend(handles=handles, loc="outside lower center", ncol=3, fontsize=7, frameon=False)
    return save(fig, out)


# ---- the pulley axis convention (docs/spatial.md, "The pulley axis") ------------------------------------
#: Where each point's label sits, as a direction of its offset (s, w) from the point when no other
#: rule applies (K and D are labelled radially outward from the sheave centre).
_PLANE_LABEL_DIR = {"C": (1.0, 0.0), "A": (-1.0, 0.6), "H": (0.7, 0.7), "B": (0.6, 0.8)}


def _label(ax, text, xy, direction, colour="k", pt=9.0):
    """``text`` next to the data point ``xy``, ``pt`` points away along ``direction``, aligned so
    that it grows away from the point."""
    u = np.asarray(direction, dtype=float)
    u = u / max(float(np.linalg.norm(u)), 1e-12)
    ha = "left" if u[0] > 0.3 else ("right" if u[0] < -0.3 else "center")
    va = "bottom" if u[1] > 0.3 else ("top" if u[1] < -0.3 else "center")
    ax.annotate(
        text,
        xy,
        xytext=(pt * u[0], pt * u[1]),
        textcoords="offset points",
        ha=ha,
        va=va,
        fontsize=9,
        color=colour,
    )


def _pulley_plane_panel(ax, g, lim):
    """One pulley drawn in its cable plane (``scans.pulley_plane_geometry`` ``g``) on ``ax`` with the
    data limits ``lim`` = (s0, s1, w0, w1) [m]."""
    P = g["plane"]
    s0, s1, w0, w1 = lim
    ax.plot([0.0, 0.0], [w0, w1 - 0.02 * (w1 - w0)], color="k", ls=(0, (4, 3)), lw=0.8, zorder=1)
    ax.annotate(
        "",
        (0.0, w1 - 0.02 * (w1 - w0)),
        xytext=(0.0, w1 - 0.12 * (w1 - w0)),
        arrowprops={"arrowstyle": "-|>", "color": "k", "lw": 1.0},
    )
    ax.annotate(
        r"$\mathbf{k}_i$",
        (0.0, w1 - 0.04 * (w1 - w0)),
        xytext=(6, 0),
        textcoords="offset points",
        ha="left",
        va="center",
        fontsize=10,
    )
    if np.isfinite(g["sheave"]).all():
        ax.plot(*g["sheave"].T, color="tab:orange", lw=1.0, zorder=2)
    cable = {"color": "tab:blue", "lw": 2.0, "zorder": 3, "solid_capstyle": "butt"}
    ax.plot(*np.stack([P["C"], P["K"]]).T, **cable)
    ax.plot(*g["arc"].T, **cable)
    ax.plot(*np.stack([P["D"], P["B"]]).T, **cable)
    ax.plot(*np.stack([P["A"], P["H"]]).T, color="tab:red", lw=1.6, zorder=4)
    arm = P["H"] - P["A"]
    if np.linalg.norm(arm) > 0:
        # h beside the arm, 30 % of the way from A: on the side of +s (below a horizontal SR arm,
        # inside the sheave; right of a DR arm, between it and the arc)
        n = np.array([arm[1], -arm[0]]) / np.linalg.norm(arm)
        if n[0] < -1e-9 or (abs(n[0]) <= 1e-9 and n[1] > 0):
            n = -n
        _label(ax, "$h$", P["A"] + 0.3 * arm, n, colour="tab:red", pt=4.0)
    names = {"C": "$C_i$", "A": "$A_i$", "H": "$H_i$", "K": "$K_i$", "D": "$D_i$", "B": "$B_i$"}
    same = np.linalg.norm(P["K"] - P["A"]) < 1e-3 * (s1 - s0)
    for n, xy in P.items():
        if same and n == "K":
            continue
        text = "$A_i = K_i$" if same and n == "A" else names[n]
        if n in ("K", "D"):
            d = xy - P["H"]
        else:
            d = _PLANE_LABEL_DIR[n]
        ax.plot(*xy, "o", color="k", ms=3.5, zorder=5)
        _label(ax, text, xy, d)
    ax.set(xlim=(s0, s1), ylim=(w0, w1), aspect="equal")
    ax.set_xlabel(r"s [m]  (perpendicular to $\mathbf{k}_i$, toward $B_i$)")
    ax.set_ylabel(r"w [m]  (along $\mathbf{k}_i$)")
    h, r = g["h"] * 1e3, g["r_p"] * 1e3
    arms = f"h = r_p = {h:.0f} mm" if abs(h - r) < 1e-9 else f"h = {h:.0f} mm, r_p = {r:.0f} mm"
    ax.set_title(
        f"{g['kind']}, {arms}\nwrap γ = {np.degrees(g['gamma']):.1f}°, |B−D| = l_E = {g['l_E']:.3f} m, "
        f"L_TE = {g['L_TE']:.3f} m",
        fontsize=9,
    )


def _swivel_panel(ax, g):
    """The pulley seen from the tip of k_i (``g`` of ``scans.pulley_plane_geometry``): i_i (the
    swivel angle's zero), j_i, the trace of the cable plane toward B and the swivel angle."""
    top = g["top"]
    b = top["B"]
    L = 0.45 * float(np.linalg.norm(b))
    arrow = {"arrowstyle": "-|>", "color": "k", "lw": 1.0}
    ax.annotate("", (L, 0.0), xytext=(0.0, 0.0), arrowprops=arrow)
    ax.annotate("", (0.0, L), xytext=(0.0, 0.0), arrowprops=arrow)
    _label(ax, r"$\mathbf{i}_i$ (zero)", (L, 0.0), (0.0, -1.0))
    _label(ax, r"$\mathbf{j}_i$", (0.0, L), (-1.0, 0.0))
    e = g["e_s"]
    ax.plot([0.0, b[0]], [0.0, b[1]], color="tab:blue", ls=(0, (4, 3)), lw=1.0)
    H, r = top["H"], g["r_p"]
    if r > 0:
        ax.plot(*np.stack([H - r * e, H + r * e]).T, color="tab:orange", lw=3.0, solid_capstyle="butt")
    ax.plot(0.0, 0.0, "o", color="k", ms=3.5)
    ax.plot(*b, "o", color="k", ms=3.5)
    _label(ax, "$A_i$", (0.0, 0.0), (-1.0, -1.0))
    _label(ax, "$B_i$ (projected)", b, (0.0, 1.0))
    sw = g["swivel"]
    t = np.linspace(0.0, sw, 60)
    rad = 0.6 * L
    ax.plot(rad * np.cos(t), rad * np.sin(t), color="tab:green", lw=1.2)
    mid = 0.5 * sw
    _label(
        ax,
        f"swivel {np.degrees(sw):.1f}°",
        (rad * np.cos(mid), rad * np.sin(mid)),
        (1.0, 0.35),
        colour="tab:green",
    )
    pad = 0.25 * float(np.linalg.norm(b))
    xs = [0.0, b[0], L]
    ys = [0.0, b[1], L]
    ax.set(xlim=(min(xs) - pad, max(xs) + pad), ylim=(min(ys) - pad, max(ys) + pad), aspect="equal")
    ax.set_xlabel(r"along $\mathbf{i}_i$ [m]")
    ax.set_ylabel(r"along $\mathbf{j}_i$ [m]")
    ax.set_title("seen from the tip of $\\mathbf{k}_i$:\nthe swivel angle", fontsize=9)


def pulley_axis_figure(geoms, out):
    """The pulley-axis convention drawn from the model (docs/spatial.md, "The pulley axis"): each
    pulley of ``geoms`` in the plane through its swivel axis k_i that contains the attachment point
    B_i (in-plane coordinates s ⟂ k_i toward B_i, w along k_i, origin the joint point A_i): the axis
    with its direction, the sheave, the points C_i = A_i - d_i k_i (winch exit), A_i, H_i (sheave
    centre), K_i (entry tangent point), D_i (exit tangent point) and B_i, the cable C→K (along
    +k_i), the wrapped arc K→D over the +k_i side, the straight part D→B and the lever arm h = |A H|;
    then the first pulley seen from the tip of k_i with i_i (the swivel angle's zero), j_i and the
    swivel angle atan2(w·j_i, w·i_i), w = B_i - A_i. Nothing is solved here: the points are those of
    ``cdpr.analyses.scans.pulley_plane_geometry`` (``models.pulleys.pulley_state``).

    Parameters
    ----------
    geoms : list of dict
        ``scans.pulley_plane_geometry`` of one or more pulleys (e.g. an SR and a DR pulley at the
        same joint point and attachment), drawn side by side to the same scale.
    out : str or Path
        The .png written (a .pdf beside it, ``save``).

    References
    ----------
    Paty et al. 2021, eq. (3)-(7) (the plane of the cable, the SR and DR sheave centres).
    """
    allp = np.vstack(
        [
            np.vstack(list(g["plane"].values()) + [g["sheave"][np.isfinite(g["sheave"]).all(axis=1)]])
            for g in geoms
        ]
    )
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    span = float((hi - lo).max())
    lim = (lo[0] - 0.22 * span, hi[0] + 0.12 * span, lo[1] - 0.06 * span, hi[1] + 0.22 * span)
    n = len(geoms)
    fig = plt.figure(figsize=(4.2 * n + 3.4, 4.6), layout="constrained")
    axes = fig.subplots(1, n + 1, width_ratios=[1.0] * n + [0.8])
    for ax, g in zip(axes, geoms):
        _pulley_plane_panel(ax, g, lim)
    _swivel_panel(axes[-1], geoms[0])
    g = geoms[0]
    k = g["frame"][2]
    w = g["points"]["B"] - g["points"]["A"]
    fig.suptitle(
        f"{g['name']}, pulley of cable {g['cable']}: k_i = [{', '.join(f'{x:.3g}' for x in k)}], "
        f"d = {g['d']:.3g} m, B_i − A_i = [{', '.join(f'{x:.3g}' for x in w)}] m\n"
        "drawn in the plane through the swivel axis k_i that contains B_i",
        fontsize=10,
    )
    handles = [
        Line2D([], [], color="tab:blue", lw=2.0, label="cable: C→K along +k_i, arc K→D, straight D→B"),
        Line2D([], [], color="tab:orange", lw=1.0, label="sheave (radius r_p)"),
        Line2D([], [], color="tab:red", lw=1.6, label="lever arm h = |A_i H_i|"),
        Line2D([], [], color="k", ls=(0, (4, 3)), lw=0.8, label="swivel axis k_i through A_i"),
    ]
    fig.legend(handles=handles, loc="outside lower center", ncol=4, fontsize=8, frameon=False)
    return save(fig, out)


def _numbers(values, tiny=1e-9):
    """Values for a title, 3 significant digits, round-off below ``tiny`` (a rotation's 1.11e-16 m,
    a -0) shown as 0."""
    return ", ".join(f"{(0.0 if abs(x) < tiny else float(x)):.3g}" for x in values)
