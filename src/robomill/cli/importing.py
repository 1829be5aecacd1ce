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

from robomill.io.errors import RawDataError

HELP = "convert native instrument exports into the data contract and add them to the manifest"


class ImportFailed(Exception):
    """An import that wrote nothing into the raw folder; ``lines`` says why."""

    def __init__(self, lines: list[str]):
        self.lines = lines
        super().__init__("; ".join(lines))


def _check_entries(entries: Any, staging: Path, module: str) -> list[dict[str, Any]]:
    from robomill.io.manifest import KIND_KEYS

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


def _with_cut_stubs(cuts: Any, entries: list[dict[str, Any]]) -> Any:
    """``cuts`` plus a stub (:func:`robomill.cli.layout.cut_stub`: feed and depth ``null``,
    to fill in) for each well-formed cut id of ``entries`` not listed yet."""
    from robomill.cli.layout import cut_stub
    from robomill.experiment import CUT_ID

    if not isinstance(cuts, list):
        return cuts
    known = {c.get("id") for c in cuts if isinstance(c, Mapping)}
    out = list(cuts)
    for e in entries:
        cid = e.get("cut")
        if isinstance(cid, str) and CUT_ID.match(cid) and cid not in known:
            out.append(cut_stub(cid))
            known.add(cid)
    return out


def import_files(module, sources: list[Path], raw_dir: Path, args: argparse.Namespace, *,
                 overwrite: bool = False) -> list[dict[str, Any]]:
    """Convert ``sources`` with importer ``module`` and add them to ``raw_dir`` atomically.

    Returns the manifest entries added (with sha256).

    Raises
    ------
    ImportFailed
        A source is missing or does not convert (the importer's
        :class:`~robomill.io.errors.RawDataError`), the importer returned bad entries, a file
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
            new["cuts"] = _with_cut_stubs(new.get("cuts"), entries)
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
        return entries
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def _format_help() -> str:
    from robomill.importers import describe

    return "formats:\n" + "\n".join(f"  {f:<16} {d}" for f, d in describe())


def format_parser(fmt: str, module) -> argparse.ArgumentParser:
    """The parser of ``robomill import FMT``: the common options and the importer's own."""
    p = argparse.ArgumentParser(prog=f"robomill import {fmt}",
                                description=f"{module.DESCRIPTION}. Converts SRC files into "
                                "the data contract and adds them to DIR/manifest.yaml; on any "
                                "failure nothing is written into DIR.")
    p.add_argument("sources", nargs="+", type=Path, metavar="SRC", help="native export(s)")
    p.add_argument("--to", required=True, type=Path, metavar="DIR", dest="to",
                   help="the raw folder (its manifest.yaml is updated)")
    p.add_argument("--cut", default=None, metavar="ID",
                   help="cut id s{set}_g{segment}_{dir} the record belongs to")
    p.add_argument("--overwrite", action="store_true",
                   help="replace files and manifest entries that exist already")
    module.add_arguments(p)
    return p


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("import", help=HELP, description=HELP + ". `robomill import FORMAT "
                       "--help` shows a format's options.", add_help=False)
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
    print(f"{fargs.to / 'manifest.yaml'}: {len(entries)} entr{'y' if len(entries) == 1 else 'ies'}"
          f" added; next: robomill manifest {fargs.to} (cuts), robomill check {fargs.to}")
    return 0
