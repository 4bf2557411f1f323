#!/usr/bin/env bash
# The Python client against a real planner-server: a venv with the iceoryx2 binding
# (target/py-venv), the release binaries, then the test and the example. Exits non-zero
# on any failure.
set -euo pipefail
cd "$(dirname "$0")/../.."

venv=target/py-venv
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
# Pinned: the client relies on 0.10.0's Slice.len() counting bytes (iceoryx2 issue 1533).
"$venv/bin/pip" install --quiet --disable-pip-version-check iceoryx2==0.10.0

cargo build --release -p planner-ipc --bins
export PLANNER_SERVER=target/release/planner-server

timeout 300 "$venv/bin/python" clients/python/test_client.py
timeout 300 "$venv/bin/python" clients/python/example.py --spawn-server
