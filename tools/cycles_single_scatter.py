# measurement: a Cycles golden with single-scatter GGX, to tell energy compensation from bugs (docs/materials.md). Run: target/tools-venv/bin/python tools/cycles_single_scatter.py MODEL OUT.exr [options]
"""Runs ../shared/peers/cycles_render.py with every Principled BSDF switched from Cycles'
default multiscatter GGX to single-scatter GGX, the glTF spec's (Appendix B) microfacet model,
to tell Cycles' energy compensation apart from glint bugs:

    /work/bpyvenv/bin/python tools/cycles_single_scatter.py MODEL OUT.exr <cycles_render.py options>

(the options of the goldens are in ../shared/khronos/README.md). Then
`tools/fidelity.py --golden 'DIR/{model}.exr' MODEL` compares glint with it. Reads the
peer script from ../shared; writes only OUT.exr."""
import importlib.util
import os
import sys
spec = importlib.util.spec_from_file_location("cr", os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "peers", "cycles_render.py"))
cr = importlib.util.module_from_spec(spec); spec.loader.exec_module(cr)
orig = cr.native_materials
def patched(bpy, mat_info, warnings, info):
    orig(bpy, mat_info, warnings, info)
    n = 0
    for m in bpy.data.materials:
        if m.node_tree:
            for node in m.node_tree.nodes:
                if node.type == "BSDF_PRINCIPLED":
                    node.distribution = "GGX"; n += 1
    info["single_scatter_principled"] = n
cr.native_materials = patched
sys.argv = ["cycles_render.py"] + sys.argv[1:]
cr.main()
