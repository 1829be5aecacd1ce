"""The planned cuts as an ABB RAPID module [ABB RAPID reference]: the spindle's ``tooldata``,
the part's ``wobjdata``, one ``jointtarget`` and one ``robtarget`` (in the work object, with
its configuration ``confdata``) per move target, and per cut a procedure that moves to the
start configuration by ``MoveAbsJ``, sets the spindle speed through the one procedure
``SetSpindle`` (which the lab maps to its I/O), plunges, feeds along the stations by ``MoveL``
at the planned feed, and retracts.

``confdata`` [cf1, cf4, cf6, cfx]: cf1, cf4, cf6 the quadrant ⌊q/90°⌋ of joints 1, 4 and 6;
cfx the configuration code of :func:`robomill.plan.feasible.configuration` (4·back + 2·down +
wrist−, the order of ABB's cfx table).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from robomill.plan.program import SPINDLE_PROC, ProgramCell, quaternion_wxyz

EXT = "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]"
"""External axes: none."""

APPROACH_SPEED = "v100"
"""Speed of the moves in the air (the start configuration, approach, retract)."""


def _num(x: float) -> str:
    return (f"{round(float(x), 6) + 0.0:.6f}".rstrip("0").rstrip(".")  # no "-0"
            if np.isfinite(x) else "0")


def _vec(v) -> str:
    return "[" + ",".join(_num(x) for x in v) + "]"


def _q9(x: float) -> str:
    return f"{round(float(x), 9) + 0.0:.9f}"


def _quat(R) -> str:
    return "[" + ",".join(_q9(x) for x in quaternion_wxyz(R)) + "]"


def _name(cut: str, k: int, move: str) -> str:
    tag = {"approach": "app", "retract": "ret"}.get(move, f"s{k:02d}")
    return f"{cut}_{tag}"


def _conf(q_deg, code: int) -> str:
    q = np.asarray(q_deg, float)
    quad = [int(np.floor(round(q[j], 6) / 90.0)) for j in (0, 3, 5)]
    return f"[{quad[0]},{quad[1]},{quad[2]},{int(code)}]"


def rapid_module(paths: Sequence, pc: ProgramCell, *, header: str) -> str:
    """The RAPID module text of the runnable :class:`robomill.plan.cutpath.CutPath` objects."""
    from robomill.plan.program import PROGRAM_NAME

    L = [f"MODULE {PROGRAM_NAME}"]
    L += [f"  ! {line}" for line in header.splitlines()]
    L.append(f"  ! robot {pc.robot_name}; targets in the work object wPart [mm, quaternion "
             "w x y z]; joint angles of the robot model [deg]")
    L.append(f"  PERS tooldata tSpindle := [TRUE,[{_vec(pc.tool_mm)},{_quat(pc.tool_R)}],"
             f"[{_num(pc.tool_mass_kg)},{_vec(pc.tool_cog_mm)},[1,0,0,0],0,0,0]];")
    L.append(f"  PERS wobjdata wPart := [FALSE,TRUE,\"\",[{_vec(pc.T_base_part[:3, 3])},"
             f"{_quat(pc.T_base_part[:3, :3])}],[[0,0,0],[1,0,0,0]]];")
    for p in paths:
        st = p.stations
        L.append(f"  CONST speeddata vFeed_{p.cut} := [{_num(p.feed_mm_s)},500,5000,1000];")
        code = int(p.summary.get("configuration_code", 0))
        for k, (_, r) in enumerate(st.iterrows()):
            q = [r[f"q{j}_deg"] for j in range(1, 7)]
            name = _name(p.cut, k - 1, r["move"])
            L.append(f"  CONST jointtarget j_{name} := [{_vec(q)},{EXT}];")
            pos = [r["x_part_mm"], r["y_part_mm"], r["z_part_mm"]]
            quat = [r["qw_part"], r["qx_part"], r["qy_part"], r["qz_part"]]
            L.append(f"  CONST robtarget p_{name} := [{_vec(pos)},"
                     f"[{','.join(_q9(x) for x in quat)}],{_conf(q, code)},{EXT}];")
    L.append("")
    L.append(f"  PROC {SPINDLE_PROC}(num rpm)")
    L.append("    ! the lab maps this to its spindle I/O, e.g. SetAO aoSpindle, rpm; and waits "
             "until the spindle runs at speed")
    L.append("    TPWrite \"spindle rpm: \"\\Num:=rpm;")
    L.append("  ENDPROC")
    L.append("")
    L.append("  PROC main()")
    L += [f"    {p.cut};" for p in paths]
    L.append("  ENDPROC")
    for p in paths:
        st = p.stations
        L.append("")
        L.append(f"  PROC {p.cut}()")
        L.append(f"    ! configuration {p.summary.get('configuration', '')}; rotation about the "
                 f"tool axis per station {p.summary.get('rotation_path_deg', '')} deg")
        names = [_name(p.cut, k - 1, m) for k, m in enumerate(st["move"])]
        L.append(f"    MoveAbsJ j_{names[0]},{APPROACH_SPEED},fine,tSpindle\\WObj:=wPart;")
        L.append(f"    {SPINDLE_PROC} {_num(p.spindle_rpm)};")
        for name, move in zip(names[1:], st["move"].iloc[1:], strict=True):
            speed = APPROACH_SPEED if move == "retract" else f"vFeed_{p.cut}"
            L.append(f"    MoveL p_{name},{speed},fine,tSpindle\\WObj:=wPart;")
        L.append(f"    {SPINDLE_PROC} 0;")
        L.append("  ENDPROC")
    L.append("ENDMODULE")
    return "\n".join(L) + "\n"
