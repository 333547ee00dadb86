#!/usr/bin/env python3
"""Band levels of a WAV's first channel over time: how a struck gong's energy moves upwards.

Usage: python3 scripts/band-levels.py OUT.wav [--until SECONDS] [--every SECONDS]

Reads a 32-bit float or 16/24-bit PCM WAV (what `noether render` and `noether play` write), takes
2048-sample Hann-windowed frames of channel 1 every `--every` seconds (default 0.1) up to
`--until` (default 1.0), and prints for each frame the power in the bands 0-500 Hz, 0.5-1 kHz,
1-2 kHz, 2-4 kHz, 4-8 kHz and 8 kHz-Nyquist in dB relative to the frame's total power, then the
total in dB (arbitrary reference). A rising level in the upper bands after the strike is the
nonlinear cascade (docs/scenes.md, "The default gong"). Python 3 standard library only (a
radix-2 FFT written here), so it runs wherever CI does.
"""

import argparse
import cmath
import math
import struct
import sys

FRAME = 2048
EDGES = [0.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0]


def read_wav(path):
    """Returns (rate, channel-1 samples as floats) of a RIFF WAVE file."""
    data = open(path, "rb").read()
    if data[:4] != b"RIFF" or data[8:12] != b"WAVE":
        sys.exit(f"{path}: not a RIFF WAVE file")
    i, fmt, rate, channels, bits = 12, None, None, None, None
    while i + 8 <= len(data):
        cid, size = data[i:i + 4], struct.unpack("<I", data[i + 4:i + 8])[0]
        body = data[i + 8:i + 8 + size]
        if cid == b"fmt ":
            fmt, channels, rate = struct.unpack("<HHI", body[:8])
            bits = struct.unpack("<H", body[14:16])[0]
            if fmt == 0xFFFE:  # WAVE_FORMAT_EXTENSIBLE: the sub-format's first two bytes
                fmt = struct.unpack("<H", body[24:26])[0]
        elif cid == b"data":
            width = bits // 8
            n = len(body) // (width * channels)
            out = []
            for k in range(n):
                at = k * width * channels
                raw = body[at:at + width]
                if fmt == 3 and bits == 32:
                    out.append(struct.unpack("<f", raw)[0])
                elif fmt == 1 and bits in (16, 24, 32):
                    v = int.from_bytes(raw, "little", signed=True)
                    out.append(v / float(1 << (bits - 1)))
                else:
                    sys.exit(f"{path}: unsupported sample format {fmt} with {bits} bits")
            return rate, out
        i += 8 + size + (size & 1)
    sys.exit(f"{path}: no data chunk")


def fft(x):
    """Radix-2 decimation-in-time FFT of a list whose length is a power of two."""
    n = len(x)
    if n == 1:
        return list(x)
    even, odd = fft(x[0::2]), fft(x[1::2])
    out = [0j] * n
    for k in range(n // 2):
        t = cmath.exp(-2j * math.pi * k / n) * odd[k]
        out[k], out[k + n // 2] = even[k] + t, even[k] - t
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("wav")
    ap.add_argument("--until", type=float, default=1.0, help="last frame start (s)")
    ap.add_argument("--every", type=float, default=0.1, help="frame spacing (s)")
    a = ap.parse_args()
    rate, x = read_wav(a.wav)
    edges = EDGES + [rate / 2.0 + 1.0]
    names = ["0-500", "500-1k", "1k-2k", "2k-4k", "4k-8k", "8k-nyq"]
    print("t (s)  " + " ".join(f"{n:>8}" for n in names) + "   total (dB re frame total; total in dB)")
    hann = [0.5 - 0.5 * math.cos(2 * math.pi * k / FRAME) for k in range(FRAME)]
    step = max(1, int(round(a.every * rate)))
    start = 0
    while start + FRAME <= len(x) and start / rate <= a.until + 1e-9:
        spec = fft([x[start + k] * hann[k] for k in range(FRAME)])
        power = [abs(c) ** 2 for c in spec[:FRAME // 2 + 1]]
        total = sum(power) or 1e-300
        row = []
        for lo, hi in zip(edges[:-1], edges[1:]):
            p = sum(pw for k, pw in enumerate(power) if lo <= k * rate / FRAME < hi)
            row.append(10 * math.log10(p / total + 1e-30))
        print(f"{start / rate:5.2f}  " + " ".join(f"{v:8.1f}" for v in row)
              + f"   {10 * math.log10(total):6.1f}")
        start += step


if __name__ == "__main__":
    main()
