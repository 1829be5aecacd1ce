"""The experiment plan (thesis §2.1): sets × segments × directions, and derived cut quantities.

A cut is identified by ``s{set}_g{segment}_{dir}`` with ``dir`` in ``px, py, my``
(+X, +Y, −Y). Each U-shaped segment is cut in the order +Y, +X, −Y.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass

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


def cuts_table(cuts: Sequence[Cut], spindle_rpm: float, flutes: int) -> pd.DataFrame:
    """The experiment plan as a table, with feed per tooth [µm] and tooth-passing frequency."""
    df = pd.DataFrame([c.as_dict() for c in cuts])
    df["feed_per_tooth_um"] = [
        1e3 * feed_per_tooth_mm(v, spindle_rpm, flutes) for v in df["feed_mm_s"]
    ]
    df["spindle_hz"] = spindle_hz(spindle_rpm)
    df["tooth_passing_hz"] = tooth_passing_hz(spindle_rpm, flutes)
    df = df.rename(columns={"id": "cut"})
    return df
