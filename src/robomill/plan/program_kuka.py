"""The planned cuts as a KUKA KRL program [KUKA System Software 8, *Programming*]: a ``.dat``
file with the tool frame (in ``$FLANGE``, x along the spindle axis: the default tool
direction), the base (work object) frame, the home axis target, one ``E6AXIS`` joint target
and one ``E6POS`` Cartesian target (in the base frame of the work object, with its Status and
Turn from the angles as printed) per move target; and a ``.src`` file that sets the motion
defaults (``BAS(#INITMOV,0)``, then the PTP velocity and acceleration, ``$VEL.CP``,
``$ACC.CP``, ``$APO.CDIS``), the tool, base and load (``$LOAD``), and runs
:mod:`robomill.plan.motion`'s moves: home by ``PTP``, per cut a ``PTP`` to the safe point
(exact stop: the spindle is set there), the approach, the entry ramp and the cut by
``LIN ... C_DIS`` at the feed (``$VEL.CP`` [m/s]) in the cut zone, the retract along the
tool axis and the safe point over the end, and home. The spindle is driven by the cell's
``$ANOUT``/``$OUT``/``$IN`` (``WAIT FOR`` ready and/or ``WAIT SEC`` run-up; stopped at the
end), each after a ``WAIT SEC 0`` that stops the advance run so that the outputs switch when
the robot stands where they belong; or the program ``HALT``\\ s with the operator's
instruction before the first cut.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from robomill.plan.controller import (
    cog_in_flange,
    kuka_status_turn,
    printed,
    tcp_turn,
    tool_in_flange,
)
from robomill.plan.program import PROGRAM_NAME, ProgramCell, spindle_rpm_int, zyx_abc_deg

TAG = {"safe_in": "SIN", "approach": "APP", "retract": "RET", "safe_out": "SOUT"}


def _num(x: float) -> str:
    return f"{float(printed(x)):.6f}".rstrip("0").rstrip(".")


def _frame(pos, R) -> str:
    a, b, c = zyx_abc_deg(R)
    return (f"{{X {_num(pos[0])},Y {_num(pos[1])},Z {_num(pos[2])},A {_num(a)},B {_num(b)},"
            f"C {_num(c)}}}")


def _axes(q) -> str:
    return ("{" + ",".join(f"A{j + 1} {_num(v)}" for j, v in enumerate(q))
            + ",E1 0,E2 0,E3 0,E4 0,E5 0,E6 0}")


def target_names(cut: str, moves) -> list[str]:
    """Target names of a cut's moves (``PLAN_01_SIN``, ``_APP``, ``_E00``, ``_S00`` …)."""
    out, k = [], {"entry": 0, "cut": 0}
    for m in moves:
        if m in k:
            out.append(f"{cut.upper()}_{m[0].upper()}{k[m]:02d}")
            k[m] += 1
        else:
            out.append(f"{cut.upper()}_{TAG[m]}")
    return out


def _spindle(pc: ProgramCell, rpm: int, first: bool) -> list[str]:
    sp = pc.spindle
    if sp is None or not sp.wired:
        return [f"  ; operator: set the spindle to {rpm} rpm"
                + (" and start it" if first else "") + ", then restart the program",
                "  HALT"]
    out = ["  WAIT SEC 0"]            # stop the advance run: the I/O after the robot stands
    if sp.speed is not None:
        out.append(f"  $ANOUT[{sp.speed}]={_num(rpm * sp.speed_per_rpm)}")
    if first:
        out.append(f"  $OUT[{sp.start}]=TRUE")
    if sp.ready is not None:
        out.append(f"  WAIT FOR $IN[{sp.ready}]")
    if sp.runup_s is not None:
        out.append(f"  WAIT SEC {_num(sp.runup_s)}")
    return out


