#!/usr/bin/env python3
"""Compare two folders of golden renders (WAV files and their JSON reports) sample by sample.

Usage: compare-wavs.py [--tolerance T] BASE_DIR HEAD_DIR

For every `*.wav` under BASE_DIR (recursively) the file of the same relative path under
HEAD_DIR is compared; files present on one side only are reported and count as failures.
Per file it prints `identical` (same sample bits), or the largest absolute difference, that
difference relative to the base file's peak |x|, the number of differing samples, the largest
distance in float32 units in the last place (ULP) and the time of the first difference.

The beside-it JSON report (`X.json` for `X.wav`), when both sides have one, is compared on a
few key numbers (scene reports: nan_count, energy.max, energy.max_rel_drift,
energy.max_balance_error, peak; preset reports: nan_count, peak, counters, bank rate and size):
integers must be equal, floats within the tolerance (relative to the larger value, or absolute
for numbers that are already relative errors). Wall times are never compared.

Tolerance (default 1e-9 of the base file's peak |x|), and why: the models run in float64 and
the WAVs hold float32. A refactor that moves code without changing any float64 operation gives
bit-identical files, which is what a pure restructure must give. One that reorders float64
arithmetic (a sum split differently, a fused multiply-add, another SIMD path) changes results
by round-off, about 1e-16 relative per operation; grown over the few thousand steps of these
short renders by stable (energy-conserving, damped) schemes it stays orders of magnitude below
1e-9 of the peak (a strongly struck gong is chaotic, so round-off grows with time there: one
more reason to keep the renders short). Any change that is not round-off (a coefficient, an
event time, a parameter mapping, the resampler's phase) shows orders of magnitude above it.
1e-9 is below float32 resolution (2^-24, 6e-8 of a sample): a float64 round-off difference
shows in a WAV only where it flips the float32 rounding of a sample, and then by one ULP of
that sample, which exceeds 1e-9 of the peak for samples above about 2 % of the peak. So a
round-off-only change fails with `max 1 ulp` at a few samples: read the float64 report numbers
printed beside it for the size of the underlying difference, and rerun with
`--tolerance 1.2e-7` (two float32 ULPs of the peak) if that is accepted.

Only the Python standard library is used (the `wave` module of Python 3.11 does not read IEEE
float WAVs, so the RIFF chunks are parsed with `struct`). Exit status: 0 if every file is
within the tolerance, 1 otherwise, 2 on a usage error.
"""

import argparse
import json
import math
import os
import struct
import sys

DEFAULT_TOLERANCE = 1e-9

# JSON keys compared: (dotted path, kind) with kind "int" (exact), "rel" (relative to the
# larger magnitude) or "abs" (already a relative quantity: absolute difference).
JSON_KEYS = [
    ("nan_count", "int"),
    ("peak", "rel"),
    ("energy.max", "rel"),
    ("energy.max_rel_drift", "abs"),
    ("energy.max_balance_error", "abs"),
    ("n_phi", "int"),
    ("n_psi", "int"),
    ("sim_rate", "rel"),
    ("contact.newton_failures", "int"),
    ("contact.max_penetration", "rel"),
    ("refused_notes", "int"),
    ("diverged_voices", "int"),
    ("newton_cap_hits", "int"),
    ("active_voices_at_end", "int"),
    ("polyphony", "int"),
    ("latency_samples", "int"),
]


class WavError(Exception):
    pass


def read_wav(path):
    """Returns (channels, rate, bits, fmt, data bytes) of a PCM-int or IEEE-float WAV."""
    with open(path, "rb") as f:
        raw = f.read()
    if len(raw) < 12 or raw[0:4] != b"RIFF" or raw[8:12] != b"WAVE":
        raise WavError(f"{path}: not a RIFF/WAVE file")
    pos, fmt, data = 12, None, None
    while pos + 8 <= len(raw):
        cid, size = raw[pos : pos + 4], struct.unpack("<I", raw[pos + 4 : pos + 8])[0]
        body = raw[pos + 8 : pos + 8 + size]
        if cid == b"fmt ":
            if len(body) < 16:
                raise WavError(f"{path}: short fmt chunk")
            tag, channels, rate, _, _, bits = struct.unpack("<HHIIHH", body[:16])
            if tag == 0xFFFE and len(body) >= 26:  # WAVE_FORMAT_EXTENSIBLE: sub-format GUID
                tag = struct.unpack("<H", body[24:26])[0]
            fmt = (tag, channels, rate, bits)
        elif cid == b"data":
            data = body
        pos += 8 + size + (size & 1)
    if fmt is None or data is None:
        raise WavError(f"{path}: missing fmt or data chunk")
    tag, channels, rate, bits = fmt
    if tag == 3 and bits == 32:
        kind = "f"
    elif tag == 3 and bits == 64:
        kind = "d"
    elif tag == 1 and bits in (16, 32):
        kind = "h" if bits == 16 else "i"
    else:
        raise WavError(f"{path}: unsupported format (tag {tag}, {bits} bits)")
    width = bits // 8
    data = data[: len(data) - len(data) % width]
    return channels, rate, kind, data


def f32_ordered(x):
    """Maps a float32 to an integer whose difference counts ULPs (sign-magnitude to two's)."""
    i = struct.unpack("<i", struct.pack("<f", x))[0]
    return i if i >= 0 else -(i & 0x7FFFFFFF)


