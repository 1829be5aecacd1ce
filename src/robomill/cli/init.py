"""``robomill init DIR``: a raw-folder skeleton with commented templates."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from robomill.cli.layout import KIND_FOLDERS

HELP = "make a raw-folder skeleton: one folder per kind, commented manifest.yaml and cell.yaml"

MANIFEST_TEMPLATE = """\
# manifest.yaml: what each raw file is (docs/data-contract.md has the full contract).
# Put your files in the kind folders (robomill init DIR --experiment flutes=2 ... fills the
# experiment block below), then run `robomill manifest .` in this folder: it lists
# every file with its kind, metadata and sha256 and keeps what you wrote here. Fill in what it
# reports it could not infer, then run `robomill check .`.
#
# experiment: the machining conditions shared by all cuts (a cut may override them)
#   spindle_rpm (number), flutes (integer), tool_diameter_mm, cut_length_mm
# cuts: one entry per cut, any id ([A-Za-z0-9_.-]+; the thesis names s{set}_g{segment}_{dir}).
#   Each cut: feed_mm_s, depth_mm and its feed direction: direction px (+X), mx (-X), py (+Y),
#   my (-Y), or direction_deg (base XY plane, 0 = +X, counter-clockwise). Where a cut differs
#   from experiment: spindle_rpm, flutes, tool_diameter_mm, radial_immersion (a_e/D, 1 = slot),
#   milling (slot, up, down), start_mm ([x, y, z] of the path start); set/segment to group.
#   - {id: s1_g1_px, set: 1, segment: 1, direction: px, feed_mm_s: 1.0, depth_mm: 0.25}
#   - {id: n6000_ae25, direction: mx, feed_mm_s: 5.0, depth_mm: 3.0, spindle_rpm: 6000,
#      radial_immersion: 0.25, milling: down}
#   - {id: diag45, direction_deg: 45.0, feed_mm_s: 2.0, depth_mm: 0.5}
#   `robomill import` adds every new cut id with the keys it cannot give left null;
#   `--cut-pattern REGEX` reads the design from the file names (named groups cut, spindle_rpm,
#   feed_mm_s or feed_mm_min, depth_mm, width_pct, direction, ...: robomill import FORMAT --help),
#   `--design KEY=VALUE` what the names do not carry (--design direction=px).
# files: path (relative to this file), kind, sha256, and the keys of the kind:
#   profile  (profiles/<cut>.csv: x_mm, z_um)            cut
#   force    (forces/<cut>.csv or .h5: t_s, Fx_N, ...)   cut, fs_hz
#   tracker  (tracker/<dir>_f<feed>.csv: t_s, x_mm, ...) direction (or direction_deg),
#                                                        feed_mm_s, fs_hz
#   impact   (impact/hit<X|Y|Z>_<k>.csv or UFF 58)       direction, hit (CSV)
#   ctrack   (ctrack/<table>.csv)                        table
#   robot    (stiffness/<robot>.yaml)                    robot
#   stiffness (stiffness/load_tests_<robot>.csv)         robot
# Native exports (DynoWare, TDMS, UFF, SpatialAnalyzer, FARO, SMATS, X3P): convert them with
# `robomill import FORMAT FILE... --to .` (robomill import --help lists the formats).
experiment:
  spindle_rpm: null
  flutes: null
  tool_diameter_mm: null
  cut_length_mm: null
cuts: []
files: []
"""

CELL_TEMPLATE = """\
# cell.yaml: the facts of the robot cell the measurements were taken in.
# The values below are the thesis cell (ABB IRB 1600, assumed transmissions): replace them.
robot:
  name: irb1600
  convention: dh            # dh (standard Denavit-Hartenberg) or mdh (modified)
  length_unit: mm
  angle_unit: deg
  joints:                   # one row per joint: a, alpha, d, theta_offset
    - {a: 150.0, alpha: -90.0, d: 486.5, theta_offset: 0.0}
    - {a: 700.0, alpha: 0.0, d: 0.0, theta_offset: -90.0}
    - {a: 0.0, alpha: -90.0, d: 0.0, theta_offset: 0.0}
    - {a: 0.0, alpha: 90.0, d: 600.0, theta_offset: 0.0}
    - {a: 0.0, alpha: -90.0, d: 0.0, theta_offset: 0.0}
    - {a: 0.0, alpha: 0.0, d: 65.0, theta_offset: 0.0}
  tool: [0.0, 0.0, 180.0]   # tool centre point in the flange frame [length_unit]
q_home_deg: [0.0, 20.0, 10.0, 0.0, 60.0, 0.0]   # posture near the workpiece (IK seed)
tool_rotation: [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]   # tool axis down
transmissions:              # gear stages per joint (straightness vs gear mesh, chapter 3.2)
  - {joint: 1, stage: motor, rev_per_joint_rev: 120.0, teeth: 17}
  - {joint: 1, stage: reducer_input, rev_per_joint_rev: 8.0, teeth: 40}
  - {joint: 2, stage: motor, rev_per_joint_rev: 125.0, teeth: 15}
  - {joint: 2, stage: reducer_input, rev_per_joint_rev: 8.3, teeth: 40}
