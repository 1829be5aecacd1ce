"""``robomill import FORMAT SRC... --to DIR``: native exports into the contract, atomically.

The importer (:func:`robomill.importers.load_importer`) converts every source into a fresh
staging folder. Only when all of them converted, and none of the files would replace a file
of the raw folder or an entry of its manifest (unless ``--overwrite``), are the files moved
into the raw folder and their entries, with their sha256, merged into ``manifest.yaml``. On any
failure nothing is written into the raw folder (a move that fails half-way is undone).
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from robomill.errors import RawDataError

HELP = "convert native instrument exports into the data contract and add them to the manifest"


class ImportFailed(Exception):
    """An import that wrote nothing into the raw folder; ``lines`` says why."""

    def __init__(self, lines: list[str]):
        self.lines = lines
        super().__init__("; ".join(lines))


def _check_entries(entries: Any, staging: Path, module: str) -> list[dict[str, Any]]:
    from robomill.io.kinds import KIND_KEYS

    if not isinstance(entries, list) or not entries:
        raise ImportFailed([f"importer {module} returned {entries!r} (expected a non-empty "
                            "list of manifest entries)"])
    out, problems = [], []
    for i, e in enumerate(entries):
        if not isinstance(e, Mapping) or not isinstance(e.get("path"), str) or not isinstance(
                e.get("kind"), str):
            problems.append(f"importer {module}: entry {i} is {e!r} (expected a mapping with "
                            "path and kind)")
            continue
        rel = Path(e["path"])
        if rel.is_absolute() or ".." in rel.parts or not (staging / rel).is_file():
            problems.append(f"importer {module}: entry {i}: {e['path']} was not written under "
                            "the staging folder")
            continue
        if e["kind"] not in KIND_KEYS:
            problems.append(f"importer {module}: entry {i} ({e['path']}): unknown kind "
                            f"{e['kind']!r} (expected one of {', '.join(KIND_KEYS)})")
            continue
        out.append({k: v for k, v in e.items() if k != "sha256"})
    if len({e["path"] for e in out}) != len(out):
        problems.append(f"importer {module}: the same path is returned twice")
    if problems:
        raise ImportFailed(problems)
    return out


def _with_cut_stubs(cuts: Any, entries: list[dict[str, Any]],
                    designs: Mapping[str, Mapping[str, Any]] | None = None, *,
                    overwrite: bool = False, mpath: Path | None = None
                    ) -> tuple[Any, list[str]]:
    """``cuts`` plus an entry for each cut id of ``entries`` not listed yet
    (:func:`robomill.cli.layout.cut_stub`: the keys the id cannot give ``null``, to fill in),
    with the design keys ``designs[id]`` read from the file names; and one line per cut added
    or completed.

    A design key the manifest already has with another value is a clash (an
    :class:`ImportFailed` line) unless ``overwrite``; an empty (``null``) one is filled.
    """
    from robomill.cli.layout import cut_stub
    from robomill.experiment import FREE_CUT_ID

    designs = designs or {}
    if not isinstance(cuts, list):
        return cuts, []
    out = [dict(c) if isinstance(c, Mapping) else c for c in cuts]
    index = {c.get("id"): i for i, c in enumerate(out) if isinstance(c, Mapping)}
    lines, clashes = [], []
    for e in entries:
        cid = e.get("cut")
        if not (isinstance(cid, str) and FREE_CUT_ID.match(cid)):
            continue
        design = dict(designs.get(cid) or {})
        if cid not in index:
            stub = cut_stub(cid)
            if "direction_deg" in design and stub.get("direction") is None:
                stub.pop("direction", None)
            stub.update(design)
            out.append(stub)
            index[cid] = len(out) - 1
            lines.append(f"cut {cid} added" + (" (" + ", ".join(
                f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"
                for k, v in design.items()) + ")" if design else " (design keys null: "
                "fill them in, robomill manifest lists them)"))
            continue
        c = out[index[cid]]
        filled = []
        for key, value in design.items():
            if c.get(key) is None or overwrite:
                if c.get(key) != value:
                    filled.append(key)
                c[key] = value
                if key == "direction_deg" and c.get("direction") is None:
                    c.pop("direction", None)
            elif c[key] != value:
                clashes.append(f"{mpath}: cuts[{index[cid]}] ({cid}) has {key} {c[key]!r}, the "
                               f"file name gives {value!r} (expected the same; pass "
                               "--overwrite to replace it)")
        if filled:
            lines.append(f"cut {cid}: {', '.join(filled)} filled from the file name")
    if clashes:
        raise ImportFailed(clashes)
    return out, lines


def _designs_from_names(args: argparse.Namespace, sources: list[Path]
                        ) -> dict[str, dict[str, Any]]:
    """With ``--cut-pattern`` or ``--design``: each source's cut id (``args.cut_ids``, read by
    the importers' :func:`robomill.importers._common.cut_id`) and the design keys its name
    and ``--design`` give, by cut id. Without either: ``{}``.

    Raises
    ------
    ImportFailed
        A bad pattern or ``--design``, a name the pattern does not match, a value that does
        not parse, a key given both by the name and by ``--design``, ``--cut``
        with a pattern that names the cut, or two sources of one cut that disagree.
    """
    from robomill.importers.names import compile_pattern, design_from_name, design_from_options

    pattern = getattr(args, "cut_pattern", None)
    try:
        common = design_from_options(getattr(args, "design", None))
        if pattern is None and not common:
            return {}
        rx = compile_pattern(pattern if pattern is not None else "")
    except RawDataError as exc:
        raise ImportFailed([" ".join(str(exc).split())]) from None
    problems: list[str] = []
    if "cut" in rx.groupindex and getattr(args, "cut", None):
        raise ImportFailed([f"--cut {args.cut} given with a --cut-pattern that names the cut "
                            "(expected one of them)"])
    args.cut_ids = {}
    designs: dict[str, dict[str, Any]] = {}
    seen: dict[str, Path] = {}
    for src in sources:
        src = Path(src)
        try:
            cid, design = design_from_name(rx, src)
        except RawDataError as exc:
            problems.append(" ".join(str(exc).split()))
            continue
        if cid is None:
            cid = getattr(args, "cut", None) or src.stem
        args.cut_ids[src] = cid
        both = sorted(set(common) & set(design))
        if both:
            problems.append(f"{src}: option --design: {', '.join(both)} given both by "
                            "--design and by the file name (expected one of them)")
        design = {**design, **common}
        if cid in designs and designs[cid] != design:
            problems.append(f"{src}: option --cut-pattern: cut {cid} gets {design}, "
                            f"{seen[cid]} gave it {designs[cid]} (expected one design per cut)")
        designs[cid], seen[cid] = design, src
    if problems:
        raise ImportFailed(problems)
    return designs


def _sidecar_design(args: argparse.Namespace) -> None:
    """A ``--sidecar`` file (YAML or JSON: the cut's conditions as a lab writes them beside a
    recording, keys among the ``--design`` names, e.g. ``{spindle_rpm: 12500, flutes: 4,
    feed_mm_min: 600, depth_mm: 0.5, tool_diameter_mm: 6}``) added to ``args.design``.

    Raises
    ------
    ImportFailed
        An unreadable file, not a mapping, or a key that is not a design name.
    """
    import yaml

    from robomill.importers.names import GROUPS

    path = getattr(args, "sidecar", None)
    if path is None:
        return
    path = Path(path)
    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError) as exc:
        raise ImportFailed([f"{path}: sidecar cannot be read ({type(exc).__name__}) "
                            "(expected a YAML or JSON mapping of the cut's design keys)"]
                           ) from None
    if not isinstance(data, Mapping) or not data:
        raise ImportFailed([f"{path}: sidecar holds {type(data).__name__} (expected a YAML or "
                            "JSON mapping of the cut's design keys)"])
    unknown = [str(k) for k in data if k not in GROUPS]
    if unknown:
        raise ImportFailed([f"{path}: sidecar key(s) {', '.join(unknown)} unknown (expected "
                            "keys among " + ", ".join(GROUPS) + ")"])
    args.design = list(getattr(args, "design", None) or []) + [
        f"{k}={v}" for k, v in data.items()]


def import_files(module, sources: list[Path], raw_dir: Path, args: argparse.Namespace, *,
                 overwrite: bool = False) -> list[dict[str, Any]]:
    """Convert ``sources`` with importer ``module`` and add them to ``raw_dir`` atomically.

    Returns the manifest entries added (with sha256).

    Raises
    ------
    ImportFailed
        A source is missing or does not convert (the importer's
        :class:`~robomill.errors.RawDataError`), the importer returned bad entries, a file
        or manifest entry would be replaced without ``overwrite``, or the manifest cannot be
        read. Nothing has been written into ``raw_dir`` then.
    """
    from robomill.cli.manifest import read_manifest_text, write_manifest_text
    from robomill.io.hashing import sha256_file

    missing = [f"{s}: source file does not exist" for s in sources if not Path(s).is_file()]
    if missing:
        raise ImportFailed(missing)
    mpath = raw_dir / "manifest.yaml"
    try:
        data, header = read_manifest_text(mpath)
    except RawDataError as exc:
        raise ImportFailed([" ".join(str(exc).split())]) from None
    _sidecar_design(args)
    designs = _designs_from_names(args, [Path(s) for s in sources])
    staging = Path(tempfile.mkdtemp(prefix="robomill-import-"))
    placed: list[tuple[Path, Path | None]] = []  # (file placed, backup of what it replaced)
    try:
        try:
            entries = module.convert([Path(s) for s in sources], staging, args)
        except RawDataError as exc:
            raise ImportFailed([" ".join(str(exc).split())]) from None
        entries = _check_entries(entries, staging, module.__name__)
        files = list(data.get("files") or []) if isinstance(data.get("files"), list) else []
        listed = {f.get("path"): i for i, f in enumerate(files) if isinstance(f, Mapping)}
        clashes = []
        for e in entries:
            target = raw_dir / e["path"]
            if not overwrite and target.exists():
                clashes.append(f"{target}: exists already (expected a new file; pass "
                               "--overwrite to replace it)")
            elif not overwrite and e["path"] in listed:
                clashes.append(f"{mpath}: files[{listed[e['path']]}] lists {e['path']} already "
                               "(expected a new entry; pass --overwrite to replace it)")
        if clashes:
            raise ImportFailed(clashes)
        if designs and not any(isinstance(e.get("cut"), str) for e in entries):
            raise ImportFailed([f"option --cut-pattern: the {entries[0]['kind']} records "
                                "written belong to no cut (expected a format whose records are "
                                "cuts: forces or profiles)"])
        cuts, cut_lines = _with_cut_stubs(
            (data.get("cuts") if data else None) or [], entries, designs,
            overwrite=overwrite, mpath=mpath)
        for e in entries:
            e["sha256"] = sha256_file(staging / e["path"])
        # move: each file beside its target first, then renamed over it; undone on failure
        try:
            raw_dir.mkdir(parents=True, exist_ok=True)
            for e in entries:
                target = raw_dir / e["path"]
                target.parent.mkdir(parents=True, exist_ok=True)
                part = target.with_name(f".{target.name}.importing")
                shutil.copy2(staging / e["path"], part)
                backup = None
                if target.exists():
                    backup = target.with_name(f".{target.name}.replaced")
                    target.replace(backup)
                part.replace(target)
                placed.append((target, backup))
            new = dict(data) if data else {"experiment": {}, "cuts": [], "files": []}
            for key, default in (("experiment", {}), ("cuts", [])):
                new.setdefault(key, default)
            kept = [f for f in files if not (isinstance(f, Mapping)
                                             and f.get("path") in {e["path"] for e in entries})]
            new["files"] = kept + entries
            new["cuts"] = cuts
            write_manifest_text(new, mpath, header)
        except OSError as exc:
            for target, backup in reversed(placed):
                target.unlink(missing_ok=True)
                if backup is not None:
                    backup.replace(target)
            for e in entries:
                (raw_dir / e["path"]).with_name(f".{Path(e['path']).name}.importing").unlink(
                    missing_ok=True)
            raise ImportFailed([f"{raw_dir}: writing failed ({exc}); nothing was changed"]
                               ) from None
        for _, backup in placed:
            if backup is not None:
                backup.unlink(missing_ok=True)
        args.cut_lines = cut_lines
        return entries
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _format_help() -> str:
    from robomill.importers import describe

    return "formats:\n" + "\n".join(f"  {f:<16} {d}" for f, d in describe())


DESIGN_HELP = (
    "Cut ids are free ([A-Za-z0-9_.-]+; the thesis' s{set}_g{segment}_{dir} is one layout): "
    "every new cut id is added to the manifest's cuts: with the keys the import cannot give "
    "left null (robomill manifest lists them). A cut's design keys are feed_mm_s, depth_mm, "
    "the feed direction (direction px, mx, py, my, or direction_deg, 0 = +X) and, per cut "
    "where they differ from experiment:, spindle_rpm, flutes, tool_diameter_mm, "
    "radial_immersion (a_e/D) and milling (slot, up, down). --cut-pattern reads them from "
    "the file names, --design gives those common to the files.")


def format_parser(fmt: str, module) -> argparse.ArgumentParser:
    """The parser of ``robomill import FMT``: the common options and the importer's own."""
    from robomill.importers.names import ACCEPTED

    p = argparse.ArgumentParser(prog=f"robomill import {fmt}",
                                description=f"{module.DESCRIPTION}. Converts SRC files into "
                                "the data contract and adds them to DIR/manifest.yaml; on any "
                                "failure nothing is written into DIR. " + DESIGN_HELP)
    p.add_argument("sources", nargs="+", type=Path, metavar="SRC", help="native export(s)")
    p.add_argument("--to", required=True, type=Path, metavar="DIR", dest="to",
                   help="the raw folder (its manifest.yaml is updated)")
    p.add_argument("--cut", default=None, metavar="ID",
                   help="cut id the record belongs to (one source; any [A-Za-z0-9_.-]+, e.g. "
                        "s1_g1_px or n6000_slot3); default: the source's file name")
    p.add_argument("--cut-pattern", default=None, metavar="REGEX",
                   help="regular expression searched in each source's file name (without "
                        "extension) whose named groups give the cut id and design: "
                        + ", ".join(ACCEPTED) + " (feed_mm_min is converted to feed_mm_s, "
                        "width_pct to radial_immersion). E.g. for 6-n6000f300ap3ae25: "
                        r"'(?P<cut>\d+)-n(?P<spindle_rpm>\d+)f(?P<feed_mm_min>\d+)"
                        r"ap(?P<depth_mm>[\d.]+)ae(?P<width_pct>\d+)'")
    p.add_argument("--design", action="append", default=None, metavar="KEY=VALUE",
                   help="a design key the file names do not carry, for every cut of this "
                        "import (repeatable; the --cut-pattern names: --design direction=px "
                        "--design flutes=2)")
    p.add_argument("--overwrite", action="store_true",
                   help="replace files, manifest entries and cut design keys that exist "
                        "already")
    module.add_arguments(p)
    return p


