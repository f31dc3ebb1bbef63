"""Plausibility of a robot: values far outside what a real cable-driven parallel robot has (a unit
slip, most likely: a diameter in millimetres typed into a metre key, a modulus in GPa typed as Pa),
each one sentence naming the key, the value and the likely slip. The robot stays valid (a user may
mean it); the command line prints each sentence on stderr and adds them to its JSON objects."""

from __future__ import annotations

import numpy as np


def _plain(v):
    """A vector as a list of plain floats, for messages (no numpy reprs)."""
    return [float(x) for x in v]


#: Young's moduli of real cables [Pa]: polymer fibres (a few GPa) to steel (about 200 GPa); outside
#: [1 GPa, 1000 GPa] a value is a unit slip more likely than a material.
E_PLAUSIBLE_PA = (1e9, 1e12)
#: The thickest cable diameter [m] taken without a word (thicker is a 50 mm rope or a unit slip) and
#: the largest fraction of the frame's size a diameter may be.
DIAMETER_MAX_M = 0.05
DIAMETER_FRAME_FRACTION = 0.01
#: The largest lever arm or sheave radius [m] taken without a word, and fraction of the frame's size.
PULLEY_MAX_M = 1.0
PULLEY_FRAME_FRACTION = 0.25
#: The largest frame [m] (the anchors' bounding-box diagonal) taken without a word: the largest
#: cable robots span a few hundred metres.
FRAME_MAX_M = 1000.0
#: An anchor this many times farther from the anchors' median than the typical anchor stands apart.
ANCHOR_OUTLIER_FACTOR = 50.0


def _same_or_each(values, default_key, cable_key):
    """``[(key, value)]`` of a per-cable quantity: the robot's default key when every cable has the
    same value, else one entry per cable (``cables[i].<cable_key>``)."""
    values = [float(v) for v in values]
    if all(v == values[0] for v in values):
        return [(default_key, values[0])]
    return [(f"cables[{i}].{cable_key}", v) for i, v in enumerate(values)]


def plausibility_warnings(robot):
    """Values far outside what a real cable-driven parallel robot has, each as one sentence naming
    the key, the value and the likely unit slip (the robot is still valid: a user may mean it).

    Checked: Young's modulus outside ``E_PLAUSIBLE_PA``; a cable diameter above ``DIAMETER_MAX_M`` or
    ``DIAMETER_FRAME_FRACTION`` of the frame; a lever arm or sheave radius above ``PULLEY_MAX_M`` or
    ``PULLEY_FRAME_FRACTION`` of the frame; a frame (the anchors' bounding-box diagonal) above
    ``FRAME_MAX_M``; one anchor ``ANCHOR_OUTLIER_FACTOR`` times farther from the anchors' median
    than the typical anchor; platform attachments that span more than the frame.

    Parameters
    ----------
    robot : Robot
        A validated robot.

    Returns
    -------
    list of str
        One sentence per implausible value (empty when every value is plausible), in a fixed order.
    """
    out = []
    a = robot.arrays
    A = a.A
    frame = float(np.linalg.norm(np.ptp(A, axis=0)))  # the anchors' bounding-box diagonal [m]
    lo, hi = E_PLAUSIBLE_PA
    for key, E in _same_or_each(a.E, "cable.young_modulus_Pa", "cable.young_modulus_Pa"):
        if not lo <= E <= hi:
            if lo <= E * 1e9 <= hi:
                hint = f"GPa typed as Pa? ({E:g} GPa = {E * 1e9:g} Pa)"
            elif lo <= E * 1e6 <= hi:
                hint = f"MPa typed as Pa? ({E:g} MPa = {E * 1e6:g} Pa)"
            else:
                hint = "a unit slip?"
            out.append(
                f"{key} = {E:g} Pa is outside the Young's moduli of real cables (1 GPa to 1000 GPa): {hint}"
            )
    diam = [c.material.diameter for c in robot.cables]
    d_max = min(DIAMETER_MAX_M, DIAMETER_FRAME_FRACTION * frame) if frame > 0 else DIAMETER_MAX_M
    for key, d in _same_or_each(diam, "cable.diameter_m", "cable.diameter_m"):
        if d > d_max:
            out.append(
                f"{key} = {d:g} m is a {d * 1e3:g} mm thick cable on a {frame:.3g} m frame: "
                f"millimetres typed as metres? ({d:g} mm = {d * 1e-3:g} m)"
            )
    p_max = min(PULLEY_MAX_M, PULLEY_FRAME_FRACTION * frame) if frame > 0 else PULLEY_MAX_M
    for name, vals in (("h_m", a.h), ("r_p_m", a.r_p)):
        what = "lever arm" if name == "h_m" else "sheave radius"
        for key, v in _same_or_each(vals, f"pulley.{name}", f"pulley.{name}"):
            if v > p_max:
                out.append(
                    f"{key} = {v:g} m is a {what} of {v:g} m on a {frame:.3g} m frame: "
                    f"millimetres typed as metres? ({v:g} mm = {v * 1e-3:g} m)"
                )
    if frame > FRAME_MAX_M:
        out.append(
            f"cables[*].A_m: the anchors span {frame:.4g} m (bounding-box diagonal), larger than any cable "
            f"robot: every location in millimetres? ({frame:.4g} mm = {frame * 1e-3:.4g} m)"
        )
    centre = np.median(A, axis=0)
    dist = np.linalg.norm(A - centre, axis=1)
    typical = float(np.median(dist))
    if typical > 0:
        for i in np.flatnonzero(dist > ANCHOR_OUTLIER_FACTOR * typical):
            out.append(
                f"cables[{i}].A_m = {_plain(A[i])} m lies {dist[i]:.4g} m from the anchors' median, "
                f"{dist[i] / typical:.0f} times the typical {typical:.3g} m: millimetres among metres?"
            )
    b = a.b
    span = float(np.linalg.norm(np.ptp(b, axis=0)))
    if frame > 0 and span > frame:
        out.append(
            f"cables[*].B_m: the platform's attachments span {span:.4g} m, more than the frame's "
            f"{frame:.4g} m (anchors' bounding-box diagonal): attachments in millimetres?"
        )
    return out
