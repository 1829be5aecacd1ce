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

DIRECTION_VECTORS = {"px": (1.0, 0.0, 0.0), "py": (0.0, 1.0, 0.0), "my": (0.0, -1.0, 0.0),
                     "mx": (-1.0, 0.0, 0.0)}
"""Unit feed direction of each named cut direction in the block frame R0 (+X, +Y, −Y, −X)."""

DIRECTION_DEG = {"px": 0.0, "py": 90.0, "mx": 180.0, "my": 270.0}
"""Feed direction angle in the base XY plane (0 = +X, counter-clockwise) of each name."""

DIRECTION_LABELS = {"px": "+X", "py": "+Y", "my": "−Y", "mx": "−X"}

CUT_ID = re.compile(r"^s(?P<set>\d+)_g(?P<segment>\d+)_(?P<direction>px|py|my)$")
"""The thesis layout's cut id ``s{set}_g{segment}_{dir}`` (checked against its fields)."""

FREE_CUT_ID = re.compile(r"^[A-Za-z0-9_.-]+$")
"""Any cut id: letters, digits, ``_``, ``.``, ``-`` (unique in the manifest)."""

MILLING = ("slot", "up", "down")
"""Milling modes: slotting (a_e = D), up (conventional) or down (climb) milling."""

CUT_PROCESS_KEYS = ("spindle_rpm", "flutes", "tool_diameter_mm", "radial_immersion", "milling",
                    "direction_deg", "start_mm", "redundancy_deg")
"""Per-cut keys that override the ``experiment`` defaults (absent = the experiment's value)."""


def cut_id(set_: int, segment: int, direction: str) -> str:
    """Cut identifier ``s{set}_g{segment}_{dir}``."""
    if direction not in DIRECTION_VECTORS:
        raise ValueError(f"direction {direction!r} is not one of {', '.join(DIRECTION_VECTORS)}")
    return f"s{int(set_)}_g{int(segment)}_{direction}"


def tracker_direction(entry: Mapping[str, Any]) -> str:
    """The direction label of a tracker run (manifest entry): its ``direction`` name, or
    ``d<deg>`` for a feed direction given as ``direction_deg`` (``d45``, ``d-30``)."""
    if entry.get("direction") is not None:
        return str(entry["direction"])
    return f"d{float(entry['direction_deg']):g}"


def tracker_run_id(direction: str, feed_mm_s: float) -> str:
    """Tracker run identifier ``<dir>_f<feed>`` (feed printed with ``%g``: ``py_f2``,
    ``my_f2.5``; ``d45_f2`` for a run along 45°)."""
    return f"{direction}_f{float(feed_mm_s):g}"


def tracker_run(entry: Mapping[str, Any]) -> str:
    """The id of a tracker run (manifest entry of kind ``tracker``): its own ``run`` key, or
    :func:`tracker_run_id` of its direction and feed. The one key that joins a run's
    artefacts (``results/straightness/runs/<run>.nc``, the ``run`` column of ``peaks.csv``
    and ``gears.csv``, the ``run`` coordinate of ``profiles.nc``) downstream of ingestion."""
    if entry.get("run") is not None:
        return str(entry["run"])
    return tracker_run_id(tracker_direction(entry), entry["feed_mm_s"])


TRACKER_PASSES = ("loaded", "air")
"""The passes of a tracker run along a cut's path (manifest key ``pass``): ``loaded`` while the
tool cuts (the default), ``air`` the same path without material. The static deflection under
the cutting force is the loaded path minus the air path
(:func:`robomill.straightness.deflection.pass_deflection_um`)."""


def tracker_pass(entry: Mapping[str, Any]) -> str:
    """The pass of a tracker run (manifest entry of kind ``tracker``): its ``pass`` key, else
    ``loaded`` (:data:`TRACKER_PASSES`)."""
    return str(entry.get("pass") or "loaded")


