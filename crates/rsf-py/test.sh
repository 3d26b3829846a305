#!/usr/bin/env bash
# Builds the Python package into a virtual environment and runs its tests (README's test
# command calls this after the cargo tests). RSF_PY_VENV chooses the environment.
set -euo pipefail
cd "$(dirname "$0")/../.."
VENV=${RSF_PY_VENV:-target/pyvenv}
[ -x "$VENV/bin/python" ] || python3 -m venv "$VENV"
"$VENV/bin/pip" install -q --disable-pip-version-check maturin numpy pytest pandas matplotlib "dask[distributed]"
"$VENV/bin/pip" install -q --disable-pip-version-check ./crates/rsf-py    # maturin builds the extension
cargo build --release -q -p rsf-cli                                           # the tests compare with the CLI
"$VENV/bin/python" -m pytest -q crates/rsf-py/tests
