"""glint: a native CPU renderer for glTF 2.0 scenes, from Python.

Load a scene once, render it many times; every render returns numpy arrays::

    import glint
    scene = glint.load("model.glb")
    img = scene.render(width=640, height=480, spp=64, aovs=["instance_id", "coverage"])
    img["radiance"]      # float32 H×W×3, W/(m²·sr)
    img["instance_id"]   # uint32 H×W: glTF node index at each pixel centre (NO_ID: nothing)

See docs/python.md in glint's repository for the whole API.
"""

from ._glint import (
    AOVS,
    COVERAGE_LAYERS,
    NO_ID,
    Camera,
    GlintError,
    Scene,
    __version__,
    load,
    render_batch,
)

__all__ = [
    "AOVS",
    "COVERAGE_LAYERS",
    "NO_ID",
    "Camera",
    "GlintError",
    "Scene",
    "__version__",
    "load",
    "render_batch",
]
