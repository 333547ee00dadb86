#!/usr/bin/env bash
# Bad plugin state blobs through the CLAP host's state path:
# `bash plugin/ci/state_blobs.sh HOST PLUGIN.clap OUTDIR`, called by .ci/plugin.
# Each blob is the stream a host stores for a nice-plug plugin (8-byte little-endian length, then
# the JSON state). Unparsable blobs (corrupt, truncated, bad length, empty) must be refused with
# every parameter unchanged; parsed but bad ones (wrong types, old version with missing
# parameters, out-of-range values) must load with the repaired values below and the plugin must
# log each repair. After every load the instance renders a note that must sound and decay.
set -euo pipefail
HOST=$1
CLAP=$2
OUT=$3
mkdir -p "$OUT"

python3 - "$(dirname "$0")" "$OUT" <<'PY'
import json, sys
sys.path.insert(0, sys.argv[1])
from plugin_state import blob, state_body
out = sys.argv[2]
def write(name, body, length=None):
    with open(f"{out}/{name}.state", "wb") as f:
        f.write(blob(body, length))
good = state_body({"size": {"f32": 0.5}, "model": {"i32": 0}}, {"preset": "\"gong-40N\""})
write("corrupt", b'{"version": "0.1.0", "params": {"size": {"f32": 0.5}, ###}')
write("truncated", good[: len(good) // 2], length=len(good))
write("bad-length", good, length=1 << 62)
write("empty", b"")
write("wrong-types", state_body({
    "model": {"string": "sitar"}, "modes": {"f32": 100.0}, "gain": {"bool": True},
    "tension": {"i32": 200}, "polyphony": {"f32": 2.5}}))
write("old-version", json.dumps({"version": "0.0.1", "params": {"size": {"f32": 0.5}},
                                 "fields": {}}).encode())
write("out-of-range", state_body({
    "size": {"f32": 100.0}, "polyphony": {"i32": 99}, "sim_rate": {"f32": -5.0},
    "no_such_parameter": {"f32": 1.0}}))
PY

run() {
    local name=$1 expect=$2
    shift 2
    echo "-- state blob: $name (expect $expect)"
    timeout 300 "$HOST" render "$CLAP" "$OUT/$name.wav" --seconds 1.5 --note-off 0.4 \
        --load-state "$OUT/$name.state" --expect-load "$expect" "$@" \
        >"$OUT/$name.out" 2>"$OUT/$name.log" || { cat "$OUT/$name.out" "$OUT/$name.log"; exit 1; }
    grep '^state ' "$OUT/$name.out"
    timeout 60 "$HOST" check "$OUT/$name.wav" --note-off 0.4 >/dev/null
}
logged() {
    grep -q -- "$2" "$OUT/$1.log" || { echo "plugin log of $1 lacks: $2"; cat "$OUT/$1.log"; exit 1; }
}

for b in corrupt truncated bad-length empty; do run "$b" refused; done
# Modes 100: the sitar bridge (6 mm) must span a grid spacing (0.4 m / (modes + 1)).
run wrong-types ok --expect "Model=sitar" --expect "Modes=100" --expect "Output gain=0" \
    --expect "Tension=200" --expect "Polyphony=4"
logged wrong-types '`model` = "sitar" has the wrong type: converted to 3'
logged wrong-types '`gain` = true has the wrong type: not a valid value, using the default 0'
run old-version ok --expect "Size=0.5" --expect "Release T60=2" --expect "Model=gong"
logged old-version 'saved by version `0.0.1`'
logged old-version 'plugin state has no `release_t60`: using the default 2'
run out-of-range ok --expect "Size=3" --expect "Polyphony=16" --expect "Simulation rate=8000"
logged out-of-range '`size` = 100 is outside \[0.05, 3\]: clamped to 3'
logged out-of-range 'unknown parameter `no_such_parameter`'
echo "state blobs: 4 refused unchanged, 3 repaired and logged, every instance played"
