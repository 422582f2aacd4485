#!/usr/bin/env bash
# The crate beside heyoka, REBOUND (+REBOUNDx) and SciPy on the problems of the performance
# claims: creates a virtual environment with the pinned peers (requirements.txt), builds the
# crate's side (examples/peers_crate.rs), runs every problem and writes out/peers.md (one
# side-by-side table) and out/<problem>.svg (work-precision figures) with out/<problem>.csv;
# then the outer Solar System beside REBOUND's WHFast (nbody.py: out/nbody.md, nbody.png/.svg,
# nbody.csv).
#
#   benches/peers/run.sh            # every problem
#   benches/peers/run.sh j2_        # problems whose name contains "j2_"
#   benches/peers/run.sh nbody      # the outer Solar System only
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="$here/.venv"
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/pip" install --quiet --disable-pip-version-check -r "$here/requirements.txt"
(cd "$root" && cargo build --release --quiet --example peers_crate)
uptime
binary="$root/target/release/examples/peers_crate"
if [ "${1:-}" != nbody ]; then
    "$venv/bin/python" "$here/peers.py" "$binary" "$here/out" "${1:-}"
fi
if [ -z "${1:-}" ] || [ "${1:-}" = nbody ]; then
    "$venv/bin/python" "$here/nbody.py" "$binary" "$here/out"
fi
uptime
