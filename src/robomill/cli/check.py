"""``robomill check DIR``: every problem of a raw folder, one line each, without Snakemake.

The manifest is validated entry by entry with the pipeline's own validator
(:func:`robomill.io.manifest.parse_manifest`), so that one bad entry does not hide the next;
the cell file with :func:`robomill.io.cell.read_cell` where this installation has it; every
listed file against its sha256 and with the reader its analysis uses (the same reader, the
same arguments), and every data file of the folder must be listed.
"""

from __future__ import annotations

import argparse
import re
import time
from collections.abc import Callable, Iterable, Mapping
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

from robomill.errors import RawDataError
from robomill.io.kinds import KIND_RECORDS

HELP = ("validate a raw folder (manifest, cell file, every data file with the pipeline's "
        "readers); one line per problem, exit status 1 if any")


CHECKERS: dict[str, Callable[[Path, Mapping[str, Any]], None]] = {
    k.name: k.checker() for k in KIND_RECORDS if k.check is not None}
"""The reader each kind's analysis uses, called as the pipeline calls it (the kind's record,
:attr:`robomill.io.kinds.Kind.check`). A kind without one is reported as not checked (a
note, not a problem)."""


def _line(exc: BaseException) -> str:
    """One line: ``file: where: problem (expected …)``."""
    return " ".join(str(exc).split())


_INDEX = re.compile(r"^(cuts|files)\[0\]")


def _reindex(exc: RawDataError, section: str, i: int) -> RawDataError:
    """The error of entry ``i`` validated alone (as ``{section}[0]``) renamed to its index."""
    where = _INDEX.sub(f"{section}[{i}]", exc.where) if exc.where else exc.where
    return RawDataError(exc.path, exc.problem, where=where, expected=exc.expected)


def manifest_problems(data: Any, path: Path) -> tuple[list[str], list[dict]]:
    """Every problem of a manifest mapping, one line each, and the file entries that are
    valid (those whose data files are then checked).

    Each section, each cut and each file is validated on its own with
    :func:`~robomill.io.manifest.parse_manifest` (files against the cuts that are valid), then
    duplicates across entries; the whole is validated last.
    """
    from robomill.io.manifest import EXPERIMENT_KEYS, parse_manifest
    from robomill.io.needs import chapter_list, file_kinds, required_experiment_keys

    good_exp = {"spindle_rpm": 1.0, "flutes": 1, "tool_diameter_mm": 1.0, "cut_length_mm": 1.0}
    files_data = data.get("files") if isinstance(data, Mapping) else None
    kinds = file_kinds(files_data) if isinstance(files_data, list) else set()
    if not isinstance(data, Mapping):
        try:
            parse_manifest(data, path)
        except RawDataError as exc:
            return [_line(exc)], []
    problems: list[str] = []
    for key in ("experiment", "cuts", "files"):
        if key not in data:
            problems.append(_line(RawDataError(path, f"top-level key '{key}' is missing",
                                               expected="top-level keys experiment, cuts, "
                                                        "files")))
    exp = data.get("experiment")
    if "experiment" in data:
        if not isinstance(exp, Mapping):
            problems.append(_line(RawDataError(path, f"{type(exp).__name__} found",
                                               where="experiment",
                                               expected="a mapping with keys "
                                                        + ", ".join(EXPERIMENT_KEYS))))
        else:
            for key in EXPERIMENT_KEYS:
                one = {k: v for k, v in good_exp.items() if k != key}
                if key in exp:
                    one[key] = exp[key]
                try:
                    parse_manifest({"experiment": one, "cuts": [], "files": []}, path)
                except RawDataError as exc:
                    problems.append(_line(exc))
    def entries(section: str, key: str, what: str, context: dict) -> list[dict]:
        """The valid, unique entries of one list section (cuts or files), each validated on
        its own with parse_manifest over ``context``; a problem line per bad entry."""
        items = data.get(section, [])
        if not isinstance(items, list):
            problems.append(_line(RawDataError(path, f"{section} is not a list", where=section,
                                               expected=f"a list of {section}")))
            return []
        seen: dict[str, int] = {}
        good: list[dict] = []
        for i, item in enumerate(items):
            try:
                parse_manifest({"experiment": good_exp, **context, section: [item]}, path,
                               kinds=kinds)
            except RawDataError as exc:
                problems.append(_line(_reindex(exc, section, i)))
                continue
            if item[key] in seen:
                problems.append(_line(RawDataError(
                    path, f"duplicate {what} {item[key]!r} (also {section}[{seen[item[key]]}])",
                    where=f"{section}[{i}].{key}",
                    expected="unique cut ids" if section == "cuts" else "each file listed once")))
                continue
            seen[item[key]] = i
            good.append(item)
        return good

    good_cuts = entries("cuts", "id", "cut id", {"files": []})
    good_files = entries("files", "path", "path", {"cuts": good_cuts})
    if isinstance(exp, Mapping):  # the keys the chapters this folder feeds read
        has_cuts = bool(data.get("cuts")) and isinstance(data.get("cuts"), list)
        for key, chapters in required_experiment_keys(kinds, has_cuts).items():
            if exp.get(key) is None:
                state = "null" if key in exp else "missing"
                problems.append(_line(RawDataError(
                    path, f"key '{key}' is {state}", where="experiment",
                    expected=f"{key}: {chapter_list(chapters)} of this folder need(s) it")))
    if not problems:
        try:
            parse_manifest(data, path)
        except RawDataError as exc:  # anything the per-entry passes cannot see
            problems.append(_line(exc))
    return problems, good_files