def tracker_pass_pairs(entries: Mapping[str, Mapping[str, Any]]) -> list[dict[str, str]]:
    """The air passes of a study's tracker runs (``run`` → manifest entry) each with the loaded
    pass of the same cut (the first listed; ``loaded_run`` "" where the cut has none): keys
    ``cut, loaded_run, air_run``."""
    loaded: dict[str, str] = {}
    for run, f in entries.items():
        if tracker_pass(f) == "loaded" and f.get("cut"):
            loaded.setdefault(str(f["cut"]), run)
    return [{"cut": str(f["cut"]), "loaded_run": loaded.get(str(f["cut"]), ""), "air_run": run}
            for run, f in entries.items() if tracker_pass(f) == "air"]


@dataclass(frozen=True)
class Cut:
    """One straight cut: its identity and process parameters.

    ``set`` and ``segment`` are optional grouping keys; ``direction`` is a name (``px``, ``mx``,
    ``py``, ``my``) or None when ``direction_deg`` gives the feed direction. The process keys
    (``spindle_rpm`` … ``start_mm``) are None when the cut takes the experiment's value
    (:func:`cut_process`). ``redundancy_deg`` is the rotation θ of the tool about its axis
    from the cell's tool orientation R0, R = R0 Rz(θ) (:func:`cut_redundancy_deg`; the
    plan's redundancy angle): None cuts at R0."""

    id: str
    set: int | None
    segment: int | None
    direction: str | None
    feed_mm_s: float
    depth_mm: float
    spindle_rpm: float | None = None
    flutes: int | None = None
    tool_diameter_mm: float | None = None
    radial_immersion: float | None = None
    milling: str | None = None
    direction_deg: float | None = None
    start_mm: tuple[float, float, float] | None = None
    redundancy_deg: float | None = None

    def as_dict(self) -> dict:
        """The manifest mapping of the cut (keys left at the experiment's value omitted)."""
        d = asdict(self)
        for k in CUT_PROCESS_KEYS:
            if d[k] is None:
                del d[k]
        if d.get("start_mm") is not None:
            d["start_mm"] = [float(x) for x in d["start_mm"]]
        return d


def cut_process(cut: Cut, experiment: Mapping[str, Any]) -> dict[str, Any]:
    """The process parameters of one cut: its own keys, else the experiment's (``spindle_rpm``,
    ``flutes``, ``tool_diameter_mm``), else the defaults (``radial_immersion`` 1 = slot,
    ``milling`` slot); ``direction_deg`` from the cut's direction name when not given.

    Returns keys ``spindle_rpm, flutes, tool_diameter_mm, radial_immersion, milling,
    direction_deg, feed_per_tooth_mm, tooth_passing_hz`` (feed per tooth c = v / (N n),
    tooth-passing frequency N n / 60)."""
    rpm = float(cut.spindle_rpm if cut.spindle_rpm is not None else experiment["spindle_rpm"])
    z = int(cut.flutes if cut.flutes is not None else experiment["flutes"])
    dia = cut.tool_diameter_mm if cut.tool_diameter_mm is not None else \
        experiment.get("tool_diameter_mm")
    ae = 1.0 if cut.radial_immersion is None else float(cut.radial_immersion)
    mode = cut.milling or ("slot" if ae >= 1.0 else "down")
    deg = (float(cut.direction_deg) if cut.direction_deg is not None
           else DIRECTION_DEG[cut.direction])
    return {"spindle_rpm": rpm, "flutes": z,
            "tool_diameter_mm": None if dia is None else float(dia),
            "radial_immersion": ae, "milling": mode, "direction_deg": deg,
            "feed_per_tooth_mm": feed_per_tooth_mm(cut.feed_mm_s, rpm, z),
            "tooth_passing_hz": tooth_passing_hz(rpm, z)}


def cut_redundancy_deg(cut: Cut) -> float:
    """The cut's rotation of the tool about its axis [deg] (0: the cell's tool orientation)."""
    return 0.0 if cut.redundancy_deg is None else float(cut.redundancy_deg)


def feed_direction(cut: Cut) -> np.ndarray:
    """Unit feed direction of a cut in the base XY plane (from ``direction`` or
    ``direction_deg``)."""
    if cut.direction_deg is None and cut.direction in DIRECTION_VECTORS:
        return np.asarray(DIRECTION_VECTORS[cut.direction], float)
    a = np.deg2rad(float(cut.direction_deg if cut.direction_deg is not None
                         else DIRECTION_DEG[cut.direction]))
    return np.array([np.cos(a), np.sin(a), 0.0])


