#!/usr/bin/env python3
# measurement input: a glTF drawing a model COUNT times with EXT_mesh_gpu_instancing (docs/instancing.md). Run: target/tools-venv/bin/python tools/instanced-scene.py MODEL.gltf COUNT OUT_DIR
"""Writes a glTF that draws a model COUNT times with EXT_mesh_gpu_instancing.

usage: tools/instanced-scene.py MODEL.gltf COUNT OUT_DIR

Every node with a mesh gets the extension: copies on a square grid on the XZ plane of the
node's own frame (the node's transform applies after the instance's), 1.5 model
sizes apart (the size is the POSITION accessors' largest extent), each turned about Y by a
different angle. The model's buffers and images are linked into OUT_DIR (their URIs stay
relative), so OUT_DIR/instanced.gltf loads like the original. For `glint render` memory and
time figures of many copies (docs/instancing.md).
"""
import base64
import json
import math
import os
import struct
import sys


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    model, count, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    if count < 1:
        sys.exit("COUNT must be at least 1")
    with open(model) as f:
        doc = json.load(f)
    src = os.path.dirname(os.path.abspath(model))
    os.makedirs(out, exist_ok=True)
    for item in doc.get("buffers", []) + doc.get("images", []):
        uri = item.get("uri")
        if uri and not uri.startswith("data:"):
            link = os.path.join(out, uri)
            os.makedirs(os.path.dirname(link), exist_ok=True)
            if not os.path.lexists(link):
                os.symlink(os.path.join(src, uri), link)
    extent = 1.0
    for acc in doc.get("accessors", []):
        if "min" in acc and "max" in acc and acc.get("type") == "VEC3":
            extent = max(extent, max(b - a for a, b in zip(acc["min"], acc["max"])))
    side = math.ceil(math.sqrt(count))
    step = 1.5 * extent
    data = bytearray()
    for i in range(count):
        data += struct.pack("<3f", (i % side) * step, 0.0, (i // side) * step)
    rotation_offset = len(data)
    for i in range(count):
        angle = i * 0.618034 * math.tau
        data += struct.pack("<4f", 0.0, math.sin(angle / 2), 0.0, math.cos(angle / 2))
    buffers = doc.setdefault("buffers", [])
    buffers.append({
        "byteLength": len(data),
        "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(data)).decode(),
    })
    views = doc.setdefault("bufferViews", [])
    accessors = doc.setdefault("accessors", [])
    views.append({"buffer": len(buffers) - 1, "byteOffset": 0, "byteLength": rotation_offset})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5126, "count": count, "type": "VEC3"})
    translation = len(accessors) - 1
    views.append({"buffer": len(buffers) - 1, "byteOffset": rotation_offset,
                  "byteLength": len(data) - rotation_offset})
    accessors.append({"bufferView": len(views) - 1, "componentType": 5126, "count": count, "type": "VEC4"})
    rotation = len(accessors) - 1
    for node in doc.get("nodes", []):
        if "mesh" in node:
            node.setdefault("extensions", {})["EXT_mesh_gpu_instancing"] = {
                "attributes": {"TRANSLATION": translation, "ROTATION": rotation}}
    used = doc.setdefault("extensionsUsed", [])
    if "EXT_mesh_gpu_instancing" not in used:
        used.append("EXT_mesh_gpu_instancing")
    with open(os.path.join(out, "instanced.gltf"), "w") as f:
        json.dump(doc, f)
    print(os.path.join(out, "instanced.gltf"))


if __name__ == "__main__":
    main()