def file_problem(raw_dir: Path, entry: Mapping[str, Any], manifest_name: str = "manifest.yaml"
                 ) -> str | None:
    """The first problem of one listed file (existence, sha256, its reader), or ``None``."""
    from robomill.io.hashing import sha256_file

    rel = entry["path"]
    full = raw_dir / rel
    if not full.is_file():
        return _line(RawDataError(full, "file listed in the manifest does not exist",
                                  where=f"{manifest_name}: files[path={rel}]",
                                  expected="the file to be present"))
    actual = sha256_file(full)
    if actual != entry.get("sha256"):
        return _line(RawDataError(full, f"sha256 is {actual}, the manifest says "
                                  f"{entry.get('sha256')}",
                                  where=f"{manifest_name}: files[path={rel}].sha256",
                                  expected="the file unchanged since the manifest was written "
                                           "(restore it, or run robomill manifest on purpose)"))
    checker = CHECKERS.get(entry["kind"])
    if checker is None:
        return None
    try:
        checker(full, entry)
    except RawDataError as exc:
        return _line(exc)
    except (ValueError, KeyError, OSError) as exc:  # a reader's non-contract failure
        return _line(RawDataError(full, f"{type(exc).__name__}: {exc}",
                                  expected=f"a readable {entry['kind']} file"))
    return None


def cell_problems(raw_dir: Path) -> tuple[list[str], list[str]]:
    """Problems of ``cell.yaml`` and notes (the file absent, or this installation without
    :mod:`robomill.io.cell`)."""
    path = raw_dir / "cell.yaml"
    if not path.exists():
        return [], [f"{path}: no cell file in the folder"]
    try:
        from robomill.io.cell import read_cell
    except ImportError:
        return [], [f"{path}: not checked (this robomill has no robomill.io.cell reader)"]
    try:
        read_cell(path)
    except RawDataError as exc:
        return [_line(exc)], []
    return [], []


