"""The planning request ``plan.yaml`` (kind ``plan``): read, validate, expand its grids.

A request states the job and what counts as acceptable:

.. code-block:: yaml

    kind: plan
    operation: {milling: slot, radial_immersion: 1.0, length_mm: 40, directions: [py, px]}
    tool: {diameter_mm: 6.0, flutes: 2}
    placement:                       # cut midpoints in the robot base frame [mm]
      box: {min_mm: [550, -150, 200], max_mm: [750, 150, 200], n: [4, 3, 1]}
      # or points_mm: [[x, y, z], ...]
    rotations_deg: {min: -60, max: 60, n: 12}    # about the tool axis (or a list)
    spindle_rpm: {min: 10000, max: 30000, n: 200}
    depth_mm: [0.1, 0.2, 0.3]
    feed_mm_s: {min: 1, max: 10, n: 4}
    constraints:                     # any may be null (not constrained)
      min_stability_margin: 0.2      # a_crit,low / depth − 1
      max_deflection_normal_um: 50
      max_deflection_axial_um: 50
      max_waviness_um: 5
      max_force_N: 200
      min_p_stable: 0.95             # probability of a stable cut (default 0.95)
      min_feed_per_tooth_mm: 0.02    # production chip loads
    stability:                       # robomill.plan.stability
      members: 24                    # bootstrap members of the stability model
      verdict_error: 0.05            # assumed rate of a wrong stable/chatter verdict
      seed: 20240601
      tool_modes:                    # modes above the impact test's band: a stated prior
        - {f_hz: [1500, 4000], zeta: [0.02, 0.06], k_N_m: [3.0e+7, 3.0e+8], shape: [1, 0, 0]}
    purpose: production              # production (largest removal rate, each cut on its own
                                     # material) | learn
    extrapolation:                   # robomill.plan.extrapolation
      max_pose_distance_mm: 150      # farther from every study cut's midpoint: extrapolated
      harmonics: 1                   # tooth-passing harmonics that must lie in the modal band
      allow: true                    # false: extrapolated candidates are not planned
    joint_limit_margin_deg: 5        # every pose this far inside the cell's joint limits
    min_wrist_angle_deg: 5           # and its wrist at least this far from the singularity
    clearance_mm: 10                 # approach and retract this far above the part
    work_object: {frame: {xyz_mm, rpy_deg}, block_mm: {min, max}}   # optional (plan.workobject)
    program: {safe_height_mm: 50, ramp_angle_deg: 3, zone_cut_mm: 0.1}  # optional (plan.motion)

The rotation grid always holds 0 (the cell's nominal tool orientation).
Directions are names (``px``, ``py``, ``mx``, ``my``) or angles in degrees in the part frame
(the work object's); a yawed work object turns them into the base frame when the request is
read (``direction_deg`` and the plan's directions are the base frame's, named
``d<angle>``). Every problem is reported as one line naming the file, the field and what was
expected (:class:`PlanRequestError`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from robomill.experiment import DIRECTION_DEG

CONSTRAINTS = ("min_stability_margin", "min_p_stable", "max_deflection_normal_um",
               "max_deflection_axial_um", "max_waviness_um", "max_force_N",
               "min_feed_per_tooth_mm")
"""Constraint keys of ``plan.yaml: constraints`` (each optional)."""

CONSTRAINT_DEFAULTS = {"min_p_stable": 0.95}
"""Constraints that hold unless the request sets them (``null``: not constrained)."""

MILLING = ("slot", "up", "down")

PURPOSES = ("production", "learn")

EXTRAPOLATION = {"max_pose_distance_mm": 150.0, "harmonics": 1, "allow": True}
"""Keys of ``plan.yaml: extrapolation`` and their values when not given
(:mod:`robomill.plan.extrapolation`)."""


class PlanRequestError(ValueError):
    """A ``plan.yaml`` that does not follow the request format (one line: file, field, what was
    expected)."""

    def __init__(self, path: str | Path, where: str, problem: str):
        self.path, self.where, self.problem = str(path), where, problem
        super().__init__(f"{path}: {where}: {problem}")


@dataclass(frozen=True)
class PlanRequest:
    """A validated request with its grids expanded."""

    path: str
    milling: str
    radial_immersion: float
    length_mm: float
    direction_deg: np.ndarray
    direction_names: tuple[str, ...]
    tool_diameter_mm: float
    flutes: int
    placements_mm: np.ndarray
    rotations_deg: np.ndarray
    spindle_rpm: np.ndarray
    depth_mm: np.ndarray
    feed_mm_s: np.ndarray
    constraints: dict[str, float | None]
    n_cuts: int = 5
    max_rotation_step_deg: float = 15.0
    path_stations: int = 5
    robot_mode_max_hz: float = 200.0
    reference_point_mm: np.ndarray | None = None
    joint_limit_margin_deg: float = 5.0
    min_wrist_angle_deg: float = 5.0
    clearance_mm: float = 10.0
    work_object: Any = None
    raw: dict[str, Any] = field(default_factory=dict)
    purpose: str = "production"
    extrapolation: dict[str, Any] = field(default_factory=lambda: dict(EXTRAPOLATION))
    motion: Any = None
    """The ``program:`` settings (:class:`robomill.plan.motion.Motion`; None: defaults)."""
    stability: Any = field(default_factory=lambda: _default_stability())
    """:class:`robomill.plan.stability.StabilitySettings` (``plan.yaml: stability``)."""

    @property
    def width_mm(self) -> float:
        """Radial width of cut a_e = (a_e/D)·D [mm]."""
        return self.radial_immersion * self.tool_diameter_mm

    def constrained(self, key: str) -> bool:
        return self.constraints.get(key) is not None


def _number(path, where: str, value, *, positive: bool = False, integer: bool = False,
            minimum: float | None = None) -> float:
    ok = isinstance(value, int | float) and not isinstance(value, bool) and np.isfinite(value)
    if ok and integer:
        ok = float(value).is_integer()
    what = "an integer" if integer else "a number"
    if positive:
        what = f"a positive {what.split(' ', 1)[1]}"
        ok = ok and value > 0
    if minimum is not None and ok and value < minimum:
        ok = False
        what = f"{what} ≥ {minimum:g}"
    if not ok:
        raise PlanRequestError(path, where, f"expected {what}, got {value!r}")
    return int(value) if integer else float(value)


def _grid(path, where: str, value, *, positive: bool = True) -> np.ndarray:
    """A list of numbers, or ``{min, max, n}`` (n evenly spaced values, ends included)."""
    if isinstance(value, list):
        if not value:
            raise PlanRequestError(path, where, "expected a non-empty list of numbers")
        vals = [_number(path, f"{where}[{i}]", v, positive=positive) for i, v in enumerate(value)]
        return np.unique(np.asarray(vals, float))
    if isinstance(value, dict):
        missing = [k for k in ("min", "max", "n") if k not in value]
        if missing:
            raise PlanRequestError(path, where, f"missing key {missing[0]!r} (expected a list "
                                   "or {min, max, n})")
        lo = _number(path, f"{where}.min", value["min"], positive=positive)
        hi = _number(path, f"{where}.max", value["max"], positive=positive)
        n = _number(path, f"{where}.n", value["n"], positive=True, integer=True)
        if hi < lo:
            raise PlanRequestError(path, f"{where}.max", f"expected ≥ min ({lo:g}), got {hi:g}")
        return np.linspace(lo, hi, n) if n > 1 else np.array([lo])
    raise PlanRequestError(path, where, f"expected a list or {{min, max, n}}, got {value!r}")


def _point(path, where: str, value) -> np.ndarray:
    if not (isinstance(value, list) and len(value) == 3):
        raise PlanRequestError(path, where, f"expected [x, y, z] in mm, got {value!r}")
    return np.array([_number(path, f"{where}[{i}]", v) for i, v in enumerate(value)])


def _placements(path, value) -> np.ndarray:
    if not isinstance(value, dict) or not ({"box", "points_mm"} & set(value)):
        raise PlanRequestError(path, "placement", "expected a mapping with 'box' "
                               "{min_mm, max_mm, n} or 'points_mm' [[x, y, z], ...]")
    if "points_mm" in value:
        pts = value["points_mm"]
        if not isinstance(pts, list) or not pts:
            raise PlanRequestError(path, "placement.points_mm", "expected a non-empty list "
                                   "of [x, y, z]")
        return np.array([_point(path, f"placement.points_mm[{i}]", p)
                         for i, p in enumerate(pts)])
    box = value["box"]
    if not isinstance(box, dict):
        raise PlanRequestError(path, "placement.box", "expected {min_mm, max_mm, n}")
    for k in ("min_mm", "max_mm", "n"):
        if k not in box:
            raise PlanRequestError(path, "placement.box", f"missing key {k!r}")
    lo = _point(path, "placement.box.min_mm", box["min_mm"])
    hi = _point(path, "placement.box.max_mm", box["max_mm"])
    n = box["n"]
    if not (isinstance(n, list) and len(n) == 3):
        raise PlanRequestError(path, "placement.box.n", f"expected [nx, ny, nz], got {n!r}")
    n = [_number(path, f"placement.box.n[{i}]", v, positive=True, integer=True)
         for i, v in enumerate(n)]
    if np.any(hi < lo):
        raise PlanRequestError(path, "placement.box.max_mm", "expected every coordinate ≥ "
                               "min_mm's")
    axes = [np.linspace(a, b, k) if k > 1 else np.array([a]) for a, b, k in zip(lo, hi, n,
                                                                                 strict=True)]
    Z, Y, X = np.meshgrid(axes[2], axes[1], axes[0], indexing="ij")
    return np.stack([X.ravel(), Y.ravel(), Z.ravel()], -1)


def _directions(path, value) -> tuple[np.ndarray, tuple[str, ...]]:
    if isinstance(value, str | int | float):
        value = [value]
    if not isinstance(value, list) or not value:
        raise PlanRequestError(path, "operation.directions", "expected a list of names "
                               f"({', '.join(DIRECTION_DEG)}) or angles in degrees")
    deg, names = [], []
    for i, d in enumerate(value):
        if isinstance(d, str):
            if d not in DIRECTION_DEG:
                raise PlanRequestError(path, f"operation.directions[{i}]", "expected one of "
                                       f"{', '.join(DIRECTION_DEG)} or an angle, got {d!r}")
            deg.append(DIRECTION_DEG[d])
            names.append(d)
        else:
            a = _number(path, f"operation.directions[{i}]", d)
            deg.append(a % 360.0)
            names.append(f"d{a:g}")
    return np.asarray(deg, float), tuple(names)


def _extrapolation(path, value) -> dict[str, Any]:
    out = dict(EXTRAPOLATION)
    if value is None:
        return out
    if not isinstance(value, dict):
        raise PlanRequestError(path, "extrapolation", "expected a mapping {"
                               f"{', '.join(EXTRAPOLATION)}}}")
    for k, v in value.items():
        where = f"extrapolation.{k}"
        if k not in EXTRAPOLATION:
            raise PlanRequestError(path, where, f"unknown field (expected one of "
                                   f"{', '.join(EXTRAPOLATION)})")
        if k == "allow":
            if not isinstance(v, bool):
                raise PlanRequestError(path, where, f"expected true or false, got {v!r}")
            out[k] = v
        elif k == "harmonics":
            out[k] = _number(path, where, v, positive=True, integer=True)
        else:
            out[k] = None if v is None else _number(path, where, v, positive=True)
    return out


def parse_request(data: Any, path: str | Path = "plan.yaml") -> PlanRequest:
    """Validate a request mapping (see the module docstring) and expand its grids."""
    if not isinstance(data, dict):
        raise PlanRequestError(path, "top level", "expected a mapping (kind: plan, ...)")
    if data.get("kind") != "plan":
        raise PlanRequestError(path, "kind", f"expected 'plan', got {data.get('kind')!r}")
    known = {"kind", "operation", "tool", "placement", "rotations_deg", "spindle_rpm",
             "depth_mm", "feed_mm_s", "constraints", "n_cuts", "max_rotation_step_deg",
             "path_stations", "robot_mode_max_hz", "reference_point_mm", "purpose",
             "extrapolation", "joint_limit_margin_deg", "min_wrist_angle_deg", "clearance_mm",
             "work_object", "program", "stability"}
    for k in data:
        if k not in known:
            raise PlanRequestError(path, str(k), f"unknown field (expected one of "
                                   f"{', '.join(sorted(known))})")
    for k in ("operation", "tool", "placement", "spindle_rpm", "depth_mm", "feed_mm_s"):
        if k not in data:
            raise PlanRequestError(path, k, "missing (a required field)")
    op, tool = data["operation"], data["tool"]
    if not isinstance(op, dict):
        raise PlanRequestError(path, "operation", "expected a mapping {milling, length_mm, "
                               "directions}")
    if not isinstance(tool, dict):
        raise PlanRequestError(path, "tool", "expected a mapping {diameter_mm, flutes}")
    milling = op.get("milling", "slot")
    if milling not in MILLING:
        raise PlanRequestError(path, "operation.milling", f"expected one of "
                               f"{', '.join(MILLING)}, got {milling!r}")
    ae = 1.0 if milling == "slot" else _number(path, "operation.radial_immersion",
                                               op.get("radial_immersion"), positive=True)
    if ae > 1:
        raise PlanRequestError(path, "operation.radial_immersion", f"expected a fraction in "
                               f"(0, 1], got {ae:g}")
    if "length_mm" not in op:
        raise PlanRequestError(path, "operation.length_mm", "missing (a required field)")
    length = _number(path, "operation.length_mm", op["length_mm"], positive=True)
    deg, names = _directions(path, op.get("directions", ["px"]))
    dia = _number(path, "tool.diameter_mm", tool.get("diameter_mm"), positive=True)
    flutes = _number(path, "tool.flutes", tool.get("flutes"), positive=True, integer=True)
    rot = _grid(path, "rotations_deg", data.get("rotations_deg", [0.0]), positive=False)
    rot = np.union1d(rot, [0.0])  # the nominal orientation is always a candidate
    cons_in = data.get("constraints") or {}
    if not isinstance(cons_in, dict):
        raise PlanRequestError(path, "constraints", "expected a mapping")
    cons: dict[str, float | None] = {}
    for k, v in cons_in.items():
        if k not in CONSTRAINTS:
            raise PlanRequestError(path, f"constraints.{k}", "unknown constraint (expected "
                                   f"one of {', '.join(CONSTRAINTS)})")
        cons[k] = None if v is None else _number(
            path, f"constraints.{k}", v,
            positive=k not in ("min_stability_margin", "min_p_stable"),
            minimum={"min_stability_margin": -1.0, "min_p_stable": 0.0}.get(k))
    for k in CONSTRAINTS:
        cons.setdefault(k, CONSTRAINT_DEFAULTS.get(k))
    if cons["min_p_stable"] is not None and not 0 <= cons["min_p_stable"] <= 1:
        raise PlanRequestError(path, "constraints.min_p_stable", "expected a probability in "
                               f"[0, 1], got {cons['min_p_stable']:g}")
    ref = data.get("reference_point_mm")
    purpose = data.get("purpose", "production")
    if purpose not in PURPOSES:
        raise PlanRequestError(path, "purpose", f"expected one of {', '.join(PURPOSES)}, got "
                               f"{purpose!r}")
    wobj = _work_object(path, data.get("work_object"))
    if wobj is not None and abs(wobj.yaw_deg) > 0:     # part-frame directions → base frame
        deg = (deg + wobj.yaw_deg) % 360.0
        names = tuple(f"d{a:g}" for a in deg)
    return PlanRequest(
        purpose=purpose, extrapolation=_extrapolation(path, data.get("extrapolation")),
        path=str(path), milling=milling, radial_immersion=ae, length_mm=length,
        direction_deg=deg, direction_names=names, tool_diameter_mm=dia, flutes=flutes,
        placements_mm=_placements(path, data["placement"]), rotations_deg=rot,
        spindle_rpm=_grid(path, "spindle_rpm", data["spindle_rpm"]),
        depth_mm=_grid(path, "depth_mm", data["depth_mm"]),
        feed_mm_s=_grid(path, "feed_mm_s", data["feed_mm_s"]), constraints=cons,
        n_cuts=_number(path, "n_cuts", data.get("n_cuts", 5), positive=True, integer=True),
        max_rotation_step_deg=_number(path, "max_rotation_step_deg",
                                      data.get("max_rotation_step_deg", 15.0), positive=True),
        path_stations=_number(path, "path_stations", data.get("path_stations", 5),
                              positive=True, integer=True),
        robot_mode_max_hz=_number(path, "robot_mode_max_hz",
                                  data.get("robot_mode_max_hz", 200.0), positive=True),
        reference_point_mm=None if ref is None else _point(path, "reference_point_mm", ref),
        joint_limit_margin_deg=_number(path, "joint_limit_margin_deg",
                                       data.get("joint_limit_margin_deg", 5.0), minimum=0.0),
        min_wrist_angle_deg=_number(path, "min_wrist_angle_deg",
                                    data.get("min_wrist_angle_deg", 5.0), minimum=0.0),
        clearance_mm=_number(path, "clearance_mm", data.get("clearance_mm", 10.0),
                             positive=True),
        work_object=wobj,
        motion=parse_motion(data.get("program"), path, PlanRequestError),
        stability=_stability(path, data.get("stability")), raw=data)


def _default_stability():
    from robomill.plan.stability import StabilitySettings

    return StabilitySettings()


def _range(path, where: str, value) -> tuple[float, float]:
    if isinstance(value, int | float) and not isinstance(value, bool):
        v = _number(path, where, value, positive=True)
        return (v, v)
    if not (isinstance(value, list) and len(value) == 2):
        raise PlanRequestError(path, where, f"expected [low, high] or a number, got {value!r}")
    lo, hi = (_number(path, f"{where}[{i}]", v, positive=True) for i, v in enumerate(value))
    if hi < lo:
        raise PlanRequestError(path, f"{where}[1]", f"expected ≥ {lo:g}, got {hi:g}")
    return (lo, hi)


def _stability(path, value):
    """``plan.yaml: stability`` as :class:`robomill.plan.stability.StabilitySettings`."""
    from robomill.plan.stability import StabilitySettings, ToolModePrior

    if value is None:
        return StabilitySettings()
    if not isinstance(value, dict):
        raise PlanRequestError(path, "stability", "expected a mapping {members, verdict_error, "
                               "seed, tool_modes}")
    for k in value:
        if k not in ("members", "verdict_error", "seed", "tool_modes"):
            raise PlanRequestError(path, f"stability.{k}", "unknown field (expected members, "
                                   "verdict_error, seed, tool_modes)")
    d = StabilitySettings()
    err = _number(path, "stability.verdict_error", value.get("verdict_error", d.verdict_error),
                  positive=True)
    if err >= 0.5:
        raise PlanRequestError(path, "stability.verdict_error", f"expected a rate below 0.5, "
                               f"got {err:g}")
    modes = value.get("tool_modes") or []
    if not isinstance(modes, list):
        raise PlanRequestError(path, "stability.tool_modes", "expected a list of {f_hz, zeta, "
                               "k_N_m, shape}")
    priors = []
    for i, m in enumerate(modes):
        where = f"stability.tool_modes[{i}]"
        if not isinstance(m, dict):
            raise PlanRequestError(path, where, "expected a mapping {f_hz, zeta, k_N_m, shape}")
        for k in ("f_hz", "zeta", "k_N_m", "shape"):
            if k not in m:
                raise PlanRequestError(path, f"{where}.{k}", "missing (a required field)")
        sh = m["shape"]
        if not (isinstance(sh, list) and len(sh) == 3):
            raise PlanRequestError(path, f"{where}.shape", f"expected [x, y, z], got {sh!r}")
        shape = tuple(_number(path, f"{where}.shape[{j}]", v) for j, v in enumerate(sh))
        if not any(shape):
            raise PlanRequestError(path, f"{where}.shape", "expected a non-zero vector")
        priors.append(ToolModePrior(_range(path, f"{where}.f_hz", m["f_hz"]),
                                    _range(path, f"{where}.zeta", m["zeta"]),
                                    _range(path, f"{where}.k_N_m", m["k_N_m"]), shape))
    return StabilitySettings(
        members=_number(path, "stability.members", value.get("members", d.members),
                        positive=True, integer=True),
        verdict_error=err,
        seed=_number(path, "stability.seed", value.get("seed", d.seed), minimum=0,
                     integer=True),
        tool_modes=tuple(priors))


def parse_motion(value, path, error):
    """``program:`` (:func:`robomill.plan.motion.parse_motion`)."""
    from robomill.plan.motion import parse_motion as parse

    return parse(value, path, error)


def _work_object(path, value):
    from robomill.plan.workobject import WorkObjectError, parse_work_object

    try:
        return None if value is None else parse_work_object(value, str(path))
    except WorkObjectError as e:
        raise PlanRequestError(path, e.where, e.problem) from None


def read_request(path: str | Path) -> PlanRequest:
    """Read and validate ``plan.yaml``."""
    path = Path(path)
    if not path.exists():
        raise PlanRequestError(path, "file", "does not exist (expected a plan request, "
                               "kind: plan)")
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark is not None else "file"
        raise PlanRequestError(path, where, "not valid YAML") from None
    return parse_request(data, path)