def add_parser(sub: Any) -> None:  # what ArgumentParser.add_subparsers() returns
    p = sub.add_parser("import", help=HELP, description=HELP + ". `robomill import FORMAT "
                       "--help` shows a format's options. " + DESIGN_HELP, add_help=False)
    p.add_argument("-h", "--help", action="store_true", dest="import_help",
                   help="show this help (with FORMAT: that format's options)")
    p.add_argument("format", nargs="?", metavar="FORMAT", help="the export's format")
    p.add_argument("rest", nargs=argparse.REMAINDER, help="SRC... --to DIR [options]")
    p.set_defaults(run=run, import_parser=p)


def run(args: argparse.Namespace) -> int:
    from robomill.importers import ImporterError, load_importer

    if args.format is None:
        args.import_parser.print_help()
        print(_format_help())
        return 0 if args.import_help else 2
    try:
        module = load_importer(args.format)
    except ImporterError as exc:
        print(f"robomill import: {exc}")
        return 2
    parser = format_parser(args.format, module)
    if args.import_help or any(a in ("-h", "--help") for a in args.rest):
        parser.print_help()
        return 0
    fargs = parser.parse_args(args.rest)
    try:
        entries = import_files(module, fargs.sources, fargs.to, fargs,
                               overwrite=fargs.overwrite)
    except ImportFailed as exc:
        for line in exc.lines:
            print(line)
        print(f"{fargs.to}: nothing was written")
        return 1
    for e in entries:
        meta = ", ".join(f"{k}={v}" for k, v in e.items() if k not in ("path", "sha256"))
        print(f"{fargs.to / e['path']}: imported ({meta})")
        if e.get("time_base") == "none":
            print(f"{fargs.to / e['path']}: no time base (--spatial-only): analysed in space "
                  "only (gear lines per mm), its peaks not classified temporal/spatial")
    for line in getattr(fargs, "cut_lines", []):
        print(f"{fargs.to / 'manifest.yaml'}: {line}")
    print(f"{fargs.to / 'manifest.yaml'}: {len(entries)} entr{'y' if len(entries) == 1 else 'ies'}"
          f" added; next: robomill manifest {fargs.to} (cuts), robomill check {fargs.to}")
    return 0
