"""The robot cell file ``cell.yaml`` (manifest kind ``cell``): the facts of the cell.

One file per raw folder describes the cell the measurements were taken in, so that every
analysis that needs the robot reads it from the data, not from the virtual cell of the
simulators (``docs/data-contract.md``, section *The cell*)::

    robot: {name: irb1600, convention: dh, length_unit: mm, angle_unit: deg,
            joints: [{a: 150.0, alpha: -90.0, d: 486.5, theta_offset: 0.0}, ...],
            tool: {xyz_mm: [0.0, 0.0, 180.0], rpy_deg: [0.0, 0.0, 0.0]},   # or [x, y, z]
            joint_limits_deg: [[-180, 180], ...], joint_speed_limits_deg_s: [150, ...],
            controller: abb}                   # the last three optional
    q_home_deg: [0, 20, 10, 0, 60, 0]          # IK seed (the posture branch)
    tool_rotation: [[1, 0, 0], [0, -1, 0], [0, 0, -1]]   # TCP orientation while cutting
    transmissions:                             # nominal gear trains (no error amplitudes)
      - {joint: 1, stage: motor, rev_per_joint_rev: 120.0, teeth: 17}
    base_from_instrument:                      # optional, per instrument (tracker, ctrack)
      tracker: {rotation: [[1, 0, 0], [0, 1, 0], [0, 0, 1]], translation_mm: [0, 0, 0]}
    mass_model:                                # optional: point masses (manufacturer data / CAD)
      links: [{link: 1, mass_kg: 60.0, com_mm: [40.0, 0.0, 300.0]}, ...]
      tool: {mass_kg: 5.0, com_mm: [880.0, 10.0, 1186.5]}
    controller_frames:                         # optional: the controller's flange and joints
      flange: {xyz_mm: [0, 0, 0], rpy_deg: [0, 0, 180]}
    spindle: {speed: aoSpindleSpeed, start: doSpindleOn, ready: diSpindleAtSpeed}  # optional

``robot`` follows the robot-file schema of the stiffness section
(:func:`robomill.io.robots.parse_robot`); its tool frame, working range, axis speeds and
controller are those of :mod:`robomill.io.tool_frame`. ``base_from_instrument[k]``
registers instrument k's frame to the robot base:
``p_base = rotation · p_instrument + translation_mm``; an absent entry means the instrument
already measures in the base frame. ``mass_model`` places point masses on the links
(``link`` 1..n, centre of mass ``com_mm`` at the zero configuration in the base
frame) and the spindle and tool on the last link: the gravity model of the calibration's
compliance terms (chapter 1); a cell without one is calibrated without the gravity term
(``docs/data-contract.md``). Every problem raises one
:class:`~robomill.errors.RawDataError` naming the file and the key.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from robomill.errors import RawDataError
from robomill.io.controller import (
    ControllerFrames,
    SpindleInterface,
    parse_controller_frames,
    parse_spindle,
)
from robomill.io.robots import parse_robot
from robomill.kinematics import SerialRobot, reachable_joint_path_rad, robot_from_mapping

CELL_KEYS = ("robot", "q_home_deg", "tool_rotation", "transmissions", "base_from_instrument",
             "mass_model", "controller_frames", "spindle")
"""Top-level keys of ``cell.yaml`` (the last four optional; ``controller_frames`` and
``spindle``: :mod:`robomill.io.controller`)."""

MASS_KEYS = ("link", "mass_kg", "com_mm")
"""Keys of one ``mass_model.links`` entry (``mass_model.tool`` has ``mass_kg, com_mm``)."""

TRANSMISSION_KEYS = ("joint", "stage", "rev_per_joint_rev", "teeth")
"""Keys of one ``transmissions`` entry."""

INSTRUMENTS = ("tracker", "ctrack")
"""Instruments whose frame ``base_from_instrument`` may register to the robot base."""

ROTATION_TOL = 1e-6
"""Largest ``|RᵀR − I|`` entry and ``|det R − 1|`` accepted for a rotation matrix."""


@dataclass(frozen=True)
class Transmission:
    """One rotating element of a joint's gear train (nominal: no error amplitudes).

    ``rev_per_joint_rev`` revolutions of this element per joint revolution and its tooth
    count ``teeth``: it turns ``r`` times and meshes ``r·z`` times per joint revolution
    (Slamani & Bonev 2013).
    """

    joint: int
    stage: str
    rev_per_joint_rev: float
    teeth: int

    def as_dict(self) -> dict[str, Any]:
        return {"joint": self.joint, "stage": self.stage,
                "rev_per_joint_rev": self.rev_per_joint_rev, "teeth": self.teeth}


@dataclass(frozen=True)
class Registration:
    """Rigid transform from an instrument's frame to the robot base frame."""

    rotation: np.ndarray
    translation_mm: np.ndarray

    def apply(self, points_mm: np.ndarray) -> np.ndarray:
        """``p_base = R p + t`` for points ``(..., 3)`` [mm]."""
        return np.asarray(points_mm, float) @ self.rotation.T + self.translation_mm


