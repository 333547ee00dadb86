"""Plugin state blobs for the plugin CI scripts.

A host stores a nice-plug plugin's state as an 8-byte little-endian length followed by the JSON
state `{"version", "params", "fields"}`. A parameter value is typed: floats as `f32`, integers
as `i32`, enumeration names as strings (the plugin's state repair converts and logs them).
Factory presets (`assets/presets/*.toml`) become states from their `[params]` table.

Used by `preset_levels.sh`, `expressions.sh`, `state_blobs.sh`, `tuning_state.sh` (through
`sys.path`) and `pedalboard_presets.py`.
"""

import json
import pathlib
import struct
import tomllib

VERSION = "0.1.0"


def typed_params(params: dict, origin: str) -> dict:
    """The state's `params` object for a `[params]` table; booleans and other types are refused
    with the key, the value and what is allowed."""
    state = {}
    for key, value in params.items():
        if isinstance(value, bool):
            raise SystemExit(f"{origin}: params.{key} = {value}: a boolean, not a number or a name")
        if isinstance(value, int):
            state[key] = {"i32": value}
        elif isinstance(value, float):
            state[key] = {"f32": value}
        elif isinstance(value, str):
            state[key] = {"string": value}
        else:
            raise SystemExit(f"{origin}: params.{key} = {value!r}: not a number or a name")
    return state


def preset_params(path: pathlib.Path) -> dict:
    """The `[params]` table of a preset file."""
    return tomllib.loads(pathlib.Path(path).read_text())["params"]


def state_body(params: dict | None = None, fields: dict | None = None) -> bytes:
    """The JSON state with the typed `params` object and the `fields` strings."""
    return json.dumps(
        {"version": VERSION, "params": params or {}, "fields": fields or {}}
    ).encode()


def blob(body: bytes, length: int | None = None) -> bytes:
    """The stored blob: the length prefix (`length`, when given, to write a wrong one) and the
    body."""
    return struct.pack("<Q", len(body) if length is None else length) + body


def preset_blob(path: pathlib.Path, **changes) -> tuple[bytes, int]:
    """The blob of a preset file with some parameters changed, and the preset's root key."""
    params = preset_params(path)
    params.update(changes)
    body = state_body(typed_params(params, pathlib.Path(path).name))
    return blob(body), int(params.get("root_key", 60))