def krl_files(paths: Sequence, pc: ProgramCell, *, header: str) -> tuple[str, str]:
    """(``.src``, ``.dat``) text of the runnable :class:`robomill.plan.cutpath.CutPath`
    objects."""
    robot, fr, mo = pc.robot, pc.frames, pc.motion
    T_tool = tool_in_flange(robot, fr, "kuka")
    cog = cog_in_flange(robot, fr, pc.tool_com_base_mm)
    turn = tcp_turn("kuka")
    dat = ["&ACCESS RVP", f"DEFDAT {PROGRAM_NAME} PUBLIC"]
    dat += [f"; {line}" for line in header.splitlines()]
    dat.append(f"; robot {pc.robot_name}; targets in the base frame F_PART [mm, deg: "
               "R = Rz(A) Ry(B) Rx(C)], tool x along the spindle axis; joint angles and tool "
               "data in the controller's frames " + ("(cell.yaml controller_frames)" if fr.stated
                                                     else "(assumed: the model's)"))
    dat.append(f"DECL FRAME F_SPINDLE={_frame(T_tool[:3, 3], T_tool[:3, :3])}")
    dat.append(f"DECL FRAME F_PART={_frame(pc.T_base_part[:3, 3], pc.T_base_part[:3, :3])}")
    if pc.home_model_deg is not None:
        dat.append(f"DECL E6AXIS XJ_HOME={_axes(fr.joints_deg(pc.home_model_deg))}")
    src = ["&ACCESS RVP", f"DEF {PROGRAM_NAME}()"]
    src += [f"  ; {line}" for line in header.splitlines()]
    src += ["  BAS(#INITMOV,0)",
            f"  BAS(#VEL_PTP,{_num(mo.joint_speed_pct)})",
            f"  BAS(#ACC_PTP,{_num(mo.joint_speed_pct)})",
            f"  $VEL.CP={_num(mo.air_speed_mm_s / 1000.0)}",
            f"  $ACC.CP={_num(mo.cp_acceleration_m_s2)}",
            f"  $APO.CDIS={_num(mo.zone_air_mm)}",
            "  $TOOL=F_SPINDLE", "  $BASE=F_PART",
            f"  $LOAD.M={_num(pc.tool_mass_kg)}",
            f"  $LOAD.CM={{X {_num(cog[0])},Y {_num(cog[1])},Z {_num(cog[2])},A 0,B 0,C 0}}",
            "  $LOAD.J={X 0,Y 0,Z 0}"]
    if pc.home_model_deg is not None:
        src.append("  PTP XJ_HOME")
    rpm_now = None
    for p in paths:
        st = p.stations
        q = st[[f"q{j}_deg" for j in range(1, 7)]].to_numpy(float)
        status, turns = kuka_status_turn(robot, fr, q)
        names = target_names(p.cut, st["move"])
        for name, (_, r), qq, s, t in zip(names, st.iterrows(), q, status, turns, strict=True):
            dat.append(f"DECL E6AXIS XJ_{name}={_axes(fr.joints_deg(qq))}")
            R = _quat_matrix([r["qw_part"], r["qx_part"], r["qy_part"], r["qz_part"]]) @ turn
            a, b, c = zyx_abc_deg(R)
            dat.append(f"DECL E6POS XP_{name}={{X {_num(r['x_part_mm'])},Y {_num(r['y_part_mm'])},"
                       f"Z {_num(r['z_part_mm'])},A {_num(a)},B {_num(b)},C {_num(c)},"
                       f"S 'B{int(s):03b}',T 'B{int(t):06b}',E1 0,E2 0,E3 0,E4 0,E5 0,E6 0}}")
        rpm = spindle_rpm_int(p.spindle_rpm)
        src.append(f"  ; {p.cut}: {rpm} rpm, feed {_num(p.feed_mm_s)} mm/s; configuration "
                   f"{p.summary.get('configuration', '')}; rotation about the tool axis per "
                   f"station {p.summary.get('rotation_path_deg', '')}")
        for name, move in zip(names, st["move"], strict=True):
            if move == "safe_in":
                src += [f"  $VEL.CP={_num(mo.air_speed_mm_s / 1000.0)}",
                        f"  $APO.CDIS={_num(mo.zone_air_mm)}", f"  PTP XP_{name}"]
                if rpm != rpm_now:
                    src += _spindle(pc, rpm, rpm_now is None)
                    rpm_now = rpm
            elif move == "entry" and name.endswith("E00"):
                src += [f"  $VEL.CP={_num(p.feed_mm_s / 1000.0)}",
                        f"  $APO.CDIS={_num(mo.zone_cut_mm)}", f"  LIN XP_{name} C_DIS"]
            elif move == "retract":
                src += [f"  $VEL.CP={_num(mo.air_speed_mm_s / 1000.0)}",
                        f"  $APO.CDIS={_num(mo.zone_air_mm)}", f"  LIN XP_{name} C_DIS"]
            else:
                src.append(f"  LIN XP_{name} C_DIS")
    if rpm_now is not None:
        sp = pc.spindle
        if sp is not None and sp.wired:
            src += ["  WAIT SEC 0", f"  $OUT[{sp.start}]=FALSE"]
            if sp.speed is not None:
                src.append(f"  $ANOUT[{sp.speed}]=0")
        else:
            src += ["  ; operator: stop the spindle, then restart the program", "  HALT"]
    if pc.home_model_deg is not None:
        src.append("  PTP XJ_HOME")
    src.append("END")
    dat.append("ENDDAT")
    return "\n".join(src) + "\n", "\n".join(dat) + "\n"


def _quat_matrix(q) -> np.ndarray:
    """Rotation matrix of a unit quaternion [w, x, y, z]."""
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
