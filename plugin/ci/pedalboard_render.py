"""Load target/bundled/noether-plugin.vst3 in pedalboard (JUCE's VST3 host), list its
parameters, set a few, play a note and write the stereo output to a 32-bit float WAV.

Usage: python3 pedalboard_render.py PLUGIN.vst3 OUT.wav [--seconds S] [--note-off S]
The WAV is then checked by `noether-test-host check` (finite, non-silent, decaying).
"""

import argparse
import re
import sys

import numpy as np
import pedalboard

RATE = 48_000


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("plugin")
    ap.add_argument("out")
    ap.add_argument("--seconds", type=float, default=3.0)
    ap.add_argument("--note-off", type=float, default=1.0)
    args = ap.parse_args()

    # nice-plug's VST3 wrapper maps MIDI CCs, channel pressure and pitch bend to 16 x 130 proxy
    # parameters named "MIDI Ch. N ...", as JUCE does with its "MIDI CC " ones, which pedalboard
    # already skips. pedalboard probes 1001 values of every parameter it wraps (two minutes for
    # the proxies on the 2-core machine): skip them the same way. MIDI still reaches the plugin.
    ignored = getattr(pedalboard._pedalboard, "PARAMETER_NAME_REGEXES_TO_IGNORE", None)
    if isinstance(ignored, set):
        ignored.add(re.compile(r"MIDI Ch\. \d+ "))
    inst = pedalboard.load_plugin(args.plugin)
    if not inst.is_instrument:
        print(f"{args.plugin} does not load as an instrument", file=sys.stderr)
        return 1
    # Noether's own parameters (the MIDI proxies, midi_ch_*, if pedalboard listed them anyway).
    own = {n: p for n, p in inst.parameters.items() if not n.startswith("midi_ch_")}
    print(f"loaded {inst.name!r}; {len(own)} parameters (MIDI CC proxies not listed)")
    for name, p in own.items():
        print(f"  {name:<28} {p.raw_value:.4f} ({p.string_value})")
    # Set two parameters that apply without a model rebuild through their normalised (raw)
    # values, and read them back: the damping scale and the release time.
    for key, raw in (("damping", 0.1), ("release_t60", 0.3)):
        p = inst.parameters.get(key)
        if p is None:
            print(f"no parameter {key!r}", file=sys.stderr)
            return 1
        p.raw_value = raw
        if abs(p.raw_value - raw) > 1e-6:
            print(f"{key}: set {raw}, reads back {p.raw_value}", file=sys.stderr)
            return 1
        print(f"set {key} raw {raw} -> {p.string_value}")
    # (raw MIDI bytes, time in seconds from the start): note on, mod wheel, pitch bend up and
    # back, note off.
    off = args.note_off
    msgs = [
        (bytes([0x90, 60, 100]), 0.0),
        (bytes([0xB0, 1, 64]), 0.2 * off),
        (bytes([0xE0, 0x00, 0x50]), 0.3 * off),
        (bytes([0xE0, 0x00, 0x40]), 0.6 * off),
        (bytes([0x80, 60, 0]), off),
    ]
    audio = inst(msgs, duration=args.seconds, sample_rate=RATE, num_channels=2, buffer_size=512)
    audio = np.asarray(audio, dtype=np.float32)
    print(f"rendered {audio.shape} peak {np.max(np.abs(audio)):.3e}")
    with pedalboard.io.AudioFile(args.out, "w", RATE, num_channels=2, bit_depth=32) as f:
        f.write(audio)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
