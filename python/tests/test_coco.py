"""Annotations and COCO files against pycocotools: RLE round trips, a three-job batch's COCO
file loads, and its areas and boxes equal the per-image annotation files'."""

import importlib.util
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

maskutils = pytest.importorskip("pycocotools.mask")
COCO = pytest.importorskip("pycocotools.coco").COCO

HERE = Path(__file__).resolve().parent


def load_helper():
    """glint.coco without importing the compiled extension (the helper is pure Python)."""
    spec = importlib.util.spec_from_file_location("glint_coco", HERE.parent / "glint" / "coco.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def batch(glint_bin, quads_path, tmp_path_factory):
    """A three-job batch of the two-quads scene (different sizes and sample counts)."""
    out = tmp_path_factory.mktemp("coco")
    jobs = out / "jobs.toml"
    lines = []
    for k, (w, h, spp) in enumerate([(7, 2, 4), (28, 8, 8), (35, 10, 16)]):
        lines += ["[[job]]", f'scene = "{quads_path}"', f'output = "img{k}.png"',
                  f"width = {w}", f"height = {h}", f"spp = {spp}", ""]
    jobs.write_text("\n".join(lines))
    coco_path = out / "dataset.json"
    subprocess.run([str(glint_bin), "batch", str(jobs), "--coco", str(coco_path), "-q"],
                   check=True)
    return out, coco_path


def test_the_batch_coco_file_loads_and_matches_the_annotation_files(batch):
    out, coco_path = batch
    coco = COCO(str(coco_path))
    assert len(coco.getImgIds()) == 3
    assert {c["name"] for c in coco.loadCats(coco.getCatIds())} == {"A", "B"}
    for image in coco.loadImgs(coco.getImgIds()):
        annotated = json.loads((out / image["file_name"]).with_suffix(".json").read_text())
        by_id = {inst["id"]: inst for inst in annotated["instances"]}
        anns = coco.loadAnns(coco.getAnnIds(imgIds=[image["id"]]))
        assert len(anns) == 2
        for ann in anns:
            inst = by_id[ann["instance_id"]]
            assert ann["area"] == inst["visible"]["area"]
            assert ann["bbox"] == inst["visible"]["bbox"]
            assert ann["amodal_bbox"] == inst["amodal"]["bbox"]
            assert ann["iscrowd"] == 0
            assert 0.0 <= ann["visible_fraction"] <= 1.0
            mask = coco.annToMask(ann)
            assert mask.shape == (image["height"], image["width"])
            assert mask.sum() == inst["visible"]["mask_pixels"]
            amodal = maskutils.decode(ann["amodal_segmentation"])
            assert np.all(amodal >= mask), "amodal must contain visible"
            # The box is the mask's tight box.
            ys, xs = np.nonzero(mask)
            assert ann["bbox"] == [xs.min(), ys.min(), xs.max() + 1 - xs.min(),
                                   ys.max() + 1 - ys.min()]


def test_rle_round_trips_through_pycocotools(batch):
    out, coco_path = batch
    for f in sorted(out.glob("img*.json")):
        for inst in json.loads(f.read_text())["instances"]:
            for region in (inst["visible"], inst["amodal"]):
                rle = dict(region["mask"])
                rle["counts"] = rle["counts"].encode()
                mask = maskutils.decode(rle)
                again = maskutils.encode(np.asfortranarray(mask))
                assert again["counts"].decode() == region["mask"]["counts"]
                assert list(again["size"]) == region["mask"]["size"]
                assert int(mask.sum()) == region["mask_pixels"]


def test_the_python_helper_writes_the_batch_file(batch):
    out, coco_path = batch
    helper = load_helper()
    images = [out / f"img{k}.png" for k in range(3)]
    ours = helper.from_annotations(images, coco_path)
    theirs = json.loads(coco_path.read_text())
    assert ours["annotations"] == theirs["annotations"]
    assert ours["images"] == theirs["images"]
    assert ours["categories"] == theirs["categories"]
    helper.write(ours, out / "again.json")
    assert len(COCO(str(out / "again.json")).getAnnIds()) == len(ours["annotations"])