@dataclass(frozen=True)
class PointMass:
    """A point mass riding on link ``link`` (1..n): ``mass_kg`` at ``com_mm``, its position at
    the zero configuration in the robot base frame [mm]."""

    link: int
    mass_kg: float
    com_mm: tuple[float, float, float]


@dataclass(frozen=True)
class CellMassModel:
    """The cell's mass model: point masses of the links and of the spindle and tool (on the
    last link), e.g. from the manufacturer's data or CAD."""

    links: tuple[PointMass, ...]
    tool: PointMass | None = None

    def point_masses(self) -> list[PointMass]:
        """Every point mass, links first, then the tool."""
        return [*self.links, *([self.tool] if self.tool is not None else [])]

    def as_dict(self) -> dict[str, Any]:
        """The ``cell.yaml`` mapping ``{links: [{link, mass_kg, com_mm}], tool: {…}}``."""
        out: dict[str, Any] = {"links": [{"link": m.link, "mass_kg": m.mass_kg,
                                          "com_mm": list(m.com_mm)} for m in self.links]}
        if self.tool is not None:
            out["tool"] = {"mass_kg": self.tool.mass_kg, "com_mm": list(self.tool.com_mm)}
        return out


@dataclass
class Cell:
    """A validated cell file (``mass_model`` None when the file states none)."""

    path: Path
    robot: SerialRobot
    robot_spec: dict[str, Any]
    q_home_deg: np.ndarray
    tool_rotation: np.ndarray
    transmissions: list[Transmission]
    base_from_instrument: dict[str, Registration] = field(default_factory=dict)
    mass_model: CellMassModel | None = None
    controller_frames: ControllerFrames | None = None
    spindle: SpindleInterface | None = None

    @property
    def q_home_rad(self) -> np.ndarray:
        return np.deg2rad(self.q_home_deg)

    @property
    def joint_limits_deg(self) -> np.ndarray | None:
        """``(n, 2)`` working range [deg] (``robot.joint_limits_deg``), None when not stated."""
        lim = self.robot_spec.get("joint_limits_deg")
        return None if lim is None else np.asarray(lim, float)

    @property
    def joint_speed_limits_deg_s(self) -> np.ndarray | None:
        """``(n,)`` axis speeds [deg/s] (``robot.joint_speed_limits_deg_s``), None if absent."""
        v = self.robot_spec.get("joint_speed_limits_deg_s")
        return None if v is None else np.asarray(v, float)

    @property
    def controller(self) -> str | None:
        """``robot.controller`` (abb | kuka), None when the cell names none."""
        return self.robot_spec.get("controller")

    def to_base_mm(self, instrument: str, points_mm: np.ndarray) -> np.ndarray:
        """Points measured by ``instrument`` expressed in the robot base frame [mm] (unchanged
        when the cell registers no frame for it)."""
        reg = self.base_from_instrument.get(instrument)
        return np.asarray(points_mm, float) if reg is None else reg.apply(points_mm)

    def fourier_orders(self) -> list[list[float]]:
        """Per joint (1..n), the sorted distinct orders of its gear elements: each element's
        revolutions per joint revolution ``r`` and its mesh order ``r·z`` (the orders of the
        calibration's joint-error Fourier model, ``calibration.error_model.orders``)."""
        out: list[list[float]] = []
        for j in range(1, self.robot.n_joints + 1):
            orders = set()
            for t in self.transmissions:
                if t.joint == j:
                    orders.update({t.rev_per_joint_rev, t.rev_per_joint_rev * t.teeth})
            out.append(sorted(round(o, 9) for o in orders))
        return out

    def joint_path_rad(self, targets: np.ndarray, q0_rad: np.ndarray | None = None, *,
                       data_file: str | Path, instrument: str) -> np.ndarray:
        """Inverse kinematics along TCP poses ``(m, 4, 4)`` in the base frame, from
        ``q_home_deg`` (:func:`robomill.kinematics.reachable_joint_path_rad` with this cell's
        robot; a pose out of reach raises :class:`RawDataError` naming ``data_file``)."""
        q0 = self.q_home_rad if q0_rad is None else q0_rad
        return reachable_joint_path_rad(self.robot, targets, q0, data_file=data_file,
                                        instrument=instrument, cell_file=self.path)


