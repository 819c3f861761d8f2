"""Type stubs of glint's extension module (re-exported by the package ``glint``)."""

import os
from typing import Dict, List, Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

NO_ID: int
"""The ID of nothing: ``instance_id``/``material_id`` where the pixel centre's ray misses,
and unused ``coverage_ids`` layers (0xFFFFFFFF)."""

COVERAGE_LAYERS: int
"""K, the number of objects the ``coverage`` AOV lists per pixel (4)."""

AOVS: List[str]
"""The AOV names ``aovs=`` accepts: albedo, normal, depth, instance_id, material_id, coverage,
z, position, uv, flow, flow_backward."""

AovName = Literal[
    "albedo", "normal", "depth", "instance_id", "material_id", "coverage",
    "z", "position", "uv", "flow", "flow_backward",
]
PathLike = Union[str, "os.PathLike[str]"]

class GlintError(Exception):
    """An error from glint (a scene that cannot be loaded, a camera that does not exist, options
    that cannot be honoured), carrying glint's message."""

class LookAt(TypedDict, total=False):
    """A perspective camera placed by position (``camera=`` of ``Scene.render``)."""

    position: Tuple[float, float, float]
    target: Tuple[float, float, float]
    up: Tuple[float, float, float]
    """World direction that appears up; default +Y."""
    yfov_degrees: float
    """Vertical field of view; default that of the scene's first camera."""
    name: str

class Mesh(TypedDict):
    name: str
    node: int
    """The ``instance_id`` of its pixels (glTF node index)."""
    material: int
    """The ``material_id`` of its pixels."""
    triangles: int

class Camera:
    """A camera of the scene, in world space."""

    name: str
    projection: Literal["perspective", "orthographic"]
    world_from_camera: List[List[float]]
    """4×4, row-major; the camera looks down its −Z."""
    position: List[float]
    yfov: Optional[float]
    """Vertical field of view in radians (perspective)."""
    aspect_ratio: Optional[float]
    xmag: Optional[float]
    ymag: Optional[float]

class Scene:
    """A loaded scene, prepared once (ray-query structure, MIP chains, area lights) and shared
    by all its renders. Renders may run from several Python threads at once."""

    @property
    def cameras(self) -> List[Camera]: ...
    @property
    def bounds(self) -> Optional[Tuple[List[float], List[float]]]:
        """((min x, y, z), (max x, y, z)) in world space, or None without triangles."""
    @property
    def meshes(self) -> List[Mesh]: ...
    @property
    def materials(self) -> List[str]:
        """Material names, indexed by ``material_id``."""
    @property
    def light_count(self) -> int: ...
    @property
    def triangles(self) -> int: ...
    @property
    def backend(self) -> str: ...
    @property
    def label(self) -> str: ...
    def render(
        self,
        *,
        width: Optional[int] = None,
        height: Optional[int] = None,
        spp: int = 16,
        camera: Union[None, int, LookAt] = None,
        lights: Optional[Sequence[str]] = None,
        lights_file: Optional[PathLike] = None,
        photometric: bool = False,
        env: Union[None, PathLike, Tuple[float, float, float]] = None,
        env_strength: float = 1.0,
        env_rotation: float = 0.0,
        env_hidden: bool = False,
        seed: int = 0,
        integrator: Literal["path", "direct"] = "path",
        brdf: Literal["compensated", "spec"] = "compensated",
        max_depth: int = 8,
        max_transmission_depth: int = 64,
        aovs: Sequence[AovName] = (),
        threads: int = 0,
        filter: str = "box",
        sampler: Literal["sobol", "stratified", "independent", "center"] = "sobol",
        time_budget: Optional[float] = None,
        target_error: Optional[float] = None,
        max_spp: int = 65536,
        adaptive: Optional[float] = None,
        clamp_indirect: Optional[float] = None,
        mis_compensation: bool = True,
        output: Optional[PathLike] = None,
        sidecar: bool = False,
        flow_dt: Optional[float] = None,
        annotations: bool = False,
        categories: Optional[Dict[str, str]] = None,
        denoise: bool = False,
    ) -> Dict[str, npt.NDArray[np.generic]]:
        """Renders the scene; the arguments and defaults are ``glint render``'s.

        Returns a dict: ``radiance`` (float32 H×W×3, W/(m²·sr)), ``alpha`` (float32 H×W, the
        fraction of the pixel's camera samples that hit the scene: the EXR's ``A``) and, per
        AOV asked for,
        ``albedo``/``normal`` (float32 H×W×3), ``depth`` (float32 H×W), ``instance_id`` and
        ``material_id`` (uint32 H×W), ``coverage_ids`` (uint32 H×W×K) with ``coverage``
        (float32 H×W×K), ``z`` (float32 H×W), ``position`` (float32 H×W×3), ``uv``, ``flow``
        and ``flow_backward`` (float32 H×W×2; NaN where invalid; docs/ground-truth.md).
        ``camera`` is the camera sidecar as a dict (K, poses, projection, time). ``output``
        also writes the image (.png or .exr, with the AOVs), and with ``sidecar=True`` its
        sidecar OUT.json beside it. Flow needs a scene loaded with ``time=``.
        ``annotations=True`` adds per-instance visible and amodal masks (COCO RLE), areas,
        visible fractions and boxes as ``instances`` (also ``camera["instances"]``, and the
        sidecar's with ``output``); ``categories`` maps node or mesh names to categories
        (``--category``).
        ``denoise=True`` denoises with Open Image Denoise (a build with the ``denoise``
        feature): ``radiance`` is then the denoised image and ``noisy`` the one before.

        Raises GlintError (glint's message) for a bad camera index, light spec, environment or
        option; ValueError/TypeError for arguments of the wrong kind; KeyboardInterrupt on
        Ctrl-C, which stops the render. The GIL is released while rendering.
        """

def load(
    path: Optional[PathLike] = None,
    *,
    backend: Optional[Literal["embree", "bvh"]] = None,
    scene: Optional[int] = None,
    time: Optional[float] = None,
    variant: Optional[str] = None,
    asset_root: Optional[PathLike] = None,
    max_texture_pixels: int = 67108864,
) -> Scene:
    """Loads a .gltf/.glb (glint's demo scene when ``path`` is None) and prepares it.
    Raises GlintError with glint's message if the file cannot be loaded."""

def render_batch(jobs: Sequence[dict], *, threads: int = 0) -> List[Dict[str, npt.NDArray[np.generic]]]:
    """Renders jobs (dicts of ``Scene.render``'s arguments plus ``scene``: a Scene or a path)
    side by side on one pool of ``threads`` workers; returns their results in order. The first
    failing job raises GlintError naming its index."""
