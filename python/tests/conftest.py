"""Shared fixtures: the glint binary (for CLI comparisons) and a scene of known layout."""

import base64
import json
import os
import struct
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def glint_bin() -> Path:
    """The command-line glint of the same build: $GLINT_BIN, else target/debug/glint."""
    path = Path(os.environ.get("GLINT_BIN", REPO / "target" / "debug" / "glint"))
    if not path.is_file():
        pytest.fail(f"no glint binary at {path}: run `cargo build --bin glint` or set GLINT_BIN")
    return path


def two_quads_gltf(path: Path) -> Path:
    """Writes a glTF of two unit-height quads side by side, facing an orthographic camera.

    Node 0 is quad A (material 0) covering x in [-2, 0], node 1 quad B (material 1) covering
    x in [0, 2], both y in [-1, 1] at z = 0. Node 2 is the camera at z = 5 looking down -Z, with
    xmag = 1.75 and ymag = 0.5: a 7x2 image has pixels 0.5 units wide, columns 0-2 on A,
    column 3 centred on the edge x = 0 (half on each quad), columns 4-6 on B. A directional
    light lights both.
    """
    positions = [
        # quad A
        (-2.0, -1.0, 0.0), (0.0, -1.0, 0.0), (0.0, 1.0, 0.0), (-2.0, 1.0, 0.0),
        # quad B
        (0.0, -1.0, 0.0), (2.0, -1.0, 0.0), (2.0, 1.0, 0.0), (0.0, 1.0, 0.0),
    ]
    indices = [0, 1, 2, 0, 2, 3]  # counter-clockwise seen from +Z
    pos_bytes = b"".join(struct.pack("<3f", *p) for p in positions)
    idx_bytes = struct.pack("<6H", *indices)
    idx_padded = idx_bytes + b"\0" * (-len(idx_bytes) % 4)
    data = pos_bytes + idx_padded
    uri = "data:application/octet-stream;base64," + base64.b64encode(data).decode()
    gltf = {
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": len(data), "uri": uri}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48, "target": 34962},
            {"buffer": 0, "byteOffset": 96, "byteLength": len(idx_bytes), "target": 34963},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [-2.0, -1.0, 0.0], "max": [0.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0.0, -1.0, 0.0], "max": [2.0, 1.0, 0.0]},
            {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"},
        ],
        "materials": [
            {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.1, 0.1, 1.0],
                                                     "metallicFactor": 0.0}},
            {"name": "green", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.8, 0.1, 1.0],
                                                       "metallicFactor": 0.0}},
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 0}, "indices": 2, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 1}, "indices": 2, "material": 1}]},
        ],
        "cameras": [{"type": "orthographic",
                     "orthographic": {"xmag": 1.75, "ymag": 0.5, "znear": 0.1, "zfar": 100.0}}],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "directional", "intensity": 3.0, "color": [1.0, 1.0, 1.0]}]}},
        "extensionsUsed": ["KHR_lights_punctual"],
        "nodes": [
            {"name": "A", "mesh": 0},
            {"name": "B", "mesh": 1},
            {"name": "camera", "camera": 0, "translation": [0.0, 0.0, 5.0]},
            {"name": "sun", "extensions": {"KHR_lights_punctual": {"light": 0}},
             "rotation": [0.0, 0.0, 0.0, 1.0]},
        ],
        "scenes": [{"nodes": [0, 1, 2, 3]}],
        "scene": 0,
    }
    path.write_text(json.dumps(gltf))
    return path


@pytest.fixture(scope="session")
def quads_path(tmp_path_factory) -> Path:
    return two_quads_gltf(tmp_path_factory.mktemp("quads") / "two_quads.gltf")