def _matrix(path: Path, where: str, value: Any, shape: tuple[int, ...], what: str
            ) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        arr = None
    if (arr is None or isinstance(value, str | bool | Mapping) or arr.shape != shape
            or not np.all(np.isfinite(arr))):
        raise RawDataError(path, f"{where} is {value!r}", where=where, expected=what)
    return arr


def _rotation(path: Path, where: str, value: Any) -> np.ndarray:
    R = _matrix(path, where, value, (3, 3), "a 3×3 rotation matrix (list of 3 rows of 3 numbers)")
    if (np.max(np.abs(R.T @ R - np.eye(3))) > ROTATION_TOL
            or abs(np.linalg.det(R) - 1.0) > ROTATION_TOL):
        raise RawDataError(path, f"{where} is not a rotation (RᵀR ≠ I or det R ≠ 1)",
                           where=where, expected="an orthonormal 3×3 matrix with determinant +1")
    return R


def _require(path: Path, data: Mapping, key: str, where: str, expected: str) -> Any:
    if key not in data:
        raise RawDataError(path, f"key '{key}' is missing", where=where, expected=expected)
    return data[key]


MASS_EXPECTED = ("a mapping {links: [{link, mass_kg, com_mm}, ...], tool: {mass_kg, com_mm}} "
                 "(tool optional)")


def _mass(path: Path, where: str, value: Any, keys: Sequence[str]) -> tuple[float, np.ndarray]:
    """``mass_kg`` (≥ 0) and ``com_mm`` (3 numbers) of one point-mass mapping."""
    expected = "a mapping with keys " + ", ".join(keys)
    if not isinstance(value, Mapping):
        raise RawDataError(path, f"{type(value).__name__} found", where=where, expected=expected)
    extra = sorted(set(value) - set(keys), key=str)
    if extra:
        raise RawDataError(path, f"unknown key(s) {', '.join(map(str, extra))}", where=where,
                           expected="keys " + ", ".join(keys))
    for key in keys:
        _require(path, value, key, where, "keys " + ", ".join(keys))
    m = value["mass_kg"]
    if (isinstance(m, bool) or not isinstance(m, int | float) or not np.isfinite(m) or m < 0):
        raise RawDataError(path, f"mass_kg is {m!r}", where=f"{where}.mass_kg",
                           expected="a number of kilograms >= 0")
    com = _matrix(path, f"{where}.com_mm", value["com_mm"], (3,),
                  "[x, y, z] in mm (the centre of mass at the zero configuration, base frame)")
    return float(m), com


def parse_mass_model(value: Any, path: str | Path, n_links: int) -> CellMassModel:
    """Validate ``cell.yaml: mass_model`` for a robot of ``n_links`` links.

    Raises
    ------
    RawDataError
        Naming the file and the key (``mass_model.links[2].link``, ``mass_model.tool.com_mm``
        …): not a mapping, a missing or unknown key, a mass that is not a number ≥ 0, a centre
        of mass that is not 3 numbers, a link outside 1..``n_links``.
    """
    path = Path(path)
    if not isinstance(value, Mapping):
        raise RawDataError(path, f"mass_model is {type(value).__name__}", where="mass_model",
                           expected=MASS_EXPECTED)
    extra = sorted(set(value) - {"links", "tool"}, key=str)
    if extra:
        raise RawDataError(path, f"unknown key(s) {', '.join(map(str, extra))}",
                           where="mass_model", expected=MASS_EXPECTED)
    links = _require(path, value, "links", "mass_model", MASS_EXPECTED)
    if not isinstance(links, list) or not links:
        raise RawDataError(path, f"links is {links!r}" if not isinstance(links, list)
                           else "links is an empty list", where="mass_model.links",
                           expected="a non-empty list of {link, mass_kg, com_mm}")
    out = []
    for i, entry in enumerate(links):
        where = f"mass_model.links[{i}]"
        m, com = _mass(path, where, entry, MASS_KEYS)
        link = entry["link"]
        if isinstance(link, bool) or not isinstance(link, int) or not 1 <= link <= n_links:
            raise RawDataError(path, f"link is {link!r}", where=f"{where}.link",
                               expected=f"an integer link number 1..{n_links} (the link the "
                                        "mass rides on)")
        out.append(PointMass(link, m, tuple(float(x) for x in com)))
    tool = None
    if value.get("tool") is not None:
        m, com = _mass(path, "mass_model.tool", value["tool"], MASS_KEYS[1:])
        tool = PointMass(n_links, m, tuple(float(x) for x in com))
    return CellMassModel(tuple(out), tool)


