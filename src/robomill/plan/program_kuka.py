"""The planned cuts as a KUKA KRL program [KUKA System Software 8, *Programming*]: a ``.dat``
file with the tool frame, the base (work object) frame, one ``E6AXIS`` joint target and one
``E6POS`` Cartesian target (in the base frame of the work object, with its Status and Turn)
per move target, and a ``.src`` file that per cut moves to the start configuration by ``PTP``,
sets the spindle speed through the one subprogram ``SetSpindle`` (which the lab maps to its
I/O), plunges, feeds along the stations by ``LIN`` at the planned feed (``$VEL.CP`` [m/s])
and retracts.

Status S (bits 2 1 0): wrist− · down · back of :func:`robomill.plan.feasible.configuration`;
Turn T: bit j set when joint j+1's angle is negative.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from robomill.plan.program import PROGRAM_NAME, SPINDLE_PROC, ProgramCell, zyx_abc_deg


def _num(x: float) -> str:
    return f"{round(float(x), 6) + 0.0:.6f}".rstrip("0").rstrip(".")  # no "-0"


def _frame(pos, R) -> str:
    a, b, c = zyx_abc_deg(R)
    return (f"{{X {_num(pos[0])},Y {_num(pos[1])},Z {_num(pos[2])},A {_num(a)},B {_num(b)},"
            f"C {_num(c)}}}")


def status_turn(q_deg, code: int) -> tuple[str, str]:
    """KRL Status and Turn as binary literals ('B010', 'B000101')."""
    code = int(code)
    s = ((code & 1) << 2) | (code & 2) | ((code >> 2) & 1)
    t = sum(1 << j for j, v in enumerate(q_deg) if v < 0)
    return f"'B{s:03b}'", f"'B{t:06b}'"


def _name(cut: str, k: int, move: str) -> str:
    tag = {"approach": "APP", "retract": "RET"}.get(move, f"S{k:02d}")
    return f"{cut.upper()}_{tag}"


def krl_files(paths: Sequence, pc: ProgramCell, *, header: str) -> tuple[str, str]:
    """(``.src``, ``.dat``) text of the runnable :class:`robomill.plan.cutpath.CutPath`
    objects."""
    dat = ["&ACCESS RVP", f"DEFDAT {PROGRAM_NAME} PUBLIC"]
    dat += [f"; {line}" for line in header.splitlines()]
    dat.append(f"; robot {pc.robot_name}; targets in the base frame F_PART [mm, deg: "
               "R = Rz(A) Ry(B) Rx(C)]; joint angles of the robot model [deg]")
    dat.append(f"DECL FRAME F_SPINDLE={_frame(pc.tool_mm, pc.tool_R)}")
    dat.append(f"DECL FRAME F_PART={_frame(pc.T_base_part[:3, 3], pc.T_base_part[:3, :3])}")
    src = ["&ACCESS RVP", f"DEF {PROGRAM_NAME}()"]
    src += [f"  ; {line}" for line in header.splitlines()]
    src += ["  BAS(#INITMOV,0)", "  $TOOL=F_SPINDLE", "  $BASE=F_PART"]
    for p in paths:
        st = p.stations
        code = int(p.summary.get("configuration_code", 0))
        names = [_name(p.cut, k - 1, m) for k, m in enumerate(st["move"])]
        for name, (_, r) in zip(names, st.iterrows(), strict=True):
            q = [float(r[f"q{j}_deg"]) for j in range(1, 7)]
            dat.append(f"DECL E6AXIS XJ_{name}={{" + ",".join(
                f"A{j + 1} {_num(v)}" for j, v in enumerate(q))
                + ",E1 0,E2 0,E3 0,E4 0,E5 0,E6 0}")
            R = _quat_matrix([r["qw_part"], r["qx_part"], r["qy_part"], r["qz_part"]])
            a, b, c = zyx_abc_deg(R)
            s, t = status_turn(q, code)
            dat.append(f"DECL E6POS XP_{name}={{X {_num(r['x_part_mm'])},Y {_num(r['y_part_mm'])},"
                       f"Z {_num(r['z_part_mm'])},A {_num(a)},B {_num(b)},C {_num(c)},"
                       f"S {s},T {t},E1 0,E2 0,E3 0,E4 0,E5 0,E6 0}}")
        src.append(f"  ; {p.cut}: configuration {p.summary.get('configuration', '')}; rotation "
                   f"about the tool axis per station {p.summary.get('rotation_path_deg', '')}")
        src.append(f"  PTP XJ_{names[0]}")
        src.append(f"  {SPINDLE_PROC}({_num(p.spindle_rpm)})")
        src.append(f"  $VEL.CP={_num(p.feed_mm_s / 1000.0)}")
        for name, move in zip(names[1:], st["move"].iloc[1:], strict=True):
            if move == "retract":
                src.append("  $VEL.CP=0.1")
            src.append(f"  LIN XP_{name}")
        src.append(f"  {SPINDLE_PROC}(0)")
    src += ["END", "", f"DEF {SPINDLE_PROC}(RPM:IN)", "  REAL RPM",
            "  ; the lab maps this to its spindle I/O (e.g. $ANOUT[1]=RPM/24000) and waits "
            "until the spindle runs at speed", "END"]
    dat.append("ENDDAT")
    return "\n".join(src) + "\n", "\n".join(dat) + "\n"


def _quat_matrix(q) -> np.ndarray:
    """Rotation matrix of a unit quaternion [w, x, y, z]."""
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])
