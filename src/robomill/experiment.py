"""The experiment plan (thesis §2.1): sets × segments × directions, and derived cut quantities.

A cut is identified by ``s{set}_g{segment}_{dir}`` with ``dir`` in ``px, py, my``
(+X, +Y, −Y). Each U-shaped segment is cut in the order +Y, +X, −Y.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np
import pandas as pd

DIRECTIONS = ("py", "px", "my")
"""Cut directions in the order a U-shaped segment is machined (+Y, +X, −Y)."""

DIRECTION_VECTORS = {"px": (1.0, 0.0, 0.0), "py": (0.0, 1.0, 0.0), "my": (0.0, -1.0, 0.0)}
"""Unit feed direction of each cut in the block frame R0."""

DIRECTION_LABELS = {"px": "+X", "py": "+Y", "my": "−Y"}

CUT_ID = re.compile(r"^s(?P<set>\d+)_g(?P<segment>\d+)_(?P<direction>px|py|my)$")


def cut_id(set_: int, segment: int, direction: str) -> str:
    """Cut identifier ``s{set}_g{segment}_{dir}``."""
    if direction not in DIRECTION_VECTORS:
        raise ValueError(f"direction {direction!r} is not one of {', '.join(DIRECTION_VECTORS)}")
    return f"s{int(set_)}_g{int(segment)}_{direction}"


def tracker_run_id(direction: str, feed_mm_s: float) -> str:
    """Tracker run identifier ``<dir>_f<feed>`` (feed printed with ``%g``: ``py_f2``,
    ``my_f2.5``)."""
    return f"{direction}_f{float(feed_mm_s):g}"


@dataclass(frozen=True)
class Cut:
    """One straight cut: its identity and process parameters."""

    id: str
    set: int
    segment: int
    direction: str
    feed_mm_s: float
    depth_mm: float

    def as_dict(self) -> dict:
        return asdict(self)


def spindle_hz(spindle_rpm: float) -> float:
    """Spindle rotation frequency [Hz]: 28 000 rpm → 466.7 Hz."""
    return spindle_rpm / 60.0


def tooth_passing_hz(spindle_rpm: float, flutes: int) -> float:
    """Tooth-passing frequency [Hz]: flutes × spindle frequency (933.3 Hz in the thesis)."""
    return flutes * spindle_hz(spindle_rpm)


def feed_per_tooth_mm(feed_mm_s: float, spindle_rpm: float, flutes: int) -> float:
    """Feed per tooth c = v / (N · n) [mm] (SPEC §0: 1.07 µm at 1 mm/s, 28 000 rpm, 2 flutes)."""
    return feed_mm_s / tooth_passing_hz(spindle_rpm, flutes)


def plan_cuts(sets: Sequence[Mapping], n_sets: int | None = None,
              directions: Sequence[str] = DIRECTIONS) -> list[Cut]:
    """All cuts of the study, in machining order.

    Parameters
    ----------
    sets
        ``[{set, depth_mm, feeds_mm_s: [...]}, ...]``; segment g uses ``feeds_mm_s[g-1]``.
    n_sets
        Number of sets to plan (``synth.sets``). Beyond ``len(sets)`` the list is cycled, set
        k taking the parameters of set ``(k-1) mod len(sets) + 1``; this scales the virtual
        study without inventing new process parameters.
    directions
        Directions of each U segment, in machining order.
    """
    if n_sets is None:
        n_sets = len(sets)
    cuts = []
    for k in range(n_sets):
        spec = sets[k % len(sets)]
        set_no = int(spec["set"]) if k < len(sets) else k + 1
        for g, feed in enumerate(spec["feeds_mm_s"], start=1):
            for d in directions:
                cuts.append(Cut(cut_id(set_no, g, d), set_no, g, d, float(feed),
                                float(spec["depth_mm"])))
    return cuts


def cuts_by_set(cuts: Iterable[Cut]) -> dict[int, list[Cut]]:
    """The cuts grouped by set (one machining session of the plan), sets and cuts in the order
    given: the unit of one synthetic-instrument job."""
    sets: dict[int, list[Cut]] = {}
    for c in cuts:
        sets.setdefault(int(c.set), []).append(c)
    return sets


def cut_endpoints_mm(cut: Cut, experiment: Mapping, set_index: int | None = None
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Start and end of a cut's TCP path in the robot base frame [mm] (slot floor).

    Layout of ``experiment.layout`` (thesis §2.1): the block frame R0 has its origin at
    ``block_origin_mm`` and axes parallel to the base axes. Segment g of set s is a U whose
    corner is at ``(margin + (g−1)·segment_pitch, margin + (s−1)·set_pitch, −depth)`` in R0;
    its cuts run +Y from the corner, then +X, then −Y, each ``cut_length_mm`` long.
    ``set_index`` overrides ``cut.set − 1`` (the row of the U).
    """
    lay = experiment["layout"]
    L = float(experiment["cut_length_mm"])
    s = (cut.set - 1) if set_index is None else set_index
    corner = np.array([lay["margin_mm"] + (cut.segment - 1) * lay["segment_pitch_mm"],
                       lay["margin_mm"] + s * lay["set_pitch_mm"], -cut.depth_mm])
    origin = np.asarray(lay["block_origin_mm"], float)
    start_local = {"py": corner, "px": corner + [0, L, 0], "my": corner + [L, L, 0]}
    a = origin + start_local[cut.direction]
    b = a + L * np.asarray(DIRECTION_VECTORS[cut.direction])
    return a, b


