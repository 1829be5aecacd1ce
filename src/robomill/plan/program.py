"""The planned cuts as a controller program (``results/plan/next/program/``): the orientation
conventions both controllers use, the tool and work-object data, and the dispatch to the
cell's ``robot.controller`` (:mod:`robomill.plan.program_abb`, RAPID;
:mod:`robomill.plan.program_kuka`, KRL), beside ``stations.csv``.

Orientations: ABB writes a rotation as the unit quaternion [q1, q2, q3, q4] = [w, x, y, z]
with w ≥ 0 [ABB RAPID reference, *orient*]; KUKA as the angles A, B, C of
R = Rz(A) Ry(B) Rx(C) (Z-Y'-X'' Euler) [KUKA System Software 8, *Frames*]. Joint angles,
the tool data and the configuration data are the controller's (the cell's
``controller_frames``, :mod:`robomill.plan.controller`); the motion around each cut is
:mod:`robomill.plan.motion`'s and the spindle is driven through the cell's ``spindle``
interface (:mod:`robomill.io.controller`), or the program stops for the operator before the
first cut. ``docs/usage.md`` reads one program of each kind line by line.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

PROGRAM_NAME = "robomill_plan"
"""Module (RAPID) and program (KRL) name."""

MOVES = ("safe_in", "approach", "entry", "cut", "retract", "safe_out")
"""The kinds of move target of ``stations.csv``, in the order a cut runs them."""


def quaternion_wxyz(R: np.ndarray) -> np.ndarray:
    """Unit quaternion [w, x, y, z] of a rotation matrix, w ≥ 0 (Shepperd's method, the
    largest of the four diagonal combinations for accuracy [Shepperd 1978]); for a half turn
    (w = 0) the first non-zero of x, y, z is positive, so one orientation is written one way."""
    R = np.asarray(R, float)
    tr = np.trace(R)
    d = np.array([tr, R[0, 0], R[1, 1], R[2, 2]])
    k = int(np.argmax(d))
    if k == 0:
        w = 0.5 * np.sqrt(1.0 + tr)
        q = np.array([w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w),
                      (R[1, 0] - R[0, 1]) / (4 * w)])
    else:
        i, j, m = (k - 1, k % 3, (k + 1) % 3)
        v = np.zeros(3)
        v[i] = 0.5 * np.sqrt(1.0 + R[i, i] - R[j, j] - R[m, m])
        v[j] = (R[j, i] + R[i, j]) / (4 * v[i])
        v[m] = (R[m, i] + R[i, m]) / (4 * v[i])
        w = (R[m, j] - R[j, m]) / (4 * v[i])
        q = np.array([w, *v])
    q = q / np.linalg.norm(q)
    if abs(q[0]) < 1e-12:        # a half turn: w = 0, the first non-zero of x, y, z made > 0
        q[0] = 0.0
        lead = q[1:][np.abs(q[1:]) > 1e-12]
        return -q if lead.size and lead[0] < 0 else q
    return -q if q[0] < 0 else q


def zyx_abc_deg(R: np.ndarray) -> np.ndarray:
    """KUKA angles [A, B, C] [deg] with R = Rz(A) Ry(B) Rx(C) (B in [−90°, 90°]); at
    B = ±90° (x along ∓z, where only A ∓ C is defined) C = 0 and A from the y column."""
    R = np.asarray(R, float)
    B = np.arctan2(-R[2, 0], np.hypot(R[0, 0], R[1, 0]))
    if np.hypot(R[0, 0], R[1, 0]) < 1e-9:
        return np.rad2deg([np.arctan2(-R[0, 1], R[1, 1]), B, 0.0])
    A = np.arctan2(R[1, 0], R[0, 0])
    C = np.arctan2(R[2, 1], R[2, 2])
    return np.rad2deg([A, B, C])


@dataclass(frozen=True)
class ProgramCell:
    """What a program states about the cell: the robot model and the controller's
    conventions (:mod:`robomill.plan.controller`), the work object's frame in the base frame
    (4×4), the tool's mass and centre of mass (base frame, model's zero posture), the
    spindle's interface, the motion settings and the home posture (model angles)."""

    robot: Any
    T_base_part: np.ndarray
    tool_mass_kg: float
    tool_com_base_mm: np.ndarray
    frames: Any
    spindle: Any = None
    motion: Any = None
    home_model_deg: np.ndarray | None = None
    plan_name: str = "plan"

    @property
    def robot_name(self) -> str:
        return self.robot.name


def program_cell(robot, T_base_part: np.ndarray, mass_model=None, *, frames=None,
                 spindle=None, motion=None, q_home_deg=None, plan_name: str = "plan"
                 ) -> ProgramCell:
    """The program's view of the cell; the tool's load from ``mass_model.tool``, else 1 kg at
    the tool point (stated in the program as assumed); ``frames`` the cell's
    ``controller_frames`` (None: the model's, :func:`robomill.io.controller.model_frames`);
    home: ``motion.home_deg`` (controller angles), else ``q_home_deg`` (model angles)."""
    from robomill.io.controller import model_frames
    from robomill.plan.motion import Motion

    frames = frames or model_frames(robot.n_joints)
    motion = motion or Motion()
    mass, com = 1.0, robot.fk(np.zeros(robot.n_joints))[:3, 3]
    if mass_model is not None and getattr(mass_model, "tool", None) is not None:
        mass = float(mass_model.tool.mass_kg)
        com = np.asarray(mass_model.tool.com_mm, float)
    if motion.home_deg is not None:
        home = frames.model_deg(np.asarray(motion.home_deg, float))
    else:
        home = None if q_home_deg is None else np.asarray(q_home_deg, float)
    return ProgramCell(robot, np.asarray(T_base_part, float), max(mass, 1e-3),
                       np.asarray(com, float), frames, spindle, motion, home, plan_name)


def spindle_rpm_int(rpm: float) -> int:
    """The speed the program commands: the planned speed rounded to a whole rpm."""
    return int(round(float(rpm)))


def write_program(paths: Sequence, controller: str | None, pcell: ProgramCell, out_dir,
                  *, header: str) -> list[Path]:
    """Write ``stations.csv`` and the controller program of the planned cuts'
    :class:`robomill.plan.cutpath.CutPath` objects (refused cuts are left out) into
    ``out_dir``; the files written. No controller: only ``stations.csv``."""
    from robomill.io.artefacts import write_table

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    runnable = [p for p in paths if p.refused is None]
    st = (pd.concat([p.stations for p in runnable], ignore_index=True) if runnable
          else pd.DataFrame(columns=["cut", "move"]))
    written = [write_table(st, out_dir / "stations.csv")]
    if controller == "abb":
        from robomill.plan.program_abb import rapid_module

        f = out_dir / f"{PROGRAM_NAME}.mod"
        f.write_text(rapid_module(runnable, pcell, header=header))
        written.append(f)
    elif controller == "kuka":
        from robomill.plan.program_kuka import krl_files

        src, dat = krl_files(runnable, pcell, header=header)
        for ext, text in (("src", src), ("dat", dat)):
            f = out_dir / f"{PROGRAM_NAME}.{ext}"
            f.write_text(text)
            written.append(f)
    return written
