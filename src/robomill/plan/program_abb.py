"""The planned cuts as an ABB RAPID module [ABB RAPID reference]: the spindle's ``tooldata``
in the ``tool0`` frame, the part's ``wobjdata``, the zones and speeds, one ``jointtarget``
and one ``robtarget`` (in the work object, with its ``confdata``) per move target, and one
routine named after the plan (``run_<first cut>_<last cut>``, not ``main``, which every
controller already has) that runs :mod:`robomill.plan.motion`'s moves: home by
``MoveAbsJ``, per cut a ``MoveJ`` to the safe point (fine: the spindle is set there), the
approach, the entry ramp and the cut by ``MoveL`` in the cut zone ``zCut``, the retract along
the tool axis and the safe point over the end, and home again. ``ConfJ``/``ConfL`` are on:
the controller keeps each target's configuration. The spindle is driven by the cell's
signals (``SetAO`` speed, ``SetDO`` start, ``WaitDI`` ready and/or ``WaitTime`` run-up;
stopped at the end), or the program writes to the operator and ``Stop``\\ s before the first
cut and at the end.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from robomill.plan.controller import abb_confdata, cog_in_flange, printed, tool_in_flange
from robomill.plan.program import ProgramCell, quaternion_wxyz, spindle_rpm_int

EXT = "[9E+09,9E+09,9E+09,9E+09,9E+09,9E+09]"
"""External axes: none."""

TAG = {"safe_in": "sin", "approach": "app", "retract": "ret", "safe_out": "sout"}


def _num(x: float) -> str:
    return (f"{float(printed(x)):.6f}".rstrip("0").rstrip(".") if np.isfinite(x) else "0")


def _vec(v) -> str:
    return "[" + ",".join(_num(x) for x in v) + "]"


def _q9(x: float) -> str:
    return f"{round(float(x), 9) + 0.0:.9f}"


def _quat(R) -> str:
    return "[" + ",".join(_q9(x) for x in quaternion_wxyz(R)) + "]"


def _zone(r: float) -> str:
    return f"[FALSE,{_num(r)},{_num(r)},{_num(r)},{_num(r / 10)},{_num(r)},{_num(r / 10)}]"


def target_names(cut: str, moves) -> list[str]:
    """Target names of a cut's moves (``plan_01_sin``, ``_app``, ``_e00``, ``_s00`` …)."""
    out, k = [], {"entry": 0, "cut": 0}
    for m in moves:
        if m in k:
            out.append(f"{cut}_{m[0]}{k[m]:02d}")
            k[m] += 1
        else:
            out.append(f"{cut}_{TAG[m]}")
    return out


def routine_name(paths: Sequence) -> str:
    """The routine's name: ``run_`` and the first and last cut's ids."""
    ids = [p.cut for p in paths] or ["none"]
    return "run_" + (ids[0] if len(ids) == 1 else f"{ids[0]}_{ids[-1].split('_')[-1]}")


def _spindle(pc: ProgramCell, rpm: int, first: bool) -> list[str]:
    sp = pc.spindle
    if sp is None or not sp.wired:
        msg = (f"Set the spindle to {rpm} rpm and start it, then press Start" if first else
               f"Set the spindle to {rpm} rpm, then press Start")
        return [f'    TPWrite "{msg}";', "    Stop;"]
    out = []
    if sp.speed is not None:
        out.append(f"    SetAO {sp.speed}, {_num(rpm * sp.speed_per_rpm)};")
    if first:
        out.append(f"    SetDO {sp.start}, 1;")
    if sp.ready is not None:
        out.append(f"    WaitDI {sp.ready}, 1;")
    if sp.runup_s is not None:
        out.append(f"    WaitTime {_num(sp.runup_s)};")
    return out