def compare_wav(base, head):
    """Returns (ok_shape, message, stats) where stats is a dict or None when identical."""
    cb, rb, kb, db = read_wav(base)
    ch, rh, kh, dh = read_wav(head)
    if (cb, rb, kb) != (ch, rh, kh):
        return False, f"format differs: {cb} ch {rb} Hz '{kb}' vs {ch} ch {rh} Hz '{kh}'", None
    if len(db) != len(dh):
        return False, f"length differs: {len(db)} vs {len(dh)} bytes", None
    if db == dh:
        return True, "identical", None
    n = len(db) // struct.calcsize(kb)
    xb = struct.unpack(f"<{n}{kb}", db)
    xh = struct.unpack(f"<{n}{kh}", dh)
    peak = max((abs(v) for v in xb if math.isfinite(v)), default=0.0)
    max_abs, count, first, max_ulp, nonfinite = 0.0, 0, None, 0, 0
    for i, (a, b) in enumerate(zip(xb, xh)):
        if a == b or (a != a and b != b):
            continue
        count += 1
        if first is None:
            first = i
        if not (math.isfinite(a) and math.isfinite(b)):
            nonfinite += 1
            max_abs = math.inf
            continue
        d = abs(a - b)
        if d > max_abs:
            max_abs = d
        if kb == "f":
            max_ulp = max(max_ulp, abs(f32_ordered(a) - f32_ordered(b)))
    if count == 0:  # only NaNs with different payloads, or +0 / -0
        return True, "identical values (different bits of zeros or NaNs)", None
    rel = max_abs / peak if peak > 0 else math.inf
    stats = {
        "max_abs": max_abs,
        "rel": rel,
        "count": count,
        "n": n,
        "first_s": (first // cb) / rb,
        "max_ulp": max_ulp,
        "nonfinite": nonfinite,
        "peak": peak,
    }
    return True, None, stats


def get_path(obj, dotted):
    for part in dotted.split("."):
        if not isinstance(obj, dict) or part not in obj:
            return None
        obj = obj[part]
    return obj


def compare_json(base, head, tol):
    """Returns (ok, list of difference strings) for the key numbers of two reports."""
    try:
        with open(base) as f:
            jb = json.load(f)
        with open(head) as f:
            jh = json.load(f)
    except (OSError, ValueError) as e:
        return False, [f"report unreadable: {e}"]
    ok, notes = True, []
    for key, kind in JSON_KEYS:
        a, b = get_path(jb, key), get_path(jh, key)
        if a is None and b is None:
            continue
        if a is None or b is None or isinstance(a, (dict, list)) or isinstance(b, (dict, list)):
            if a != b:
                ok = False
                notes.append(f"{key}: {a} vs {b}")
            continue
        if a == b:
            continue
        if kind == "int" or not all(isinstance(v, (int, float)) for v in (a, b)):
            ok = False
            notes.append(f"{key}: {a} vs {b}")
            continue
        d = abs(a - b)
        scale = max(abs(a), abs(b)) if kind == "rel" else 1.0
        r = d / scale if scale > 0 else 0.0
        bad = not (r <= tol)
        ok = ok and not bad
        notes.append(f"{key}: {a!r} vs {b!r} ({'rel' if kind == 'rel' else 'abs'} {r:.3e}{', OVER' if bad else ''})")
    return ok, notes


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("base")
    p.add_argument("head")
    p.add_argument("--tolerance", type=float, default=DEFAULT_TOLERANCE,
                   help="largest accepted |difference| / base peak (default 1e-9)")
    a = p.parse_args()
    if not (a.tolerance >= 0 and math.isfinite(a.tolerance)):
        p.error(f"invalid --tolerance {a.tolerance} (allowed: a finite number >= 0)")
    for d in (a.base, a.head):
        if not os.path.isdir(d):
            p.error(f"not a folder: {d}")

    def wavs(root):
        out = set()
        for dirpath, _, files in os.walk(root):
            for f in files:
                if f.endswith(".wav"):
                    out.add(os.path.relpath(os.path.join(dirpath, f), root))
        return out

    wb, wh = wavs(a.base), wavs(a.head)
    names = sorted(wb | wh)
    if not names:
        print("no WAV files to compare", file=sys.stderr)
        return 1
    failed = 0
    width = max(len(n) for n in names)
    for name in names:
        label = name.ljust(width)
        if name not in wh or name not in wb:
            print(f"{label}  FAIL: only in {'base' if name in wb else 'head'}")
            failed += 1
            continue
        pb, ph = os.path.join(a.base, name), os.path.join(a.head, name)
        try:
            shape_ok, msg, s = compare_wav(pb, ph)
        except (OSError, WavError) as e:
            print(f"{label}  FAIL: {e}")
            failed += 1
            continue
        ok = shape_ok
        if s is None:
            line = msg if shape_ok else f"FAIL: {msg}"
        else:
            ok = s["rel"] <= a.tolerance and s["nonfinite"] == 0
            line = (f"{'within tolerance' if ok else 'FAIL'}: max |diff| {s['max_abs']:.3e} = "
                    f"{s['rel']:.3e} of peak {s['peak']:.4e}; {s['count']}/{s['n']} samples differ"
                    + (f", max {s['max_ulp']} ulp" if s["max_ulp"] else "")
                    + f", first at {s['first_s']:.6f} s"
                    + (f", {s['nonfinite']} non-finite mismatches" if s["nonfinite"] else ""))
        jb, jh = pb[:-4] + ".json", ph[:-4] + ".json"
        if os.path.isfile(jb) and os.path.isfile(jh):
            jok, notes = compare_json(jb, jh, a.tolerance)
            if notes:
                line += "; report: " + "; ".join(notes)
            if not jok:
                ok = False
                if not line.startswith("FAIL"):
                    line = "FAIL (report): " + line
        print(f"{label}  {line}")
        failed += 0 if ok else 1
    print(f"{len(names) - failed} within tolerance {a.tolerance:g} of the peak, {failed} failed "
          f"({len(names)} files)")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
