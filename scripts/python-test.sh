#!/usr/bin/env bash
# The Python package's tests: a venv under the repository (.venv, ignored
# by git) with the test dependencies from PyPI, the package built by
# maturin from pyproject.toml into it (release profile, in cargo's target
# dir, so a second run rebuilds only what changed), then pytest on
# python/tests. Arguments go to pytest. Called by scripts/test.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
venv=${WMSLICE_VENV:-.venv}
if [ ! -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install -q --disable-pip-version-check \
  "maturin>=1.9,<2" numpy pytest "dask[distributed]" trimesh "shapely>=2" manifold3d scipy networkx
# Built without build isolation: maturin is in the venv already (on PATH).
export PATH="$(cd "$venv" && pwd)/bin:$PATH"
"$venv/bin/python" -m pip install -q --disable-pip-version-check --no-build-isolation --force-reinstall --no-deps .
"$venv/bin/python" -m pytest -q -p no:cacheprovider python/tests "$@"