def cut_joint_path_rad(robot: Any, cut: Cut, experiment: Mapping, s_mm: np.ndarray, *,
                       tool_rotation: np.ndarray, q0_rad: np.ndarray) -> np.ndarray:
    """Joint angles ``(len(s), n)`` along a cut at path abscissae ``s_mm`` [mm]: inverse
    kinematics of the straight TCP line of :func:`cut_endpoints_mm` at the fixed orientation
    ``tool_rotation``, from the posture ``q0_rad`` (``cell.yaml: q_home_deg``)."""
    a, b = cut_endpoints_mm(cut, experiment)
    u = (b - a) / np.linalg.norm(b - a)
    P = a + np.outer(np.asarray(s_mm, float), u)
    T = np.broadcast_to(np.eye(4), (len(P), 4, 4)).copy()
    T[:, :3, :3] = tool_rotation
    T[:, :3, 3] = P
    return robot.ik_path(T, q0_rad)


KIND_LABELS = {"profile": "profile", "force": "force", "tracker": "tracker", "impact": "impact",
               "ctrack": "ctrack", "robot": "robot", "stiffness": "stiffness"}


def missing_data(files: Iterable[Mapping], cuts: Sequence[Cut], needs: Sequence[str]
                 ) -> str | None:
    """Why a chapter cannot be built from this raw folder, or None if it can.

    ``needs`` lists raw-data kinds (``profile``, ``force``, ``impact`` …) and/or ``cuts``; the
    reason names what the manifest lacks: ``no impact files in manifest.yaml``."""
    kinds = {f["kind"] for f in files}
    lacking = [k for k in needs if (not cuts if k == "cuts" else k not in kinds)]
    if not lacking:
        return None
    names = [("cuts" if k == "cuts" else f"{KIND_LABELS.get(k, k)} files") for k in lacking]
    return f"no {' and no '.join(names)} in manifest.yaml"


def cuts_table(cuts: Sequence[Cut], spindle_rpm: float, flutes: int) -> pd.DataFrame:
    """The experiment plan as a table, with feed per tooth [µm] and tooth-passing frequency
    (no rows, the same columns, for a folder without cuts)."""
    if not cuts:
        return pd.DataFrame(columns=["cut", "set", "segment", "direction", "feed_mm_s",
                                     "depth_mm", "feed_per_tooth_um", "spindle_hz",
                                     "tooth_passing_hz"])
    df = pd.DataFrame([c.as_dict() for c in cuts])
    df["feed_per_tooth_um"] = [
        1e3 * feed_per_tooth_mm(v, spindle_rpm, flutes) for v in df["feed_mm_s"]
    ]
    df["spindle_hz"] = spindle_hz(spindle_rpm)
    df["tooth_passing_hz"] = tooth_passing_hz(spindle_rpm, flutes)
    df = df.rename(columns={"id": "cut"})
    return df
