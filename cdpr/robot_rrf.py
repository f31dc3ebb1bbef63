"""Hangprinter robot files from RepRapFirmware configurations, and firmware lines from robot files.

``robot_dict_from_rrf`` reads the ``M669 K6 A.. B.. C.. D..`` (anchors, mm) and ``M666 Q R U O L H
W S X Y`` lines of a RepRapFirmware ``config.g`` (HangprinterKinematics: buildup factor Q [mm],
spool radii R [mm], mechanical advantage U, lines per spool O, motor and spool gear teeth L and H,
mover weight W [kg], line stiffness per unit length S [N] = E A of the line, maximum planned force
X [N], guy-wire lengths Y [mm]); every other G-code is ignored, and ``;`` starts a comment. The
robot it builds: a point mass on the anchors' cables through fixed pulleys (``pulley.kind:
fixed``), a spool winch per cable (``winch: {kind: spool}``), the line's E A, the mover's mass.
Every value the configuration does not give takes RepRapFirmware's default and is listed as assumed.

``rrf_lines`` and ``klipper_text`` write a robot file's geometry back as firmware configuration.
Klipper's ``winch`` kinematics has no spool buildup model.

Modelling choices (docs/hangprinter.md): the U strands between anchor and mover make one cdpr cable
of axial stiffness U E A (``cdpr.robot``); the guy wire from the spool to its anchor (M666 Y; by
RepRapFirmware's default, with every spool at the top anchor D, |A_i - D| for the others and 0 for
D) stretches with the line: it becomes the dead length d_i = Y_i / U_i (the strands' share of it).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from cdpr.errors import CdprError

#: The anchors' letters of M669 (RepRapFirmware's ANCHOR_CHARS for up to 5 anchors).
ANCHOR_LETTERS = "ABCDI"

#: RepRapFirmware's defaults (HangprinterKinematics::Init), used where a configuration is silent.
RRF_DEFAULTS = {
    "Q": 0.007,  # buildup factor [mm]
    "R": 75.0,  # spool radius [mm]
    "U": (2, 2, 2, 2, 4),  # mechanical advantage per anchor
    "O": 1,  # lines per spool
    "L": 20,  # motor gear teeth
    "H": 255,  # spool gear teeth
    "S": 20000.0,  # line stiffness per unit length [N]
    "X": 70.0,  # maximum planned force [N]
}

#: The line's diameter written into imported robot files [m] (not in a RepRapFirmware
#: configuration; only E S = the M666 S value enters the model). 0.5 mm: the FireLine of
#: RepRapFirmware's buildup-factor comment.
LINE_DIAMETER_M = 0.0005

#: The mover's mass written when M666 W is absent or 0 [kg] (RepRapFirmware's W = 0 disables its
#: flex compensation; cdpr's platform needs a mass).
DEFAULT_MASS_KG = 1.0

_NUMBER = re.compile(r"^[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


def _words(line):
    """The words of one G-code line without its comment: [(letter, value text), ...]."""
    code = line.split(";", 1)[0].strip()
    return [(w[0].upper(), w[1:]) for w in code.split()] if code else []


def _numbers(path, lineno, command, letter, text, count=None, integer=False):
    """The colon-separated numbers of one parameter word; CdprError naming the file and the word."""
    word = f"{command} {letter}{text}"
    parts = text.split(":")
    if not text or not all(_NUMBER.match(p) for p in parts):
        raise CdprError(
            f"{path} line {lineno}: {word!r}: expected {'numbers' if count != 1 else 'a number'} separated by ':'"
        )
    vals = [float(p) for p in parts]
    if count is not None and len(vals) not in ((count,) if letter in "ABCDI" else (1, count)):
        raise CdprError(
            f"{path} line {lineno}: {word!r}: expected {count} values separated by ':'"
            + ("" if letter in "ABCDI" else " (or one for every anchor)")
            + f", got {len(vals)}"
        )
    if integer and not all(v == int(v) and v >= 1 for v in vals):
        raise CdprError(f"{path} line {lineno}: {word!r}: expected positive integers")
    if count is not None and len(vals) == 1 and count > 1:
        vals = vals * count
    return [int(v) for v in vals] if integer else vals


def parse_rrf(path):
    """The Hangprinter parameters of a RepRapFirmware configuration file.

    Parameters
    ----------
    path : str or Path
        The configuration (``config.g``).

    Returns
    -------
    dict
        ``anchors_mm``: the m anchors (x, y, z) in mm; ``given``: the M666 values found, by
        letter: Q (mm), W (kg), S (N) floats; R (mm), X (N), Y (mm) lists of m floats; U, O, L, H
        lists of m ints.

    Raises
    ------
    CdprError
        No M669 K6 line, a missing anchor, a malformed or non-positive value: one line naming the
        file, the line and the word.
    """
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise CdprError(f"cannot read RepRapFirmware configuration {path}: {exc}") from None
    anchors, n_anchors, kinematics, m666 = {}, None, None, []
    for lineno, line in enumerate(text.splitlines(), start=1):
        words = _words(line)
        if not words or words[0][0] != "M" or words[0][1] not in ("669", "666"):
            continue  # other G-code is not the geometry
        command = "M" + words[0][1]
        if command == "M666":
            m666.append((lineno, words[1:]))
            continue
        for letter, val in words[1:]:
            if letter == "K":
                kinematics = (lineno, val)
                if val not in ("6", "6.0"):
                    raise CdprError(
                        f"{path} line {lineno}: 'M669 K{val}': not the Hangprinter kinematics (K6)"
                    )
        for letter, val in words[1:]:
            if letter == "N":
                n_anchors = _numbers(path, lineno, command, letter, val, 1, integer=True)[0]
            elif letter in ANCHOR_LETTERS:
                anchors[letter] = _numbers(path, lineno, command, letter, val, 3)
    if kinematics is None:
        raise CdprError(f"{path}: no 'M669 K6' line (RepRapFirmware's Hangprinter kinematics)")
    n = n_anchors or 4
    if not 3 <= n <= len(ANCHOR_LETTERS):
        raise CdprError(f"{path}: 'M669 N{n}': a Hangprinter has 3 to {len(ANCHOR_LETTERS)} anchors")
    letters = ANCHOR_LETTERS[:n]
    missing = [c for c in letters if c not in anchors]
    if missing:
        raise CdprError(
            f"{path}: M669 gives no anchor {', '.join(missing)} (x:y:z in mm, e.g. 'M669 K6 A0:-1600:-120')"
        )
    given = {}
    for lineno, words in m666:
        for letter, val in words:
            if letter in ("Q", "W", "S"):
                v = _numbers(path, lineno, "M666", letter, val, 1)[0]
                if v < 0 or (v == 0 and letter == "S"):
                    raise CdprError(
                        f"{path} line {lineno}: 'M666 {letter}{val}': must be {'> 0' if letter == 'S' else '>= 0'}"
                    )
                given[letter] = v
            elif letter in ("R", "X", "Y"):
                v = _numbers(path, lineno, "M666", letter, val, n)
                if any(x < 0 or (x == 0 and letter != "Y") for x in v):
                    raise CdprError(
                        f"{path} line {lineno}: 'M666 {letter}{val}': must be {'>= 0' if letter == 'Y' else '> 0'}"
                    )
                given[letter] = v
            elif letter in ("U", "O", "L", "H"):
                given[letter] = _numbers(path, lineno, "M666", letter, val, n, integer=True)
    return {"anchors_mm": [anchors[c] for c in letters], "given": given}


def robot_dict_from_rrf(path, name=None):
    """A robot file's mapping (``cdpr.robot`` keys, SI) from a RepRapFirmware configuration, and
    the values it assumed.

    Parameters
    ----------
    path : str or Path
        The configuration (``parse_rrf``).
    name : str, optional
        The robot's name (default: the file's stem).

    Returns
    -------
    data : dict
        The robot file's mapping: platform (W), cable (E = S / area of a ``LINE_DIAMETER_M`` line,
        max_tension_N = X), fixed pulleys, a spool per cable (R, Q, U, O, L, H), dead lengths
        Y / U, one cable per anchor (mm -> m).
    assumed : list of str
        One phrase per value that did not come from the configuration.
    """
    parsed = parse_rrf(path)
    anchors, given = parsed["anchors_mm"], parsed["given"]
    n = len(anchors)
    assumed = []

    def value(letter, per_anchor, what):
        if letter in given:
            return given[letter]
        d = RRF_DEFAULTS[letter]
        v = list(d[:n]) if isinstance(d, tuple) else ([d] * n if per_anchor else d)
        shown = ":".join(f"{x:g}" for x in v) if per_anchor else f"{v:g}"
        assumed.append(f"{what} M666 {letter}{shown} (RepRapFirmware's default)")
        return v

    Q = value("Q", False, "buildup factor")
    R = value("R", True, "spool radii")
    U = value("U", True, "mechanical advantage")
    O = value("O", True, "lines per spool")  # noqa: E741  (the firmware's letter)
    L = value("L", True, "motor gear teeth")
    H = value("H", True, "spool gear teeth")
    S = value("S", False, "line stiffness per unit length")
    X = value("X", True, "maximum planned force")
    if given.get("W", 0.0) > 0:
        mass = given["W"]
    else:
        mass = DEFAULT_MASS_KG
        assumed.append(f"mover mass {mass:g} kg (M666 W {'is 0' if 'W' in given else 'absent'})")
    if "Y" in given:
        guy = given["Y"]
    else:  # RepRapFirmware's default: every spool at the last (top) anchor
        top = anchors[-1]
        guy = [math.dist(a, top) for a in anchors[:-1]] + [0.0]
        assumed.append(
            "guy-wire lengths M666 Y" + ":".join(f"{g:.1f}" for g in guy) + " (RepRapFirmware's default: "
            "spools at the top anchor, |A_i - D|)"
        )
    assumed.append(f"line diameter {LINE_DIAMETER_M * 1e3:g} mm (only E S = M666 S enters the model)")
    area = math.pi * LINE_DIAMETER_M**2 / 4.0
    cables = []
    for i, a in enumerate(anchors):
        cab = {
            "A_m": [round(x / 1000.0, 9) for x in a],
            "dead_length_m": round(guy[i] / 1000.0 / U[i], 9),
            "winch": {
                "spool_radius_m": round(R[i] / 1000.0, 9),
                "mechanical_advantage": int(U[i]),
                "lines_per_spool": int(O[i]),
                "motor_gear_teeth": int(L[i]),
                "spool_gear_teeth": int(H[i]),
            },
        }
        if X[i] != X[0]:
            cab["cable"] = {"max_tension_N": float(X[i])}
        cables.append(cab)
    data = {
        "name": name or Path(str(path)).stem,
        "description": f"Hangprinter imported from {Path(str(path)).name} (RepRapFirmware M669 K6 / M666)",
        "platform": {"mass_kg": float(mass), "gravity_m_per_s2": 9.81},
        "cable": {
            "young_modulus_Pa": float(S / area),
            "diameter_m": LINE_DIAMETER_M,
            "max_tension_N": float(X[0]),
        },
        "pulley": {"kind": "fixed"},
        "winch": {"kind": "spool", "buildup_factor_m": float(Q) / 1000.0},
        "cables": cables,
    }
    return data, assumed


def _per_anchor(values, fmt):
    return ":".join(fmt.format(v) for v in values)


def check_hangprinter(robot, what):
    """Refuse a robot that a Hangprinter firmware cannot describe: not a point mass, pulleys other
    than fixed, a cable without a spool, fewer than 3 or more than 5 cables.

    Parameters
    ----------
    robot : Robot
    what : str
        The export's name, for the message.

    Raises
    ------
    CdprError
    """
    problems = []
    if not robot.point_mass:
        problems.append("its platform is not a point mass")
    if any(c.pulley.kind != "fixed" and (c.pulley.h or c.pulley.r_p) for c in robot.cables):
        problems.append("its pulleys are not fixed points")
    if any(c.spool is None for c in robot.cables):
        problems.append("not every cable has a spool winch (winch: {kind: spool, ...})")
    if not 3 <= robot.m <= len(ANCHOR_LETTERS):
        problems.append(f"it has {robot.m} cables (a Hangprinter has 3 to {len(ANCHOR_LETTERS)})")
    if problems:
        raise CdprError(f"{robot.source}: {what} needs a Hangprinter robot: " + "; ".join(problems))


def rrf_lines(robot):
    """RepRapFirmware's ``M669`` and ``M666`` lines of a Hangprinter robot, and the warnings of the
    export.

    RepRapFirmware has one buildup factor per machine (``M666 Q``): a robot with a buildup factor
    per cable (a per-cable fit) is exported with their mean and a warning; likewise the line's E A
    (``M666 S``, the cable's E S / U). Guy-wire lengths Y = d_i U_i.

    Parameters
    ----------
    robot : Robot
        A Hangprinter (``check_hangprinter``).

    Returns
    -------
    lines : list of str
        ``M669 K6 A.. B.. ..`` (anchors, mm) and ``M666 Q.. R.. U.. O.. L.. H.. W.. S.. X.. Y..``.
    warnings : list of str
    """
    check_hangprinter(robot, "export rrf")
    sp = robot.spools
    letters = ANCHOR_LETTERS[: robot.m]
    warnings = []
    Q = [p.Q * 1000.0 for p in sp]
    q = sum(Q) / len(Q)
    if max(Q) - min(Q) > 1e-12 * max(1.0, abs(q)):
        warnings.append(
            "RepRapFirmware has one buildup factor per machine: M666 Q is the mean "
            f"{q:.6g} mm of the cables' {', '.join(f'{x:.6g}' for x in Q)} mm"
        )
    ea = [c.material.E * c.material.S for c in robot.cables]
    s = sum(ea) / len(ea)
    if max(ea) - min(ea) > 1e-9 * s:
        warnings.append(
            f"RepRapFirmware has one line stiffness: M666 S is the mean {s:.6g} N of the lines' "
            + ", ".join(f"{x:.6g}" for x in ea)
            + " N"
        )
    anchors = " ".join(
        f"{c}{_per_anchor([x * 1000.0 for x in cab.A], '{:.3f}')}" for c, cab in zip(letters, robot.cables)
    )
    m669 = f"M669 K6 N{robot.m} {anchors}" if robot.m != 4 else f"M669 K6 {anchors}"
    m666 = " ".join(
        [
            "M666",
            f"Q{q:.6f}",
            "R" + _per_anchor([p.r0 * 1000.0 for p in sp], "{:.3f}"),
            "U" + _per_anchor([p.U for p in sp], "{:d}"),
            "O" + _per_anchor([p.lines_per_spool for p in sp], "{:d}"),
            "L" + _per_anchor([p.motor_teeth for p in sp], "{:d}"),
            "H" + _per_anchor([p.spool_teeth for p in sp], "{:d}"),
            f"W{robot.platform.mass:.3f}",
            f"S{s:.2f}",
            "X" + _per_anchor([c.material.T_a for c in robot.cables], "{:.1f}"),
            "Y" + _per_anchor([c.dead_length * p.U * 1000.0 for c, p in zip(robot.cables, sp)], "{:.3f}"),
        ]
    )
    return [m669, m666], warnings


def klipper_text(robot):
    """Klipper's ``[printer] kinematics: winch`` section and ``anchor_x/y/z`` (mm) of each
    ``[stepper_a..]`` of a Hangprinter robot, and the warnings of the export.

    Klipper's winch kinematics moves each stepper by the anchor-mover distance with a constant
    ``rotation_distance`` (mm of that distance per motor turn): it has no spool buildup model. The
    value written is the one at the origin, 2 pi r0 L / (H U) (the spool's radius r0 there).

    Parameters
    ----------
    robot : Robot
        A Hangprinter (``check_hangprinter``).

    Returns
    -------
    text : str
        The configuration sections.
    warnings : list of str
    """
    check_hangprinter(robot, "export klipper")
    out = [
        "# Hangprinter geometry written by `cdpr export klipper` (Klipper's winch kinematics).",
        "# Klipper has no spool buildup model: rotation_distance is exact at the origin only.",
        "[printer]",
        "kinematics: winch",
        "",
    ]
    warnings = []
    if any(p.Q > 0 for p in robot.spools):
        warnings.append(
            "Klipper's winch kinematics has no spool buildup model: the buildup factor is not exported "
            "(rotation_distance is exact at the origin only)"
        )
    for i, (cab, p) in enumerate(zip(robot.cables, robot.spools)):
        rd = 2.0 * math.pi * p.r0 * 1000.0 * p.motor_teeth / (p.spool_teeth * p.U)
        out += [
            f"[stepper_{chr(ord('a') + i)}]",
            f"rotation_distance: {rd:.6f}",
            f"anchor_x: {cab.A[0] * 1000.0:.3f}",
            f"anchor_y: {cab.A[1] * 1000.0:.3f}",
            f"anchor_z: {cab.A[2] * 1000.0:.3f}",
            "",
        ]
    return "\n".join(out), warnings