# Optional: where each instrument's frame sits in the robot base frame (omit when the
# instrument already reports in base axes).
# base_from_instrument:
#   tracker: {rotation: [[1, 0, 0], [0, 1, 0], [0, 0, 1]], translation_mm: [0.0, 0.0, 0.0]}
#   ctrack: {rotation: [[1, 0, 0], [0, 1, 0], [0, 0, 1]], translation_mm: [0.0, 0.0, 0.0]}
# Optional: point masses of the links and of the spindle and tool (manufacturer data / CAD;
# centres of mass at the zero configuration, base frame): the gravity model of the
# calibration (chapter 1). Without it the calibration runs without the gravity term.
# mass_model:
#   links:
#     - {link: 2, mass_kg: 35.0, com_mm: [170.0, 0.0, 840.0]}
#   tool: {mass_kg: 5.0, com_mm: [880.0, 10.0, 1186.5]}
"""


def experiment_from_options(items: list[str] | None) -> dict[str, Any]:
    """``--experiment KEY=VALUE`` items → the experiment block's values, parsed as
    ``--design`` parses them (:data:`robomill.importers.names.GROUPS`; ``cut_length_mm`` a
    number of mm).

    Raises
    ------
    RawDataError
        An item without ``=``, a key that is not an experiment key, a value that does not
        parse, a key given twice.
    """
    from robomill.errors import RawDataError
    from robomill.importers.names import GROUPS
    from robomill.io.manifest import EXPERIMENT_KEYS

    where, expected = "option --experiment", "keys among " + ", ".join(EXPERIMENT_KEYS)
    out: dict[str, Any] = {}
    for item in items or []:
        name, eq, text = (part.strip() for part in item.partition("="))
        if not eq or name not in EXPERIMENT_KEYS:
            raise RawDataError("--experiment", f"--experiment {item!r} is not KEY=VALUE with "
                               "an experiment key", where=where, expected=expected)
        _, parse, what = GROUPS.get(name, (name, float, "a number [mm]"))
        try:
            value = parse(text)
        except ValueError:
            raise RawDataError("--experiment", f"--experiment {name}={text!r}", where=where,
                               expected=what) from None
        if name in out:
            raise RawDataError("--experiment", f"--experiment gives {name} twice",
                               where=where, expected="one value per key")
        out[name] = value
    return out


def _set_experiment(path: Path, values: dict[str, Any]) -> str:
    """Write ``values`` into the experiment block of the manifest at ``path`` (its other
    keys, its cuts, files and leading comments kept); one line saying what was set."""
    from robomill.cli.manifest import read_manifest_text, write_manifest_text

    data, header = read_manifest_text(path)
    data = dict(data) if data else {"experiment": {}, "cuts": [], "files": []}
    data["experiment"] = {**(data.get("experiment") or {}), **values}
    write_manifest_text(data, path, header)
    return f"{path}: experiment " + ", ".join(f"{k}={v}" for k, v in values.items())


def init_folder(raw_dir: str | Path, experiment: dict[str, Any] | None = None) -> list[str]:
    """Create the skeleton of a raw folder; existing files are never overwritten, except the
    manifest's experiment block where ``experiment`` gives values (the lab's tool and
    conditions, written once for every cut).

    Returns one line per thing made or kept.
    """
    raw_dir = Path(raw_dir)
    lines = []
    raw_dir.mkdir(parents=True, exist_ok=True)
    for folder in dict.fromkeys(KIND_FOLDERS.values()):
        d = raw_dir / folder
        lines.append(f"{d}/: {'kept' if d.exists() else 'made'}")
        d.mkdir(exist_ok=True)
    for name, text in (("manifest.yaml", MANIFEST_TEMPLATE), ("cell.yaml", CELL_TEMPLATE)):
        p = raw_dir / name
        if p.exists():
            lines.append(f"{p}: exists, kept as it is")
        else:
            p.write_text(text)
            lines.append(f"{p}: template written")
    if experiment:
        lines.append(_set_experiment(raw_dir / "manifest.yaml", experiment))
    return lines


def add_parser(sub: Any) -> None:  # what ArgumentParser.add_subparsers() returns
    p = sub.add_parser("init", help=HELP, description=HELP + " (existing files are kept).")
    p.add_argument("dir", type=Path, metavar="DIR", help="the raw folder to make")
    p.add_argument("--experiment", action="append", metavar="KEY=VALUE",
                   help="a value of the manifest's experiment block, shared by every cut "
                        "(repeatable): spindle_rpm, flutes, tool_diameter_mm, cut_length_mm; "
                        "e.g. --experiment flutes=2 --experiment tool_diameter_mm=10")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from robomill.errors import RawDataError

    try:
        experiment = experiment_from_options(args.experiment)
    except RawDataError as exc:
        print(" ".join(str(exc).split()))
        return 1
    try:
        lines = init_folder(args.dir, experiment)
    except RawDataError as exc:
        print(" ".join(str(exc).split()))
        return 1
    except OSError as exc:
        print(f"{args.dir}: cannot make the raw folder ({exc})")
        return 1
    for line in lines:
        print(line)
    print(f"next: put your files in {args.dir}/<kind>/, then robomill manifest {args.dir}")
    return 0
