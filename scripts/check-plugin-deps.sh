#!/usr/bin/env bash
# The plugin links the real-time core only: none of the offline tool's crates (progress bars,
# plots, WAV, CSV, offline resampling) may be in its normal dependency tree, and `clap` only
# through nice-plug (its standalone's command-line flags). Exits non-zero naming the crate and
# the path that brought it in. Needs only cargo (reads Cargo.lock; builds nothing).
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
for pkg in noether-plugin; do
    tree=$(cargo tree -p "$pkg" -e normal --prefix none --format '{p}' | awk '{print $1}' | sort -u)
    for banned in indicatif plotters hound csv rubato noether; do
        if grep -qx "$banned" <<<"$tree"; then
            echo "error: $pkg depends on '$banned' (offline-only crate); path:" >&2
            cargo tree -p "$pkg" -e normal -i "$banned" >&2 || true
            status=1
        fi
    done
    if grep -qx clap <<<"$tree"; then
        parents=$(cargo tree -p "$pkg" -e normal -i clap --depth 1 --prefix none --format '{p}' |
            tail -n +2 | awk '{print $1}' | sort -u)
        if [ "$parents" != "nice-plug" ]; then
            echo "error: $pkg reaches 'clap' through: $parents (allowed: nice-plug only)" >&2
            status=1
        fi
    fi
done
if [ "$status" = 0 ]; then
    echo "plugin dependencies: core only (no offline crate; clap only through nice-plug)"
fi
exit "$status"
