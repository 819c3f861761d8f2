#!/usr/bin/env python3
# docs picture: draws docs/images/ground-truth-flow.png (docs/ground-truth.md). Run: target/tools-venv/bin/python tools/ground-truth-picture.py FRAME.exr SIDECAR.json OUT.png
"""Draws docs/images/ground-truth-flow.png: one frame of InterpolationTest (a render, its
visible and amodal masks decoded from the sidecar with pycocotools, and its forward flow as
colour: hue the direction, saturation the length, grey where the flow is NaN).

    glint render ../shared/khronos/InterpolationTest/glTF-Binary/InterpolationTest.glb -o f.exr \
        --time 1.2 --width 480 --height 270 --spp 16 --env ../shared/env/studio.exr --sidecar \
        --annotations --aov z,position,flow,flow_backward,instance_id --flow-dt 0.1
    glint check-gt f.exr
    PY tools/ground-truth-picture.py f.exr f.json docs/images/ground-truth-flow.png

PY: a Python with numpy, OpenEXR (3.x), pillow and pycocotools.
"""
import json
import sys

import numpy as np
import OpenEXR
from PIL import Image, ImageDraw
from pycocotools import mask as cm
f = OpenEXR.File(sys.argv[1]); side = json.load(open(sys.argv[2]))
ch = f.channels()
def get(name): return np.asarray(ch[name].pixels, dtype=np.float64)
rgb = np.stack([get(c) for c in ("R","G","B")], -1) if "R" in ch else get("RGBA")[..., :3]
H, W = rgb.shape[:2]
srgb = np.where(rgb <= 0.0031308, 12.92*rgb, 1.055*np.power(np.clip(rgb,0,None),1/2.4)-0.055)
panel = lambda a: Image.fromarray((np.clip(a,0,1)*255).astype(np.uint8))
rng = np.random.default_rng(3)
def masks(kind):
    out = srgb*0.25
    for inst in side["instances"]:
        m = inst[kind]["mask"] if "mask" in inst[kind] else inst[kind]["segmentation"]
        r = {"size": m["size"], "counts": m["counts"].encode()}
        mk = cm.decode(r).astype(bool)
        c = rng.random(3)*0.7+0.3
        out = np.where(mk[..., None], out*0.4 + c*0.6, out)
    return out
rng = np.random.default_rng(3); vis = masks("visible")
rng = np.random.default_rng(3); amo = masks("amodal")
fx, fy = get("flow.X"), get("flow.Y")
valid = np.isfinite(fx) & np.isfinite(fy)
mag = np.hypot(np.nan_to_num(fx), np.nan_to_num(fy)); ang = np.arctan2(np.nan_to_num(fy), np.nan_to_num(fx))
nz = mag[valid & (mag > 1e-3)]; scale = np.percentile(nz, 60) if nz.size else 1
hsv = np.stack([(ang/(2*np.pi))%1, np.clip(mag/scale,0,1), np.ones_like(mag)], -1)
flowimg = np.zeros((H,W,3))
h6 = hsv[...,0]*6; i = np.floor(h6).astype(int)%6; fr = h6-np.floor(h6); s=hsv[...,1]; v=hsv[...,2]
p=v*(1-s); q=v*(1-s*fr); t=v*(1-s*(1-fr))
for k,(a,b,c) in enumerate([(v,t,p),(q,v,p),(p,v,t),(p,q,v),(t,p,v),(v,p,q)]):
    sel = i==k; flowimg[sel] = np.stack([a,b,c],-1)[sel]
flowimg[~valid] = 0.15
grid = Image.new("RGB", (2*W, 2*H+40), (255,255,255))
d = ImageDraw.Draw(grid)
for (img, label, x, y) in [(srgb,"render (16 spp)",0,0),(vis,"visible masks",W,0),(amo,"amodal masks",0,H+20),(flowimg,f"forward flow (hue: direction, saturation: length, full at {scale:.1f} px; white: still; grey: NaN)",W,H+20)]:
    grid.paste(panel(img),(x,y+20 if y==0 else y+20)); d.text((x+4,y+4 if y==0 else y+4),label,fill=(0,0,0))
grid.save(sys.argv[3]); print("saved", grid.size, "flow px99", scale, "valid", valid.sum())
