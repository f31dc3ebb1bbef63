"""The winch figure of Métillon et al. 2022 (Fig. 7): the drum angle's two roots and the length error
along the cable length (the study's ``winch`` part).
"""

from __future__ import annotations

import matplotlib.pyplot as plt

from cdpr.pipeline.plots.style import OKABE_ITO, save


def fig7_winch(df, l_pm0, q0, out, mode=None):
    """Métillon 2022 Fig. 7: (a) the two roots q1, q2 of the drum angle versus the length l_pm and
    the angle without the winch model, and (b) the length error δl = k_w (q1 - q_nw). The figure's
    point: q1, not q2, passes through the initial point (l_pm0, q0). ``df`` has columns l_pm, q1,
    q2, q_nw, dl. One cable: the same in both redundancy modes (the title says so)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.4), layout="constrained")
    a.plot(df.l_pm, df.q1, color=OKABE_ITO[0], label="q1 (winch model, physical root)")
    a.plot(df.l_pm, df.q2, color=OKABE_ITO[1], ls="-.", label="q2 (winch model, other root)")
    a.plot(df.l_pm, df.q_nw, "--", color="0.3", label="q_nw (winch neglected)")
    a.plot([l_pm0], [q0], "ko", label=f"initial point (l_pm0 = {l_pm0:.3f} m, q0 = {q0:g} rad)")
    a.set(xlabel="cable length l_pm [m]", ylabel="drum angle q [rad]", title="(a) drum angle (Fig. 7a)")
    a.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    a.grid(alpha=0.3)
    b.plot(df.l_pm, df.dl * 1e3, "k-", label="δl = k_w (q1 - q_nw)")
    b.axvline(l_pm0, color="0.5", ls=":", label=f"l_pm0 = {l_pm0:.3f} m")
    b.axhline(0.0, color="0.7", lw=0.8)
    b.set(xlabel="cable length l_pm [m]", ylabel="length error δl [mm]", title="(b) length error (Fig. 7b)")
    b.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2, frameon=False)
    b.grid(alpha=0.3)
    fig.suptitle(
        "Winch exit point (Métillon 2022): one cable, the same in paper rule and physical modes", fontsize=10
    )
    return save(fig, out)