def cut_axes(cut: Cut) -> np.ndarray:
    """The cut's frame as columns ``[u, z × u, z]``: feed direction u (:func:`feed_direction`),
    the in-plane normal to the feed (the slot wall) and the vertical tool axis (the floor)."""
    u = feed_direction(cut)
    z = np.array([0.0, 0.0, 1.0])
    return np.stack([u, np.cross(z, u), z], axis=1)


def is_thesis_design(cuts: Sequence[Cut]) -> bool:
    """Whether the cuts follow the thesis design (ids ``s{set}_g{segment}_{dir}``, directions
    px/py/my, no per-cut process overrides): the thesis-layout tables and comparisons apply."""
    return bool(cuts) and all(
        CUT_ID.match(c.id) and all(getattr(c, k) is None for k in CUT_PROCESS_KEYS)
        for c in cuts)


THESIS_PROCESS = {"spindle_rpm": 28000.0, "flutes": 2}
"""The thesis' machining process (§2.1): its numbers are for this spindle speed and tool."""


def is_thesis_study(cuts: Sequence[Cut], experiment: Mapping[str, Any]) -> bool:
    """Whether a study is the thesis' design, so that comparisons with the thesis' numbers
    (the scorecard, the chapters' "thesis: …" remarks) mean something: the cuts follow the
    thesis layout (:func:`is_thesis_design`) and the experiment's spindle speed and flutes are
    the thesis' (:data:`THESIS_PROCESS`). Someone else's data with thesis-style cut ids but
    another process is not."""
    return is_thesis_design(cuts) and all(
        experiment.get(k) is not None and float(experiment[k]) == float(v)
        for k, v in THESIS_PROCESS.items())


def spindle_hz(spindle_rpm: float) -> float:
    """Spindle rotation frequency [Hz]: 28 000 rpm → 466.7 Hz."""
    return spindle_rpm / 60.0


def tooth_passing_hz(spindle_rpm: float, flutes: int) -> float:
    """Tooth-passing frequency [Hz]: flutes × spindle frequency (933.3 Hz in the thesis)."""
    return flutes * spindle_hz(spindle_rpm)


def feed_per_tooth_mm(feed_mm_s: float, spindle_rpm: float, flutes: int) -> float:
    """Feed per tooth c = v / (N · n) [mm] ([Pulatbek 2024, §2.1]: 1.07 µm at 1 mm/s,
    28 000 rpm, 2 flutes)."""
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