def unlisted_problems(raw_dir: Path, listed: Iterable[str],
                      ignore: list[str] | None = None) -> tuple[list[str], list[str]]:
    """Unlisted data files of the folder (those matching ``ignore``, the manifest's gitignore
    patterns, left aside): a problem line for each one inside a kind's folder (ingestion
    stops on them) and one note naming those elsewhere (ingestion warns and goes on)."""
    from robomill.cli.layout import KIND_FOLDERS, data_files, infer_file

    listed = set(listed)
    folders = set(KIND_FOLDERS.values()) | {Path(r).parts[0] for r in listed
                                            if len(Path(r).parts) > 1}
    out, elsewhere = [], []
    for p in data_files(raw_dir, ignore):
        rel = p.relative_to(raw_dir).as_posix()
        if rel in listed:
            continue
        if not (rel == "cell.yaml" or len(Path(rel).parts) > 1 and Path(rel).parts[0] in folders):
            elsewhere.append(rel)
            continue
        note = infer_file(raw_dir, p).note
        out.append(_line(RawDataError(
            p, "file is present but not listed in the manifest",
            where="manifest.yaml: files",
            expected=note or "every raw data file listed with kind and sha256 "
                             "(robomill manifest adds it)")))
    notes = [f"{len(elsewhere)} file(s) outside the data folders not listed (left out of the "
             f"study; list them under ignore: to silence this): {', '.join(elsewhere)}"
             ] if elsewhere else []
    return out, notes


def check_folder(raw_dir: str | Path, *, jobs: int = 2) -> tuple[list[str], list[str]]:
    """Every problem of raw folder ``raw_dir`` (one line each, manifest first, then the cell
    file, then the files in manifest order, then unlisted files) and the notes.

    ``jobs`` files are read at a time (threads: the readers spend their time in NumPy, HDF5
    and hashing, which release the GIL).
    """
    from robomill.cli.manifest import read_manifest_text

    raw_dir = Path(raw_dir)
    mpath = raw_dir / "manifest.yaml"
    if not raw_dir.is_dir():
        return [_line(RawDataError(raw_dir, "not a folder",
                                   expected="a raw folder with manifest.yaml"))], []
    if not mpath.exists():
        return [_line(RawDataError(mpath, "manifest does not exist",
                                   expected="manifest.yaml in the raw folder (robomill "
                                            "manifest writes it)"))], []
    try:
        data, _ = read_manifest_text(mpath)
    except RawDataError as exc:
        return [_line(exc)], []
    problems, valid = manifest_problems(data, mpath)
    cell, notes = cell_problems(raw_dir)
    problems += cell
    files = data.get("files") if isinstance(data, Mapping) and isinstance(
        data.get("files"), list) else []
    for kind in sorted({f["kind"] for f in valid if f["kind"] not in CHECKERS} - {"cell"}):
        notes.append(f"{kind} files: checked for presence and sha256 only (no reader for "
                     f"kind {kind!r} in robomill check)")
    robots = {f["robot"]: raw_dir / f["path"] for f in valid if f["kind"] == "robot"}
    valid = [{**f, "_robot_path": robots.get(f.get("robot"))} if f["kind"] == "stiffness"
             else f for f in valid]
    with ThreadPoolExecutor(max(1, jobs)) as pool:
        results = list(pool.map(lambda f: file_problem(raw_dir, f, mpath.name), valid))
    problems += [r for r in results if r]
    ignore = data.get("ignore") if isinstance(data, Mapping) else None
    unlisted, elsewhere = unlisted_problems(
        raw_dir, [f["path"] for f in files if isinstance(f, Mapping) and "path" in f],
        ignore if isinstance(ignore, list) and all(isinstance(q, str) for q in ignore)
        else None)
    return problems + unlisted, notes + elsewhere


def add_parser(sub: Any) -> None:  # what ArgumentParser.add_subparsers() returns
    p = sub.add_parser("check", help=HELP, description=HELP + ". Each line reads "
                       "'file: where: problem (expected ...)'.")
    p.add_argument("dir", type=Path, metavar="DIR", help="the raw folder")
    p.add_argument("-j", "--jobs", type=int, default=2, help="files read at a time (default 2)")
    p.add_argument("-q", "--quiet", action="store_true", help="print problems only")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    t0 = time.perf_counter()
    problems, notes = check_folder(args.dir, jobs=args.jobs)
    for line in problems:
        print(line)
    if not args.quiet:
        for line in notes:
            print(f"note: {line}")
        print(f"{args.dir}: {len(problems)} problem(s) ({time.perf_counter() - t0:.1f} s)")
    return 1 if problems else 0
