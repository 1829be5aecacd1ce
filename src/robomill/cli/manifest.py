"""``robomill manifest DIR``: write or update ``DIR/manifest.yaml`` from the folder's files.

Builds on :func:`robomill.io.manifest.build_manifest` (every sha256 computed from the bytes);
the kind and metadata of each file come from :func:`robomill.cli.layout.infer_file`.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import yaml

from robomill.cli.layout import cut_stub, data_files, infer_file, merge_entry
from robomill.errors import RawDataError

HELP = "scan a raw folder and write or update its manifest.yaml (kinds, metadata, sha256)"


def read_manifest_text(path: Path) -> tuple[dict[str, Any], str]:
    """The manifest mapping as the user wrote it (not validated) and its leading comment block
    (kept when the file is rewritten); ``({}, "")`` when there is no manifest yet.

    Raises
    ------
    RawDataError
        The file is not valid YAML or not a mapping (nothing is rewritten then).
    """
    from robomill.io.manifest import SAFE_LOADER

    if not path.exists():
        return {}, ""
    text = path.read_text()
    try:
        data = yaml.load(text, Loader=SAFE_LOADER)
    except yaml.YAMLError as exc:
        raise RawDataError(path, f"not valid YAML: {' '.join(str(exc).split())}",
                           expected="a YAML mapping (fix it by hand; it was not rewritten)"
                           ) from None
    if data is None:
        data = {}
    if not isinstance(data, dict):
        raise RawDataError(path, f"{type(data).__name__} found at the top level",
                           expected="a YAML mapping with experiment, cuts, files")
    header = []
    for line in text.splitlines():
        if line.startswith("#") or not line.strip():
            header.append(line)
        else:
            break
    return data, "\n".join(header).rstrip() + ("\n" if header else "")


def update_manifest(raw_dir: str | Path) -> tuple[dict[str, Any], list[str], list[str]]:
    """The updated manifest mapping of ``raw_dir`` and two lists of lines: what changed, and
    what could not be inferred (to fill in by hand).

    What the user wrote is kept: existing entries keep their values (an inferred value that
    disagrees is reported, not applied), listed files that are gone stay listed (reported),
    unknown top-level keys stay. Every listed file's sha256 is recomputed from its bytes.
    Required keys that cannot be inferred are written as ``null``.
    """
    from robomill.io.kinds import KIND_KEYS
    from robomill.io.manifest import build_manifest
    from robomill.io.needs import (
        chapter_list,
        file_kinds,
        required_cut_keys,
        required_experiment_keys,
    )

    raw_dir = Path(raw_dir)
    mpath = raw_dir / "manifest.yaml"
    old, _ = read_manifest_text(mpath)
    changes: list[str] = []
    todo: list[str] = []
    old_files = old.get("files") if isinstance(old.get("files"), list) else []
    by_path = {f["path"]: f for f in old_files if isinstance(f, dict)
               and isinstance(f.get("path"), str)}
    for i, f in enumerate(old_files):
        if not (isinstance(f, dict) and isinstance(f.get("path"), str)):
            todo.append(f"manifest.yaml: files[{i}] is {f!r}, not an entry with a path: "
                        "dropped (list the file again)")
    entries: dict[str, dict[str, Any]] = {}
    patterns = old.get("ignore")
    if patterns is not None and not (isinstance(patterns, list)
                                     and all(isinstance(q, str) for q in patterns)):
        raise RawDataError(mpath, f"ignore is {patterns!r}", where="ignore",
                           expected="a list of patterns as in .gitignore (fix it by hand; "
                                    "it was not rewritten)")
    for p in data_files(raw_dir, patterns):
        inf = infer_file(raw_dir, p)
        rel = inf.path
        if inf.note:
            todo.append(f"{rel}: {inf.note}")
            continue
        if not inf.entry:
            if rel in by_path:  # the user listed it: keep it as written
                entries[rel] = dict(by_path[rel])
            else:
                todo.append(f"{rel}: not listed: {'; '.join(inf.missing)}")
            continue
        if rel in by_path:
            merged, disagree = merge_entry(by_path[rel], inf.entry)
            changes += [f"{rel}: {d}" for d in disagree]
        else:
            merged = dict(inf.entry)
            changes.append(f"{rel}: added as {merged['kind']}")
        for key in KIND_KEYS.get(merged.get("kind"), {}):
            if merged.get(key) is None:
                merged[key] = None
                todo.append(f"{rel}: {key} not inferred (write it in manifest.yaml)")
        entries[rel] = merged
    for rel in by_path:
        if rel not in entries and not (raw_dir / rel).exists():
            todo.append(f"{rel}: listed in manifest.yaml but the file does not exist "
                        "(kept; remove the entry or restore the file)")
    order = [p for p in by_path if p in entries] + sorted(p for p in entries if p not in by_path)
    present = [entries[p] for p in order]
    old_sha = {p: by_path[p].get("sha256") for p in by_path}
    for e in present:
        e.pop("sha256", None)
    built = build_manifest({}, [], present, raw_dir)
    for e in built["files"]:
        if e["path"] in old_sha and old_sha[e["path"]] not in (None, e["sha256"]):
            changes.append(f"{e['path']}: sha256 changed (the file was modified since the "
                           "manifest was written)")
    # in the user's order, new files after; files that are gone (or native exports the user
    # listed) stay as the user wrote them (check reports them)
    fresh = {e["path"]: e for e in built["files"]}
    files = [fresh.get(p, dict(f)) for p, f in by_path.items()] + [
        fresh[p] for p in order if p not in by_path]

    experiment = dict(old.get("experiment") or {})
    cuts = [dict(c) for c in old.get("cuts") or [] if isinstance(c, dict)]
    known = {c.get("id") for c in cuts}
    for f in files:
        cid = f.get("cut")
        if isinstance(cid, str) and cid not in known:
            try:
                cuts.append(cut_stub(cid))
            except TypeError:
                continue
            known.add(cid)
            changes.append(f"manifest.yaml: cut {cid} added" + (
                " (set, segment, direction from the id)" if "set" in cuts[-1] else ""))
    # only the keys of the chapters this folder's kinds feed (robomill.io.needs)
    kinds = file_kinds(files)
    for key, chapters in required_experiment_keys(kinds, bool(cuts)).items():
        if experiment.get(key) is None:
            experiment[key] = None
            todo.append(f"manifest.yaml: experiment.{key} not inferred (write it; "
                        f"{chapter_list(chapters)} need(s) it)")
    for i, c in enumerate(cuts):
        for key, chapters in required_cut_keys(kinds).items():
            if c.get(key) is None:
                c[key] = None
                todo.append(f"manifest.yaml: cuts[{i}] ({c.get('id')}): {key} not inferred "
                            f"(write it; {chapter_list(chapters)} need(s) it)")
        if (required_cut_keys(kinds) and c.get("direction") is None
                and c.get("direction_deg") is None):
            c.setdefault("direction", None)
            todo.append(f"manifest.yaml: cuts[{i}] ({c.get('id')}): direction not inferred "
                        "(write direction px, mx, py or my, or direction_deg)")
    out = {"experiment": experiment, "cuts": cuts, "files": files}
    # unknown top-level keys stay, ignore: (the user's gitignore patterns) among them
    out.update({k: v for k, v in old.items() if k not in out})
    return out, changes, todo


def write_manifest_text(manifest: dict[str, Any], path: Path, header: str = "") -> Path:
    """Write ``manifest`` as YAML atomically, after ``header`` (the user's leading comments)."""
    from robomill.io.atomic import atomic_path

    with atomic_path(path) as tmp:
        tmp.write_text(header + yaml.safe_dump(manifest, sort_keys=False, width=100))
    return path


def add_parser(sub: Any) -> None:  # what ArgumentParser.add_subparsers() returns
    p = sub.add_parser("manifest", help=HELP, description=HELP + ". What you already wrote is "
                       "kept; what could not be inferred is listed (and written as null).")
    p.add_argument("dir", type=Path, metavar="DIR", help="the raw folder")
    p.add_argument("--dry-run", action="store_true",
                   help="report what would change without writing manifest.yaml")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    raw_dir: Path = args.dir
    if not raw_dir.is_dir():
        print(f"{raw_dir}: not a folder (expected a raw folder; robomill init {raw_dir} makes "
              "one)")
        return 1
    mpath = raw_dir / "manifest.yaml"
    try:
        _, header = read_manifest_text(mpath)
        manifest, changes, todo = update_manifest(raw_dir)
    except RawDataError as exc:
        print(exc)
        return 1
    for line in changes:
        print(line)
    if not args.dry_run:
        write_manifest_text(manifest, mpath, header)
    n = len(manifest["files"])
    print(f"{mpath}: {'would list' if args.dry_run else 'lists'} {n} file(s), "
          f"{len(manifest['cuts'])} cut(s)")
    if todo:
        print(f"could not infer ({len(todo)}):")
        for line in todo:
            print(f"  {line}")
    return 0
