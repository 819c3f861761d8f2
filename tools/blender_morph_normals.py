#!/usr/bin/env python3
# measurement: what Blender's glTF importer does to morphed normals without NORMAL targets (docs/materials.md). Run: target/tools-venv/bin/python tools/blender_morph_normals.py
"""What Blender's glTF importer does to the normals of a morphed primitive whose targets carry
no NORMAL (issue 34). glTF 2.0, 3.7.2.2: "Attributes present in the base mesh primitive but
not included in a given morph target MUST retain their original values for the morph
target", so the file's normals stay as they are; glint and three.js keep them.

    VENV/bin/python tools/blender_morph_normals.py      # VENV with the bpy wheel

Builds a quad in the xy plane with NORMAL +Z and one POSITION-only target that lifts its
y = 1 edge by 1 (mesh weight 0.5: the quad tilts by 26.6°), imports it as the goldens do
(import_shading NORMALS, merge_vertices off) and prints the evaluated mesh's corner normals
in glTF axes. Blender 5.0.1 prints (0, -0.447, 0.894) for every corner, the tilted quad's
geometric normal, where glTF keeps (0, 0, 1)."""
import base64
import json
import os
import struct
import sys
import tempfile

import bpy


def main():
    f3 = lambda vs: b"".join(struct.pack("<3f", *v) for v in vs)  # noqa: E731
    positions = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    data = (f3(positions) + f3([(0, 0, 1)] * 4) + f3([(0, 0, 0), (0, 0, 0), (0, 0, 1), (0, 0, 1)])
            + struct.pack("<6H", 0, 1, 2, 0, 2, 3) + b"\0\0")
    views = [{"buffer": 0, "byteOffset": 48 * k, "byteLength": 48} for k in range(3)]
    views.append({"buffer": 0, "byteOffset": 144, "byteLength": 12})
    vec3 = lambda view, **kw: {"bufferView": view, "componentType": 5126, "count": 4, "type": "VEC3", **kw}  # noqa: E731
    doc = {
        "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1},
                                    "targets": [{"POSITION": 2}], "indices": 3}], "weights": [0.5]}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": views,
        "accessors": [vec3(0, min=[0, 0, 0], max=[1, 1, 0]), vec3(1), vec3(2, min=[0, 0, 0], max=[0, 0, 1]),
                      {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    }
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "morph.gltf")
        with open(path, "w") as f:
            json.dump(doc, f)
        bpy.ops.wm.read_factory_settings(use_empty=True)
        bpy.ops.import_scene.gltf(filepath=path, import_shading="NORMALS", merge_vertices=False)
    obj = next(o for o in bpy.context.scene.objects if o.type == "MESH")
    mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).to_mesh()
    # Blender is Z-up: glTF (x, y, z) = Blender (x, z, -y).
    normals = {tuple(round(c, 3) for c in (n.vector.x, n.vector.z, -n.vector.y)) for n in mesh.corner_normals}
    print(f"file NORMAL (0, 0, 1); Blender's evaluated corner normals (glTF axes): {sorted(normals)}",
          file=sys.stdout)


if __name__ == "__main__":
    main()
