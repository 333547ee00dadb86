#!/usr/bin/env bash
# compare-renders.sh: prove that a refactor does not change what Noether renders.
#
# Usage: scripts/compare-renders.sh BASE_REV [HEAD_REV]
#
# For BASE_REV and HEAD_REV (default: this repository's working tree, uncommitted changes
# included) it
#   1. checks the revision out in a temporary git worktree (or reuses the one given in
#      BASE_WORKTREE / HEAD_WORKTREE; HEAD as the working tree builds in place), copying
#      examples/render_presets.rs into it if the revision lacks it;
#   2. builds release once: cargo build --release -p noether --bin noether --example render_presets
#   3. renders every scene of assets/scenes/*.toml with `noether render`, shortened to
#      SCENE_SECONDS (scenes with at least BIG_MODES plate modes, the lecture's 800-1000-mode
#      plates, to BIG_SCENE_SECONDS; `quality = "auto"` scenes verify their candidates over
#      min(excerpt, output.seconds), so the same setting bounds them), and every factory preset
#      of assets/presets/*.toml through the real-time engine (examples/render_presets.rs: root
#      key at full velocity, held 1 s, 1.5 s at 48 kHz in 256-sample blocks);
#   4. compares the WAVs sample by sample and the reports' key numbers (scripts/compare-wavs.py;
#      its header explains the tolerance) and exits non-zero if any file differs by more than
#      TOLERANCE of its peak (default 1e-9), a file is missing on one side, or a render failed.
#
# The base's renders are cached in $GOLDEN_CACHE/<sha>/ (complete renders only, keyed by the
# render settings and the preset renderer's source), so a later run against a new HEAD only
# builds and renders the head. HEAD is always rendered afresh (into $GOLDEN_CACHE/head/), so
# `compare-renders.sh REV REV` checks that two runs of one revision agree (determinism).
# Each revision renders with an empty modal-basis cache of its own (NOETHER_CACHE), so no
# revision reads a basis another one computed. RAYON_NUM_THREADS is pinned (the rectangular
# plate's basis depends on it at round-off level) and the cache key holds the CPU's features.
#
# Environment (all optional):
#   GOLDEN_CACHE        cache and output root          (default ~/.cache/noether-golden)
#   CARGO_TARGET_DIR    one target dir for every revision; dependencies build once
#                                                       (default $GOLDEN_CACHE/target)
#   BASE_WORKTREE, HEAD_WORKTREE   existing checkouts of the revisions to reuse
#   TOLERANCE           largest |diff| / peak accepted (default 1e-9)
#   RAYON_NUM_THREADS   rayon threads of the renders (default 2; see below)
#   SCENE_SECONDS       scene length (default 0.1)
#   BIG_SCENE_SECONDS   length of scenes with n_phi >= BIG_MODES (default 0.02, BIG_MODES 500)
#   PRESET_SECONDS, PRESET_HOLD   preset render length and note-off time (default 1.5, 1.0)
#   REFRESH_BASE=1      re-render the base even if cached
#
# Needs git, cargo, python3 (standard library only), awk, sha256sum.
set -euo pipefail

