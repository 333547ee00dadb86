#!/usr/bin/env bash
# Factory presets' levels through the plugin, as a musician meets them:
# `bash plugin/ci/preset_levels.sh HOST PLUGIN.clap OUTDIR`, called by .ci/plugin.
# Each assets/presets/*.toml becomes a plugin state blob (8-byte little-endian length, then the
# JSON state; every key of its [params] table: floats as f32, integers as i32, enumeration names
# as strings, which the plugin's state repair converts and logs). The CLAP host loads it and
# plays the root key at velocity 127, and keys 36 to 96 at velocities 127 and 40, each held 1 s
# (the tanpura drone: one pluck cycle, its strings plucked one after another) and released for
# 1 s at 48 kHz; the sitar with its taraf and the drone at the keys within an octave of their
# root (their strings are retuned by tension and tuned by ear over that octave each way). The bounds are those of tests/engine/preset_levels.rs (the
# engine alone): every sample finite and within 0 dBFS; the root key at 127 peaks between -6
# and -1 dBFS; every key at 127 within 6 dB of the root's peak; velocity 40 quieter than 127;
# the last 0.1 s at least 20 dB under the note's peak.
set -euo pipefail
HOST=$1
CLAP=$2
OUT=$3
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT"

# One state blob per preset; prints "stem root_key held_seconds keys" lines (keys comma-separated).
python3 - "$ROOT/plugin/ci" "$ROOT/assets/presets" "$OUT" >"$OUT/presets.txt" <<'PY'
import pathlib, sys
sys.path.insert(0, sys.argv[1])
from plugin_state import preset_blob, preset_params
src, out = pathlib.Path(sys.argv[2]), pathlib.Path(sys.argv[3])
for path in sorted(src.glob("*.toml")):
    state, root = preset_blob(path)
    (out / f"{path.stem}.state").write_bytes(state)
    params = preset_params(path)
    held = float(params.get("drone_cycle", 4.0)) if params.get("model") == "tanpura-drone" else 1.0
    keys = [36, 48, 60, 72, 84, 96]
    if params.get("model") in ("sitar-taraf", "tanpura-drone"):
        keys = [k for k in keys if abs(k - root) <= 12]
    print(path.stem, root, held, ",".join(map(str, keys)))
PY

SOFT=0.31496063 # velocity 40 of 127
render() {
    local stem=$1 key=$2 vel=$3 tag=$4
    local total
    total=$(python3 -c "print($HELD + 1.0)")
    timeout 300 "$HOST" render "$CLAP" "$OUT/$stem-$key-$tag.wav" --seconds "$total" --note-off "$HELD" \
        --load-state "$OUT/$stem.state" --expect-load ok --key "$key" --velocity "$vel" \
        >"$OUT/$stem-$key-$tag.out" 2>"$OUT/$stem-$key-$tag.log" || {
        echo "$stem: render of key $key at velocity $tag failed"
        cat "$OUT/$stem-$key-$tag.out" "$OUT/$stem-$key-$tag.log"
        exit 1
    }
}
while read -r stem root HELD KEYS; do
    echo "-- preset $stem (root key $root, held $HELD s, keys $KEYS)"
    render "$stem" "$root" 1.0 127
    for key in ${KEYS//,/ }; do
        render "$stem" "$key" 1.0 127
        render "$stem" "$key" "$SOFT" 40
    done
done <"$OUT/presets.txt"

python3 - "$OUT" <<'PY'
import math, pathlib, struct, sys
out = pathlib.Path(sys.argv[1])

def read_wav(path):
    """(rate, channels, interleaved float32 samples) of a 32-bit float WAV."""
    data = path.read_bytes()
    if data[:4] != b"RIFF" or data[8:12] != b"WAVE":
        sys.exit(f"{path}: not a RIFF WAVE file")
    pos, fmt, samples = 12, None, None
    while pos + 8 <= len(data):
        cid, size = data[pos:pos + 4], struct.unpack_from("<I", data, pos + 4)[0]
        body = data[pos + 8:pos + 8 + size]
        if cid == b"fmt ":
            fmt = struct.unpack_from("<HHIIHH", body)
        elif cid == b"data":
            samples = body
        pos += 8 + size + (size & 1)
    if fmt is None or samples is None:
        sys.exit(f"{path}: no fmt or data chunk")
    tag, channels, rate, _, _, bits = fmt
    if bits != 32 or tag not in (3, 0xFFFE):
        sys.exit(f"{path}: format tag {tag}, {bits} bits: expected 32-bit float")
    n = len(samples) // 4
    return rate, channels, struct.unpack(f"<{n}f", samples[:4 * n])

def db(x):
    return 20.0 * math.log10(max(x, 1e-12))

def levels(stem, key, tag, failures):
    """Peak (dBFS) of the whole render and of its last 0.1 s."""
    path = out / f"{stem}-{key}-{tag}.wav"
    rate, ch, x = read_wav(path)
    if rate != 48000:
        failures.append(f"{stem} key {key} velocity {tag}: rendered at {rate} Hz, not 48000")
    bad = [v for v in x if not math.isfinite(v) or abs(v) > 1.0]
    if bad:
        failures.append(f"{stem} key {key} velocity {tag}: {len(bad)} samples non-finite or "
                        f"above 0 dBFS (first {bad[0]})")
        return 0.0, 0.0
    tail = len(x) - ch * int(0.1 * rate)
    return db(max(map(abs, x))), db(max(map(abs, x[tail:])))

failures = []
for line in (out / "presets.txt").read_text().splitlines():
    fields = line.split()
    stem, root = fields[0], int(fields[1])
    keys = [int(k) for k in fields[3].split(",")]
    root_peak, _ = levels(stem, root, "127", failures)
    print(f"{stem}: root key {root} at velocity 127 peaks at {root_peak:.1f} dBFS")
    if not -6.0 <= root_peak <= -1.0:
        failures.append(f"{stem} root key {root} velocity 127: peak {root_peak:.1f} dBFS "
                        "outside [-6, -1]")
    print("    key  127 dBFS  re root   40 dBFS  last 0.1 s re peak")
    for key in keys:
        loud, tail = levels(stem, key, "127", failures)
        soft, soft_tail = levels(stem, key, "40", failures)
        print(f"    {key:3d}  {loud:8.1f}  {loud - root_peak:+7.1f}  {soft:8.1f}  "
              f"{tail - loud:+8.1f} dB")
        if abs(loud - root_peak) > 6.0:
            failures.append(f"{stem} key {key} velocity 127: {loud - root_peak:+.1f} dB re "
                            "the root key's peak, outside ±6 dB")
        if soft >= loud:
            failures.append(f"{stem} key {key}: velocity 40 peaks at {soft:.1f} dBFS, not "
                            f"under velocity 127's {loud:.1f}")
        if tail > loud - 20.0:
            failures.append(f"{stem} key {key} velocity 127: last 0.1 s at {tail - loud:+.1f} "
                            "dB re the peak, not 20 dB under")
        if soft_tail > soft - 20.0:
            failures.append(f"{stem} key {key} velocity 40: last 0.1 s at "
                            f"{soft_tail - soft:+.1f} dB re the peak, not 20 dB under")
if failures:
    print("preset levels FAILED:")
    print("\n".join(f"  {f}" for f in failures))
    sys.exit(1)
print("preset levels: every factory preset within bounds through the plugin")
PY
