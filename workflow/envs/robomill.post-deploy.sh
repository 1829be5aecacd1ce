#!/usr/bin/env bash
# Snakemake runs this once after creating the conda env: install the robomill package itself.
set -euo pipefail
pip install --no-deps -e "$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
