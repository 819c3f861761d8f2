"""COCO detection files from glint's per-instance annotations, in pure Python.

``glint batch --coco FILE.json`` writes the same document; this helper builds it from images
rendered any other way (``glint render --annotations``, or several batches)::

    from glint.coco import from_annotations, write
    coco = from_annotations(["out/a.png", "out/b.png"], "out/dataset.json")
    write(coco, "out/dataset.json")

Each image's annotations are read from its camera sidecar ``IMAGE.json`` (its ``instances``). See
docs/ground-truth.md for the fields.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Iterable


def sidecar_path(image: str | os.PathLike) -> Path:
    """The camera sidecar of an image, which holds its annotations: ``OUT.json`` for
    ``OUT.png``."""
    return Path(image).with_suffix(".json")


def from_annotations(images: Iterable[str | os.PathLike], coco_path: str | os.PathLike) -> dict:
    """The COCO document of ``images`` (in order), with file names relative to the folder of
    ``coco_path`` where they lie inside it."""
    images = [Path(i) for i in images]
    files = [json.loads(sidecar_path(i).read_text()) for i in images]
    names = sorted({inst["category"] for f in files for inst in f["instances"]})
    category_id = {name: k + 1 for k, name in enumerate(names)}
    folder = Path(coco_path).parent.resolve()
    coco = {
        "info": {"description": "glint: exact per-instance ground truth"},
        "images": [],
        "categories": [{"id": category_id[n], "name": n, "supercategory": ""} for n in names],
        "annotations": [],
    }
    for image_id, (image, f) in enumerate(zip(images, files), start=1):
        absolute = image.resolve()
        try:
            file_name = str(absolute.relative_to(folder))
        except ValueError:
            file_name = str(absolute)
        coco["images"].append(
            {"id": image_id, "file_name": file_name, "width": f["width"], "height": f["height"]}
        )
        for inst in f["instances"]:
            bbox = inst["visible"]["bbox"]
            if bbox is None:
                continue
            coco["annotations"].append({
                "id": len(coco["annotations"]) + 1,
                "image_id": image_id,
                "category_id": category_id[inst["category"]],
                "segmentation": inst["visible"]["mask"],
                "area": inst["visible"]["area"],
                "bbox": bbox,
                "iscrowd": 0,
                "amodal_segmentation": inst["amodal"]["mask"],
                "amodal_bbox": inst["amodal"]["bbox"] or bbox,
                "amodal_area": inst["amodal"]["area"],
                "visible_fraction": inst["visible_fraction"],
                "instance_id": inst["id"],
            })
    return coco


def write(coco: dict, path: str | os.PathLike) -> None:
    """Writes ``coco`` as JSON to ``path`` (through a temporary file, then renamed)."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_text(json.dumps(coco) + "\n")
    os.replace(tmp, path)