usage() {
    sed -n '2,/^set -euo/p' "$0" | sed -e '/^set -euo/d' -e 's/^# \{0,1\}//'
    exit 2
}
[[ $# -ge 1 && $# -le 2 && $1 != -h && $1 != --help ]] || usage

die() {
    echo "compare-renders: error: $*" >&2
    exit 2
}
now() { date +%s.%N; }
elapsed() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(git -C "$script_dir/.." rev-parse --show-toplevel 2>/dev/null) ||
    die "$script_dir/.. is not inside a git repository (run the script from its checkout)"
example_src="$repo/examples/render_presets.rs"
compare_tool="$script_dir/compare-wavs.py"
[[ -f $example_src ]] || die "missing $example_src"
[[ -f $compare_tool ]] || die "missing $compare_tool"
for tool in git cargo python3 awk sha256sum; do
    command -v "$tool" >/dev/null || die "'$tool' not found in PATH"
done

GOLDEN_CACHE=${GOLDEN_CACHE:-$HOME/.cache/noether-golden}
TOLERANCE=${TOLERANCE:-1e-9}
SCENE_SECONDS=${SCENE_SECONDS:-0.1}
BIG_SCENE_SECONDS=${BIG_SCENE_SECONDS:-0.02}
BIG_MODES=${BIG_MODES:-500}
PRESET_SECONDS=${PRESET_SECONDS:-1.5}
PRESET_HOLD=${PRESET_HOLD:-1.0}
target=${CARGO_TARGET_DIR:-$GOLDEN_CACHE/target}
# The rectangular plate's Airy basis uses faer's global parallelism (rayon's thread count): a
# different thread count changes those renders by round-off (measured: 1-CPU against 2-CPU runs
# differ by 4e-11 of the peak in presets/rect-plate.wav). Pin it so that renders made on
# machines with other core counts compare.
export RAYON_NUM_THREADS=${RAYON_NUM_THREADS:-2}
# The plate kernels pick an AVX2 + FMA path when the CPU has both: cached renders are only
# reused on the same architecture and features.
cpu_key=$(uname -m)
for flag in avx2 fma; do
    if grep -qw "$flag" /proc/cpuinfo 2>/dev/null; then cpu_key+="+$flag"; fi
done
mkdir -p "$GOLDEN_CACHE" "$target"
GOLDEN_CACHE=$(cd "$GOLDEN_CACHE" && pwd)
target=$(cd "$target" && pwd)

resolve() {
    git -C "$repo" rev-parse --verify --quiet "$1^{commit}" ||
        die "'$1' is not a revision of $repo"
}
base_sha=$(resolve "$1")
head_arg=${2:-}
if [[ -z $head_arg ]]; then
    head_sha=worktree
else
    head_sha=$(resolve "$head_arg")
fi

tmp=$(mktemp -d "${TMPDIR:-/tmp}/compare-renders.XXXXXX")
made_worktrees=()
# shellcheck disable=SC2317 # called through the EXIT trap
cleanup() {
    for wt in "${made_worktrees[@]}"; do
        git -C "$repo" worktree remove --force "$wt" >/dev/null 2>&1 ||
            echo "compare-renders: warning: could not remove the worktree $wt" >&2
    done
    rm -rf "${tmp:?}"
}
trap cleanup EXIT

# checkout SHA GIVEN_DIR: sets `tree` to the directory holding the revision's files (not in a
# subshell: the worktrees it makes are removed on exit).
checkout() {
    local sha=$1 given=$2 at
    if [[ $sha == worktree ]]; then
        tree=$repo
        return
    fi
    if [[ -n $given ]]; then
        [[ -d $given ]] || die "worktree $given does not exist"
        at=$(git -C "$given" rev-parse HEAD 2>/dev/null) || die "$given is not a git checkout"
        [[ $at == "$sha" ]] || die "$given is at $at, not $sha"
        if [[ -n $(git -C "$given" status --porcelain --untracked-files=no) ]]; then
            echo "compare-renders: warning: $given has uncommitted changes to tracked files" >&2
        fi
        tree=$(cd "$given" && pwd)
        return
    fi
    tree="$tmp/wt-${sha:0:12}"
    git -C "$repo" worktree add --detach --quiet "$tree" "$sha" ||
        die "git worktree add $tree $sha failed"
    made_worktrees+=("$tree")
}

# A scene's length: BIG_SCENE_SECONDS if its plate has n_phi >= BIG_MODES, else SCENE_SECONDS.
scene_seconds() {
    awk -v big="$BIG_MODES" -v s="$SCENE_SECONDS" -v b="$BIG_SCENE_SECONDS" '
        /^[ \t]*\[/ { sec = $0 }
        sec ~ /^[ \t]*\[plate\]/ && /^[ \t]*n_phi[ \t]*=/ {
            v = $0; sub(/^[^=]*=[ \t]*/, "", v); sub(/[ \t#].*$/, "", v)
            if (v + 0 >= big) n = 1
        }
        END { print (n ? b : s) }' "$1"
}

# First existing folder among the candidates under a tree (assets may move in a restructure).
find_dir() {
    local root=$1 c
    shift
    for c in "$@"; do
        if [[ -d $root/$c ]]; then
            echo "$root/$c"
            return
        fi
    done
    die "none of $* found under $root"
}

# render_revision LABEL TREE DEST: build and render into DEST/renders; exit status 1 if
# any render failed (DEST/complete is written only when all succeeded).
render_revision() {
    local label=$1 tree=$2 dest=$3 t0 t start ok=1
    rm -rf "${dest:?}"
    mkdir -p "$dest/renders/scenes" "$dest/renders/presets" "$dest/bin"
    local timings="$dest/timings.tsv"
    printf 'kind\tname\tseconds\twall_s\tstatus\n' >"$timings"
    if [[ ! -f $tree/examples/render_presets.rs ]]; then
        echo "[$label] copying examples/render_presets.rs into $tree (the revision lacks it)"
        mkdir -p "$tree/examples"
        cp "$example_src" "$tree/examples/render_presets.rs"
    fi
    echo "[$label] building release in $tree (target $target; log $dest/build.log)"
    t0=$(now)
    if ! (cd "$tree" && CARGO_TARGET_DIR=$target cargo build --release -p noether \
        --bin noether --example render_presets) >"$dest/build.log" 2>&1; then
        tail -n 30 "$dest/build.log" >&2
        die "[$label] build failed (see $dest/build.log)"
    fi
    t=$(elapsed "$t0")
    printf 'build\tcargo build --release\t-\t%s\tok\n' "$t" >>"$timings"
    echo "[$label] build: ${t} s"
    cp "$target/release/noether" "$target/release/examples/render_presets" "$dest/bin/"

    export NOETHER_CACHE="$dest/modal-cache"
    rm -rf "${NOETHER_CACHE:?}"
    mkdir -p "$NOETHER_CACHE"
    local scenes presets f name secs
    scenes=$(find_dir "$tree" assets/scenes core/assets/scenes)
    presets=$(find_dir "$tree" assets/presets core/assets/presets)
    start=$(now)
    for f in "$scenes"/*.toml; do
        name=$(basename "$f" .toml)
        secs=$(scene_seconds "$f")
        t0=$(now)
        if (cd "$tree" && "$dest/bin/noether" render "$f" --quiet \
            -o "$dest/renders/scenes/$name.wav" --report "$dest/renders/scenes/$name.json" \
            --set "output.seconds=$secs") >"$dest/renders/scenes/$name.log" 2>&1; then
            t=$(elapsed "$t0")
            printf 'scene\t%s\t%s\t%s\tok\n' "$name" "$secs" "$t" >>"$timings"
            printf '[%s] scene  %-22s %6s s  %7s s wall\n' "$label" "$name" "$secs" "$t"
        else
            t=$(elapsed "$t0")
            ok=0
            printf 'scene\t%s\t%s\t%s\tFAILED\n' "$name" "$secs" "$t" >>"$timings"
            echo "[$label] scene $name FAILED after $t s:" >&2
            tail -n 5 "$dest/renders/scenes/$name.log" >&2
        fi
    done
    local files=("$presets"/*.toml)
    t0=$(now)
    if (cd "$tree" && "$dest/bin/render_presets" --out "$dest/renders/presets" \
        --seconds "$PRESET_SECONDS" --hold "$PRESET_HOLD" "${files[@]}") \
        >"$dest/renders/presets/render.log" 2>&1; then
        :
    else
        ok=0
        echo "[$label] preset renders FAILED:" >&2
        tail -n 10 "$dest/renders/presets/render.log" >&2
    fi
    t=$(elapsed "$t0")
    # One line per preset from the renderer's own timing (bank build + render of each).
    awk -v label="$label" -v s="$PRESET_SECONDS" -v tsv="$timings" '
        /: [0-9]+ samples,/ {
            name = $1; sub(/:$/, "", name)
            match($0, /build [0-9.]+ s/); b = substr($0, RSTART + 6, RLENGTH - 8)
            match($0, /render [0-9.]+ s/); r = substr($0, RSTART + 7, RLENGTH - 9)
            printf "[%s] preset %-22s %6s s  %7.2f s wall (bank %s s, render %s s)\n", label, name, s, b + r, b, r
            printf "preset\t%s\t%s\t%.2f\tok\n", name, s, b + r >> tsv
        }' "$dest/renders/presets/render.log"
    printf 'presets\tall (process)\t%s\t%s\t%s\n' "$PRESET_SECONDS" "$t" \
        "$([[ $ok == 1 ]] && echo ok || echo FAILED)" >>"$timings"
    echo "[$label] presets: ${t} s (process); renders total $(elapsed "$start") s"
    rm -rf "${NOETHER_CACHE:?}" "${dest:?}/bin"
    unset NOETHER_CACHE
    if [[ $ok == 1 ]]; then
        echo "$settings_for_rev" >"$dest/settings"
        touch "$dest/complete"
        return 0
    fi
    return 1
}

run_t0=$(now)
status=0

# Base: from the cache when a complete render with the same settings exists.
checkout "$base_sha" "${BASE_WORKTREE:-}"
base_tree=$tree
if [[ -f $base_tree/examples/render_presets.rs ]]; then
    base_example_hash=$(sha256sum "$base_tree/examples/render_presets.rs" | cut -c1-16)
else
    base_example_hash=$(sha256sum "$example_src" | cut -c1-16)
fi
settings_for_rev="scene=$SCENE_SECONDS big=$BIG_SCENE_SECONDS big_modes=$BIG_MODES preset=$PRESET_SECONDS hold=$PRESET_HOLD example=$base_example_hash rayon=$RAYON_NUM_THREADS cpu=$cpu_key"
base_dest="$GOLDEN_CACHE/$base_sha"
if [[ ${REFRESH_BASE:-0} != 1 && -f $base_dest/complete &&
    $(cat "$base_dest/settings" 2>/dev/null) == "$settings_for_rev" ]]; then
    echo "[base ${base_sha:0:12}] using cached renders in $base_dest"
else
    render_revision "base ${base_sha:0:12}" "$base_tree" "$base_dest" || status=1
fi

# Head: always rendered afresh.
if [[ $head_sha == "$base_sha" && -z ${HEAD_WORKTREE:-} ]]; then
    HEAD_WORKTREE=$base_tree # same revision: reuse its checkout (and build)
fi
checkout "$head_sha" "${HEAD_WORKTREE:-}"
head_tree=$tree
head_label=$([[ $head_sha == worktree ]] && echo worktree || echo "${head_sha:0:12}")
if [[ $head_sha == worktree && -n $(git -C "$repo" status --porcelain) ]]; then
    echo "[head worktree] note: the working tree has uncommitted changes (they are rendered)"
fi
settings_for_rev="head"
head_dest="$GOLDEN_CACHE/head/$head_label"
render_revision "head $head_label" "$head_tree" "$head_dest" || status=1

echo
echo "comparing $base_dest/renders (base ${base_sha:0:12}) with $head_dest/renders (head $head_label), tolerance $TOLERANCE of the peak"
if ! python3 "$compare_tool" --tolerance "$TOLERANCE" "$base_dest/renders" "$head_dest/renders"; then
    status=1
fi
echo "total wall time $(elapsed "$run_t0") s; timings in $base_dest/timings.tsv and $head_dest/timings.tsv"
if [[ $status != 0 ]]; then
    echo "compare-renders: FAILED (a render failed or a file differs beyond the tolerance)" >&2
fi
exit $status
