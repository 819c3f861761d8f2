#!/usr/bin/env python3
# measurement: a Cycles golden with one glTF rule its importer skips put back (docs/materials.md). Run: target/tools-venv/bin/python tools/cycles_spec_variant.py RULE MODEL OUT.exr [options]
"""Renders a Cycles golden with one glTF rule that Blender's importer does not follow put back,
to show which part of a gap between glint and a golden is that rule (issue 22).

    VENV/bin/python tools/cycles_spec_variant.py RULE MODEL OUT.exr [cycles_render.py options]

RULE is one of
  cull-single-sided   back faces of single-sided materials (doubleSided false) are transparent
                      to camera rays, as glint culls them (docs/alpha.md); Cycles through the
                      importer draws them (TextureSettingsTest's single-sided row);
  flip-normal-green   the normal texture's green channel is inverted before Blender's Normal
                      Map node: for a model whose supplied TANGENT has the opposite handedness
                      of the UV-derived MikkTSpace frame Blender builds (same tangent, negated
                      bitangent), this is the frame the file gives (TwoSidedPlane). Blender's
                      importer ignores TANGENT.
  tint-per-interface  the base colour of a fully transmitting Principled BSDF (Transmission
                      Weight 1) is squared: Cycles tints a closed glass object by its base
                      colour c once (measured: a c = (0.5, 0.7, 0.9) glass sphere in a white
                      furnace is (0.52, 0.71, 0.90) at its centre), where KHR_materials_volume
                      changes the light's colour "at the volume boundary", i.e. by c at each of
                      the two crossings (c², glint); exact where the material's diffuse and
                      metal parts are 0 (TransmissionRoughnessTest).
The rest is `../shared/peers/cycles_render.py --materials native` unchanged (same options;
pass the goldens' settings from ../shared/khronos/README.md). The rule is added to the
importer's node trees after `native_materials` has run."""
import os
import sys

PEERS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "peers")
sys.path.insert(0, PEERS)
import cycles_render  # noqa: E402


def cull_single_sided(bpy, mat_info, warnings):
    for mat in bpy.data.materials:
        rec = mat_info.get(mat.name)
        nt = mat.node_tree
        if nt is None or rec is None or rec["double_sided"]:
            continue
        out = next((n for n in nt.nodes if n.type == "OUTPUT_MATERIAL"), None)
        if out is None or not out.inputs["Surface"].is_linked:
            continue
        shader = out.inputs["Surface"].links[0].from_socket
        geometry = nt.nodes.new("ShaderNodeNewGeometry")
        light_path = nt.nodes.new("ShaderNodeLightPath")
        both = nt.nodes.new("ShaderNodeMath")
        both.operation = "MULTIPLY"
        nt.links.new(geometry.outputs["Backfacing"], both.inputs[0])
        nt.links.new(light_path.outputs["Is Camera Ray"], both.inputs[1])
        clear = nt.nodes.new("ShaderNodeBsdfTransparent")
        mix = nt.nodes.new("ShaderNodeMixShader")
        nt.links.new(both.outputs[0], mix.inputs["Fac"])
        nt.links.new(shader, mix.inputs[1])
        nt.links.new(clear.outputs[0], mix.inputs[2])
        for link in list(out.inputs["Surface"].links):
            nt.links.remove(link)
        nt.links.new(mix.outputs[0], out.inputs["Surface"])
        warnings.append(f"variant: {mat.name}: back faces transparent to camera rays")


def flip_normal_green(bpy, mat_info, warnings):
    for mat in bpy.data.materials:
        nt = mat.node_tree
        if nt is None:
            continue
        for normal_map in [n for n in nt.nodes if n.type == "NORMAL_MAP"]:
            if not normal_map.inputs["Color"].is_linked:
                continue
            texel = normal_map.inputs["Color"].links[0].from_socket
            split = nt.nodes.new("ShaderNodeSeparateColor")
            invert = nt.nodes.new("ShaderNodeMath")
            invert.operation = "SUBTRACT"
            invert.inputs[0].default_value = 1.0
            join = nt.nodes.new("ShaderNodeCombineColor")
            nt.links.new(texel, split.inputs[0])
            nt.links.new(split.outputs[1], invert.inputs[1])
            nt.links.new(split.outputs[0], join.inputs[0])
            nt.links.new(invert.outputs[0], join.inputs[1])
            nt.links.new(split.outputs[2], join.inputs[2])
            nt.links.new(join.outputs[0], normal_map.inputs["Color"])
            warnings.append(f"variant: {mat.name}: normal texture green inverted")


def tint_per_interface(bpy, mat_info, warnings):
    for mat in bpy.data.materials:
        nt = mat.node_tree
        if nt is None:
            continue
        for node in [n for n in nt.nodes if n.type == "BSDF_PRINCIPLED"]:
            weight = node.inputs["Transmission Weight"]
            if weight.is_linked or weight.default_value < 1.0:
                continue
            base = node.inputs["Base Color"]
            square = nt.nodes.new("ShaderNodeVectorMath")
            square.operation = "MULTIPLY"
            if base.is_linked:
                source = base.links[0].from_socket
                nt.links.new(source, square.inputs[0])
                nt.links.new(source, square.inputs[1])
            else:
                for k in (0, 1):
                    square.inputs[k].default_value = base.default_value[:3]
            nt.links.new(square.outputs[0], base)
            warnings.append(f"variant: {mat.name}: transmission tint squared")


RULES = {
    "cull-single-sided": cull_single_sided,
    "flip-normal-green": flip_normal_green,
    "tint-per-interface": tint_per_interface,
}


def main():
    if len(sys.argv) < 4 or sys.argv[1] not in RULES:
        sys.exit(__doc__)
    rule = RULES[sys.argv[1]]
    native = cycles_render.native_materials

    def with_rule(bpy, mat_info, warnings, info):
        native(bpy, mat_info, warnings, info)
        rule(bpy, mat_info, warnings)

    cycles_render.native_materials = with_rule
    sys.argv = [sys.argv[0]] + sys.argv[2:] + ["--materials", "native"]
    cycles_render.main()


if __name__ == "__main__":
    main()
