"""Every factory preset through the VST3 in pedalboard (JUCE's VST3 host), with the bounds of
plugin/ci/preset_levels.sh (the CLAP host) and tests/engine/preset_levels.rs (the engine): the
root key at velocity 127 peaks between -6 and -1 dBFS; keys 36 to 96 at 127 within 6 dB of it;
velocity 40 quieter; every sample finite and within 0 dBFS; the last 0.1 s at least 20 dB under
the note's peak (each note held 1 s, released 1 s, 48 kHz).

The preset reaches the plugin as its saved state: pedalboard's `raw_state` is JUCE's VST3 state
(`VC2!`, a little-endian size, an XML document whose <IComponent> holds the plugin's own state
in JUCE's base64 variant: "<byte count>.<6-bit groups, least significant bits first, alphabet
.A-Za-z0-9+>"). The plugin's own state is nice-plug's JSON, as in the CLAP blobs.

Usage: python3 plugin/ci/pedalboard_presets.py PLUGIN.vst3 [PRESET.toml ...]
(run by hand: the plugin CI runs the CLAP version, plugin/ci/preset_levels.sh).
"""

import json
import pathlib
import re
import struct
import sys

import numpy as np
import pedalboard

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from plugin_state import preset_params, state_body, typed_params  # noqa: E402

RATE = 48_000
KEYS = [36, 48, 60, 72, 84, 96]
B64 = ".ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+"


def juce_b64_decode(text: str) -> bytes:
    size, enc = text.split(".", 1)
    v = 0
    for i, c in enumerate(enc):
        v |= B64.index(c) << (6 * i)
    return v.to_bytes((len(enc) * 6 + 7) // 8 + 1, "little")[: int(size)]


def juce_b64_encode(data: bytes) -> str:
    v = int.from_bytes(data, "little")
    n = (len(data) * 8 + 5) // 6
    return f"{len(data)}." + "".join(B64[(v >> (6 * i)) & 63] for i in range(n))


def with_component_state(raw: bytes, component: bytes) -> bytes:
    """JUCE's VST3 state `raw` with its <IComponent> replaced by `component`."""
    assert raw[:4] == b"VC2!", raw[:8]
    n = struct.unpack("<I", raw[4:8])[0]
    xml = raw[8 : 8 + n].decode()
    xml = re.sub(
        r"<IComponent>[^<]*</IComponent>",
        f"<IComponent>{juce_b64_encode(component)}</IComponent>",
        xml,
    )
    body = xml.encode()
    return b"VC2!" + struct.pack("<I", len(body)) + body


def preset_state(path: pathlib.Path) -> tuple[bytes, int]:
    """The plugin's JSON state of a preset file (no length prefix: JUCE wraps it) and its root
    key."""
    params = preset_params(path)
    return state_body(typed_params(params, path.name)), int(params.get("root_key", 60))


def db(x: float) -> float:
    return 20 * np.log10(max(x, 1e-12))


def main() -> int:
    plugin_path, files = sys.argv[1], sys.argv[2:]
    root_dir = pathlib.Path(__file__).resolve().parents[2]
    paths = [pathlib.Path(f) for f in files] or sorted((root_dir / "assets/presets").glob("*.toml"))
    ignored = getattr(pedalboard._pedalboard, "PARAMETER_NAME_REGEXES_TO_IGNORE", None)
    if isinstance(ignored, set):
        ignored.add(re.compile(r"MIDI Ch\. \d+ "))
    inst = pedalboard.load_plugin(plugin_path)
    # A state of the plugin's own to patch (JUCE's wrapper around nice-plug's JSON).
    template = inst.raw_state
    json.loads(juce_b64_decode(re.search(rb"<IComponent>([^<]*)<", template).group(1).decode()))
    failures = []
    for path in paths:
        component, root = preset_state(path)
        inst.raw_state = with_component_state(template, component)

        def play(key: int, vel: int) -> tuple[float, float]:
            msgs = [(bytes([0x90, key, vel]), 0.0), (bytes([0x80, key, 0]), 1.0)]
            # The plugin keeps its voices between calls: reset, then render.
            inst.reset()
            a = np.asarray(
                inst(msgs, duration=2.0, sample_rate=RATE, num_channels=2, buffer_size=256),
                dtype=np.float64,
            )
            if not np.all(np.isfinite(a)) or np.max(np.abs(a)) > 1.0:
                failures.append(f"{path.stem} key {key} vel {vel}: non-finite or above 0 dBFS")
            return db(np.max(np.abs(a))), db(np.max(np.abs(a[:, -RATE // 10 :])))

        root_peak, _ = play(root, 127)
        line = [f"{path.stem} (root {root}: {root_peak:.1f} dBFS)"]
        if not -6.0 <= root_peak <= -1.0:
            failures.append(f"{path.stem}: root peak {root_peak:.1f} dBFS")
        for key in KEYS:
            loud, tail = play(key, 127)
            soft, _ = play(key, 40)
            line.append(f"{key}: {loud:.1f}/{loud - root_peak:+.1f} ({soft:.1f})")
            if abs(loud - root_peak) > 6.0:
                failures.append(f"{path.stem} key {key}: {loud - root_peak:+.1f} dB re root")
            if soft >= loud:
                failures.append(f"{path.stem} key {key}: velocity 40 not quieter")
            if tail > loud - 20.0:
                failures.append(f"{path.stem} key {key}: {tail:.1f} dBFS 1 s after the note-off")
        print("  ".join(line), flush=True)
    for f in failures:
        print("FAIL", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
