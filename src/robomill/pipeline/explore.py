"""``make explore``: from a finished run into a live notebook.

``python -m robomill.pipeline.explore`` opens ``notebooks/explore.ipynb`` in Jupyter Lab;
``python -m robomill.pipeline.explore ch2`` writes ``results/explore/<chapter>.ipynb``, a copy
of the chapter notebook with the current run's artefact paths injected as its parameters (read from
the executed chapter's papermill metadata), and opens it, so every figure can be remade and
changed live. ``--no-launch`` only prepares the notebook and prints its path.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

import nbformat


def chapter_parameters(executed: Path) -> dict:
    """The parameters a chapter was run with (papermill metadata of the executed notebook)."""
    nb = nbformat.read(executed, as_version=4)
    return dict(nb.metadata.get("papermill", {}).get("parameters", {}))


def prepare_chapter(chapter: str, *, repo: Path, results: Path) -> list[Path]:
    """Parameterized copies of the chapter notebook(s) ``chapter`` names: the chapter itself
    (``ch0``) or the chapters of a group (``ch3``: ``ch3_forces``, ``ch3_straightness``, …)."""
    from papermill.iorw import load_notebook_node
    from papermill.parameterize import parameterize_notebook

    folder = results / "chapters"
    executed = sorted({*folder.glob(f"{chapter}.ipynb"), *folder.glob(f"{chapter}_*.ipynb")})
    if not executed:
        raise SystemExit(f"no executed notebook for {chapter!r} under {results / 'chapters'}: "
                         f"build it first (snakemake -j2 {chapter})")
    out = []
    for ex in executed:
        params = chapter_parameters(ex)
        base = results.resolve().parent  # the run's working directory
        for key, value in params.items():  # relative artefact paths → absolute
            if isinstance(value, str) and value and (base / value).exists():
                params[key] = str(base / value)
        params["fig_dir"] = str((results / "explore" / "figures" / ex.stem).resolve())
        source = repo / "notebooks" / ex.name
        nb = parameterize_notebook(load_notebook_node(str(source)), params)
        dst = results / "explore" / ex.name
        dst.parent.mkdir(parents=True, exist_ok=True)
        nbformat.write(nb, dst)
        out.append(dst)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("chapter", nargs="?", default="", help="e.g. ch2 (empty: explore.ipynb)")
    ap.add_argument("--results", default="results")
    ap.add_argument("--no-launch", action="store_true")
    args = ap.parse_args(argv)
    from robomill.pipeline.config import repo_root

    repo = repo_root()
    if args.chapter:
        paths = prepare_chapter(args.chapter, repo=repo, results=Path(args.results))
    else:
        paths = [repo / "notebooks" / "explore.ipynb"]
    for p in paths:
        print(p)
    if args.no_launch:
        return 0
    jupyter = Path(sys.executable).with_name("jupyter")
    return subprocess.call([str(jupyter), "lab", *map(str, paths)])


if __name__ == "__main__":
    raise SystemExit(main())
