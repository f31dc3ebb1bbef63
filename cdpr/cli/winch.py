"""``cdpr winch``: the winch curves of Métillon et al. 2022 (Fig. 7) over a range of free lengths,
for the Table 1 winch or a winch file (``cdpr.models.winch``)."""

from __future__ import annotations

from cdpr import io
from cdpr.cli.commands import emit_json, text_table
from cdpr.errors import CdprError
from cdpr.models import winch
from cdpr.robot import TABLE1, load_winch_params


def cmd_winch(args):
    p = load_winch_params(args.params) if args.params else TABLE1
    if args.out:
        io.check_output(args.out)
    if not args.lpm_from < args.lpm_to:
        raise CdprError(f"--lpm-from must be below --lpm-to, got {args.lpm_from:g} and {args.lpm_to:g}")
    winch.check_range(p, args.lpm_from, args.lpm_to)
    # lazy: pandas, for this command only
    from cdpr import table_io
    from cdpr.analyses import scans

    df = scans.winch_table(p, args.lpm_from, args.lpm_to, args.steps)
    if args.out:
        table_io.write_table(df, args.out)
    if args.json:
        emit_json(df.to_dict(orient="records"), args)
        return
    print(f"winch (l_pm0 = {winch.l_pm0(p):.6f} m, q0 = {p.q0:g} rad)")
    rows = [
        [f"{r.l_pm:.4f}", f"{r.q1:.6f}", f"{r.q2:.6f}", f"{r.q_nw:.6f}", f"{r.dl * 1e3:.4f}"]
        for r in df.itertuples()
    ]
    print(text_table(rows, ["l_pm [m]", "q1 [rad]", "q2 [rad]", "q_nw [rad]", "dl [mm]"]))