def parse_cell(data: Any, path: str | Path) -> Cell:
    """Validate a cell mapping (as loaded from ``cell.yaml``) and return a :class:`Cell`.

    Raises
    ------
    RawDataError
        Naming the file and the key (``robot.joints[2].alpha``, ``tool_rotation``,
        ``transmissions[3].teeth``, ``base_from_instrument.tracker.rotation`` …).
    """
    path = Path(path)
    top = ("keys robot, q_home_deg, tool_rotation, transmissions (base_from_instrument, "
           "mass_model, controller_frames, spindle optional)")
    if not isinstance(data, Mapping):
        raise RawDataError(path, "not a YAML mapping", expected=top)
    unknown = sorted(set(data) - set(CELL_KEYS))
    if unknown:
        raise RawDataError(path, f"unknown key(s) {', '.join(map(str, unknown))}",
                           where="<top level>", expected=top)
    spec = _require(path, data, "robot", "robot", top)
    try:
        spec = parse_robot(spec, path, n_joints=None)
    except RawDataError as err:  # the same checks as a robot file, keys under 'robot'
        where = "robot" + (f".{err.where}" if err.where else "")
        raise RawDataError(path, err.problem, where=where, expected=err.expected) from None
    robot = robot_from_mapping(spec)
    n = robot.n_joints

    q_home = _require(path, data, "q_home_deg", "q_home_deg", top)
    q_home = _matrix(path, "q_home_deg", q_home, (n,),
                     f"a list of {n} joint angles [deg] (one per joint of the robot)")
    R_tool = _rotation(path, "tool_rotation", _require(path, data, "tool_rotation",
                                                       "tool_rotation", top))

    trans = _require(path, data, "transmissions", "transmissions", top)
    if not isinstance(trans, list):
        raise RawDataError(path, f"transmissions is {type(trans).__name__}",
                           where="transmissions",
                           expected="a list of {joint, stage, rev_per_joint_rev, teeth}")
    transmissions = []
    seen: dict[tuple[int, str], int] = {}
    for i, t in enumerate(trans):
        where = f"transmissions[{i}]"
        keys = "keys " + ", ".join(TRANSMISSION_KEYS)
        if not isinstance(t, Mapping):
            raise RawDataError(path, f"{type(t).__name__} found", where=where,
                               expected="a mapping with " + keys)
        extra = sorted(set(t) - set(TRANSMISSION_KEYS))
        if extra:
            raise RawDataError(path, f"unknown key(s) {', '.join(map(str, extra))}", where=where,
                               expected=keys + " (error amplitudes are not facts of the cell)")
        for key in TRANSMISSION_KEYS:
            _require(path, t, key, where, keys)
        joint, stage, rev, teeth = (t[k] for k in TRANSMISSION_KEYS)
        if isinstance(joint, bool) or not isinstance(joint, int) or not 1 <= joint <= n:
            raise RawDataError(path, f"joint is {joint!r}", where=f"{where}.joint",
                               expected=f"an integer joint number 1..{n}")
        if not isinstance(stage, str) or not stage:
            raise RawDataError(path, f"stage is {stage!r}", where=f"{where}.stage",
                               expected="a stage name (text)")
        if (isinstance(rev, bool) or not isinstance(rev, int | float) or not np.isfinite(rev)
                or rev <= 0):
            raise RawDataError(path, f"rev_per_joint_rev is {rev!r}",
                               where=f"{where}.rev_per_joint_rev",
                               expected="a positive number (element revolutions per joint "
                                        "revolution)")
        if isinstance(teeth, bool) or not isinstance(teeth, int) or teeth < 1:
            raise RawDataError(path, f"teeth is {teeth!r}", where=f"{where}.teeth",
                               expected="a positive integer tooth count")
        if (joint, stage) in seen:
            raise RawDataError(path, f"joint {joint} stage {stage!r} listed twice (also "
                               f"transmissions[{seen[(joint, stage)]}])", where=where,
                               expected="each (joint, stage) once")
        seen[(joint, stage)] = i
        transmissions.append(Transmission(joint, stage, float(rev), teeth))

    regs: dict[str, Registration] = {}
    bfi = data.get("base_from_instrument")
    if bfi is not None:
        if not isinstance(bfi, Mapping):
            raise RawDataError(path, f"base_from_instrument is {type(bfi).__name__}",
                               where="base_from_instrument",
                               expected="a mapping instrument -> {rotation, translation_mm} "
                                        "with instruments " + ", ".join(INSTRUMENTS))
        for inst, reg in bfi.items():
            where = f"base_from_instrument.{inst}"
            if inst not in INSTRUMENTS:
                raise RawDataError(path, f"unknown instrument {inst!r}", where=where,
                                   expected="one of " + ", ".join(INSTRUMENTS))
            if not isinstance(reg, Mapping):
                raise RawDataError(path, f"{type(reg).__name__} found", where=where,
                                   expected="a mapping {rotation, translation_mm}")
            extra = sorted(set(reg) - {"rotation", "translation_mm"})
            if extra:
                raise RawDataError(path, f"unknown key(s) {', '.join(map(str, extra))}",
                                   where=where, expected="keys rotation, translation_mm")
            R = _rotation(path, f"{where}.rotation",
                          _require(path, reg, "rotation", where, "keys rotation, translation_mm"))
            t = _matrix(path, f"{where}.translation_mm",
                        _require(path, reg, "translation_mm", where,
                                 "keys rotation, translation_mm"),
                        (3,), "[x, y, z] in mm")
            regs[str(inst)] = Registration(R, t)
    masses = data.get("mass_model")
    masses = None if masses is None else parse_mass_model(masses, path, n)
    frames = parse_controller_frames(data.get("controller_frames"), path, n)
    spindle = parse_spindle(data.get("spindle"), path, spec.get("controller"))
    return Cell(path=path, robot=robot, robot_spec=spec, q_home_deg=q_home,
                tool_rotation=R_tool, transmissions=transmissions, base_from_instrument=regs,
                mass_model=masses, controller_frames=frames, spindle=spindle)