def cut_endpoints_mm(cut: Cut, experiment: Mapping, set_index: int | None = None
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Start and end of a cut's TCP path in the robot base frame [mm] (slot floor).

    Layout of ``experiment.layout`` (thesis §2.1): the block frame R0 has its origin at
    ``block_origin_mm`` and axes parallel to the base axes. Segment g of set s is a U whose
    corner is at ``(margin + (g−1)·segment_pitch, margin + (s−1)·set_pitch, −depth)`` in R0;
    its cuts run +Y from the corner, then +X, then −Y, each ``cut_length_mm`` long.
    ``set_index`` overrides ``cut.set − 1`` (the row of the U). A cut with its own
    ``start_mm`` (base frame) runs from there along :func:`feed_direction`.
    """
    L = float(experiment["cut_length_mm"])
    if cut.start_mm is not None:  # a cut of any design: its own start, its own direction
        a = np.asarray(cut.start_mm, float)
        return a, a + L * feed_direction(cut)
    lay = experiment["layout"]
    s = (cut.set - 1) if set_index is None else set_index
    corner = np.array([lay["margin_mm"] + (cut.segment - 1) * lay["segment_pitch_mm"],
                       lay["margin_mm"] + s * lay["set_pitch_mm"], -cut.depth_mm])
    origin = np.asarray(lay["block_origin_mm"], float)
    start_local = {"py": corner, "px": corner + [0, L, 0], "my": corner + [L, L, 0]}
    a = origin + start_local[cut.direction]
    b = a + L * np.asarray(DIRECTION_VECTORS[cut.direction])
    return a, b


def cut_tool_rotation(cut: Cut, tool_rotation: np.ndarray) -> np.ndarray:
    """The tool's orientation while cutting ``cut``: the cell's ``tool_rotation`` R0 turned by
    the cut's redundancy angle θ about the tool axis, R0 Rz(θ) [Yi 2025, §4.2]; R0 itself
    when θ = 0."""
    theta = np.deg2rad(cut_redundancy_deg(cut))
    if theta == 0.0:
        return tool_rotation
    c, s = np.cos(theta), np.sin(theta)
    return np.asarray(tool_rotation, float) @ np.array([[c, -s, 0.0], [s, c, 0.0],
                                                        [0.0, 0.0, 1.0]])


def cut_joint_path_rad(robot: Any, cut: Cut, experiment: Mapping, s_mm: np.ndarray, *,
                       tool_rotation: np.ndarray, q0_rad: np.ndarray) -> np.ndarray:
    """Joint angles ``(len(s), n)`` along a cut at path abscissae ``s_mm`` [mm]: inverse
    kinematics of the straight TCP line of :func:`cut_endpoints_mm` at the fixed orientation
    ``tool_rotation`` turned by the cut's redundancy angle (:func:`cut_tool_rotation`), from
    the posture ``q0_rad`` (``cell.yaml: q_home_deg``)."""
    a, b = cut_endpoints_mm(cut, experiment)
    u = (b - a) / np.linalg.norm(b - a)
    P = a + np.outer(np.asarray(s_mm, float), u)
    T = np.broadcast_to(np.eye(4), (len(P), 4, 4)).copy()
    T[:, :3, :3] = cut_tool_rotation(cut, tool_rotation)
    T[:, :3, 3] = P
    return robot.ik_path(T, q0_rad)


def missing_data(files: Iterable[Mapping], cuts: Sequence[Cut], needs: Sequence[str]
                 ) -> str | None:
    """Why a chapter cannot be built from this raw folder, or None if it can.

    ``needs`` lists raw-data kinds (``profile``, ``force``, ``impact`` …; ``profile|areal`` for
    either) and/or ``cuts``; the
    reason names what the manifest lacks: ``no impact files in manifest.yaml``."""
    kinds = {f["kind"] for f in files}
    lacking = [k for k in needs
               if (not cuts if k == "cuts" else not any(a in kinds for a in k.split("|")))]
    if not lacking:
        return None
    names = ["cuts" if k == "cuts" else f"{k.replace('|', ' or ')} files" for k in lacking]
    return f"no {' and no '.join(names)} in manifest.yaml"


def cuts_table(cuts: Sequence[Cut], spindle_rpm: float, flutes: int) -> pd.DataFrame:
    """The experiment plan as a table, with feed per tooth [µm] and tooth-passing frequency
    (no rows, the same columns, for a folder without cuts)."""
    if not cuts:
        return pd.DataFrame(columns=["cut", "set", "segment", "direction", "feed_mm_s",
                                     "depth_mm", "feed_per_tooth_um", "spindle_hz",
                                     "tooth_passing_hz"])
    exp = {"spindle_rpm": spindle_rpm, "flutes": flutes}
    base = ["id", "set", "segment", "direction", "feed_mm_s", "depth_mm"]
    df = pd.DataFrame([{k: c.as_dict().get(k) for k in base} for c in cuts])
    proc = [cut_process(c, exp) for c in cuts]
    df["feed_per_tooth_um"] = [1e3 * p["feed_per_tooth_mm"] for p in proc]
    df["spindle_hz"] = [spindle_hz(p["spindle_rpm"]) for p in proc]
    df["tooth_passing_hz"] = [p["tooth_passing_hz"] for p in proc]
    # a design beyond the thesis': the cuts' own process keys, as columns
    for key in ("spindle_rpm", "flutes", "tool_diameter_mm", "radial_immersion", "milling",
                "direction_deg"):
        if any(getattr(c, key) is not None for c in cuts):
            df[key] = [p[key] for p in proc]
    if any(c.redundancy_deg is not None for c in cuts):  # the tool's rotation about its axis
        df["redundancy_deg"] = [cut_redundancy_deg(c) for c in cuts]
    df = df.rename(columns={"id": "cut"})
    return df