def rapid_module(paths: Sequence, pc: ProgramCell, *, header: str) -> str:
    """The RAPID module text of the runnable :class:`robomill.plan.cutpath.CutPath` objects."""
    from robomill.plan.program import PROGRAM_NAME

    robot, fr, mo = pc.robot, pc.frames, pc.motion
    T_tool = tool_in_flange(robot, fr, "abb")
    cog = cog_in_flange(robot, fr, pc.tool_com_base_mm)
    L = [f"MODULE {PROGRAM_NAME}"]
    L += [f"  ! {line}" for line in header.splitlines()]
    L.append(f"  ! robot {pc.robot_name}; targets in the work object wPart [mm, quaternion "
             "w x y z]; joint angles and tool data in the controller's frames "
             + ("(cell.yaml controller_frames)" if fr.stated else
                "(assumed: the model's, cell.yaml states no controller_frames)"))
    L.append(f"  PERS tooldata tSpindle := [TRUE,[{_vec(T_tool[:3, 3])},{_quat(T_tool[:3, :3])}],"
             f"[{_num(pc.tool_mass_kg)},{_vec(cog)},[1,0,0,0],0,0,0]];")
    L.append(f"  PERS wobjdata wPart := [FALSE,TRUE,\"\",[{_vec(pc.T_base_part[:3, 3])},"
             f"{_quat(pc.T_base_part[:3, :3])}],[[0,0,0],[1,0,0,0]]];")
    L.append(f"  CONST zonedata zCut := {_zone(mo.zone_cut_mm)};")
    L.append(f"  CONST zonedata zAir := {_zone(mo.zone_air_mm)};")
    L.append(f"  CONST speeddata vAir := [{_num(mo.air_speed_mm_s)},500,5000,1000];")
    home = pc.home_model_deg
    if home is not None:
        L.append(f"  CONST jointtarget jHome := [{_vec(fr.joints_deg(home))},{EXT}];")
    for p in paths:
        st = p.stations
        L.append(f"  CONST speeddata vFeed_{p.cut} := [{_num(p.feed_mm_s)},500,5000,1000];")
        q = st[[f"q{j}_deg" for j in range(1, 7)]].to_numpy(float)
        conf = abb_confdata(robot, fr, q)
        for name, (_, r), qq, cf in zip(target_names(p.cut, st["move"]), st.iterrows(), q, conf,
                                        strict=True):
            L.append(f"  CONST jointtarget j_{name} := [{_vec(fr.joints_deg(qq))},{EXT}];")
            pos = [r["x_part_mm"], r["y_part_mm"], r["z_part_mm"]]
            quat = [r["qw_part"], r["qx_part"], r["qy_part"], r["qz_part"]]
            L.append(f"  CONST robtarget p_{name} := [{_vec(pos)},"
                     f"[{','.join(_q9(x) for x in quat)}],[{','.join(str(int(c)) for c in cf)}],"
                     f"{EXT}];")
    L.append("")
    L.append(f"  PROC {routine_name(paths)}()")
    L.append("    ConfJ \\On;")
    L.append("    ConfL \\On;")
    if home is not None:
        L.append("    MoveAbsJ jHome,vAir,fine,tSpindle\\WObj:=wPart;")
    rpm_now = None
    for p in paths:
        st = p.stations
        names = target_names(p.cut, st["move"])
        rpm = spindle_rpm_int(p.spindle_rpm)
        L.append(f"    ! {p.cut}: {rpm} rpm, feed {_num(p.feed_mm_s)} mm/s; configuration "
                 f"{p.summary.get('configuration', '')}; rotation about the tool axis per "
                 f"station {p.summary.get('rotation_path_deg', '')} deg")
        for name, move in zip(names, st["move"], strict=True):
            if move == "safe_in":
                L.append(f"    MoveJ p_{name},vAir,fine,tSpindle\\WObj:=wPart;")
                if rpm != rpm_now:
                    L += _spindle(pc, rpm, rpm_now is None)
                    rpm_now = rpm
            elif move in ("entry", "cut"):
                L.append(f"    MoveL p_{name},vFeed_{p.cut},zCut,tSpindle\\WObj:=wPart;")
            else:
                L.append(f"    MoveL p_{name},vAir,zAir,tSpindle\\WObj:=wPart;")
    if rpm_now is not None:
        sp = pc.spindle
        if sp is not None and sp.wired:
            L.append(f"    SetDO {sp.start}, 0;")
            if sp.speed is not None:
                L.append(f"    SetAO {sp.speed}, 0;")
        else:
            L += ['    TPWrite "Stop the spindle, then press Start";', "    Stop;"]
    if home is not None:
        L.append("    MoveAbsJ jHome,vAir,fine,tSpindle\\WObj:=wPart;")
    L.append("  ENDPROC")
    L.append("ENDMODULE")
    return "\n".join(L) + "\n"
