#!/usr/bin/env bash
# Regenerates the tables and figures of docs/ACCURACY.md (one command: `bash docs/accuracy.sh`;
# add `--long` for the lecture's 2 MHz sitar rate study, about 4 minutes of CPU).
# Writes docs/figures/<scene>-accuracy-<setting>.{csv,json,png} and prints each table.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
N=${CARGO_TARGET_DIR:-target}/release/noether
OUT=docs/figures
# The 0.3 m gong (the full model of gong-auto.toml: 100 transverse and 30 in-plane modes,
# 48 kHz, 60 N strike), 0.3 s; files named gong-accuracy-*.
GONG=(assets/scenes/gong-auto.toml --set quality.mode=as-given --set name=gong
    --set output.seconds=0.3 --out "$OUT")
"$N" accuracy "${GONG[@]}" --vary scheme --values conservative,conservative-exact,stormer-verlet,sav
"$N" accuracy "${GONG[@]}" --vary rate --values 12000,24000,48000 --reference-rate 96000
"$N" accuracy "${GONG[@]}" --vary modes --values 25,50,100
"$N" accuracy "${GONG[@]}" --vary psi --values 5,10,20,30
# The default scene, the lecture's gong over its full band (docs/scenes.md, "The default gong"),
# 0.6 s: its simulation rate and in-plane modes; files named default-gong-accuracy-*.
DEF=(assets/scenes/gong.toml --set name=default-gong --set output.seconds=0.6 --out "$OUT")
"$N" accuracy "${DEF[@]}" --vary rate --values 12000,14000,16000,20000 --reference-rate 32000
"$N" accuracy "${DEF[@]}" --vary psi --values 15,20,30 \
    --reference-set plate.n_psi=60 --reference-set plate.sim_rate=32000
# The musical sitar (384 kHz), 0.2 s: how many modes the buzz needs.
"$N" accuracy assets/scenes/sitar.toml --set output.seconds=0.2 --out "$OUT" \
    --vary modes --values 110,220,440 --reference-set string.modes=880
# The factory presets as the instrument plays them (root key, one voice, 48 kHz, 0.3 s, through
# the engine): modes and simulation rate around each preset's own setting.
P=(--seconds 0.3 --out "$OUT/presets")
for g in gong-40N gong-80N rect-plate; do
    "$N" accuracy --preset "$g" "${P[@]}" --vary modes --values 25,50,100
    "$N" accuracy --preset "$g" "${P[@]}" --vary rate --values 8000,16000,32000 --reference-rate 64000
    "$N" accuracy --preset "$g" "${P[@]}" --vary scheme \
        --values conservative,conservative-exact,stormer-verlet,sav
done
# (The sitar bridge, 1 cm long, needs at least one grid spacing: 100 modes or more.)
for s in sitar sitar-b0; do
    "$N" accuracy --preset "$s" "${P[@]}" --vary modes --values 100,150,200
done
for s in tanpura tanpura-b0; do
    "$N" accuracy --preset "$s" "${P[@]}" --vary modes --values 50,100,200
done
for s in sitar sitar-b0 tanpura tanpura-b0; do
    "$N" accuracy --preset "$s" "${P[@]}" --vary rate --values 48000,96000,192000 --reference-rate 384000
done
if [ "${1:-}" = "--long" ]; then
    "$N" accuracy assets/scenes/seed-sitar.toml --vary rate \
        --values 96000,192000,384000,1000000,2000000 --reference-rate 4000000 \
        --set output.seconds=0.2 --out "$OUT"
    # The string's quadratised contact against Newton at 4 MHz (docs/ACCURACY.md, "contact
    # schemes"): the quadratised scheme at several rates, and Newton on the tanpura at 2 MHz.
    Q=(--set output.seconds=0.2 --set string.contact_scheme=quadratised
       --reference-set string.contact_scheme=newton --reference-set string.sim_rate=4000000
       --out "$OUT/quadratised" --vary rate)
    "$N" accuracy assets/scenes/seed-sitar.toml "${Q[@]}" --values 384000,2000000,4000000
    "$N" accuracy assets/scenes/seed-tanpura.toml "${Q[@]}" --values 2000000,4000000
    "$N" accuracy assets/scenes/seed-tanpura.toml --set output.seconds=0.2 --vary rate \
        --values 2000000 --reference-rate 4000000 --out "$OUT"
fi
