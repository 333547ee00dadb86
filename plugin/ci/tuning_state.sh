#!/usr/bin/env bash
# Microtuning through the CLAP host's state path:
# `bash plugin/ci/tuning_state.sh HOST PLUGIN.clap OUTDIR`, called by .ci/plugin.
# A state blob holding a 19-EDO scale (the plugin's persisted `tuning` field) is loaded and key
# 79 rendered: 19 steps above key 60, it must sound an octave above it, i.e. at the pitch 12-TET
# plays on key 72. `compare` checks the two renders with its default bounds (level 2e-5 dB,
# log-spectral distance 1e-3 dB, strongest partial 5e-4 cents): the voices take the pitch ratio
# to the preset's root key from the table, so the same pitch must give the same sound. A blob
# whose stored scale no longer parses must load, log the error and play 12-TET (key 79 as 12-TET
# key 79), and a blob without the field (saved before tunings) plays 12-TET.
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
def write(name, fields):
    with open(f"{out}/{name}.state", "wb") as f:
        f.write(blob(state_body(fields=fields)))
edo19 = "! 19edo.scl\n19-EDO\n19\n" + "".join(f"{1200 * i / 19:.6f}\n" for i in range(1, 19)) + "2/1\n"
tuning = lambda name, text: json.dumps({"scl": {"name": name, "text": text}, "kbm": None})
write("edo19", {"tuning": tuning("19edo.scl", edo19)})
write("bad-scale", {"tuning": tuning("broken.scl", "Broken\n3\n100.0\nnot a pitch\n")})
write("no-tuning", {})
PY

render() { # NAME STATE KEY
    timeout 300 "$HOST" render "$CLAP" "$OUT/$1.wav" --seconds 1.5 --note-off 0.6 --key "$3" \
        --load-state "$OUT/$2.state" --expect-load ok >"$OUT/$1.out" 2>"$OUT/$1.log" \
        || { cat "$OUT/$1.out" "$OUT/$1.log"; exit 1; }
    timeout 60 "$HOST" check "$OUT/$1.wav" --note-off 0.6 >/dev/null
}
render edo19-k79 edo19 79
render tet-k72 no-tuning 72
render tet-k79 no-tuning 79
render bad-k79 bad-scale 79
echo "-- 19-EDO key 79 against 12-TET key 72 (an octave above key 60)"
timeout 60 "$HOST" compare "$OUT/edo19-k79.wav" "$OUT/tet-k72.wav" | tee "$OUT/edo19-vs-tet72.log"
# The comparison can fail: 12-TET key 79 against key 72 (7 semitones apart) must not pass.
if timeout 60 "$HOST" compare "$OUT/tet-k79.wav" "$OUT/tet-k72.wav" >"$OUT/tet79-vs-tet72.log" 2>&1; then
    echo "compare passed 12-TET key 79 against key 72"; exit 1
fi
echo "-- bad stored scale: key 79 plays 12-TET"
grep -q "tuning file broken.scl" "$OUT/bad-k79.log" \
    || { echo "plugin log of bad-k79 lacks the scale's error"; cat "$OUT/bad-k79.log"; exit 1; }
timeout 60 "$HOST" compare "$OUT/bad-k79.wav" "$OUT/tet-k79.wav" | tee "$OUT/bad-vs-tet79.log"
