"""The ``robomill`` command: raw folders of real measurements, from native exports to a
folder the pipeline reads (``docs/data-contract.md``).

Verbs (each with ``--help``):

- ``robomill init DIR``: a raw-folder skeleton with commented templates;
- ``robomill import FORMAT SRC... --to DIR``: native exports converted into the contract;
- ``robomill manifest DIR``: write or update ``manifest.yaml`` from the files;
- ``robomill check DIR``: every problem of the folder, one line each (exit status 1 if any);
- ``robomill plan DIR --request plan.yaml``: the next cuts from the study's measurements;
- ``robomill listen FILE [--rpm N --flutes Z]``: the chatter verdict of one recording;
- ``robomill predict STUDY CUTS [--out FILE]``: any cuts predicted from a study's results.

Then ``snakemake -j2 all --config data=DIR`` runs the study on it.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

VERBS = ("init", "import", "manifest", "check", "plan", "listen", "predict")


def build_parser() -> argparse.ArgumentParser:
    """The parser of the ``robomill`` command."""
    from robomill.cli import check, importing, init, listen, manifest, plan, predict

    parser = argparse.ArgumentParser(
        prog="robomill", description="Prepare a folder of real measurements for the robomill "
        "pipeline: init, import, manifest, check; then snakemake -j2 all --config data=DIR.")
    sub = parser.add_subparsers(dest="verb", metavar="VERB", required=True)
    for module in (init, importing, manifest, check, plan, listen, predict):
        module.add_parser(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command; returns the exit status (0 ok, 1 problems found or nothing done,
    2 usage error)."""
    parser = build_parser()
    args = parser.parse_args(sys.argv[1:] if argv is None else list(argv))
    return int(args.run(args))
