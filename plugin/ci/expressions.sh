#!/usr/bin/env bash
# Per-note expressions measured from the plugin's sound through the CLAP host:
# `bash plugin/ci/expressions.sh HOST PLUGIN.clap OUTDIR`, called by .ci/plugin.
# The state is the factory preset sitar-b0 (ideal B = 0 string) with its bridge out of reach
# (curvature 1 /m over 1 % of the length, as tests/engine/pitch_from_sound.rs), polyphony 2,
# output gain -12 dB (two notes at velocity 1 stay clear of the output stage) and threads 1: a
# harmonic string with a closed-form fundamental at its root key. Threads 1 (the audio thread
# alone, as the engine's pitch tests): with the default 0 the voice pool's bounded wait leaves a
# late worker's chunk out of the mix (docs/architecture.md), which an offline render on the
# loaded 2-core machine hits: two renders then differ and the fundamentals smear by 2e-4 to
# 1.3e-3, where the audio thread alone measures 1e-8. `expression` renders CLAP tuning and
# volume expressions on two overlapping notes and MPE member-channel bends, and measures each
# note's fundamental and level (its module doc has the estimator and tolerances), a CLAP
# polyphonic modulation of one note's damping (its decay rate), a CLAP pressure on one note
# (the hand: a faster decay) and the plugin's note ends
# after the note-offs (release T60 0.1 s; plugin/test-host/src/polymod.rs). Then each
# deliberately broken input (an expression or the MPE configuration left out) must fail.
set -euo pipefail
HOST=$1
CLAP=$2
OUT=$3
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"

python3 - "$ROOT/plugin/ci" "$ROOT/assets/presets/sitar-b0.toml" "$OUT/ideal-string.state" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from plugin_state import preset_blob
state, _ = preset_blob(sys.argv[2], bridge_curvature=1.0, bridge_fraction=0.01, polyphony=2,
                       gain=-12.0, threads=1, release_t60=0.1)
open(sys.argv[3], "wb").write(state)
PY

timeout 600 "$HOST" expression "$CLAP" "$OUT/ideal-string.state" --out "$OUT" \
    2>"$OUT/expression.log" | tee "$OUT/expression.out"
for what in tuning volume mpe-config member-bend poly-mod note-off pressure; do
    if timeout 600 "$HOST" expression "$CLAP" "$OUT/ideal-string.state" --break "$what" \
        >"$OUT/broken-$what.out" 2>"$OUT/broken-$what.log"; then
        echo "expression passed with the $what left out"
        cat "$OUT/broken-$what.out"
        exit 1
    fi
    echo "-- $what left out: fails as it must"
    grep '^FAIL' "$OUT/broken-$what.out"
done