def read_cell(path: str | Path) -> Cell:
    """Read and validate ``cell.yaml`` (see the module docstring)."""
    path = Path(path)
    if not path.exists():
        raise RawDataError(path, "cell file does not exist",
                           expected="cell.yaml in the raw folder (docs/data-contract.md)")
    try:
        data = yaml.safe_load(path.read_text())
    except yaml.YAMLError as exc:
        raise RawDataError(path, f"not valid YAML: {exc}") from None
    return parse_cell(data, path)


def cell_mapping(cell: Mapping[str, Any]) -> dict[str, Any]:
    """The ``cell.yaml`` mapping of a configuration's ``cell:`` section (plain YAML types)."""
    out: dict[str, Any] = {k: cell[k] for k in CELL_KEYS[:4]}
    out["transmissions"] = [{k: t[k] for k in TRANSMISSION_KEYS} for t in cell["transmissions"]]
    if cell.get("base_from_instrument"):
        out["base_from_instrument"] = dict(cell["base_from_instrument"])
    for key in ("mass_model", "controller_frames", "spindle"):
        if cell.get(key) is not None:
            out[key] = dict(cell[key])
    return _plain(out)


def _plain(obj: Any) -> Any:
    if isinstance(obj, Mapping):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, Sequence) and not isinstance(obj, str):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


def write_cell(cell: Mapping[str, Any], path: str | Path) -> Path:
    """Write a configuration's ``cell:`` section as ``cell.yaml`` (validated, atomically)."""
    from robomill.io.atomic import atomic_path

    data = cell_mapping(cell)
    parse_cell(data, path)
    with atomic_path(path) as tmp:
        tmp.write_text(yaml.safe_dump(data, sort_keys=False, width=100))
    return Path(path)


def peek_robot_name(path: str | Path) -> str | None:
    """The name of the cell's robot (``robot: name``) for planning the workflow, without
    validating the file (:func:`read_cell` does that when a rule reads it); None when the file
    is missing or has no such key, so that a bad cell file fails its own rules, not the plan."""
    try:
        data = yaml.safe_load(Path(path).read_text())
        name = data["robot"]["name"]
    except (OSError, yaml.YAMLError, TypeError, KeyError):
        return None
    return name if isinstance(name, str) else None
